"""Every path through the model, one suite (issue 19): the same trajectories and the same drops through each.

The control flow is written twice (scalar in numba, arrays in JAX) and the engines couple it with dynamics
in their own ways; the physics is written once (``mudforce.model``). This module runs the same prescribed
trajectories through every trajectory path and the same drops through every drop path, and holds each path
to the tolerance stated for it in one table, :data:`PATHS` (docs/model.md, "Conformance: every path, one
suite", lists it too). Tests are parametrised over the paths, so a failure names its path; a path whose
optional package is missing is skipped. Each path's outputs are computed once (module fixtures), the JAX
trajectories in one compilation and the MJX drops as four feet of one world, in one compilation.

Tolerances are a little above what was measured (on x86-64 Linux, float64), never above what a path's own
tests and docs promise; the "measured" figures are in each row's ``why``.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pytest

import mudforce as mf
from jax_compile import light_jit
from mudforce.engines.dynamics import REST_SPEED, FootResult, Phase, simulate_foot
from mudforce.model import shapes
from mudforce.motions.gait import gait
from mudforce.references.drop import GRAVITY, ExactDrop, exact_drop
from mudforce.references.trajectory import reference_simulate


@dataclass(frozen=True)
class PathSpec:
    """One path through the model and the tolerances it is held to.

    Trajectory paths are compared with batch :func:`mudforce.simulate` (exact branch rule): ``force`` is the
    largest force difference as a fraction of the trajectory's peak ``|force|`` [-]; ``modes`` whether the
    contact state (FREE, CONTACT, NECKED) must equal batch's at every sample; ``neck`` the largest difference of
    the necking instants [s] (``None``: the path reports the sample of a neck, which must be the sample whose
    step holds batch's instant). Drop paths are compared with the exact drop
    (:func:`mudforce.references.drop.exact_drop`): ``depth`` is the largest depth difference over the drop as a
    fraction of the exact drop's deepest point [-]; ``end`` the relative difference of the depth at the end [-];
    ``force`` the relative difference of the mean force over the last 0.1 s from the weight ``m g``, for drops
    at rest there [-]; ``neck`` how late the first NECKED sample may come after the exact necking instant [s].
    """

    kind: str  # "trajectory" or "drop"
    code: str  # what it runs
    why: str
    force: float = 0.0
    modes: bool = False
    neck: float | None = None
    depth: float = 0.0
    end: float = 0.0


# ------------------------------------------------------------------------------------------------ the table
PATHS: dict[str, PathSpec] = {
    # -- prescribed trajectories, against batch `simulate` (exact rule), the reference of this half
    "batch": PathSpec(
        "trajectory", "mudforce.simulate(time, depth, params, velocity_filter='exact')",
        "the reference of the trajectories: the compiled loop over the state machine's advance",
        force=0.0, modes=True, neck=0.0),
    "stream": PathSpec(
        "trajectory", "MudContact(params).step(z, dt), one sample a call",
        "bit for bit: the same compiled advance; a neck on the sample whose step holds batch's instant",
        force=0.0, modes=True, neck=None),
    "many": PathSpec(
        "trajectory", "MudContacts([params, W35], 2).step(depths, dt); the second foot on other mud",
        "bit for bit: the same advance per foot, each foot its own mud row (the second foot checked against "
        "its own batch run)", force=0.0, modes=True),
    "jax": PathSpec(
        "trajectory", "mudforce.jax.step under jit and lax.scan, float64 on JAX's CPU backend, dt per foot",
        "the control flow written again for arrays; README and docs/gpu.md promise 1e-12 of the peak for steps "
        "of 0.1 ms and longer (measured: at most 5.2e-15)", force=1e-12, modes=True),
    "reference": PathSpec(
        "trajectory", "mudforce.references.trajectory.reference_simulate (solve_ivp, events located)",
        "an independent integration of the ODEs; docs/model.md says about 1e-11 of the peak (measured: at most "
        "1.0e-12; necking instants 3e-15 s)", force=1e-10, modes=True, neck=1e-9),
    "3d": PathSpec(
        "trajectory", "MudContact3D(params, shapes.sole(Foot.paper())).step, moved straight up and down",
        "the law per surface element is the paper's for a flat sole moved vertically: the vertical force to "
        "1e-9 of the peak, as tests/steppers/test_contact3d.py holds it (measured: 3.9e-15); no sideways "
        "force; torque only the rounding of a symmetric sum", force=1e-9),
    # -- drops of the paper's foot released at the surface, against the exact drop
    "exact": PathSpec(
        "drop", "mudforce.references.drop.exact_drop (DOP853 per phase, rtol 1e-11; sticking in closed form)",
        "the reference of the drops", neck=0.0),
    "builtin": PathSpec(
        "drop", "mudforce.engines.dynamics.simulate_foot (event-driven RK4, 0.1 ms sub-steps, 1 ms output)",
        "events located inside the step (measured: depth 1.0e-6 of the deepest point, end depth 1.0e-8, rest "
        "force 2e-16 of m g; the first NECKED sample the one after the instant)",
        force=1e-9, neck=1e-3, depth=1e-5, end=1e-7),
    "mujoco": PathSpec(
        "drop", "mudforce.engines.mujoco.simulate_drop (MudAdapter, 1 ms steps)",
        "MuJoCo's semi-implicit Euler with the band as a soft tendon friction, first order in the step "
        "(docs/dynamics.md; measured: depth 1.1e-2 of the deepest point, at touchdown, end depth 4.9e-3, rest "
        "force 2.3e-8 of m g, necking 2.1 ms late); tests/engines/test_mujoco.py allows 5 % at rest",
        force=1e-6, neck=3e-3, depth=0.02, end=0.01),
    "mjx": PathSpec(
        "drop", "mudforce.engines.mjx.step (what mjx.simulate_drop steps): the four drops as four of drop_model's "
        "feet, each on its own joint and mud, in one world and one jit, float64",
        "MJX's Euler step with the band at the step's start (measured: depth 1.9e-2 of the deepest point, at "
        "touchdown, end depth 7.0e-4, rest force 2e-16 of m g, necking 1.1 ms late); "
        "tests/cli/test_drop3d_cli.py allows 5 % at rest", force=1e-9, neck=2e-3, depth=0.03, end=2e-3),
}
TRAJECTORY_PATHS = [name for name, p in PATHS.items() if p.kind == "trajectory" and name != "batch"]
DROP_PATHS = [name for name, p in PATHS.items() if p.kind == "drop" and name != "exact"]


# ------------------------------------------------------------------------------------------------ the inputs
@dataclass(frozen=True)
class Trajectory:
    """A prescribed motion: times [s], depths [m] (positive down) and the mud."""

    time: np.ndarray
    depth: np.ndarray
    params: mf.MudParameters = field(compare=False)


def _trajectories() -> dict[str, Trajectory]:
    w = mf.MudParameters.from_water_content
    t, z = mf.Protocol.paper(depth=0.02, velocity=0.01).sample()  # 20 mm at 10 mm/s, hold 6 s, 100 Hz
    walk = gait(1, duration=6.0, rate=200.0)  # touchdowns, stances with sway, lift-offs; two necks at W = 30 %
    jittered = gait(1, duration=6.0, rate=200.0, jitter=0.3)  # time stamps moved by up to 0.3 of a sample
    noisy = jittered.depth + 5e-5 * np.random.default_rng(1).standard_normal(jittered.time.size)  # 0.05 mm
    dip_t = np.arange(801) * 1e-3  # a shallow dip and a hold above the surface: CONTACT -> FREE
    dip_z = np.interp(dip_t, [0.0, 0.3, 0.6, 0.8], [-2e-3, 1e-3, -0.5e-3, -0.5e-3])
    return {
        "paper-W15": Trajectory(t, z, w(0.15)),  # does not neck: the mud clings above the surface
        "paper-W25": Trajectory(t, z, w(0.25)),  # necks at 8.66 s
        "gait-W30": Trajectory(walk.time, walk.depth, w(0.30)),
        "noisy-jittered-W20": Trajectory(jittered.time, noisy, w(0.20)),  # reversals all along, 4 necks
        "dip-W20": Trajectory(dip_t, dip_z, w(0.20)),
    }


TRAJECTORIES = _trajectories()
W35 = mf.MudParameters.from_water_content(0.35)  # the second foot's mud on the many-feet path
DROPS = [(w, m) for w in (0.15, 0.25) for m in (5.0, 20.0)]  # (water content, mass [kg])
DROP_DURATION = 1.0  # [s]; W = 25 %, 20 kg rebounds and necks at 0.633 s, the others stick
DT = 1e-3  # [s], every drop path's output step


def _dts(time: np.ndarray) -> list[float]:
    """The step before each sample [s], the first 0 (a first step sets the initial sample and ignores it)."""
    return [0.0, *np.diff(time).tolist()]


# ------------------------------------------------------------------------------------------------ the paths
@dataclass
class Run:
    """One path's outputs on one trajectory: forces [N], contact states (codes of mf.STATE_NAMES), necks."""

    force: np.ndarray
    modes: np.ndarray | None = None
    necks: np.ndarray | None = None  # instants [s], or (stream) the samples that necked
    extra: dict[str, Any] = field(default_factory=dict)


def _batch() -> dict[str, Run]:
    out = {}
    for name, tr in TRAJECTORIES.items():
        res = mf.simulate(tr.time, tr.depth, tr.params, velocity_filter="exact")
        out[name] = Run(res.force, res.state.astype(np.int64), res.necking_times)
    return out


def _stream() -> dict[str, Run]:
    out = {}
    codes = {s: i for i, s in enumerate(mf.STATE_NAMES)}
    for name, tr in TRAJECTORIES.items():
        contact = mf.MudContact(tr.params)
        force, modes, necked = [], [], []
        for k, dt in enumerate(_dts(tr.time)):
            force.append(contact.step(float(tr.depth[k]), dt))
            modes.append(codes[contact.last.state])
            if contact.last.necked:
                necked.append(k)
        out[name] = Run(np.array(force), np.array(modes), np.array(necked, dtype=np.int64))
    return out


def _many() -> dict[str, Run]:
    out = {}
    codes = {s: i for i, s in enumerate(mf.STATE_NAMES)}
    for name, tr in TRAJECTORIES.items():
        feet = mf.MudContacts([tr.params, W35], 2)
        force = np.empty((tr.time.size, 2))
        modes = np.empty((tr.time.size, 2), dtype=np.int64)
        for k, dt in enumerate(_dts(tr.time)):
            force[k] = feet.step(np.full(2, tr.depth[k]), dt)
            modes[k] = [codes[m] for m in feet.modes]
        other = mf.simulate(tr.time, tr.depth, W35, velocity_filter="exact")
        out[name] = Run(force[:, 0], modes[:, 0], extra={"other": (force[:, 1], modes[:, 1], other)})
    return out


def _jax() -> dict[str, Run]:
    """All trajectories as the feet of one ``lax.scan`` (one compilation), each with its own ``dt`` and mud."""
    jax = pytest.importorskip("jax")
    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    import mudforce.jax as mj

    names = list(TRAJECTORIES)
    steps = max(tr.time.size for tr in TRAJECTORIES.values())
    z = np.empty((steps, len(names)))
    dt = np.ones((steps, len(names)))  # the first step's is ignored; a shorter trajectory holds its last depth
    for j, name in enumerate(names):
        tr = TRAJECTORIES[name]
        m = tr.time.size
        z[:m, j], z[m:, j] = tr.depth, tr.depth[-1]
        dt[1:m, j] = np.diff(tr.time)
    params = mj.make_params([TRAJECTORIES[n].params for n in names])

    @jax.jit  # the default compile users get (the other JAX and MJX tests compile light: tests/jax_compile.py)
    def run(params: Any, z: Any, dt: Any) -> Any:
        def body(s: Any, x: Any) -> Any:
            s, f = mj.step(s, params, x[0], x[1])
            return s, (f, s.mode)
        return jax.lax.scan(body, mj.init(len(names)), (z, dt))[1]

    force, mode = (np.asarray(a) for a in run(params, jnp.asarray(z), jnp.asarray(dt)))
    assert (mj.FREE, mj.CONTACT, mj.NECKED) == tuple(mf.STATE_NAMES.index(n) for n in ("FREE", "CONTACT", "NECKED"))
    return {n: Run(force[: TRAJECTORIES[n].time.size, j], mode[: TRAJECTORIES[n].time.size, j].astype(np.int64))
            for j, n in enumerate(names)}


def _reference() -> dict[str, Run]:
    out = {}
    for name, tr in TRAJECTORIES.items():
        ref = reference_simulate(tr.time, tr.depth, tr.params)
        out[name] = Run(ref.force, ref.state.astype(np.int64), ref.necking_times)
    return out


def _three_d() -> dict[str, Run]:
    sole = shapes.sole(mf.Foot.paper())
    upright = [1.0, 0.0, 0.0, 0.0]
    out = {}
    for name, tr in TRAJECTORIES.items():
        contact = mf.MudContact3D(tr.params, sole)
        wrenches = [contact.step([0.0, 0.0, -z], upright, dt) for z, dt in zip(tr.depth.tolist(), _dts(tr.time),
                                                                                    strict=True)]
        force = np.array([w.force for w in wrenches])
        torque = np.array([w.torque for w in wrenches])
        out[name] = Run(force[:, 2], extra={"sideways": force[:, :2], "torque": torque})
    return out


TRAJECTORY_RUNNERS: dict[str, Callable[[], dict[str, Run]]] = {
    "batch": _batch, "stream": _stream, "many": _many, "jax": _jax, "reference": _reference, "3d": _three_d,
}


@dataclass
class Drop:
    """One drop path's outputs: samples every DT [s] of depth [m], force [N], phase codes, and at-rest."""

    depth: np.ndarray
    force: np.ndarray
    phase: np.ndarray
    at_rest: bool


def _from_result(res: FootResult) -> Drop:
    return Drop(res.depth, res.force, res.phase, res.at_rest)


def _builtin() -> dict[tuple[float, float], Drop]:
    return {(w, m): _from_result(simulate_foot(m, mf.MudParameters.from_water_content(w), duration=DROP_DURATION,
                                               dt=DT)) for w, m in DROPS}


def _mujoco() -> dict[tuple[float, float], Drop]:
    pytest.importorskip("mujoco")
    from mudforce.engines.mujoco import simulate_drop

    return {(w, m): _from_result(simulate_drop(m, mf.MudParameters.from_water_content(w), duration=DROP_DURATION,
                                               dt=DT)) for w, m in DROPS}


def _mjx() -> dict[tuple[float, float], Drop]:
    """The four drops as four feet of one MJX world, in one jit, stepped by :func:`mudforce.engines.mjx.step`.

    Each foot is ``drop_model(mass)``'s foot (asserted below: its mass, box and sole site), on its own slide
    joint, with its own mud; the joints are independent, so each foot's effective mass is its own and the
    world is four drops (checked equal to four ``simulate_drop`` runs, to 2e-15 N, when this was written).
    One world with four feet compiles once and faster than four worlds of a batched model.
    """
    pytest.importorskip("jax")
    mujoco = pytest.importorskip("mujoco")
    pytest.importorskip("mujoco.mjx")
    import jax
    from mujoco import mjx

    import mudforce.engines.mjx as mud
    import mudforce.jax as mj

    jax.config.update("jax_enable_x64", True)
    one = mud.drop_model(DROPS[0][1], dt=DT)
    size, sole = one.geom_size[0].tolist(), one.site_pos[0].tolist()
    bodies = "".join(f"""
    <body name="foot{j}" pos="{0.2 * j!r} 0 {-sole[2]!r}"><joint type="slide" axis="0 0 1"/>
      <geom type="box" size="{size[0]!r} {size[1]!r} {size[2]!r}" mass="{m!r}" contype="0" conaffinity="0"/>
      <site name="sole{j}" pos="0 0 {sole[2]!r}"/></body>""" for j, (_, m) in enumerate(DROPS))
    model = mujoco.MjModel.from_xml_string(f"""<mujoco><option timestep="{DT!r}" gravity="0 0 {-GRAVITY!r}"
        integrator="Euler"/><worldbody>{bodies}</worldbody></mujoco>""")
    for j, (_, m) in enumerate(DROPS):  # each foot is drop_model's
        alone = mud.drop_model(m, dt=DT)
        np.testing.assert_array_equal(model.body_mass[j + 1], alone.body_mass[1])
        np.testing.assert_array_equal(model.body_inertia[j + 1], alone.body_inertia[1])
        np.testing.assert_array_equal(model.geom_size[j], alone.geom_size[0])
        np.testing.assert_array_equal(model.site_pos[j], alone.site_pos[0])
        np.testing.assert_array_equal(model.body_pos[j + 1][2], alone.body_pos[1][2])
        assert (model.opt.timestep, model.opt.integrator) == (alone.opt.timestep, alone.opt.integrator)
        np.testing.assert_array_equal(model.opt.gravity, alone.opt.gravity)
    m_x = mjx.put_model(model)
    patch = mud.add_mud(model, [f"sole{j}" for j in range(len(DROPS))],
                        [mf.MudParameters.from_water_content(w) for w, _ in DROPS])
    n = round(DROP_DURATION / DT) + 1

    @light_jit  # XLA's light compile (tests/jax_compile.py): compiling is most of this path's cost
    def run(data: Any) -> Any:
        def body(carry: Any, _: Any) -> Any:
            d, c = carry
            d, c, f = mud.step(m_x, d, c, patch)
            return (d, c), (d.qpos, d.qvel, f, c.state.mode, c.stuck)
        return jax.lax.scan(body, (data, mud.init(patch)), None, length=n - 1)[1]

    qpos, qvel, force, mode, stuck = (np.asarray(a) for a in run(mjx.make_data(m_x)))
    out = {}
    for j, case in enumerate(DROPS):
        phase = np.where(mode[:, j] == mj.FREE, Phase.FREE, np.where(mode[:, j] == mj.NECKED, Phase.NECKED,
                         np.where(stuck[:, j], Phase.STUCK, Phase.INTRUSION)))
        at_rest = bool(stuck[-1, j]) and abs(float(qvel[-1, j])) <= REST_SPEED
        out[case] = Drop(np.r_[0.0, -qpos[:, j]], np.r_[0.0, force[:, j]], np.r_[Phase.FREE, phase], at_rest)
    return out


DROP_RUNNERS: dict[str, Callable[[], dict[tuple[float, float], Drop]]] = {
    "builtin": _builtin, "mujoco": _mujoco, "mjx": _mjx,
}


class _Once(dict[str, Any]):
    """Each path's outputs, computed on first use (a path that skips skips again on every use)."""

    def __init__(self, runners: Mapping[str, Callable[[], Any]]) -> None:
        super().__init__()
        self.runners = runners

    def __missing__(self, name: str) -> Any:
        value = self[name] = self.runners[name]()
        return value


@pytest.fixture(scope="module")
def runs() -> _Once:
    return _Once(TRAJECTORY_RUNNERS)


@pytest.fixture(scope="module")
def drops() -> _Once:
    return _Once(DROP_RUNNERS)


@pytest.fixture(scope="module")
def exact() -> dict[tuple[float, float], ExactDrop]:
    return {(w, m): exact_drop(m, mf.MudParameters.from_water_content(w), duration=DROP_DURATION, dt=DT)
            for w, m in DROPS}


# ------------------------------------------------------------------------------------------------ the tests
def test_the_table_names_every_path_once() -> None:
    assert set(TRAJECTORY_RUNNERS) == {n for n, p in PATHS.items() if p.kind == "trajectory"}
    assert set(DROP_RUNNERS) | {"exact"} == {n for n, p in PATHS.items() if p.kind == "drop"}
    assert all(p.why and p.code for p in PATHS.values())


def test_the_inputs_cover_every_transition_and_necking(runs: _Once) -> None:
    """What the trajectories pass through: every contact transition, necks on the paper's protocol, the gait
    and the noisy one, none at W = 15 %; an exact hold and irregular steps."""
    batch = runs["batch"]
    pairs = {(int(a), int(b)) for r in batch.values() for a, b in itertools.pairwise(r.modes) if a != b}
    assert pairs == {(0, 1), (1, 0), (1, 2), (2, 0), (2, 1)}
    assert [batch[n].necks.size for n in TRAJECTORIES] == [0, 1, 2, 4, 0]
    assert np.ptp(np.diff(TRAJECTORIES["noisy-jittered-W20"].time)) > 0.5 * 5e-3
    assert (np.diff(TRAJECTORIES["paper-W25"].depth) == 0.0).any()


@pytest.mark.parametrize("trajectory", list(TRAJECTORIES))
@pytest.mark.parametrize("path", TRAJECTORY_PATHS)
def test_trajectory_paths_agree_with_batch(runs: _Once, path: str, trajectory: str) -> None:
    spec = PATHS[path]
    ref: Run = runs["batch"][trajectory]
    got: Run = runs[path][trajectory]
    peak = float(np.max(np.abs(ref.force)))
    err = float(np.max(np.abs(got.force - ref.force)))
    assert err <= spec.force * peak, f"{path}: force differs by {err / peak:.3g} of the peak (allowed {spec.force:g})"
    if spec.modes:
        assert got.modes is not None
        bad = np.flatnonzero(got.modes != ref.modes)
        assert bad.size == 0, f"{path}: contact state differs at t = {TRAJECTORIES[trajectory].time[bad[:5]]} s"
    if got.necks is not None and spec.neck is not None:
        assert got.necks.size == ref.necks.size, f"{path}: {got.necks.size} necks, batch {ref.necks.size}"
        np.testing.assert_allclose(got.necks, ref.necks, rtol=0, atol=spec.neck, err_msg=f"{path}: necking instants")
    elif got.necks is not None:  # the samples that necked: each the one whose step holds batch's instant
        # (a neck at a reversal, where the drag jumps, can be at the step's start)
        t = TRAJECTORIES[trajectory].time
        assert got.necks.size == ref.necks.size, f"{path}: {got.necks.size} necks, batch {ref.necks.size}"
        assert all(t[k - 1] <= tn <= t[k] for k, tn in zip(got.necks, ref.necks, strict=True)), path
    if path == "many":  # the second foot, on its own mud, is its own batch run
        force, modes, other = got.extra["other"]
        np.testing.assert_array_equal(force, other.force)
        np.testing.assert_array_equal(modes, other.state)
    if path == "3d":  # straight up and down: no sideways force, and torque only the rounding of a symmetric sum
        assert np.all(got.extra["sideways"] == 0.0)
        assert np.max(np.abs(got.extra["torque"])) <= 1e-12 * peak * 0.05  # [N m], the sole's half-length 25 mm


@pytest.mark.parametrize("drop", DROPS, ids=[f"W{round(w * 100)}-{m:g}kg" for w, m in DROPS])
@pytest.mark.parametrize("path", DROP_PATHS)
def test_drop_paths_agree_with_the_exact_drop(drops: _Once, exact: dict[tuple[float, float], ExactDrop],
                                             path: str, drop: tuple[float, float]) -> None:
    spec = PATHS[path]
    ref = exact[drop]
    got: Drop = drops[path][drop]
    deepest = float(np.max(ref.depth))
    err = float(np.max(np.abs(got.depth - ref.depth)))
    assert err <= spec.depth * deepest, f"{path}: depth differs by {err / deepest:.3g} of the deepest point"
    end = abs(float(got.depth[-1]) / ref.end_depth - 1.0)
    assert end <= spec.end, f"{path}: depth at the end differs by {end:.3g} (allowed {spec.end:g})"
    # at rest at the end exactly when the exact drop is, and then carrying the weight
    resting = ref.events[-1][1] == "STUCK"
    assert got.at_rest == resting, f"{path}: at rest {got.at_rest}, exact drop {resting}"
    if resting:
        weight = drop[1] * GRAVITY
        last = np.arange(got.force.size) * DT >= DROP_DURATION - 0.1 + 1e-9
        off = abs(float(np.mean(got.force[last])) / weight - 1.0)
        assert off <= spec.force, f"{path}: rest force off the weight by {off:.3g} (allowed {spec.force:g})"
    # each neck at the first NECKED sample at or after the exact instant, at most spec.neck later
    necks = [e[0] for e in ref.events if e[1] == "NECKED"]
    starts = np.flatnonzero((got.phase[1:] == Phase.NECKED) & (got.phase[:-1] != Phase.NECKED)) + 1
    assert starts.size == len(necks), f"{path}: {starts.size} necks, exact drop {len(necks)}"
    for k, tn in zip(starts, necks, strict=True):
        late = k * DT - tn
        assert spec.neck is not None and -1e-9 <= late <= spec.neck, f"{path}: necked {late * 1e3:.3g} ms after"


def test_the_drops_rest_and_neck(exact: dict[tuple[float, float], ExactDrop]) -> None:
    """The drops are what the table says: three stick within the second, W = 25 %, 20 kg rebounds and necks."""
    events = {case: [e[1] for e in ref.events] for case, ref in exact.items()}
    assert [names[-1] == "STUCK" for names in events.values()] == [True, True, True, False]
    assert "NECKED" in events[(0.25, 20.0)] and "WITHDRAWAL" in events[(0.25, 5.0)]
