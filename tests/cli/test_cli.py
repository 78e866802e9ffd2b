"""The command line, tested through a subprocess: exit codes, stdout, stderr and the files left behind.

Every bad input must give exit status 2, one short line on stderr that
names the problem (no traceback), nothing on stdout, and leave every file in
the working directory byte-for-byte as it was (outputs are written
atomically, and only after everything has been checked).

Each run is its own ``python -m mudforce`` process (importing numba costs
about half a second), so the cases are chosen to cover each kind of error
once rather than every combination.
"""

from __future__ import annotations

import csv
import json
import math
import os
import shutil
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mudforce import Foot, MudParameters, simulate
from mudforce.cli.simulate import parse_foot
from mudforce.errors import InputError
from mudforce_cli_harness import Run, run_batch, run_cli, snapshot

PREVIOUS_CSV = b"previous output, must survive any error\n"
PREVIOUS_PNG = b"not really a PNG, must survive any error\n"



def read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with path.open(newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], rows[1:]


# ------------------------------------------------------------------------- happy paths


def test_simulate_paper_protocol_with_plot(tmp_path: Path) -> None:
    """Defaults at W = 25%: 1201 samples at 100 Hz, peak about 59.5 N (docs/model.md), a PNG, old files replaced."""
    (tmp_path / "out.csv").write_bytes(PREVIOUS_CSV)
    (tmp_path / "out.png").write_bytes(PREVIOUS_PNG)
    proc = run_cli(["simulate", "--water-content", "25%", "--out", "out.csv", "--plot", "out.png"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    header, rows = read_csv(tmp_path / "out.csv")
    for column in ("time_s", "depth_m", "force_N", "mud_displacement_m", "state"):
        assert column in header
    assert len(rows) == 1201
    force = np.array([float(r[header.index("force_N")]) for r in rows])
    time = np.array([float(r[header.index("time_s")]) for r in rows])
    states = {r[header.index("state")] for r in rows}
    assert force.max() == pytest.approx(59.5, abs=0.05)
    assert force.min() == pytest.approx(-6e3 * 0.051 * 0.038, abs=0.01)  # -sigma_y S at necking
    assert time[0] == 0.0 and time[-1] == pytest.approx(12.0)
    assert states == {"FREE", "CONTACT", "NECKED"}
    png = (tmp_path / "out.png").read_bytes()
    assert png.startswith(b"\x89PNG\r\n\x1a\n") and len(png) > 10_000
    assert b"Software" not in png and b"matplotlib version" not in png
    assert sorted(os.listdir(tmp_path)) == ["out.csv", "out.png"]  # no temporary files left
    summary = proc.stdout
    assert "peak force: 59.5 N" in summary
    assert "min force: -11.63 N" in summary
    assert "necking: 8.66 s" in summary
    assert "wrote 1201 rows to out.csv" in summary
    assert "out.png" in summary


def test_simulate_trajectory_params_file_and_foot(tmp_path: Path) -> None:
    """A depth_mm trajectory with a parameter file and a custom foot equals the library's result."""
    params = MudParameters.from_water_content(0.2)
    (tmp_path / "mud.json").write_text(params.to_json())
    time = np.arange(0.0, 6.0, 0.01)
    depth_mm = 15.0 * np.sin(np.pi * time / 4.0)  # in, then out past the surface
    lines = ["time_s,depth_mm,comment"] + [f"{t:.2f},{float(z)!r},x" for t, z in zip(time, depth_mm, strict=True)]
    (tmp_path / "traj.csv").write_text("\n".join(lines) + "\n")
    proc = run_cli(
        ["simulate", "--params", "mud.json", "--trajectory", "traj.csv", "--foot", "area:12cm2,width:30mm",
         "--velocity-filter", "exact", "--out", "result.csv", "--quiet"],
        tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "" and proc.stderr == ""
    header, rows = read_csv(tmp_path / "result.csv")
    got = np.array([float(r[header.index("force_N")]) for r in rows])
    depth = np.array([float(r[header.index("depth_m")]) for r in rows])
    expected = simulate(np.round(time, 2), depth_mm * 1e-3, params, Foot(area=12e-4, width=0.03),
                        velocity_filter="exact")
    assert len(rows) == time.size
    np.testing.assert_allclose(depth, depth_mm * 1e-3, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(got, expected.force, rtol=1e-9, atol=1e-9 * expected.peak_force)


def _sine_record() -> tuple[np.ndarray, np.ndarray]:
    """The issue's case: a 3.14 s sine of 10 mm about 20 mm, 100 Hz, depths printed to 12 digits (the record of
    tests/model/test_velocity_noise.py, whose API tests it drives)."""
    i = np.arange(600)
    time = np.array([float(f"{k / 100:.2f}") for k in i])
    depth = np.array([float(f"{0.02 + 0.01 * math.sin(2 * math.pi * k / 314):.12g}") for k in i])
    return time, depth


def test_simulate_command_says_which_rule(tmp_path: Path) -> None:
    """The issue's command line: exit 0, the exact force at 0.80 s (5.14 N, not 209 N), and the rule printed."""
    t, z = _sine_record()
    rows = "".join(f"{a:.2f},{b:.12g}\n" for a, b in zip(t, z, strict=True))
    (tmp_path / "sine.csv").write_text("time_s,depth_m\n" + rows)
    run = run_cli(["simulate", "--water-content", "20%", "--trajectory", "sine.csv", "--out", "a.csv"], tmp_path)
    assert run.returncode == 0, run.stderr
    assert "branch rule: exact (the sign of each step, the paper's rule); clean" in run.stdout
    row = next(line for line in (tmp_path / "a.csv").read_text().splitlines() if line.startswith("0.8,"))
    assert float(row.split(",")[8]) == pytest.approx(5.143, abs=1e-3)


def test_params_one_water_content_json(tmp_path: Path) -> None:
    """``params --water-content 25% --json`` prints the flat 11-key object in SI and nothing else."""
    proc = run_cli(["params", "--water-content", "25%", "--json"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    assert data == MudParameters.from_water_content(0.25).to_dict()
    assert list(data) == ["k_m_i", "b_m_i", "k_m_w", "b_m_w", "alpha", "beta", "sigma_y", "zeta", "omega_0",
                          "rho_m", "lambda"]


def test_params_table_i(tmp_path: Path) -> None:
    """Without --water-content: all of Table I in SI with units and the citation."""
    proc = run_cli(["params"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    for w in ("15%", "20%", "25%", "30%", "35%"):
        assert f"W = {w}" in out
    for text in ("Pa/m", "Pa s/m", "rad/s", "kg/m^3", "sigma_y", "lambda", "arXiv:2403.02617", "Table I"):
        assert text in out
    assert "6000" in out  # sigma_y at 25%: 6 kPa in Pa


def test_params_table_i_json(tmp_path: Path) -> None:
    """``params --json``: an object keyed by water content, each the 11 keys in SI."""
    proc = run_cli(["params", "--json"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    assert list(data) == ["0.15", "0.20", "0.25", "0.30", "0.35"]
    for key, values in data.items():
        assert values == MudParameters.table_i(float(key)).to_dict()


def _console_script() -> str | None:
    beside = Path(sys.executable).with_name("mudforce")
    return str(beside) if beside.exists() else shutil.which("mudforce")


def test_console_script(tmp_path: Path) -> None:
    """The installed ``mudforce`` script runs the same command line."""
    script = _console_script()
    if script is None:
        pytest.skip("the mudforce console script is not installed")
    proc = run_cli(["params", "--water-content", "30%", "--json"], tmp_path, command=[script])
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout) == MudParameters.table_i(0.30).to_dict()


def test_help_lists_commands(tmp_path: Path) -> None:
    proc = run_cli(["simulate", "--help"], tmp_path)
    assert proc.returncode == 0
    for option in ("--water-content", "--params", "--trajectory", "--foot", "--out", "--plot", "cuboid:51mmx38mm"):
        assert option in proc.stdout


# ------------------------------------------------------------------------- bad input

GOOD_TRAJECTORY = "time_s,depth_m\n0,0\n0.01,0.0001\n0.02,0.0002\n0.03,0.0001\n"
GOOD_PARAMS = MudParameters.from_water_content(0.25).to_dict()


def _params_json(**changes: object) -> str:
    data: dict[str, object] = {**GOOD_PARAMS, **changes}
    return json.dumps({k: v for k, v in data.items() if v is not None})


def _random_text() -> bytes:
    rng = np.random.default_rng(7)
    alphabet = list("abcxyz ,;:\"'0123456789.-\n\t")
    return "".join(rng.choice(alphabet, size=4000)).encode()


def sim(*args: str) -> list[str]:
    """``simulate`` at 25% writing ``out.csv``, with extra arguments."""
    return ["simulate", "--water-content", "25%", *args, "--out", "out.csv"]


def sim_traj() -> list[str]:
    return sim("--trajectory", "traj.csv")


def sim_params() -> list[str]:
    return ["simulate", "--params", "mud.json", "--out", "out.csv"]


#: (id, argv, files to create, words the message must contain)
BAD: list[tuple[str, list[str], dict[str, bytes], tuple[str, ...]]] = [
    ("water-content-90%", ["simulate", "--water-content", "90%", "--out", "out.csv"], {},
     ("--water-content", "90%", "range")),
    ("water-content-bare-25", ["simulate", "--water-content", "25", "--out", "out.csv"], {},
     ("--water-content", "25%")),
    ("water-content-bare-fraction", ["simulate", "--water-content", "0.25", "--out", "out.csv"], {},
     ("--water-content", "no unit", "25%")),
    ("params-water-content-90%", ["params", "--water-content", "90%", "--json"], {}, ("--water-content", "range")),
    ("unitless-depth", sim("--depth", "20"), {}, ("--depth", "no unit", "20mm")),
    ("negative-depth", sim("--depth", "-20mm"), {}, ("--depth", "negative")),
    ("unknown-unit", sim("--depth", "20furlongs"), {}, ("--depth", "furlongs")),
    ("zero-velocity", sim("--velocity", "0mm/s"), {}, ("--velocity", "greater than zero")),
    ("zero-rate", sim("--rate", "0Hz"), {}, ("--rate", "greater than zero")),
    ("huge-rate", sim("--rate", "1e9Hz"), {}, ("--rate", "samples")),
    ("trajectory-missing", sim("--trajectory", "missing.csv"), {}, ("missing.csv", "not found")),
    ("trajectory-empty", sim_traj(), {"traj.csv": b""}, ("traj.csv", "empty")),
    ("trajectory-header-only", sim_traj(), {"traj.csv": b"time_s,depth_m\n"}, ("traj.csv", "no data rows")),
    ("trajectory-binary", sim_traj(), {"traj.csv": bytes(range(256)) * 8}, ("traj.csv", "UTF-8")),
    ("trajectory-random-text", sim_traj(), {"traj.csv": _random_text()}, ("traj.csv",)),
    ("trajectory-ragged", sim_traj(), {"traj.csv": b"time_s,depth_m\n0,0\n0.01,0.0001,5\n"},
     ("traj.csv", "row 3", "ragged")),
    ("trajectory-nan", sim_traj(), {"traj.csv": b"time_s,depth_m\n0,0\n0.01,nan\n0.02,0\n"},
     ("traj.csv", "row 3", "depth_m", "not finite")),
    ("trajectory-not-a-number", sim_traj(), {"traj.csv": b"time_s,depth_m\n0,0\n0.01,deep\n"},
     ("traj.csv", "row 3", "'deep'", "not a number")),
    ("trajectory-time-repeats", sim_traj(), {"traj.csv": b"time_s,depth_m\n0,0\n0.01,0.001\n0.01,0.002\n"},
     ("traj.csv", "row 4", "time_s", "repeats")),
    ("trajectory-time-backwards", sim_traj(), {"traj.csv": b"time_s,depth_m\n0,0\n0.02,0.001\n0.01,0.002\n"},
     ("traj.csv", "row 4", "backwards")),
    ("trajectory-missing-column", sim_traj(), {"traj.csv": b"time_s,height_m\n0,0\n0.01,0.001\n"},
     ("traj.csv", "missing column", "depth_m")),
    ("trajectory-with-protocol-option", sim("--trajectory", "traj.csv", "--depth", "20mm"),
     {"traj.csv": GOOD_TRAJECTORY.encode()}, ("--depth", "--trajectory")),
    ("out-is-the-trajectory", ["simulate", "--water-content", "25%", "--trajectory", "traj.csv", "--out", "traj.csv"],
     {"traj.csv": GOOD_TRAJECTORY.encode()}, ("--out", "traj.csv")),
    ("params-malformed", sim_params(), {"mud.json": b'{"k_m_i": 260000.0, "b_m_i": '}, ("mud.json", "malformed JSON")),
    ("params-not-an-object", sim_params(), {"mud.json": b"[1, 2, 3]"}, ("mud.json", "object")),
    ("params-beta-above-1", sim_params(), {"mud.json": _params_json(beta=1.5).encode()}, ("mud.json", "beta", "1.5")),
    ("params-negative-stiffness", sim_params(), {"mud.json": _params_json(k_m_i=-1e5).encode()},
     ("mud.json", "k_m_i", "within")),
    ("params-missing-key", sim_params(), {"mud.json": _params_json(sigma_y=None).encode()},
     ("mud.json", "missing", "sigma_y")),
    ("params-unknown-key", sim_params(), {"mud.json": _params_json(sigmay=6000.0).encode()},
     ("mud.json", "unknown", "sigmay")),
    ("params-file-missing", sim_params(), {}, ("mud.json", "not found")),
    ("params-and-water-content", ["simulate", "--water-content", "25%", "--params", "mud.json", "--out", "out.csv"],
     {"mud.json": _params_json().encode()}, ("--water-content", "--params")),
    ("no-mud", ["simulate", "--out", "out.csv"], {}, ("--water-content", "--params", "required")),
    ("unknown-option", sim("--depht", "20mm"), {}, ("--depht",)),
    ("foot-unknown-shape", sim("--foot", "hexagon:30mm"), {}, ("--foot", "hexagon", "cuboid:51mmx38mm")),
    ("foot-unitless", sim("--foot", "cuboid:51x38mm"), {}, ("--foot", "no unit")),
    ("plot-not-png", sim("--plot", "out.pdf"), {}, ("--plot", "out.pdf", ".png")),
    ("out-directory-missing", ["simulate", "--water-content", "25%", "--out", "no/such/dir/out.csv"], {},
     ("--out", "does not exist")),
]


class BadRun:
    """One bad-input case, run in its own directory holding earlier outputs and the case's files."""

    def __init__(self, directory: Path, argv: list[str], files: dict[str, bytes]) -> None:
        self.directory = directory
        self.argv = argv
        (directory / "out.csv").write_bytes(PREVIOUS_CSV)
        (directory / "out.png").write_bytes(PREVIOUS_PNG)
        for name, content in files.items():
            (directory / name).write_bytes(content)
        self.before = snapshot(directory)
        self.proc: Run | None = None


@pytest.fixture(scope="module")
def bad_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, BadRun]:
    """All bad-input cases in ONE subprocess (``run_batch``: ``mudforce.cli.main`` per case, each in its own
    folder; a process each spent most of its time importing). Real processes' exit statuses are checked in
    test_cli_outputs.py::test_refusal_end_to_end_exit_status."""
    runs = {case_id: BadRun(tmp_path_factory.mktemp(f"bad-{i:02d}"), argv, files)
            for i, (case_id, argv, files, _) in enumerate(BAD)}
    done = run_batch([(r.argv, r.directory) for r in runs.values()])
    for r, result in zip(runs.values(), done, strict=True):
        r.proc = result
    return runs


@pytest.mark.parametrize(("case_id", "words"), [(case[0], case[3]) for case in BAD], ids=[case[0] for case in BAD])
def test_bad_input(bad_runs: dict[str, BadRun], case_id: str, words: tuple[str, ...]) -> None:
    """Exit 2, one short line naming the problem, nothing on stdout, every file untouched."""
    run = bad_runs[case_id]
    assert run.proc is not None
    err = run.proc.stderr
    assert run.proc.returncode == 2, (run.proc.returncode, err)
    assert "Traceback" not in err
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert len(err) < 300, err
    assert err.startswith("mudforce") and ": error: " in err, err
    for word in words:
        assert word in err, (word, err)
    assert run.proc.stdout == ""
    assert snapshot(run.directory) == run.before


def test_plot_needs_matplotlib(tmp_path: Path, tmp_path_factory: pytest.TempPathFactory) -> None:
    """Without matplotlib, --plot is refused up front with the pip extra to install; nothing is written."""
    (tmp_path / "out.csv").write_bytes(PREVIOUS_CSV)
    blocker = tmp_path_factory.mktemp("blocker")  # apart: importing it may write its bytecode beside it
    (blocker / "matplotlib.py").write_text("raise ImportError('matplotlib is hidden for this test')\n")
    before = snapshot(tmp_path)
    proc = run_cli(["simulate", "--water-content", "25%", "--out", "out.csv", "--plot", "out.png"], tmp_path,
                   path_first=[blocker])
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert "matplotlib" in proc.stderr and "mudforce[plot]" in proc.stderr
    assert snapshot(tmp_path) == before


# ------------------------------------------------------------------------- in-process pieces


@pytest.mark.parametrize(
    ("spec", "area", "width"),
    [
        ("cuboid:51mmx38mm", 0.051 * 0.038, 0.038),
        ("cuboid:3.8cm x 5.1cm", 0.051 * 0.038, 0.038),
        ("CUBOID:0.051m*0.038m", 0.051 * 0.038, 0.038),
        ("disc:50mm", np.pi * 0.05**2 / 4, 0.05),
        ("area:19.38cm2,width:38mm", 19.38e-4, 0.038),
        ("width:38mm,area:1938mm2", 1938e-6, 0.038),
        ("paper", 0.051 * 0.038, 0.038),
    ],
)
def test_parse_foot(spec: str, area: float, width: float) -> None:
    foot = parse_foot(spec)
    assert foot.area == pytest.approx(area, rel=1e-12)
    assert foot.width == pytest.approx(width, rel=1e-12)


@pytest.mark.parametrize(
    "spec",
    ["", "cuboid", "cuboid:", "cuboid:51mm", "cuboid:51mmx38mmx25mm", "cuboid:51x38", "disc:50", "disc:-5mm",
     "area:19cm2", "area:19cm2,width:38mm,area:1cm2", "area:19mm,width:38mm", "sphere:5mm", "51mmx38mm",
     # not a str: str() raised ValueError (4300 digits), spanned lines, read "None"
     pytest.param(10**5000, id="10**5000"), pytest.param(np.zeros((3, 3)), id="2-D array"), None],
)
def test_parse_foot_refuses(spec: Any) -> None:
    with pytest.raises(InputError, match="--foot") as info:
        parse_foot(spec)
    assert "\n" not in str(info.value)


def test_plot_is_deterministic_and_atomic(tmp_path: Path) -> None:
    """Two plots of the same result are byte-identical PNGs; a failing save leaves the old file."""
    pytest.importorskip("matplotlib")
    from mudforce import Protocol
    from mudforce import errors as mf_errors
    from mudforce.io.plotting import save_png
    from mudforce.steppers.plots import plot_result

    time, depth = Protocol.paper().sample()
    result = simulate(time, depth, MudParameters.from_water_content(0.25))
    fig = plot_result(result, tmp_path / "a.png", title="W = 25%")
    result.plot(tmp_path / "b.png", title="W = 25%")
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
    labels = [ax.get_xlabel() + ax.get_ylabel() for ax in fig.axes]
    assert all("[" in text for text in labels)  # every axis names its unit

    target = tmp_path / "c.png"
    target.write_bytes(PREVIOUS_PNG)

    class Boom(Exception):
        pass

    def explode(*args: object, **kwargs: object) -> None:
        raise Boom

    fig.savefig = explode  # rendering fails before anything is written
    with pytest.raises(Boom):
        save_png(fig, target)
    assert target.read_bytes() == PREVIOUS_PNG
    # a name in another format is refused before rendering (plot_foot_result wrote PNG bytes into 'foot.pdf')
    with pytest.raises(mf_errors.InputError, match=r"^'.*c.pdf' must end in .png \(only PNG is written\)$"):
        save_png(fig, tmp_path / "c.pdf")
    assert sorted(os.listdir(tmp_path)) == ["a.png", "b.png", "c.png"]
