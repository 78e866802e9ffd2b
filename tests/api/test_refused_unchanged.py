"""An object that refuses an input is left exactly as it was; finite input within bounds gives finite output.

Hypothesis drives :class:`~mudforce.MudContact` and
:class:`~mudforce.steppers.many.MudContacts` through valid steps, then offers
a bad input (a NaN, an infinity, a depth beyond 100 m, a step shorter than
1 ns, a wrong type, a corrupt state): it must raise :class:`InputError`,
leave the state bit for bit as it was, and the next good step must give
what a twin that never saw the bad input gives.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudforce as mf
from mudforce._kernel import layout as K  # the state layout's columns, drawn to corrupt them
from mudforce.errors import InputError
from mudforce.estimation.calibration.dataset import load_dataset
from mudforce.io.tables import read_trajectory
from mudforce.io.units import parse_quantity
from mudforce.model.parameters import PARAMETER_NAMES, PARAMETER_RANGES
from mudforce.steppers.contact import ContactState
from mudforce.steppers.many import MudContacts
from mudforce.steppers.simulation import MAX_DEPTH, MAX_DT, MAX_TIME, MIN_DT

W25 = mf.MudParameters.from_water_content(0.25)
SETTINGS = settings(max_examples=40, deadline=None)

good_depth = st.floats(-0.03, 0.03)
good_dt = st.floats(1e-4, 0.05)
bad_depth = st.sampled_from([np.nan, np.inf, -np.inf, 1e307, -1e307, MAX_DEPTH * 1.0001, None, "0.01", [0.01]])
bad_dt = st.sampled_from([np.nan, np.inf, 0.0, -0.01, 1e-320, 1e-310, 1e-200, MIN_DT / 2, MAX_DT * 2, None, "x"])


def _history(draw: st.DrawFn) -> list[tuple[float, float]]:
    return draw(st.lists(st.tuples(good_depth, good_dt), min_size=1, max_size=30))


@SETTINGS
@given(st.data())
def test_mud_contact_refused_means_unchanged(data: st.DataObject) -> None:
    history = data.draw(st.lists(st.tuples(good_depth, good_dt), min_size=1, max_size=30))
    contact, twin = mf.MudContact(W25), mf.MudContact(W25)
    for z, dt in history:
        contact.step(z, dt)
        twin.step(z, dt)
    before, last = contact.state, contact.last
    bad = data.draw(st.one_of(st.tuples(bad_depth, good_dt), st.tuples(good_depth, bad_dt)))
    try:
        contact.step(*bad)  # type: ignore[arg-type]
    except InputError:
        pass
    else:
        raise AssertionError(f"accepted {bad!r}")
    assert contact.state == before and contact.last == last
    assert np.array_equal(contact.state.data, before.data)
    z, dt = data.draw(st.tuples(good_depth, good_dt))
    assert contact.step(z, dt) == twin.step(z, dt)
    repr(contact)  # a refused input never leaves a state that repr cannot show


@SETTINGS
@given(st.data())
def test_contact_state_garbage_is_refused(data: st.DataObject) -> None:
    contact = mf.MudContact(W25)
    for z, dt in data.draw(st.lists(st.tuples(good_depth, good_dt), min_size=2, max_size=10)):
        contact.step(z, dt)
    before = contact.state
    garbage = before.data.copy()
    column = data.draw(st.sampled_from([K.S_STARTED, K.S_MODE, K.S_DIRECTION, K.S_TIME, K.S_DEPTH, K.S_MUD,
                                        K.S_NECK_AGE, K.S_CACHE_DECAY_I, K.S_STRAIN, K.S_VELOCITY, K.S_NECK_V,
                                        K.S_NECK_G, K.S_NECK_GI]))
    value = data.draw(st.sampled_from([np.nan, np.inf, 7.0, 0.5, -3.0, 1e9, -1e300, 1e300]))
    garbage[column] = value
    plausible = {K.S_MUD: np.isfinite(value), K.S_TIME: 0 <= value <= MAX_TIME, K.S_NECK_AGE: 0 <= value < np.inf,
                 K.S_DEPTH: abs(value) <= MAX_DEPTH, K.S_CACHE_DECAY_I: 0 <= value <= 1,
                 K.S_STRAIN: abs(value) <= 2.0 * MAX_DEPTH, K.S_VELOCITY: abs(value) <= 2.0 * MAX_DEPTH / MIN_DT,
                 K.S_NECK_V: abs(value) <= 2.0 * MAX_DEPTH / MIN_DT, K.S_NECK_G: abs(value) <= 1.0,
                 K.S_NECK_GI: abs(value) <= garbage[K.S_NECK_AGE] * (1.0 + 1e-6) + 1e-12}
    if plausible.get(column, False):
        return  # a value a contact can hold
    try:
        contact.state = ContactState(garbage, before.params_key)
    except InputError:
        pass
    else:
        raise AssertionError(f"accepted column {column} = {value}")
    assert contact.state == before
    assert contact.state.mode in ("FREE", "CONTACT", "NECKED") and "MudContact(" in repr(contact)


def test_a_state_time_beyond_the_time_bound_is_refused_by_every_contact_and_changes_nothing() -> None:
    """steppers.contact.check_states (every contact's, and the MuJoCo adapters' through it): a time beyond MAX_TIME
    (1e9 s, a recording's bound) was taken, 1e308 s included, by MudContact, MudContacts and both 3-D contacts."""
    from mudforce.model import shapes

    contact, feet = mf.MudContact(W25), MudContacts(W25, 2)
    toe, toes = mf.MudContact3D(W25, shapes.sphere(0.04)), mf.MudContacts3D(W25, shapes.sphere(0.04), 2)
    for _ in range(2):
        contact.step(0.01, 0.01)
        feet.step(np.full(2, 0.01), 0.01)
    message = r"time is beyond 1e\+09 s; expected a state taken from a contact$"
    before = contact.state
    data = before.data.copy()
    data[K.S_TIME] = 1e308
    with pytest.raises(InputError, match=r"^a contact state: " + message):
        contact.state = ContactState(data, before.params_key, before.ring)
    assert contact.state == before
    saved = feet.state
    rows = saved.copy()
    rows[1, K.S_TIME] = MAX_TIME * (1.0 + 1e-15)
    with pytest.raises(InputError, match=r"\(foot 1\): " + message):
        feet.state = rows
    assert np.array_equal(feet.state, saved)
    for three_d in (toe, toes):
        kept = three_d.state
        elements = kept.elements.copy()
        elements[0, K.S_TIME] = 1e308
        with pytest.raises(InputError, match=r"\(element 0\): " + message):
            three_d.state = kept._replace(elements=elements)
        assert np.array_equal(three_d.state.elements, kept.elements)


@settings(max_examples=25, deadline=None)
@given(st.data())
def test_mud_contacts_refused_means_unchanged(data: st.DataObject) -> None:
    n = data.draw(st.integers(1, 40))
    threads = data.draw(st.sampled_from([1, 2]))
    feet, twin = MudContacts(W25, n, threads=threads), MudContacts(W25, n, threads=1)
    # at least one step: a foot's first step ignores dt (as MudContact's does), so a bad dt is refused only after it
    steps = data.draw(st.lists(st.tuples(st.lists(good_depth, min_size=n, max_size=n), good_dt), min_size=1,
                               max_size=8))
    for z, dt in steps:
        feet.step(np.array(z), dt)
        twin.step(np.array(z), dt)
    before = feet.state
    z = np.array(data.draw(st.lists(good_depth, min_size=n, max_size=n)), dtype=object)
    kind = data.draw(st.sampled_from(["depth", "dt", "shape", "restore"]))
    dt: object = data.draw(good_dt)
    try:
        if kind == "depth":
            z[data.draw(st.integers(0, n - 1))] = data.draw(bad_depth.filter(lambda v: not isinstance(v, list)))
            feet.step(z, dt)  # type: ignore[arg-type]
        elif kind == "dt":
            feet.step(z.astype(float), data.draw(bad_dt))  # type: ignore[arg-type]
        elif kind == "shape":
            feet.step(np.zeros(n + 1), dt)  # type: ignore[arg-type]
        else:
            garbage = before.copy()
            garbage[data.draw(st.integers(0, n - 1)), data.draw(st.sampled_from([K.S_MODE, K.S_STARTED]))] = 7.0
            feet.state = garbage
    except InputError:
        pass
    else:
        raise AssertionError(f"accepted a bad {kind}")
    assert np.array_equal(feet.state, before, equal_nan=True)
    retry = np.array(data.draw(st.lists(good_depth, min_size=n, max_size=n)))
    got = feet.step(retry, 0.01)
    assert np.array_equal(got, twin.step(retry, 0.01))
    assert got is not feet.step(retry, 0.01)  # a new array each call
    out = np.empty(n)
    assert feet.step(retry, 0.01, out=out) is out


def test_api_type_errors_are_input_errors() -> None:
    """Bad types raise InputError, not TypeError or AttributeError."""
    for call in (lambda: MudContacts(None, 3), lambda: MudContacts(W25, None), lambda: mf.MudContact(None),
                 lambda: mf.MudContact(W25, "disc"), lambda: mf.MudContact(W25).step(None, 0.01),
                 lambda: mf.Foot(None, 0.1), lambda: mf.Foot.disc("5cm"), lambda: MudContacts(W25, 2).step("ab", 0.1),
                 lambda: MudContacts(W25, 2, foot=[None, None]), lambda: setattr(MudContacts(W25, 2), "state", None),
                 lambda: ContactState(None), lambda: mf.simulate(None, None, W25),
                 lambda: mf.MudParameters.from_water_content("25%"), lambda: mf.MudParameters.load(None),
                 lambda: load_dataset(None), lambda: read_trajectory(3.0), lambda: parse_quantity(None, "length"),
                 lambda: mf.Foot.cuboid(None, 0.01)):
        try:
            call()
        except InputError:
            continue
        raise AssertionError("accepted a bad type")


def _log_uniform(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(np.log10(lo), np.log10(hi)).map(lambda e: float(10.0**e))


@st.composite
def extreme_parameters(draw: st.DrawFn) -> mf.MudParameters:
    """Parameter sets anywhere within PARAMETER_RANGES, their ends included."""
    values = {}
    for name in PARAMETER_NAMES:
        lo, hi = PARAMETER_RANGES[name]
        values[name] = draw(st.one_of(st.sampled_from([lo, hi]), _log_uniform(max(lo, 1e-6), hi)))
    return mf.MudParameters.from_dict(values)


@settings(max_examples=60, deadline=None)
@given(extreme_parameters(), st.data())
def test_finite_in_bounds_gives_finite_out(params: mf.MudParameters, data: st.DataObject) -> None:
    """Any parameters, depths, steps and foot within their stated bounds: every output column is finite."""
    n = data.draw(st.integers(2, 12))
    dts = data.draw(st.lists(st.one_of(st.sampled_from([MIN_DT, MAX_DT]), _log_uniform(MIN_DT, MAX_DT)),
                             min_size=n - 1, max_size=n - 1))
    time = np.concatenate([[0.0], np.cumsum(dts)])
    depth = np.array(data.draw(st.lists(st.one_of(st.sampled_from([-MAX_DEPTH, MAX_DEPTH, 0.0]),
                                                  st.floats(-MAX_DEPTH, MAX_DEPTH)), min_size=n, max_size=n)))
    size = data.draw(st.sampled_from([1e-4, 0.05, 10.0]))
    foot = mf.Foot.cuboid(size, size)
    try:
        res = mf.simulate(time, depth, params, foot, velocity_filter="exact")
    except InputError as exc:
        # only a step lost to rounding (time + dt == time at large times) may be refused
        assert "time step" in str(exc) or "repeats" in str(exc), str(exc)
        return
    for name in ("force", "f_e1", "f_e2", "f_s", "mud_displacement", "mud_velocity", "velocity"):
        assert np.isfinite(getattr(res, name)).all(), name


def test_a_restored_cache_is_kept_only_where_it_is_the_steppers_own() -> None:
    """A snapshot's step-length cache is kept on restore only if it is, bit for bit, what the stepper computes for
    its step length (so a replay is the same bits); cached decays edited within [0, 1] under the snapshot's own
    parameters are recomputed (they were used as given: a silently wrong force)."""
    params = mf.MudParameters.from_water_content(0.25)
    t, z = mf.Protocol.paper(depth=0.02, velocity=0.01).sample()
    contact = mf.MudContact(params)
    dt = float(t[1] - t[0])
    for k in range(len(t) // 3):
        contact.step(z[k], dt)
    saved = contact.state
    later = range(len(t) // 3, len(t) // 2)
    ref = [contact.step(z[k], dt) for k in later]
    contact.state = saved  # the stepper's own cache: kept, the same bits
    assert [contact.step(z[k], dt) for k in later] == ref
    edited = saved.data.copy()
    assert edited[K.S_CACHE_DT] > 0.0  # a cache is there to edit
    edited[K.S_CACHE_DECAY_I] = edited[K.S_CACHE_DECAY_W] = 0.5
    fresh = mf.MudContact(params)
    fresh.state = ContactState(edited, saved.params_key, saved.ring)
    forces = [fresh.step(z[k], dt) for k in later]
    np.testing.assert_allclose(forces, ref, rtol=1e-12, atol=1e-12 * max(map(abs, ref)))
