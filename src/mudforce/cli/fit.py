"""Fit the model to an intrusion dataset: the nine parameters per water content, with standard errors.

DATASET is a folder with dataset.json and one CSV per trial (or the
dataset.json itself, or a tidy CSV with the columns trial, water_content,
time_s, depth_m, force_N); see docs/calibration.md. Trials may be of any
motion (docs/estimation.md): each step's branch comes from the depth and
the force's jumps, the force is tared from the samples before the first
contact (or its bias estimated when the trial starts in the mud), and the
force noise is measured from the force's high-frequency content; a lab
protocol trial has its corners fitted to a fraction of a sample instead.
The fit is staged: intrusion and hold
(k_m_i, b_m_i, alpha, beta); withdrawal (k_m_w, b_m_w, sigma_y, zeta,
omega_0) with a seeded global search; then all jointly. rho_m and lambda
stay fixed unless --free names them. fit.json holds, per water content,
the 11 parameters in SI, their standard errors (null where fixed or not
determined), the RMSE over all samples and per trial, the noise floor and
misfit_ratio (RMSE / floor; model_misses_data above 1.25), the parameter
correlation matrix, warnings for parameters the data cannot determine
and for a model that misses the data, and, for a recording of any motion,
rest_reading: how a foot at rest was read (the narrowest of the branch,
the rest band at the turns alone, or the rest band everywhere that reads
the data as well as the band; where a band stays its pull widens the
standard errors).

With --report DIR, the fit and its report are built aside and swapped in
together once both are complete (DIR must be new, empty or an earlier
report's: it is replaced whole), so an interrupted run leaves the old pair
or the new one; the next run removes what a killed one left beside them.
"""

from __future__ import annotations

import argparse
import math

from mudforce.cli import plain_int, refuse_empty_inputs
from mudforce.cli._outputs import check_suffix
from mudforce.cli.identify import _force_gain_uncertainty
from mudforce.errors import InputError, seed_int
from mudforce.io import (
    StagedOutputs,
    check_output_path,
    check_replaceable_dir,
    refuse_overwriting_inputs,
    write_outputs,
)
from mudforce.model.foot import FOOT_EXAMPLES

__all__ = ["HELP", "NAME", "add_arguments", "run"]

NAME = "fit"
HELP = "fit the model to an intrusion dataset (per water content, staged, with standard errors)"

#: What a report folder may hold besides its PNG figures (it is replaced whole).
_REPORT_FILES = frozenset({"report.md"})
#: The tag in the names of the staged siblings of --out and --report.
_TAG = "mudforce-fit"


def _names(text: str | None, option: str) -> list[str]:
    if text is None:
        return []
    names = [x.strip() for x in text.split(",") if x.strip()]
    if not names:
        raise InputError(f"{option}: empty list; expected parameter names such as k_m_w,b_m_w")
    return names


def _fixed(text: str | None) -> dict[str, float]:
    from mudforce.io.tables import NUMBER
    from mudforce.model.parameters import PARAMETER_RANGES

    out: dict[str, float] = {}
    for item in _names(text, "--fix"):
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or NUMBER.fullmatch(value.strip()) is None:
            raise InputError(f"--fix: cannot read {item!r}; expected NAME=VALUE with a finite number in SI, "
                             "e.g. beta=0.5")
        number = float(value)
        lo, hi = PARAMETER_RANGES.get(name, (-math.inf, math.inf))
        if not (math.isfinite(number) and lo <= number <= hi):
            raise InputError(f"--fix {name}: {value.strip()!r} is outside [{lo:g}, {hi:g}] (SI)")
        if name in out:
            raise InputError(f"--fix: {name} is given twice; give each parameter once")
        out[name] = number
    return out


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``mudforce fit``."""
    parser.add_argument("dataset", metavar="DATASET", help="dataset folder, its dataset.json, or a tidy CSV")
    parser.add_argument("--out", required=True, metavar="FIT.json", help="where to write the fit (JSON)")
    parser.add_argument("--report", metavar="DIR",
                        help="also write a markdown + PNG report there (needs matplotlib): a new or empty folder, "
                             "or an earlier report's, replaced whole with FIT.json when both are complete")
    parser.add_argument("--shared", metavar="NAMES", help="parameters shared across water contents, e.g. k_m_w,b_m_w")
    parser.add_argument("--free", metavar="NAMES", help="also fit these normally fixed parameters, e.g. lambda")
    parser.add_argument("--fix", metavar="NAME=VALUE,...", help="hold parameters at values in SI, e.g. beta=0.5")
    parser.add_argument("--model", default="chen2024", help="force model to fit (default chen2024)")
    parser.add_argument("--foot", help=f"foot of a tidy CSV: {FOOT_EXAMPLES}")
    parser.add_argument("--seed", type=plain_int, default=0, help="seed of the global search (default 0)")
    parser.add_argument("--force-gain-uncertainty", default="5%",
                        help="relative uncertainty of the force sensor's gain (default 5%%): a gain error reads as "
                             "every stiffness, viscosity, alpha and sigma_y off by as much, so their standard errors "
                             "are widened by it")
    parser.add_argument("--quiet", action="store_true", help="no progress, no summary")


def run(args: argparse.Namespace) -> int:
    """Load, fit, write fit.json (and the report), print a summary."""
    from mudforce.estimation.calibration.dataset import load_dataset, parse_foot
    from mudforce.estimation.calibration.fit import fit_by_velocity, fit_dataset, speed_key
    from mudforce.estimation.calibration.models import get_model

    refuse_empty_inputs(("DATASET", args.dataset, "a dataset folder, its dataset.json, or a tidy CSV"))
    if args.report:
        from mudforce._plumbing.optional import require

        require("matplotlib", "plot", "--report")
    # refuse unusable outputs before the fit, not after it
    out = check_output_path(args.out, "--out")
    seed = seed_int(args.seed)
    gain = _force_gain_uncertainty(args.force_gain_uncertainty)
    if args.report is not None and not args.report.strip():  # not the folder '.' the overlap checks would take it for
        raise InputError("--report: empty folder name; expected a folder for the report")  # check_replaceable_dir's
    if args.report is not None:
        refuse_overwriting_inputs([("--out", out)], [], [("--report", args.report)])
    model = get_model(args.model)
    dataset = load_dataset(args.dataset, foot=parse_foot(args.foot) if args.foot is not None else None)
    # every input the dataset was read from (a manifest's trial files too), before anything is written
    inputs = [("DATASET", args.dataset), *(("file", p) for p in dataset.inputs)]
    refuse_overwriting_inputs([("--out", out)], inputs, [("--report", args.report)])
    check_suffix(out, "--out", "JSON", ".json", "--report DIR writes a report with plots")
    report = check_replaceable_dir(args.report, "--report", _REPORT_FILES, _TAG) if args.report is not None else None
    extra = _names(args.free, "--free")
    for name in extra:
        if name not in model.parameter_names:
            raise InputError(f"--free {name}: unknown parameter; expected one of {', '.join(model.parameter_names)}")
    free = [n for n in model.parameter_names if n not in model.fixed or n in extra]
    fixed = _fixed(args.fix)
    for name in fixed:
        if name not in model.parameter_names:
            raise InputError(f"--fix {name}: unknown parameter; expected one of {', '.join(model.parameter_names)}")
        if name in extra:
            raise InputError(f"--free {name} and --fix {name}=... conflict; give one of them")
    if report is None:
        result = fit_dataset(dataset, model=model, free=free, fixed=fixed, shared=_names(args.shared, "--shared"),
                             seed=seed, quiet=args.quiet, force_gain_uncertainty=gain)
        write_outputs(_TAG, {out: result.save})  # a failure as a one-line error naming --out's file
    else:
        from mudforce.estimation.calibration.report import write_report

        # the fit and its report are built aside and swapped in together at the end: an interrupted run
        # leaves the old pair (or, once swapped, the new one), and the next run removes what a killed one left
        # before the fit, so that nothing is lost to it: a failure names the output (InputError, or an OSError)
        with StagedOutputs(_TAG, folders=[report], files=[out]) as staged:
            result = fit_dataset(dataset, model=model, free=free, fixed=fixed,
                                 shared=_names(args.shared, "--shared"), seed=seed, quiet=args.quiet,
                                 force_gain_uncertainty=gain)
            speeds = {speed_key(t.nominal_velocity, t.velocity) for c in result.conditions for t in c.trials}
            per_speed = fit_by_velocity(dataset, model=model, free=free, fixed=fixed, seed=seed,
                                        quiet=args.quiet, force_gain_uncertainty=gain) if len(speeds) > 1 else []
            result.save(staged.staged_path(out))
            write_report(result, staged.staged_path(report), velocity_fits=per_speed)
            staged.commit()
    if not args.quiet:
        for c in result.conditions:
            rest = {"band": ", a foot at rest read through its rest band",
                    "branch": ", a foot at rest read on the branch",
                    "turns": ", the turns read through the rest band"}.get(c.rest_reading, "")
            print(f"W = {c.water_content:.1%}: RMSE {c.rmse:.3f} N (force noise {c.force_noise:.3f} N, "
                  f"noise floor {c.noise_floor:.3f} N), "
                  f"{len(c.trials)} trials{rest}, {len(c.warnings)} warning(s)")
            for w in c.warnings:
                print(f"  warning: {w}")
        print(f"wrote {args.out}" + (f" and {args.report}/report.md" if args.report else ""))
    return 0
