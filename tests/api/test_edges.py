"""Edges of the API (issue 20, item 6): the first step's dt, protocols simulate() refuses, arrays that are
not real numbers, and messages that show a value just outside a bound as it is."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import mudforce as mf
from mudforce.estimation.calibration import Trial
from mudforce.estimation.calibration.drag import fit_drag
from mudforce.estimation.tracker import MudTracker, MudTrackers, track
from mudforce.model.baselines import granular_rft_force
from mudforce.motions.protocol import MAX_RATE, MAX_SAMPLES, MIN_RATE
from mudforce.references.trajectory import reference_simulate
from mudforce.steppers.simulation import MAX_DEPTH, MIN_DT

W25 = mf.MudParameters.from_water_content(0.25)


# ---------------------------------------------------------------- the first step ignores dt
@pytest.mark.parametrize("dt", [0.0, -1.0, float("nan"), 1e9])
def test_the_first_step_ignores_dt_in_both_steppers(dt: float) -> None:
    one, many = mf.MudContact(W25), mf.MudContacts(W25, 3)
    f0 = one.step(0.001, dt)
    np.testing.assert_array_equal(many.step(np.full(3, 0.001), dt), [f0, f0, f0])
    # then both refuse it, leaving the state as it was, and agree on the next step
    with pytest.raises(mf.InputError, match=r"dt must be within \[1e-09, 1000\] s"):
        one.step(0.002, dt)
    with pytest.raises(mf.InputError, match=r"dt must be within \[1e-09, 1000\] s"):
        many.step(np.full(3, 0.002), dt)
    f = one.step(0.002, 0.01)
    assert f > 0.0
    np.testing.assert_array_equal(many.step(np.full(3, 0.002), 0.01), [f, f, f])


def test_a_reset_foot_alone_does_not_let_a_bad_dt_through() -> None:
    many = mf.MudContacts(W25, 2)
    many.step(np.zeros(2), 0.01)
    many.reset([0])  # foot 1 has started: dt matters
    with pytest.raises(mf.InputError, match="dt must be within"):
        many.step(np.zeros(2), 0.0)
    many.reset()
    many.step(np.zeros(2), 0.0)


# ---------------------------------------------------------------- protocols within what simulate() accepts
@pytest.mark.parametrize(("kwargs", "expected"), [
    ({"rate": 1e12}, "sampling rate must be within [0.001, 1e+08] Hz"),
    ({"rate": 1e-4}, "sampling rate must be within [0.001, 1e+08] Hz"),
    ({"depth": 1000.0}, "intrusion depth must be within +-100 m"),
    ({"rise": 100.5}, "withdrawal rise must be within +-100 m"),
    ({"approach": 1e3}, "start depth must be within +-100 m"),
    ({"rate": 1e6, "hold": 60.0}, "samples, more than 10,000,000"),
    ({"rate": 1e-3, "velocity": 1e-5, "hold": 2e9}, "its last sample beyond simulate()'s 1e+09 s"),
    ({"rate": 1e-3, "hold": 1e5}, "longer than step 1 (Intrude, 2 s), which the samples would cut"),
])
def test_a_protocol_simulate_would_refuse_is_refused_on_construction(kwargs: dict[str, float],
                                                                      expected: str) -> None:
    with pytest.raises(mf.InputError) as err:
        mf.Protocol.paper(**kwargs)
    assert expected in str(err.value) and "\n" not in str(err.value), str(err.value)


@pytest.mark.parametrize("protocol", [
    mf.Protocol.paper(depth=MAX_DEPTH, velocity=10.0, hold=1.0, rise=MAX_DEPTH, rate=100.0),
    mf.Protocol.paper(velocity=1e-5, rate=MIN_RATE, hold=1e5),  # each step at least a sample long
    mf.Protocol.paper(depth=1e-4, velocity=10.0, hold=1e-5, rise=1e-4, rate=MAX_RATE),
])
def test_a_protocol_at_the_bounds_is_simulated(protocol: mf.Protocol) -> None:
    t, z = protocol.sample()
    assert t.size <= MAX_SAMPLES and np.diff(t).min() >= MIN_DT
    res = mf.simulate(t, z, W25, velocity_filter="exact")
    assert np.isfinite(res.force).all()


# ---------------------------------------------------------------- arrays of real numbers only
T = np.arange(40) * 0.01
Z = np.linspace(-0.01, 0.02, 40)

# each entry of the API that takes arrays, with one argument replaced by `bad`
ENTRIES: dict[str, Callable[[Any], object]] = {
    "simulate time": lambda bad: mf.simulate(bad, Z, W25),
    "simulate depth": lambda bad: mf.simulate(T, bad, W25),
    "MudContact.step": lambda bad: mf.MudContact(W25).step(bad[:1].reshape(()), 0.01),  # a 0-d array
    "MudContacts.step": lambda bad: mf.MudContacts(W25, 40).step(bad, 0.01),
    "MudContacts.state": lambda bad: setattr(mf.MudContacts(W25, 1), "state",
                                             np.asarray(mf.MudContacts(W25, 1).state, dtype=bad.dtype)),
    "MudTrackers.update": lambda bad: MudTrackers(40).update(bad, np.zeros(40), 0.01),
    "MudTracker.update": lambda bad: MudTracker().update(0.0, bad[:1].reshape(()), 0.01),
    "track": lambda bad: track(T, Z, bad),
    "Trial": lambda bad: Trial("t.csv", 0.25, T, bad, np.zeros(40)),
    "fit_drag": lambda bad: fit_drag(bad, np.ones(40), area=0.002),
    "granular_rft_force": lambda bad: granular_rft_force(T, bad, 1e6),
    "reference_simulate": lambda bad: reference_simulate(bad, Z, W25),
}
BAD: dict[str, Any] = {
    "complex": Z + 0j,
    "boolean": Z > 0.0,
    "string": Z.astype(str),
    "object": Z.astype(object),
}


@pytest.mark.parametrize("dtype", BAD)
@pytest.mark.parametrize("entry", ENTRIES)
def test_arrays_that_are_not_real_numbers_are_refused(entry: str, dtype: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning: a refusal
        with pytest.raises(mf.InputError) as err:
            ENTRIES[entry](BAD[dtype])
    message = str(err.value)
    assert "\n" not in message and "real number" in message, message


#: the entries that take any sequence (not only an array: those above that slice or read a dtype are left out)
SEQUENCE_ENTRIES = ["simulate time", "simulate depth", "MudContacts.step", "MudTrackers.update", "track", "Trial",
                    "fit_drag", "granular_rft_force", "reference_simulate"]


@pytest.mark.parametrize("entry", SEQUENCE_ENTRIES)
def test_a_list_with_a_boolean_among_its_numbers_is_refused(entry: str) -> None:
    mixed = [*Z[:-1].tolist(), True]  # numpy alone reads it as float64, the True as 1.0
    assert np.asarray(mixed).dtype == np.float64
    with pytest.raises(mf.InputError) as err:
        ENTRIES[entry](mixed)
    message = str(err.value)
    assert "\n" not in message and "real number" in message and "boolean" in message, message


def test_real_array_names_the_dtype() -> None:
    from mudforce.errors import real_array

    with pytest.raises(mf.InputError, match=r"^time must be an array of real numbers \[s\], got complex values "
                                            r"\(dtype complex128\)$"):
        real_array(np.zeros(2) + 1j, "time", "s")
    assert real_array([1, 2], "time", "s").dtype == np.float64
    given = np.zeros(3)
    assert real_array(given, "time", "s") is given


# ---------------------------------------------------------------- a value just outside a bound, shown as it is
def test_a_step_just_under_1_ns_is_shown_as_it_is() -> None:
    step = 9.9999e-10
    t = np.array([0.0, step])
    with pytest.raises(mf.InputError) as err:
        mf.simulate(t, np.zeros(2), W25)
    assert f"is {float(t[1] - t[0])!r} s; expected steps within [1e-09, 1000] s" in str(err.value), str(err.value)
    one, many = mf.MudContact(W25), mf.MudContacts(W25, 1)
    one.step(0.0, 0.01)
    many.step(np.zeros(1), 0.01)
    for stepper in (lambda: one.step(0.0, step), lambda: many.step(np.zeros(1), step)):
        with pytest.raises(mf.InputError, match=r"got 9\.9999e-10$"):
            stepper()


def test_real_array_refuses_a_masked_array_with_masked_values_and_reads_one_without() -> None:
    """A masked value was read as a number: simulate ran on a masked time sample (float64 kept its mask; other
    dtypes dropped it in np.asarray)."""
    from mudforce.errors import real_array

    for dtype in (np.float64, np.int64):
        masked = np.ma.array(np.arange(5, dtype=dtype), mask=[0, 0, 1, 0, 0])
        with pytest.raises(mf.InputError, match=r"^time must be an array of real numbers \[s\], got a masked array "
                                                r"with 1 masked value\(s\); fill or drop them first$"):
            real_array(masked, "time", "s")
    plain = real_array(np.ma.array([0.0, 0.01]), "time", "s")
    assert type(plain) is np.ndarray and plain.tolist() == [0.0, 0.01]
