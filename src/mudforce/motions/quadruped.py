"""A small planar quadruped walking on mud in MuJoCo: foot trajectories with impacts, for testing estimators.

Needs MuJoCo (``pip install 'mudforce[mujoco]'``). The robot
(:data:`QUADRUPED_XML`): a 1.5 kg torso on a planar root (slide x, slide z
within +-0.15 m, pitch within +-0.5 rad), four two-link legs (hip and knee hinges, 0.12 m links, PD position
servos) and spherical feet of 25 mm radius, whose contact with the mud is
the paper's model through :class:`mudforce.engines.mujoco.MudAdapter` (1-D,
vertical, per foot), with the cross-section of the sphere as the contact
area: a 50 mm disc (:meth:`Foot.disc`). There is no other ground contact.

The legs are driven open-loop (no feedback on the body): each foot's
target runs round a step cycle in the hip's frame: a stance that sweeps
back at a target depth below the surface, a swing that lifts it and brings
it forward and down, so the foot strikes the mud at the end of the swing
(an impact), and the servos and the body ring (vibration). The gaits of
:data:`GAITS` (walk, trot, bound, at two speeds) differ in period, duty
factor and the legs' phases; each cycle's stride, swing height, target
depth and period are drawn from a seeded generator. What the foot really
does comes out of the simulation: the mud resists, holds and lets go. In
wet mud (W >= 30 %) the open-loop robot sinks, a foot down to some 100 mm,
and pitches against its limits: real motion, not a tidy one.

:func:`robot_walk` returns, at MuJoCo's fine time step, one foot's true
depth [m] and two true forces [N]: the force the foot felt in MuJoCo (the
load it carried, which while the foot sticks is anywhere in the mud's
rest band, as the solver finds) and the model's force along the foot's
true path (:func:`mudforce.simulate`, exact), which is what an estimator of
the kinematic model should explain. Same inputs, same outputs, on one
machine and MuJoCo version.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np

from mudforce.errors import InputError, number_within, seed_int
from mudforce.model.foot import Foot
from mudforce.model.parameters import WATER_CONTENT_RANGE, MudParameters

__all__ = ["FEET", "GAITS", "QUADRUPED_XML", "ROBOT_FOOT", "QuadrupedGait", "RobotWalk", "robot_walk"]

#: The feet, in the order of :data:`QuadrupedGait.phases`: front left, front right, hind left, hind right.
FEET = ("foot_fl", "foot_fr", "foot_hl", "foot_hr")

_LINK = 0.12  # [m] thigh and shin
_RADIUS = 0.025  # [m] foot sphere
_HIP_X = 0.15  # [m] hips fore and aft of the torso's centre
_HIP_HEIGHT = 0.19  # [m] nominal hip height above the mud's surface
_START = 0.01  # [m] the feet start this far above the surface

#: The contact of each foot with the mud: the 50 mm disc of the sphere's cross-section.
ROBOT_FOOT = Foot.disc(2.0 * _RADIUS)


def _leg(name: str, x: float, y: float) -> str:
    return f"""
      <body name="thigh_{name}" pos="{x} {y} 0">
        <joint name="hip_{name}" type="hinge" axis="0 1 0" damping="0.05"/>
        <geom type="capsule" fromto="0 0 0 0 0 -{_LINK}" size="0.012" mass="0.15"/>
        <body name="shin_{name}" pos="0 0 -{_LINK}">
          <joint name="knee_{name}" type="hinge" axis="0 1 0" damping="0.05"/>
          <geom type="capsule" fromto="0 0 0 0 0 -{_LINK - _RADIUS}" size="0.01" mass="0.1"/>
          <geom name="foot_{name}" type="sphere" pos="0 0 -{_LINK}" size="{_RADIUS}" mass="0.06"/>
        </body>
      </body>"""


#: The robot (MJCF): planar root, four legs; every geom has contype 0 (the mud is the only ground).
QUADRUPED_XML = f"""<mujoco model="mudforce_quadruped">
  <option timestep="0.0005" integrator="implicitfast"/>
  <default><geom contype="0" conaffinity="0"/></default>
  <worldbody>
    <body name="torso" pos="0 0 {_HIP_HEIGHT}">
      <joint name="root_x" type="slide" axis="1 0 0" damping="20"/>
      <joint name="root_z" type="slide" axis="0 0 1" limited="true" range="-0.15 0.15"/>
      <joint name="root_pitch" type="hinge" axis="0 1 0" damping="1" limited="true" range="-0.5 0.5"/>
      <geom type="box" size="0.18 0.08 0.03" mass="1.5"/>{_leg("fl", _HIP_X, 0.09)}{_leg("fr", _HIP_X, -0.09)}{
        _leg("hl", -_HIP_X, 0.09)}{_leg("hr", -_HIP_X, -0.09)}
    </body>
  </worldbody>
  <actuator>
    {"".join(f'<position joint="{j}_{n}" kp="120" kv="2"/>' for n in ("fl", "fr", "hl", "hr") for j in ("hip", "knee"))}
  </actuator>
</mujoco>
"""


@dataclass(frozen=True)
class QuadrupedGait:
    """An open-loop gait of the quadruped.

    Attributes
    ----------
    period : float
        Step cycle [s].
    duty : float
        Fraction of the cycle in stance [-].
    phases : tuple of float
        Phase offset of each foot of :data:`FEET` [-] (fractions of a cycle).
    stride : float
        Half the fore-aft sweep of a foot [m].
    swing_height : float
        Apex of the swing above the surface [m].
    press : float
        Target depth of the stance below the surface [m] (the servos push
        there; the mud decides how deep the foot goes).
    """

    period: float
    duty: float
    phases: tuple[float, float, float, float]
    stride: float
    swing_height: float
    press: float


#: The gaits :func:`robot_walk` knows: walk, trot and bound, each at a slow and a fast pace.
GAITS: dict[str, QuadrupedGait] = {
    "walk": QuadrupedGait(1.2, 0.75, (0.0, 0.5, 0.75, 0.25), 0.03, 0.03, 0.02),
    "walk-fast": QuadrupedGait(0.8, 0.7, (0.0, 0.5, 0.75, 0.25), 0.04, 0.03, 0.02),
    "trot": QuadrupedGait(0.7, 0.6, (0.0, 0.5, 0.5, 0.0), 0.03, 0.03, 0.025),
    "trot-fast": QuadrupedGait(0.45, 0.55, (0.0, 0.5, 0.5, 0.0), 0.04, 0.035, 0.025),
    "bound": QuadrupedGait(0.6, 0.5, (0.0, 0.0, 0.5, 0.5), 0.035, 0.04, 0.025),
}


@dataclass(frozen=True)
class RobotWalk:
    """One foot of the quadruped walking on mud, at MuJoCo's time step (from :func:`robot_walk`).

    Attributes
    ----------
    time : numpy.ndarray
        Times [s], from 0, one per MuJoCo step.
    depth : numpy.ndarray
        The foot's true depth below the mud's surface [m], positive down.
    force : numpy.ndarray
        The model's force along that path [N] (:func:`mudforce.simulate`, exact velocity).
    force_contact : numpy.ndarray
        The vertical mud force the foot felt in MuJoCo [N] (the load it carried while stuck).
    water_content : float
        The mud's water content [-].
    gait : str
        The gait's name (a key of :data:`GAITS`).
    foot : str
        The foot's name (one of :data:`FEET`).
    """

    time: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    force_contact: np.ndarray
    water_content: float
    gait: str
    foot: str


def _ik(x: float, z: float) -> tuple[float, float]:
    """Hip and knee angles [rad] that put the foot's centre at (x, z) from the hip (planar two-link leg)."""
    reach = math.hypot(x, z)
    reach = min(reach, 2.0 * _LINK * 0.999)
    c = (reach * reach - 2.0 * _LINK * _LINK) / (2.0 * _LINK * _LINK)
    knee = math.acos(max(-1.0, min(1.0, c)))  # knee bends backwards (positive about y)
    hip = math.atan2(-x, -z) - math.atan2(_LINK * math.sin(knee), _LINK + _LINK * math.cos(knee))
    return hip, knee


def _cycles(g: QuadrupedGait, duration: float, rng: np.random.Generator) -> np.ndarray:
    """Per cycle: start time [s], period [s], stride [m], swing height [m], press [m]."""
    rows = []
    t = -g.period  # one cycle before 0, so every foot's phase is defined from the start
    while t < duration + g.period:
        period = g.period * float(rng.uniform(0.9, 1.1))
        rows.append((t, period, g.stride * float(rng.uniform(0.8, 1.2)), g.swing_height * float(rng.uniform(0.8, 1.2)),
                     g.press * float(rng.uniform(0.6, 1.2))))
        t += period
    return np.array(rows)


def _target(g: QuadrupedGait, cycles: list[list[float]], starts: list[float], t: float,
            offset: float) -> tuple[float, float]:
    """Foot centre target (x, z) relative to its hip [m] for a foot whose phase is ``offset``.

    ``cycles`` are :func:`_cycles`' rows and ``starts`` their start times [s], as lists (Python floats: this runs
    four times a MuJoCo step).
    """
    shifted = t + offset * g.period
    k = bisect.bisect_right(starts, shifted) - 1
    start, period, stride, height, press = cycles[k]
    phase = (shifted - start) / period
    bottom = -_HIP_HEIGHT + _RADIUS  # the foot's centre with its bottom at the surface
    if phase < g.duty:  # stance: sweep back at the target depth
        s = phase / g.duty
        return stride * (1.0 - 2.0 * s), bottom - press
    s = (phase - g.duty) / (1.0 - g.duty)  # swing: up, forward, and down into the mud (it strikes at s = 1)
    z = bottom + height * math.sin(math.pi * s) - press * (2.0 * s - 1.0) ** 2
    return stride * (2.0 * s - 1.0), z


def robot_walk(gait: str = "trot", water_content: float = 0.25, *, seed: int = 0, duration: float = 10.0,
               foot: str = "foot_fl") -> RobotWalk:
    """Simulate the quadruped walking on mud and return one foot's true depth and force at MuJoCo's step.

    Parameters
    ----------
    gait : str
        One of :data:`GAITS` (walk, walk-fast, trot, trot-fast, bound).
    water_content : float
        The mud's water content [-], within Table I's range (Table I, interpolated).
    seed : int
        Seed of the cycles' random stride, swing height, target depth and period.
    duration : float
        Simulated time [s], within [0.1, 600] (2000 MuJoCo steps a second).
    foot : str
        Which foot to return, one of :data:`FEET`.

    Returns
    -------
    RobotWalk
        Time [s], depth [m], the model's force along the path [N] and the force MuJoCo applied [N].
    """
    from mudforce._plumbing.optional import require
    from mudforce.engines.mujoco import MudAdapter, MudPatch, add_mud
    from mudforce.steppers.simulation import simulate

    mj = require("mujoco", "mujoco", "the quadruped test bench")
    if not isinstance(gait, str) or gait not in GAITS:  # a list was looked up in the dict: TypeError, unhashable
        raise InputError(f"gait must be one of {', '.join(GAITS)}, got {gait!r}")
    if foot not in FEET:
        raise InputError(f"foot must be one of {', '.join(FEET)}, got {foot!r}")
    w = number_within(water_content, "water content", *WATER_CONTENT_RANGE, "(fraction)")
    seed = seed_int(seed, "seed")
    duration = number_within(duration, "duration", 0.1, 600.0, "s")
    g = GAITS[gait]
    table = _cycles(g, duration, np.random.default_rng([seed, 7]))
    cycles, starts = table.tolist(), table[:, 0].tolist()
    spec = mj.MjSpec.from_string(QUADRUPED_XML)
    add_mud(spec, list(FEET))
    model = spec.compile()
    data = mj.MjData(model)
    params = MudParameters.from_water_content(w)

    def control(t: float) -> None:
        data.ctrl[:8] = [angle for phase in g.phases[:4] for angle in _ik(*_target(g, cycles, starts, t, phase))]

    control(0.0)
    # the torso raised so that the lowest foot starts _START above the surface, and the robot drops into the mud
    lowest = min(_target(g, cycles, starts, 0.0, phase)[1] for phase in g.phases)
    data.qpos[1] = _START + (-_HIP_HEIGHT + _RADIUS) - lowest
    data.qpos[3:] = data.ctrl  # the legs start at their targets (qpos: x, z, pitch, then hip/knee pairs)
    mud = MudAdapter(model, data, list(FEET), MudPatch(params), ROBOT_FOOT)
    j = FEET.index(foot)
    dt = float(model.opt.timestep)
    n = round(duration / dt) + 1
    depth = np.empty(n)
    contact = np.empty(n)
    depth[0], contact[0] = float(mud.depths[j]), 0.0
    for k in range(1, n):
        control(k * dt)
        mud.step()
        depth[k] = mud.depths[j]
        contact[k] = mud.contact_forces[j]
    time = np.arange(n) * dt
    if not (np.all(np.isfinite(depth)) and np.all(np.isfinite(contact))) or np.max(np.abs(depth)) > 0.5:
        raise InputError(f"the quadruped's simulation ({gait}, W {w:g}, seed {seed}) diverged (a foot beyond 0.5 m "
                         "of the surface, or not finite); expected another seed or a shorter duration")
    force = simulate(time, depth, params, ROBOT_FOOT, velocity_filter="exact").force
    return RobotWalk(time, depth, np.asarray(force, dtype=np.float64), contact, w, gait, foot)
