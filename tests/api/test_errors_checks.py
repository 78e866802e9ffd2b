"""The shared checks of single values in :mod:`mudforce.errors`: what they accept, what they refuse, their messages."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import pytest

from mudforce.errors import (
    MAX_FEET,
    InputError,
    feet_count,
    finite_number,
    is_integer,
    number_within,
    positive_number,
    real_array,
    real_number,
    true_or_false,
)


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (3, 3.0),
        (-2.5, -2.5),
        (np.float64(0.25), 0.25),
        (np.float32(0.5), 0.5),
        (np.int64(7), 7.0),
        (np.uint8(255), 255.0),
        (np.array(1.5), 1.5),  # a 0-d array
        (np.array(4, dtype=np.int32), 4.0),
    ],
)
def test_real_number_accepts_python_and_numpy_reals(value: Any, expected: float) -> None:
    got = real_number(value, "depth")
    assert type(got) is float and got == expected


def test_real_number_lets_non_finite_values_through() -> None:
    """No bounds: the caller checks them."""
    assert real_number(float("inf"), "depth") == float("inf")
    assert np.isnan(real_number(float("nan"), "depth"))


@pytest.mark.parametrize(
    ("value", "type_name"),
    [
        (True, "bool"),
        (np.bool_(False), "bool"),  # numpy's bool is no real number either
        ("0.1", "str"),
        (None, "NoneType"),
        ([0.1], "list"),
        (np.array([0.1]), "ndarray"),  # not 0-d
        (np.array(True), "ndarray"),  # 0-d of kind b
        (1j, "complex"),
    ],
)
def test_real_number_refuses_with_the_type_named(value: Any, type_name: str) -> None:
    with pytest.raises(InputError) as info:
        real_number(value, "depth")
    assert str(info.value) == f"depth must be a real number, got {type_name}"


def test_finite_number_accepts_reals_and_returns_a_float() -> None:
    assert finite_number(np.int64(2), "mass", "kg") == 2.0
    assert type(finite_number(np.float32(0.5), "mass", "kg")) is float
    assert finite_number(-1.0, "gravity", "m/s^2") == -1.0


@pytest.mark.parametrize(
    ("value", "kwargs", "message"),
    [
        (True, {}, "mass must be a number [kg], got bool True"),
        ("5", {}, "mass must be a number [kg], got str '5'"),
        (None, {}, "mass must be a number [kg], got NoneType None"),
        (np.array(5.0), {}, "mass must be a number [kg], got ndarray array(5.)"),  # 0-d arrays: not here
        (float("nan"), {}, "mass must be finite [kg], got nan"),
        (float("inf"), {"positive": True}, "mass must be finite [kg], got inf"),
        (-float("inf"), {"nonnegative": True}, "mass must be finite [kg], got -inf"),
        (0.0, {"positive": True}, "mass must be > 0 [kg], got 0.0"),
        (-1e-300, {"positive": True}, "mass must be > 0 [kg], got -1e-300"),
        (-1e-300, {"nonnegative": True}, "mass must be >= 0 [kg], got -1e-300"),
        (-3, {"nonnegative": True}, "mass must be >= 0 [kg], got -3"),
    ],
)
def test_finite_number_refuses_with_exact_messages(value: Any, kwargs: dict[str, bool], message: str) -> None:
    with pytest.raises(InputError, match=f"^{re.escape(message)}$"):
        finite_number(value, "mass", "kg", **kwargs)


def test_finite_number_boundaries() -> None:
    """``positive`` excludes 0, ``nonnegative`` includes it (and -0.0); neither bounds from above."""
    assert finite_number(0.0, "height", "m", nonnegative=True) == 0.0
    assert finite_number(-0.0, "height", "m", nonnegative=True) == 0.0
    assert finite_number(5e-324, "mass", "kg", positive=True) == 5e-324
    assert finite_number(1.7e308, "mass", "kg", positive=True) == 1.7e308
    assert finite_number(-1.7e308, "gravity", "m/s^2") == -1.7e308


def test_the_checks_share_one_type_test() -> None:
    """What ``finite_number`` refuses as a type, ``number_within`` and ``positive_number`` refuse too."""
    for bad in (True, "1", None, np.bool_(True)):
        for check in (lambda v: finite_number(v, "x", "m"), lambda v: number_within(v, "x", 0.0, 2.0, "m"),
                      lambda v: positive_number(v, "x", "m")):
            with pytest.raises(InputError, match="x must be a number"):
                check(bad)
    for good in (1, 1.0, np.int16(1), np.float32(1.0)):
        assert finite_number(good, "x", "m") == number_within(good, "x", 0.0, 2.0, "m") \
            == positive_number(good, "x", "m") == 1.0


def _huge_int_calls() -> list[Any]:
    from mudforce import Foot, MudContact, MudParameters, VelocityFilter
    from mudforce.estimation.calibration.drag import fit_drag

    paper = MudParameters.from_water_content(0.25)
    return [
        (lambda v: real_number(v, "depth"), "depth must be a real number within float64's range"),
        (lambda v: finite_number(v, "mass", "kg"), "mass must be a real number within float64's range"),
        (lambda v: number_within(v, "x", 0.0, 2.0, "m"), "x must be a real number within float64's range"),
        (lambda v: positive_number(v, "x", "m"), "x must be a real number within float64's range"),
        (lambda v: MudContact(paper).step(v, 0.01), "depth must be a real number within float64's range"),
        (lambda v: paper.replace(alpha=v), "parameter alpha must be a real number within float64's range"),
        (lambda v: MudParameters.from_water_content(v), "water content must be a real number within float64's"),
        (lambda v: Foot(v, 0.03), "foot area must be a real number within float64's range"),
        (lambda v: VelocityFilter(2, v), "velocity filter deadband must be a real number within float64's range"),
        (lambda v: VelocityFilter.for_noise(v, 0.01), "noise level must be a real number within float64's range"),
        # fit_drag's refusal showed the value by its repr: ValueError (Exceeds the limit (4300 digits))
        (lambda v: fit_drag([0.01, 0.02], [1.0, 2.0], v), "area must be a real number within float64's range"),
        (lambda v: fit_drag([0.01, 0.02], [1.0, 2.0], 0.002, rho_m=v), "rho_m must be a real number within"),
    ]


@pytest.mark.parametrize("sign", [1, -1])
def test_a_python_int_beyond_float64_is_refused_in_one_line(sign: int) -> None:
    """float(10**400) raises OverflowError, which every check of a number let out (and a repr of 10**5000 raises
    ValueError, so the message gives its size, not its digits)."""
    for call, words in _huge_int_calls():
        with pytest.raises(InputError) as error:
            call(sign * 10**5000)
        assert words in str(error.value) and "integer of 16610 bits" in str(error.value), str(error.value)


def test_an_integer_of_over_4300_digits_is_shown_by_its_size_in_every_refusal_of_a_count_or_index() -> None:
    """A refusal that printed the integer itself raised ValueError instead (Python prints at most 4,300 digits):
    positive_int(-10**5000), seed_int(10**5000), synth's seed, a foot index, identify's points."""
    import mudforce as mf
    from mudforce.errors import number_within, positive_int, seed_int, shown, true_or_false
    from mudforce.estimation.calibration.dataset import Trial
    from mudforce.estimation.calibration.identify import identify_water_content
    from mudforce.estimation.calibration.synth import synthesize_gait
    from mudforce.model import shapes

    # a numpy scalar as the number it holds: a sphere of np.float64(-0.02) m was refused as "got np.float64(-0.02)"
    assert [shown(v) for v in (3, np.int64(-7), 10**20, -(10**5000), 2.5, True, np.float64(-0.0), np.float32(0.5),
                               np.bool_(True))] == [
        "3", "-7", "1e+20", "a negative integer of 16610 bits", "2.5", "True", "-0.0", "0.5", "True"]
    with pytest.raises(InputError, match=r"^sphere diameter must be within \[0.0001, 10\] m, got -0.02$"):
        shapes.sphere(np.float64(-0.02))
    feet = mf.MudContacts3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04), 2)
    t = np.arange(3) * 0.01
    for call, words in ((lambda: positive_int(-(10**5000), "n"), "n must be an integer >= 1, got a negative"),
                        (lambda: seed_int(10**5000), r"--seed must be an integer in \[0, 4294967295\], got an"),
                        (lambda: feet.element_slice(10**5000), r"foot index out of range 0..1: an integer"),
                        (lambda: mf.VelocityFilter(10**5000), r"window must be 1..64 steps, got an"),
                        (lambda: synthesize_gait(seed=-(10**5000)), "seed must be an integer >= 0, got a negative"),
                        (lambda: identify_water_content(Trial("w", 0.25, t, np.zeros(3), np.zeros(3)), points=10**5000),
                         r"points must be an integer in \[2, \d+\], got an")):
        with pytest.raises(InputError, match=words) as error:
            call()
        assert "integer of 16610 bits" in str(error.value), str(error.value)
    with pytest.raises(InputError, match=r"^quiet must be True or False, got an integer of 16610 bits$"):
        true_or_false(10**5000, "quiet")  # ValueError too
    with pytest.raises(InputError, match=r"^x must be within \[0, 1\] m, got 1e\+200$"):
        number_within(10**200, "x", 0.0, 1.0, "m")  # its 201 digits


@pytest.mark.parametrize("bad", ["x", None, True, float("nan"), -1.0])
def test_velocity_filter_refuses_a_deadband_that_is_not_a_number(bad: object) -> None:
    from mudforce import VelocityFilter

    with pytest.raises(InputError, match="deadband must be finite and >= 0"):
        VelocityFilter(3, bad)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="noise level must be finite and >= 0"):
        VelocityFilter.for_noise(bad, 0.01)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="velocity window must be finite and > 0"):
        VelocityFilter.for_noise(1e-4, 0.01, bad)  # type: ignore[arg-type]


def test_true_or_false_takes_only_booleans() -> None:
    assert true_or_false(True, "quiet") is True and true_or_false(np.bool_(False), "quiet") is False
    for bad in ("no", None, 0, 1, 1.0, np.array([True])):
        with pytest.raises(InputError, match=r"^quiet must be True or False, got "):
            true_or_false(bad, "quiet")


def test_is_integer_takes_python_and_numpy_integers_only() -> None:
    """The one integer test of the package's counts, seeds and indices (identify's points, gait's seed, a dataset's
    repeat, MudContact3D.element_slice's foot): a bool, a float (even a whole one) or a 0-d array is not one."""
    assert all(is_integer(x) for x in (0, -3, 2**70, np.int64(5), np.uint8(1), np.int32(-1)))
    assert not any(is_integer(x) for x in (True, np.bool_(False), 1.0, 0.7, np.float64(2.0), np.array(3), "1", None))


def _boolean_options(tmp: Any) -> dict[str, Any]:
    """Each public boolean option, as a call taking its value."""
    import mudforce as mf
    from mudforce.estimation.calibration.dataset import Dataset, Trial
    from mudforce.estimation.calibration.drag import fit_drag
    from mudforce.estimation.calibration.fit import fit_by_velocity, fit_dataset
    from mudforce.estimation.calibration.preprocess import prepare_trial
    from mudforce.estimation.tracker import MudTrackers
    from mudforce.io.tables import write_csv
    from mudforce.model import shapes
    from mudforce.motions.gait import gait, walk
    from mudforce.reproduce.experiments import ReproduceConfig
    from mudforce.reproduce.report import reproduce
    from mudforce.steppers.contact3d import simulate_3d

    t = np.arange(3) * 0.01
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (3, 1))
    mud = mf.MudParameters.from_water_content(0.25)
    result = mf.simulate(t, np.array([-1e-3, 0.0, 1e-3]), mud)
    path = walk(0.25, seed=0, duration=2.0)
    trial = Trial("w", 0.25, path.time, path.depth, path.force)
    return {
        "elements": lambda v: simulate_3d(t, np.zeros((3, 3)), quat, mud, shapes.sphere(0.04), elements=v),
        "quiet (to_csv)": lambda v: result.to_csv(tmp / "r.csv", quiet=v),
        "quiet (write_csv)": lambda v: write_csv(tmp / "w.csv", {"a": np.zeros(2)}, quiet=v),
        "quiet (fit_dataset)": lambda v: fit_dataset(Dataset(mf.Foot.paper(), (trial,)), quiet=v),
        "quiet (fit_by_velocity)": lambda v: fit_by_velocity(Dataset(mf.Foot.paper(), (trial,)), quiet=v),
        "quiet (reproduce)": lambda v: reproduce(tmp / "report", quiet=v),
        "intercept": lambda v: fit_drag(np.linspace(0.01, 0.05, 5), np.linspace(1.0, 2.0, 5), area=0.002,
                                        rho_m=1500.0, intercept=v),
        "start_below (gait)": lambda v: gait(0, start_below=v),
        "start_below (walk)": lambda v: walk(0.25, seed=0, start_below=v),
        "quick": lambda v: ReproduceConfig(quick=v),
        "twin": lambda v: MudTrackers(1, twin=v),
        "protocol": lambda v: prepare_trial(trial, protocol=v),
    }


@pytest.mark.parametrize("bad", ["no", None, 0, np.array([True])])
def test_boolean_options_refuse_anything_but_true_or_false(bad: Any, tmp_path: Any) -> None:
    """A boolean option was read by its truth value: simulate_3d(..., elements="no") returned the elements'
    forces, quiet="no" silenced a write, protocol=0 meant "decide" (as None); now each is refused in one line,
    before anything is written."""
    for name, call in _boolean_options(tmp_path).items():
        if bad is None and name == "protocol":
            continue  # protocol's None is its documented default (decide from the trial)
        option = name.split(" ")[0]
        with pytest.raises(InputError, match=rf"{option} must be True(, False or None| or False), got ") as info:
            call(bad)
        assert "\n" not in str(info.value), name
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing written


def test_boolean_options_take_numpy_booleans(tmp_path: Any) -> None:
    options = _boolean_options(tmp_path)
    for name in ("elements", "quiet (write_csv)", "intercept", "start_below (gait)", "quick", "twin"):
        options[name](np.bool_(True))
    assert options["elements"](np.bool_(True)).element_forces is not None


def test_a_count_of_feet_past_ten_million_is_refused_in_one_line_before_anything_is_allocated() -> None:
    """``feet_count``, which every stepper and tracker of many feet takes its ``n`` through: before, 10**30 feet
    raised numpy's OverflowError and 10**12 its MemoryError."""
    import mudforce as mf
    from mudforce.model import shapes

    assert feet_count(MAX_FEET) == MAX_FEET == 10**7 and feet_count(np.int64(3)) == 3
    mud = mf.MudParameters.from_water_content(0.25)
    for n, shown in ((MAX_FEET + 1, "10000001"), (10**30, "1e+30"), (10**5000, "an integer of 16610 bits")):
        for make, args in ((mf.MudContacts, (mud, n)), (mf.MudContacts3D, (mud, shapes.sphere(0.04), n)),
                           (mf.MudTrackers, (n,))):
            with pytest.raises(InputError) as info:
                make(*args)
            assert str(info.value) == f"the number of feet n must be at most 10000000 (one object's feet), got {shown}"
    for bad in (0, True, 2.0):
        with pytest.raises(InputError, match=r"^the number of feet n must be an integer >= 1, got "):
            feet_count(bad)


def _calls_of_a_value() -> list[Any]:
    import mudforce as mf
    from mudforce.errors import positive_int
    from mudforce.model import baselines
    from mudforce.model.bounds import bounded_depth

    w25 = mf.MudParameters.from_water_content(0.25)
    t = np.arange(5) * 0.01
    return [lambda v: finite_number(v, "x", "m", positive=True), lambda v: positive_int(v, "n"),
            lambda v: positive_number(v, "d", "s"), lambda v: mf.MudContacts(w25, v), mf.VelocityFilter,
            lambda v: mf.VelocityFilter(2, v), lambda v: mf.VelocityFilter.for_noise(v, 0.01),
            lambda v: w25.replace(beta=v), lambda v: baselines.granular_rft_force(t, t, v),
            lambda v: baselines.maxwell_only_force(t, t, v, 1.0, 1.0, 1.0), lambda v: bounded_depth(v, "h")]


@pytest.mark.parametrize("value", [np.zeros((3, 3)), -(10**300), "64 feet"], ids=["2-D array", "-10**300", "64 feet"])
def test_a_refused_value_is_shown_in_one_short_line(value: Any) -> None:
    """The messages printed the value's repr: a 2-D array's spans lines, -10**300 ran to 301 digits, and a list of
    64 Foot objects (given where MudContacts takes n) to 4,658 characters (shown() gives the one line, the size,
    and a long repr's start with what it is)."""
    if isinstance(value, str):
        import mudforce as mf

        value = [mf.Foot.paper()] * 64
    for call in _calls_of_a_value():
        with pytest.raises(InputError) as error:
            call(value)
        assert "\n" not in str(error.value) and len(str(error.value)) < 200, str(error.value)


def test_a_long_repr_is_shown_by_its_start_and_what_it_is() -> None:
    """shown() keeps a repr of up to 160 characters whole and cuts a longer one to its first 80 and its type and
    size; MudContacts given a list of 64 feet where it takes n names what it got in one short line."""
    import mudforce as mf
    from mudforce.errors import shown

    assert shown(list(range(40))) == repr(list(range(40)))
    assert shown(list(range(1000))) == repr(list(range(1000)))[:80] + "... (a list of 1000 items)"
    assert shown("x" * 500) == repr("x" * 500)[:80] + "... (a str of 500 characters)"
    with pytest.raises(InputError) as error:
        mf.MudContacts(mf.MudParameters.from_water_content(0.25), [mf.Foot.paper()] * 64)  # type: ignore[arg-type]
    assert str(error.value).endswith("... (a list of 64 items)") and len(str(error.value)) < 200


@pytest.mark.parametrize(("value", "got"), [
    ([1.0, 2j], "complex values (dtype complex128)"),
    ([1.0, True], "a sequence holding booleans (True/False among the numbers)"),
    (np.ma.masked_array([1.0, 2.0], mask=[True, False]),
     "a masked array with 1 masked value(s); fill or drop them first"),
    ([[1.0], [1.0, 2.0]], "list"),
])
def test_real_array_words_its_refusal_in_the_callers_words(value: Any, got: str) -> None:
    """A caller that expects something narrower (3 numbers) passes its words; they replace "<name> must be an array
    of real numbers [<unit>]" before ", got ...", which callers cut off the message and replaced before."""
    with pytest.raises(InputError, match=f"^{re.escape(f'time must be an array of real numbers [s], got {got}')}$"):
        real_array(value, "time", "s")
    with pytest.raises(InputError, match=f"^{re.escape(f'position must be 3 real numbers [m], got {got}')}$"):
        real_array(value, "position", "m", must="position must be 3 real numbers [m]")
