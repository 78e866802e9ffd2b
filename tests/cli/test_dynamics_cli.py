"""``mudforce drop`` through a subprocess: output columns, both engines, bad input (exit 2, one line)."""

from __future__ import annotations

import csv
import importlib.util
import subprocess
from pathlib import Path

import pytest

from mudforce import MudParameters
from mudforce.engines.dynamics import exact_drop
from mudforce_cli_harness import assert_refused, run_batch, run_cli

PREVIOUS = b"previous output, must survive any error\n"


def run(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return run_cli(["drop", *args], cwd, timeout=120)


def read(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


@pytest.mark.parametrize("engine", ["builtin", "mujoco"])
def test_drop_writes_the_csv(tmp_path: Path, engine: str) -> None:
    if engine == "mujoco" and importlib.util.find_spec("mujoco") is None:
        pytest.skip("mujoco is not installed")
    args = ["--engine", engine, "--mass", "5kg", "--water-content", "25%", "--duration", "3s", "--out", "drop.csv"]
    if engine == "builtin":
        args += ["--plot", "drop.png", "--height", "10mm"]
    proc = run(args, tmp_path)
    assert proc.returncode == 0, proc.stderr
    rows = read(tmp_path / "drop.csv")
    assert list(rows[0]) == ["time_s", "depth_m", "velocity_m_s", "force_N", "state"]
    assert len(rows) == 3001
    height = 0.01 if engine == "builtin" else 0.0
    assert float(rows[0]["depth_m"]) == -height and rows[0]["state"] == "FREE"
    assert rows[-1]["state"] == "STUCK"
    ref = exact_drop(5.0, MudParameters.from_water_content(0.25), duration=3.0, height=height)
    assert float(rows[-1]["depth_m"]) == pytest.approx(ref.rest_depth, rel=0.02 if engine == "builtin" else 0.05)
    assert float(rows[-1]["force_N"]) == pytest.approx(5.0 * 9.81, rel=1e-6)
    if engine == "builtin":
        assert (tmp_path / "drop.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


BAD_INPUTS = [
        (["--mass", "5", "--water-content", "25%"], "--mass: '5' has no unit"),
        (["--mass", "5kg", "--water-content", "25%", "--duration", "8"], "--duration: '8' has no unit"),
        (["--mass", "5kg", "--water-content", "50%"], "outside Table I's range"),
        (["--mass", "5kg", "--water-content", "25%", "--height=-3mm"], "must not be negative"),
]


def test_bad_input_exit_2_one_line_output_untouched(tmp_path: Path) -> None:
    """Each in its own folder, all through one subprocess (run_batch): one line, exit 2, the output untouched."""
    folders = [tmp_path / str(i) for i in range(len(BAD_INPUTS))]
    for folder in folders:
        folder.mkdir()
        (folder / "drop.csv").write_bytes(PREVIOUS)
    runs = run_batch([(["drop", *args, "--out", "drop.csv"], folder)
                      for (args, _), folder in zip(BAD_INPUTS, folders, strict=True)])
    for run, (_, message), folder in zip(runs, BAD_INPUTS, folders, strict=True):
        assert_refused(run, message)
        assert (folder / "drop.csv").read_bytes() == PREVIOUS
        assert sorted(p.name for p in folder.iterdir()) == ["drop.csv"]
