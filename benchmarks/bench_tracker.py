"""Benchmark the online tracker: cost per update, and (``--acceptance``) convergence and coverage over many walks.

Run: ``python benchmarks/bench_tracker.py`` (cost) or
``python benchmarks/bench_tracker.py --acceptance --seeds 100`` (issue 12's
acceptance figures). Prints figures; asserts nothing.

Targets (issue 12, point 4): ``MudTracker.update`` <= 20 us per call from
Python for one foot; the estimate converges within a few steps, re-converges
within a few steps after a change of mud, and its 95 % interval holds the
truth >= 90 % of the time on stationary terrain after convergence.

Acceptance walks (:func:`mudforce.motions.gait.walk`): for each seed, water contents
drawn from 15-35 %, force noise from 0.1-0.5 N, depth noise 0.03 mm, a
force offset from -2 to 2 N, 100 Hz.

* stationary: one mud for 40 s. Converged: the first sample after which the
  median stays within 1 point of the truth. Coverage: share of samples
  with the truth inside the 95 % interval, counted from the convergence, and
  (stricter, not depending on the estimate) from the end of the 3rd step.
* change: 20 % then 30 % (``--pairs 18-28``: issue 23's 18 % then 28 %;
  ``--pairs random``: two draws at least 5 points apart), the mud changing at
  the first swing after 20 s, 50 s in all. Re-converged: as converged, from
  the change. Flag: the first change flag after the change, and the flags
  raised elsewhere (false alarms). Followed (issue 23, point 5): every sample
  from 3 s after the change on within 1.5 points of the new mud, and covered.

Steps are counted as touchdowns (swing apexes) from the start, or from the
change, to the convergence.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from mudforce.estimation.tracker import MudTracker, MudTrackers, TrackResult, track
from mudforce.motions.gait import gait, walk

TOLERANCE = 0.01  # [-] converged: median within 1 point of the truth from then on (--tolerance)


def timings(fn, repeats: int) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    """Best and median CPU time of the repeats [s]."""
    times = []
    for _ in range(repeats):
        c0 = time.process_time()
        fn()
        times.append(time.process_time() - c0)
    return min(times), float(np.median(times))


def cost(calls: int, feet: int) -> None:
    w = walk(0.25, seed=0, duration=max(2.0, calls / 100.0 + 1.0), force_noise=0.3, bias=0.5)
    z = w.depth[:calls].tolist()
    f = w.force[:calls].tolist()
    tracker = MudTracker()
    tracker.update(z[0], f[0], 0.01)

    def one() -> None:
        update = tracker.update
        for k in range(calls):
            update(z[k], f[k], 0.01)

    best, med = timings(one, 5)
    models = tracker.grid.size * len(tracker._bank.depth_offsets)
    print(f"MudTracker.update (one foot, {models} models): {best / calls * 1e6:.2f} us/update "
          f"(median {med / calls * 1e6:.2f})")
    # the models scored per sample of contact (the others are spared: tracker.py's _SPARE_MASS), untimed
    bank = tracker._bank
    bank.reset()
    scored = []
    for k in range(calls):
        contact = bank._aux[0, 4]  # _A_CONTACT: grows on the samples the likelihood is updated
        tracker.update(z[k], f[k], 0.01)
        if bank._aux[0, 4] != contact:
            scored.append(bank._scored.sum())
    print(f"  models scored per sample of contact: mean {np.mean(scored):.0f} of {models} "
          f"(median {np.median(scored):.0f}, max {np.max(scored):.0f})")

    many = MudTrackers(feet)
    zz = np.tile(np.asarray(w.depth[:calls])[:, None], (1, feet))
    ff = np.tile(np.asarray(w.force[:calls])[:, None], (1, feet))
    many.update(zz[0], ff[0], 0.01)
    rows = min(calls, 2000)

    def vec() -> None:
        for k in range(rows):
            many.update(zz[k], ff[k], 0.01)

    best, med = timings(vec, 3)
    print(f"MudTrackers.update ({feet} feet x {many.grid.size * len(many.depth_offsets)} models): "
          f"{best / rows * 1e6:.1f} us/update, "
          f"{best / rows / feet * 1e6:.2f} us per foot (median {med / rows / feet * 1e6:.2f})")


def settle(result: TrackResult, truth: np.ndarray, start: int) -> int | None:
    """First sample >= start after which the median stays within TOLERANCE of the truth (None: never)."""
    bad = np.flatnonzero(np.abs(result.water_content[start:] - truth[start:]) > TOLERANCE)
    if bad.size == 0:
        return start
    k = start + int(bad[-1]) + 1
    return k if k < truth.size else None


def touchdowns(swings: tuple[float, ...], t0: float, t1: float) -> int:
    return sum(1 for s in swings if t0 <= s < t1)


def covered(result: TrackResult, truth: np.ndarray) -> np.ndarray:
    return (result.low <= truth + 1e-12) & (truth <= result.high + 1e-12)


def acceptance(seeds: int, pairs: str, options: dict[str, float], verbose: bool) -> None:
    conv_steps: list[int] = []
    conv_time: list[float] = []
    never = 0
    cov_after_conv: list[float] = []
    cov_after_3: list[float] = []
    widths: list[float] = []
    false_stationary = 0
    noise_ratio: list[float] = []
    bias_error: list[float] = []
    for seed in range(seeds):
        rng = np.random.default_rng([seed, 12])
        w_true = float(rng.uniform(0.15, 0.35))
        sigma = float(rng.uniform(0.1, 0.5))
        bias = float(rng.uniform(-2.0, 2.0))
        wk = walk(w_true, seed=seed, duration=40.0, force_noise=sigma, depth_noise=3e-5, bias=bias)
        r = track(wk.time, wk.depth, wk.force, **options)
        path = gait(seed, duration=40.0)
        k = settle(r, wk.water_content, 0)
        if k is None:
            never += 1
        else:
            conv_steps.append(touchdowns(path.swings, 0.0, float(wk.time[k])))
            conv_time.append(float(wk.time[k]))
            cov_after_conv.append(float(covered(r, wk.water_content)[k:].mean()))
        third = path.swings[3] if len(path.swings) > 3 else wk.time[-1]
        k3 = int(np.searchsorted(wk.time, third))
        cov_after_3.append(float(covered(r, wk.water_content)[k3:].mean()))
        widths.append(float(np.median((r.high - r.low)[k3:])))
        false_stationary += int(r.changed.sum())
        noise_ratio.append(float(r.noise[-1] / sigma))
        bias_error.append(float(r.bias[-1] - bias))
        if verbose:
            print(f"  stationary seed {seed}: W {w_true:.3f} sigma {sigma:.2f} N bias {bias:+.2f} N -> "
                  f"final {r.water_content[-1]:.3f} [{r.low[-1]:.3f}, {r.high[-1]:.3f}], "
                  f"converged {'never' if k is None else f'{wk.time[k]:.1f} s'}, "
                  f"coverage after step 3 {cov_after_3[-1]:.3f}", flush=True)

    re_steps: list[int] = []
    re_time: list[float] = []
    re_never = 0
    flagged = 0
    flag_delay: list[float] = []
    false_change = 0
    cov_new: list[float] = []
    within3 = covered3 = 0
    for seed in range(seeds):
        rng = np.random.default_rng([seed, 13])
        if pairs == "random":
            while True:
                a, b = rng.uniform(0.15, 0.35, 2)
                if abs(a - b) >= 0.05:
                    break
            contents = (float(a), float(b))
        else:
            contents = (0.18, 0.28) if pairs == "18-28" else (0.20, 0.30)
        sigma = float(rng.uniform(0.1, 0.5))
        bias = float(rng.uniform(-2.0, 2.0))
        wk = walk(contents, change_times=[20.0], seed=seed, duration=50.0, force_noise=sigma,
                  depth_noise=3e-5, bias=bias)
        r = track(wk.time, wk.depth, wk.force, **options)
        path = gait(seed, duration=50.0)
        tc = wk.changes[0]
        kc = int(np.searchsorted(wk.time, tc))
        k = settle(r, wk.water_content, kc)
        if k is None:
            re_never += 1
        else:
            re_steps.append(touchdowns(path.swings, tc, float(wk.time[k])))
            re_time.append(float(wk.time[k] - tc))
            cov_new.append(float(covered(r, wk.water_content)[k:].mean()))
        later = wk.time >= tc + 3.0
        within3 += int(np.all(np.abs(r.water_content[later] - contents[1]) <= 0.015))
        covered3 += int(np.all(covered(r, wk.water_content)[later]))
        flags = wk.time[r.changed]
        after = flags[flags >= tc]
        if after.size:
            flagged += 1
            flag_delay.append(float(after[0] - tc))
        false_change += int(flags.size - min(after.size, 1))
        if verbose:
            print(f"  change seed {seed}: {contents[0]:.3f} -> {contents[1]:.3f} at {tc:.1f} s: re-converged "
                  f"{'never' if k is None else f'{wk.time[k] - tc:.1f} s later'}, flags at "
                  f"{', '.join(f'{x:.1f}' for x in flags) or 'none'}", flush=True)

    def q(values: list[float] | list[int]) -> str:
        if not values:
            return "n/a"
        a = np.asarray(values, dtype=float)
        return f"median {np.median(a):.3g}, 90th percentile {np.percentile(a, 90):.3g}, max {a.max():.3g}"

    print()
    print(f"stationary, {seeds} seeds (W 15-35 %, force noise 0.1-0.5 N, depth noise 0.03 mm, offset -2..2 N):")
    print(f"  converged (median within {100 * TOLERANCE:g} point(s) for good): {seeds - never}/{seeds}")
    print(f"  convergence [steps]: {q(conv_steps)}")
    print(f"  convergence [s]: {q(conv_time)}")
    print(f"  95 % interval coverage after convergence: mean {np.mean(cov_after_conv):.4f}, "
          f"runs >= 0.90: {sum(c >= 0.9 for c in cov_after_conv)}/{len(cov_after_conv)}")
    print(f"  95 % interval coverage after the 3rd step: mean {np.mean(cov_after_3):.4f}, "
          f"runs >= 0.90: {sum(c >= 0.9 for c in cov_after_3)}/{seeds}")
    print(f"  interval width after the 3rd step [points]: {q([100 * x for x in widths])}")
    print(f"  change flags raised (false alarms): {false_stationary} in {seeds * 40} s")
    print(f"  noise estimate / truth: {q(noise_ratio)}; offset error [N]: {q([abs(b) for b in bias_error])}")
    label = {"random": "random pairs", "18-28": "18 % -> 28 %"}.get(pairs, "20 % -> 30 %")
    print(f"change {label}, {seeds} seeds:")
    print(f"  re-converged: {seeds - re_never}/{seeds}")
    print(f"  re-convergence [steps]: {q(re_steps)}")
    print(f"  re-convergence [s]: {q(re_time)}")
    print(f"  coverage after re-convergence: mean {np.mean(cov_new) if cov_new else float('nan'):.3f}")
    print(f"  change flagged: {flagged}/{seeds}, delay [s]: {q(flag_delay)}; false alarms {false_change}")
    print(f"  from 3 s after the change on, every sample within 1.5 points: {within3}/{seeds}; "
          f"covered: {covered3}/{seeds}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--calls", type=int, default=20_000, help="updates timed for one foot")
    ap.add_argument("--feet", type=int, default=64, help="feet of the vectorised tracker")
    ap.add_argument("--acceptance", action="store_true", help="run the acceptance walks instead")
    ap.add_argument("--seeds", type=int, default=50)
    ap.add_argument("--pairs", choices=("20-30", "18-28", "random"), default="20-30")
    ap.add_argument("--quiet", action="store_true", help="only the summary")
    ap.add_argument("--tolerance", type=float, default=TOLERANCE,
                    help="converged: the median within this of the truth for good [-] (default 0.01)")
    for name in ("tau", "misfit", "floor", "dof", "correlation_time", "discrepancy"):  # tracker options
        ap.add_argument(f"--{name}", type=float, default=None, help=f"tracker option {name} (default: the tracker's)")
    args = ap.parse_args()
    globals()["TOLERANCE"] = args.tolerance  # read by settle() and the summary
    if args.acceptance:
        names = ("tau", "misfit", "floor", "dof", "correlation_time", "discrepancy")
        options = {name: getattr(args, name) for name in names if getattr(args, name) is not None}
        acceptance(args.seeds, args.pairs, options, not args.quiet)
    else:
        cost(args.calls, args.feet)


if __name__ == "__main__":
    main()
