"""Write a synthetic intrusion dataset from the model: the paper's protocol, with sensor noise and bias.

Each trial approaches from 5 mm above the surface, intrudes to the depth,
holds, and withdraws at the same speed (Section II-A of Chen, Yi & Shan
2024), with parameters from Table I (interpolated between its rows). The
folder gets a dataset.json and one CSV per trial (time_s, depth_m,
force_N), the format `mudforce fit` reads; the true parameters are kept
under "synthetic" in dataset.json.

DIR is replaced whole when the dataset is complete, so an interrupted run
leaves the old folder or the new one. It must be new, empty, or an earlier
`mudforce synth` dataset (a dataset.json with a "synthetic" entry and only
the CSV files it lists), which --force replaces; a folder holding anything
else (your own files, a measured dataset) is refused, never overwritten.

Every option is bounded by what `fit` and `identify` read back: force
noise at most 1000 N, bias within +-10000 N, the depths (with 7 standard
deviations of depth noise) within +-100 m, trials of at least 20 samples
and at most 1e9 s; no file is written that they cannot read.

A robot's sensor chain (mudforce.motions.sensor_chain), each seeded by --seed:
--depth-offset (a surface estimate off by so much), --drift (the surface
estimate drifting), --force-lag (a force low-pass and/or delay) and
--force-gain. With any of them the model is simulated along the true path
at 2 kHz and the chain samples it at --rate; they are recorded under
"synthetic" -> "sensor_chain" in dataset.json.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from mudforce.cli import plain_float, plain_int, refuse_not_finite
from mudforce.errors import InputError, seed_int, shown
from mudforce.io.units import parse_list, parse_quantity
from mudforce.model.foot import FOOT_EXAMPLES

if TYPE_CHECKING:
    from mudforce.motions.sensor_chain import SensorChain

__all__ = ["DEPTH_NOISE_SIGMAS", "HELP", "MAX_BIAS", "MAX_FORCE_NOISE", "MAX_SAMPLES", "MAX_TRIALS", "NAME",
           "add_arguments", "run"]

#: Most trials one ``mudforce synth`` writes [-].
MAX_TRIALS = 1000
#: Most samples one ``mudforce synth`` writes, all trials together [-] (~30 MB a million).
MAX_SAMPLES = 5_000_000
#: Largest white force noise, standard deviation [N] (as :func:`mudforce.motions.gait.walk` takes).
MAX_FORCE_NOISE = 1e3
#: Largest force-sensor offset, either sign [N] (as :func:`mudforce.motions.gait.walk` takes).
MAX_BIAS = 1e4
#: Standard deviations of depth noise [-] that must stay, added to the motion's depths, within the
#: readers' +-100 m (``mudforce.io.tables.COLUMN_LIMITS["depth"]``): a sample beyond 7 is a 1e-12 event.
DEPTH_NOISE_SIGMAS = 7
#: Final height of the protocol's withdrawal above the surface [m]
#: (:func:`mudforce.estimation.calibration.synthesize`'s rise).
_RISE = 0.02
#: The protocol's options (``--motion protocol`` only) and their defaults.
_PROTOCOL_DEFAULTS = {"--velocities": "10mm/s,20mm/s,40mm/s", "--depth": "20mm", "--hold": "6s", "--approach": "5mm"}
#: The hidden folders beside DIR while it is written: ``.DIR.mudforce-synth-new-XXXXXXXX``.
_TAG = "mudforce-synth"

NAME = "synth"
HELP = "write a synthetic dataset (paper's protocol or robot-like gaits, noise, bias) for testing fits"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``mudforce synth``."""
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="folder to write: new, empty or an earlier synth dataset (replaced whole when done)")
    parser.add_argument("--motion", choices=("protocol", "gait"), default="protocol",
                        help="the paper's intrude/hold/withdraw protocol (default), or robot-like walks: "
                             "touchdowns, stances with sway, re-pushes, lift-offs (--repeats walks per water content)")
    parser.add_argument("--duration", default=None, help="gait: length of each walk (default 25s)")
    parser.add_argument("--jitter", type=plain_float, default=None, metavar="FRACTION",
                        help="gait: time-stamp jitter, fraction of a sample period (default 0)")
    parser.add_argument("--start-below", choices=("never", "always", "alternate"), default=None,
                        help="gait: which walks start in the mud (default never)")
    parser.add_argument("--water-content", default="25%", metavar="LIST", help="e.g. 15%%,25%% (default 25%%)")
    parser.add_argument("--velocities", default=None, metavar="LIST",
                        help="protocol: intrusion/withdrawal speeds (default 10mm/s,20mm/s,40mm/s)")
    parser.add_argument("--repeats", type=plain_int, default=3, metavar="N", help="trials per condition (default 3)")
    parser.add_argument("--force-noise", default="0.2N", metavar="F",
                        help=f"white force noise, std, at most {MAX_FORCE_NOISE:g}N (default 0.2N)")
    parser.add_argument("--depth-noise", default="0.03mm", metavar="Z", help="white depth noise, std (default 0.03mm)")
    parser.add_argument("--bias", default="0.5N", metavar="F",
                        help=f"force-sensor offset, within +-{MAX_BIAS:g}N, e.g. -0.5N (default 0.5N)")
    parser.add_argument("--depth", default=None, help="protocol: hold depth (default 20mm)")
    parser.add_argument("--hold", default=None, help="protocol: hold time (default 6s)")
    parser.add_argument("--approach", default=None, help="protocol: start height above the surface (default 5mm)")
    parser.add_argument("--rate", default="100Hz", help="sampling rate (default 100Hz)")
    parser.add_argument("--depth-offset", default=None, metavar="Z",
                        help="sensor chain: error of the surface estimate, within +-100mm; a positive offset reads "
                             "every depth deeper, e.g. 2mm or -2mm (default none)")
    parser.add_argument("--drift", default=None, metavar="Z[/T]",
                        help="sensor chain: the surface estimate drifts by Z every T (default T 30s), plus a smooth "
                             "wander of at most |Z|/4, e.g. 2mm, -2mm or 2mm/60s (default none)")
    parser.add_argument("--force-lag", default=None, metavar="SPEC",
                        help="sensor chain: a first-order force low-pass and/or a pure delay, each at most 1s: "
                             "10ms (a low-pass of 10 ms), delay:5ms, lowpass:10ms,delay:10ms (default none)")
    parser.add_argument("--force-gain", default=None, metavar="G",
                        help="sensor chain: force-sensor gain within [0.5, 2], as a factor or a change, "
                             "e.g. 1.05, +5%% or -5%% (default none)")
    parser.add_argument("--foot", default="paper", help=f"{FOOT_EXAMPLES} (default paper)")
    parser.add_argument("--seed", type=plain_int, default=0, help="noise seed (default 0)")
    parser.add_argument("--force", action="store_true", help="replace an earlier synth dataset in DIR")
    parser.add_argument("--quiet", action="store_true", help="print nothing on success")


def _foreign(folder: Path) -> list[str]:
    """The entries of ``folder`` that an earlier ``mudforce synth`` did not write, sorted.

    An earlier synth dataset is a ``dataset.json`` (read strictly) with a
    ``"synthetic"`` entry, and the plain CSV files its trials list; atomic
    writers' leftovers (``.mf-*.tmp``) are its own too. Anything else (a
    link, a folder, a file it does not list, a measured dataset's manifest)
    is the user's.
    """
    from mudforce.estimation.calibration.dataset import MANIFEST_NAME
    from mudforce.io import load_json

    listed: set[str] = set()
    manifest = folder / MANIFEST_NAME
    if manifest.is_file() and not manifest.is_symlink():
        try:
            data = load_json(manifest, "manifest")
        except InputError:
            data = None
        if isinstance(data, dict) and isinstance(data.get("synthetic"), dict) and isinstance(data.get("trials"), list):
            listed = {MANIFEST_NAME} | {e["file"] for e in data["trials"]
                                        if isinstance(e, dict) and isinstance(e.get("file"), str)}
    ours = [p.name for p in folder.iterdir()
            if not p.is_symlink() and p.is_file()
            and (p.name in listed or (p.name.startswith(".mf-") and p.name.endswith(".tmp")))]
    return sorted({p.name for p in folder.iterdir()} - set(ours))


def _parse_drift(text: str) -> tuple[float, float]:
    """``--drift Z[/T]``: the drift [m] and the time it builds up over [s] (30 s by default)."""
    value, slash, over = str(text).partition("/")
    if slash and not over.strip():
        raise InputError(f"--drift: {text!r} has no time after /; expected e.g. 2mm (over 30 s) or 2mm/60s")
    drift = parse_quantity(value, "length", name="--drift", allow_negative=True, allow_zero=True)
    time = parse_quantity(over, "time", name="--drift (the time after /)") if slash else 30.0
    return drift, time


def _parse_lag(text: str) -> tuple[float, float]:
    """``--force-lag SPEC``: (delay [s], low-pass time constant [s])."""
    delay = lowpass = 0.0
    seen: set[str] = set()
    for item in str(text).split(","):
        kind, colon, value = item.strip().rpartition(":")
        kind = kind.strip().lower() if colon else "lowpass"
        if kind not in ("lowpass", "delay") or kind in seen:
            raise InputError(f"--force-lag: cannot read {item.strip()!r} in {text!r}; expected e.g. 10ms (a low-pass), "
                             "delay:5ms, or lowpass:10ms,delay:10ms (each kind once)")
        seen.add(kind)
        name = f"--force-lag {kind}"
        try:
            seconds = parse_quantity(value.strip(), "time", name=name, allow_zero=True)
        except InputError as exc:  # why, in the parser's words ("'-5ms' must not be negative"): not "cannot read"
            why = getattr(exc, "why", str(exc))
            raise InputError(f"--force-lag: {item.strip()!r} in {text!r} is no {kind} time ({why}); expected e.g. "
                             "10ms (a low-pass), delay:5ms, or lowpass:10ms,delay:10ms") from None
        if kind == "delay":
            delay = seconds
        else:
            lowpass = seconds
    return delay, lowpass


def _parse_gain(text: str) -> float:
    """``--force-gain G``: a factor (1.05) or a change in percent (+5%, -5%)."""
    raw = str(text).strip()
    try:  # plain ASCII decimals (float() took "1_0%" as +10 %); NaN and inf are refused below, in the gain's words
        number = plain_float(raw[:-1] if raw.endswith("%") else raw)
    except ValueError:
        raise InputError(f"--force-gain: cannot read {raw!r}; expected a factor or a change, e.g. 1.05, +5% "
                         "or -5%") from None
    refuse_not_finite(number, raw, "--force-gain", "a factor or a change, e.g. 1.05, +5% or -5%",
                      literal=raw.removesuffix("%"))
    gain = 1.0 + number / 100.0 if raw.endswith("%") else number
    if not (math.isfinite(gain) and 0.5 <= gain <= 2.0):
        raise InputError(f"--force-gain: {raw!r} is a gain of {gain:g}, outside [0.5, 2]; expected e.g. 1.05, +5% "
                         "or -5%")
    return gain


def _parse_chain(args: argparse.Namespace) -> SensorChain | None:
    """The sensor chain of the options (None when none is given); each value bounded, naming its option."""
    from mudforce.motions.sensor_chain import LIMITS, SensorChain

    if all(getattr(args, k) is None for k in ("depth_offset", "drift", "force_lag", "force_gain")):
        return None
    fields: dict[str, float] = {}
    if args.depth_offset is not None:
        fields["depth_offset"] = parse_quantity(args.depth_offset, "length", name="--depth-offset",
                                                allow_negative=True, allow_zero=True)
    if args.drift is not None:
        fields["drift"], fields["drift_time"] = _parse_drift(args.drift)
    if args.force_lag is not None:
        fields["force_delay"], fields["force_lowpass"] = _parse_lag(args.force_lag)
    if args.force_gain is not None:
        fields["force_gain"] = _parse_gain(args.force_gain)
    option = {"depth_offset": "--depth-offset", "drift": "--drift", "drift_time": "--drift (the time after /)",
              "force_delay": "--force-lag delay", "force_lowpass": "--force-lag lowpass", "force_gain": "--force-gain"}
    for name, value in fields.items():
        lo, hi, unit = LIMITS[name]
        if not lo <= value <= hi:
            raise InputError(f"{option[name]}: {value:g} {unit} is outside [{lo:g}, {hi:g}] {unit}")
    return SensorChain(**fields)


def _check_bounds(args: argparse.Namespace, velocities: list[float], *, depth: float,
                  hold: float, approach: float, rate: float, force_noise: float, depth_noise: float,
                  bias: float, chain: SensorChain | None = None, duration: float = 0.0) -> None:
    """Refuse options whose dataset ``fit`` and ``identify`` would not read, each naming its bound."""
    from mudforce.cli.params import parse_water_content
    from mudforce.estimation.calibration.dataset import MIN_SAMPLES
    from mudforce.io.tables import COLUMN_LIMITS
    from mudforce.steppers.simulation import MAX_DT

    for item in str(args.water_content).split(","):
        if item.strip():
            parse_water_content(item.strip())  # within Table I's 15% to 35%, naming --water-content
    if force_noise > MAX_FORCE_NOISE:
        raise InputError(f"--force-noise: {args.force_noise!r} is more than {MAX_FORCE_NOISE:g} N; "
                         "expected e.g. 0.2N")
    if abs(bias) > MAX_BIAS:
        raise InputError(f"--bias: {args.bias!r} is beyond +-{MAX_BIAS:g} N; expected e.g. 0.5N or -0.5N")
    limit = COLUMN_LIMITS["depth"]
    reach = 0.0 if args.motion == "gait" else max(depth, approach + _RISE)
    if chain is not None:  # the surface estimate's error: the offset, and the drift over the longest trial
        longest = duration if args.motion == "gait" else max(
            (approach + depth) / v + hold + (depth + _RISE) / v for v in velocities)
        moved = abs(chain.depth_offset) + abs(chain.drift) * (longest / chain.drift_time + 0.25)
        if reach + moved + DEPTH_NOISE_SIGMAS * depth_noise > limit:
            raise InputError(f"--depth-offset and --drift: depths would reach {reach + moved:.7g} m over a trial of "
                             f"{longest:.6g} s, past the +-{limit:g} m that fit and identify read; lower --drift "
                             "or shorten the trials")
        if args.jitter:
            raise InputError("--jitter cannot go with --depth-offset, --drift, --force-lag or --force-gain (the sensor "
                             "chain samples on a regular clock); expected --jitter 0")
        if rate > 1e5:
            raise InputError(f"--rate: {args.rate!r} is above the sensor chain's 100 kHz; expected e.g. 100Hz")
    if reach + DEPTH_NOISE_SIGMAS * depth_noise > limit:
        most = (limit - reach) / DEPTH_NOISE_SIGMAS
        gait = args.motion == "gait"
        motion = "" if gait else f"--depth {args.depth} or --approach {args.approach} with "
        made = f"{DEPTH_NOISE_SIGMAS} standard deviations" if gait else \
            f"the motion's {reach:g} m plus {DEPTH_NOISE_SIGMAS} standard deviations"
        room = f"at most {most:.4g} m of noise here" if most > 0 else "no room left for noise"
        raise InputError(f"{motion}--depth-noise {args.depth_noise}: depths would reach "
                         f"{reach + DEPTH_NOISE_SIGMAS * depth_noise:.7g} m ({made}), past the +-{limit:g} m that "
                         f"fit and identify read ({room})")
    if args.motion == "gait":
        return  # mudforce.motions.gait.walk bounds its own duration (1 s to 1 h) and rate (10 Hz to 100 kHz)
    if rate < 1.0 / MAX_DT:
        raise InputError(f"--rate: {args.rate!r} is below {1.0 / MAX_DT:g} Hz (the model's longest time step is "
                         f"{MAX_DT:g} s); expected e.g. 100Hz")
    from mudforce.motions.protocol import Protocol

    for v in velocities:
        try:
            duration = Protocol.paper(depth=depth, velocity=v, hold=hold, rise=_RISE, rate=rate,
                                      approach=approach).duration
        except InputError as exc:  # the protocol's own bounds (simulate()'s): name the options that set them
            raise InputError(f"--depth, --hold, --velocities, --rate: a trial at {v * 1e3:g} mm/s: {exc}") from None
        if duration > COLUMN_LIMITS["time"]:
            raise InputError(f"a trial at {v * 1e3:g} mm/s would last {duration:.12g} s, beyond the "
                             f"{COLUMN_LIMITS['time']:g} s that fit and identify read; lower --hold or raise "
                             "--velocities")
        samples = math.ceil(duration * rate - 1e-9) + 1
        if samples < MIN_SAMPLES:
            raise InputError(f"--rate {args.rate}: a trial at {v * 1e3:g} mm/s would have {samples} samples, fewer "
                             f"than the {MIN_SAMPLES} that fit and identify read; raise --rate or --hold")


def run(args: argparse.Namespace) -> int:
    """Make the dataset and print where it went."""
    from mudforce.estimation.calibration.dataset import MANIFEST_NAME, parse_foot, save_dataset
    from mudforce.estimation.calibration.synth import synthesize
    from mudforce.io import StagedOutputs, check_replaceable_dir

    gait = args.motion == "gait"
    # refused, not ignored (a gait walk with --hold 100s wrote the same dataset as without): a walk draws its own
    # touchdown speeds, depths and stances
    for option, default in _PROTOCOL_DEFAULTS.items():
        value = getattr(args, option[2:])
        if gait and value is not None:
            raise InputError(f"{option} applies to --motion protocol only; a gait draws its own touchdown speeds, "
                             "depths and stances (--duration, --jitter and --start-below shape it)")
        setattr(args, option[2:], default if value is None else value)
    waters = parse_list(args.water_content, "fraction", name="--water-content")
    velocities = parse_list(args.velocities, "velocity", name="--velocities")
    for option, values in (("--water-content", waters), ("--velocities", velocities)):
        if len(set(values)) != len(values):
            raise InputError(f"{option}: a value is repeated; give each once (each makes its own trials)")
    seed = seed_int(args.seed)
    if args.repeats < 1 or args.repeats > MAX_TRIALS:
        raise InputError(f"--repeats: {shown(args.repeats)} must be within [1, {MAX_TRIALS}]")
    if not gait:  # refused, not ignored: the protocol's trials are timed by --depth, --hold and --velocities
        for option, value in (("--duration", args.duration), ("--jitter", args.jitter),
                              ("--start-below", args.start_below)):
            if value is not None:
                raise InputError(f"{option} applies to --motion gait only; the protocol's trials are timed by "
                                 "--depth, --hold and --velocities")
    args.duration = "25s" if args.duration is None else args.duration
    args.jitter = 0.0 if args.jitter is None else args.jitter
    refuse_not_finite(args.jitter, args.jitter, "--jitter", "a fraction of a sample period within [0, 0.4]",
                      literal="")  # an infinity (1e400 too) is out of the range below
    if not 0.0 <= args.jitter <= 0.4:  # (gait's bound, in the option's words: 1e400 was 'jitter ... got inf')
        raise InputError(f"--jitter: {shown(args.jitter)} must be within [0, 0.4] (a fraction of a sample period)")
    args.start_below = "never" if args.start_below is None else args.start_below
    duration = parse_quantity(args.duration, "time", name="--duration") if gait else 0.0
    trials = len(waters) * (1 if gait else len(velocities)) * args.repeats
    if trials > MAX_TRIALS:
        raise InputError(f"{trials} trials requested; at most {MAX_TRIALS} per command (fewer repeats, "
                         "water contents or velocities)")
    depth = parse_quantity(args.depth, "length", name="--depth")
    hold = parse_quantity(args.hold, "time", name="--hold")
    approach = parse_quantity(args.approach, "length", name="--approach")
    rate = parse_quantity(args.rate, "frequency", name="--rate")
    from mudforce.steppers.simulation import MAX_DEPTH

    for option, value in (("--depth", depth), ("--approach", approach)):
        if value > MAX_DEPTH:
            raise InputError(f"{option}: {value:g} m is beyond the model's {MAX_DEPTH:g} m")
    # the protocol's duration per speed: approach and intrude, hold, withdraw to 20 mm above
    samples = args.repeats * len(waters) * sum(
        ((approach + depth) / v + hold + (depth + 0.02) / v) * rate + 1 for v in velocities)
    if gait:  # one walk of --duration per repeat and water content
        samples = args.repeats * len(waters) * (duration * rate + 1)
    if samples > MAX_SAMPLES:  # a gait's options: --hold and --depth are the protocol's, refused with a gait
        shorter = "--duration" if gait else "--hold, --depth"
        raise InputError(f"the dataset would have {samples:.3g} samples, more than {MAX_SAMPLES:,} per command; "
                         f"lower --rate, {shorter} or the number of trials")
    foot = parse_foot(args.foot)
    force_noise = parse_quantity(args.force_noise, "force", name="--force-noise", allow_zero=True)
    depth_noise = parse_quantity(args.depth_noise, "length", name="--depth-noise", allow_zero=True)
    bias = parse_quantity(args.bias, "force", name="--bias", allow_zero=True, allow_negative=True)
    chain = _parse_chain(args)
    _check_bounds(args, velocities, depth=depth, hold=hold, approach=approach, rate=rate,
                  force_noise=force_noise, depth_noise=depth_noise, bias=bias, chain=chain, duration=duration)
    out = Path(args.out)
    path = check_replaceable_dir(args.out, "--out", (), _TAG, foreign=_foreign, what="synth dataset")
    if (path / MANIFEST_NAME).exists() and not args.force:
        raise InputError(f"--out {out}: already holds a mudforce synth dataset; pass --force to replace it")
    if gait:
        from mudforce.estimation.calibration.synth import synthesize_gait

        dataset = synthesize_gait(None, water_contents=waters, repeats=args.repeats, duration=duration, rate=rate,
                                  jitter=args.jitter, start_below=args.start_below, force_noise=force_noise,
                                  depth_noise=depth_noise, bias=bias, seed=seed, foot=foot, chain=chain)
    else:
        dataset = synthesize(None, water_contents=waters, velocities=velocities, repeats=args.repeats,
                             force_noise=force_noise, depth_noise=depth_noise, bias=bias, seed=seed, foot=foot,
                             depth=depth, hold=hold, approach=approach, rise=_RISE, rate=rate, chain=chain)
    # built aside and swapped in whole: an interrupt leaves the old folder or the new one, never a mix
    with StagedOutputs(_TAG, folders=[path]) as staged:
        save_dataset(dataset, staged.staged_path(path))  # refuses, before writing, a trial the readers would refuse
        staged.commit()
    if not args.quiet:
        print(f"wrote {len(dataset.trials)} {'walks' if gait else 'trials'} to {out / MANIFEST_NAME}")
    return 0
