"""Drops of every shape rest where the exact 3-D drop does, on the CPU adapter and in MJX, at the default step.

The reference: :func:`mudforce.references.drop.exact_drop_3d` (DOP853 with events on every element level of the
same elements the engines use; the paper's sole: the 1-D :func:`~mudforce.references.drop.exact_drop`). Each foot
is released with its lowest point at the surface and dropped straight down; 0.1 s is past its stop (every drop
here sticks for good, by 0.07 s: the spring of Eq. (4) alone then carries it). Coarse 10 mm elements, W = 15 % and
20 %. The CPU adapter at 1 ms (``simulate_drop_3d``'s default); MJX at 2 ms, the largest step docs/engines3d.md
recommends (its 1 ms is closer still, and twice the test's run time): every foot of both muds in one model (two
patches), one jitted scan compiled with XLA's light options.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("mujoco")

from mudforce import MudParameters
from mudforce.model import shapes
from mudforce.model.foot import Foot
from mudforce.references.drop import exact_drop, exact_drop_3d

RES = 0.01  # [m]
DT = 1e-3  # [s]
MJX_DT = 2e-3  # [s]
DURATION = 0.1  # [s]
WATER = (0.15, 0.20)
LYING = math.pi / 2  # the capsule's tilt about x: its axis horizontal [rad]
# (name, MuJoCo geom kind, full sizes [m], mass [kg], tilt [rad], the lowest point below the centre [m])
FEET = (("sphere", "sphere", (0.04,), 2.0, 0.0, 0.02), ("capsule", "capsule", (0.03, 0.06), 2.0, LYING, 0.015),
        ("box", "box", (0.03, 0.03, 0.03), 3.0, 0.0, 0.015), ("sole", "box", (0.051, 0.038, 0.025), 5.0, 0.0, 0.0125))


def _reference(name: str, mass: float, water: float) -> float:
    """The exact rest depth of the lowest point [m]."""
    params = MudParameters.from_water_content(water)
    if name == "sole":  # the box's bottom is the paper's sole: the 1-D exact drop
        return exact_drop(mass, params, Foot.cuboid(0.051, 0.038), duration=DURATION).rest_depth
    shape = {"sphere": lambda: shapes.sphere(0.04, resolution=RES),
             "capsule": lambda: shapes.capsule(0.03, 0.06, resolution=RES),
             "box": lambda: shapes.box(0.03, 0.03, 0.03, resolution=RES)}[name]()
    quat = (math.cos(LYING / 2), math.sin(LYING / 2), 0.0, 0.0) if name == "capsule" else (1.0, 0.0, 0.0, 0.0)
    low = next(f[5] for f in FEET if f[0] == name)
    return exact_drop_3d(mass, params, shape, orientation=quat, bottom=-low, duration=DURATION).rest_depth


@pytest.fixture(scope="module")
def references() -> dict[tuple[str, float], float]:
    return {(f[0], w): _reference(f[0], f[3], w) for f in FEET for w in WATER}


@pytest.mark.parametrize("water", WATER)
def test_cpu_adapter_drops_rest_where_the_exact_drop_does(references: dict[tuple[str, float], float],
                                                          water: float) -> None:
    """Measured (1 ms): sphere -0.04 %, lying capsule, box, sole +0.35 % (W = 15 %)."""
    from mudforce.engines.mujoco import simulate_drop_3d

    params = MudParameters.from_water_content(water)
    for name, kind, size, mass, tilt, _ in FEET:
        res = simulate_drop_3d(mass, params, kind, size, duration=DURATION, tilt=tilt, dt=DT, resolution=RES)
        ref = references[name, water]
        print(f"cpu {water} {name}: {res.depth[-1] * 1e3:.4f} mm, exact {ref * 1e3:.4f} mm, "
              f"{(res.depth[-1] / ref - 1) * 100:+.2f} %")
        assert res.depth[-1] == pytest.approx(ref, rel=0.02), name
        assert res.speed(0.02) < 1e-4, name  # at rest: creep < 0.1 mm/s


def _mjx_xml() -> str:
    bodies = []
    for k in range(len(WATER)):
        for j, (name, kind, size, mass, tilt, low) in enumerate(FEET):
            half = " ".join(repr(s / 2) for s in size)
            quat = f"{math.cos(tilt / 2)!r} {math.sin(tilt / 2)!r} 0 0"
            bodies.append(f'<body pos="{5 * k + j} 0 {low!r}" quat="{quat}"><freejoint/>'
                          f'<geom name="{name}{k}" type="{kind}" size="{half}" mass="{mass!r}"/></body>')
    return (f'<mujoco><option timestep="{MJX_DT!r}" integrator="Euler"/><default><geom contype="0" conaffinity="0"/>'
            f'</default><worldbody>{"".join(bodies)}</worldbody></mujoco>')


def test_mjx_drops_rest_where_the_exact_drop_does(references: dict[tuple[str, float], float]) -> None:
    """Measured (2 ms, float32): within 0.3 %."""
    pytest.importorskip("mujoco.mjx")
    import jax
    import mujoco
    from mujoco import mjx

    import mudforce.engines.mjx3d as mud3d
    from jax_compile import light
    from mudforce.engines.mujoco import MudPatch

    model = mujoco.MjModel.from_xml_string(_mjx_xml())
    names = [f"{f[0]}{k}" for k in range(len(WATER)) for f in FEET]
    patches = [MudPatch(MudParameters.from_water_content(WATER[0]), extent=(-1.0, 4.0, -1.0, 1.0)),
               MudPatch(MudParameters.from_water_content(WATER[1]))]
    mud = mud3d.add_mud(model, names, patches, resolution=RES)
    m = mjx.put_model(model)
    steps = round(DURATION / MJX_DT)

    def body(carry, _):  # type: ignore[no-untyped-def]
        d, s = carry
        d, s, _ = mud3d.step(m, d, s, mud)
        return (d, s), s.depth

    run = jax.jit(lambda d: jax.lax.scan(body, (d, mud3d.init(mud)), None, length=steps)[1])
    d0 = mjx.make_data(m)
    depth = np.asarray(run.lower(d0).compile(light())(d0), dtype=np.float64)  # (steps, feet): lowest element [m]
    # s.depth is the lowest element's depth, a fixed height above the geom's lowest point (the feet do not turn):
    # how far it sank since the release (every lowest point at the surface, the first step's pose)
    sink = depth[-1] - depth[0]
    moved = np.abs(depth[-1] - depth[-11])  # the last 20 ms
    for i, name in enumerate(names):
        ref = references[name[:-1], WATER[int(name[-1])]]
        print(f"mjx {name}: {sink[i] * 1e3:.4f} mm, exact {ref * 1e3:.4f} mm, {(sink[i] / ref - 1) * 100:+.2f} %")
        assert sink[i] == pytest.approx(ref, rel=0.02), name
        assert moved[i] / 0.02 < 1e-4, name
