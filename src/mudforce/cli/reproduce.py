"""Regenerate the paper's figures and tables as a report: report.html, summary.json and PNG figures in DIR.

The paper's measurements are not public, so the report works from the model
and from synthetic experiments (as `mudforce synth` makes them: the paper's
protocol at five water contents and several speeds, three repeats, force and
depth noise, sensor bias, and trial-to-trial scatter of the mud). It fits
the model back to them per water content (Table I as fitted, beside the
paper's) and per speed, fits the granular baselines (granular RFT, dynamic
RFT, Maxwell-only) to the same data, and draws the paper's Figs. 2, 6, 7, 8,
9, 10 and 11, the critical withdrawal velocity for necking, and the
baselines' errors. Each figure is captioned with the paper's figure it
corresponds to. The output is byte-for-byte the same for the same seed.
--quick makes fewer trials (two speeds, two repeats, 50 Hz) and fits with a
smaller budget: about 10 s instead of 20-30 s on two cores.

DIR is replaced whole when the report is complete (it must be new, empty or
an earlier report's), so an interrupted run leaves the old report or the new
one; the worker processes end with the command, even when it is killed.
"""

from __future__ import annotations

import argparse
import os

from mudforce.cli import plain_int
from mudforce.errors import InputError, shown

NAME = "reproduce"
HELP = "regenerate the paper's figures and tables (with granular baselines) as an HTML report"

__all__ = ["HELP", "NAME", "add_arguments", "run"]


def _default_jobs() -> int:
    try:
        n = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        n = os.cpu_count() or 1
    return max(1, min(n, 2))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``mudforce reproduce``."""
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="folder for report.html, summary.json, PNGs: new, empty or an earlier report's "
                             "(replaced whole when the report is complete)")
    parser.add_argument("--quick", action="store_true", help="fewer trials and a smaller fit budget (about 10 s)")
    parser.add_argument("--seed", default="0", metavar="N",
                        help="seed of the synthetic data and the fits, an integer >= 0 (default 0)")
    parser.add_argument("--jobs", default=None, metavar="N",
                        help="worker processes for the fits (default: up to 2 CPUs); does not change the output")
    parser.add_argument("--quiet", action="store_true", help="no progress, no summary")


def _integer(text: str, option: str, low: int, high: int) -> int:
    try:
        value = plain_int(text)  # not int(): it took "1_0" as 10
    except (TypeError, ValueError):
        raise InputError(f"{option}: {text!r} is not an integer; expected an integer in [{low}, {high}]") from None
    except argparse.ArgumentTypeError as exc:  # past 4,300 digits: its size, not its digits
        raise InputError(f"{option}: {exc}; expected an integer in [{low}, {high}]") from None
    if not low <= value <= high:
        raise InputError(f"{option}: {shown(value)} is out of range; expected an integer in [{low}, {high}]")
    return value


def run(args: argparse.Namespace) -> int:
    """Validate the options, run :func:`mudforce.reproduce.reproduce`, print where the report went."""
    from mudforce._plumbing.optional import require
    from mudforce.reproduce import MAX_SEED, check_output_dir
    from mudforce.reproduce.jobs import MAX_JOBS

    seed = _integer(args.seed, "--seed", 0, MAX_SEED)
    jobs = _default_jobs() if args.jobs is None else _integer(args.jobs, "--jobs", 1, MAX_JOBS)
    require("matplotlib", "plot", "mudforce reproduce")
    check_output_dir(args.out)

    from mudforce.reproduce import ReproduceConfig, reproduce

    config = ReproduceConfig.quick_config(seed) if args.quick else ReproduceConfig.full(seed)
    result = reproduce(args.out, config, jobs=jobs, quiet=args.quiet)
    if not args.quiet:
        base = result.summary["baselines"]
        rmse = ", ".join(f"{name} {entry['rmse_N']:.3g} N" for name, entry in base.items())
        print(f"RMSE on the same mud data: {rmse}")
        print(f"wrote {os.path.join(args.out, 'report.html')}, summary.json and {len(result.figures)} figures")
    return 0
