"""mudforce.jax against the CPU stepper (MudContacts, exact rule): every transition, all five Table I rows."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

jax = pytest.importorskip("jax")
jax.config.update("jax_enable_x64", True)  # float64 comparisons; float32 is asked for explicitly below

import jax.numpy as jnp  # noqa: E402

import mudforce.jax as mj  # noqa: E402
from jax_compile import light_jit  # noqa: E402
from mudforce._kernel import layout as K  # noqa: E402  (the state layout's columns, to compare states)
from mudforce.engines import dynamics  # noqa: E402
from mudforce.errors import InputError  # noqa: E402
from mudforce.model.foot import Foot  # noqa: E402
from mudforce.model.parameters import MudParameters  # noqa: E402
from mudforce.steppers.many import MudContacts  # noqa: E402

WATER = (0.15, 0.20, 0.25, 0.30, 0.35)
DT = 1e-3
STEP = light_jit(mj.step)  # shared: eager mode would dispatch every operation on its own
BRANCH_FORCES = light_jit(mj.branch_forces)


def gait(n: int, steps: int, dt: float, seed: int) -> np.ndarray:
    """Depths [m], shape (steps, n): two sines per foot, half of them capped (exact holds).

    Means from 5 mm above to 18 mm below the surface and speeds up to
    ~0.4 m/s, so every foot touches down, intrudes, holds, withdraws fast
    enough to neck (inside a step) at every water content, and re-pushes
    from NECKED both below the surface (to CONTACT) and above it (to FREE).
    """
    rng = np.random.default_rng(seed)
    t = np.arange(steps)[:, None] * dt
    c = rng.uniform(-5e-3, 18e-3, n)
    a = rng.uniform(3e-3, 25e-3, n)
    f = rng.uniform(0.4, 2.5, n)
    ph = rng.uniform(0.0, 2.0 * np.pi, n)
    a2 = rng.uniform(0.0, 4e-3, n)
    f2 = rng.uniform(2.0, 6.0, n)
    z = c + a * np.sin(2.0 * np.pi * f * t + ph) + a2 * np.sin(2.0 * np.pi * f2 * t)
    cap = np.where(rng.random(n) < 0.5, rng.uniform(5e-3, 30e-3, n), np.inf)
    z = np.minimum(z, cap)
    # and two crafted feet: a shallow dip that leaves CONTACT for FREE on the intrusion branch
    # (a hold above the surface before the neck breaks), and a deep push, fast pull (necks
    # below the surface at every water content) and re-push into CONTACT
    z[:, 0] = np.interp(t[:, 0], [0.0, 0.3, 0.6, 0.8], [-2e-3, 1e-3, -0.5e-3, -0.5e-3])
    z[:, 1] = np.interp(t[:, 0], [0.0, 0.2, 0.4, 0.485, 0.9, 1.5], [0.0, 20e-3, 20e-3, 3e-3, 10e-3, -5e-3])
    return z


def cpu_run(muds: list[MudParameters], z: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forces [N], contact states and neck offsets per step from MudContacts."""
    steps, n = z.shape
    feet = MudContacts(muds, n, threads=1)
    forces = np.empty((steps, n))
    modes = np.empty((steps, n), dtype=np.int64)
    for k in range(steps):
        forces[k] = feet.step(z[k], dt)
        modes[k] = feet.state[:, K.S_MODE]
    return forces, modes, np.array(feet.state[:, : K.N_STATE])


def _scan(params: mj.Params, z: jax.Array, dt: jax.Array) -> tuple[mj.State, tuple[jax.Array, jax.Array]]:
    """Every foot through its depths ``z`` (steps, n) [m], steps ``dt`` (steps, n) [s]: final state, forces, modes."""
    def body(s: mj.State, x: tuple[jax.Array, jax.Array]) -> tuple[mj.State, tuple[jax.Array, jax.Array]]:
        s, f = mj.step(s, params, x[0], x[1])
        return s, (f, s.mode)
    return jax.lax.scan(body, mj.init(z.shape[1], z.dtype), (z, dt))


# one compile per dtype for every trajectory below (each array shape compiles anew: the float64 runs are one batch)
RUN = light_jit(_scan)
STEPS = 2000
PER = 16  # feet per water content in the comparison with the CPU
PROMISE_PER = 3  # feet per water content for each step size of the promise (0.1 ms, 2 ns)
PROMISE_DTS = ((1e-4, 1e-12), (2e-9, 1e-10))  # (dt [s], bound on the error / peak)


@pytest.fixture(scope="module")
def batch() -> dict[str, object]:
    """One float64 JAX run of every foot the module compares, side by side: the CPU comparison's (PER per water
    content, DT, STEPS steps), the promise's (1500 steps of each of PROMISE_DTS, then held), the float32 check's
    (five, DT) and the vmap check's (five, DT, 200 steps, then held). A later step never changes an earlier
    one's output: each group is read over its own steps."""
    groups: dict[str, tuple[list[MudParameters], np.ndarray, float, int]] = {
        "cpu": ([MudParameters.table_i(w) for w in WATER for _ in range(PER)],
                np.concatenate([gait(PER, STEPS, DT, seed=i) for i in range(len(WATER))], axis=1), DT, STEPS)}
    for j, (dt, _) in enumerate(PROMISE_DTS):
        z = np.concatenate([gait(PROMISE_PER, 1500, dt, seed=10 + i) for i in range(len(WATER))], axis=1)
        groups[f"promise{j}"] = ([MudParameters.table_i(w) for w in WATER for _ in range(PROMISE_PER)],
                                 np.concatenate([z, np.repeat(z[-1:], STEPS - 1500, axis=0)]), dt, 1500)
    groups["f32"] = ([MudParameters.table_i(w) for w in WATER], gait(5, STEPS, DT, seed=5), DT, STEPS)
    z = gait(5, 200, DT, seed=3)
    groups["vmap"] = ([MudParameters.table_i(w) for w in WATER], np.concatenate([z, np.repeat(z[-1:], STEPS - 200,
                                                                                               axis=0)]), DT, 200)
    muds = [m for g in groups.values() for m in g[0]]
    z = np.concatenate([g[1] for g in groups.values()], axis=1)
    dt = np.concatenate([np.full(g[1].shape, g[2]) for g in groups.values()], axis=1)
    final, (forces, modes) = RUN(mj.make_params(muds), jnp.asarray(z), jnp.asarray(dt))
    out: dict[str, object] = {}
    start = 0
    for name, (group_muds, gz, gdt, used) in groups.items():
        cols = slice(start, start + gz.shape[1])
        start = cols.stop
        out[name] = {"muds": group_muds, "z": gz[:used], "dt": gdt, "jax": np.asarray(forces)[:used, cols],
                     "jax_modes": np.asarray(modes)[:used, cols],
                     "final": jax.tree.map(lambda a, c=cols: a[c], final)}
    return out


@pytest.fixture(scope="module")
def compared(batch: dict[str, dict[str, object]]) -> dict[str, np.ndarray]:
    run = batch["cpu"]
    forces, modes, states = cpu_run(run["muds"], run["z"], DT)  # type: ignore[arg-type]
    return {"cpu": forces, "modes": modes, "states": states, "jax": run["jax"], "jax_modes": run["jax_modes"],
            "final": run["final"], "per": np.array(PER)}


def test_equal_to_cpu_at_every_water_content(compared: dict[str, np.ndarray]) -> None:
    per = int(compared["per"])
    for i, w in enumerate(WATER):
        cols = slice(i * per, (i + 1) * per)
        cpu = compared["cpu"][:, cols]
        peak = np.abs(cpu).max()
        err = np.abs(compared["jax"][:, cols] - cpu).max()
        assert err <= 1e-12 * peak, (w, err / peak)
        assert (compared["jax_modes"][:, cols] == compared["modes"][:, cols]).all()


def test_gaits_pass_every_transition(compared: dict[str, np.ndarray]) -> None:
    per = int(compared["per"])
    for i in range(len(WATER)):
        m = compared["modes"][:, i * per:(i + 1) * per]
        pairs = {(int(a), int(b)) for a, b in zip(m[:-1].ravel(), m[1:].ravel(), strict=True) if a != b}
        assert pairs == {(0, 1), (1, 0), (1, 2), (2, 0), (2, 1)}, (WATER[i], pairs)
    assert (np.diff(gait(per, STEPS, DT, seed=0), axis=0) == 0.0).any()  # exact holds


def test_final_state_equals_cpu(compared: dict[str, np.ndarray]) -> None:
    s = compared["final"]
    cpu = compared["states"]
    np.testing.assert_array_equal(np.asarray(s.mode), cpu[:, K.S_MODE])
    np.testing.assert_array_equal(np.asarray(s.depth), cpu[:, K.S_DEPTH])
    np.testing.assert_allclose(np.asarray(mj.mud_depth(s)), cpu[:, K.S_MUD], rtol=0, atol=1e-14)
    contact = cpu[:, K.S_MODE] == K.CONTACT
    np.testing.assert_allclose(np.asarray(s.strain)[contact], cpu[contact, K.S_STRAIN], rtol=0, atol=1e-14)


def test_the_promise_holds_from_0_1_ms_and_shorter_steps_drift_as_documented(
        batch: dict[str, dict[str, object]]) -> None:
    """1e-12 of the peak for dt >= 1e-4 s (README, docs/gpu.md); at 2 ns the CPU's ``1 - exp(-dt/tau)`` loses
    digits (~1e-16 tau/dt) that JAX's expm1 keeps, and the two drift apart, measured 1.6e-12 to 2.5e-11."""
    per = PROMISE_PER
    for j, (dt, bound) in enumerate(PROMISE_DTS):
        run = batch[f"promise{j}"]
        assert run["dt"] == dt
        cpu, _, _ = cpu_run(run["muds"], run["z"], dt)  # type: ignore[arg-type]
        got = run["jax"]
        for i, w in enumerate(WATER):
            cols = slice(i * per, (i + 1) * per)
            err = np.abs(got[:, cols] - cpu[:, cols]).max() / np.abs(cpu[:, cols]).max()  # type: ignore[index]
            assert err <= bound, (dt, w, err)


def test_first_step_reset_and_bad_input() -> None:
    params = mj.make_params(MudParameters.from_water_content(0.25))
    s = mj.init(3)
    s, f = STEP(s, params, jnp.array([-1e-3, 0.0, 5e-3]), 123.0)  # dt ignored by the first step
    assert np.asarray(s.mode).tolist() == [mj.FREE, mj.FREE, mj.CONTACT]
    cpu = MudContacts(MudParameters.from_water_content(0.25), 3)
    np.testing.assert_allclose(np.asarray(f), cpu.step(np.array([-1e-3, 0.0, 5e-3]), 1.0), rtol=1e-14)
    s2, f2 = STEP(s, params, jnp.array([jnp.nan, 1e-3, 6e-3]), DT)
    assert np.isnan(np.asarray(f2)[0]) and np.isfinite(np.asarray(f2)[1:]).all()
    assert float(s2.depth[0]) == -1e-3  # refused foot unchanged
    s3, f3 = STEP(s, params, jnp.array([1e-3, 1e-3, 6e-3]), 0.0)
    assert np.isnan(np.asarray(f3)).all() and (np.asarray(s3.depth) == np.asarray(s.depth)).all()
    for dt in (1e-12, 5000.0):  # outside [MIN_DT, MAX_DT]: were 4.6e16 N (a velocity of 1e9 m/s kept) and taken
        s4, f4 = STEP(s, params, jnp.array([1e-3, 1e-3, 6e-3]), dt)
        assert np.isnan(np.asarray(f4)).all() and (np.asarray(s4.depth) == np.asarray(s.depth)).all()
    s5, f5 = STEP(s, params, jnp.array([1e-3, 1e3, 6e-3]), DT)  # beyond MAX_DEPTH: was 4.6e10 N, the depth kept
    assert np.isnan(np.asarray(f5)[1]) and float(s5.depth[1]) == 0.0 and np.isfinite(np.asarray(f5)[[0, 2]]).all()
    r = light_jit(mj.reset)(s2, jnp.array([False, True, False]))
    assert np.asarray(r.mode).tolist() == [mj.FREE, mj.UNSTARTED, mj.CONTACT]


@pytest.mark.parametrize(("call", "words"), [
    (lambda s, p: mj.step(s, p, jnp.zeros(4), DT), r"^depths must be one value or one per foot, shape \(3,\)"),
    (lambda s, p: mj.step(s, p, np.zeros((3, 1)), DT), r"^depths .* got shape \(3, 1\)"),  # was a (3, 3) state
    (lambda s, p: mj.step(s, p, "0.01", DT), r"^depths must be real numbers \[m\]"),  # was parsed
    (lambda s, p: mj.step(s, p, True, DT), r"^depths must be real numbers .* bool"),  # was 1 m
    (lambda s, p: mj.step(s, p, np.full(3, 0.01 + 1j), DT), "^depths .* complex"),  # 1j was dropped
    (lambda s, p: mj.step(s, p, [0.0, 0.0, 10**400], DT), "^depths .* integer too large"),  # was OverflowError
    (lambda s, p: mj.step(s, p, jnp.zeros(3), "1e-3"), r"^dt must be real numbers \[s\]"),  # was a force of 0
    (lambda s, p: mj.step(s, p, jnp.zeros(3), np.full(2, DT)), r"^dt must be one value or one per foot"),
    (lambda s, p: mj.step(s, p._replace(area=jnp.ones(4)), jnp.zeros(3), DT), r"^params.area must be one value"),
    (lambda s, p: mj.step(s, None, jnp.zeros(3), DT), "^params must be a mudforce.jax.Params"),  # was a TypeError
    (lambda s, p: mj.step(None, p, jnp.zeros(3), DT), "^state must be a mudforce.jax.State"),  # was AttributeError
    (lambda s, p: mj.reset(s, [True, False]), r"^mask must be a bool or bools of the state's shape \(3,\)"),
    (lambda s, p: mj.reset(s, np.ones((3, 1), bool)), "^mask must be a bool"),  # was a (3, 3) state
    (lambda s, p: mj.reset(s, "x"), "^mask must be a bool"),  # was True for every foot
    (lambda s, p: mj.reset(s, [0.5, 0.0, 0.0]), "^mask must be a bool"),  # was True for every foot
    (lambda s, p: mj.reset(None, [True] * 3), "^state must be a mudforce.jax.State"),  # was AttributeError
    (lambda s, p: mj.reset(s, [True, [False], True]), r"^mask .* shape \(3,\), got a ragged list"),  # was ValueError
    # branch_forces, checked as step: "0.01" was parsed, a weight of 2 extrapolated the band, None and a dt of
    # shape (4,) ended in AttributeError and JAX's TypeError
    (lambda s, p: mj.branch_forces(s, p, "0.01"), r"^dt must be real numbers \[s\]"),
    (lambda s, p: mj.branch_forces(s, p, np.full(4, DT)), r"^dt must be one value or one per foot, shape \(3,\)"),
    (lambda s, p: mj.branch_forces(s, p, DT, 2.0), r"^weight must be within \[0, 1\] -, got 2.0"),
    (lambda s, p: mj.branch_forces(s, p, DT, [0.0, np.nan, 1.0]), r"^weight must be within \[0, 1\] -, got nan"),
    (lambda s, p: mj.branch_forces(s, p, DT, True), "^weight must be real numbers .* bool"),
    (lambda s, p: mj.branch_forces(None, p, DT), "^state must be a mudforce.jax.State"),
    (lambda s, p: mj.branch_forces(s, None, DT), "^params must be a mudforce.jax.Params"),
])
def test_step_and_reset_refuse_inputs_of_wrong_type_or_shape(call: Any, words: str) -> None:
    """Checked when tracing (types, dtypes, shapes), before anything is computed or compiled."""
    with pytest.raises(InputError, match=words):
        call(mj.init(3), mj.make_params(MudParameters.from_water_content(0.25)))


def test_vmap_per_foot_params_equals_batch(batch: dict[str, dict[str, object]]) -> None:
    """``jax.vmap`` of the step over feet (params, depth and dt per foot) equals the batch step, bit for bit."""
    run = batch["vmap"]
    single = jax.vmap(mj.step, in_axes=(0, 0, 0, 0))

    def scan_single(params: mj.Params, z: jax.Array, dt: jax.Array) -> jax.Array:
        return jax.lax.scan(lambda s, x: single(s, params, x[0], x[1]), mj.init(z.shape[1]), (z, dt))[1]

    z = np.asarray(run["z"])
    mapped = light_jit(scan_single)(mj.make_params(run["muds"]), jnp.asarray(z), jnp.full(z.shape, DT))
    np.testing.assert_array_equal(run["jax"], np.asarray(mapped))


def test_make_params_shapes_and_errors() -> None:
    mud = MudParameters.from_water_content(0.25)
    assert mj.make_params(mud).k_i.shape == ()
    assert mj.make_params(mud, n=7).alpha.shape == (7,)
    p = mj.make_params([mud, mud], foot=Foot.disc(0.05))
    assert p.area.shape == (2,) and float(p.area[0]) == pytest.approx(Foot.disc(0.05).area)
    assert mj.make_params(mud, dtype=jnp.float32).k_w.dtype == jnp.float32
    for dtype in ("int32", jnp.float16, "no such type"):  # the 3-D step's dtype check, now the one both use
        with pytest.raises(InputError, match="dtype must be float32 or float64"):
            mj.make_params(mud, dtype=dtype)
    with pytest.raises(InputError, match="one per foot"):
        mj.make_params([mud, mud, mud], foot=[Foot.paper(), Foot.paper()])
    with pytest.raises(InputError, match="n = 4"):
        mj.make_params([mud, mud], n=4)
    with pytest.raises(InputError):
        mj.make_params("mud")  # type: ignore[arg-type]
    for mud_given in (5, None, {mud}, {mud: 1}):  # were list()'s TypeError; a set (merging equal muds) was taken
        with pytest.raises(InputError, match=r"^make_params needs MudParameters or a non-empty sequence"):
            mj.make_params(mud_given)  # type: ignore[arg-type]
    for foot in ({Foot.paper()}, True):  # a set in its hashes' order; both were read as the count n, warned as 0.1's
        with pytest.raises(InputError, match=r"^foot must be a Foot or a non-empty sequence of Foot, got (set|bool)"):
            mj.make_params(mud, foot=foot)  # type: ignore[arg-type]
        with pytest.raises(InputError, match=r"^foot must be a Foot"):
            mj.params_from_water_content(0.25, foot=foot)  # type: ignore[arg-type]


def test_rest_band_and_branch_forces_equal_dynamics(compared: dict[str, np.ndarray]) -> None:
    per = int(compared["per"])
    muds = [MudParameters.table_i(w) for w in WATER for _ in range(per)]
    states = compared["states"]
    rows = MudContacts(muds, len(muds)).params_array
    n = len(muds)
    up, down, drag = np.empty(n), np.empty(n), np.empty(n)
    for weight in (0.0, 1.0):
        dynamics.branch_forces(states, rows, DT, weight, up, down, drag)
        ju, jd, jdr = BRANCH_FORCES(compared["final"], mj.make_params(muds), DT, weight)
        scale = np.abs(down).max()
        np.testing.assert_allclose(np.asarray(ju), up, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(np.asarray(jd), down, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(np.asarray(jdr), drag, rtol=0, atol=1e-12 * scale)
    lo, hi = light_jit(mj.rest_band)(mj.make_params(muds[0]), jnp.array(mj.CONTACT), jnp.array(0.01),
                                     jnp.array(1e-3), jnp.array(0.0))  # jitted: one compile, not one per operation
    ref = dynamics.rest_band(rows[0], K.CONTACT, 0.01, 1e-3, 0.0)
    assert float(lo) == pytest.approx(ref[0], rel=1e-14) and float(hi) == pytest.approx(ref[1], rel=1e-14)
    force, stuck = light_jit(mj.stick_force)(jnp.array(-5.0), jnp.array(20.0), jnp.array(0.0),
                                             jnp.array([3.0, 30.0]), jnp.array(0.0))
    assert np.asarray(force).tolist() == [3.0, 20.0] and np.asarray(stuck).tolist() == [True, False]


def test_float32_tracks_float64(batch: dict[str, dict[str, object]]) -> None:
    """A short float32 run stays close to float64 (the 10 s measurement is in benchmarks/bench_gpu.py)."""
    run = batch["f32"]
    z = np.asarray(run["z"])
    f64 = np.asarray(run["jax"])
    _, (f32, _) = RUN(mj.make_params(run["muds"], dtype=jnp.float32), jnp.asarray(z, jnp.float32),
                      jnp.full(z.shape, DT, jnp.float32))
    assert f32.dtype == jnp.float32
    f32 = np.asarray(f32, dtype=np.float64)
    assert np.abs(f32 - f64).max() <= 1e-4 * np.abs(f64).max()


def test_neck_filter_transition_is_the_cpu_matrix_on_short_and_long_steps() -> None:
    """Eq. (7)'s one-step matrix minus I (shared increment forms) against the CPU's matrix, 0.1 ms to 50 ms steps."""
    from mudforce.model import equations as eq

    grid = np.meshgrid([1e-4, 1e-3, 4e-3, 0.05], [0.05, 0.4, 0.99, 1.0, 1.01, 1.8, 6.0], [2.0, 60.0, 400.0, 2000.0],
                       indexing="ij")
    dt, zeta, omega = (g.ravel() for g in grid)
    got = np.array(light_jit(mj.neck_filter_transition)(jnp.asarray(dt), jnp.asarray(zeta), jnp.asarray(omega)))
    got[0] += 1.0
    got[3] += 1.0
    ref = np.array([eq.neck_filter_transition(z, o, *eq.neck_filter_response(h, z, o))
                    for h, z, o in zip(dt, zeta, omega, strict=True)]).T
    assert np.isfinite(got).all()
    np.testing.assert_allclose(got[[0, 3]], ref[[0, 3]], rtol=0, atol=1e-13)
    np.testing.assert_allclose(got[[1, 2]], ref[[1, 2]], rtol=1e-12, atol=0)
