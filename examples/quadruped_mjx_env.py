"""The quadruped of ``quadruped_in_mud.py`` in MJX, as a Playground-style environment with mud randomised per world.

The robot is ``quadruped_in_mud.py``'s (its MJCF and its open-loop trot, imported from there): a 10 kg
torso, four legs of two hinges, position servos, 50 mm spherical toes (about 11.6 kg). Here it stands on
one patch of mud (no rigid floor: every collision is off) whose water content each world draws in
:meth:`QuadrupedMudEnv.reset`, under ``jit``, from ``water_range``. The toes' mud is
:mod:`mudforce.engines.mjx3d` (the 3-D law: each toe's surface from its sphere geom, the whole force,
held in every direction); each control step is ``substeps`` physics steps of it.

The environment follows MuJoCo Playground's shape: ``reset(rng) -> State`` and ``step(state, action) ->
State``, pure functions of pytrees, to ``jax.vmap`` over worlds and ``jax.jit``; ``State`` carries the
``mjx.Data``, the mud's state and this world's mud, ``obs``, ``reward``, ``done`` and ``metrics``
(``sinkage`` [m]: the deepest toe below the surface; ``slip`` [m]: the toes' horizontal travel while in the
mud during the step; ``energy`` [J]: the work the mud took from the toes during the step).

Run::

    python examples/quadruped_mjx_env.py                      # 16 worlds, 1 s, per-world W, sinkage, slip
    python examples/quadruped_mjx_env.py --plot env.png       # with plots (matplotlib)
    python examples/quadruped_mjx_env.py --bench              # time a control step for 16 worlds
    python examples/quadruped_mjx_env.py --gpu                # 1,024 worlds (on a GPU)
    python examples/quadruped_mjx_env.py --worlds 4096        # any number of worlds from 1 to 16,384
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from pathlib import Path
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

import mudforce.engines.mjx3d as mud3d
import mudforce.jax as mjax
from mudforce import MudParameters
from mudforce.engines.mujoco import MudPatch
from mudforce.errors import InputError
from mudforce.io import check_output_path


def _quadruped() -> Any:
    """``examples/quadruped_in_mud.py`` as a module (this file's neighbour; not an installed package)."""
    name = "quadruped_in_mud"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, Path(__file__).with_name("quadruped_in_mud.py"))
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


Q = _quadruped()
FEET: list[str] = Q.FEET
#: Most worlds ``--worlds`` takes: 16 times a GPU's 1024 (--gpu)
MAX_WORLDS = 16_384
#: Most control steps of all worlds a run records (worlds x steps): 2**27, 16384 worlds for 81 s, 1024 for 600 s
MAX_RECORDED = 2**27


class State(NamedTuple):
    """One world's state (a pytree): MJX's data, the mud's state and mud, and what RL needs.

    ``obs`` (torso height [m], orientation, joint angles [rad], velocities, toe depths [m]); ``reward``
    the torso's forward speed [m/s]; ``done`` 1.0 when the torso has fallen or a number is not finite;
    ``metrics``: ``sinkage`` [m], ``slip`` [m], ``energy`` [J] of the step, ``water_content`` [-].
    """

    data: Any
    mud_state: mud3d.MudState3D
    mud: mud3d.Mud3D
    obs: jax.Array
    reward: jax.Array
    done: jax.Array
    metrics: dict[str, jax.Array]


class QuadrupedMudEnv:
    """The quadruped trotting in mud whose water content each world draws in :meth:`reset`.

    Parameters
    ----------
    water_range : (float, float)
        Water contents [-] to draw from, uniformly, within Table I's [0.15, 0.35].
    dt : float
        Physics time step [s].
    substeps : int
        Physics steps per control step (:meth:`step`).
    resolution : float
        Element size of the toes' surfaces [m] (coarse toes are cheaper).
    """

    def __init__(self, water_range: tuple[float, float] = (0.15, 0.30), *, dt: float = 2e-3, substeps: int = 5,
                 resolution: float = 0.01) -> None:
        lo, hi = (float(w) for w in water_range)
        if not 0.15 <= lo <= hi <= 0.35:
            raise ValueError(f"water_range must lie within Table I's [0.15, 0.35], got {water_range!r}")
        spec = Q.quadruped_spec(dt=dt, mud=False)
        for g in spec.geoms:  # the mud carries the toes: no rigid floor under them, no other contact
            g.contype = 0
            g.conaffinity = 0
        spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
        self.model = spec.compile()
        self.m = mjx.put_model(self.model)
        self.water_range = (lo, hi)
        self.substeps = int(substeps)
        self.dt = float(dt)
        self.control_dt = self.dt * self.substeps
        self.mud = mud3d.add_mud(self.model, FEET, MudPatch(MudParameters.from_water_content(lo)),
                                 resolution=resolution)
        self.toes = np.array([mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_GEOM, f) for f in FEET])
        self.radius = float(self.model.geom_size[self.toes[0], 0])
        self._qpos0 = jnp.asarray(self.model.qpos0)

    # ---------------------------------------------------------------- the environment
    def reset(self, rng: jax.Array) -> State:
        """A fresh world: the robot standing on the mud's surface, its own water content drawn from ``rng``."""
        lo, hi = self.water_range
        w = jax.random.uniform(rng, (), minval=lo, maxval=hi)
        mud = mud3d.set_mud(self.mud, mjax.params_from_water_content(w))
        d = mjx.make_data(self.m).replace(qpos=self._qpos0)  # the first step's mjx.forward places it
        mud_state = mud3d.init(mud)
        zero = jnp.zeros(())
        metrics = {"sinkage": zero, "slip": zero, "energy": zero, "water_content": w}
        return State(d, mud_state, mud, self._obs(d), zero, zero, metrics)

    def step(self, state: State, action: jax.Array) -> State:
        """One control step: the servo targets ``action`` (hip and knee [rad] per leg) held for ``substeps``."""
        d0 = state.data.replace(ctrl=jnp.asarray(action, dtype=state.data.ctrl.dtype))
        # this world's mud; the feet (geoms, bodies, elements) are the model's constants, not traced per world
        mud = self.mud._replace(elements=state.mud.elements, lateral_stiffness=state.mud.lateral_stiffness)

        def physics(carry: tuple[Any, mud3d.MudState3D], _: Any) -> tuple[Any, jax.Array]:
            d, last = carry
            d, s, _ = mud3d.step(self.m, d, last, mud)
            # the toes' motion between the last two commits (the poses the mud saw), under the force of that step
            moved = jnp.where((last.patch >= 0)[:, None], s.position - last.position, 0.0)
            in_mud = s.depth > -1e-3  # touching or below the surface (NaN off the patch: False)
            slip = jnp.sum(jnp.where(in_mud, jnp.hypot(moved[:, 0], moved[:, 1]), 0.0))
            energy = -jnp.sum(last.force * moved)  # the work the mud took from the toes [J]
            sink = jnp.max(jnp.where(in_mud, s.depth, 0.0))
            return (d, s), jnp.stack([slip, energy, sink])

        # the per-substep numbers come out of the scan rather than ride in its carry: under jax.vmap a carry
        # that starts unbatched (a constant) makes jax batch the whole physics step twice
        (d, s), per = jax.lax.scan(physics, (d0, state.mud_state), None, length=self.substeps)
        acc = jnp.zeros(3)
        for k in range(self.substeps):  # in order, as the scan's carry summed them
            acc = jnp.stack([acc[0] + per[k, 0], acc[1] + per[k, 1], jnp.maximum(acc[2], per[k, 2])])
        reward = d.qvel[0]  # the torso's forward speed [m/s]
        finite = jnp.isfinite(d.qpos).all() & jnp.isfinite(d.qvel).all()
        done = jnp.where(finite & (d.qpos[2] > 0.08), 0.0, 1.0)
        metrics = {**state.metrics, "sinkage": acc[2], "slip": acc[0], "energy": acc[1]}
        return State(d, s, state.mud, self._obs(d, s), reward, done, metrics)

    def _obs(self, d: Any, s: mud3d.MudState3D | None = None) -> jax.Array:
        depths = jnp.zeros(len(FEET)) if s is None else jnp.nan_to_num(s.depth)
        return jnp.concatenate([d.qpos[2:], d.qvel, depths])

    # ---------------------------------------------------------------- helpers
    def trot_actions(self, steps: int, *, frequency: float = 2.0) -> jax.Array:
        """The open-loop trot of ``quadruped_in_mud.trot`` for ``steps`` control steps, shape (steps, 8) [rad]."""
        return jnp.asarray(np.stack([Q.trot(k * self.control_dt, frequency=frequency) for k in range(steps)]))

    def rollout_function(self) -> Any:
        """``rollout(keys, actions) -> (water contents, metrics per step)``: reset every world, then play
        ``actions`` (steps, 8) in all of them; a pure function of ``keys`` (worlds, 2), to ``jax.jit``.

        As Brax and MuJoCo Playground write it: ``jax.vmap(reset)``, then one ``lax.scan`` over the control
        steps of the vmapped :meth:`step`, a scan of a vmap. (A vmap of the scan gives the same numbers, bit for
        bit, but jax batches the physics step five times over to trace it, not once.) The metrics come back
        (worlds, steps).
        """
        vstep = jax.vmap(self.step, in_axes=(0, None))

        def control(state: State, action: jax.Array) -> tuple[State, dict[str, jax.Array]]:
            state = vstep(state, action)
            return state, {**state.metrics, "x": state.data.qpos[:, 0], "done": state.done}

        def rollout(keys: jax.Array, actions: jax.Array) -> tuple[jax.Array, dict[str, jax.Array]]:
            first = jax.vmap(self.reset)(keys)
            _, metrics = jax.lax.scan(control, first, actions)
            return first.metrics["water_content"], {k: v.T for k, v in metrics.items()}

        return rollout


def compile_rollout(env: QuadrupedMudEnv, worlds: int, steps: int,
                    compiler_options: dict[str, Any] | None = None) -> Any:
    """``rollout(seed) -> dict of numpy arrays``: ``worlds`` worlds reset from ``seed`` and trotted ``steps``
    control steps, compiled once (``compiler_options`` go to XLA).

    The arrays: ``water_content`` (worlds,) [-]; ``sinkage`` [m], ``slip`` [m], ``energy`` [J], ``x`` [m] the
    torso's position, ``done`` (worlds, steps); ``time`` (steps,) [s].
    """
    actions = env.trot_actions(steps)
    keys = jax.random.split(jax.random.PRNGKey(0), worlds)
    compiled = jax.jit(env.rollout_function()).lower(keys, actions).compile(compiler_options)

    def rollout(seed: int) -> dict[str, np.ndarray]:
        w, metrics = compiled(jax.random.split(jax.random.PRNGKey(seed), worlds), actions)
        out = {k: np.asarray(v, dtype=np.float64) for k, v in metrics.items() if k != "water_content"}
        out["water_content"] = np.asarray(w, dtype=np.float64)
        out["time"] = np.arange(1, steps + 1) * env.control_dt
        return out

    return rollout


def run(worlds: int = 16, duration: float = 1.0, *, seed: int = 0, env: QuadrupedMudEnv | None = None,
        compiler_options: dict[str, Any] | None = None) -> dict[str, np.ndarray]:
    """Trot ``worlds`` worlds for ``duration`` [s]: :func:`compile_rollout`'s arrays for ``seed``."""
    env = env or QuadrupedMudEnv()
    return compile_rollout(env, worlds, max(1, round(duration / env.control_dt)), compiler_options)(seed)


def bench(worlds: int = 16, steps: int = 50, *, env: QuadrupedMudEnv | None = None) -> float:
    """Seconds per control step of ``worlds`` worlds (``env.substeps`` physics steps each), after compiling.

    One jitted ``lax.scan`` of ``steps`` control steps of the vmapped :meth:`QuadrupedMudEnv.step`, timed
    on its second call (the first compiles).
    """
    env = env or QuadrupedMudEnv()
    keys = jax.random.split(jax.random.PRNGKey(0), worlds)
    states = jax.jit(jax.vmap(env.reset))(keys)
    actions = env.trot_actions(steps)
    vstep = jax.vmap(env.step, in_axes=(0, None))
    play = jax.jit(lambda s, a: jax.lax.scan(lambda s, x: (vstep(s, x), s.reward), s, a)[0].reward)
    jax.block_until_ready(play(states, actions))
    start = time.perf_counter()
    jax.block_until_ready(play(states, actions))
    return (time.perf_counter() - start) / steps


def plot(result: dict[str, np.ndarray], path: str) -> None:
    """Save sinkage, slip and energy lost per control step of every world, coloured by water content."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    w = result["water_content"]
    colours = plt.get_cmap("viridis")((w - w.min()) / max(float(np.ptp(w)), 1e-9))
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for key, ax, label, scale in (("sinkage", axes[0], "deepest toe sinkage [mm]", 1e3),
                                  ("slip", axes[1], "toe slip per step [mm]", 1e3),
                                  ("energy", axes[2], "energy lost per step [J]", 1.0)):
        for k in range(len(w)):
            ax.plot(result["time"], result[key][k] * scale, color=colours[k], lw=1)
        ax.set_ylabel(label)
    axes[0].set_title("each world's own mud: colour from dry (dark) to wet (light)")
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", type=int, default=None,
                    help=f"number of worlds, 1 to {MAX_WORLDS} (16; 1024 with --gpu)")
    ap.add_argument("--gpu", action="store_true", help="1,024 worlds (for a GPU)")
    ap.add_argument("--duration", type=float, default=1.0, help="simulated time [s]")
    ap.add_argument("--seed", type=int, default=0, help="seed of the worlds' water contents")
    ap.add_argument("--plot", default=None, help="save plots of sinkage, slip and energy as this PNG")
    ap.add_argument("--bench", action="store_true", help="time a control step of the worlds instead")
    args = ap.parse_args(argv)
    if args.worlds is not None and not 1 <= args.worlds <= MAX_WORLDS:  # 10**12 aborted in XLA (a check failure)
        ap.error(f"--worlds must be from 1 to {MAX_WORLDS}, got {args.worlds}")
    if not 0.0 < args.duration <= 600.0:
        ap.error(f"--duration must be within (0, 600] s, got {args.duration}")
    if not 0 <= args.seed < 2**32:
        ap.error(f"--seed must be an integer in [0, {2**32 - 1}], got {args.seed}")
    if args.plot:
        try:  # before the compile and the run, not after them
            check_output_path(args.plot, "--plot", suffix=".png")
        except InputError as error:
            ap.error(str(error))
    worlds = args.worlds or (1024 if args.gpu else 16)
    defaults = QuadrupedMudEnv.__init__.__kwdefaults__ or {}  # the env's control step, before it is built
    steps = max(1, round(args.duration / (defaults["dt"] * defaults["substeps"])))  # as run() takes them
    if not args.bench and worlds * steps > MAX_RECORDED:  # (16384 worlds for 600 s: 983 million)
        ap.error(f"{worlds} worlds for --duration {args.duration:g} s would record {worlds * steps:,} control steps "
                 f"(worlds x steps), more than {MAX_RECORDED:,}; lower --worlds or --duration")
    env = QuadrupedMudEnv()
    if args.bench:
        per = bench(worlds, env=env)
        print(f"{worlds} worlds: {per * 1e3:.2f} ms a control step ({env.substeps} physics steps of "
              f"{env.dt * 1e3:g} ms), {per / env.substeps * 1e6:.0f} us a physics step")
        return
    res = run(worlds, args.duration, seed=args.seed, env=env)
    print("world  W [%]  sinkage [mm]  slip [mm]  energy [J]  torso x [mm]  fell")
    for k, w in enumerate(res["water_content"]):
        print(f"{k:5d}  {w * 100:5.1f}  {res['sinkage'][k].max() * 1e3:12.2f}  {res['slip'][k].sum() * 1e3:9.1f}"
              f"  {res['energy'][k].sum():10.3f}  {(res['x'][k, -1] - res['x'][k, 0]) * 1e3:12.1f}  "
              f"{'yes' if res['done'][k].any() else 'no'}")
    if args.plot:
        plot(res, args.plot)
        print(f"saved {args.plot}")


if __name__ == "__main__":
    main()
