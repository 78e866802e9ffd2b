"""A small quadruped with spherical feet trotting open-loop across rigid ground and two muds, in MuJoCo.

The robot (the MJCF below, ``QUADRUPED_XML``): a 10 kg box torso, four legs
of two hinges each (hip and knee, pitch), position servos, and 50 mm
spherical toes. The servos play an open-loop trot (diagonal pairs in
antiphase, the swing leg's knee bent to lift the toe). It starts on rigid
ground (a box whose top is at z = 0, which the toes collide with) and trots
+x into a stiff mud (``--dry``, default 15 %) and then a soft one (``--wet``,
default 30 %): two :class:`mudforce.engines.mujoco.MudPatch` regions side by
side. Under the mud there is no floor (the adapter would warn of one). Where
a toe in the mud touches the side of the rigid ground's box, at its edge,
the adapter warns that a rigid contact carries part of that toe's load (a
RuntimeWarning, once a toe): true, and harmless here.

Each toe's surface is its sphere geom's (:func:`mudforce.model.shapes.from_mujoco_geom`).
:class:`mudforce.engines.mujoco.MudAdapter3D` applies the whole mud wrench and
holds stuck toes in every direction through MuJoCo's constraint solver.

Run::

    python examples/quadruped_in_mud.py --duration 6s --out quadruped.png

It prints, per gait cycle, where the torso is, each region's mean toe
sinkage, slip (the toes' horizontal travel while loaded) and the energy the
mud took; with ``--out`` it saves plots of the three. ``run(...)`` is the
same as a function (the test runs it at a small size).
"""

from __future__ import annotations

import argparse
import itertools
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from mudforce import MudParameters
from mudforce.engines.mujoco import MudAdapter3D, MudPatch, add_mud_3d
from mudforce.errors import InputError
from mudforce.io import check_output_path
from mudforce.io.units import parse_quantity

#: The robot: torso 0.40 x 0.20 x 0.08 m, legs 2 x 0.14 m, toes 50 mm spheres; about 11.6 kg.
QUADRUPED_XML = """
<mujoco model="mud_quadruped">
  <compiler angle="radian"/>
  <option timestep="0.002"/>
  <default>
    <joint damping="2" armature="0.01"/>
    <geom contype="0" conaffinity="0" rgba="0.6 0.6 0.7 1"/>
    <position kp="200" forcerange="-60 60"/>
  </default>
  <worldbody>
    <light pos="0 0 3"/>
    <geom name="rigid" type="box" pos="-1.5 0 -0.1" size="1.5 1 0.1" contype="1" conaffinity="1" rgba="0.5 0.5 0.5 1"/>
    <body name="torso" pos="0 0 0.265">
      <freejoint/>
      <geom type="box" size="0.2 0.1 0.04" mass="10"/>
      LEGS
    </body>
  </worldbody>
  <actuator>ACTUATORS</actuator>
</mujoco>
"""
LEG = """
      <body name="hip_{n}" pos="{x} {y} -0.04">
        <joint name="hip_{n}" type="hinge" axis="0 1 0" range="-0.8 0.8"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.1" size="0.015" mass="0.2"/>
        <body name="shin_{n}" pos="0 0 -0.1">
          <joint name="knee_{n}" type="hinge" axis="0 1 0" range="-1.6 0.1"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.1" size="0.012" mass="0.1"/>
          <geom name="toe_{n}" type="sphere" pos="0 0 -0.1" size="0.025" mass="0.1" contype="1" conaffinity="1"/>
        </body>
      </body>"""
#: The legs: front left, front right, hind left, hind right; and the trot's diagonal pairs (phase 0 or pi).
LEGS = {"fl": (0.17, 0.15, 0.0), "fr": (0.17, -0.15, math.pi), "hl": (-0.17, 0.15, math.pi),
        "hr": (-0.17, -0.15, 0.0)}
FEET = [f"toe_{n}" for n in LEGS]


def quadruped_spec(*, dt: float = 2e-3, mud: bool = True) -> mujoco.MjSpec:
    """The robot as an ``mujoco.MjSpec``, prepared for mud under its toes (``mud=False``: rigid ground only).

    ``dt`` the time step [s]. Without mud, the rigid box is the whole floor (for timing the same robot on
    rigid ground).
    """
    legs = "".join(LEG.format(n=n, x=x, y=y) for n, (x, y, _) in LEGS.items())
    acts = "".join(f'<position joint="hip_{n}"/><position joint="knee_{n}"/>' for n in LEGS)
    xml = QUADRUPED_XML.replace("LEGS", legs).replace("ACTUATORS", acts)
    if not mud:
        xml = xml.replace('pos="-1.5 0 -0.1" size="1.5 1 0.1"', 'pos="0 0 -0.1" size="10 10 0.1"')
    spec = mujoco.MjSpec.from_string(xml)
    spec.option.timestep = dt
    if mud:
        add_mud_3d(spec, FEET)
    return spec


def trot(t: float, *, frequency: float = 2.0, swing: float = 0.2, lift: float = 0.9, ramp: float = 0.5) -> np.ndarray:
    """The servo targets at time ``t`` [s]: hip and knee [rad] per leg, in the actuators' order.

    A hip swings ``swing`` [rad] about upright at ``frequency`` [Hz]; while it swings forward the knee bends
    by up to ``lift`` [rad]. The amplitude ramps up over ``ramp`` [s] from standing.
    """
    scale = min(1.0, t / ramp) if ramp > 0 else 1.0
    out = np.empty(2 * len(LEGS))
    for k, (_, _, phase) in enumerate(LEGS.values()):
        a = 2.0 * math.pi * frequency * t + phase
        out[2 * k] = scale * swing * math.sin(a)  # rising angle: the toe moves back (stance)
        out[2 * k + 1] = -scale * lift * max(0.0, -math.cos(a))  # bent while the hip swings forward
    return out


@dataclass
class Trot:
    """What :func:`run` recorded, one row per step (``time`` [s]); per foot columns in ``FEET``'s order.

    ``torso`` (m, 3) [m]; ``sinkage`` (m, 4): the toe's lowest point below the surface [m], NaN off the mud;
    ``region`` (m, 4): -1 rigid, 0 dry, 1 wet; ``slip_speed`` (m, 4): horizontal toe speed while in stance
    (touching or below the surface) [m/s], else 0; ``power`` (m, 4): power the mud takes from each toe, ``-F.v`` [W]
    (0 off the mud); ``cycle`` [s], the gait period.
    """

    time: np.ndarray
    torso: np.ndarray
    sinkage: np.ndarray
    region: np.ndarray
    slip_speed: np.ndarray
    power: np.ndarray
    cycle: float

    def per_cycle(self) -> list[dict[str, float]]:
        """Per gait cycle: torso x [m], and per region touched: deepest sinkage [mm], slip [mm], energy lost [J]."""
        dt = float(self.time[1] - self.time[0])
        rows = []
        edges = np.arange(0.0, self.time[-1] + 1e-9, self.cycle)
        for a, b in itertools.pairwise(edges):
            k = (self.time > a) & (self.time <= b)
            row = {"t": float(b), "x": float(self.torso[k][-1, 0])}
            for r, name in ((0, "dry"), (1, "wet")):
                on = self.region[k] == r
                if on.any():
                    row[f"sink_{name}_mm"] = float(np.max(self.sinkage[k][on])) * 1e3
                    row[f"slip_{name}_mm"] = float(np.sum(self.slip_speed[k] * on) * dt) * 1e3
                    row[f"energy_{name}_J"] = float(np.sum(self.power[k] * on) * dt)
            rows.append(row)
        return rows


def run(duration: float = 6.0, *, dry: float = 0.15, wet: float = 0.30, dt: float = 2e-3, frequency: float = 2.0,
        resolution: float | None = None, start: float = 0.05, boundary: float = 0.7,
        frictionless: bool = False) -> Trot:
    """Trot for ``duration`` [s]: rigid ground for x < 0, ``dry`` mud on [0, boundary) [m], ``wet`` beyond.

    ``dry``, ``wet``: water contents [-]; ``dt`` [s]; ``frequency`` [Hz]; ``resolution`` the toes' element
    size [m] (default: the shape module's); ``start`` the torso's starting x [m] relative to the rigid edge.
    ``frictionless=True``: no mud, a frictionless rigid floor everywhere (the skating a missing sideways
    hold gives, for comparison).
    """
    spec = quadruped_spec(dt=dt, mud=not frictionless)
    if frictionless:
        for g in spec.geoms:
            g.condim = 1  # normal force only: no friction
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qpos[0] = -0.17 - 0.05 + start  # the hind toes on the rigid ground, the front ones at its edge
    patches = [MudPatch(MudParameters.from_water_content(dry), extent=(0.0, boundary, -1.0, 1.0)),
               MudPatch(MudParameters.from_water_content(wet), extent=(boundary, 50.0, -1.0, 1.0))]
    mud = None if frictionless else MudAdapter3D(model, data, FEET, patches, resolution=resolution)
    toes = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f) for f in FEET]
    radius = float(model.geom_size[toes[0], 0])
    steps = max(1, round(duration / dt))
    out = {k: np.zeros((steps, 4)) for k in ("sinkage", "region", "slip_speed", "power")}
    torso = np.zeros((steps, 3))
    last = np.array(data.geom_xpos[toes])
    for k in range(steps):
        data.ctrl[:] = trot(data.time, frequency=frequency)
        if mud is None:
            mujoco.mj_step(model, data)
        else:
            mud.step()
        pos = np.array(data.geom_xpos[toes])
        vel = (pos - last) / dt
        last = pos
        x = pos[:, 0]
        region = np.where(x < 0.0, -1, np.where(x < boundary, 0, 1))
        in_mud = region >= 0 if mud is not None else np.ones(4, dtype=bool)
        sink = radius - pos[:, 2]  # the toe's lowest point below the surface [m]
        out["region"][k] = region if mud is not None else 0
        out["sinkage"][k] = np.where(in_mud, sink, np.nan)
        stance = sink > -1e-3  # touching or in the ground: its horizontal travel is slip
        out["slip_speed"][k] = np.where(stance & in_mud, np.hypot(vel[:, 0], vel[:, 1]), 0.0)
        if mud is not None:
            out["power"][k] = np.where(in_mud, -np.einsum("ij,ij->i", mud.contact_forces, vel), 0.0)
        torso[k] = data.qpos[:3]
    return Trot(np.arange(1, steps + 1) * dt, torso, out["sinkage"], out["region"], out["slip_speed"], out["power"],
                1.0 / frequency)


def plot(result: Trot, path: str) -> None:
    """Save sinkage, slip and energy lost per gait cycle, per region, as a PNG at ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = result.per_cycle()
    fig, axes = plt.subplots(4, 1, figsize=(7, 9), sharex=True)
    t = [r["t"] for r in rows]
    axes[0].plot(result.time, result.torso[:, 0], color="k")
    axes[0].set_ylabel("torso x [m]")
    for key, ax, label in (("sink", axes[1], "deepest toe sinkage [mm]"), ("slip", axes[2], "toe slip per cycle [mm]"),
                           ("energy", axes[3], "energy lost per cycle [J]")):
        for name, colour in (("dry", "tab:brown"), ("wet", "tab:blue")):
            unit = "_J" if key == "energy" else "_mm"
            ax.plot(t, [r.get(f"{key}_{name}{unit}", np.nan) for r in rows], "o-", color=colour, label=name)
        ax.set_ylabel(label)
    axes[1].legend()
    axes[-1].set_xlabel("time [s] (end of each gait cycle)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", default="6s", help="simulated time (e.g. 6s)")
    ap.add_argument("--dry", default="15%", help="water content of the first mud (e.g. 15%%)")
    ap.add_argument("--wet", default="30%", help="water content of the second mud (e.g. 30%%)")
    ap.add_argument("--dt", default="2ms", help="time step (e.g. 2ms)")
    ap.add_argument("--out", default=None, help="save the plots as this PNG")
    args = ap.parse_args(argv)
    try:  # a bad value: one line and exit status 2, as the mudforce command line gives
        duration = parse_quantity(args.duration, "time", name="--duration")
        dt = parse_quantity(args.dt, "time", name="--dt")
        dry, wet = (parse_quantity(w, "fraction", name=name) for w, name in ((args.dry, "--dry"), (args.wet, "--wet")))
        for w in (dry, wet):
            MudParameters.from_water_content(w)  # within Table I's range
        if args.out:
            check_output_path(args.out, "--out", suffix=".png")  # before the simulation, not after it
    except InputError as error:
        ap.error(str(error))
    if not 1e-4 <= dt <= 0.01:
        ap.error(f"--dt must be within 0.1ms to 10ms, got {args.dt}")
    cycle = 1.0 / 2.0  # [s] run()'s trot, 2 Hz
    if not cycle <= duration <= 600.0:
        ap.error(f"--duration must be from one gait cycle ({cycle:g}s) to 600s, got {args.duration}")
    res = run(duration, dry=dry, wet=wet, dt=dt)
    for r in res.per_cycle():
        cells = "  ".join(f"{k} {v:7.3f}" for k, v in r.items())
        print(cells)
    if args.out:
        plot(res, args.out)
        print(f"saved {args.out}")


if __name__ == "__main__":
    main()
