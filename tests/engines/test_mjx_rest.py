"""mudforce.engines.mjx: the stuck feet of one world are held together (issue 22: a box on four soles rests)."""

from __future__ import annotations

import numpy as np
import pytest

from jax_compile import light_jit

pytest.importorskip("jax")
pytest.importorskip("mujoco.mjx")

from mudforce.model.parameters import MudParameters
from mudforce.references.drop import exact_drop

W15 = MudParameters.from_water_content(0.15)
CORNERS = ((0.2, 0.15), (-0.2, 0.15), (0.2, -0.15), (-0.2, -0.15))


def box_xml(dt: float) -> str:
    """A 100 kg box on a free joint, a sole site at each of four corners 50 mm below its centre."""
    sites = "".join(f'<site name="s{i}" pos="{x} {y} -0.05"/>' for i, (x, y) in enumerate(CORNERS))
    return f"""<mujoco><option timestep="{dt!r}" gravity="0 0 -9.81" integrator="Euler"/>
<worldbody><body name="box" pos="0 0 0.05"><freejoint/>
<geom type="box" size="0.25 0.2 0.04" mass="100" contype="0" conaffinity="0"/>{sites}</body></worldbody></mujoco>"""


def test_box_on_four_soles_rests_where_one_sole_under_a_quarter_does() -> None:
    import jax
    import mujoco
    from mujoco import mjx

    import mudforce.engines.mjx as mud

    dt, n = 5e-3, 400  # 2 s; the box rests within 0.3 s
    model = mujoco.MjModel.from_xml_string(box_xml(dt))
    m = mjx.put_model(model)
    patch = mud.add_mud(model, [f"s{i}" for i in range(4)], W15)

    def body(carry, _):  # type: ignore[no-untyped-def]
        d, c = carry
        d, c, f = mud.step(m, d, c, patch)
        return (d, c), (d.qpos[2], f, c.stuck)

    run = light_jit(lambda d: jax.lax.scan(body, (d, mud.init(patch)), None, length=n)[1])  # numbers, not speed
    z, force, stuck = (np.asarray(a, dtype=np.float64) for a in run(mjx.make_data(m)))
    t = np.arange(1, n + 1) * dt
    last = t >= t[-1] - 1.0
    creep = -np.polyfit(t[last], z[last], 1)[0]  # [m/s], positive down; was 6.1 mm/s with each foot alone
    assert abs(creep) < 1e-5
    assert stuck[last].all()
    np.testing.assert_allclose(force[last].sum(axis=1), 100.0 * 9.81, rtol=1e-4)  # the feet carry the weight
    np.testing.assert_allclose(force[-1], 25.0 * 9.81, rtol=1e-3)  # shared evenly, by symmetry
    rest = exact_drop(25.0, W15, duration=2.0).rest_depth
    assert abs((0.05 - z[-1]) / rest - 1.0) < 0.005  # each sole rests where one sole under 25 kg does


def test_joint_forces_are_the_box_constrained_solution() -> None:
    """Each foot's force is in its band; a stuck sole ends the step at rest, another at the edge it is pushed to."""
    import jax
    import jax.numpy as jnp

    import mudforce.jax as mj
    from mudforce.engines.mjx import _joint_forces

    was = bool(jax.config.jax_enable_x64)  # put back as found: other modules in this worker may run in float64
    jax.config.update("jax_enable_x64", True)
    try:
        rng = np.random.default_rng(7)
        n = 3
        state = mj.init(n, jnp.float64)._replace(mode=jnp.full((n,), mj.CONTACT, dtype=jnp.int8))
        solve = light_jit(lambda *a: _joint_forces(*a, state, jnp.zeros(n)))
        for _ in range(20):
            j = rng.normal(size=(n, 5))
            delassus = j @ np.diag(rng.uniform(0.01, 0.1, 5)) @ j.T  # J M^-1 J^T [1/kg]
            target = rng.normal(scale=500.0, size=n) @ delassus  # [m/s^2]: the forces that stop them ~ 500 N
            f_up = rng.uniform(-300.0, 0.0, n)
            f_down = f_up + rng.uniform(10.0, 600.0, n)
            force, stuck = (np.asarray(a) for a in solve(jnp.asarray(delassus), jnp.asarray(target),
                                                          jnp.asarray(f_up), jnp.asarray(f_down), jnp.zeros(n)))
            residual = delassus @ force - target  # dt times this is each sole's upward velocity at the step's end
            scale = np.abs(target).max()
            assert np.all(force >= f_up - 1e-9) and np.all(force <= f_down + 1e-9)
            assert np.all(np.abs(residual[stuck]) <= 1e-8 * scale)
            at_up, at_down = ~stuck & (force <= f_up + 1e-9), ~stuck & (force >= f_down - 1e-9)
            assert np.all(at_up | at_down | stuck)
            assert np.all(residual[at_up] >= -1e-6 * scale)  # held by the least it can: it rises (or rests)
            assert np.all(residual[at_down] <= 1e-6 * scale)  # pushed by the most it can: it sinks (or rests)
    finally:
        jax.config.update("jax_enable_x64", was)
