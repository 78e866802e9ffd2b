"""Benchmarks of the dynamics issue: vectorised stepping, the built-in engine, MuJoCo adapter overhead.

Run: ``python benchmarks/bench_dynamics.py`` (prints figures; asserts nothing).

* ``MudContacts``: 4096 feet, each on its own sinusoidal intrusion/withdrawal
  cycle (phases spread, so CONTACT on both branches and NECKED all occur),
  1 kHz; nanoseconds per foot per step, best of several repeats (the best
  is the least disturbed by other processes on a shared machine).
* The built-in engine: wall time of one 8 s drop (8000 samples, 80000 RK4 steps).
* MuJoCo: a quadruped-like body (free torso, four legs with hip and knee
  hinges under PD position actuators, box feet); ``MudAdapter.step`` with
  the four feet in mud against a bare ``mj_step`` of the same robot on a
  rigid floor and with no contact at all (the cheapest step; the target is
  at most 2x that). Short runs interleaved, best of many: the machine's
  speed can change by 2x from one minute to the next.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from typing import Any

import numpy as np

from mudforce import MudParameters
from mudforce.steppers.many import MudContacts


def _best(fn: Any, repeats: int) -> float:
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def bench_contacts(n: int = 4096, steps: int = 500, repeats: int = 5) -> dict[int, float]:
    """Nanoseconds per foot per step of ``MudContacts.step``, on one thread and on the automatic number.

    The two are timed in alternation, the best of ``repeats`` rounds each.
    Keys: the number of threads.
    """
    params = MudParameters.from_water_content(0.25)
    runs = {1: MudContacts(params, n, threads=1)}
    auto = MudContacts(params, n)
    runs[auto.threads] = auto
    rng = np.random.default_rng(0)
    dt = 1e-3
    t = np.arange(steps * repeats + 1) * dt
    phase = rng.uniform(0.0, 2.0 * np.pi, n)
    freq = rng.uniform(0.2, 2.0, n)
    depths = np.ascontiguousarray(0.008 + 0.012 * np.sin(2.0 * np.pi * freq * t[:, None] + phase))
    best = {k: math.inf for k in runs}
    for contacts in runs.values():
        contacts.step(depths[0], dt)
    forces = np.empty(n)  # a control loop's own buffer: out= spares an allocation per step
    for r in range(repeats):
        for k, contacts in runs.items():
            rows = depths[1 + r * steps: 1 + (r + 1) * steps]
            t0 = time.perf_counter()
            for z in rows:
                contacts.step(z, dt, out=forces)
            best[k] = min(best[k], time.perf_counter() - t0)
    return {k: b / (steps * n) * 1e9 for k, b in best.items()}


def bench_builtin(repeats: int = 3) -> float:
    """Seconds per 8 s drop with the built-in engine."""
    from mudforce.engines.dynamics import simulate_foot

    params = MudParameters.from_water_content(0.25)
    simulate_foot(5.0, params, duration=0.1)
    return _best(lambda: simulate_foot(10.0, params), repeats)


QUADRUPED = """
<mujoco model="quadruped">
  <option timestep="0.001" integrator="implicitfast"/>
  <default>
    <joint damping="0.5" armature="0.01"/>
    <geom contype="1" conaffinity="1" friction="1 0.005 0.0001"/>
    <position kp="300" kv="10"/>
  </default>
  <worldbody>
    {floor}
    <body name="torso" pos="0 0 {height}">
      <freejoint/>
      <geom type="box" size="0.2 0.1 0.04" mass="8"/>
      {legs}
    </body>
  </worldbody>
  <actuator>{actuators}</actuator>
</mujoco>
"""
LEG = """
      <body name="thigh{i}" pos="{x} {y} -0.04">
        <joint name="hip{i}" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.15" size="0.015" mass="0.5"/>
        <body name="shin{i}" pos="0 0 -0.15">
          <joint name="knee{i}" type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.15" size="0.012" mass="0.3"/>
          <geom name="foot{i}" type="box" pos="0 0 -0.1625" size="0.0255 0.019 0.0125" mass="0.2"/>
        </body>
      </body>"""


def quadruped_xml(floor: bool) -> str:
    corners = [(0.15, 0.08), (0.15, -0.08), (-0.15, 0.08), (-0.15, -0.08)]
    legs = "".join(LEG.format(i=i, x=x, y=y) for i, (x, y) in enumerate(corners))
    acts = "".join(f'<position joint="hip{i}"/><position joint="knee{i}"/>' for i in range(4))
    plane = '<geom name="floor" type="plane" size="5 5 0.1"/>' if floor else ""
    # feet bottoms at z = 0 when standing straight: 0.04 + 0.15 + 0.15 + 0.175
    return QUADRUPED.format(floor=plane, height=0.04 + 0.3 + 0.175, legs=legs, actuators=acts)


def bench_mujoco(steps: int = 500, repeats: int = 40,
                 settle: int = 2000) -> tuple[float, float, float, float, float]:
    """Microseconds per step: bare ``mj_step`` on a rigid floor, bare without floor, ``MudAdapter.step``;
    then the median over rounds of the adapter's time over each bare time in the same round.

    Each model first runs ``settle`` steps (the robot stands, or sinks into
    the mud and sticks); then ``repeats`` rounds of ``steps`` steps of each.
    The times are the best over the rounds (the least disturbed); the
    ratios within a round are steadier still, as the machine's speed
    changes little within one.
    """
    import mujoco

    from mudforce.engines.mujoco import MudAdapter, MudPatch, add_mud

    bare_model = mujoco.MjModel.from_xml_string(quadruped_xml(floor=True))
    bare_data = mujoco.MjData(bare_model)
    air_model = mujoco.MjModel.from_xml_string(quadruped_xml(floor=False))
    air_data = mujoco.MjData(air_model)
    spec = mujoco.MjSpec.from_string(quadruped_xml(floor=False))
    feet = [f"foot{i}" for i in range(4)]
    add_mud(spec, feet)
    model = spec.compile()
    data = mujoco.MjData(model)
    mud = MudAdapter(model, data, feet, MudPatch(MudParameters.from_water_content(0.20)))

    def bare(n: int = steps) -> None:
        for _ in range(n):
            mujoco.mj_step(bare_model, bare_data)

    def air(n: int = steps) -> None:
        for _ in range(n):
            mujoco.mj_step(air_model, air_data)

    def adapted(n: int = steps) -> None:
        for _ in range(n):
            mud.step()

    bare(settle)
    adapted(settle)
    air(settle)
    # interleaved, best of each: the least disturbed by other processes
    rounds = np.empty((repeats, 3))
    for r in range(repeats):
        for i, fn in enumerate((bare, air, adapted)):
            rounds[r, i] = _best(fn, 1)
    best = rounds.min(axis=0) / steps * 1e6
    vs_floor = float(np.median(rounds[:, 2] / rounds[:, 0]))
    vs_air = float(np.median(rounds[:, 2] / rounds[:, 1]))
    return float(best[0]), float(best[1]), float(best[2]), vs_floor, vs_air


def main() -> None:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args()  # --help, and no stray options
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"machine: {os.cpu_count()} CPUs, load average {load:.2f}")
    figures = bench_contacts()
    text = ", ".join(f"{ns:.1f} on {k} thread{'s' if k > 1 else ''}" for k, ns in sorted(figures.items(), reverse=True))
    print(f"MudContacts, 4096 feet: ns per foot per step (wall, best of 5 rounds of 500 steps): {text}")
    print(f"built-in engine, one 8 s drop (8000 samples): {bench_builtin() * 1e3:.0f} ms")
    try:
        t_bare, t_air, t_mud, vs_floor, vs_air = bench_mujoco()
    except ImportError:
        print("MuJoCo: not installed")
        return
    # the paired ratio leads: this machine's speed swings 1.7-2x between minutes,
    # so bests taken at different moments can pair a fast bare step with a slow adapted one
    print(f"MuJoCo quadruped, MudAdapter on 4 feet in mud / a bare mj_step, median over 40 paired rounds: "
          f"{vs_floor:.2f} (bare: standing on a rigid floor), {vs_air:.2f} (bare: falling with no contact); "
          f"best times {t_mud:.1f} us adapted, {t_bare:.1f} us on a floor, {t_air:.1f} us with no contact "
          f"(ratios of the bests {t_mud / t_bare:.2f}, {t_mud / t_air:.2f})")


if __name__ == "__main__":
    main()
