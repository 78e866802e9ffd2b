"""mudforce.engines.mjx3d: the 3-D law in MJX rests where the references do and holds in every direction.

One small model, one jitted scan (compiled with XLA's light optimisation: this test is about numbers, not
speed), 5 ms steps, every body on its own free joint, released at the surface: a box (the paper's sole) and two
spheres dropped, a sphere and a capsule loaded slowly (an upward push from m g to 0 over 0.6 s), and a 100 kg
box on four soles. After 1 s one dropped sphere is pushed sideways by half its hold, the other by 1.5 times it.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from jax_compile import light

pytest.importorskip("jax")
pytest.importorskip("mujoco.mjx")
import mujoco

from mudforce import MudParameters
from mudforce.engines.dynamics import GRAVITY, exact_drop
from mudforce.engines.mujoco import MudPatch
from mudforce.errors import InputError
from mudforce.model.foot import Foot

MUD = MudParameters.from_water_content(0.15)
DT = 5e-3
SETTLE, PUSH = 200, 100  # steps: 1 s to rest, then 0.5 s of sideways loads
RAMP = 0.6  # [s]
FEET = ["hold", "slide", "box", "sphere", "capsule", "sole0", "sole1", "sole2", "sole3"]
SOLES = "".join(f'<body pos="{x} {y} -0.0875"><geom name="sole{i}" type="box" size="0.0255 0.019 0.0125" '
                f'mass="0.05"/></body>'
                for i, (x, y) in enumerate(((0.15, 0.1), (0.15, -0.1), (-0.15, 0.1), (-0.15, -0.1))))
XML = f"""<mujoco><option timestep="{DT!r}" integrator="Euler"/><default><geom contype="0" conaffinity="0"/></default>
<worldbody>
<body pos="0 0 0.02"><freejoint/><geom name="hold" type="sphere" size="0.02" mass="2"/></body>
<body pos="1 0 0.02"><freejoint/><geom name="slide" type="sphere" size="0.02" mass="2"/></body>
<body pos="2 0 0.0125"><freejoint/><geom name="box" type="box" size="0.0255 0.019 0.0125" mass="10"/></body>
<body pos="3 0 0.02"><freejoint/><geom name="sphere" type="sphere" size="0.02" mass="2"/></body>
<body pos="4 0 0.045"><freejoint/><geom name="capsule" type="capsule" size="0.015 0.03" mass="2"/></body>
<body pos="6 0 0.1"><freejoint/><geom type="box" size="0.2 0.15 0.03" mass="99.8"/>{SOLES}</body>
</worldbody></mujoco>"""
LOWEST = np.array([0.02, 0.02, 0.0125, 0.02, 0.045])  # the drops' lowest points at release: depth = this - centre z


@pytest.fixture(scope="module")
def run() -> dict[str, np.ndarray]:
    import jax
    import jax.numpy as jnp
    from mujoco import mjx

    import mudforce.engines.mjx3d as mud3d

    model = mujoco.MjModel.from_xml_string(XML)
    m = mjx.put_model(model)
    mud = mud3d.add_mud(model, FEET, MudPatch(MUD))

    def body(carry, k):  # type: ignore[no-untyped-def]
        d, s = carry
        pushing = k >= SETTLE
        load = jnp.where(pushing, jnp.asarray([0.5, 1.5]) * s.capacity[:2, 0], 0.0)  # along u = +x
        lift = 2.0 * GRAVITY * jnp.maximum(0.0, 1.0 - k * DT / RAMP)
        d = d.replace(xfrc_applied=d.xfrc_applied.at[1:3, 0].set(load).at[4:6, 2].set(lift))
        d, s, force = mud3d.step(m, d, s, mud)
        # the 100 kg box's free joint is the sixth: its centre's z is qpos[37]; the sliding sphere's vx qvel[6]
        return (d, s), (d.geom_xpos, d.qvel[6:9], d.qpos[37], force, s.capacity, s.stuck, load)

    scan = jax.jit(lambda d: jax.lax.scan(body, (d, mud3d.init(mud)), jnp.arange(SETTLE + PUSH)))
    _, out = scan.lower(mjx.make_data(m)).compile(light())(mjx.make_data(m))
    names = ("xpos", "vel_slide", "torso_z", "force", "capacity", "stuck", "load")
    res = {k: np.asarray(v, dtype=np.float64) for k, v in zip(names, out, strict=True)}
    res["geoms"] = np.array([mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f) for f in FEET])
    return res


def _spring_depth(shape: object, mass: float, bottom: float) -> float:
    """How deep the lowest point of an upright foot rests when Eq. (4)'s spring alone carries ``m g`` [m].

    The quasi-static reference (the Maxwell strain relaxed under a slow load), computed here with numpy and
    scipy's brentq on the foot's own elements: ``sum alpha (d_i/H)^beta A_i max(-n_z, 0) = m g``.
    """
    from scipy.optimize import brentq

    c, n, a, h = shape.centroids, shape.normals, shape.areas, shape.width  # type: ignore[attr-defined]

    def excess(sink: float) -> float:
        depth = np.maximum(sink - bottom - c[:, 2], 0.0)  # the lowest point (bottom [m] below the centre) at -sink
        return float(np.sum(MUD.alpha * (depth / h) ** MUD.beta * a * np.maximum(-n[:, 2], 0.0))) - mass * GRAVITY

    return float(brentq(excess, 1e-6, 0.2))


def test_drops_and_slow_loads_rest_where_the_references_do(run: dict[str, np.ndarray]) -> None:
    """The dropped box against the 1-D exact drop (its bottom is the paper's sole); the slowly loaded sphere and
    capsule against the quasi-static depth (the CPU adapter's check, tests/engines/test_mujoco3d.py).

    Measured: box +0.52 %, sphere +0.7 %, capsule +1.05 %. The dropped spheres rest at 9.050 mm, the
    CPU adapter's at 9.047 mm (both at 5 ms, W = 15 %, 2 kg).
    """
    from mudforce.model import shapes

    z = run["xpos"][SETTLE - 1, run["geoms"][:5], 2]
    depth = LOWEST - z
    box = exact_drop(10.0, MUD, Foot.cuboid(0.051, 0.038), duration=1.0).rest_depth
    assert depth[2] == pytest.approx(box, rel=0.02)
    assert depth[3] == pytest.approx(_spring_depth(shapes.sphere(0.04), 2.0, 0.02), rel=0.02)
    assert depth[4] == pytest.approx(_spring_depth(shapes.capsule(0.03, 0.06), 2.0, 0.045), rel=0.02)
    assert depth[0] == pytest.approx(depth[1], rel=1e-6)  # the two dropped spheres are one until pushed
    assert depth[0] == pytest.approx(9.047e-3, rel=0.02)  # MudAdapter3D's, measured (simulate_drop_3d, 5 ms)


def test_a_box_on_four_soles_rests_held_jointly(run: dict[str, np.ndarray]) -> None:
    """Issue 22's case (the 1-D MJX step let it sink 6.3 mm/s at 5 ms): creep < 0.1 mm/s, force std < 2 % of m g."""
    last = slice(SETTLE - 50, SETTLE)  # the last 0.25 s at rest
    z = run["torso_z"]
    assert abs(z[SETTLE - 1] - z[SETTLE - 51]) / (50 * DT) < 1e-4
    weight = 100.0 * GRAVITY
    fz = run["force"][:, 5:, 2].sum(axis=1)
    assert fz[last].std() <= 0.02 * weight
    assert fz[SETTLE - 1] == pytest.approx(weight, rel=1e-3)
    assert run["stuck"][last, 5:, 0].all()
    assert 0.02 < 0.1 - z[SETTLE - 1] < 0.06  # its soles' depth: plausible (MudAdapter3D: 37.5 mm)


def test_sideways_below_the_hold_stays_put_above_it_slides_at_the_law_s_rate(run: dict[str, np.ndarray]) -> None:
    geoms = run["geoms"]
    hold = run["capacity"][SETTLE - 1, 0, 0]
    assert hold > 5.0  # [N]
    x = run["xpos"][:, geoms[0], 0]
    assert abs(x[-1] - x[-51]) / (50 * DT) < 1e-4  # half the hold: creep < 0.1 mm/s
    fx = run["force"][SETTLE + 50:, 0, 0]
    assert fx.mean() == pytest.approx(-run["load"][SETTLE + 50:, 0].mean(), rel=1e-3)  # it carries the load
    assert run["force"][SETTLE + 50:, 0].std(axis=0).max() <= 0.02 * 2.0 * GRAVITY
    # 1.5 holds: the sphere accelerates at (load - the law's capacity) / m
    span = slice(SETTLE + 1, SETTLE + 26)
    resist = -run["force"][span, 1, 0]
    capacity = run["capacity"][span, 1, 0]
    np.testing.assert_allclose(resist, capacity, rtol=0.05)
    accel = (run["vel_slide"][SETTLE + 25, 0] - run["vel_slide"][SETTLE, 0]) / (25 * DT)
    assert accel == pytest.approx(float(np.mean(run["load"][span, 1] - resist)) / 2.0, rel=0.1)
    assert run["xpos"][-1, geoms[1], 0] - 1.0 > 0.01  # it slid


PLANE = """<mujoco><worldbody><geom name="floor" type="plane" size="1 1 0.1"/>
<body name="ball" pos="0 0 0.02"><freejoint/><geom name="toe" type="sphere" size="0.02" mass="2"
 contype="0" conaffinity="0"/></body>
<body name="two" pos="1 0 0.2"><freejoint/><geom type="sphere" size="0.01"/><geom type="sphere" size="0.01"/></body>
</worldbody></mujoco>"""


def test_bad_input_is_refused_in_one_line() -> None:
    import mudforce.engines.mjx3d as mud3d

    model = mujoco.MjModel.from_xml_string(PLANE)
    hidden = [MudPatch(MUD), MudPatch(MUD, extent=(-0.1, 0.1, -0.1, 0.1))]
    for feet, patches, match in ((["floor"], MudPatch(MUD), "plane"), (["nope"], MudPatch(MUD), "names no geom"),
                                 (["toe"], hidden, "misses every foot"), (["two"], MudPatch(MUD), "2 geoms"),
                                 (["toe", "toe"], MudPatch(MUD), "distinct"),
                                 # its repr raised ValueError (an integer of over 4,300 digits)
                                 ([10**5000], MudPatch(MUD), "got a list holding an integer too long to show")):
        with pytest.raises(InputError, match=match) as err:
            mud3d.add_mud(model, feet, patches)
        assert "\n" not in str(err.value)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mud3d.add_mud(model, ["toe"], MudPatch(MUD))  # the toe cannot collide with the floor: no warning



def test_drop_and_step_refuse_bad_options_before_compiling(monkeypatch: pytest.MonkeyPatch) -> None:
    """A box of 1e-6 kg at 1 ms steps was flung 872 m up in 0.3 s without a word (the mud pushing 1850 times its
    weight); refused by the CPU drop's rule (the 1-D drops' lightest foot on the foot's projection), before the scan
    is compiled."""
    import jax

    import mudforce.engines.mjx3d as mud3d

    def no_compile(*args: object, **kwargs: object) -> None:
        raise AssertionError("compiled")

    monkeypatch.setattr(jax, "jit", no_compile)
    for mass, tilt, least in ((1e-6, 0.0, "0.00234"), (2e-3, 0.3, "0.0027")):
        with pytest.raises(InputError, match=rf"^mass {mass:g} kg is too light for a MuJoCo time step of 0.001 s in "
                                             rf"this mud: .* only from {least} kg") as err:
            mud3d.simulate_drop(mass, MudParameters.from_water_content(0.25), "box", (0.051, 0.038, 0.025),
                                tilt=tilt)
        assert "\n" not in str(err.value)
    # step's weight, as mudforce.engines.mjx.step's (refused before anything is read or traced): 2.0 and -5.0
    # extrapolated the band, NaN gave no force at all (the foot fell through the mud), True and "0.5" were taken
    for weight, words in ((2.0, r"within \[0, 1\] -, got 2.0"), (-5.0, "within"), (float("nan"), "got nan"),
                          (True, r"a number \[-\], got bool"), ("0.5", "got str")):
        with pytest.raises(InputError, match=rf"^weight must be .*{words}"):
            mud3d.step(None, None, None, None, weight)  # type: ignore[arg-type]
    # compiler_options that are no dict of names: JAX's AttributeError ('int' object has no attribute 'items') after
    # the scan was traced
    for options in (5, "fast", [("a", 1)], {1: True}):
        with pytest.raises(InputError, match=r"^compiler_options must be a dict of XLA's compile options \(name: "
                                             r"value\) or None, got "):
            mud3d.simulate_drop(2.0, MUD, "sphere", (0.04,), compiler_options=options)  # type: ignore[arg-type]


def test_step_refuses_a_state_or_mud_of_another_model_before_tracing_mjx() -> None:
    """As MJX's 1-D step: None for the state or mud ended in an AttributeError, a state of another mud's feet in
    JAX's broadcasting errors, MuJoCo's model in "'MjModel' object has no attribute 'opt'"-like errors, and a mud
    of another model was read with this model's geoms; each refused in one line before anything is traced."""
    from mujoco import mjx

    import mudforce.engines.mjx3d as mud3d

    model = mujoco.MjModel.from_xml_string(PLANE)
    mud = mud3d.add_mud(model, ["toe"], MudPatch(MUD))
    m, state = mjx.put_model(model), mud3d.init(mud)
    d = mjx.make_data(m)
    two = mud3d.add_mud(mujoco.MjModel.from_xml_string(XML), FEET[:2], MudPatch(MUD))
    other = mud3d.add_mud(mujoco.MjModel.from_xml_string(XML), ["sphere"], MudPatch(MUD))
    for args, words in (((m, d, None, mud), r"^state must be a MudState3D \(init\(mud\)\), got NoneType$"),
                        ((m, d, state, None), r"^mud must be a Mud3D \(add_mud\), got NoneType$"),
                        ((m, d, mud3d.init(two), mud),
                         r"^the state has 2 feet and the mud 1: a state of another mud\?"),
                        ((model, d, state, mud), r"^m must be MJX's \(mjx.put_model\(model\), mjx.make_data\(m\)\), "
                                                 r"got mujoco.MjModel$"),
                        ((m, d, state, other), r"^the mud's geoms \[\d+\] \(on bodies \[\d+\]\) are not this "
                                               r"model's \(\d+ geoms\): a mud of another model\?")):
        with pytest.raises(InputError, match=words):
            mud3d.step(*args)  # type: ignore[arg-type]


def test_set_mud_refuses_a_bool_patch_and_another_type_of_mud() -> None:
    """``set_mud(mud, params, True)`` set patch 1 (True is an int to isinstance); a mud that is not a Mud3D raised
    AttributeError. A numpy integer patch is an index like any other."""
    import mudforce.engines.mjx3d as mud3d

    model = mujoco.MjModel.from_xml_string(PLANE)
    patches = [MudPatch(MUD, extent=(-0.5, 0.5, -0.5, 0.5)), MudPatch(MUD, extent=(0.5, 1.5, -0.5, 0.5))]
    mud = mud3d.add_mud(model, ["toe"], patches)
    wet = MudParameters.from_water_content(0.3)
    for args, match in (((mud, wet, True), "patch must be an index 0 to 1"),
                        ((mud, wet, 1.0), "patch must be an index 0 to 1"),
                        ((None, wet, 0), "mud must be a Mud3D")):
        with pytest.raises(InputError, match=match):
            mud3d.set_mud(*args)  # type: ignore[arg-type]
    changed = mud3d.set_mud(mud, wet, np.int64(1))
    assert float(changed.lateral_stiffness[1, 0]) == pytest.approx(wet.k_m_w)
    assert float(changed.lateral_stiffness[0, 0]) == pytest.approx(MUD.k_m_w)
    # a mudforce.jax.Params of three worlds' muds for one foot (set_mud not vmapped) raised JAX's broadcasting
    # ValueError; its area and width, which set_mud ignores, did too. One of as many worlds as feet (here one) was
    # taken as a mud per foot without a word, against the docstring's scalars
    import mudforce.jax as mj

    for count in (3, 1):
        with pytest.raises(InputError, match=rf"^a mud's fields must be scalars \(one mud for every foot\), got k_i of "
                                             rf"shape \({count},\); vmap set_mud over worlds for a mud per world$"):
            mud3d.set_mud(mud, mj.Params(*[np.ones(count)] * len(mj.Params._fields)))
    ignored = mud3d.set_mud(mud, mj.make_params(wet)._replace(area=np.ones(3), width=np.ones(2)), 1)
    assert all(np.array_equal(a, b) for a, b in zip(ignored.elements, changed.elements, strict=True))



def test_add_mud_refuses_a_dtype_that_is_not_float_and_init_another_type_of_mud() -> None:
    """add_mud(dtype="int32") held the mud's NaN and fractions as garbage integers, "foo" raised TypeError;
    init(None) raised AttributeError."""
    import mudforce.engines.mjx3d as mud3d

    model = mujoco.MjModel.from_xml_string(PLANE)
    for dtype in ("int32", "foo", np.complex64):
        with pytest.raises(InputError, match="dtype must be float32 or float64"):
            mud3d.add_mud(model, ["toe"], MudPatch(MUD), dtype=dtype)
    with pytest.raises(InputError, match="mud must be a Mud3D"):
        mud3d.init(None)  # type: ignore[arg-type]



def test_an_extent_past_float32_is_the_infinity_it_rounds_to_without_a_warning() -> None:
    """add_mud(dtype="float32") of a patch reaching +-1e300 m: numpy's "overflow encountered in cast"."""
    import warnings

    import mudforce.engines.mjx3d as mud3d

    model = mujoco.MjModel.from_xml_string(PLANE)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mud = mud3d.add_mud(model, ["toe"], MudPatch(MUD, extent=(-1e300, 0.5, -0.5, 1e300)), dtype="float32")
    assert np.asarray(mud.extents).tolist() == [[-np.inf, 0.5, -0.5, np.inf]]
    assert mud3d.add_mud(model, ["toe"], MudPatch(MUD), dtype=np.float32).areas.dtype == np.float32


def test_add_mud_bounds_a_patch_s_surface_height_as_the_cpu_adapter_does() -> None:
    """A patch's surface 1 km up was taken (MudPatch itself now refuses it, as MudAdapter3D did: beyond +-100 m
    the law's depths mean nothing and are refused on the CPU), and 1e300 m became inf in float32 with numpy's
    overflow warning."""
    import mudforce.engines.mjx3d as mud3d

    model = mujoco.MjModel.from_xml_string(PLANE)
    for height in (1e3, -1e3, 1e300):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(InputError, match=r"^patch surface_height must be within \+-100 m, got ") as err:
                mud3d.add_mud(model, ["toe"], [MudPatch(MUD, extent=(-0.5, 0.5, -0.5, 0.5)),
                                                MudPatch(MUD, surface_height=height)], dtype=np.float32)
        assert "\n" not in str(err.value)
    assert float(mud3d.add_mud(model, ["toe"], MudPatch(MUD, surface_height=-100.0)).surface_height[0]) == -100.0
