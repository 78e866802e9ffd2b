"""mudforce.jax.contact3d against MudContact3D (the CPU reference): soles, spheres, capsules; vmap, scan, grad,
bad input.

JAX compiles each function once per array shape, and compiling costs seconds: every foot here has the capsule's
element count (the other shapes are padded with inert elements, zero area and a metre above the body origin,
never in the mud), and two jitted functions serve every comparison: one foot through a trajectory (``RUN``)
and many feet at once (``RUN_MANY``, ``vmap`` of the same), both compiled with XLA's light options
(tests/jax_compile.py).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

jax = pytest.importorskip("jax")
jax.config.update("jax_enable_x64", True)  # float64 comparisons

import jax.numpy as jnp  # noqa: E402

import mudforce as mf  # noqa: E402
import mudforce.jax.contact3d as mj3  # noqa: E402
from jax_compile import light_jit  # noqa: E402
from mudforce.errors import InputError  # noqa: E402
from mudforce.model import shapes  # noqa: E402
from mudforce.steppers.contact3d import MudContact3D  # noqa: E402

DT = 2e-3
TIME = np.arange(600) * DT  # 1.2 s
UPRIGHT = np.array([1.0, 0.0, 0.0, 0.0])
SOLE = shapes.sole(mf.Foot.paper(), resolution=0.01)  # 24 elements
SPHERE = shapes.sphere(0.04, resolution=0.008)  # 104
CAPSULE = shapes.capsule(0.03, 0.06, resolution=0.008)  # 156: every foot here is padded to this
N = CAPSULE.n


def _scan(state: mj3.State3D, params: mj3.Params3D, pos: Any, quat: Any, dts: Any) -> Any:
    def body(s: mj3.State3D, x: Any) -> Any:
        s, force, torque = mj3.step3d(s, params, *x)
        return s, (force, torque)
    return jax.lax.scan(body, state, (pos, quat, dts))


RUN = light_jit(_scan)  # shared module-wide: one compilation for every single-foot run
RUN_MANY = light_jit(jax.vmap(_scan))


def _quat(axis: Any, angle: Any) -> np.ndarray:
    """Unit quaternions (w, x, y, z) of rotations by ``angle`` [rad] (array) about ``axis``."""
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    angle = np.asarray(angle, dtype=float)
    return np.concatenate([np.cos(angle / 2)[..., None], np.sin(angle / 2)[..., None] * a], axis=-1)


def _mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Quaternion product ``p q`` (rotate by q, then by p), rows."""
    w1, x1, y1, z1 = np.moveaxis(p, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(q, -1, 0)
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], axis=-1)


def _depth(knots: list[float], depths: list[float]) -> np.ndarray:
    return np.interp(TIME, knots, depths)


def _cases() -> list[tuple[str, mf.MudParameters, shapes.Shape, float, np.ndarray, np.ndarray]]:
    """(name, mud, shape, surface height [m], positions (T, 3) [m], quaternions (T, 4)) through every event."""
    cases = []
    # the paper's sole moved vertically: in to 20 mm, hold, a fast pull that necks below the surface, re-push, out
    z = _depth([0.0, 0.2, 0.4, 0.46, 0.8, 1.2], [-2e-3, 20e-3, 20e-3, 3e-3, 10e-3, -5e-3])
    for w in (0.15, 0.20, 0.25, 0.30, 0.35):
        pos = np.zeros((TIME.size, 3))
        pos[:, 2] = -z
        cases.append((f"sole w={w}", mf.MudParameters.from_water_content(w), SOLE, 0.0, pos,
                      np.tile(UPRIGHT, (TIME.size, 1))))
    horizontal = _quat([1.0, 0.0, 0.0], np.full(TIME.size, math.pi / 2))  # a capsule lying along y
    # a sphere pushed in, slid 20 mm sideways (yielding, bearing), pulled out (necking)
    bottom = _depth([0.0, 0.3, 0.9, 1.05, 1.2], [-3e-3, 25e-3, 22e-3, 2e-3, -6e-3])
    pos = np.stack([_depth([0.0, 0.3, 0.8, 1.2], [0.0, 0.0, 0.02, 0.024]),
                    _depth([0.0, 0.5, 1.2], [0.0, -4e-3, -3e-3]), 0.0191 - bottom + 0.0123], axis=1)
    cases.append(("sphere sliding", mf.MudParameters.from_water_content(0.22), SPHERE, 0.0123, pos,
                  np.tile(UPRIGHT, (TIME.size, 1))))
    # a sphere rolling in +x (turning about y at v / r) at 15 mm, touching down and withdrawn
    bottom = _depth([0.0, 0.25, 0.95, 1.1, 1.2], [-2e-3, 15e-3, 15e-3, -1e-3, -4e-3])
    x = 0.05 * TIME - 0.011
    pos = np.stack([x, np.full(TIME.size, 3e-3), 0.0192 - bottom], axis=1)
    cases.append(("sphere rolling", mf.MudParameters.from_water_content(0.32), SPHERE, 0.0, pos,
                  _quat([0.0, 1.0, 0.0], x / 0.02)))
    # a capsule lying down, tilting +-25 degrees about x as it goes in and is pulled out fast (peels and necks)
    bottom = _depth([0.0, 0.3, 0.7, 0.78, 1.2], [-2e-3, 18e-3, 18e-3, -8e-3, -10e-3])
    tilt = np.radians(25.0) * np.sin(2.0 * math.pi * 1.3 * TIME)
    pos = np.stack([np.full(TIME.size, 1e-3), np.zeros(TIME.size), 0.0143 - bottom], axis=1)
    cases.append(("capsule tilting", mf.MudParameters.from_water_content(0.27), CAPSULE, 0.0, pos,
                  _mul(_quat([1.0, 0.0, 0.0], tilt), horizontal)))
    # a capsule lying down, slid diagonally while it yaws and bobs, then withdrawn. (Not an exact hold: a foot
    # that turns moves its elements' depths by rounding, and the paper's branch follows the sign of that motion;
    # the CPU and JAX round differently.)
    bottom = _depth([0.0, 0.2, 1.0, 1.2], [-1e-3, 12e-3, 12e-3, -3e-3]) + 2e-3 * np.sin(2.0 * math.pi * 1.1 * TIME)
    pos = np.stack([0.015 * np.sin(2.0 * math.pi * 0.8 * TIME), 0.01 * TIME, 0.0143 - bottom], axis=1)
    yaw = _quat([0.0, 0.0, 1.0], 0.6 * TIME)
    cases.append(("capsule sliding", mf.MudParameters.from_water_content(0.18), CAPSULE, 0.0, pos,
                  _mul(yaw, horizontal)))
    # the sole tilted 20 degrees, in to 20 mm, held, pulled out: it peels element by element
    z = _depth([0.0, 0.4, 0.8, 1.0], [-1e-3, 20e-3, 20e-3, -30e-3])
    pos = np.stack([np.zeros(TIME.size), np.zeros(TIME.size), -z], axis=1)
    cases.append(("tilted sole", mf.MudParameters.from_water_content(0.25), SOLE, 0.0, pos,
                  np.tile(_quat([0.0, 1.0, 0.0], math.radians(20.0)), (TIME.size, 1))))
    return cases


def _padded(params: mj3.Params3D) -> mj3.Params3D:
    """``params`` with inert elements up to N: zero area, a metre above the body origin (never in the mud)."""
    extra = N - params.areas.shape[0]
    return params._replace(
        centroids=jnp.concatenate([params.centroids, jnp.tile(jnp.array([0.0, 0.0, 1.0]), (extra, 1))]),
        normals=jnp.concatenate([params.normals, jnp.tile(jnp.array([0.0, 0.0, 1.0]), (extra, 1))]),
        areas=jnp.concatenate([params.areas, jnp.zeros(extra)]))


def _stack(trees: list[Any]) -> Any:
    return jax.tree.map(lambda *leaves: jnp.stack(leaves), *trees)


DTS = np.concatenate([[0.0], np.diff(TIME)])  # the first step's dt is ignored
BEARING = {"sphere sliding": 0.5, "capsule sliding": 2.0}  # bearing scales other than 1 (law3d.bearing_stress)


@pytest.fixture(scope="module")
def compared() -> dict[str, Any]:
    cases = _cases()
    cpu, modes = [], []
    for name, mud, shape, h, pos, quat in cases:  # MudContact3D, step by step (simulate_3d's loop), with the modes
        contact = MudContact3D(mud, shape, h, bearing_scale=BEARING.get(name))
        seen: set[str] = set()
        wrenches = []
        for k in range(TIME.size):
            wrenches.append(contact.step(pos[k], quat[k], DTS[k]))
            seen.update(contact.modes)
        cpu.append((np.array([w.force for w in wrenches]), np.array([w.torque for w in wrenches])))
        modes.append(seen)
    params = [_padded(mj3.make_params3d(mud, shape, h, bearing_scale=BEARING.get(name)))
              for name, mud, shape, h, _, _ in cases]
    many = len(cases)
    _, (force, torque) = RUN_MANY(mj3.init3d(CAPSULE, batch=many), _stack(params),
                                  jnp.asarray(np.stack([c[4] for c in cases])),
                                  jnp.asarray(np.stack([c[5] for c in cases])), jnp.asarray(np.tile(DTS, (many, 1))))
    return {"cases": cases, "cpu": cpu, "modes": modes, "params": params, "force": np.asarray(force),
            "torque": np.asarray(torque)}


def test_equal_to_the_cpu_step(compared: dict[str, Any]) -> None:
    """Force and torque to 1e-12 of the peak force (torque: times the foot's reach) on every case (two with a bearing
    scale other than 1)."""
    for k, (name, _, shape, _, _, _) in enumerate(compared["cases"]):
        cpu_force, cpu_torque = compared["cpu"][k]
        peak = float(np.abs(cpu_force).max())
        reach = float(np.linalg.norm(shape.centroids, axis=1).max())
        assert np.abs(compared["force"][k] - cpu_force).max() <= 1e-12 * peak, name
        assert np.abs(compared["torque"][k] - cpu_torque).max() <= 1e-12 * peak * reach, name
        if name.startswith("sole"):  # the paper's own case: no sideways force
            assert np.all(compared["force"][k][:, :2] == 0.0)


def test_the_cases_pass_through_every_event(compared: dict[str, Any]) -> None:
    """Touchdown, withdrawal, necking (below the surface), re-push; sideways yielding and bearing."""
    for (name, *_), seen in zip(compared["cases"], compared["modes"], strict=True):
        if name not in ("sphere rolling", "capsule sliding"):
            assert seen == {"FREE", "CONTACT", "NECKED"}, name
    for k in (5, 6, 7, 8):  # sphere sliding and rolling, capsule tilting and sliding: resisted sideways [N]
        assert np.abs(compared["cpu"][k][0][:, :2]).max() > 4.0


def test_vmap_equals_single_runs(compared: dict[str, Any]) -> None:
    """The batch of feet (different muds, shapes and motions) equals each foot run on its own."""
    for k, (_, _, _, _, pos, quat) in enumerate(compared["cases"][:8]):
        _, (force, torque) = RUN(mj3.init3d(CAPSULE), compared["params"][k], jnp.asarray(pos), jnp.asarray(quat),
                                 jnp.asarray(DTS))
        peak = np.abs(np.asarray(force)).max()
        np.testing.assert_allclose(compared["force"][k], np.asarray(force), rtol=0, atol=1e-14 * peak)
        np.testing.assert_allclose(compared["torque"][k], np.asarray(torque), rtol=0, atol=1e-14 * peak)


def test_per_foot_params_stack_single_ones() -> None:
    muds = [mf.MudParameters.from_water_content(w) for w in (0.15, 0.2, 0.3)]
    many = mj3.make_params3d(muds, SPHERE, 0.01)
    for k, mud in enumerate(muds):
        one = mj3.make_params3d(mud, SPHERE, 0.01)
        for a, b in zip(jax.tree.leaves(many), jax.tree.leaves(one), strict=True):
            np.testing.assert_array_equal(np.asarray(a)[k], np.asarray(b))
    assert float(many.lateral_stiffness[2]) == muds[2].k_m_w
    assert float(mj3.make_params3d(muds[0], SPHERE, lateral_stiffness=1e5).lateral_stiffness) == 1e5
    assert float(mj3.make_params3d(muds[0], SPHERE, width=0.05).elements.width) == 0.05
    state = mj3.init3d(SPHERE, batch=3)
    assert state.slip.shape == (3, SPHERE.n, 2) and state.elements.mode.shape == (3, SPHERE.n)


def test_bad_input_gives_nan_and_keeps_the_state(compared: dict[str, Any]) -> None:
    """What MudContact3D refuses (InputError), the JAX step answers with NaN and skips: the run goes on as if
    the bad sample had not been there, bit for bit."""
    k = 8  # the capsule sliding
    _, mud, shape, _, pos, quat = compared["cases"][k]
    bad = [  # (before sample, position, quaternion, dt): each refused by MudContact3D.step
        (0, [math.nan, 0.0, 0.0], UPRIGHT, 0.0),  # before the first step: it stays unstarted
        (100, [0.0, math.inf, -0.01], UPRIGHT, DT),
        (150, pos[150], [2.0, 0.0, 0.0, 0.0], DT),  # not of norm 1
        (200, pos[200], [1.0, 0.0, math.nan, 0.0], DT),
        (250, pos[250], quat[250], 0.0),  # dt out of range
        (300, pos[300], quat[300], math.nan),
        (350, pos[350], quat[350], 2e3),
        (400, [0.0, 0.0, -200.0], UPRIGHT, DT),  # 200 m deep
        (450, [2e4, 0.0, -0.01], UPRIGHT, DT),  # 20 km from the world origin
    ]
    contact = MudContact3D(mud, shape)
    for j, (_, p, q, dt) in enumerate(bad):
        if j == 1:
            contact.step(pos[0], quat[0], 0.0)
        with pytest.raises(InputError):
            contact.step(p, q, dt)
    # the same run with the bad samples inserted, cut to the same length (RUN is compiled for it)
    kept = TIME.size - len(bad)
    rows_p, rows_q, rows_dt, inserted = [], [], [], []
    at = {b[0]: b for b in bad}
    for i in range(kept):
        if i in at:
            inserted.append(len(rows_p))
            rows_p.append(at[i][1])
            rows_q.append(at[i][2])
            rows_dt.append(at[i][3])
        rows_p.append(pos[i])
        rows_q.append(quat[i])
        rows_dt.append(DTS[i])
    params = compared["params"][k]
    _, (force, torque) = RUN(mj3.init3d(CAPSULE), params, jnp.asarray(np.array(rows_p)),
                             jnp.asarray(np.array(rows_q)), jnp.asarray(np.array(rows_dt)))
    force, torque = np.asarray(force), np.asarray(torque)
    good = np.setdiff1d(np.arange(len(rows_p)), inserted)
    assert np.isnan(force[inserted]).all() and np.isnan(torque[inserted]).all()
    _, (clean_f, clean_t) = RUN(mj3.init3d(CAPSULE), params, jnp.asarray(pos), jnp.asarray(quat), jnp.asarray(DTS))
    np.testing.assert_array_equal(force[good], np.asarray(clean_f)[:kept])
    np.testing.assert_array_equal(torque[good], np.asarray(clean_t)[:kept])


def test_wrong_shapes_and_bad_params_raise() -> None:
    mud = mf.MudParameters.from_water_content(0.25)
    params = mj3.make_params3d(mud, SPHERE)
    state = mj3.init3d(SPHERE)
    with pytest.raises(InputError, match="position must be 3"):
        mj3.step3d(state, params, jnp.zeros(2), jnp.asarray(UPRIGHT), DT)
    with pytest.raises(InputError, match="same shape"):
        mj3.step3d(mj3.init3d(SOLE), params, jnp.zeros(3), jnp.asarray(UPRIGHT), DT)
    for call, match in (
        (lambda: mj3.make_params3d(mud, mf.Foot.paper()), "Shape"),
        (lambda: mj3.make_params3d("mud", SPHERE), "MudParameters"),
        (lambda: mj3.make_params3d([], SPHERE), "MudParameters"),
        (lambda: mj3.make_params3d(mud, SPHERE, math.nan), "surface_height"),
        (lambda: mj3.make_params3d(mud, SPHERE, lateral_stiffness=-1.0), "lateral_stiffness"),
        (lambda: mj3.make_params3d(mud, shapes.Shape(SOLE.centroids, SOLE.normals, SOLE.areas)), "width"),
        (lambda: mj3.init3d(SPHERE, batch=0), "batch"),
        (lambda: mj3.init3d(SPHERE, batch=10**400), r"^batch \(the number of feet\) must be at most 10000000"),
    ):
        with pytest.raises(InputError, match=match):
            call()


def test_reset_makes_the_next_step_a_first_step() -> None:
    state = mj3.init3d(SPHERE, batch=2)._replace(started=jnp.array([True, True]),
                                                  slip=jnp.ones((2, SPHERE.n, 2)))
    fresh = light_jit(mj3.reset3d)(state, jnp.array([True, False]))  # one compile, not one per operation
    assert np.asarray(fresh.started).tolist() == [False, True]
    assert float(jnp.abs(fresh.slip[0]).max()) == 0.0 and float(fresh.slip[1].min()) == 1.0
    assert (np.asarray(fresh.elements.mode[0]) == -1).all()


def _one_step(position: Any, angle: Any, stiffness: Any, alpha: Any, slip: Any, state: mj3.State3D,
              params: mj3.Params3D) -> Any:
    """A combination of the next step's force [N] and torque [N m] from ``state``, at a pose tilted by ``angle``."""
    params = params._replace(lateral_stiffness=stiffness, elements=params.elements._replace(alpha=alpha))
    quat = jnp.stack([jnp.cos(angle / 2), 0.0, jnp.sin(angle / 2), 0.0])
    _, force, torque = mj3.step3d(state._replace(slip=slip), params, position, quat, DT)
    return force[0] + 0.1 * force[2] + 30.0 * torque[1]


def test_grad_is_finite_and_matches_finite_differences() -> None:
    """Gradients of a step's wrench with respect to the pose, two parameters and the carried slips (the
    state a lax.scan passes on): finite, and equal to central differences where the law is smooth."""
    mud = mf.MudParameters.from_water_content(0.25)
    params = _padded(mj3.make_params3d(mud, SPHERE))
    # pushed in to 15 mm (0.3 s), then slid sideways and turned: bearing, yielding and elastic elements
    x = np.interp(TIME, [0.0, 0.3, 1.2], [0.0, 0.0, 0.02])
    pos = np.stack([x, np.zeros(TIME.size), 0.0192 - np.interp(TIME, [0.0, 0.3], [-2e-3, 15e-3])], axis=1)
    angle = np.interp(TIME, [0.0, 0.3, 1.2], [0.0, 0.0, 0.3])
    state, _ = RUN(mj3.init3d(CAPSULE), params, jnp.asarray(pos),
                   jnp.asarray(_quat([0.0, 1.0, 0.0], angle)), jnp.asarray(DTS))
    assert float(jnp.abs(state.slip).max()) > 0.0
    value_and_grad = light_jit(jax.value_and_grad(_one_step, argnums=(0, 1, 2, 3, 4)))
    args = [jnp.asarray(pos[-1] + [4e-5, 1e-5, 0.0]), 0.302, mud.k_m_w, mud.alpha, state.slip]
    value, grads = value_and_grad(*args, state, params)
    assert np.isfinite(float(value))
    for g in grads:
        assert np.isfinite(np.asarray(g)).all()
    assert float(jnp.abs(grads[0]).min()) > 0.0 and float(grads[1]) != 0.0 and float(grads[2]) != 0.0
    assert float(grads[3]) != 0.0 and float(jnp.abs(grads[4]).max()) > 0.0

    def moved(i: int, h: float) -> float:
        shifted = list(args)
        shifted[i] = shifted[i] + h if i else shifted[i].at[0].add(h)
        return float(value_and_grad(*shifted, state, params)[0])

    for i, h, g in ((0, 1e-8, float(grads[0][0])), (2, 1e-5 * mud.k_m_w, float(grads[2])),
                    (3, 1e-5 * mud.alpha, float(grads[3]))):  # x, k, alpha: no element crosses the surface
        fd = (moved(i, h) - moved(i, -h)) / (2.0 * h)
        assert g == pytest.approx(fd, rel=1e-5), i


def test_inputs_of_wrong_types_are_refused_when_tracing() -> None:
    """Strings, booleans, complex numbers, ragged lists, a dt or hold of many values, a state or params of another
    type, a dtype that is not float32/float64 and a stiffness beyond MudContact3D's bound are refused with one
    line (jnp.asarray read "0.01" as a number and True as 1; an int32 dtype truncated the mud; a stiffness of
    1e300 became inf in float32), and traced inputs still go through. A hold known when tracing must be finite
    and >= 0 (inf held every element still: a foot that never sinks)."""
    mud = mf.MudParameters.from_water_content(0.25)
    params = mj3.make_params3d(mud, SPHERE)
    state = mj3.init3d(SPHERE)
    p, q = [0.0, 0.0, 0.01], UPRIGHT
    for call, match in (
        (lambda: mj3.step3d(state, params, ["0", "0", "0.01"], q, DT), "position must be real numbers"),
        (lambda: mj3.step3d(state, params, [0.0, 0.0, True], q, DT), "booleans"),
        (lambda: mj3.step3d(state, params, [0.0, 0.0, 0.01 + 1j], q, DT), "complex"),
        (lambda: mj3.step3d(state, params, [0.0, 0.0, [0.01]], q, DT), "position must be real numbers"),
        (lambda: mj3.step3d(state, params, p, jnp.asarray([True, False, False, False]), DT), "quaternion"),
        (lambda: mj3.step3d(state, params, p, q, "0.01"), "dt must be real numbers"),
        (lambda: mj3.step3d(state, params, p, q, True), "dt must be real numbers"),
        (lambda: mj3.step3d(state, params, p, q, np.array([DT, DT])), "dt must be one number"),
        (lambda: mj3.step3d(state, params, p, q, DT, hold="x"), "hold must be real numbers"),
        (lambda: mj3.step3d(state, params, p, q, DT, hold=np.ones(5)), "hold must be one number"),
        (lambda: mj3.step3d(state, params, p, q, DT, hold=math.inf), "hold must be finite and >= 0"),
        (lambda: mj3.step3d(state, params, p, q, DT, hold=-1e-9), "hold must be finite and >= 0"),
        (lambda: mj3.step3d(state, params, [0, 0, 10**400], q, DT), "^position .* integer too large"),  # OverflowError
        (lambda: mj3.step3d(state, params, p, q, 10**400), "^dt .* integer too large"),  # was OverflowError
        (lambda: mj3.step3d(None, params, p, q, DT), "State3D"),
        (lambda: mj3.step3d(params, state, p, q, DT), "State3D"),
        (lambda: mj3.step3d(state, None, p, q, DT), "Params3D"),
        (lambda: mj3.make_params3d(mud, SPHERE, dtype="int32"), "float32 or float64"),
        (lambda: mj3.make_params3d(mud, SPHERE, dtype="no such type"), "float32 or float64"),
        (lambda: mj3.make_params3d(mud, SPHERE, dtype=jnp.float16), "float32 or float64"),
        (lambda: mj3.init3d(SPHERE, dtype=np.complex64), "float32 or float64"),
        (lambda: mj3.make_params3d(mud, SPHERE, lateral_stiffness=1e300), r"within \(0, 1e\+12\]"),
        (lambda: mj3.reset3d(state, "x"), "mask must be a bool"),
        (lambda: mj3.reset3d(mj3.init3d(SPHERE, batch=3), [True, False]), "mask must be a bool"),
        (lambda: mj3.reset3d(mj3.init3d(SPHERE, batch=2), [True, [False]]), "mask .* got a ragged list"),  # numpy's
    ):
        with pytest.raises(InputError, match=match):
            call()
    # numbers and lists go through the checks as before (traced, not run: running the step op by op takes seconds)
    shapes = jax.eval_shape(lambda: mj3.step3d(state, params, p, q, DT, hold=1e-9))
    assert shapes[1].shape == (3,)
    step = light_jit(lambda pos, dt: mj3.step3d(state, params, pos, jnp.asarray(UPRIGHT), dt, hold=1e-9)[1])  # traced
    assert float(step(jnp.asarray(p), DT)[2]) > 0.0
