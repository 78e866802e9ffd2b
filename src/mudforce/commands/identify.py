"""Estimate the water content of one trial of any motion from the Table I family, with an interval.

TRIAL.csv has the columns time_s, depth_m (or depth_mm), force_N of one
trial: the lab protocol or any foot motion (steps, stances with sway,
re-pushes; starting above or below the surface). The trial is prepared as
for a fit (branch of every step from the depth and the force's jumps,
force tared or its bias estimated; docs/estimation.md) and compared with
the model for Table I's parameters, interpolated between its rows (15% to
35%). The interval is a likelihood-ratio interval that widens when the
family misfits the trial. With --json: {"water_content": 0.23,
"nearest_water_content": 0.23, "interval": [0.21, 0.25], "rmse_N": ...,
"level": 0.95, "force_noise_N": ..., "noise_floor_N": ..., "misfit_ratio":
..., "model_misses_data": false, "off_family_N": ..., "bias_N": ...,
"bias_method": "tared", "bias_stderr_N": ..., "warnings": [...]}.
"""

from __future__ import annotations

import argparse
import json

from mudforce.foot import FOOT_EXAMPLES

NAME = "identify"
HELP = "estimate the water content of one trial (Table I family, with an interval)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``mudforce identify``."""
    parser.add_argument("trial", metavar="TRIAL.csv", help="columns time_s, depth_m (or depth_mm), force_N")
    parser.add_argument("--foot", default="paper", help=f"{FOOT_EXAMPLES} (default paper)")
    parser.add_argument("--level", default="95%", help="confidence level of the interval (default 95%%)")
    parser.add_argument("--json", action="store_true", help="print JSON")


def run(args: argparse.Namespace) -> int:
    """Read the trial, identify, print."""
    from mudforce.calibration.dataset import load_trial, parse_foot
    from mudforce.calibration.identify import identify_water_content
    from mudforce.errors import InputError
    from mudforce.units import parse_quantity

    level = round(parse_quantity(args.level, "fraction", name="--level"), 9)
    if not 0.0 < level < 1.0:
        raise InputError(f"--level: {args.level!r} must be between 0% and 100%, e.g. 95%")
    result = identify_water_content(load_trial(args.trial), parse_foot(args.foot), level=level)
    if args.json:
        print(json.dumps(result.to_dict(), indent=2))
    else:
        lo, hi = result.interval
        print(f"water content {result.water_content:.2%} ({level:.0%} interval {lo:.2%} to {hi:.2%}), "
              f"RMSE {result.rmse:.3g} N")
        for w in result.warnings:
            print(f"warning: {w}")
    return 0
