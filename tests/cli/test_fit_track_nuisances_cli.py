"""track's --force-gain-uncertainty from the command line (issue 23, point 5): the interval spans what each
gain would read; 0% turns it off; a bad value is refused in one line, nothing written."""

from __future__ import annotations

import csv
from pathlib import Path

from mudforce_cli_harness import assert_refused, run_batch


def _last_interval(path: Path) -> tuple[float, float]:
    with path.open() as handle:
        row = list(csv.DictReader(handle))[-1]
    return float(row["water_content_low"]), float(row["water_content_high"])


def test_force_gain_uncertainty_widens_track(tmp_path: Path) -> None:
    walk = "walks/w22_gait_r1.csv"
    runs = run_batch([
        (["synth", "--motion", "gait", "--out", "walks", "--water-content", "22%", "--repeats", "1",
          "--seed", "1", "--duration", "8s"], tmp_path),
        (["track", walk, "--out", "none.csv", "--force-gain-uncertainty", "0%", "--quiet"], tmp_path),
        (["track", walk, "--out", "default.csv", "--quiet"], tmp_path),
        (["track", walk, "--out", "wide.csv", "--force-gain-uncertainty", "20%", "--quiet"], tmp_path),
        (["track", walk, "--out", "bad.csv", "--force-gain-uncertainty", "80%"], tmp_path),
        # 0% in other words: refused as 'must be greater than zero', though [0%, 50%) is what it takes
        (["track", walk, "--out", "zero.csv", "--force-gain-uncertainty", "0.0%", "--quiet"], tmp_path),
    ])
    for r in [*runs[:4], runs[5]]:
        assert r.returncode == 0, r.stderr
    assert (tmp_path / "zero.csv").read_bytes() == (tmp_path / "none.csv").read_bytes()
    none, default, wide = (_last_interval(tmp_path / f"{n}.csv") for n in ("none", "default", "wide"))
    # the gain hypotheses the walk's force shape rules out get no mass: wider or equal, never narrower than none
    # (to 0.01 of a point: the surface offsets' weights move with the gain's; here by 0.0002 points the other way)
    assert default[1] - default[0] >= none[1] - none[0] - 1e-4
    for low, high in (none, default, wide):
        assert low <= 0.22 <= high
    assert_refused(runs[4], "--force-gain-uncertainty")
    assert not (tmp_path / "bad.csv").exists()
