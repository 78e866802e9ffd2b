"""fit's --force-gain-uncertainty from the command line (issue 23, point 5): fit.json records it and the
force-scale parameters' standard errors hold it; a bad value is refused in one line, nothing written."""

from __future__ import annotations

import json
import math
from pathlib import Path

from mudforce_cli_harness import assert_refused, run_batch


def test_fit_force_gain_uncertainty(tmp_path: Path) -> None:
    runs = run_batch([
        (["synth", "--out", "d", "--water-content", "25%", "--velocities", "40mm/s", "--repeats", "1",
          "--seed", "3"], tmp_path),
        (["fit", "d", "--out", "f.json", "--quiet", "--force-gain-uncertainty", "10%"], tmp_path),
        (["fit", "d", "--out", "bad.json", "--force-gain-uncertainty", "80%"], tmp_path),
    ])
    assert runs[0].returncode == 0 and runs[1].returncode == 0, (runs[0].stderr, runs[1].stderr)
    fit = json.loads((tmp_path / "f.json").read_text())
    assert fit["force_gain_uncertainty"] == 0.1
    cond = fit["conditions"][0]
    for name in ("k_m_i", "alpha", "sigma_y"):
        assert cond["stderr"][name] / cond["parameters"][name] >= math.log(1.1) / 1.96 - 1e-12
    assert_refused(runs[2], "--force-gain-uncertainty")
    assert not (tmp_path / "bad.json").exists()
