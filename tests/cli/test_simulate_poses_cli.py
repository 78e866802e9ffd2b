"""`mudforce simulate --trajectory poses.csv`: a pose trajectory through the 3-D law, its wrench as CSV.

One subprocess (``run_batch``) for every command line: a sphere pushed down and slid sideways equals
``simulate_3d`` to the printed digits; the same motion in mm with the mud surface moved with it is the same
wrench; a flat sole moved straight down equals the 1-D ``mudforce simulate``; and each bad input is one line,
exit 2, nothing written.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mudforce_cli_harness import Run, assert_refused, run_batch

HEADER = "time_s,x_m,y_m,z_m,qw,qx,qy,qz"
OUT = "time_s,x_m,y_m,z_m,qw,qx,qy,qz,force_x_N,force_y_N,force_z_N,torque_x_N_m,torque_y_N_m,torque_z_N_m"
MUD = ["simulate", "--water-content", "25%"]
#: a constant tilt of 30 degrees about x: (w, x, y, z)
QUAT = (math.cos(math.radians(15.0)), math.sin(math.radians(15.0)), 0.0, 0.0)


def _sphere_motion() -> tuple[np.ndarray, np.ndarray]:
    """A 40 mm sphere, bottom at the surface, pushed down 20 mm in 1 s, then slid 5 mm along x in 1 s."""
    time = np.linspace(0.0, 2.0, 201)
    down = np.clip(time, 0.0, 1.0)
    slide = np.clip(time - 1.0, 0.0, 1.0)
    pos = np.stack([0.005 * slide, np.zeros_like(time), 0.02 - 0.02 * down], axis=1)
    return time, pos


def _write(path: Path, header: str, rows: np.ndarray) -> None:
    path.write_text(header + "\n" + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows))


def _read(path: Path) -> tuple[list[str], np.ndarray]:
    lines = path.read_text().splitlines()
    return lines, np.array([[float(v) for v in line.split(",")[:14]] for line in lines[1:]])


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[Run]]:
    d = tmp_path_factory.mktemp("poses")
    time, pos = _sphere_motion()
    quat = np.tile(QUAT, (time.size, 1))
    _write(d / "poses.csv", HEADER, np.column_stack([time, pos, quat]))
    # the same motion in ms and mm, 10 mm higher, over a surface 10 mm higher; the columns shuffled
    shifted = np.column_stack([quat[:, ::-1], 1e3 * time, 1e3 * pos + [0.0, 0.0, 10.0]])
    _write(d / "mm.csv", "qz,qy,qx,qw,time_ms,x_mm,y_mm,z_mm", shifted)
    # a flat sole straight down 15 mm and back up: poses and depths
    t1 = np.linspace(0.0, 3.0, 151)
    depth = 0.015 * np.sin(np.pi * t1 / 3.0) - 0.002
    _write(d / "sole.csv", HEADER, np.column_stack([t1, 0 * t1, 0 * t1, -depth, 1 + 0 * t1, 0 * t1, 0 * t1, 0 * t1]))
    _write(d / "depth.csv", "time_s,depth_m", np.column_stack([t1, depth]))
    bad = {
        "noq.csv": "time_s,x_m,y_m,z_m,qw,qx,qy\n0,0,0,0,1,0,0\n",
        "cm.csv": "time_s,x_cm,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n",
        "nan.csv": f"{HEADER}\n0,0,0,0,1,0,0,0\n0.1,0,0,nan,1,0,0,0\n",
        "back.csv": f"{HEADER}\n0,0,0,0,1,0,0,0\n0.2,0,0,0,1,0,0,0\n0.1,0,0,0,1,0,0,0\n",
        "norm.csv": f"{HEADER}\n0,0,0,0.1,1,0,0,0\n0.1,0,0,0.1,1,0.1,0,0\n",
        "deep.csv": f"{HEADER}\n0,0,0,0,1,0,0,0\n0.1,0,0,-150,1,0,0,0\n",
        "tiny.csv": f"{HEADER}\n0,0,0,0,1,0,0,0\n1e-12,0,0,0,1,0,0,0\n",
    }
    for name, text in bad.items():
        (d / name).write_text(text)
    (d / "empty.csv").write_text("")
    # an upright sphere's quaternions in ROS's (x, y, z, w) order under the headers qw,qx,qy,qz
    _write(d / "ros.csv", HEADER, np.column_stack([time, pos, np.tile([0.0, 0.0, 0.0, 1.0], (time.size, 1))]))
    (d / "latin1.csv").write_bytes(f"{HEADER}\n0,0,0,0,1,0,0,0\n0.1,0,0,-1e-3,1,0,0,0 # \xb5m\n".encode("latin-1"))
    poses = ["--trajectory", "poses.csv"]
    sphere = ["--shape", "sphere:40mm"]
    cases = [
        [*MUD, *poses, *sphere, "--out", "wrench.csv"],
        [*MUD, "--trajectory", "mm.csv", *sphere, "--surface-height", "10mm", "--out", "mm_out.csv", "--quiet"],
        [*MUD, "--trajectory", "sole.csv", "--foot", "cuboid:51mmx38mm", "--out", "sole_out.csv"],
        [*MUD, "--trajectory", "depth.csv", "--foot", "cuboid:51mmx38mm", "--out", "depth_out.csv"],
        # refusals, each writing nothing to x.csv
        [*MUD, *poses, "--out", "x.csv"],
        [*MUD, "--trajectory", "depth.csv", *sphere, "--out", "x.csv"],
        [*MUD, *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "depth.csv", "--surface-height", "5mm", "--out", "x.csv"],
        [*MUD, "--trajectory", "noq.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "cm.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "nan.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "back.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "norm.csv", *sphere, "--out", "x.csv"],
        [*MUD, *poses, "--shape", "sphere:2m", "--out", "x.csv"],
        [*MUD, *poses, "--shape", "cone:40mm", "--out", "x.csv"],
        [*MUD, *poses, *sphere, "--plot", "x.png", "--out", "x.csv"],
        [*MUD, *poses, *sphere, "--foot", "disc:50mm", "--out", "x.csv"],
        [*MUD, *poses, *sphere, "--velocity-filter", "exact", "--out", "x.csv"],
        [*MUD, *poses, *sphere, "--depth", "20mm", "--out", "x.csv"],
        [*MUD, *poses, *sphere, "--surface-height", "20", "--out", "x.csv"],
        [*MUD, "--trajectory", "deep.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "tiny.csv", *sphere, "--out", "x.csv"],
        # a file that is no trajectory at all, with --shape or --surface-height: what is wrong with it
        [*MUD, "--trajectory", "missing.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "empty.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", "latin1.csv", *sphere, "--out", "x.csv"],
        [*MUD, "--trajectory", ".", "--surface-height", "5mm", "--out", "x.csv"],
        [*MUD, "--trajectory", "cm.csv", "--surface-height", "5mm", "--foot", "disc:50mm", "--out", "x.csv"],
        [*MUD, "--trajectory", "ros.csv", *sphere, "--out", "ros_out.csv", "--quiet"],
    ]
    return d, run_batch([(argv, d) for argv in cases])


def test_a_sphere_pushed_down_and_slid_is_simulate_3d_to_the_printed_digits(runs: tuple[Path, list[Run]]) -> None:
    import mudforce as mf
    from mudforce.model import shapes

    d, out = runs
    assert out[0].returncode == 0, out[0].stderr
    lines = out[0].stdout.splitlines()
    assert lines[0] == "mud: Table I, W = 25%" and lines[-1] == "wrote 201 rows to wrench.csv"
    assert lines[2].startswith("foot: sphere 40 mm, ") and lines[2].endswith("mud surface at z = 0 mm")
    rows, table = _read(d / "wrench.csv")
    assert rows[0] == OUT and len(rows) == 202
    time, pos = _sphere_motion()
    quat = np.tile(QUAT, (time.size, 1))
    ref = mf.simulate_3d(time, pos, quat, mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04))
    expected = np.column_stack([time, pos, quat, ref.force, ref.torque])
    assert rows[1:] == [",".join(f"{v:.12g}" for v in row) for row in expected.tolist()]
    fz, fx = table[:, 10], table[:, 8]
    k_z, k_s = int(np.argmax(np.abs(fz))), int(np.argmax(np.hypot(fx, table[:, 9])))
    assert lines[3] == f"peak vertical force: {fz[k_z]:.4g} N at {time[k_z]:.4g} s"
    assert lines[4] == f"peak sideways force: {np.hypot(fx, table[:, 9])[k_s]:.4g} N at {time[k_s]:.4g} s"
    assert fz.max() > 10.0 and fx[-1] < -1.0  # held up, and resisted as it slides along +x
    # ms, mm, shuffled columns, and the surface 10 mm up with the motion: the same wrench
    assert out[1].returncode == 0 and out[1].stdout == "", out[1].stderr
    _, moved = _read(d / "mm_out.csv")
    np.testing.assert_allclose(moved[:, 8:], table[:, 8:], rtol=0, atol=1e-9 * np.abs(table[:, 8:11]).max())
    np.testing.assert_allclose(moved[:, 3], table[:, 3] + 0.01, rtol=0, atol=1e-15)


def test_a_sole_moved_straight_down_is_the_1d_force(runs: tuple[Path, list[Run]]) -> None:
    d, out = runs
    assert out[2].returncode == 0 and out[3].returncode == 0, (out[2].stderr, out[3].stderr)
    assert "foot: sole of cuboid" in out[2].stdout
    _, sole = _read(d / "sole_out.csv")
    depth_rows = (d / "depth_out.csv").read_text().splitlines()
    column = depth_rows[0].split(",").index("force_N")
    force_1d = np.array([float(r.split(",")[column]) for r in depth_rows[1:]])
    peak = np.abs(force_1d).max()
    assert peak > 10.0 and force_1d.min() < -1.0  # loaded, then suction on the way up
    np.testing.assert_allclose(sole[:, 10], force_1d, rtol=0, atol=1e-9 * peak)
    np.testing.assert_allclose(sole[:, [8, 9, 11, 12, 13]], 0.0, atol=1e-9 * peak)


@pytest.mark.parametrize(("case", "words"), [
    (4, ("a pose trajectory needs --shape (e.g. sphere:40mm) or --foot",)),
    (5, ("--shape needs a pose trajectory", "not a depth trajectory")),
    (6, ("--shape needs a pose trajectory", "not the paper's protocol")),
    (7, ("--surface-height needs a pose trajectory",)),
    (8, ("noq.csv", "missing column qz")),
    (9, ("cm.csv", "missing column x_m or x_mm")),
    (10, ("nan.csv: row 3, column z_m", "not finite")),
    (11, ("back.csv: row 4, column time_s", "goes backwards")),
    (12, ("norm.csv: row 3, columns qw,qx,qy,qz", "norm 1.00498756", "unit quaternion")),
    (13, ("--shape", "larger than 1 m")),
    (14, ("--shape", "KIND:SIZE", "disc:50mmx5mm")),
    (15, ("--plot is not available with a pose trajectory",)),
    (16, ("--shape or --foot", "not both")),
    (17, ("--velocity-filter applies to a depth trajectory",)),
    (18, ("--depth cannot be used with --trajectory",)),
    (19, ("--surface-height", "20")),
    (20, ("deep.csv: the pose at time 0.1 s (sample 2)", "more than 100 m from the mud surface")),
    (21, ("tiny.csv: the pose at time 1e-12 s (sample 2)", "within [1e-09, 1000] s")),
])
def test_bad_input_is_one_line_exit_2_and_nothing_written(runs: tuple[Path, list[Run]], case: int,
                                                          words: tuple[str, ...]) -> None:
    d, out = runs
    assert_refused(out[case], *words)
    assert not (d / "x.csv").exists() and not (d / "x.png").exists()


@pytest.mark.parametrize(("case", "words"), [
    (22, ("missing.csv: file not found",)),
    (23, ("empty.csv: file is empty", "time_s,x_m,y_m,z_m,qw,qx,qy,qz")),
    (24, ("latin1.csv: not a text CSV file (cannot decode as UTF-8)",)),
    (25, (": is a directory; expected a CSV file",)),
    (26, ("cm.csv: missing column x_m or x_mm",)),
])
def test_a_file_that_is_no_trajectory_is_refused_for_what_it_is_not_as_a_depth_trajectory(
        runs: tuple[Path, list[Run]], case: int, words: tuple[str, ...]) -> None:
    """With --shape or --surface-height, a missing, empty, non-UTF-8 or misnamed --trajectory was refused as "--shape
    needs a pose trajectory ..., not a depth trajectory": the file's own problem, as poses, is named instead."""
    d, out = runs
    assert_refused(out[case], *words)
    assert "not a depth trajectory" not in out[case].stderr
    assert not (d / "x.csv").exists() and not (d / "x.png").exists()


def test_quaternions_in_ros_order_are_warned_of_in_one_line(runs: tuple[Path, list[Run]]) -> None:
    """A file whose qw,qx,qy,qz columns hold an upright foot's (x, y, z, w), 0,0,0,1 (ROS's order), was simulated as
    a foot turned half a turn without a word; now the wrench is written as before and one line on stderr says so
    (simulate_3d's Python warning, two lines with a source path, is not shown). Valid poses: no warning."""
    d, out = runs
    assert out[0].stderr == "" and out[1].stderr == ""
    run = out[27]
    assert run.returncode == 0 and run.stdout == ""
    assert run.stderr == ("mudforce simulate: warning: ros.csv: every row's qw is within +-0.1 (the foot turned half "
                          "a turn at every sample; the first row's qw,qx,qy,qz = 0,0,0,1); if those columns hold x, y, "
                          "z, w (ROS's order), name them qx,qy,qz,qw\n")
    assert len((d / "ros_out.csv").read_text().splitlines()) == 202
