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
"bias_method": "tared", "bias_stderr_N": ..., "depth_offset_m": ...,
"force_lag_s": ..., "gain_shift": ..., "force_gain": ..., "discretisation_N": ..., "warnings": [...]}.
On a trial of any motion the surface offset of the depth and a force lag
are fitted with the water content, and the force's gain is read where the
recording determines it ("force_gain": a sensor's gain, or a mud uniformly
stiffer or softer than Table I's); --force-gain-uncertainty
(default 5%) widens the interval by the shift a further gain error causes.
A robot that knows its depth noise (the surface estimate's) gives it with
--depth-noise (e.g. 0.03mm); by default it is estimated from the depth.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path

from mudforce.cli import nuisance_text, refuse_empty_inputs
from mudforce.io import dumps_json
from mudforce.model.foot import FOOT_EXAMPLES, Foot

__all__ = ["HELP", "NAME", "add_arguments", "run"]

NAME = "identify"
HELP = "estimate the water content of one trial (Table I family, with an interval)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``mudforce identify``."""
    parser.add_argument("trial", metavar="TRIAL.csv", help="columns time_s, depth_m (or depth_mm), force_N")
    parser.add_argument("--foot", default=None, help=f"{FOOT_EXAMPLES} (default paper)")
    parser.add_argument("--level", default="95%", help="confidence level of the interval (default 95%%)")
    parser.add_argument("--force-gain-uncertainty", default="5%",
                        help="relative uncertainty of the force sensor's gain (default 5%%): a gain error reads "
                             "as stiffer or softer mud, so the interval is widened by the shift it causes (about "
                             "the gain read from the recording where it determines one; 0%% reads none)")
    parser.add_argument("--depth-noise", default=None, metavar="LENGTH",
                        help="the depth's noise when the robot knows it, e.g. 0.03mm (default: estimated from the "
                             "depth, which at 50-100 Hz reads a foot's ringing between the samples as noise)")
    parser.add_argument("--json", action="store_true", help="print JSON")


def _force_gain_uncertainty(value: str) -> float:
    """``--force-gain-uncertainty`` (identify's and fit's) as a fraction [-] in [0, 0.5), or a one-line error."""
    from mudforce.errors import InputError
    from mudforce.io.units import parse_quantity

    text = str(value).strip()
    # 0 without its unit too (no other value is unambiguous without one); 0.0% and 0 % are 0%
    gain = 0.0 if text == "0" else parse_quantity(text, "fraction", name="--force-gain-uncertainty", allow_zero=True,
                                                     example="5%")
    if not 0.0 <= gain < 0.5:
        raise InputError(f"--force-gain-uncertainty: {value!r} must be in [0%, 50%), e.g. 5%")
    return gain


def run(args: argparse.Namespace) -> int:
    """Read the trial, identify, print."""
    from mudforce.errors import InputError
    from mudforce.estimation.calibration.dataset import load_trial, parse_foot
    from mudforce.estimation.calibration.identify import identify_water_content
    from mudforce.estimation.calibration.preprocess import MAX_DEPTH_NOISE_M
    from mudforce.io.units import parse_quantity

    refuse_empty_inputs(("TRIAL.csv", args.trial, "a CSV file"))
    asked = parse_quantity(args.level, "fraction", name="--level", example="95%")  # > 0: at least 1e-7 %
    level = round(asked, 9)
    if not level < 1.0:  # "between 0% and 100%" read as if 99.99999999999% were outside that range
        if not asked < 1.0:
            raise InputError(f"--level: {args.level!r} must be below 100%, e.g. 95%")
        raise InputError(f"--level: {args.level!r} rounds to 100% (a level is read to 1e-7 %); expected at most "
                         "99.9999999%, e.g. 95%")
    gain = _force_gain_uncertainty(args.force_gain_uncertainty)
    foot = parse_foot(args.foot if args.foot is not None else "paper")
    depth_noise = None if args.depth_noise is None else parse_quantity(args.depth_noise, "length", allow_zero=True,
                                                                        name="--depth-noise")
    if depth_noise is not None and depth_noise > MAX_DEPTH_NOISE_M:  # (prepare_trial's message named the CSV file)
        raise InputError(f"--depth-noise: {args.depth_noise!r} is beyond {MAX_DEPTH_NOISE_M * 1e3:g} mm (beyond it "
                         f"the depth tells nothing); expected 0mm to {MAX_DEPTH_NOISE_M * 1e3:g}mm, e.g. 0.03mm")
    result = identify_water_content(load_trial(args.trial), foot, level=level, force_gain_uncertainty=gain,
                                    depth_noise=depth_noise)
    listed = _manifest_foot(args.trial)
    if listed is not None and (abs(listed.area - foot.area) > 1e-9 * foot.area
                               or abs(listed.width - foot.width) > 1e-9 * foot.width):
        given = f"--foot {args.foot}" if args.foot is not None else "the paper's foot (no --foot given)"
        note = (f"the dataset's manifest names the foot {listed.shape} (S = {listed.area:.4g} m^2), but "
                f"{given} was assumed (S = {foot.area:.4g} m^2): pass the trial's own foot with --foot")
        result = dataclasses.replace(result, warnings=(*result.warnings, note))
    if args.json:
        print(dumps_json(result.to_dict(), indent=2))
    else:
        lo, hi = result.interval
        ls = result.least_squares_water_content
        fit = f" (the least-squares fit, at {ls:.2%})" if math.isfinite(ls) and ls != result.water_content else ""
        print(f"water content {result.water_content:.2%} ({100 * level:.10g}% interval {lo:.2%} to {hi:.2%}), "
              f"RMSE {result.rmse:.3g} N{fit}")
        if math.isfinite(result.depth_offset):  # a motion's recording: the sensor nuisances fitted with it
            nuisances = nuisance_text(result.depth_offset, result.depth_offset_stderr, result.force_lag,
                                      result.force_lag_stderr, "identify")
            print(f"sensor nuisances fitted with it: {nuisances}, force bias {result.bias:+.2f} +- "
                  f"{result.bias_stderr:.2f} N")
        if result.force_gain != 1.0:
            print(f"force gain read from the recording: {result.force_gain:.4g} (the measured force over the mud's: "
                  "a sensor's gain, or a mud uniformly stiffer or softer than Table I's at this water content)")
        for w in result.warnings:
            print(f"warning: {w}")
    return 0


def _manifest_foot(trial: str) -> Foot | None:
    """The foot that a dataset.json beside ``trial`` names for it, if one lists it (else None)."""
    from mudforce.errors import InputError
    from mudforce.estimation.calibration.dataset import MANIFEST_NAME, foot_from_json
    from mudforce.io import load_json

    path = Path(trial)
    manifest = path.parent / MANIFEST_NAME
    if not manifest.is_file():
        return None
    try:
        data = load_json(manifest, "manifest")
        listed = {entry.get("file") for entry in data.get("trials", ()) if isinstance(entry, dict)}
        if path.name not in listed:
            return None
        return foot_from_json(data.get("foot"), str(manifest))
    except (InputError, AttributeError, TypeError):
        return None  # not a manifest this trial can be matched with: nothing to compare
