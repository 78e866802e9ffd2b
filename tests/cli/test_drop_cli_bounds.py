"""``mudforce drop`` through a subprocess: masses out of bounds refused (exit 2, one line); "at rest" only at rest."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from mudforce_cli_harness import assert_refused, run_batch, run_cli

PREVIOUS = b"previous output, must survive any error\n"


def run(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return run_cli(["drop", *args], cwd, timeout=120)


TOO_LIGHT = [
        # were: 7,991 NaN cells and exit 0; a traceback from MuJoCo
        (["--mass", "1e-8kg"], "--mass: '1e-8kg' is too small"),  # the unit parser's bound on any mass
        (["--mass", "0.01kg"], "--mass: '0.01kg' is less than 0.1 kg"),  # the engine's own
        (["--engine", "mujoco", "--mass", "1e-300kg"], "--mass: '1e-300kg' is too small"),
        (["--engine", "mujoco", "--mass", "0.5kg"], "--mass: '0.5kg' is less than 1 kg"),
]


def test_too_light_a_foot_is_refused(tmp_path: Path) -> None:
    """Were: 7,991 NaN cells and exit 0; a traceback from MuJoCo. All through one subprocess (run_batch)."""
    folders = [tmp_path / str(i) for i in range(len(TOO_LIGHT))]
    for folder in folders:
        folder.mkdir()
        (folder / "drop.csv").write_bytes(PREVIOUS)
    runs = run_batch([(["drop", *args, "--water-content", "25%", "--out", "drop.csv"], folder)
                      for (args, _), folder in zip(TOO_LIGHT, folders, strict=True)])
    for run, (_, message), folder in zip(runs, TOO_LIGHT, folders, strict=True):
        assert_refused(run, message)
        assert (folder / "drop.csv").read_bytes() == PREVIOUS


def test_a_foot_still_moving_is_not_called_at_rest(tmp_path: Path) -> None:
    proc = run(["--mass", "5kg", "--water-content", "25%", "--duration", "50ms", "--out", "drop.csv"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "rest depth" not in proc.stdout
    assert "not at rest after 0.05 s: depth 9.003 mm, moving at 292.003 mm/s (INTRUSION)" in proc.stdout
    assert "force std over the last 0.05 s" in proc.stdout


def test_a_water_content_out_of_range_is_refused_as_simulate_refuses_it(tmp_path: Path) -> None:
    """Was: "water content 0.35 is outside Table I's range [0.15, 0.35]", not naming --water-content and showing
    35.0000000001% as 0.35; drop now reads it with the parser the other commands use, in their words."""
    (tmp_path / "drop.csv").write_bytes(PREVIOUS)
    values = ["50%", "35.0000000001%"]
    runs = run_batch([([command, *extra, "--water-content", w, "--out", "drop.csv"], tmp_path)
                      for w in values for command, extra in (("drop", ["--mass", "5kg"]), ("simulate", []))])
    for w, drop, simulate in zip(values, runs[::2], runs[1::2], strict=True):
        assert_refused(drop, f"--water-content: '{w}' is outside Table I's range 15% to 35%; expected e.g. 25%")
        assert drop.stderr.replace("mudforce drop:", "mudforce simulate:") == simulate.stderr
    assert (tmp_path / "drop.csv").read_bytes() == PREVIOUS


def test_plot_with_a_shape_is_refused_before_matplotlib_is_required(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """Was, without matplotlib: "--plot needs matplotlib, which is not installed; install it with: pip install
    'mudforce[plot]'", and once it was installed "--plot is not available with --shape"; now the latter at once. In
    this process, matplotlib hidden: the refusal comes before any engine is imported or anything written."""
    from mudforce.cli import main

    monkeypatch.chdir(tmp_path)
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # `import matplotlib` raises ImportError
    status = main(["drop", "--engine", "mujoco", "--shape", "sphere:40mm", "--mass", "2kg", "--water-content", "25%",
                   "--out", "a.csv", "--plot", "a.png"])
    assert (status, capsys.readouterr().err) == (2, "mudforce drop: error: --plot is not available with --shape; "
                                                    "plot the CSV\n")
    assert list(tmp_path.iterdir()) == []


def test_a_shape_s_csv_that_cannot_be_written_is_named_as_every_command_names_it(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """``--shape``'s CSV was written its own way: a full disk said "cannot write output (OSError: No space left on
    device)", naming no file, where the 1-D drop and every other command say "cannot write FILE: ...". Now through
    the same writer: the file named, exit 1 as theirs (a full disk is the system's failure, not bad input), the old
    file as it was. (In process, the engine replaced by a canned result: the write is what is tested.)"""
    import os
    from types import SimpleNamespace

    import numpy as np

    pytest.importorskip("mujoco")
    import mudforce.engines.mujoco as engine
    from mudforce.cli import main

    n = 3
    canned = SimpleNamespace(time=np.arange(n) * 1e-3, position=np.zeros((n, 3)), force=np.zeros((n, 3)),
                             depth=np.zeros(n), velocity=np.zeros((n, 3)), tilt=np.zeros(n), speed=lambda span: 0.0)
    monkeypatch.setattr(engine, "simulate_drop_3d", lambda *args, **kwargs: canned)
    (tmp_path / "s.csv").write_bytes(PREVIOUS)
    monkeypatch.chdir(tmp_path)

    def full(fd: int) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    status = main(["drop", "--engine", "mujoco", "--shape", "disc:50mmx5mm", "--mass", "2kg", "--water-content",
                   "25%", "--duration", "3ms", "--out", "s.csv"])
    assert (status, capsys.readouterr().err) == (1, "mudforce drop: error: cannot write s.csv: No space left on "
                                                    "device\n")
    assert [p.name for p in tmp_path.iterdir()] == ["s.csv"] and (tmp_path / "s.csv").read_bytes() == PREVIOUS
