"""Bounds and types at the dynamics' public entry points (InputError, nothing changed), and honest results."""

from __future__ import annotations

import importlib.util
from typing import Any

import numpy as np
import pytest

import mudforce.engines.dynamics as dyn
from mudforce import Foot, MudParameters
from mudforce import _kernel as K
from mudforce.engines.dynamics import FootResult, Phase, exact_drop, naive_drop, simulate_foot
from mudforce.errors import InputError

W25 = MudParameters.from_water_content(0.25)
HAS_MUJOCO = importlib.util.find_spec("mujoco") is not None
needs_mujoco = pytest.mark.skipif(not HAS_MUJOCO, reason="mujoco is not installed")


def test_phase_names_and_codes_are_stable() -> None:
    # (the module's __all__ is pinned in tests/api/test_public_all.py)
    # the CSV's state column and the phase codes are what they were
    assert dyn.PHASE_NAMES == ("FREE", "INTRUSION", "WITHDRAWAL", "STUCK", "NECKED")
    assert [int(p) for p in Phase] == [0, 1, 2, 3, 4]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"mass": "5"}, "mass must be a number"),
        ({"mass": None}, "mass must be a number"),
        ({"mass": True}, "mass must be a number"),
        ({"mass": float("nan")}, "mass must be finite"),
        ({"mass": 1e-6}, "too light"),  # was NaN (W = 25%) or -1e62 m (W = 15%)
        ({"mass": 1e-300}, "too light"),
        ({"params": "mud"}, "MudParameters"),
        ({"foot": 0.002}, "foot must be a Foot"),
        ({"duration": "8s"}, "duration must be a number"),
        ({"duration": 1e12}, "too many"),
        ({"dt": 0.0}, "dt must be > 0"),
        ({"substeps": 2.5}, "substeps"),
        ({"substeps": 10**400}, r"substeps must be an integer in \[1, 1000000\]"),  # was OverflowError
        ({"dt": 1e308, "substeps": 10**400}, r"dt must be within \[1e-09, 1000\] s"),  # was OverflowError
        ({"substeps": 10**7}, r"an RK4 sub-step dt / substeps of at least 1e-09 s"),  # a 0.1 ns step: was taken
        ({"height": [0.0]}, "height must be a number"),
        ({"height": -200.0}, r"height must be within \+-100 m of the mud surface, got -200.0"),  # was taken
        ({"height": 200.0}, r"height must be within \+-100 m"),
        ({"velocity0": float("inf")}, "velocity0 must be finite"),
        # a foot leaving the model's depth bound was returned: 1e6 m/s sent it 27 km, -900 m/s 1.78 km up (2 s)
        ({"velocity0": 1e6, "duration": 2.0}, r"velocity0 must be within \[-1000, 1000\] m/s, got 1000000.0"),
        ({"velocity0": -900.0, "duration": 2.0}, r"foot leaves the model's depth bound \(\+-100 m of the mud surf"),
        ({"gravity": "g"}, "gravity must be a number"),
        # model.bounds.check_gravity: 1e200 was refused as "not finite ... use a heavier foot"; MuJoCo's sign,
        # -9.81, was taken and threw the 5 kg foot 1.23 m up in 0.5 s
        ({"gravity": 1e200}, r"^gravity must be within \[0, 10000\] m/s\^2 \(positive pulls the foot down, into the "),
        ({"gravity": -9.81}, r"^gravity must be within \[0, 10000\] m/s\^2 .*, got -9.81$"),
        ({"gravity": float("nan")}, "^gravity must be finite"),
        ({"applied_force": "push"}, "applied_force"),
        ({"applied_force": 10**400}, r"applied force must be a real number within float64's range"),  # OverflowError
        ({"applied_force": ("01", "23")}, r"applied_force times must be an array of real numbers \[s\], got string"),
        ({"applied_force": ([0.0, 0.005], [True, False])},  # was parsed, read as 0 and 1
         r"applied_force forces must be an array of real numbers \[N\], got boolean"),
        # a step of inf s (numpy's overflow warning): the force's slope 0, 1 N held where 1.5 N was asked
        ({"applied_force": ([-1e308, 1e308], [1.0, 2.0])}, r"applied_force times must be finite and strictly incr"),
    ],
)
def test_simulate_foot_refuses(kwargs: dict[str, Any], message: str) -> None:
    args: dict[str, Any] = {"mass": 5.0, "params": W25, "duration": 0.01, **kwargs}
    with pytest.raises(InputError, match=message):
        simulate_foot(args.pop("mass"), args.pop("params"), **args)


def test_lightest_stable_foot_is_simulated_and_accurate() -> None:
    """Just above the bound (S max(k) h^2 = 2.3e-5 kg at W = 25%) the engine still follows the exact drop."""
    res = simulate_foot(3e-5, W25, duration=0.2)
    ref = exact_drop(3e-5, W25, duration=0.2)
    assert np.isfinite(res.depth).all() and res.at_rest
    assert res.rest_depth == pytest.approx(ref.rest_depth, rel=0.05)


def test_a_diverging_solution_is_refused_not_returned() -> None:
    """Where no bound can be stated (a pull beyond any float), the non-finite output is refused."""
    with pytest.raises(InputError, match="not finite from t = "):
        simulate_foot(5.0, W25, duration=0.01, applied_force=1e308)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: naive_drop("5", W25), "mass must be a number"),
        (lambda: naive_drop(5.0, W25, dt=-1e-3), "dt must be > 0"),
        (lambda: naive_drop(5.0, None), "MudParameters"),  # type: ignore[arg-type]
        # the stepper's bounds: each was "the naive engine's solution is not finite ... use a heavier foot"
        (lambda: naive_drop(5.0, W25, duration=0.01, height=-200.0), r"height must be within \+-100 m"),
        (lambda: naive_drop(5.0, W25, duration=1e-6, dt=1e-12), r"dt must be within \[1e-09, 1000\] s"),
        (lambda: naive_drop(5.0, W25, duration=0.01, gravity=1e200), r"gravity must be within \[0, 10000\] m/s\^2"),
        (lambda: naive_drop(5.0, W25, duration=0.01, gravity=-9.81), r"gravity must be within \[0, 10000\] m/s\^2"),
        # shorter than one step: an empty NaiveDrop was returned (under half a step), or the start alone
        (lambda: naive_drop(5.0, W25, duration=1e-3, dt=1e-2), r"duration 0.001 s is shorter than one step"),
        (lambda: naive_drop(5.0, W25, duration=6e-3, dt=1e-2), r"duration 0.006 s is shorter than one step"),
        (lambda: simulate_foot(5.0, W25, duration=5e-4), r"duration 0.0005 s is shorter than one step \(dt = 0.001"),
        (lambda: exact_drop(5.0, W25, duration=5e-4), r"duration 0.0005 s is shorter than one step \(dt = 0.001"),
        (lambda: exact_drop(5.0, W25, height=-0.01), "height must be >= 0"),
        # the engines' gravity bound (model.bounds.check_gravity): 1e200 raised IndexError, 1e6 sank 1.9 km in 0.2 s
        (lambda: exact_drop(5.0, W25, gravity=1e200), r"^gravity must be within \[0, 10000\] m/s\^2"),
        (lambda: exact_drop(5.0, W25, gravity=1e6), r"^gravity must be within \[0, 10000\] m/s\^2"),
        (lambda: exact_drop(5.0, W25, gravity=0.0), r"^gravity must be > 0 \[m/s\^2\] for the exact drop, got 0$"),
        (lambda: exact_drop(5.0, W25, gravity=-9.81), r"^gravity must be within \[0, 10000\] m/s\^2"),
        (lambda: exact_drop("5", W25), "mass must be a number"),
        (lambda: exact_drop(5.0, W25, foot="cube"), "foot must be a Foot"),  # type: ignore[arg-type]
        # a release from 1e12 m was taken (and simulated as a foot that never arrives), simulate_foot's bound not
        (lambda: exact_drop(5.0, W25, height=1e12), r"height must be within \+-100 m of the mud surface"),
        # scipy's "rtol is too small" UserWarning (then 2.2e-14 silently), and a tolerance of 1e12 taken
        (lambda: exact_drop(5.0, W25, rtol=1e-300), r"rtol must be within \[1e-13, 0.1\] -, got 1e-300"),
        (lambda: exact_drop(5.0, W25, rtol=1e12), r"rtol must be within \[1e-13, 0.1\]"),
    ],
)
def test_other_entry_points_refuse_bad_types(call: Any, message: str) -> None:
    with pytest.raises(InputError, match=message):
        call()


def test_a_moving_foot_has_no_rest_depth() -> None:
    """Still falling at the end: not at rest, rest_depth NaN, end_depth the last sample's depth."""
    moving = simulate_foot(5.0, W25, duration=0.05)
    assert not moving.at_rest and moving.velocity[-1] > 0.1
    assert np.isnan(moving.rest_depth) and moving.end_depth == moving.depth[-1]
    # a creeping foot (stick-slip, W = 25%, 15 kg) that is sliding at the end is not at rest either
    creep = FootResult(np.arange(3.0), np.full(3, 0.05), np.array([0.0, 0.0, 8e-4]), np.zeros(3),
                       np.array([Phase.STUCK, Phase.STUCK, Phase.INTRUSION], dtype=np.int8), 15.0)
    assert not creep.at_rest and np.isnan(creep.rest_depth)
    held = simulate_foot(5.0, W25, duration=3.0)
    assert held.at_rest and held.rest_depth == held.depth[-1] > 0.0


def test_the_exact_drop_has_a_rest_depth_only_at_rest() -> None:
    """exact_drop's rest_depth follows the engines' rule: NaN unless stuck at the end; end_depth always.

    At 100 m/s^2 the 5 kg paper foot is thrown back out of W = 25 % mud and is in flight at 0.5 s (measured:
    end depth -0.358 m, simulate_foot within 2e-6 m); the old rest_depth returned that flight depth.
    """
    held = exact_drop(5.0, W25, duration=0.5)
    assert held.at_rest and held.rest_depth == held.end_depth == held.depth[-1] > 0.0
    thrown = exact_drop(5.0, W25, duration=0.5, gravity=100.0)
    assert not thrown.at_rest and np.isnan(thrown.rest_depth) and thrown.end_depth < -0.3
    assert thrown.end_depth == pytest.approx(simulate_foot(5.0, W25, duration=0.5, gravity=100.0).end_depth,
                                             abs=1e-5)
    # a load too small for DOP853's tolerances stalls at t = 0: one line at once, not 10,000 phases (35 s)
    with pytest.raises(InputError, match=r"cannot follow this drop .* load m g = 5e-09 N"):
        exact_drop(5.0, W25, duration=0.5, gravity=1e-9)


@needs_mujoco
def test_mujoco_entry_points_refuse() -> None:
    import mujoco

    from mudforce.engines.mujoco import MudAdapter, MudPatch, _drop_spec, add_mud, drop_model, simulate_drop

    with pytest.raises(InputError, match="too light"):
        simulate_drop(1e-300, W25, duration=0.01)  # was a traceback from MuJoCo's compiler
    with pytest.raises(InputError, match="too light"):
        simulate_drop(1e-3, W25, duration=0.01)  # was a foot thrown 16 km up
    with pytest.raises(InputError, match="height must be >= 0"):
        simulate_drop(5.0, W25, height=-0.01)
    with pytest.raises(InputError, match=r"duration 0.0005 s is shorter than one step"):
        simulate_drop(5.0, W25, duration=5e-4)  # was the start alone
    for call in (lambda: simulate_drop(5.0, W25, height=1e12), lambda: drop_model(5.0, height=1e308)):
        with pytest.raises(InputError, match=r"height must be within \+-100 m of the mud surface"):
            call()  # were taken: a foot 1e12 m up, at -1e308 m depth
    with pytest.raises(InputError, match=r"^thickness must be within \[1e-06, 100\] m, got 1e-12"):
        drop_model(5.0, thickness=1e-12)  # was MuJoCo's ValueError "mass and inertia ... larger than mjMINVAL"
    with pytest.raises(InputError, match=r"^dt must be within \[1e-09, 1000\] s, got 1e-300"):
        drop_model(5.0, dt=1e-300)  # was taken
    with pytest.raises(InputError, match="mass must be a number"):
        drop_model("5")
    with pytest.raises(InputError, match="patch surface_height must be a number"):
        MudPatch(W25, surface_height="0")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="patch extent"):
        MudPatch(W25, extent=(0.0, 1.0))  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"spec must be a mujoco\.MjSpec"):
        add_mud("robot.xml", ["foot"])
    spec = _drop_spec(5.0, None, 0.0, 1e-3, 0.025)
    before = spec.to_xml()
    with pytest.raises(InputError, match="no geom or body named 'nope'"):
        add_mud(spec, ["foot", "nope"])  # the first name is valid: still nothing is added
    assert spec.to_xml() == before
    with pytest.raises(InputError, match="feet must be"):
        add_mud(spec, [3])  # type: ignore[list-item]
    model = spec.compile()
    data = mujoco.MjData(model)
    with pytest.raises(InputError, match="patches must be"):
        MudAdapter(model, data, ["sole"], W25)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="foot must be"):
        MudAdapter(model, data, ["sole"], MudPatch(W25), foot=0.002)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="model and data"):
        MudAdapter(data, model, ["sole"], MudPatch(W25))
    mud = MudAdapter(model, data, ["sole"], MudPatch(W25), Foot.paper())
    with pytest.raises(InputError, match="weight must be in"):
        mud.weight = 2.0
    with pytest.raises(InputError, match=r"weight must be in \[0, 1\] \[-\], got an integer of 997 bits$"):
        mud.weight = 10**300  # was its 301 digits
    with pytest.raises(InputError, match="nstep"):
        mud.step(0.5)  # type: ignore[arg-type]
    mud.step(5)
    # the state is a read-only snapshot: looking cannot change the simulation, and it does not follow it
    snapshot = mud.state
    with pytest.raises(ValueError, match="read-only"):
        snapshot[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        mud.params[0, 0] = 1.0
    mud.step()
    assert K.state_column(mud.state, "time")[0] > K.state_column(snapshot, "time")[0]
    # a refused restore changes nothing
    before = mud.state
    garbage = np.array(before)
    garbage[0, 1] = 7.0  # the mode column (kernel layout)
    for bad in (garbage, before[:, :3], None):
        with pytest.raises(InputError, match="state"):
            mud.state = bad  # type: ignore[assignment]
        assert np.array_equal(mud.state, before)
    late = np.array(before)
    K.state_column(late, "time")[0] = 1e308  # was taken (check_states refuses only a negative time)
    with pytest.raises(InputError, match=r"^a state: time is beyond 1e\+09 s; expected a state taken from a contact$"):
        mud.state = late
    assert np.array_equal(mud.state, before)
    # text, booleans and complex numbers are no state (np.asarray parsed the text, took an all-True array for a
    # contact at 1 m, and dropped the imaginary parts with a warning only)
    for bad in (before.astype(str), np.ones(before.shape, dtype=bool), before.astype(complex)):
        with pytest.raises(InputError, match=r"^a state of 1 feet \(from MudAdapter.state\) must be an array of real"):
            mud.state = bad
        assert np.array_equal(mud.state, before)


def test_result_methods_refuse_bad_types(tmp_path: Any) -> None:
    res = simulate_foot(5.0, W25, duration=0.01)
    with pytest.raises(InputError, match="path must be a file path"):
        res.to_csv(123)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="last must be a number"):
        res.force_std("1")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="path must be a file path"):
        res.plot(123)  # type: ignore[arg-type]
    # 'foot.pdf' was written with PNG bytes; refused before drawing (io.check_output_path), as plot_result does
    with pytest.raises(InputError, match=r"^path: '.*foot.pdf' must end in .png \(only PNG is written\)$"):
        res.plot(tmp_path / "foot.pdf")
    assert list(tmp_path.iterdir()) == []


@needs_mujoco
def test_a_step_count_below_one_or_beyond_mujoco_s_int_is_refused_by_both_adapters() -> None:
    """MudAdapter.step(0) and step(-1) (and MudAdapter3D's) returned having done nothing: a plain int skipped the
    check that a float or a numpy integer gets; now every count below 1 is refused, and nothing moves. So is one
    beyond MuJoCo's C int, which mj_step's own nstep refuses."""
    import mujoco

    from mudforce.engines.mujoco import MudAdapter, MudAdapter3D, MudPatch, _drop_spec
    from mudforce.engines.mujoco.adapter3d import drop_model_3d

    model = _drop_spec(5.0, None, 0.0, 1e-3, 0.025).compile()
    data = mujoco.MjData(model)
    model_3d = drop_model_3d(2.0, "sphere", (0.04,), dt=2e-3)
    data_3d = mujoco.MjData(model_3d)
    adapters = [(MudAdapter(model, data, ["sole"], MudPatch(W25)), data),
                (MudAdapter3D(model_3d, data_3d, ["foot"], MudPatch(W25)), data_3d)]
    for mud, state in adapters:
        mud.step(1)
        before = (float(state.time), np.array(state.qpos))
        for bad in (0, -1, np.int64(0)):
            with pytest.raises(InputError, match=r"^nstep must be an integer >= 1, got "):
                mud.step(bad)
        for bad in (2**31, 10**30, np.int64(2**40)):  # 10**30 was taken and stepped for ever (mj_step: a C int)
            with pytest.raises(InputError, match=r"^nstep must be at most 2147483647 \(MuJoCo's mj_step takes a C"):
                mud.step(bad)
        assert (float(state.time), np.array(state.qpos).tolist()) == (before[0], before[1].tolist())


@needs_mujoco
def test_a_restored_mud_adapter_state_leaves_xfrc_applied_alone_and_replays_bit_for_bit() -> None:
    """MudAdapter.state = saved took the coming step's mid-band force from data.xfrc_applied (16.4 N on a 5 kg sole
    after 30 steps, once more at each restore), which then pushed the foot at every later step: a replay with
    mj_setState had differed by 142 N within 200 steps."""
    import mujoco

    from mudforce.engines.mujoco import MudAdapter, MudPatch, drop_model

    model = drop_model(5.0)
    data = mujoco.MjData(model)
    mud = MudAdapter(model, data, ["sole"], MudPatch(W25))
    mud.step(30)
    kind = mujoco.mjtState.mjSTATE_INTEGRATION
    physics = np.empty(mujoco.mj_stateSize(model, kind))
    mujoco.mj_getState(model, data, physics, kind)
    saved = mud.state
    mud.state = saved
    assert not data.xfrc_applied.any()

    def run() -> list[float]:
        out = []
        for _ in range(50):
            mud.step()
            out += [float(data.qpos[0]), float(mud.contact_forces[0])]
        return out

    first = run()
    mujoco.mj_setState(model, data, physics, kind)
    mud.state = saved
    assert run() == first


@needs_mujoco
def test_both_adapters_refuse_the_data_of_another_model() -> None:
    """MudAdapter(model, data) with the data of another model was taken, and MuJoCo stepped the model on it without
    a word (the sole's slide moved the x of a sphere's free joint); MudAdapter3D's steps ended in NaN with MuJoCo's
    "unstable" warning. Now refused when made, as a swapped model and data are."""
    import mujoco

    from mudforce.engines.mujoco import MudAdapter, MudAdapter3D, MudPatch, drop_model
    from mudforce.engines.mujoco.adapter3d import drop_model_3d

    model, model_3d = drop_model(5.0), drop_model_3d(2.0, "sphere", (0.04,))
    with pytest.raises(InputError, match=r"^data is not this model's mujoco.MjData: its qpos has 7 rows, the mod"):
        MudAdapter(model, mujoco.MjData(model_3d), ["sole"], MudPatch(W25))
    with pytest.raises(InputError, match=r"^data is not this model's mujoco.MjData: its qpos has 1 rows, the mod"):
        MudAdapter3D(model_3d, mujoco.MjData(model), ["foot"], MudPatch(W25))
    MudAdapter(model, mujoco.MjData(drop_model(2.0)), ["sole"], MudPatch(W25))  # another model's of its sizes: taken


@needs_mujoco
def test_add_mud_twice_for_a_foot_is_refused_and_changes_nothing() -> None:
    """add_mud on a foot that already has mud raised MuJoCo's ValueError ("Error: repeated name 'mud_site_sole'
    in site") after the feet before it had been given their sites and tendons; now refused in one line, as
    add_mud_3d refuses it, before the spec changes."""
    from mudforce.engines.mujoco import _drop_spec, add_mud

    spec = _drop_spec(5.0, None, 0.0, 1e-3, 0.025)  # its "sole" has mud already
    spec.worldbody.add_body(name="other").add_geom(name="toe", size=[0.01, 0.01, 0.01])
    before = spec.to_xml()
    for feet in (["sole"], ["toe", "sole"]):
        with pytest.raises(InputError, match=r"^the model already has 'mud_site_sole': add_mud was called twice"):
            add_mud(spec, feet)
        assert spec.to_xml() == before
    add_mud(spec, ["sole"], prefix="more_")  # another prefix is another set of names


@needs_mujoco
@pytest.mark.parametrize("extent", [{0: 1.0, 1: 2.0, 2: 3.0, 3: 4.0}, {0.0, 1.0, 2.0, 3.0},
                                    (v for v in (0.0, 1.0, 0.0, 1.0)), "abcd", np.zeros((2, 2))])
def test_a_patch_extent_that_is_no_sequence_of_four_is_refused(extent: Any) -> None:
    from mudforce.engines.mujoco import MudPatch

    # a dict's keys and a set's members were taken as the bounds; a generator was checked, then kept exhausted
    with pytest.raises(InputError, match=r"^patch extent must be \(xmin, xmax, ymin, ymax\) \[m\], got"):
        MudPatch(W25, extent=extent)


@needs_mujoco
@pytest.mark.parametrize("bad", [[10**5000], np.array(["sole"] * 30)], ids=["10**5000", "30 names"])
def test_refused_feet_patches_and_extents_are_shown_in_one_line_whatever_they_hold(bad: Any) -> None:
    """A list holding 10**5000 raised ValueError ("Exceeds the limit (4300 digits)") from the message's repr in place
    of the refusal of add_mud's feet, a patch extent or MudAdapter3D's patches, and an array's repr spanned lines."""
    import mujoco

    from mudforce.engines.mujoco import MudAdapter3D, MudPatch, _drop_spec, add_mud

    spec = _drop_spec(5.0, None, 0.0, 1e-3, 0.025)
    model = spec.compile()
    for call, words in ((lambda: add_mud(spec, bad), "feet must be a name"),
                        (lambda: MudPatch(W25, extent=bad), r"patch extent must be \(xmin"),
                        (lambda: MudAdapter3D(model, mujoco.MjData(model), ["sole"], bad), "patches must be a")):
        with pytest.raises(InputError, match=f"^{words}") as error:
            call()
        assert "\n" not in str(error.value) and len(str(error.value)) < 600, str(error.value)


@needs_mujoco
def test_a_patch_keeps_its_extent_as_given_then() -> None:
    from mudforce.engines.mujoco import MudPatch

    bounds = [0.0, 1.0, -1.0, 1.0]
    patch = MudPatch(W25, extent=bounds)  # type: ignore[arg-type]
    bounds[1] = -5.0  # the list's later edits do not reach the patch that checked it
    assert patch.extent == (0.0, 1.0, -1.0, 1.0)
    assert MudPatch(W25, extent=np.array([0.0, 1.0, -1.0, 1.0])) == patch  # type: ignore[arg-type]


@needs_mujoco
@pytest.mark.parametrize("height", [1e12, -1e12, 1e300, 100.5])
def test_a_patch_surface_beyond_the_depth_bound_is_refused(height: float) -> None:
    from mudforce.engines.mujoco import MudPatch

    # the 1-D adapter took it (1e300: a force of 2e164 N and MuJoCo's "Nan, Inf or huge value" warning); the 3-D
    # adapter refused it only when it was built
    with pytest.raises(InputError, match=r"^patch surface_height must be within \+-100 m"):
        MudPatch(W25, height)
    assert MudPatch(W25, np.float64(-100.0)).surface_height == -100.0


@needs_mujoco
@pytest.mark.parametrize("points", [[{0.0, 1.0, 2.0}], [{0: 0.0, 1: 0.0, 2: 0.0}], {0: (0.0, 0.0, 0.0)}, "xyz",
                                    [[0.0, 0.0]], [[0.0, 0.0, float("nan")]], [[True, 0.0, 0.0]],
                                    [[0.0, 0.0, 1e308]], [[-100.5, 0.0, 0.0]]])  # the last two were taken
def test_add_mud_refuses_contact_points_that_are_no_triples_of_numbers(points: Any) -> None:
    from mudforce.engines.mujoco import _drop_spec, add_mud

    spec = _drop_spec(5.0, None, 0.0, 1e-3, 0.025)
    before = spec.to_xml()
    with pytest.raises(InputError, match=r"^(points|contact point) must be"):
        add_mud(spec, ["sole"], points=points)  # a set's members (in set order) or a dict's keys were the point
    assert spec.to_xml() == before
