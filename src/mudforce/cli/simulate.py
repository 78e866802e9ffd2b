"""Simulate the mud force on a foot for the paper's protocol, a depth trajectory or poses, and write it as CSV.

The motion is either the paper's experiment (intrude at --velocity to
--depth, hold for --hold, withdraw at the same speed to --rise above the
surface, sampled at --rate; defaults 20mm, 10mm/s, 6s, 20mm, 100Hz) or a
CSV file given with --trajectory (header with time_s and depth_m or
depth_mm; depth positive below the surface). The mud is a row of Table I
(--water-content, interpolated between rows) or a parameter file
(--params, the flat JSON of `mudforce params --json`, SI).

Every quantity needs its unit (20mm, 10mm/s, 6s, 100Hz, 25%). The foot is
--foot cuboid:51mmx38mm (the paper's, the default), disc:50mm, or
area:19.38cm2,width:38mm for any other flat foot (contact area S and the
width H of Eq. (4)). Everything is checked before anything is written;
the output files are replaced together (the CSV and the plot: both or
neither), so an error leaves them as they were.

Output columns: time_s, depth_m, velocity_m_s, mud_displacement_m,
mud_velocity_m_s, f_e1_Pa, f_e2_Pa, f_s_Pa, force_N (+ up), state
(FREE, CONTACT or NECKED).

Poses (3-D): a --trajectory whose header names time_s, x_m, y_m, z_m, qw,
qx, qy, qz (x_mm, y_mm, z_mm and time_ms accepted) moves a foot of any
shape in any way: the body origin's position in a world frame with z up,
and its orientation as a unit quaternion (w, x, y, z), MuJoCo's order. The
foot is --shape KIND:SIZE (as `mudforce drop --shape`: sphere:40mm,
capsule:30mmx60mm, cylinder:30mmx20mm, disc:50mmx5mm, box:50mmx40mmx20mm;
centred on the body origin, axis along body z) or, with --foot alone, the
flat sole of that foot (its centre at the body origin, facing body -z);
the mud surface is at z = --surface-height (default 0mm). The 3-D law
(mudforce.simulate_3d; docs/model.md, "Mud in 3-D") gives the columns
time_s, x_m, y_m, z_m, qw, qx, qy, qz, force_x_N, force_y_N, force_z_N,
torque_x_N_m, torque_y_N_m, torque_z_N_m: the mud's force on the foot and its
torque about the body origin, world frame, z up.

examples:
  mudforce simulate --water-content 25% --depth 20mm --velocity 10mm/s --out force.csv --plot force.png
  mudforce simulate --water-content 25% --trajectory poses.csv --shape sphere:40mm --out wrench.csv
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mudforce.cli import refuse_empty_inputs
from mudforce.cli._outputs import check_suffix
from mudforce.cli._shape import SHAPE_EXAMPLES, make_shape, parse_shape
from mudforce.errors import InputError
from mudforce.io import check_output_path, refuse_overwriting_inputs
from mudforce.io.units import format_quantity, parse_quantity
from mudforce.model.foot import FOOT_EXAMPLES, parse_foot
from mudforce.motions.protocol import MAX_SAMPLES  # the bound's home: the protocol (here checked first, to name --rate)

if TYPE_CHECKING:
    from mudforce.model.parameters import MudParameters
    from mudforce.model.shapes import Shape
    from mudforce.steppers.simulation import SimulationResult

__all__ = ["FOOT_EXAMPLES", "HELP", "MAX_SAMPLES", "NAME", "add_arguments", "check_output_path", "parse_foot", "run"]

NAME = "simulate"
HELP = "simulate the force for the paper's protocol or a trajectory CSV, write CSV (and a plot)"

#: The accepted --foot forms, for help and error messages.


#: The paper-protocol options: (attribute, option, kind, default text, zero allowed).
_PROTOCOL_OPTIONS: tuple[tuple[str, str, str, str, bool], ...] = (
    ("depth", "--depth", "length", "20mm", False),
    ("velocity", "--velocity", "velocity", "10mm/s", False),
    ("hold", "--hold", "time", "6s", False),
    ("rise", "--rise", "length", "20mm", True),
    ("rate", "--rate", "frequency", "100Hz", False),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Declare the options of ``mudforce simulate``."""
    parser.formatter_class = argparse.RawDescriptionHelpFormatter  # keep the docstring's paragraphs
    mud = parser.add_argument_group("mud (exactly one)")
    which = mud.add_mutually_exclusive_group(required=True)
    which.add_argument("--water-content", metavar="W",
                       help="water content within Table I's 15%%-35%%, e.g. 25%%; between rows "
                            "the parameters are interpolated log-linearly")
    which.add_argument("--params", metavar="FILE.json",
                       help="parameter file: a flat JSON object with the 11 keys in SI "
                            "(as `mudforce params --water-content 25%% --json` prints)")

    motion = parser.add_argument_group(
        "motion: the paper's protocol (defaults shown), or --trajectory")
    for attr, option, kind, default, _ in _PROTOCOL_OPTIONS:
        text = {
            "depth": "intrusion depth below the surface",
            "velocity": "intrusion and withdrawal speed",
            "hold": "hold time at depth",
            "rise": "final height of the foot above the surface",
            "rate": "sampling rate",
        }[attr]
        motion.add_argument(option, dest=attr, metavar=kind.upper(), default=None,
                            help=f"{text} (default {default})")
    motion.add_argument("--trajectory", metavar="FILE.csv",
                        help="prescribed motion instead: CSV with a header naming time_s and "
                             "depth_m (or depth_mm), depth positive down; or poses (3-D): time_s, x_m, y_m, z_m, "
                             "qw, qx, qy, qz (z up, quaternion (w, x, y, z)); excludes the options above")

    parser.add_argument("--foot", metavar="SPEC", default=None,
                        help=f"foot geometry: {FOOT_EXAMPLES} (default: the paper's cuboid:51mmx38mm); "
                             "with poses, its flat sole")
    parser.add_argument("--shape", metavar="KIND:SIZE", default=None,
                        help=f"with poses: the foot's surface, {SHAPE_EXAMPLES} (as mudforce drop --shape)")
    parser.add_argument("--surface-height", metavar="Z", default=None,
                        help="with poses: the height of the mud surface in the world frame, e.g. 0mm (default)")
    parser.add_argument("--velocity-filter", choices=("auto", "exact"), default=None,
                        help="how the intrusion/withdrawal branch is chosen from the depth: auto "
                             "(exact for clean input of any shape, noise-robust when white noise is found in "
                             "the depth; default; the summary says which) or exact")
    parser.add_argument("--out", metavar="FILE.csv", required=True, help="write the samples here (CSV)")
    parser.add_argument("--plot", metavar="FILE.png", default=None,
                        help="also draw force over time and depth as PNG (needs matplotlib; not with poses)")
    parser.add_argument("--quiet", action="store_true", help="print nothing on success")


# ---------------------------------------------------------------------------- checks

def _load_params(args: argparse.Namespace) -> tuple[MudParameters, str]:
    """The mud parameters and a short label for them."""
    from mudforce.cli.params import parse_water_content
    from mudforce.model.parameters import TABLE_I_WATER_CONTENTS, MudParameters

    if args.params is not None:
        return MudParameters.load(args.params), f"parameters from {args.params}"
    w = parse_water_content(args.water_content)
    on_row = any(abs(w - row) < 1e-9 for row in TABLE_I_WATER_CONTENTS)
    label = "Table I" if on_row else "Table I interpolated"
    return MudParameters.from_water_content(w), f"{label}, W = {format_quantity(w, 'fraction')}"


def _refuse_protocol_options(args: argparse.Namespace) -> None:
    """With --trajectory (depths or poses) the file sets the motion: any protocol option is refused."""
    given = [option for attr, option, *_ in _PROTOCOL_OPTIONS if getattr(args, attr) is not None]
    if given:
        raise InputError(f"{', '.join(given)} cannot be used with --trajectory (the file sets the motion); "
                         "give either the protocol options or --trajectory")


def _motion(args: argparse.Namespace) -> tuple[np.ndarray, np.ndarray, str]:
    """Sampled time [s] and depth [m], and a label for the motion."""
    if args.trajectory is not None:
        _refuse_protocol_options(args)
        from mudforce.io.tables import read_trajectory

        time, depth = read_trajectory(args.trajectory)
        _check_steps(args.trajectory, time, "sample")
        return time, depth, f"trajectory {args.trajectory}"

    from mudforce.motions.protocol import Protocol

    values: dict[str, float] = {}
    for attr, option, kind, default, zero in _PROTOCOL_OPTIONS:
        text = getattr(args, attr)
        values[attr] = parse_quantity(default if text is None else text, kind, name=option, allow_zero=zero)
    duration = 2.0 * values["depth"] / values["velocity"] + values["hold"] + values["rise"] / values["velocity"]
    samples = duration * values["rate"]
    if not math.isfinite(samples) or samples > MAX_SAMPLES:
        raise InputError(
            f"--rate: {format_quantity(values['rate'], 'frequency')} over the {duration:.4g} s protocol is "
            f"{samples:.3g} samples, more than {MAX_SAMPLES:,}; lower --rate or shorten the motion"
        )
    protocol = Protocol.paper(values["depth"], values["velocity"], values["hold"], values["rise"], values["rate"])
    time, depth = protocol.sample()
    label = (
        f"paper protocol: {format_quantity(values['depth'], 'length')} at "
        f"{format_quantity(values['velocity'], 'velocity')}, hold {format_quantity(values['hold'], 'time')}, "
        f"{format_quantity(values['rate'], 'frequency')}"
    )
    return time, depth, label


def _summary(result: SimulationResult, mud: str, motion: str, out: Path, plot: Path | None) -> str:
    from mudforce.model.velocity import describe_velocity_rule

    k_max = int(np.argmax(result.force))
    k_min = int(np.argmin(result.force))
    necks = [f"{t:.4g} s" for t in result.necking_times[:5]]
    if result.necking_times.size > 5:
        necks.append(f"and {result.necking_times.size - 5} more")
    if not necks:
        necks = [f"none (suction never exceeded sigma_y = {result.params.sigma_y:g} Pa)"]
    lines = [
        f"mud: {mud}",
        f"motion: {motion}",
        f"foot: {result.foot.shape} (S = {result.foot.area * 1e6:.6g} mm^2, H = {result.foot.width * 1e3:.6g} mm)",
        f"peak force: {result.force[k_max]:.4g} N at {result.time[k_max]:.4g} s",
        f"min force: {result.force[k_min]:.4g} N at {result.time[k_min]:.4g} s",
        f"necking: {', '.join(necks)}",
        f"branch rule: {describe_velocity_rule(result.velocity_filter, result.depth_noise)}",
        f"wrote {len(result)} rows to {out}",
    ]
    if plot is not None:
        lines.append(f"wrote plot to {plot}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------- run

def _refuse_a_pipe(trajectory: str | None) -> None:
    """Refuse a --trajectory that is a pipe (``<(...)``, ``/dev/stdin`` fed by a pipe, a named pipe): its header is
    read to tell depths from poses, then the file again from its start, which a pipe cannot give; it was reported
    as an empty file (or, a named pipe without a writer, the command waited for ever)."""
    import os
    import stat

    if trajectory is None:
        return
    try:
        mode = os.stat(trajectory).st_mode
    except (OSError, ValueError):  # not there, a NUL in the name, ...: the reader says what is wrong
        return
    if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
        raise InputError(f"--trajectory: {str(trajectory)[:80]!r} is a pipe, which can be read only once, and "
                         "--trajectory is read twice (its header, then its rows); expected a CSV file: save the "
                         "stream to one first")


def run(args: argparse.Namespace) -> int:
    """Check all inputs, simulate, then write the CSV (and PNG) atomically; print a summary."""
    refuse_empty_inputs(("--trajectory", args.trajectory, "a CSV file"),
                        ("--params", args.params, "a parameter file (JSON)"))
    _refuse_a_pipe(args.trajectory)
    out = check_output_path(args.out, "--out")
    plot = check_output_path(args.plot, "--plot", suffix=".png") if args.plot is not None else None
    refuse_overwriting_inputs([("--out", out), ("--plot", plot)],
                              [("--trajectory", args.trajectory), ("--params", args.params)])
    check_suffix(out, "--out", "CSV", ".csv", "--plot FILE.png writes a plot")
    from mudforce.io.tables import is_pose_trajectory

    if args.trajectory is not None and is_pose_trajectory(args.trajectory):
        return _run_poses(args, out, plot)
    for option, value in (("--shape", args.shape), ("--surface-height", args.surface_height)):
        if value is not None:
            if args.trajectory is not None:  # not a depth trajectory either (missing, empty, not text, other
                from mudforce.io.tables import read_poses, read_trajectory  # columns): what is wrong with it as poses

                try:
                    read_trajectory(args.trajectory)
                except InputError:
                    read_poses(args.trajectory)
            where = "a depth trajectory" if args.trajectory is not None else "the paper's protocol"
            raise InputError(f"{option} needs a pose trajectory (--trajectory with columns time_s,x_m,y_m,z_m,qw,qx,"
                             f"qy,qz), not {where}, which moves the flat --foot straight down")
    if plot is not None:
        from mudforce._plumbing.optional import require

        require("matplotlib", "plot", "--plot")
    foot = parse_foot(args.foot) if args.foot is not None else None
    params, mud = _load_params(args)
    time, depth, motion = _motion(args)

    from mudforce.steppers.simulation import simulate

    # refuses a non-finite force
    result = simulate(time, depth, params, foot, velocity_filter=args.velocity_filter or "auto")
    png: bytes | None = None
    if plot is not None:
        from mudforce.io.plotting import figure_to_png
        from mudforce.steppers.plots import plot_result

        png = figure_to_png(plot_result(result, title=f"{mud}; {motion}"))

    from mudforce.io import write_outputs

    write_outputs("mudforce-simulate", {out: lambda path: result.to_csv(path, quiet=args.quiet),
                                        plot: None if png is None else (lambda path: path.write_bytes(png))})
    if not args.quiet:
        print(_summary(result, mud, motion, out, plot))
    return 0


# ---------------------------------------------------------------------------- poses (3-D)

#: The columns ``mudforce simulate`` writes for a pose trajectory, in order.
_POSE_OUTPUT = ("time_s", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz", "force_x_N", "force_y_N", "force_z_N",
                "torque_x_N_m", "torque_y_N_m", "torque_z_N_m")


def _check_steps(path: str, time: np.ndarray, what: str) -> None:
    """Refuse, naming the file and the sample (1-based data row) by its time, a time step [s] outside
    ``[MIN_DT, MAX_DT]``, which the stepper would refuse without naming the file (``what``: "sample" or "pose")."""
    from mudforce._kernel.bounds import MAX_DT, MIN_DT

    steps = np.diff(time)
    bad = np.flatnonzero((steps < MIN_DT) | (steps > MAX_DT))
    if bad.size:
        k = int(bad[0]) + 1
        # repr: a step just outside a bound must not print as the bound
        raise InputError(f"{path}: the {what} at time {float(time[k])!r} s (sample {k + 1}) comes "
                         f"{float(steps[k - 1])!r} s after the last; expected time steps within "
                         f"[{MIN_DT:g}, {MAX_DT:g}] s")


def _check_poses(path: str, time: np.ndarray, positions: np.ndarray, shape: Shape, surface: float) -> None:
    """Refuse, naming the sample by its time, a step or a depth the 3-D stepper would refuse without saying where.

    ``time`` [s], ``positions`` [m] (m, 3), ``surface`` [m]: the time steps must lie within
    ``[MIN_DT, MAX_DT]``, and every point of the shape within ``MAX_DEPTH`` of the surface.
    """
    from mudforce._kernel.bounds import MAX_DEPTH

    _check_steps(path, time, "pose")
    reach = float(np.sqrt(np.einsum("ij,ij->i", shape.centroids, shape.centroids)).max())
    deep = np.flatnonzero(np.abs(surface - positions[:, 2]) + reach > MAX_DEPTH)
    if deep.size:
        k = int(deep[0])
        raise InputError(f"{path}: the pose at time {float(time[k])!r} s (sample {k + 1}) puts the foot more than "
                         f"{MAX_DEPTH:g} m from the mud surface (z = {float(positions[k, 2]):g} m); check the units")


def _run_poses(args: argparse.Namespace, out: Path, plot: Path | None) -> int:
    """A pose trajectory: every option checked, the 3-D law along the poses, the wrench's CSV written atomically."""
    from mudforce._kernel.bounds import MAX_DEPTH

    _refuse_protocol_options(args)
    if plot is not None:
        raise InputError("--plot is not available with a pose trajectory; plot the CSV's force_x_N, force_y_N "
                         "and force_z_N columns")
    if args.velocity_filter is not None:
        raise InputError("--velocity-filter applies to a depth trajectory; the 3-D law takes each element's "
                         "velocity from the poses")
    if args.shape is not None and args.foot is not None:
        raise InputError("give --shape or --foot with a pose trajectory, not both (--foot: its flat sole)")
    if args.shape is None and args.foot is None:
        raise InputError("a pose trajectory needs --shape (e.g. sphere:40mm) or --foot (its flat sole, "
                         "e.g. cuboid:51mmx38mm)")
    if args.shape is not None:
        shape = make_shape(*parse_shape(args.shape))
    else:
        from mudforce.model import shapes

        shape = shapes.sole(parse_foot(args.foot))
    surface = 0.0
    if args.surface_height is not None:
        surface = parse_quantity(args.surface_height, "length", name="--surface-height", allow_negative=True,
                                 allow_zero=True)
        if abs(surface) > MAX_DEPTH:
            raise InputError(f"--surface-height: {args.surface_height!r} is beyond +-{MAX_DEPTH:g} m; "
                             "expected e.g. 0mm")
    params, mud = _load_params(args)

    from mudforce.io.tables import read_poses, write_csv
    from mudforce.model.law3d import QUATERNION_TOLERANCE
    from mudforce.steppers.contact3d import HALF_TURN_W, simulate_3d

    time, positions, quaternions = read_poses(args.trajectory, quaternion_tolerance=QUATERNION_TOLERANCE)
    _check_poses(args.trajectory, time, positions, shape, surface)
    with warnings.catch_warnings():  # said below in the file's words, on one line
        warnings.filterwarnings("ignore", "simulate_3d: every quaternion has w", RuntimeWarning)
        result = simulate_3d(time, positions, quaternions, params, shape, surface_height=surface)
    if not (np.all(np.isfinite(result.force)) and np.all(np.isfinite(result.torque))):
        raise InputError(f"{args.trajectory}: the wrench is not finite along these poses; check their units")
    columns = dict(zip(_POSE_OUTPUT, [time, *positions.T, *quaternions.T, *result.force.T, *result.torque.T],
                       strict=True))
    try:
        write_csv(out, columns, quiet=args.quiet)
    except OSError as exc:
        raise InputError(f"cannot write {exc.filename or out}: {exc.strerror or exc}") from None
    if not args.quiet:
        sideways = np.hypot(result.force[:, 0], result.force[:, 1])
        k_z = int(np.argmax(np.abs(result.force[:, 2])))
        k_s = int(np.argmax(sideways))
        print("\n".join([
            f"mud: {mud}",
            f"motion: poses from {args.trajectory}, {time.size} samples over {time[-1] - time[0]:.4g} s",
            f"foot: {shape.name}; mud surface at z = {format_quantity(surface, 'length')}",
            f"peak vertical force: {result.force[k_z, 2]:.4g} N at {time[k_z]:.4g} s",
            f"peak sideways force: {sideways[k_s]:.4g} N at {time[k_s]:.4g} s",
            f"wrote {time.size} rows to {out}",
        ]))
    if np.all(np.abs(quaternions[:, 0]) <= HALF_TURN_W):  # as simulate_3d warns: (x, y, z, w) under qw,qx,qy,qz?
        first = ",".join(f"{v:.6g}" for v in quaternions[0].tolist())
        print(f"mudforce simulate: warning: {args.trajectory}: every row's qw is within +-{HALF_TURN_W:g} (the foot "
              f"turned half a turn at every sample; the first row's qw,qx,qy,qz = {first}); if those columns hold "
              "x, y, z, w (ROS's order), name them qx,qy,qz,qw", file=sys.stderr)
    return 0
