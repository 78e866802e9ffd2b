"""Write a synthetic intrusion dataset from the model: the paper's protocol, with sensor noise and bias.

Each trial approaches from 5 mm above the surface, intrudes to the depth,
holds, and withdraws at the same speed (Section II-A of Chen, Yi & Shan
2024), with parameters from Table I (interpolated between its rows). The
folder gets a dataset.json and one CSV per trial (time_s, depth_m,
force_N), the format `mudforce fit` reads; the true parameters are kept
under "synthetic" in dataset.json.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from mudforce.errors import InputError, seed_int
from mudforce.foot import FOOT_EXAMPLES
from mudforce.io import check_output_dir
from mudforce.units import parse_list, parse_quantity

__all__ = ["HELP", "MAX_SAMPLES", "MAX_TRIALS", "NAME", "add_arguments", "run"]

#: Most trials one ``mudforce synth`` writes [-].
MAX_TRIALS = 1000
#: Most samples one ``mudforce synth`` writes, all trials together [-] (~30 MB a million).
MAX_SAMPLES = 5_000_000

NAME = "synth"
HELP = "write a synthetic dataset (paper's protocol or robot-like gaits, noise, bias) for testing fits"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``mudforce synth``."""
    parser.add_argument("--out", required=True, metavar="DIR", help="folder to write (created)")
    parser.add_argument("--motion", choices=("protocol", "gait"), default="protocol",
                        help="the paper's intrude/hold/withdraw protocol (default), or robot-like walks: "
                             "touchdowns, stances with sway, re-pushes, lift-offs (--repeats walks per water content)")
    parser.add_argument("--duration", default="25s", help="gait: length of each walk (default 25s)")
    parser.add_argument("--jitter", type=float, default=0.0, metavar="FRACTION",
                        help="gait: time-stamp jitter, fraction of a sample period (default 0)")
    parser.add_argument("--start-below", choices=("never", "always", "alternate"), default="never",
                        help="gait: which walks start in the mud (default never)")
    parser.add_argument("--water-content", default="25%", metavar="LIST", help="e.g. 15%%,25%% (default 25%%)")
    parser.add_argument("--velocities", default="10mm/s,20mm/s,40mm/s", metavar="LIST",
                        help="intrusion/withdrawal speeds (default 10mm/s,20mm/s,40mm/s)")
    parser.add_argument("--repeats", type=int, default=3, metavar="N", help="trials per condition (default 3)")
    parser.add_argument("--force-noise", default="0.2N", metavar="F", help="white force noise, std (default 0.2N)")
    parser.add_argument("--depth-noise", default="0.03mm", metavar="Z", help="white depth noise, std (default 0.03mm)")
    parser.add_argument("--bias", default="0.5N", metavar="F", help="force-sensor offset (default 0.5N)")
    parser.add_argument("--depth", default="20mm", help="hold depth (default 20mm)")
    parser.add_argument("--hold", default="6s", help="hold time (default 6s)")
    parser.add_argument("--approach", default="5mm", help="start height above the surface (default 5mm)")
    parser.add_argument("--rate", default="100Hz", help="sampling rate (default 100Hz)")
    parser.add_argument("--foot", default="paper", help=f"{FOOT_EXAMPLES} (default paper)")
    parser.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    parser.add_argument("--force", action="store_true", help="overwrite an existing dataset in DIR")
    parser.add_argument("--quiet", action="store_true", help="print nothing on success")


def run(args: argparse.Namespace) -> int:
    """Make the dataset and print where it went."""
    from mudforce.calibration.dataset import MANIFEST_NAME, parse_foot
    from mudforce.calibration.synth import synthesize

    waters = parse_list(args.water_content, "fraction", name="--water-content")
    velocities = parse_list(args.velocities, "velocity", name="--velocities")
    for option, values in (("--water-content", waters), ("--velocities", velocities)):
        if len(set(values)) != len(values):
            raise InputError(f"{option}: a value is repeated; give each once (each makes its own trials)")
    seed = seed_int(args.seed)
    if args.repeats < 1 or args.repeats > MAX_TRIALS:
        raise InputError(f"--repeats: {args.repeats} must be within [1, {MAX_TRIALS}]")
    gait = args.motion == "gait"
    duration = parse_quantity(args.duration, "time", name="--duration") if gait else 0.0
    trials = len(waters) * (1 if gait else len(velocities)) * args.repeats
    if trials > MAX_TRIALS:
        raise InputError(f"{trials} trials requested; at most {MAX_TRIALS} per command (fewer repeats, "
                         "water contents or velocities)")
    depth = parse_quantity(args.depth, "length", name="--depth")
    hold = parse_quantity(args.hold, "time", name="--hold")
    approach = parse_quantity(args.approach, "length", name="--approach")
    rate = parse_quantity(args.rate, "frequency", name="--rate")
    from mudforce.simulation import MAX_DEPTH

    for option, value in (("--depth", depth), ("--approach", approach)):
        if value > MAX_DEPTH:
            raise InputError(f"{option}: {value:g} m is beyond the model's {MAX_DEPTH:g} m")
    # the protocol's duration per speed: approach and intrude, hold, withdraw to 20 mm above
    samples = args.repeats * len(waters) * sum(
        ((approach + depth) / v + hold + (depth + 0.02) / v) * rate + 1 for v in velocities)
    if gait:  # one walk of --duration per repeat and water content
        samples = args.repeats * len(waters) * (duration * rate + 1)
    if samples > MAX_SAMPLES:
        raise InputError(f"the dataset would have {samples:.3g} samples, more than {MAX_SAMPLES:,} per command; "
                         "lower --rate, --hold, --depth or the number of trials")
    foot = parse_foot(args.foot)
    force_noise = parse_quantity(args.force_noise, "force", name="--force-noise", allow_zero=True)
    depth_noise = parse_quantity(args.depth_noise, "length", name="--depth-noise", allow_zero=True)
    bias = parse_quantity(args.bias, "force", name="--bias", allow_zero=True, allow_negative=True)
    out = Path(args.out)
    if (out / MANIFEST_NAME).exists() and not args.force:
        raise InputError(f"--out {out}: already holds a {MANIFEST_NAME}; pass --force to overwrite it")
    check_output_dir(args.out, "--out")
    if gait:
        from mudforce.calibration.synth import synthesize_gait

        dataset = synthesize_gait(out, water_contents=waters, repeats=args.repeats, duration=duration, rate=rate,
                                  jitter=args.jitter, start_below=args.start_below, force_noise=force_noise,
                                  depth_noise=depth_noise, bias=bias, seed=seed, foot=foot)
        if not args.quiet:
            print(f"wrote {len(dataset.trials)} walks to {out / MANIFEST_NAME}")
        return 0
    dataset = synthesize(
        out,
        water_contents=waters,
        velocities=velocities,
        repeats=args.repeats,
        force_noise=force_noise,
        depth_noise=depth_noise,
        bias=bias,
        seed=seed,
        foot=foot,
        depth=depth,
        hold=hold,
        approach=approach,
        rate=rate,
    )
    if not args.quiet:
        print(f"wrote {len(dataset.trials)} trials to {out / MANIFEST_NAME}")
    return 0
