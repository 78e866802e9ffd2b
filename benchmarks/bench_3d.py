"""Benchmark the 3-D law: ns per element per step and us per step, one foot and many (MudContacts3D).

Run: ``python benchmarks/bench_3d.py`` (``--quick`` for a short run).
Prints figures; asserts nothing. One thread unless a line says otherwise. Targets (issue 21, "Speed"): at most
20 ns per element per step on one CPU thread, and at most 2 us a step for
a 64-element foot; on an H100, 4,096 quadrupeds x 4 feet x 64 elements
in at most 1 ms per step (the JAX step, :mod:`mudforce.jax.contact3d`; its CPU
figures are printed here, and :func:`bench_jax` runs on any JAX device).

The feet walk: each foot's origin follows its own loop (phases and
frequencies spread, 1 kHz), down into the mud, sideways while in it
(sliding, so the lateral law yields), tilting, and out again, so every
contact state and the lateral law's every branch occur. The foot is a
64-element sphere (40 mm, elements on a Fibonacci lattice) or a 64-element
sole (48 x 48 mm, 8 x 8). CPU time of this process, best and median of the
repeats (bench_core.py's convention: the best is the figure for the code,
the median shows how far the shared machine strays).
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import mudforce as mf
from mudforce.model import shapes
from mudforce.steppers.contact3d import MudContact3D, MudContacts3D

RATE = 1000.0  # steps per second [1/s]


def fibonacci_sphere(diameter: float = 0.04, n: int = 64) -> shapes.Shape:
    """A sphere of ``n`` equal elements on a Fibonacci lattice [m]."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    r = np.sqrt(1.0 - z * z)
    phi = k * math.pi * (3.0 - math.sqrt(5.0))
    normals = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    radius = diameter / 2.0
    areas = np.full(n, 4.0 * math.pi * radius * radius / n)
    return shapes.Shape(normals * radius, normals, areas, name=f"fibonacci sphere {n}", width=diameter)


def walk(feet: int, steps: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Poses of ``feet`` feet over ``steps`` steps at 1 kHz: positions (steps, feet, 3) [m], quaternions (.., 4)."""
    rng = np.random.default_rng(seed)
    t = np.arange(steps)[:, None] / RATE
    freq = rng.uniform(1.0, 2.5, feet)
    phase = rng.uniform(0.0, 2.0 * math.pi, feet)
    heading = rng.uniform(0.0, 2.0 * math.pi, feet)
    w = 2.0 * math.pi * freq * t + phase
    along = 0.03 * np.cos(w)  # sideways 60 mm a cycle, while in the mud half of it
    pos = np.empty((steps, feet, 3))
    pos[..., 0] = along * np.cos(heading)
    pos[..., 1] = along * np.sin(heading)
    pos[..., 2] = 0.005 + 0.03 * np.sin(w)  # the origin from 25 mm deep to 35 mm up
    tilt = 0.25 * np.sin(w + 1.0)
    quat = np.zeros((steps, feet, 4))
    quat[..., 0] = np.cos(tilt / 2.0)
    quat[..., 1] = np.sin(tilt / 2.0) * -np.sin(heading)
    quat[..., 2] = np.sin(tilt / 2.0) * np.cos(heading)
    return np.ascontiguousarray(pos), np.ascontiguousarray(quat)


def timings(fn: Callable[[], Any], repeats: int, clock: Callable[[], float] = time.process_time
            ) -> tuple[float, float]:
    """Best and median time of the repeats [s], by ``clock`` (by default the CPU time of this process)."""
    times = []
    for _ in range(repeats):
        c0 = clock()
        fn()
        times.append(clock() - c0)
    return min(times), float(np.median(times))


def bench_many(shape: shapes.Shape, feet: int, steps: int, repeats: int, threads: int | None = 1,
               wall: bool = False) -> tuple[float, float]:
    """Seconds per step (best, median) of ``MudContacts3D.step`` for ``feet`` feet of ``shape``.

    CPU time on one thread; wall time (``wall=True``) for several, whose CPU time adds up.
    """
    params = mf.MudParameters.from_water_content(0.25)
    pos, quat = walk(feet, steps + 1)
    contacts = MudContacts3D(params, shape, feet, threads=threads)
    out = (np.empty((feet, 3)), np.empty((feet, 3)))
    contacts.step(pos[0], quat[0], 0.0, out=out)
    start = contacts.state
    dt = 1.0 / RATE

    poses = [(pos[k], quat[k]) for k in range(1, steps + 1)]  # (made before the timing, as in bench_one)

    def run() -> None:
        contacts.state = start
        for p, q in poses:
            contacts.step(p, q, dt, out=out)

    run()  # warm-up (and compile, or load numba's cache)
    best, median = timings(run, repeats, time.perf_counter if wall else time.process_time)
    return best / steps, median / steps


def bench_kernel(shape: shapes.Shape, steps: int, repeats: int) -> tuple[float, float]:
    """Seconds per step (best, median) of one foot's compiled step called from Python as ``MudContacts3D.step``
    calls it, without its checks: what the Python front end adds is the difference from :func:`bench_many`."""
    from mudforce._kernel import step3d

    params = mf.MudParameters.from_water_content(0.25)
    pos, quat = walk(1, steps + 1)
    contacts = MudContacts3D(params, shape, 1)
    out = (np.empty((1, 3)), np.empty((1, 3)))
    contacts.step(pos[0], quat[0], 0.0, out=out)
    start = contacts.state
    none = np.zeros((0, 3))  # no element forces (MudContacts3D's)
    args = contacts._kernel_args  # the compiled step's own arrays (private: a benchmark's look inside)
    dt = 1.0 / RATE

    poses = [(pos[k], quat[k]) for k in range(1, steps + 1)]  # (made before the timing, as in bench_one)

    def run() -> None:
        contacts.state = start
        for p, q in poses:
            step3d.step_feet(p, q, dt, *args, out[0], out[1], none)

    run()
    best, median = timings(run, repeats)
    return best / steps, median / steps


def bench_one(shape: shapes.Shape, steps: int, repeats: int, numpy: bool = False, keep: bool = False
              ) -> tuple[float, float]:
    """Seconds per step (best, median) of ``MudContact3D.step`` for one foot (compiled); with ``numpy``, of the
    numpy step it compiles bit for bit (``_step_numpy``, private: a benchmark's look inside).

    The loop holds each step's Wrench until the next (a control loop's ``w = contact.step(...)``), so the step
    reuses its outputs; with ``keep``, every Wrench is kept, so each step makes new ones. The poses are the
    walk's, one (3,) and one (4,) array a step, made before the timing: what is timed is the step, not the
    caller's indexing of its own arrays (``pos[k, 0]`` makes a view, ~0.1 us each)."""
    params = mf.MudParameters.from_water_content(0.25)
    pos, quat = walk(1, steps + 1)
    contact = MudContact3D(params, shape)
    contact.step(pos[0, 0], quat[0, 0], 0.0)
    start = contact.state
    dt = 1.0 / RATE
    step = contact._step_numpy if numpy else contact.step
    poses = [(pos[k, 0], quat[k, 0]) for k in range(1, steps + 1)]

    def run() -> None:
        contact.state = start
        kept = []
        w = None
        for p, q in poses:
            w = step(p, q, dt)
            if keep:
                kept.append(w)

    run()
    best, median = timings(run, repeats)
    return best / steps, median / steps


def bench_jax(shape: shapes.Shape, feet: int, steps: int, repeats: int) -> tuple[float, float] | None:
    """Seconds per step (best, median; wall time) of :mod:`mudforce.jax.contact3d` on JAX's CPU, float64; None
    without it.

    ``jax.vmap`` of ``step3d`` over the feet, ``jax.lax.scan`` over the
    steps, jitted (compiled before timing); the same walk. An H100's
    figures (the issue's 4,096 x 4 x 64 elements) come from the same
    function on a machine with one (JAX's default device).
    """
    if importlib.util.find_spec("jax") is None or importlib.util.find_spec("mudforce.jax.contact3d") is None:
        return None
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    import mudforce.jax.contact3d as mj3

    params = mj3.make_params3d(mf.MudParameters.from_water_content(0.25), shape)
    pos, quat = walk(feet, steps + 1)
    step = jax.vmap(mj3.step3d, in_axes=(0, None, 0, 0, None))
    dt = 1.0 / RATE

    @jax.jit
    def run(state: Any, pos: Any, quat: Any) -> Any:
        def body(s: Any, pose: Any) -> Any:
            s, force, torque = step(s, params, pose[0], pose[1], dt)
            return s, force[:, 2].sum() + torque[:, 0].sum()

        return jax.lax.scan(body, state, (pos, quat))

    state, _, _ = step(mj3.init3d(shape, feet), params, jnp.asarray(pos[0]), jnp.asarray(quat[0]), 0.0)
    p, q = jnp.asarray(pos[1:]), jnp.asarray(quat[1:])
    jax.block_until_ready(run(state, p, q))  # compile

    def once() -> None:
        jax.block_until_ready(run(state, p, q))

    best, median = timings(once, repeats, time.perf_counter)
    return best / steps, median / steps


def _example(name: str) -> Any:
    """``examples/NAME.py`` imported as the module ``NAME`` (registered in ``sys.modules``: a dataclass of the
    script looks itself up there)."""
    path = Path(__file__).resolve().parents[1] / "examples" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def bench_engines(steps: int, repeats: int) -> None:
    """Issue 22, "Speed": the MuJoCo quadruped of examples/quadruped_in_mud.py trotting, four mud feet vs rigid.

    (Engines section, kept apart from the 3-D law's benchmarks above; run with ``--engines``.) Both
    trot open-loop with the same servo targets at 2 ms steps; CPU time per step, best and median.
    """
    import mujoco

    from mudforce.engines.mujoco import MudAdapter3D, MudPatch

    q = _example("quadruped_in_mud")

    made: list[Any] = []

    def rigid() -> Callable[[], None]:
        model = q.quadruped_spec(mud=False).compile()
        data = mujoco.MjData(model)

        def run() -> None:
            mujoco.mj_resetData(model, data)
            for _ in range(steps):
                data.ctrl[:] = q.trot(data.time)
                mujoco.mj_step(model, data)
        return run

    def mud() -> Callable[[], None]:
        model = q.quadruped_spec().compile()
        data = mujoco.MjData(model)
        data.qpos[0] = 0.3  # in the mud from the start
        adapter = MudAdapter3D(model, data, q.FEET, MudPatch(mf.MudParameters.from_water_content(0.20)))
        made[:] = [adapter]

        def run() -> None:
            mujoco.mj_resetData(model, data)
            data.qpos[0] = 0.3
            adapter.reset()
            for _ in range(steps):
                data.ctrl[:] = q.trot(data.time)
                adapter.step()
        return run

    mud()()  # compile
    r = timings(rigid(), repeats)
    m = timings(mud(), repeats)
    elements = sum(s.n for s in made[0].shapes)
    print(f"MuJoCo quadruped (examples/quadruped_in_mud.py), {steps} steps of 2 ms, CPU time, best and median of "
          f"{repeats} (issue 22 target: mud feet at most 2x rigid)")
    print(f"  rigid ground                     {r[0] / steps * 1e6:8.1f} {r[1] / steps * 1e6:8.1f} us/step")
    print(f"  four mud feet ({elements} elements)   {m[0] / steps * 1e6:8.1f} {m[1] / steps * 1e6:8.1f} us/step")
    print(f"  ratio mud/rigid                  {m[0] / r[0]:8.2f} {m[1] / r[1]:8.2f}")


def bench_mjx_env(worlds: int) -> None:
    """The MJX quadruped environment: seconds per control step of ``worlds`` worlds, after compiling."""
    module = _example("quadruped_mjx_env")
    per_step = module.bench(worlds=worlds, steps=50)
    substeps = module.QuadrupedMudEnv().substeps
    print(f"MJX quadruped in mud (examples/quadruped_mjx_env.py), {worlds} worlds on {module.jax.default_backend()}: "
          f"{per_step * 1e3:.2f} ms per control step ({substeps} physics steps), "
          f"{per_step / worlds / substeps * 1e6:.1f} us per world per physics step")


def _walking_feet(feet: int, steps: int) -> tuple[MudContacts3D, np.ndarray, np.ndarray,
                                                  tuple[np.ndarray, np.ndarray]]:
    """``feet`` sphere feet in 25 % mud after the first pose of a ``steps``-step walk: the feet, the walk's
    positions [m] and quaternions, and the output pair that ``--walk-only`` and ``--census`` step into."""
    pos, quat = walk(feet, steps + 1)
    contacts = MudContacts3D(mf.MudParameters.from_water_content(0.25), fibonacci_sphere(), feet)
    out = (np.empty((feet, 3)), np.empty((feet, 3)))
    contacts.step(pos[0], quat[0], 0.0, out=out)
    return contacts, pos, quat, out


def walk_only(feet: int, steps: int) -> None:
    """Step ``feet`` walking sphere feet ``steps`` steps and print their last wrench sums; nothing timed.

    For instruction counts, which the shared machine's load does not change (docs/speed.md, "Mud in 3-D"): run
    it under ``valgrind --tool=callgrind`` for two values of ``steps`` and take the difference of the instructions
    in numba's compiled code over ``feet x 64 x`` the extra steps (the import and the compile cancel).
    """
    contacts, pos, quat, out = _walking_feet(feet, steps)
    for k in range(1, steps + 1):
        contacts.step(pos[k], quat[k], 1.0 / RATE, out=out)
    print(f"{feet} feet, {steps} steps: force sum {float(out[0].sum())!r} N, torque sum {float(out[1].sum())!r} N m")


def census(feet: int, steps: int) -> None:
    """Count the walk's element-steps by the path the compiled step takes for them (docs/speed.md, "Mud in 3-D").

    Steps ``feet`` walking sphere feet ``steps`` steps and classifies each element-step by the element's contact
    state before and after it (read from the 1-D state rows: a benchmark's look inside): a quiet step in FREE,
    CONTACT moving down, at rest or up, or NECKED, above or below the surface, or a change of contact state (the
    state machine's). Prints the shares; nothing timed.
    """
    from mudforce._kernel import layout

    contacts, pos, quat, out = _walking_feet(feet, steps)
    states = contacts._kernel_args[1]  # the 1-D state rows (private: a benchmark's look inside)
    counts: dict[str, int] = {}
    names = layout.STATE_NAMES
    for k in range(1, steps + 1):
        contacts._export_rows()  # the rows as the lanes hold them (the compiled step keeps its state there)
        before = states[:, layout.S_MODE].astype(int)
        contacts.step(pos[k], quat[k], 1.0 / RATE, out=out)
        contacts._export_rows()
        after = states[:, layout.S_MODE].astype(int)
        below = states[:, layout.S_DEPTH] > 0.0
        direction = states[:, layout.S_DIRECTION]
        labels = np.where(before != after, np.char.add(np.char.add(np.array(names)[before], " -> "),
                                                       np.array(names)[after]), "")
        quiet = before == after
        for label, mask in (("FREE, quiet", quiet & (before == layout.FREE)),
                            ("CONTACT moving down, quiet", quiet & (before == layout.CONTACT) & (direction > 0.0)),
                            ("CONTACT at rest, quiet", quiet & (before == layout.CONTACT) & (direction == 0.0)),
                            ("CONTACT moving up, below the surface, quiet",
                             quiet & (before == layout.CONTACT) & (direction < 0.0) & below),
                            ("CONTACT moving up, above the surface, quiet",
                             quiet & (before == layout.CONTACT) & (direction < 0.0) & ~below),
                            ("NECKED above the surface, quiet", quiet & (before == layout.NECKED) & ~below),
                            ("NECKED below the surface, quiet", quiet & (before == layout.NECKED) & below)):
            counts[label] = counts.get(label, 0) + int(mask.sum())
        for label in labels[~quiet]:
            counts[str(label)] = counts.get(str(label), 0) + 1
    total = contacts.n_elements * steps
    print(f"{feet} walking sphere feet, {steps} steps: {total} element-steps (\"quiet\": the same contact state "
          f"after the step; a change of state is the state machine's)")
    for label, count in sorted(counts.items(), key=lambda item: -item[1]):
        print(f"  {label:45s} {count:9d} {100.0 * count / total:6.2f} %")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats, and no 4096-foot run")
    ap.add_argument("--repeats", type=int, default=None)
    ap.add_argument("--engines", action="store_true", help="only the MuJoCo quadruped, mud feet vs rigid ground")
    ap.add_argument("--mjx-env", type=int, default=None, metavar="WORLDS",
                    help="only the MJX quadruped environment (examples/quadruped_mjx_env.py), WORLDS worlds "
                         "(16 on a CPU, 4096 on a GPU)")
    ap.add_argument("--walk-only", type=int, nargs=2, default=None, metavar=("FEET", "STEPS"),
                    help="only step FEET walking sphere feet STEPS steps, untimed (for instruction counts)")
    ap.add_argument("--census", type=int, nargs=2, default=None, metavar=("FEET", "STEPS"),
                    help="only count the walk's element-steps by contact state and path, untimed")
    args = ap.parse_args()
    if args.census is not None:
        census(*args.census)
        return
    if args.walk_only is not None:
        walk_only(*args.walk_only)
        return
    if args.mjx_env is not None:
        bench_mjx_env(args.mjx_env)
        return
    repeats = args.repeats or (3 if args.quick else 7)
    # (--quick keeps the full bench's 1,000 steps: a shorter stretch of the walk is not its average: the first 200
    # steps hold most of its touchdowns and read 15-30 % more)
    steps = 1000
    if args.engines:
        bench_engines(steps, repeats)
        return
    sphere = fibonacci_sphere()
    sole = shapes.sole(mf.Foot.cuboid(0.048, 0.048), resolution=0.006)
    print(f"3-D law, 1 kHz walk (down, sliding, tilting, out); CPU time, best and median of {repeats}; one thread")
    print(f"  {'case':52s} {'us/step':>17s} {'ns/element-step':>17s}")

    def row(label: str, per_step: tuple[float, float], elements: int) -> None:
        best, median = per_step
        print(f"  {label:52s} {best * 1e6:8.2f} {median * 1e6:8.2f} {best / elements * 1e9:8.2f} "
              f"{median / elements * 1e9:8.2f}")

    cases: list[tuple[str, shapes.Shape, int, int]] = []
    for name, shape in (("sphere", sphere), ("sole", sole)):
        cases.append((f"MudContacts3D, 1 {name} foot ({shape.n} el.)", shape, 1, steps * 5))
        cases.append((f"MudContacts3D, 64 {name} feet", shape, 64, steps))
    if not args.quick:
        cases.append(("MudContacts3D, 4096 sphere feet (4 x 1024)", sphere, 4096, max(steps // 20, 20)))
    for label, shape, feet, n_steps in cases:
        row(label, bench_many(shape, feet, n_steps, repeats), feet * shape.n)
        if feet == 1:
            row("  its compiled step alone (no Python checks)", bench_kernel(shape, n_steps, repeats), shape.n)
    if not args.quick:
        auto = MudContacts3D(mf.MudParameters.from_water_content(0.25), sphere, 4096, threads=None).threads
        for threads in sorted({1, auto}):
            row(f"  the same on {threads} thread(s), wall time",
                bench_many(sphere, 4096, max(steps // 20, 20), repeats, threads=threads, wall=True), 4096 * sphere.n)
    row("MudContact3D.step, 1 sphere foot (64 el.)", bench_one(sphere, steps * 2, repeats), sphere.n)
    row("  the same, every Wrench kept (new outputs each step)", bench_one(sphere, steps * 2, repeats, keep=True),
        sphere.n)
    row("  its numpy step (the same bits)", bench_one(sphere, max(steps // 5, 50), repeats, numpy=True), sphere.n)
    jax = bench_jax(sphere, 64, steps // 2, repeats)
    if jax is None:
        print("  JAX (mudforce.jax.contact3d): not installed here")
    else:
        row("mudforce.jax.contact3d on JAX's CPU, 64 sphere feet (wall)", jax, 64 * sphere.n)


if __name__ == "__main__":
    main()
