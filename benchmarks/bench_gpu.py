"""Benchmark mudforce.jax on whatever backend JAX has (GPU if present, else CPU); prints figures, asserts nothing.

Run: ``python benchmarks/bench_gpu.py`` (on a CPU: 16,384 and 65,536 feet;
``--all`` adds 1M and 16M feet, which want a GPU). For each foot count and
float64/float32 it prints

* ``scan``: time per step inside one jitted ``lax.scan`` of ``--steps`` steps
  (per-foot parameters, a gait generated inside the scan from two per-foot
  arrays), and ns per foot;
* ``floor``: the least memory traffic such a step needs, measured the same
  way: one fused pass per step that reads the state, the parameters and
  the gait's arrays once and writes the state and the forces once, with
  no model (the ratio ``scan / floor`` is the figure of merit on a GPU);
* ``call``: time per call of the jitted step from Python (state donated,
  results left on the device, synchronised once at the end);
* ``cpu``: :class:`mudforce.steppers.many.MudContacts` on this machine's CPU
  cores, per step, on the same gait.

Then it measures float32 against float64 over a 10 s gait at 1 kHz (all
five Table I rows) and prints the worst error relative to the peak force.

Targets (issue 14, on an H100): at 16M feet <= 2x the floor (float64) and
1.3x (float32); at 16,384 feet <= 15 us per step inside jit.
"""

from __future__ import annotations

import os

# keep JAX from taking most of the GPU's memory at start-up; must be set before jax is imported
os.environ.setdefault("XLA_PYTHON_CLIENT_PREALLOCATE", "false")

import argparse
import time

import jax

jax.config.update("jax_enable_x64", True)  # float64 available; every array below has an explicit dtype

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

import mudforce.jax as mj  # noqa: E402
from mudforce.model.parameters import MudParameters  # noqa: E402

DT = 1e-3
WATER = (0.15, 0.20, 0.25, 0.30, 0.35)


def per_foot_params(n: int, dtype: object, seed: int = 0) -> mj.Params:
    """Per-foot parameters: Table I rows cycled over the feet, each mud value scaled by up to +-10 % (randomised)."""
    base = mj.make_params([MudParameters.table_i(w) for w in WATER], dtype=jnp.float64)
    idx = np.arange(n) % len(WATER)
    rng = np.random.default_rng(seed)
    fields = []
    for i, f in enumerate(base):
        col = np.asarray(f)[idx] * (rng.uniform(0.9, 1.1, n) if i < 11 else 1.0)  # the mud varies, not the foot
        fields.append(jnp.asarray(col, dtype=dtype))
    return mj.Params(*fields)


def gait_arrays(n: int, dtype: object, seed: int = 1) -> tuple[jax.Array, jax.Array]:
    """Per-foot mean depth and amplitude [m] of a 1.5 Hz stepping gait (in the mud ~40 % of the time)."""
    rng = np.random.default_rng(seed)
    return (jnp.asarray(rng.uniform(-8e-3, 0.0, n), dtype=dtype), jnp.asarray(rng.uniform(0.02, 0.03, n), dtype=dtype))


def depth_at(k: jax.Array, mean: jax.Array, amp: jax.Array) -> jax.Array:
    """The gait's depths [m] at step ``k``."""
    phase = (2.0 * np.pi * 1.5 * DT) * k.astype(mean.dtype)
    return mean + amp * jnp.sin(phase)


def make_scan(steps: int):  # type: ignore[no-untyped-def]
    """A jitted ``run(state, params, mean, amp, k0)`` of ``steps`` steps of every foot -> (final state, last forces).

    The parameters and the gait's arrays are arguments, as in a training
    loop, not constants closed over: XLA would fold the parameter-only
    arithmetic at compile time (measuring less than a real step) and, at
    16M feet, embed gigabytes of constants in the program.
    """
    def run(state: mj.State, params: mj.Params, mean: jax.Array, amp: jax.Array,
            k0: jax.Array) -> tuple[mj.State, jax.Array]:
        def body(carry, k):  # type: ignore[no-untyped-def]
            s, _ = carry
            s, f = mj.step(s, params, depth_at(k, mean, amp), DT)
            return (s, f), None
        (s, f), _ = jax.lax.scan(body, (state, jnp.zeros_like(mean)), k0 + jnp.arange(steps))
        return s, f
    return jax.jit(run, donate_argnums=0)


def make_floor(steps: int):  # type: ignore[no-untyped-def]
    """The memory floor: per step, read the state, params and gait arrays once, write state and forces once."""
    def run(state: mj.State, params: mj.Params, mean: jax.Array, amp: jax.Array,
            k0: jax.Array) -> tuple[mj.State, jax.Array]:
        def body(carry, k):  # type: ignore[no-untyped-def]
            s, _ = carry
            z = depth_at(k, mean, amp)
            psum = sum(params[1:], params[0])  # reads every parameter array
            f = z * psum
            floats = [x + z for x in s[1:]]  # reads and writes every float field
            return (mj.State(s.mode + jnp.int8(1), *floats), f), None
        (s, f), _ = jax.lax.scan(body, (state, jnp.zeros_like(mean)), k0 + jnp.arange(steps))
        return s, f
    return jax.jit(run, donate_argnums=0)


def timed(fn, state: mj.State, args: tuple, repeats: int) -> tuple[float, mj.State]:  # type: ignore[no-untyped-def]
    """Best wall time of ``fn(state, *args, k0)`` over the repeats [s] (compiled first)."""
    state, f = fn(state, *args, jnp.asarray(0))
    f.block_until_ready()
    best = np.inf
    for r in range(repeats):
        t0 = time.perf_counter()
        state, f = fn(state, *args, jnp.asarray(r + 1))
        f.block_until_ready()
        best = min(best, time.perf_counter() - t0)
    return best, state


def bench_n(n: int, dtype: object, steps: int, calls: int, repeats: int, cpu: bool) -> None:
    name = jnp.dtype(dtype).name
    params = per_foot_params(n, dtype)
    mean, amp = gait_arrays(n, dtype)
    t_scan, _ = timed(make_scan(steps), mj.init(n, dtype), (params, mean, amp), repeats)
    t_floor, _ = timed(make_floor(steps), mj.init(n, dtype), (params, mean, amp), repeats)
    # per call from Python: the jitted step, state donated, depths precomputed on the device
    step = jax.jit(mj.step, donate_argnums=0)
    zs = [depth_at(jnp.asarray(k), mean, amp) for k in range(8)]
    s = mj.init(n, dtype)
    dt = jnp.asarray(DT, dtype)
    s, f = step(s, params, zs[0], dt)
    f.block_until_ready()
    best_call = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        for c in range(calls):
            s, f = step(s, params, zs[c % 8], dt)
        f.block_until_ready()
        best_call = min(best_call, (time.perf_counter() - t0) / calls)
    per = t_scan / steps
    floor = t_floor / steps
    line = (f"n={n:>10,d} {name:>7}: scan {per * 1e6:9.2f} us/step ({per / n * 1e9:7.3f} ns/foot); "
            f"floor {floor * 1e6:9.2f} us/step -> {per / floor:5.2f}x floor; call {best_call * 1e6:9.2f} us/call")
    if cpu and name == "float64":
        from mudforce.steppers.many import MudContacts

        values = np.column_stack([np.asarray(f) for f in per_foot_params(n, jnp.float64)[:11]])
        mean_np = np.asarray(mean, dtype=np.float64)
        amp_np = np.asarray(amp, dtype=np.float64)
        cpu_steps = max(20, min(200, 2_000_000 // n))
        for threads in (None, 1):
            feet = MudContacts(values, n, threads=threads)
            t_cpu = np.inf
            k = 0
            for _ in range(repeats + 1):  # the first repeat warms up (compiled code, numba's threads)
                spent = 0.0
                for _ in range(cpu_steps):
                    z = mean_np + amp_np * np.sin(2.0 * np.pi * 1.5 * DT * k)  # the same gait, in sequence
                    k += 1
                    t0 = time.perf_counter()
                    feet.step(z, DT)
                    spent += time.perf_counter() - t0
                t_cpu = min(t_cpu, spent / cpu_steps)
            line += (f"; MudContacts ({feet.threads} thread{'s' if feet.threads > 1 else ''}) "
                     f"{t_cpu * 1e6:.1f} us/step ({t_cpu / n * 1e9:.2f} ns/foot)")
    print(line, flush=True)


def float32_error(seconds: float = 10.0, feet_per_row: int = 8) -> None:
    """Worst |F32 - F64| over a ``seconds`` gait at 1 kHz, relative to the peak force, per Table I row."""
    steps = round(seconds / DT)
    n = feet_per_row * len(WATER)
    muds = [MudParameters.table_i(w) for w in WATER for _ in range(feet_per_row)]
    rng = np.random.default_rng(7)
    mean = rng.uniform(-5e-3, 15e-3, n)
    amp = rng.uniform(5e-3, 25e-3, n)
    freq = rng.uniform(0.5, 2.5, n)
    t = np.arange(steps)[:, None] * DT
    z = mean + amp * np.sin(2.0 * np.pi * freq * t)

    def run(dtype: object) -> tuple[np.ndarray, np.ndarray]:
        params = mj.make_params(muds, dtype=dtype)
        dt = jnp.asarray(DT, dtype)

        def body(s: mj.State, zk: jax.Array) -> tuple[mj.State, tuple[jax.Array, jax.Array]]:
            s, f = mj.step(s, params, zk, dt)
            return s, (f, s.velocity)

        f, v = jax.jit(lambda z: jax.lax.scan(body, mj.init(n, dtype), z)[1])(jnp.asarray(z, dtype=dtype))
        return np.asarray(f, dtype=np.float64), np.asarray(v, dtype=np.float64)

    f64, v64 = run(jnp.float64)
    f32, v32 = run(jnp.float32)
    flips = np.sign(v32) != np.sign(v64)  # steps whose branch (the sign of the motion) float32 cannot resolve
    worst = 0.0
    for i, w in enumerate(WATER):
        cols = slice(i * feet_per_row, (i + 1) * feet_per_row)
        diff = np.abs(f32[:, cols] - f64[:, cols])
        peak = np.abs(f64[:, cols]).max()
        err = diff.max() / peak
        flip = flips[:, cols]
        near = np.zeros_like(flip)
        for k in np.flatnonzero(flip.any(axis=1)):  # a flipped step and the 50 ms after it
            near[k:k + 50] |= flip[k]
        print(f"float32 vs float64, W = {w:.0%}, {seconds:g} s at 1 kHz, {feet_per_row} feet: max error {err:.2e} "
              f"of the peak force; {int(flip.sum())} steps with a different branch; "
              f"away from them (50 ms after): {np.where(near, 0.0, diff).max() / peak:.2e}")
        worst = max(worst, err)
    print(f"float32 vs float64: worst {worst:.2e} of the peak force (target 1e-5); branch flips happen where a "
          "step moves the foot by less than float32's resolution of the depth (|v| dt < ulp(z_i))")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, nargs="*", default=None, help="foot counts (default: 16384 65536)")
    ap.add_argument("--all", action="store_true", help="also 1M and 16M feet (a GPU's sizes)")
    ap.add_argument("--steps", type=int, default=None, help="steps per scan (default: 1000 on GPU, 100 on CPU)")
    ap.add_argument("--calls", type=int, default=100, help="calls from Python per repeat")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--no-cpu", action="store_true", help="skip MudContacts")
    ap.add_argument("--no-accuracy", action="store_true", help="skip the float32 accuracy measurement")
    args = ap.parse_args()
    backend = jax.default_backend()
    devices = jax.devices()
    print(f"JAX {jax.__version__}, backend {backend}: {devices[0].device_kind} x {len(devices)}", flush=True)
    if backend == "cpu":
        print(f"no GPU available: these are CPU figures ({os.cpu_count()} cores), not the issue's H100 targets",
              flush=True)
    sizes = args.n or ([16_384, 65_536, 1 << 20, 1 << 24] if args.all else [16_384, 65_536])
    steps = args.steps or (1000 if backend == "gpu" else 100)
    for n in sizes:
        for dtype in (jnp.float64, jnp.float32):
            bench_n(n, dtype, steps, args.calls, args.repeats, cpu=not args.no_cpu)
    if not args.no_accuracy:
        float32_error()


if __name__ == "__main__":
    main()
