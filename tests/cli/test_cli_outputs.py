"""No command overwrites its own input, and outputs go safely to what the user named (issue 15, items 1-2).

Each refused case must exit 2 with one line and leave every file (links
included) as it was; the accepted cases must write through links, leave no
temporary file behind, and cope with long names. All cases run in one
subprocess (``run_batch``); one real ``python -m mudforce`` run checks the
exit status end to end.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from mudforce.estimation.calibration.synth import synthesize
from mudforce_cli_harness import Run, assert_refused, run_batch, run_cli, snapshot

PREVIOUS = b"previous output, must survive any error\n"
TRAJECTORY = "time_s,depth_m\n" + "".join(f"{0.01 * k:.2f},{0.0005 * k:.4f}\n" for k in range(30))


def _setup(root: Path) -> None:
    """A dataset folder, a tidy CSV, a trajectory, a parameter file and links to them, in ``root``."""
    synthesize(root / "ds", velocities=(0.02,), repeats=1, seed=1)
    trial = next(p for p in sorted((root / "ds").iterdir()) if p.suffix == ".csv")
    lines = trial.read_text().splitlines()
    (root / "tidy.csv").write_text("trial,water_content," + lines[0] + "\n"
                                   + "".join(f"t1,0.25,{line}\n" for line in lines[1:]))
    (root / "traj.csv").write_text(TRAJECTORY)
    (root / "out.csv").write_bytes(PREVIOUS)
    (root / "link-to-trial.csv").symlink_to(trial)
    (root / "link-to-traj.csv").symlink_to("traj.csv")
    os.link(root / "ds" / "dataset.json", root / "hard-manifest.json")


#: (id, argv, words in the message); run in a fresh copy of the setup
REFUSED: list[tuple[str, list[str], tuple[str, ...]]] = [
    ("fit-out-manifest", ["fit", "ds", "--out", "ds/dataset.json", "--quiet"], ("--out", "dataset.json", "input")),
    ("fit-out-trial", ["fit", "ds", "--out", "ds/w25_v20_r1.csv", "--quiet"], ("--out", "w25_v20_r1.csv", "input")),
    ("fit-out-link-to-trial", ["fit", "ds", "--out", "link-to-trial.csv", "--quiet"], ("--out", "input")),
    ("fit-out-hardlink-to-manifest", ["fit", "ds", "--out", "hard-manifest.json", "--quiet"], ("--out", "input")),
    ("fit-tidy-onto-itself", ["fit", "tidy.csv", "--out", "tidy.csv", "--quiet"], ("--out", "tidy.csv")),
    ("fit-report-holds-inputs", ["fit", "ds", "--out", "fit.json", "--report", "ds", "--quiet"],
     ("--report", "input")),
    ("fit-report-is-out", ["fit", "ds", "--out", "fit.json", "--report", "fit.json", "--quiet"],
     ("--out", "--report")),
    ("simulate-out-link-to-trajectory", ["simulate", "--water-content", "25%", "--trajectory", "traj.csv",
                                         "--out", "link-to-traj.csv"], ("--out", "input", "traj.csv")),
    ("simulate-empty-out", ["simulate", "--water-content", "25%", "--out", ""], ("--out", "empty")),
    ("fit-empty-out", ["fit", "ds", "--out", ""], ("--out", "empty")),
    ("synth-empty-out", ["synth", "--out", ""], ("--out", "empty")),
    ("simulate-out-fifo", ["simulate", "--water-content", "25%", "--out", "fifo.csv"], ("--out", "FIFO")),
    ("simulate-out-device", ["simulate", "--water-content", "25%", "--out", "/dev/null"], ("--out", "regular")),
    # an --out in another format's suffix: simulate --out o.png wrote CSV under that name
    ("simulate-out-png", ["simulate", "--water-content", "25%", "--out", "o.png"],
     ("--out: 'o.png' ends in .png (PNG), but --out writes CSV; expected a name ending in .csv "
      "(--plot FILE.png writes a plot)",)),
    ("drop-out-json", ["drop", "--mass", "5kg", "--water-content", "25%", "--out", "d.JSON"],
     ("--out: 'd.JSON' ends in .JSON (JSON)", ".csv", "--plot")),
    ("track-out-svg", ["track", "traj.csv", "--out", "t.svg"], ("--out", "(SVG)", ".csv", "--plot")),
    ("fit-out-csv", ["fit", "ds", "--out", "fit.csv", "--quiet"],
     ("--out: 'fit.csv' ends in .csv (CSV), but --out writes JSON; expected a name ending in .json "
      "(--report DIR writes a report with plots)",)),
    ("simulate-name-too-long", ["simulate", "--water-content", "25%", "--out", "n" * 300 + ".csv"],
     ("--out", "longer than the file system allows")),
]


@pytest.fixture(scope="module")
def refused_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Run, Path, dict[str, bytes | str]]]:
    cases = []
    for case_id, argv, _ in REFUSED:
        root = tmp_path_factory.mktemp(case_id)
        _setup(root)
        if hasattr(os, "mkfifo"):
            os.mkfifo(root / "fifo.csv")
        cases.append((argv, root))
    befores = [snapshot(root) for _, root in cases]
    runs = run_batch(cases)
    return {c[0]: (run, root, before) for c, run, (_, root), before in zip(REFUSED, runs, cases, befores, strict=True)}


@pytest.mark.parametrize(("case_id", "words"), [(c[0], c[2]) for c in REFUSED], ids=[c[0] for c in REFUSED])
def test_refused_before_anything_is_written(refused_runs: dict[str, tuple[Run, Path, dict[str, bytes | str]]],
                                            case_id: str, words: tuple[str, ...]) -> None:
    """Exit 2, one line naming the output and the input, every file and link exactly as before."""
    if case_id == "simulate-out-fifo" and not hasattr(os, "mkfifo"):
        pytest.skip("no FIFOs here")
    run, root, before = refused_runs[case_id]
    assert_refused(run, *words)
    assert snapshot(root) == before


def test_outputs_write_through_links_atomically(tmp_path: Path) -> None:
    """A link stays a link and its target gets the output; a dangling link creates its target; a long
    name works; no temporary file is left; a subprocess run exits 0."""
    (tmp_path / "target.csv").write_bytes(PREVIOUS)
    (tmp_path / "target.csv").chmod(0o640)
    (tmp_path / "link.csv").symlink_to("target.csv")
    (tmp_path / "sub").mkdir()
    (tmp_path / "dangling.csv").symlink_to("sub/new.csv")
    long_name = "L" * 240 + ".csv"  # valid; the temporary name must not be longer than the file system allows
    runs = run_batch([(["simulate", "--water-content", "25%", "--out", name, "--quiet"], tmp_path)
                      for name in ("link.csv", "dangling.csv", long_name)])
    for run in runs:
        assert run.returncode == 0, run.stderr
    assert (tmp_path / "link.csv").is_symlink() and os.readlink(tmp_path / "link.csv") == "target.csv"
    assert (tmp_path / "target.csv").read_bytes().startswith(b"time_s,depth_m")
    assert (tmp_path / "target.csv").stat().st_mode & 0o777 == 0o640  # its permissions kept
    assert (tmp_path / "dangling.csv").is_symlink() and (tmp_path / "sub" / "new.csv").is_file()
    assert (tmp_path / long_name).read_bytes() == (tmp_path / "target.csv").read_bytes()
    leftovers = [p.name for p in tmp_path.rglob(".*")]
    assert leftovers == []
    proc = run_cli(["simulate", "--water-content", "25%", "--out", "link.csv", "--quiet"], tmp_path)
    assert proc.returncode == 0 and proc.stderr == ""
    header = np.genfromtxt(tmp_path / "target.csv", delimiter=",", max_rows=1, dtype=str)
    assert "force_N" in header


def test_refusal_end_to_end_exit_status(tmp_path: Path) -> None:
    """The real process: ``fit DIR --out DIR/dataset.json`` exits 2 with one line and destroys nothing."""
    _setup(tmp_path)
    before = snapshot(tmp_path)
    proc = run_cli(["fit", "ds", "--out", "ds/dataset.json", "--quiet"], tmp_path)
    assert_refused(Run(proc.returncode, proc.stdout, proc.stderr), "--out", "input")
    assert snapshot(tmp_path) == before
