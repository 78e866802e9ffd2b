"""A MuJoCo leg stepping in mud, and the same leg on granular ground for contrast.

The rig: a 4 kg carriage on a vertical rail (a spring of 3000 N/m holds it
up when the foot is in the air), a two-link leg (hip and knee hinges, PD
position servos) and the paper's 51 x 38 mm cuboid foot. The servos drive
the foot round an elliptic path: 40 mm above the surface, down to a target
30 mm below it, and back up, once per 1.2 s step. What the foot really does
comes out of the simulation: the mud resists, the foot sinks and sticks, the
mud holds it on the way up (suction) until the neck breaks (Eq. (9)).

For contrast the same leg steps on granular ground with the linear
resistive-force baseline (Li, Zhang & Goldman 2013): force ``k z S`` while
intruding, no relaxation and no suction; at rest the ground holds any load
up to ``k z S`` (applied with the same tendon friction as the mud, so it
does not chatter either). This is the force law of
``mudforce.model.baselines.granular_rft`` (which takes a prescribed trajectory),
written here for a simulated foot. ``k = 0.5 N/cm^3`` is an illustrative value.

Run::

    python examples/mujoco_leg_in_mud.py --water-content 25% --cycles 5 --out leg.png

It prints the work lost to the ground in each step and saves a figure of
force, depth and work per step.
"""

from __future__ import annotations

import argparse
import math

import mujoco
import numpy as np

from mudforce import MudParameters
from mudforce.engines.mujoco import MudAdapter, MudPatch, add_mud
from mudforce.errors import InputError
from mudforce.io import check_output_path
from mudforce.io.units import parse_quantity
from mudforce.model.foot import Foot

LEG_XML = """
<mujoco model="leg_rig">
  <option timestep="0.001" integrator="implicitfast"/>
  <default><geom contype="0" conaffinity="0"/></default>
  <worldbody>
    <geom type="plane" size="0.5 0.5 0.01" rgba="0.45 0.35 0.25 1"/>
    <body name="carriage" pos="0 0 0.36">
      <joint name="rail" type="slide" axis="0 0 1" stiffness="3000" damping="30"/>
      <geom type="box" size="0.05 0.05 0.03" mass="4"/>
      <body name="thigh">
        <joint name="hip" type="hinge" axis="0 1 0" damping="0.2"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.015" mass="0.6"/>
        <body name="shin" pos="0 0 -0.2">
          <joint name="knee" type="hinge" axis="0 1 0" damping="0.2"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.012" mass="0.3"/>
          <geom name="foot" type="box" pos="0 0 -0.2125" size="0.0255 0.019 0.0125" mass="0.2"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="hip" joint="hip" kp="600" kv="10"/>
    <position name="knee" joint="knee" kp="600" kv="10"/>
  </actuator>
</mujoco>
"""
L1 = L2 = 0.2  # [m] thigh and shin
SOLE = 0.025  # [m] from the ankle to the sole
HIP_Z = 0.36 - 0.017  # [m] nominal hip height (the rail spring sags under the carriage)
PERIOD = 1.2  # [s] one step
SWING_HEIGHT = 0.04  # [m] above the surface
TARGET_DEPTH = 0.03  # [m] below the surface
STRIDE = 0.06  # [m] half the fore-aft sweep
RFT_K = 0.5e6  # [N/m^3] linear RFT depth coefficient (0.5 N/cm^3), illustrative
MAX_DURATION = 600.0  # [s] the most simulated time --cycles asks for (the other examples' bound too)


def foot_target(t: float) -> tuple[float, float]:
    """Sole target (x, z) in world [m]: an ellipse, top at +40 mm, bottom at -30 mm."""
    s = 2.0 * math.pi * (t % PERIOD) / PERIOD
    z = SWING_HEIGHT - (SWING_HEIGHT + TARGET_DEPTH) * 0.5 * (1.0 - math.cos(s))
    return STRIDE * math.cos(s), z


def inverse_kinematics(x: float, z: float) -> tuple[float, float]:
    """Hip and knee angles [rad] that put the ankle above the sole target (planar two-link leg)."""
    ax, az = x, z + SOLE - HIP_Z  # ankle relative to the hip
    big_x, big_z = -ax, -az
    c = (big_x**2 + big_z**2 - L1**2 - L2**2) / (2.0 * L1 * L2)
    knee = -math.acos(max(-1.0, min(1.0, c)))
    hip = math.atan2(big_x, big_z) - math.atan2(L2 * math.sin(knee), L1 + L2 * math.cos(knee))
    return hip, knee


class LinearRFT:
    """Granular ground, linear RFT: ``F = k z S`` while intruding, no suction; held at rest by tendon friction."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, foot_name: str, k: float, area: float) -> None:
        self.model, self.data, self.k, self.area = model, data, k, area
        self.site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"mud_site_{foot_name}")
        self.tendon = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TENDON, f"mud_tendon_{foot_name}")
        # the tendon's upper end: a world-body site that add_mud made, moved through model.site_pos
        self.anchor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"mud_anchor_site_{foot_name}")
        self.body = int(model.site_bodyid[self.site])
        self.mid = 0.0
        mujoco.mj_forward(model, data)
        self._prepare()

    def _prepare(self) -> None:
        d = self.data
        p = d.site_xpos[self.site]
        depth = max(-p[2], 0.0)
        band = self.k * depth * self.area  # the band [0, k z S]: 0 moving up, k z S moving down
        self.model.tendon_frictionloss[self.tendon] = 0.5 * band
        r = p - d.xipos[self.body]
        d.xfrc_applied[self.body, :] = 0.0
        d.xfrc_applied[self.body, 2] = 0.5 * band
        d.xfrc_applied[self.body, 3] = r[1] * 0.5 * band
        d.xfrc_applied[self.body, 4] = -r[0] * 0.5 * band
        self.model.site_pos[self.anchor] = p + np.array([0.0, 0.0, 1.0])
        self.mid = 0.5 * band

    def step(self) -> None:
        mujoco.mj_step(self.model, self.data)
        self.last_mid = self.mid
        self._prepare()

    @property
    def depth(self) -> float:
        return float(-self.data.site_xpos[self.site, 2])

    @property
    def force(self) -> float:
        d = self.data
        rows = np.flatnonzero((d.efc_type == mujoco.mjtConstraint.mjCNSTR_FRICTION_TENDON) & (d.efc_id == self.tendon))
        return self.last_mid - (float(d.efc_force[rows[0]]) if rows.size else 0.0)


def run(ground: str, params: MudParameters, cycles: int) -> dict[str, np.ndarray]:
    """Simulate ``cycles`` steps on mud or sand; returns time, depth, force, target depth arrays."""
    spec = mujoco.MjSpec.from_string(LEG_XML)
    add_mud(spec, ["foot"])
    model = spec.compile()
    data = mujoco.MjData(model)
    hip, knee = inverse_kinematics(*foot_target(0.0))
    data.qpos[1], data.qpos[2] = hip, knee
    data.ctrl[:] = hip, knee
    if ground == "mud":
        mud = MudAdapter(model, data, ["foot"], MudPatch(params))
    else:
        sand = LinearRFT(model, data, "foot", RFT_K, Foot.paper().area)
    n = round(cycles * PERIOD / model.opt.timestep)
    time, depth, force = np.empty(n), np.empty(n), np.empty(n)
    for k in range(n):
        t = data.time
        data.ctrl[:] = inverse_kinematics(*foot_target(t + model.opt.timestep))
        if ground == "mud":
            mud.step()
            depth[k], force[k] = mud.depths[0], mud.contact_forces[0]
        else:
            sand.step()
            depth[k], force[k] = sand.depth, sand.force
        time[k] = data.time
    return {"time": time, "depth": depth, "force": force}


def work_per_step(res: dict[str, np.ndarray], cycles: int) -> np.ndarray:
    """Energy the foot loses to the ground in each step [J]: the sum of F dz over the step (F up, z down)."""
    dz = np.diff(res["depth"], prepend=res["depth"][0])
    contact = res["depth"] > 0.0
    contact[1:] |= res["depth"][:-1] > 0.0
    dw = np.where(contact | (res["force"] != 0.0), res["force"] * dz, 0.0)
    step = np.minimum((res["time"] / PERIOD).astype(int), cycles - 1)
    return np.bincount(step, weights=dw, minlength=cycles)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--water-content", default="25%", help="mud water content, e.g. 25%%")
    parser.add_argument("--cycles", type=int, default=5, help="number of steps, 1 to 500 (default 5)")
    parser.add_argument("--out", default="leg_in_mud.png", help="figure (PNG)")
    args = parser.parse_args(argv)
    if args.cycles < 1:
        parser.error(f"--cycles must be at least 1, got {args.cycles}")
    if args.cycles * PERIOD > MAX_DURATION:  # 10**9 was numpy's MemoryError (8.73 TiB) after compiling
        parser.error(f"--cycles must be at most {round(MAX_DURATION / PERIOD)} ({MAX_DURATION:g} s of stepping), "
                     f"got {args.cycles}")
    try:
        params = MudParameters.from_water_content(parse_quantity(args.water_content, "fraction",
                                                                 name="--water-content"))
        check_output_path(args.out, "--out", suffix=".png")  # before the simulation, not after it
    except InputError as error:  # one line and exit status 2, as the mudforce command line gives
        parser.error(str(error))
    mud = run("mud", params, args.cycles)
    sand = run("sand", params, args.cycles)
    w_mud, w_sand = work_per_step(mud, args.cycles), work_per_step(sand, args.cycles)
    for i in range(args.cycles):
        print(f"step {i + 1}: work lost to mud {w_mud[i]:7.3f} J, to granular ground (linear RFT) {w_sand[i]:7.3f} J")
    print(f"peak mud force {mud['force'].max():.1f} N, strongest suction {mud['force'].min():.1f} N; "
          f"deepest {mud['depth'].max() * 1e3:.1f} mm (mud), {sand['depth'].max() * 1e3:.1f} mm (granular)")

    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 8.0))
    ax = fig.subplots(3, 1)
    for res, label, colour in ((mud, f"mud (W = {args.water_content})", "#8c510a"),
                               (sand, "granular, linear RFT", "#01665e")):
        ax[0].plot(res["time"], res["force"], color=colour, lw=1.0, label=label)
        ax[1].plot(res["time"], res["depth"] * 1e3, color=colour, lw=1.0, label=label)
    ax[0].set_ylabel("vertical force on foot [N]")
    ax[0].legend(loc="upper right")
    ax[1].axhline(0.0, color="0.5", lw=0.6)
    ax[1].set_ylabel("foot depth [mm]")
    ax[1].set_xlabel("time [s]")
    steps = np.arange(1, args.cycles + 1)
    ax[2].bar(steps - 0.18, w_mud, width=0.36, color="#8c510a", label="mud")
    ax[2].bar(steps + 0.18, w_sand, width=0.36, color="#01665e", label="granular (linear RFT)")
    ax[2].set_xlabel("step")
    ax[2].set_ylabel("work lost to the ground [J]")
    ax[2].legend()
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle("A PD-controlled leg stepping in mud (mudforce + MuJoCo)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
