"""``mudforce fit`` through a subprocess: a deterministic fit.json, and outputs refused before any fitting.

Refused runs exit 2 with one line and leave every file as it was: an --out that cannot be written, a
--report folder that cannot be replaced whole, a bad manifest (and, in the same test, a bad trial given to
``identify`` and a unitless ``synth --velocities``).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import pytest

from mudforce.estimation.calibration import load_fit_parameters, synthesize
from mudforce_cli_harness import assert_refused, run_batch, run_cli, snapshot


@pytest.fixture(scope="module")
def small(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A written synthetic dataset: W = 25%, 10 and 40 mm/s, one repeat each (about 10 ms to make)."""
    out = tmp_path_factory.mktemp("ds")
    synthesize(out, water_contents=[0.25], velocities=[0.01, 0.04], repeats=1, seed=3)
    return out


def _manifest(folder: Path, data: object) -> Path:
    (folder / "dataset.json").write_text(json.dumps(data))
    return folder


def _hidden(root: Path) -> list[str]:
    return sorted(n for n in os.listdir(root) if n.startswith("."))


def test_cli_fit_is_deterministic_and_reports(tmp_path: Path) -> None:
    data = tmp_path / "data"
    synthesize(data, water_contents=[0.3], velocities=[0.02, 0.04], repeats=1, seed=9, force_noise=0.2)
    outs = []
    for i in range(2):
        out = tmp_path / f"fit{i}.json"
        proc = run_cli(["fit", str(data), "--out", str(out), "--quiet", "--seed", "3"], timeout=300)
        assert proc.returncode == 0, proc.stderr
        assert proc.stdout == ""
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    fit = json.loads(outs[0])
    cond = fit["conditions"][0]
    assert cond["water_content"] == 0.3
    assert set(cond["parameters"]) == set(cond["stderr"]) and len(cond["parameters"]) == 11
    assert [t["file"] for t in cond["trials"]] == ["w30_v20_r1.csv", "w30_v40_r1.csv"]
    assert math.isfinite(cond["rmse_N"]) and cond["correlation"]["parameters"][0] == "k_m_i"
    params = load_fit_parameters(tmp_path / "fit0.json")
    assert list(params) == [0.3] and params[0.3].alpha == cond["parameters"]["alpha"]


UNUSABLE_OUTPUTS = [
    (["--out", "no/such/dir/fit.json"], "--out: directory 'no/such/dir' does not exist"),
    (["--out", "."], "names a directory"),
    (["--out", "same", "--report", "same"], "is the --report folder"),
    # an empty --report was refused as a folder holding --out ("--out 'fit.json' is inside the --report folder '.'")
    (["--out", "fit.json", "--report", ""], "--report: empty folder name; expected a folder for the report"),
]


def test_fit_refuses_unusable_outputs_before_fitting(small: Path, tmp_path: Path) -> None:
    folders = [tmp_path / str(i) for i in range(len(UNUSABLE_OUTPUTS))]
    for folder in folders:
        folder.mkdir()
    runs = run_batch([(["fit", str(small), *extra, "--quiet"], folder)
                      for (extra, _), folder in zip(UNUSABLE_OUTPUTS, folders, strict=True)])
    for run, (_, words), folder in zip(runs, UNUSABLE_OUTPUTS, folders, strict=True):
        assert_refused(run, words)
        assert not any(folder.iterdir())  # nothing written, no report folder made


def test_fit_refuses_a_report_folder_it_cannot_replace_whole(tmp_path: Path) -> None:
    """A --report folder holding other files, or holding --out: one line, exit 2, nothing touched."""
    synthesize(tmp_path / "ds", velocities=(0.02,), repeats=1, seed=1)
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "notes.txt").write_text("mine\n")
    (tmp_path / "notes" / "fit.json").write_text("old fit\n")
    before = snapshot(tmp_path)
    runs = run_batch([
        (["fit", "ds", "--out", "fit.json", "--report", "notes", "--quiet"], tmp_path),
        (["fit", "ds", "--out", "notes/fit.json", "--report", "notes", "--quiet"], tmp_path),
    ])
    assert_refused(runs[0], "--report notes", "'fit.json' and 1 more, not part of a mudforce report")
    assert_refused(runs[1], "--out", "inside the --report folder", "replaced whole")
    assert snapshot(tmp_path) == before and _hidden(tmp_path) == []


def test_cli_bad_input_exit_2(small: Path, tmp_path: Path) -> None:
    manifest = json.loads((small / "dataset.json").read_text())
    manifest["trials"][0]["water_content"] = 1.5
    _manifest(tmp_path, manifest)
    bad = tmp_path / "bad.csv"
    bad.write_text("time_s,depth_m,force_N\n0,0,0\n0.01,0,\n")
    fit, identify, synth = run_batch([
        (["fit", str(tmp_path), "--out", str(tmp_path / "fit.json"), "--quiet"], tmp_path),
        (["identify", str(bad)], tmp_path),
        (["synth", "--out", str(tmp_path / "x"), "--velocities", "10"], tmp_path),
    ])
    assert_refused(fit, "water_content is 1.5")
    assert not (tmp_path / "fit.json").exists()
    assert_refused(identify, "row 3, column force_N")
    assert_refused(synth, "has no unit")
