"""The MuJoCo adapter: drops against the exact solution, sticking without chatter, any foot body."""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

from mudforce import MudParameters  # noqa: E402
from mudforce.dynamics import GRAVITY, exact_drop  # noqa: E402
from mudforce.errors import InputError  # noqa: E402
from mudforce.mujoco import MudAdapter, MudPatch, add_mud, simulate_drop  # noqa: E402

CASES = [(w, m) for w in (0.15, 0.20, 0.25) for m in (5.0, 10.0, 20.0)]


@pytest.mark.parametrize(("water", "mass"), CASES)
def test_mujoco_drop_rests_at_the_exact_depth(water: float, mass: float) -> None:
    params = MudParameters.from_water_content(water)
    res = simulate_drop(mass, params)
    ref = exact_drop(mass, params)
    assert abs(res.end_depth / ref.rest_depth - 1.0) < 0.05  # measured: at most 0.42% at 1 ms steps
    assert res.force_std(1.0) <= 0.02 * mass * GRAVITY
    assert np.mean(res.force[res.time >= 7.0]) == pytest.approx(mass * GRAVITY, rel=1e-3)
    late = res.time >= 5.0
    assert set(np.array(res.phase_names)[late]) <= {"STUCK", "INTRUSION"}  # no withdrawal chatter


def test_mujoco_and_builtin_agree_from_a_height() -> None:
    from mudforce.dynamics import simulate_foot

    params = MudParameters.from_water_content(0.20)
    a = simulate_drop(10.0, params, duration=2.0, height=0.03)
    b = simulate_foot(10.0, params, duration=2.0, height=0.03)
    assert a.at_rest and b.at_rest
    assert a.rest_depth == pytest.approx(b.rest_depth, rel=0.02)
    assert np.max(np.abs(a.depth - b.depth)) < 0.05 * b.rest_depth


XML = """
<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <body name="a" pos="0 0 0.02"><freejoint/>
      <geom name="sole_a" type="box" size="0.0255 0.019 0.0125" mass="5"/></body>
    <body name="b" pos="1 0 0.0125"><freejoint/><geom type="box" size="0.0255 0.019 0.0125" mass="5"/></body>
  </worldbody>
</mujoco>
"""


def test_free_bodies_named_by_geom_or_body_with_patches() -> None:
    spec = mujoco.MjSpec.from_string(XML)
    add_mud(spec, ["sole_a", "b"], points=[(0.0, 0.0, -0.0125), (0.0, 0.0, -0.0125)])
    model = spec.compile()
    data = mujoco.MjData(model)
    params = MudParameters.from_water_content(0.20)
    patches = [MudPatch(params, height=0.0), MudPatch(params, height=0.0, extent=(-0.5, 0.5, -0.5, 0.5))]
    mud = MudAdapter(model, data, ["sole_a", "b"], patches)
    for _ in range(3000):
        data.xfrc_applied[:] = 0.0  # users may clear their forces between steps
        mud.step()
    assert not data.xfrc_applied.any()  # the mud force is taken back after each step
    ref = exact_drop(5.0, params, duration=3.0, height=0.0075)
    # foot a (free joint: 6 dof) sinks and sticks at the 1-dof solution; foot b is outside its patch and falls
    assert mud.depths[0] == pytest.approx(ref.rest_depth, rel=0.05)
    assert mud.modes[1] == "FREE" and data.xpos[2, 2] < -1.0
    f = mud.contact_forces
    assert f[0] == pytest.approx(5.0 * GRAVITY, rel=1e-3)
    assert f[1] == 0.0
    # the foot stays upright (the force acts at the bottom centre, below the centre of mass)
    assert abs(data.qvel[3:6]).max() < 1e-6


def test_unprepared_foot_is_refused() -> None:
    spec = mujoco.MjSpec.from_string(XML)
    model = spec.compile()
    with pytest.raises(InputError, match="add_mud"):
        MudAdapter(model, mujoco.MjData(model), ["sole_a"], MudPatch(MudParameters.from_water_content(0.2)))
    with pytest.raises(InputError, match="no geom or body"):
        add_mud(mujoco.MjSpec.from_string(XML), ["nope"])


def test_nstep_equals_single_steps_and_anchor_stays_above_the_foot() -> None:
    runs = []
    for nsteps in ([5, 5, 5], [1] * 15):
        spec = mujoco.MjSpec.from_string(XML)
        add_mud(spec, ["sole_a"], points=[(0.0, 0.0, -0.0125)])
        model = spec.compile()
        data = mujoco.MjData(model)
        mud = MudAdapter(model, data, ["sole_a"], MudPatch(MudParameters.from_water_content(0.20)))
        for n in nsteps:
            mud.step(n)
        runs.append((data.qpos.copy(), mud.state))
        # the tendon's anchor (a world site the adapter moves) is 1 m above the contact point
        foot = data.site("mud_site_sole_a").xpos
        anchor = model.site("mud_anchor_site_sole_a").pos
        assert anchor[:2] == pytest.approx(foot[:2]) and anchor[2] == pytest.approx(foot[2] + 1.0)
    assert np.array_equal(runs[0][0], runs[1][0]) and np.array_equal(runs[0][1], runs[1][1])
