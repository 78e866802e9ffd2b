"""Acceptance check and timing of the calibration: synth -> fit -> compare, over water contents and seeds.

For each Table I water content and each seed, makes the dataset that
``mudforce synth`` makes (the paper's protocol after a 5 mm approach;
10, 20 and 40 mm/s x 3 repeats; force noise 0.2 N, depth noise 0.03 mm,
sensor bias 0.5 N), fits it with :func:`mudforce.estimation.calibration.fit_condition`
(default budget), and reports:

* per parameter: the relative error, and the error in standard errors
  (``z``, on the logarithm, where the fit works and where the standard
  error of a poorly determined parameter is meaningful); a parameter
  passes when within 5% or within 3 standard errors, or when the fit flags
  it as not determined (no standard error);
* the RMSE against the force noise (the noise floor);
* ``identify`` on every trial: the error in percentage points;
* the wall time of each condition's fit.

Usage::

    python benchmarks/bench_fit.py [--seeds 3] [--water-contents 15%,20%,25%,30%,35%] [--noise 0.2N]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from mudforce.estimation.calibration import fit_condition, identify_water_content, prepare_trial, synthesize
from mudforce.io.units import parse_list, parse_quantity
from mudforce.model.parameters import MudParameters


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--water-contents", default="15%,20%,25%,30%,35%")
    parser.add_argument("--noise", default="0.2N")
    parser.add_argument("--no-identify", action="store_true")
    args = parser.parse_args()
    waters = parse_list(args.water_contents, "fraction")
    noise = parse_quantity(args.noise, "force")
    # compile the kernels once, outside the timing
    warm = synthesize(water_contents=[0.25], velocities=[0.04], repeats=1, seed=0)
    fit_condition(warm.trials, warm.foot)
    worst_rel: dict[str, float] = {}
    worst_z: dict[str, float] = {}
    failures: list[str] = []
    times: list[float] = []
    cpu: list[float] = []
    ratios: list[float] = []
    id_errors: list[float] = []
    for w in waters:
        truth = MudParameters.from_water_content(w).to_dict()
        for seed in range(args.seeds):
            ds = synthesize(water_contents=[w], velocities=[0.01, 0.02, 0.04], repeats=3, seed=seed,
                            force_noise=noise, depth_noise=3e-5, bias=0.5)
            prepared = [prepare_trial(t) for t in ds.trials]
            t0, c0 = time.perf_counter(), time.process_time()
            fit = fit_condition(ds.trials, ds.foot, seed=seed)
            elapsed = time.perf_counter() - t0
            times.append(elapsed)
            cpu.append(time.process_time() - c0)
            ratios.append(fit.rmse / noise)
            cells = []
            for n in fit.free:
                rel = fit.parameters[n] / truth[n] - 1.0
                se = fit.stderr[n]
                # in log space, where the fit works: se / value is the standard error of log(value)
                z = math.log(fit.parameters[n] / truth[n]) / (se / fit.parameters[n]) if se else math.nan
                ok = abs(rel) <= 0.05 or (se is not None and abs(z) <= 3.0) or se is None
                if se is not None:
                    worst_z[n] = max(worst_z.get(n, 0.0), abs(z))
                if se is not None or abs(rel) < 1:
                    worst_rel[n] = max(worst_rel.get(n, 0.0), abs(rel))
                cells.append(f"{n}={rel:+.1%}" + ("" if se else "(undet.)") + ("" if ok else " FAIL"))
                if not ok:
                    failures.append(f"W={w:.0%} seed={seed} {n}: {rel:+.2%}, z={z:+.1f}")
            print(f"W={w:.0%} seed={seed}: {elapsed:5.2f} s (CPU {cpu[-1]:.2f} s), "
                  f"RMSE {fit.rmse:.3f} N (noise {noise:g} N); " + ", ".join(cells))
            for warning in fit.warnings:
                print(f"    warning: {warning}")
            if not args.no_identify:
                for tr in prepared:
                    id_errors.append(identify_water_content(tr, ds.foot).water_content - w)
    print()
    print("worst |relative error| per parameter: " + ", ".join(f"{n} {v:.2%}" for n, v in worst_rel.items()))
    print("worst |z| per parameter (where determined): " + ", ".join(f"{n} {v:.2f}" for n, v in worst_z.items()))
    print(f"RMSE / noise: mean {np.mean(ratios):.3f}, max {np.max(ratios):.3f}")
    if id_errors:
        err = np.abs(np.array(id_errors)) * 100
        print(f"identify: {len(id_errors)} trials, |error| mean {err.mean():.3f} pp, max {err.max():.3f} pp")
    print(f"fit time per condition (9 trials): wall mean {np.mean(times):.2f} s, max {np.max(times):.2f} s; "
          f"CPU mean {np.mean(cpu):.2f} s, max {np.max(cpu):.2f} s")
    print("failures: " + ("none" if not failures else "; ".join(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
