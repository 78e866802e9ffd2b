"""The harness's warm children behave as a fresh ``python -m mudforce`` does (tests/mudforce_cli_harness.py).

Most command-line tests run in a child forked from a warm parent that has
already imported the package: each of these commands is run both ways and
must give the same exit status, stdout, stderr and files.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

from mudforce_cli_harness import run_batch, run_cli


def test_a_warm_child_gives_what_a_fresh_process_gives(tmp_path: Path) -> None:
    commands = [
        ["params", "--water-content", "30%", "--json"],  # output
        ["simulate", "--water-content", "20%", "--out", "run.csv"],  # a kernel run and a file
        ["--bogus"],  # argparse's own refusal
    ]
    for i, args in enumerate(commands):
        runs = []
        for fresh in (True, False):
            folder = tmp_path / f"{i}-{fresh}"
            folder.mkdir()
            proc = run_cli(args, folder, fresh=fresh)
            files = {p.name: p.read_bytes() for p in sorted(folder.iterdir())}
            runs.append((proc.returncode, proc.stdout, proc.stderr, files))
        assert runs[0] == runs[1], args
    assert runs[0][0] == 2 and "unrecognized arguments" in runs[0][2]


def test_a_warm_child_has_its_own_folder_environment_and_stdin(tmp_path: Path) -> None:
    proc = run_cli(["simulate", "--water-content", "20%", "--out", "a.csv"], tmp_path, env={"MUDFORCE_X": "1"})
    assert proc.returncode == 0 and (tmp_path / "a.csv").is_file()
    assert "MUDFORCE_X" not in os.environ  # the variable went to the child only
    assert Path.cwd() != tmp_path  # and so did the folder


def test_a_batch_runs_in_a_warm_child(tmp_path: Path) -> None:
    runs = run_batch([(["params", "--water-content", "25%"], tmp_path), (["params", "--nope"], tmp_path)])
    assert runs[0].returncode == 0 and "25" in runs[0].stdout
    assert runs[1].returncode == 2 and runs[1].stdout == ""


def test_a_run_past_its_timeout_is_stopped(tmp_path: Path) -> None:
    try:
        run_cli(["reproduce", "--out", str(tmp_path / "r")], tmp_path, timeout=0.5)
    except subprocess.TimeoutExpired:
        pass
    else:
        raise AssertionError("not stopped")
    ok = run_cli(["params", "--water-content", "25%"], tmp_path)  # the warm parent serves on
    assert ok.returncode == 0
