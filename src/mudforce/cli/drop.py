"""Drop a foot into mud and simulate how it sinks, sticks and settles.

By default the paper's 51 x 38 mm cuboid foot of the given mass is released at rest
with its bottom at the mud surface (or --height above it) and falls under
gravity (9.81 m/s^2) into mud of the given water content (Table I of Chen,
Yi & Shan 2024, interpolated between rows). The mud force is the model's,
coupled with the foot's motion: the foot sinks on the intrusion branch,
and at rest it sticks while its weight lies between the withdrawal- and
intrusion-branch forces (README, "Dynamics").

Engines: "builtin" integrates the one-degree-of-freedom foot event-driven
(RK4 with event location, 0.1 ms sub-steps); "mujoco" runs MuJoCo (1 ms
steps) with the mudforce.engines.mujoco adapter (needs: pip install 'mudforce[mujoco]'); "mjx" runs
MuJoCo's JAX port MJX (1 ms steps, one jitted scan) with mudforce.engines.mjx (needs: pip install 'mudforce[mjx]').

With --shape (sphere:40mm, capsule:30mmx60mm, box:..., cylinder:..., disc:...; --engine mujoco or mjx), a free
foot of that shape goes through the 3-D law in MuJoCo (mudforce.engines.mujoco.MudAdapter3D) or MJX
(mudforce.engines.mjx3d, one jitted scan: compiling it takes seconds to a minute), 1 ms steps, optionally
tilted (--tilt) and moving sideways (--vx); its CSV columns are time_s, x_m, y_m, z_m, depth_m, vx_m_s,
vz_m_s, force_x_N, force_y_N, force_z_N, tilt_deg.

Output CSV columns: time_s, depth_m (positive down), velocity_m_s
(positive down), force_N (mud force, positive up), state (FREE, INTRUSION,
WITHDRAWAL, STUCK, NECKED), one row per millisecond. The summary line gives
the rest depth only if the foot is at rest (STUCK) at the end; otherwise
it says the foot is still moving, and how fast.

Bounds: --mass from 0.1 kg (builtin) or 1 kg (mujoco and mjx: MuJoCo's contact's
~10-20 um creep is a large part of a lighter foot's rest depth) to 10000 kg;
--height 0 to 10 m; --duration 2 ms to 600 s; --water-content within
Table I (15%-35%).

examples:
  mudforce drop --mass 5kg --water-content 25% --out drop.csv
  mudforce drop --engine mujoco --mass 10kg --water-content 20% --duration 4s --out drop.csv --plot drop.png
  mudforce drop --mass 5kg --water-content 15% --height 20mm --out drop.csv
  mudforce drop --engine mujoco --shape sphere:40mm --tilt 10 --vx 50mm/s --mass 2kg --water-content 25% --out s.csv
  mudforce drop --engine mjx --shape sphere:40mm --mass 2kg --water-content 20% --duration 0.5s --out s.csv
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from mudforce.cli import plain_float, refuse_not_finite
from mudforce.cli._outputs import check_suffix
from mudforce.cli._shape import SHAPE_EXAMPLES, parse_shape
from mudforce.errors import InputError
from mudforce.io import check_output_path
from mudforce.io.units import parse_quantity

__all__ = ["HELP", "NAME", "add_arguments", "run"]

NAME = "drop"
HELP = ("drop a foot into mud (the paper's cuboid: built-in, MuJoCo or MJX engine; a sphere, capsule, box, cylinder or "
        "disc with --shape: MuJoCo or MJX) and write its depth and force (CSV)")

_MAX_DURATION = 600.0  # [s]
_MIN_DURATION = 2e-3  # [s]: two samples
_MAX_MASS = 1e4  # [kg]
#: Lightest foot per engine [kg]: the built-in engine is accurate far below (3e-5 kg is its stability
#: limit), MuJoCo's soft friction lets a foot creep ~10-20 um, 10% of a 1 kg foot's rest depth at W = 15%;
#: MJX's limit is MuJoCo's (the same model, stepped at 1 ms)
_MIN_MASS = {"builtin": 0.1, "mujoco": 1.0, "mjx": 1.0}
_MAX_HEIGHT = 10.0  # [m]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Declare the options of ``mudforce drop``."""
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("--engine", choices=("builtin", "mujoco", "mjx"), default="builtin",
                        help="dynamics engine (default: builtin)")
    parser.add_argument("--mass", required=True, metavar="M",
                        help="foot mass with unit, e.g. 5kg: 0.1kg (builtin) or 1kg (mujoco) to 10000kg")
    parser.add_argument("--water-content", required=True, metavar="W",
                        help="mud water content within 15%%-35%%, e.g. 25%%")
    parser.add_argument("--duration", default="8s", metavar="T",
                        help="simulated time with unit, 2ms to 600s (default: 8s)")
    parser.add_argument("--height", default="0mm", metavar="H",
                        help="release height of the foot's bottom above the surface, 0 to 10m (default: 0mm)")
    parser.add_argument("--shape", default=None, metavar="KIND:SIZE",
                        help="a free foot of this shape through the 3-D law (needs --engine mujoco or mjx): "
                             f"{SHAPE_EXAMPLES} (capsule: diameter x length; a disc is a cylinder)")
    parser.add_argument("--tilt", default=None, metavar="DEG",
                        help="with --shape: the foot's rotation about x in degrees, e.g. 20 or 20deg (default: 0)")
    parser.add_argument("--vx", default=None, metavar="V",
                        help="with --shape: initial horizontal velocity along x with unit, e.g. 50mm/s (default: 0)")
    parser.add_argument("--out", required=True, metavar="FILE.csv", help="CSV file to write (atomically)")
    parser.add_argument("--plot", default=None, metavar="FILE.png", help="also save a PNG figure")


def run(args: argparse.Namespace) -> int:
    """Run ``mudforce drop``; returns the exit status."""
    from mudforce.cli.params import parse_water_content
    from mudforce.model.parameters import MudParameters

    mass = parse_quantity(args.mass, "mass", name="--mass")
    water = parse_water_content(args.water_content)  # within Table I's range, in the other commands' words
    duration = parse_quantity(args.duration, "time", name="--duration")
    height = parse_quantity(args.height, "length", name="--height", allow_zero=True)
    if duration > _MAX_DURATION:
        raise InputError(f"--duration: {args.duration!r} is longer than {_MAX_DURATION:g} s")
    if duration < _MIN_DURATION:
        raise InputError(f"--duration: {args.duration!r} is shorter than 2 ms (two samples)")
    if mass > _MAX_MASS:
        raise InputError(f"--mass: {args.mass!r} is more than {_MAX_MASS:g} kg; expected e.g. 5kg")
    lightest = _MIN_MASS[args.engine]
    if mass < lightest:
        raise InputError(f"--mass: {args.mass!r} is less than {lightest:g} kg, the lightest foot the {args.engine} "
                         f"engine simulates reliably; expected e.g. 5kg")
    if height > _MAX_HEIGHT:
        raise InputError(f"--height: {args.height!r} is more than {_MAX_HEIGHT:g} m; expected e.g. 20mm")
    params = MudParameters.from_water_content(water)
    shape3d = _shape_options(args)
    out = check_output_path(args.out, "--out")
    plot = check_output_path(args.plot, "--plot", suffix=".png") if args.plot is not None else None
    check_suffix(out, "--out", "CSV", ".csv", "--plot FILE.png writes a plot")
    if plot is not None and plot.resolve() == out.resolve():
        raise InputError("--plot and --out name the same file")
    if plot is not None and shape3d is not None:  # before matplotlib is required, which would not help
        raise InputError("--plot is not available with --shape; plot the CSV")
    if plot is not None:
        from mudforce._plumbing.optional import require

        require("matplotlib", "plot", "--plot")
    if shape3d is not None:
        return _run_3d(args, mass, params, duration, height, shape3d, out)
    if args.engine == "mujoco":
        from mudforce._plumbing.optional import require

        require("mujoco", "mujoco", "--engine mujoco")
        from mudforce.engines.mujoco import simulate_drop

        result = simulate_drop(mass, params, duration=duration, height=height)
    elif args.engine == "mjx":
        from mudforce._plumbing.optional import require

        require("jax", "mjx", "--engine mjx")  # mudforce.engines.mjx checks for mujoco.mjx itself
        from mudforce.engines.mjx import simulate_drop as simulate_drop_mjx

        result = simulate_drop_mjx(mass, params, duration=duration, height=height)
    else:
        from mudforce.engines.dynamics import simulate_foot

        result = simulate_foot(mass, params, duration=duration, height=height)
    from mudforce.io import write_outputs

    title = f"{mass:g} kg foot dropped into mud at W = {water:.0%} ({args.engine})"
    write_outputs("mudforce-drop", {out: result.to_csv, plot: lambda path: result.plot(path, title=title)})
    weight = mass * result.gravity
    if result.at_rest:
        where = f"rest depth {result.rest_depth * 1e3:.3f} mm after {duration:g} s"
    else:
        where = (f"not at rest after {duration:g} s: depth {result.end_depth * 1e3:.3f} mm, "
                 f"moving at {result.velocity[-1] * 1e3:.3f} mm/s ({result.phase_names[-1]})")
    span = "second" if duration >= 1.0 else f"{duration:g} s"
    print(f"{args.engine}: {where}; "
          f"force std over the last {span} {100.0 * result.force_std(1.0) / weight:.3f}% of m g; wrote {out}")
    return 0


def _shape_options(args: argparse.Namespace) -> tuple[str, list[float], float, float] | None:
    """``(kind, sizes [m], tilt [rad], vx [m/s])`` from --shape, --tilt, --vx; None without them."""
    import math

    if args.shape is None:
        if args.tilt is not None or args.vx is not None:
            raise InputError("--tilt and --vx need --shape (e.g. --shape sphere:40mm)")
        return None
    if args.engine not in ("mujoco", "mjx"):
        raise InputError(f"--shape needs --engine mujoco or mjx (the 3-D engines), got --engine {args.engine}")
    kind, dims = parse_shape(args.shape)  # a disc stays "disc" here, as the summary names it; _run_3d simulates it
    tilt = 0.0
    if args.tilt is not None:
        try:  # plain ASCII decimals only, as every other number the command line reads (float() took "1_0" as 10)
            tilt = plain_float(str(args.tilt).strip().removesuffix("deg"))
        except ValueError:
            raise InputError(f"--tilt: {args.tilt!r} is not an angle in degrees; expected e.g. 20 or 20deg") from None
        refuse_not_finite(tilt, args.tilt, "--tilt", "an angle within -180 to 180 degrees, e.g. 20 or 20deg")
        if abs(tilt) > 180.0:  # (1e400, read as infinite, too)
            raise InputError(f"--tilt: {args.tilt!r} is outside -180 to 180 degrees")
        # as parse_quantity reads a quantity: a literal that is not zero is not read as zero ("1e-400"), nor as a
        # denormal, whose digits are lost
        if 0.0 < abs(tilt) < sys.float_info.min or (tilt == 0.0 and re.search(
                r"[1-9]", str(args.tilt).lower().partition("e")[0]) is not None):
            raise InputError(f"--tilt: {args.tilt!r} is too small (at least {sys.float_info.min:.3g} degrees, or 0); "
                             "expected e.g. 20 or 20deg")
    vx = 0.0
    if args.vx is not None:
        vx = parse_quantity(args.vx, "velocity", name="--vx", allow_negative=True, allow_zero=True)
        if abs(vx) > 10.0:
            raise InputError(f"--vx: {args.vx!r} is faster than 10 m/s; expected e.g. 50mm/s")
    return kind, dims, math.radians(tilt), vx


def _run_3d(args: argparse.Namespace, mass: float, params: object, duration: float, height: float,
            shape3d: tuple[str, list[float], float, float], out: Path) -> int:
    """``mudforce drop --shape``: the 3-D MuJoCo adapter or MJX; CSV of the foot's pose, velocity and force."""
    import math

    from mudforce._plumbing.optional import require
    from mudforce.io import write_outputs
    from mudforce.io.results import write_text

    name, dims, tilt, vx = shape3d
    # a disc is a cylinder as high as it is thick (mudforce.model.shapes.disc); the summary names what was asked for
    kind = "cylinder" if name == "disc" else name
    if args.engine == "mjx":
        require("jax", "mjx", "--engine mjx")
        require("mujoco.mjx", "mjx", "--engine mjx")
        from mudforce.engines.mjx3d import simulate_drop

        res = simulate_drop(mass, params, kind, dims, duration=duration, height=height, tilt=tilt, vx=vx)
    else:
        require("mujoco", "mujoco", "--engine mujoco")
        from mudforce.engines.mujoco import simulate_drop_3d

        res = simulate_drop_3d(mass, params, kind, dims, duration=duration, height=height, tilt=tilt, vx=vx)
    lines = ["time_s,x_m,y_m,z_m,depth_m,vx_m_s,vz_m_s,force_x_N,force_y_N,force_z_N,tilt_deg"]
    for k in range(res.time.size):
        x, y, z = res.position[k]
        fx, fy, fz = res.force[k]
        # + 0.0: the start's depth, the surface minus the lowest point, was -0 (written '-0'), as Protocol's was
        lines.append(f"{res.time[k]:.6g},{x:.9g},{y:.9g},{z:.9g},{res.depth[k] + 0.0:.9g},{res.velocity[k, 0]:.9g},"
                     f"{res.velocity[k, 2]:.9g},{fx:.9g},{fy:.9g},{fz:.9g},{math.degrees(res.tilt[k]):.6g}")
    # through write_outputs, as the 1-D drop and every other command write: a failed write names the file
    write_outputs("mudforce-drop", {out: lambda path: write_text(path, "\n".join(lines) + "\n")})
    speed = res.speed(min(0.5, duration / 2))
    state = "at rest" if speed <= 1e-4 else f"moving at {speed * 1e3:.3f} mm/s"
    print(f"{args.engine} 3-D {name}: depth {res.depth[-1] * 1e3:.3f} mm after {duration:g} s, {state}; "
          f"drifted {res.position[-1, 0] * 1e3:.3f} mm in x; wrote {out}")
    return 0
