"""Track the mud's water content along a recording of a foot walking on it, sample by sample, and write it as CSV.

FILE.csv has a header naming time_s (or time_ms), depth_m (or depth_mm,
positive below the surface) and force_N (the measured force, + up, offset
and all). Each sample goes through mudforce.MudTracker in turn, as a
robot's control loop would feed it: a bank of Table I models on a grid of
water contents, Bayesian updating with forgetting, the sensor offset tared
while the foot is free (see docs/tracking.md). Nothing looks ahead: the
branch rule is the tracker's own, chosen online from the depth noise it
estimates, with a twin bank on a 2-step secant whose interval the reported
one also holds (the configuration the sensor-chain bench measures).

Output columns: time_s, water_content, water_content_low,
water_content_high (the estimate and its 95 % interval, fractions: 0.25 is
25 %), force_predicted_N (the force the model predicts for the sample,
offset included), force_N (as measured), changed (1 where a change of mud
was flagged), misfit (1 where the model misses the data: the mud may not
be in the Table I family, or the sensor chain is off), depth_offset_m and
depth_offset_stderr_m (the surface offset the model follows the depth plus,
and its spread), force_lag_s and force_lag_stderr_s (the force sensor's lag
as a first-order low-pass, and its spread), force_bias_N (the force offset
tared), and with --family-check WINDOW family_misfit (1 from a check that
found the mud off the Table I family: identify's misfit flag on the last
WINDOW of samples, every --family-every, as mudforce.estimation.family_check
runs it online). A force-gain error cannot be told from stiffer mud:
--force-gain-uncertainty (default 5%) widens the interval by what it does.
Everything is checked before anything is written; the
outputs are replaced together (the CSV and the plot: both or neither) and
never overwrite the input.

example: mudforce track walk.csv --out track.csv --plot track.png
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mudforce.cli import nuisance_text, refuse_empty_inputs
from mudforce.cli._outputs import check_suffix
from mudforce.errors import InputError
from mudforce.io import check_output_path, refuse_overwriting_inputs
from mudforce.model.foot import FOOT_EXAMPLES, parse_foot

if TYPE_CHECKING:
    from mudforce.estimation.tracker import TrackResult

__all__ = ["COLUMNS", "HELP", "NAME", "add_arguments", "run"]

NAME = "track"
HELP = "track the mud's water content online along a recording (time, depth, force), write CSV (and a plot)"

#: The output columns, in order (:attr:`mudforce.estimation.tracker.TrackResult.COLUMNS`; written out here so that
#: building the command line does not import the tracker).
COLUMNS = ("time_s", "water_content", "water_content_low", "water_content_high", "force_predicted_N", "force_N",
           "changed", "misfit", "depth_offset_m", "depth_offset_stderr_m", "force_lag_s", "force_lag_stderr_s",
           "force_bias_N")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Declare the options of ``mudforce track``."""
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("file", metavar="FILE.csv",
                        help="recording: CSV with time_s, depth_m (or depth_mm) and force_N")
    parser.add_argument("--foot", metavar="SPEC", default=None,
                        help=f"foot geometry: {FOOT_EXAMPLES} (default: the paper's cuboid:51mmx38mm)")
    parser.add_argument("--out", metavar="FILE.csv", required=True, help="write the estimates here (CSV)")
    parser.add_argument("--plot", metavar="FILE.png", default=None,
                        help="also draw force (measured, predicted) and the water content with its band (PNG)")
    parser.add_argument("--force-gain-uncertainty", default="5%",
                        help="relative uncertainty of the force sensor's gain (default 5%%, as identify's): a gain "
                             "error reads as stiffer or softer mud, so the interval spans what each gain would read")
    parser.add_argument("--family-check", metavar="WINDOW", default=None,
                        help="also test the mud's family online: identify's misfit flag on the samples of the last "
                             "WINDOW (e.g. 10s) every --family-every; adds the column family_misfit (costs "
                             "identify's time per check)")
    parser.add_argument("--family-every", metavar="TIME", default="2.5s",
                        help="how often the family check runs, in the recording's time (default 2.5s)")
    parser.add_argument("--quiet", action="store_true", help="print nothing on success")


def run(args: argparse.Namespace) -> int:
    """Check all inputs, track, then write the CSV (and PNG) atomically; print a summary."""
    refuse_empty_inputs(("FILE.csv", args.file, "a CSV file"))
    source = Path(args.file)
    out = check_output_path(args.out, "--out")
    plot = check_output_path(args.plot, "--plot", suffix=".png") if args.plot is not None else None
    refuse_overwriting_inputs([("--out", out), ("--plot", plot)], [("file", source)])
    check_suffix(out, "--out", "CSV", ".csv", "--plot FILE.png writes a plot")
    if plot is not None:
        from mudforce._plumbing.optional import require

        require("matplotlib", "plot", "--plot")
    foot = parse_foot(args.foot) if args.foot is not None else None
    from mudforce.cli.identify import _force_gain_uncertainty

    gain = _force_gain_uncertainty(args.force_gain_uncertainty)  # identify's and fit's reading
    from mudforce.io.units import parse_quantity

    window = None if args.family_check is None else parse_quantity(args.family_check, "time", name="--family-check",
                                                                   example="10s")
    every = parse_quantity(args.family_every, "time", name="--family-every", example="2.5s")

    from mudforce.io.tables import COLUMN_UNITS, check_time, read_columns

    matched: dict[str, str] = {}
    cols = read_columns(source, {q: COLUMN_UNITS[q] for q in ("time", "depth", "force")}, matched=matched)
    time, depth, force = cols["time"], cols["depth"], cols["force"]
    check_time(source, time, matched["time"], lines=cols["line"])
    if time.size < 2:
        raise InputError(f"{source}: has {time.size} data row; expected at least 2 samples to track")

    from mudforce.estimation.tracker import track

    # the tracker's own branch rule, as a robot's loop runs it: the file's depth noise read from the whole file
    # (as `simulate` does) gave a rule that the sensor-chain bench never measures, and with no twin bank
    # (docs/estimation-history.md, "`mudforce track` runs the tracker's own branch rule")
    result = track(time, depth, force, foot, force_gain_uncertainty=gain, family_window=window, family_every=every,
                   quiet=args.quiet)
    png: bytes | None = None
    if plot is not None:
        from mudforce.estimation.tracking_plots import plot_track
        from mudforce.io.plotting import figure_to_png

        png = figure_to_png(plot_track(result, title=f"Tracking {source.name}"))
    text = result._csv_text()

    from mudforce.io import atomic_write_text, write_outputs

    # the CSV through atomic_open also when it is the only output (write_outputs writes that one in place)
    write_outputs("mudforce-track", {out: lambda path: atomic_write_text(path, text),
                                     plot: None if png is None else (lambda path: path.write_bytes(png))})
    if not args.quiet:
        k = time.size - 1
        flags = time[result.changed]
        lines = [
            f"tracked {time.size} samples of {source} ({time[-1] - time[0]:.4g} s)",
            f"final water content: {100 * result.water_content[k]:.3g} % "
            f"(95 % interval {100 * result.low[k]:.3g}-{100 * result.high[k]:.3g} %)",
            f"force offset {result.bias[k]:.3g} N, noise {result.noise[k]:.3g} N (estimated while the foot was free)",
            *_nuisance_line(result, k),
            "branch rule: the tracker's own, online (from the depth noise it estimates; a twin bank on a 2-step "
            "secant widens the interval)",
            "change of mud flagged at: " + (", ".join(f"{x:.4g} s" for x in flags[:10]) or "none")
            + (f" and {flags.size - 10} more" if flags.size > 10 else ""),
        ]
        lines += [line for line in (_misfit_line(result), _family_line(result, window, every), _edge_line(result))
                  if line]
        lines.append(f"wrote {time.size} rows to {out}")
        if plot is not None:
            lines.append(f"wrote plot to {plot}")
        print("\n".join(lines))
    return 0


def _nuisance_line(result: TrackResult, k: int) -> list[str]:
    """The summary's line on the surface offset and the force lag at sample ``k`` (none where not estimated)."""
    if result.depth_offset is None or result.depth_offset_stderr is None or result.force_lag is None \
            or result.force_lag_stderr is None:
        return []
    return [nuisance_text(float(result.depth_offset[k]), float(result.depth_offset_stderr[k]),
                          float(result.force_lag[k]), float(result.force_lag_stderr[k]), "track")]


def _misfit_line(result: TrackResult) -> str:
    """The summary's line on the misfit flag over the whole recording (:attr:`TrackResult.model_misses_data`): the
    final estimate alone hid a flag raised on much of the recording and cleared by its end (a force of noise alone
    read 34.1 % [27.5, 35.2] without a word)."""
    if result.misfit is None:
        return ""
    flagged, time = result.misfit, result.time
    if not flagged.any():  # the tracker's own flag (the family check's has its own line)
        return "model misses the data (misfit): never flagged"
    last = float(time[np.flatnonzero(flagged)[-1]])
    now = " (flagged at the end)" if flagged[-1] else ""
    return (f"model misses the data (misfit): flagged on {100 * flagged.mean():.3g} % of the samples, last at "
            f"{last:.4g} s{now}: the mud may not be in the model's family, or the recording not what it seems")


def _family_line(result: TrackResult, window: float | None, every: float) -> str:
    """The summary's line on the family check (none where it did not run)."""
    if window is None or result.family_misfit is None:
        return ""
    checks = result.family_checks
    told = [(k, v) for k, v in checks if v.model_misses_data is not None]
    off = [k for k, v in told if v.model_misses_data]
    head = (f"family check (identify's misfit flag on the last {window:g} s, every {every:g} s): {len(checks)} "
            f"check{'' if len(checks) == 1 else 's'}, {len(checks) - len(told)} told nothing")
    if not off:
        return head + ", none found the mud off the family"
    return (head + f", {len(off)} found the mud off the family (first at {float(result.time[off[0]]):.4g} s"
            + (", and at the end)" if result.family_misfit[-1] else ")")
            + ": the mud may not be in the model's family, or the recording not what it seems")


def _edge_line(result: TrackResult) -> str:
    """A line when the final interval reaches the tracker's grid's end (15 % or 35 %; :attr:`TrackResult.family_edge`):
    the mud may lie beyond the family, and the estimate then means only 'at least as dry/wet as the family holds'."""
    edge, (dry, wet) = result.family_edge, result.water_content_range
    lines = []
    if edge in ("wet", "both"):
        lines.append(f"the interval reaches the family's wet end ({100 * wet:.3g} %): the mud may be wetter")
    if edge in ("dry", "both"):
        lines.append(f"the interval reaches the family's dry end ({100 * dry:.3g} %): the mud may be drier")
    return "\n".join(lines)
