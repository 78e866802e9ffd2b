"""Benchmark the core model: batch ns per sample and streaming us per call.

Run: ``python benchmarks/bench_core.py``. Prints figures; asserts nothing.
Targets (issue 2): batch <= 15 ns/sample on one core for a 2-million-sample
gait; ``MudContact.step`` <= 2 us per call from Python.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import mudforce as mf


def gait(n: int, rate: float = 1000.0) -> tuple[np.ndarray, np.ndarray]:
    """A foot stepping at 1.5 Hz: in the mud ~40 % of the time, 25 mm deep at most [s], [m]."""
    t = np.arange(n) / rate
    z = 0.03 * np.sin(2 * np.pi * 1.5 * t) - 0.005
    return t, z


def best_of(fn, repeats: int) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """Best wall time and best CPU time of this process [s] (CPU time is robust to a busy machine)."""
    wall = cpu = float("inf")
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall = min(wall, time.perf_counter() - w0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--samples", type=int, default=2_000_000)
    ap.add_argument("--calls", type=int, default=200_000)
    args = ap.parse_args()
    params = mf.MudParameters.from_water_content(0.25)
    t, z = gait(args.samples)
    mf.simulate(t[:1000], z[:1000], params, velocity_filter="exact")  # compile / load cache
    res = mf.simulate(t, z, params, velocity_filter="exact")
    states = np.bincount(res.state, minlength=3) / res.state.size
    necks = res.necking_times.size

    from mudforce import _kernel as K
    from mudforce.simulation import params_row

    prow = params_row(params, mf.Foot.paper(), mf.VelocityFilter.exact())[None, :]
    out = K.new_out(t.size)
    ring = K.new_ring(1, 1)

    def kernel_only() -> None:
        K.run_batch(t, z, K.new_states(1), ring, prow, out)

    def whole() -> None:
        mf.simulate(t, z, params, velocity_filter="exact")

    n = args.samples
    kw, kc = best_of(kernel_only, 5)
    ww, wc = best_of(whole, 3)
    print(f"batch gait: {n:,} samples at 1 kHz "
          f"(FREE {states[0]:.0%}, CONTACT {states[1]:.0%}, NECKED {states[2]:.0%}, {necks} neckings)")
    print(f"  compiled stepper loop : {kw / n * 1e9:6.2f} ns/sample wall, {kc / n * 1e9:6.2f} ns/sample CPU")
    print(f"  mudforce.simulate()   : {ww / n * 1e9:6.2f} ns/sample wall, {wc / n * 1e9:6.2f} ns/sample CPU "
          "(incl. validation, noise estimate, result arrays)")

    contact = mf.MudContact(params)
    depths = z[: args.calls].tolist()
    contact.step(depths[0], 0.0)
    step = contact.step

    def stream() -> None:
        for d in depths:
            step(d, 0.001)

    sw, sc = best_of(stream, 3)
    print(f"streaming MudContact.step: {sw / args.calls * 1e6:6.3f} us/call wall, "
          f"{sc / args.calls * 1e6:6.3f} us/call CPU "
          f"({args.calls:,} calls from Python)")


if __name__ == "__main__":
    main()
