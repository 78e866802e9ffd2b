"""Legs stepping in mud, many worlds in one jit with MJX: per-world water content, sinkage and work lost per step.

Each world is a robot leg on a test rig: a 1 kg foot (the paper's 51 x 38
mm cuboid) on a vertical prismatic joint, driven by a position servo
(3000 N/m) through a 1.5 Hz stepping pattern, from 20 mm above the mud
surface (``z = 0``) to a target 25 mm below it and back. World ``i`` has
water content spread evenly over ``--water`` (default 15-25 %, Table I
interpolated). Wetter mud, around W = 30 %, where the withdrawal
stiffness ``k_m_w`` is 11x the intrusion stiffness ``k_m_i``, throws this
leg back out at every reversal and pumps energy into it (the paper's
model is not passive there; docs/gpu.md): try ``--water 0.15 0.35``. All
worlds run in one ``jax.jit`` of a ``lax.scan`` over the steps,
``jax.vmap`` over the worlds; the mud force comes from
:func:`mudforce.engines.mjx.step` on every physics step, with sticking. The servo
is compliant, so how deep the foot gets and the work the mud takes depend
on the mud.

Run::

    python examples/mjx_hoppers_in_mud.py                 # 16 worlds, 4 s (a 2-core CPU: ~half a minute)
    python examples/mjx_hoppers_in_mud.py --worlds 1024   # on a GPU (at most 16384 worlds)

Writes a PNG (``--out``): sinkage over time for a few worlds, and the work
the mud takes from the foot per step cycle [J] against water content.
Needs: pip install 'mudforce[mjx,plot]'.
"""

from __future__ import annotations

import os

# keep JAX from taking most of the GPU's memory at start-up; set before jax is imported
os.environ.setdefault("XLA_PYTHON_CLIENT_PREALLOCATE", "false")

import argparse
import time

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

import mudforce.engines.mjx as mud
from mudforce import MudParameters
from mudforce.errors import InputError
from mudforce.io import check_output_path

LEG = """
<mujoco model="leg_in_mud">
  <option timestep="0.001" gravity="0 0 -9.81" integrator="Euler"/>
  <worldbody>
    <body name="foot" pos="0 0 0.0125">
      <joint name="leg" type="slide" axis="0 0 1" damping="2"/>
      <geom type="box" size="0.0255 0.019 0.0125" mass="1.0" contype="0" conaffinity="0"/>
      <site name="sole" pos="0 0 -0.0125"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="leg" kp="3000"/>
  </actuator>
</mujoco>
"""
STEP_HZ = 1.5  # stepping frequency [Hz]
LIFT = 0.02  # sole's target height at the top of a step [m]
PUSH = 0.025  # sole's target depth at the bottom of a step [m]
#: Most worlds ``--worlds`` takes: 16 times a GPU's 1024
MAX_WORLDS = 16_384
#: Most samples of depth and force a run records, worlds x 1 ms steps: 2**27 (about 4 GiB on the host), 32 times
#: a GPU's 1024 worlds for the default 4 s (16384 worlds for 8 s, 1024 for 131 s)
MAX_RECORDED = 2**27


def build(worlds: int, water: np.ndarray) -> tuple[object, object, mud.MudPatch, object]:
    """The MJX model, a batch of data (one world per water content), per-world patches and the MuJoCo model."""
    model = mujoco.MjModel.from_xml_string(LEG)
    m = mjx.put_model(model)
    patches = [mud.add_mud(model, ["sole"], MudParameters.from_water_content(float(w))) for w in water]
    patch = jax.tree_util.tree_map(lambda *xs: jnp.stack(xs), *patches)  # a world axis on every field
    d0 = mjx.make_data(m)
    data = jax.tree_util.tree_map(lambda x: jnp.broadcast_to(x, (worlds, *x.shape)), d0)
    return m, data, patch, model


def simulate(m: object, data: object, patch: mud.MudPatch, steps: int) -> dict[str, np.ndarray]:
    """Every world for ``steps`` physics steps in one jit: sole depth [m] and work the mud takes [J] per step."""
    dt = float(m.opt.timestep)  # type: ignore[attr-defined]

    def one_world(d: object, c: mud.MudState, p: mud.MudPatch, k: jax.Array) -> tuple[object, mud.MudState, jax.Array,
                                                                                    jax.Array]:
        # the sole's target height: LIFT above the surface to PUSH below it and back, once per cycle
        cycle = 0.5 - 0.5 * jnp.cos(2.0 * jnp.pi * STEP_HZ * k * dt)
        d = d.replace(ctrl=jnp.full_like(d.ctrl, LIFT - (LIFT + PUSH) * cycle))  # type: ignore[attr-defined]
        d, c, f = mud.step(m, d, c, p)
        # the sole's depth at this step's start (as committed to the mud) and the force during the step
        return d, c, c.state.depth[0], f[0]

    batched = jax.vmap(one_world, in_axes=(0, 0, 0, None))

    @jax.jit
    def run(data: object, patch: mud.MudPatch) -> tuple[jax.Array, jax.Array]:
        # the per-world mud is an argument, not a constant closed over (see docs/gpu.md)
        def body(carry, k):  # type: ignore[no-untyped-def]
            d, c = carry
            d, c, depth, force = batched(d, c, patch, k)
            return (d, c), (depth, force)
        contacts = jax.vmap(mud.init)(patch)
        _, (depth, force) = jax.lax.scan(body, (data, contacts), jnp.arange(steps))
        return depth, force

    depth, force = (np.asarray(a, dtype=np.float64) for a in run(data, patch))
    # work the mud takes from the foot in each step: force up times the distance moved down [J]
    work = np.zeros_like(force)
    work[:-1] = force[:-1] * np.diff(depth, axis=0)
    return {"depth": depth, "work": work}


def main(argv: list[str] | None = None) -> dict[str, np.ndarray]:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--worlds", type=int, default=16,
                    help=f"number of worlds, 1 to {MAX_WORLDS} (default 16; 1024 on a GPU)")
    ap.add_argument("--duration", type=float, default=4.0, help="simulated time [s] (default 4)")
    ap.add_argument("--water", type=float, nargs=2, default=(0.15, 0.25), metavar=("LOW", "HIGH"),
                    help="water contents of the first and last world, fractions (default 0.15 0.25)")
    ap.add_argument("--out", default="mjx_hoppers_in_mud.png", help="PNG to write ('' for none)")
    args = ap.parse_args(argv)
    if not 1 <= args.worlds <= MAX_WORLDS:  # 10**12 was numpy's MemoryError (7.28 TiB), a traceback
        ap.error(f"--worlds must be from 1 to {MAX_WORLDS}, got {args.worlds}")
    cycle = 1.0 / STEP_HZ  # [s]
    if not 2.0 * cycle <= args.duration <= 600.0:  # the work is reported per cycle after the first
        ap.error(f"--duration must be from {2.0 * cycle:.3g} s (two step cycles) to 600 s, got {args.duration}")
    if not all(0.15 <= w <= 0.35 for w in args.water):
        ap.error(f"--water must be two fractions within Table I's range [0.15, 0.35], got {args.water}")
    if args.worlds * round(args.duration / 1e-3) > MAX_RECORDED:  # (16384 worlds for 600 s: 315 GB)
        ap.error(f"--worlds {args.worlds} for --duration {args.duration:g} s would record "
                 f"{args.worlds * round(args.duration / 1e-3):,} samples (worlds x 1 ms steps), more than "
                 f"{MAX_RECORDED:,}; lower --worlds or --duration")
    if args.out:
        try:  # before the compile and the run, not after them
            check_output_path(args.out, "--out", suffix=".png")
        except InputError as error:
            ap.error(str(error))
    water = np.linspace(args.water[0], args.water[1], args.worlds)
    m, data, patch, _ = build(args.worlds, water)
    steps = round(args.duration / 1e-3)
    t0 = time.perf_counter()
    out = simulate(m, data, patch, steps)
    wall = time.perf_counter() - t0
    depth, work = out["depth"], out["work"]
    per_cycle = round(1.0 / (STEP_HZ * 1e-3))
    cycles = steps // per_cycle
    lost = work[: cycles * per_cycle].reshape(cycles, per_cycle, -1).sum(axis=1)  # [J] per cycle and world
    print(f"{args.worlds} worlds x {steps} steps on {jax.default_backend()}: {wall:.1f} s with compilation "
          f"({wall / steps * 1e6:.0f} us per step of all worlds)")
    for i in np.linspace(0, args.worlds - 1, min(args.worlds, 5)).astype(int):
        print(f"  W = {water[i]:.1%}: deepest sinkage {depth[:, i].max() * 1e3:6.2f} mm, "
              f"work lost per step cycle {lost[1:, i].mean():7.4f} J (after the first)")
    if args.out:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(9.0, 4.0))
        ax1, ax2 = fig.subplots(1, 2)
        t = np.arange(steps) * 1e-3
        for i in np.linspace(0, args.worlds - 1, min(args.worlds, 5)).astype(int):
            ax1.plot(t, np.maximum(depth[:, i], 0.0) * 1e3, lw=1.0, label=f"W = {water[i]:.0%}")
        ax1.set_xlabel("time [s]")
        ax1.set_ylabel("sinkage [mm]")
        ax1.legend(fontsize="small")
        ax2.plot(water * 100, lost[1:].mean(axis=0), "o-", ms=3)
        ax2.set_xlabel("water content [%]")
        ax2.set_ylabel("work lost per step cycle [J]")
        fig.suptitle(f"{args.worlds} legs stepping in mud (MJX, one jit)")
        fig.tight_layout()
        fig.savefig(args.out, dpi=100)
        print(f"wrote {args.out}")
    return {"depth": depth, "lost": lost, "water": water}


if __name__ == "__main__":
    main()
