"""Fit the drag factor lambda of Eq. (5) to a sliding experiment (Fig. 5 of Chen, Yi & Shan 2024).

FILE.csv has the columns velocity_m_s (or velocity_mm_s) and force_N: the
sliding speed and the measured resistance of each sample (or of each
steady-speed run). The model is F = sign(v) lambda rho_m v^2 S, with S the
contact area (--area, or the area of --foot) and rho_m the mud density
(--rho-m, the paper's 1840 kg/m^3 by default). Prints lambda with its
standard error (linear least squares), or JSON with --json.
"""

from __future__ import annotations

import argparse
import re
import sys

from mudforce.cli import refuse_empty_inputs
from mudforce.errors import InputError
from mudforce.io import dumps_json
from mudforce.model.foot import FOOT_EXAMPLES

__all__ = ["HELP", "NAME", "add_arguments", "run"]

NAME = "fit-drag"
HELP = "fit the drag factor lambda (Eq. 5) to sliding-experiment data"

_DENSITY = re.compile(r"^\s*([+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)\s*"
                      r"(kg/m3|kg/m\^3|g/cm3|g/cm\^3)\s*$")


def _density(text: str) -> float:
    match = _DENSITY.match(text)
    if match is None:
        raise InputError(f"--rho-m: cannot read {text!r} as a density; expected e.g. 1840kg/m3 or 1.84g/cm3")
    try:
        value = float(match.group(1)) * (1.0 if match.group(2).startswith("kg") else 1e3)
    except ValueError:
        raise InputError(f"--rho-m: cannot read {text!r} as a density; expected e.g. 1840kg/m3") from None
    from mudforce.model.parameters import PARAMETER_RANGES

    lo, hi = PARAMETER_RANGES["rho_m"]
    if not lo <= value <= hi:
        raise InputError(f"--rho-m: {text!r} must be a density within [{lo:g}, {hi:g}] kg/m3, e.g. 1840kg/m3")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``mudforce fit-drag``."""
    parser.add_argument("file", metavar="FILE.csv", help="columns velocity_m_s (or velocity_mm_s), force_N")
    area = parser.add_mutually_exclusive_group()
    area.add_argument("--area", help="contact area, e.g. 19.38cm2 (default: the paper's foot)")
    area.add_argument("--foot", help=f"foot giving the area: {FOOT_EXAMPLES}")
    parser.add_argument("--rho-m", default="1840kg/m3", help="mud density (default 1840kg/m3)")
    parser.add_argument("--intercept", action="store_true", help="also fit a constant force offset")
    parser.add_argument("--json", action="store_true", help="print JSON")


def run(args: argparse.Namespace) -> int:
    """Read, fit, print."""
    from mudforce.estimation.calibration.dataset import parse_foot
    from mudforce.estimation.calibration.drag import fit_drag, read_sliding
    from mudforce.io.units import parse_quantity

    refuse_empty_inputs(("FILE.csv", args.file, "a CSV file"))
    if args.area is not None:
        from mudforce.model.foot import AREA_RANGE

        area = parse_quantity(args.area, "area", name="--area")
        lo, hi = AREA_RANGE
        if not lo <= area <= hi:  # (fit_drag's own refusal named "area", not the option)
            raise InputError(f"--area: {args.area!r} must be an area within [{lo:g}, {hi:g}] m2, e.g. 19.38cm2")
    else:
        area = parse_foot("paper" if args.foot is None else args.foot).area
    velocity, force = read_sliding(args.file)
    result = fit_drag(velocity, force, area, rho_m=_density(args.rho_m), intercept=args.intercept)
    if args.json:
        print(dumps_json(result.to_dict(), indent=2))
    else:
        line = f"lambda = {result.lambda_:.5g} ± {result.stderr:.2g} (RMSE {result.rmse:.3g} N, {result.n} samples"
        if result.intercept is not None:
            line += f", offset {result.intercept:.3g} ± {result.intercept_stderr:.2g} N"
        print(line + ")")
    for warning in result.warnings:
        print(f"mudforce fit-drag: warning: {warning}", file=sys.stderr)
    return 0
