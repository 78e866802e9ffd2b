"""The MuJoCo adapter: drops against the exact solution, sticking without chatter, any foot body."""

from __future__ import annotations

import math

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

from mudforce import MudParameters  # noqa: E402
from mudforce.engines.dynamics import GRAVITY, exact_drop  # noqa: E402
from mudforce.engines.mujoco import MudAdapter, MudPatch, add_mud, simulate_drop  # noqa: E402
from mudforce.errors import InputError  # noqa: E402

CASES = [(w, m) for w in (0.15, 0.20, 0.25) for m in (5.0, 10.0, 20.0)]


@pytest.mark.parametrize(("water", "mass"), CASES)
def test_mujoco_drop_rests_at_the_exact_depth(water: float, mass: float) -> None:
    params = MudParameters.from_water_content(water)
    res = simulate_drop(mass, params)
    ref = exact_drop(mass, params)
    assert abs(res.end_depth / ref.end_depth - 1.0) < 0.05  # measured: at most 0.42% at 1 ms steps
    assert res.force_std(1.0) <= 0.02 * mass * GRAVITY
    assert np.mean(res.force[res.time >= 7.0]) == pytest.approx(mass * GRAVITY, rel=1e-3)
    late = res.time >= 5.0
    assert set(np.array(res.phase_names)[late]) <= {"STUCK", "INTRUSION"}  # no withdrawal chatter


def test_mujoco_and_builtin_agree_from_a_height() -> None:
    from mudforce.engines.dynamics import simulate_foot

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
    patches = [MudPatch(params, surface_height=0.0),
               MudPatch(params, surface_height=0.0, extent=(-0.5, 0.5, -0.5, 0.5))]
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


FEET_XML = """
<mujoco>
  <asset><mesh name="wedge" vertex="0 0 0  0.04 0 0  0 0.02 0  0 0 0.01"/></asset>
  <worldbody>
    <body name="ball"><freejoint/><geom name="toe" type="sphere" size="0.04" mass="1"/></body>
    <body name="plate"><freejoint/><geom type="box" size="0.01 0.03 0.005" mass="1"/></body>
    <body name="rod"><freejoint/><geom name="rod" type="capsule" size="0.01 0.05" quat="0.7071068 0.7071068 0 0"
                                       mass="1"/></body>
    <body name="post"><freejoint/><geom name="post" type="cylinder" size="0.015 0.02" mass="1"/></body>
    <body name="egg"><freejoint/><geom name="egg" type="ellipsoid" size="0.03 0.02 0.01" mass="1"/></body>
    <body name="wedge"><freejoint/><geom name="wedge" type="mesh" mesh="wedge" mass="1"/></body>
    <body name="two"><freejoint/><geom type="sphere" size="0.01"/><geom type="sphere" size="0.01"/></body>
    <body name="none" pos="0 0 1"><freejoint/><site name="s"/><inertial pos="0 0 0" mass="1"
                                                                  diaginertia="1 1 1"/></body>
  </worldbody>
</mujoco>
"""


def test_each_foot_takes_its_sole_from_its_geom_and_none_is_silently_the_paper_s() -> None:
    """A spherical toe is a disc of its diameter, not the paper's 51 x 38 mm block (a 107 kg robot sank 346 mm)."""
    from mudforce.engines.mujoco import foot_of
    from mudforce.model.foot import Foot

    model = mujoco.MjModel.from_xml_string(FEET_XML)
    assert foot_of(model, "toe") == Foot.disc(0.08)
    assert foot_of(model, "ball") == Foot.disc(0.08)  # a body with one geom
    assert foot_of(model, "plate") == Foot.cuboid(0.06, 0.02)
    rod = foot_of(model, "rod")  # lying down: its length with the caps, by its diameter
    assert rod.area == pytest.approx(0.12 * 0.02) and rod.width == pytest.approx(0.02)
    assert foot_of(model, "post") == Foot.disc(0.03)  # upright
    egg = foot_of(model, "egg")
    assert egg.area == pytest.approx(np.pi * 0.03 * 0.02) and egg.width == pytest.approx(0.04)
    wedge = foot_of(model, "wedge")  # MuJoCo stores a mesh in its inertial frame: the extents there
    extent = np.ptp(model.mesh_vert[: model.mesh_vertnum[0]], axis=0)
    assert wedge.width == pytest.approx(min(extent[:2])) and wedge.area == pytest.approx(extent[0] * extent[1])
    for name, match in (("two", "2 geoms"), ("none", "0 geoms"), ("nope", "no geom or body")):
        with pytest.raises(InputError, match=match):
            foot_of(model, name)
    # a geom_type or mesh id written by hand after compiling: a mesh id of -1 was the model's last mesh (the wedge's
    # 20 x 20 mm sole for the toe), 3 numpy's IndexError, a geom_type of 99 mjtGeom's ValueError
    edited = mujoco.MjModel.from_xml_string(FEET_XML)
    edited.geom_type[edited.geom("toe").id] = mujoco.mjtGeom.mjGEOM_MESH
    edited.geom_dataid[edited.geom("wedge").id] = 3
    for name, mesh in (("toe", -1), ("wedge", 3)):
        with pytest.raises(InputError) as err:
            foot_of(edited, name)
        assert str(err.value) == (f"foot {name!r} is a mesh geom of mesh id {mesh} (geom_dataid); expected a mesh "
                                  "id 0 to 0")
    edited.geom_type[edited.geom("toe").id] = 99
    with pytest.raises(InputError, match=r"^foot 'toe' has geom_type 99, which is no MuJoCo geom type; expected "
                                         r"sphere, .*, or give foot= \(a mudforce.Foot per foot\)$"):
        foot_of(edited, "toe")
    spec = mujoco.MjSpec.from_string(FEET_XML)
    add_mud(spec, ["toe", "two"])
    model = spec.compile()
    with pytest.raises(InputError, match="2 geoms"):
        MudAdapter(model, mujoco.MjData(model), ["toe", "two"], MudPatch(MudParameters.from_water_content(0.25)))
    mud = MudAdapter(model, mujoco.MjData(model), ["toe"], MudPatch(MudParameters.from_water_content(0.25)))
    assert mud.params[0, 0] > 0.0  # built with the toe's disc


def test_a_turned_foot_s_contact_point_is_its_lowest_point() -> None:
    """add_mud took a geom's bottom along its local z, from the spec, where a geom turned by euler or axisangle or
    placed in a <frame> keeps its quat (and a frame's placement) unset: a box turned 90 degrees about y got its
    contact point 15 mm above its lowest point; now the lowest point of the compiled geom with its body upright
    (an upright geom's as before)."""
    xml = ('<mujoco><worldbody><body pos="0 0 0.3"><freejoint/>'
           '<geom name="b" type="box" size="0.02 0.01 0.005" euler="0 90 0" pos="0 0 -0.1" mass="0.2"/>'
           '<frame euler="0 0 30" pos="0 0 -0.05"><geom name="f" type="capsule" size="0.01 0.02" '
           'axisangle="1 0 0 90" pos="0.05 0 -0.1" mass="0.2"/></frame>'
           '<geom name="u" type="box" size="0.02 0.01 0.005" pos="0.2 0 -0.1" mass="0.1"/>'
           '</body></worldbody></mujoco>')
    spec = mujoco.MjSpec.from_string(xml)
    add_mud(spec, ["b", "f", "u"])
    model = spec.compile()
    np.testing.assert_allclose(model.site("mud_site_b").pos, [0.0, 0.0, -0.12], rtol=0, atol=1e-15)
    np.testing.assert_allclose(model.site("mud_site_f").pos, [0.05 * math.cos(math.pi / 6),
                                                            0.05 * math.sin(math.pi / 6), -0.16], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(model.site("mud_site_u").pos, [0.2, 0.0, -0.1 - 0.005])  # as before, bit for bit


def test_a_fromto_foot_s_contact_point_is_its_bottom() -> None:
    """add_mud read a geom's pos, quat and size from the spec, where a fromto geom leaves them unset: a capsule
    foot from 0.25 to 0.3 m below its body's origin got its contact point 10 mm below the origin (its radius), so
    the foot met the mud 0.3 m late; now its bottom, where compiling puts it (local z from its second point to
    its first), as a geom given by pos and quat."""
    xml = ('<mujoco><worldbody><body pos="0 0 0.31"><freejoint/><geom name="pill" type="capsule" '
           'fromto="0.1 0 -0.25 0.1 0 -0.3" size="0.01" mass="0.2"/><geom name="same" type="capsule" '
           'pos="0.3 0 -0.275" size="0.01 0.025" mass="0.2"/></body></worldbody></mujoco>')
    spec = mujoco.MjSpec.from_string(xml)
    add_mud(spec, ["pill", "same"])
    model = spec.compile()
    np.testing.assert_allclose(model.site("mud_site_pill").pos, [0.1, 0.0, -0.31], rtol=0, atol=1e-15)
    np.testing.assert_allclose(model.site("mud_site_same").pos, [0.3, 0.0, -0.31], rtol=0, atol=1e-15)
