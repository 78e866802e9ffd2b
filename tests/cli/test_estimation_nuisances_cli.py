"""identify's --force-gain-uncertainty from the command line (issue 23, point 3): the interval widens
by the shift a gain error causes; 0% turns it off; a bad value is refused in one line. identify's
--depth-noise (point 7: what a robot should log) is used and reported; fit's --force-gain-uncertainty and
identify's --depth-noise refuse a bad value in one line, writing nothing."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from mudforce_cli_harness import assert_refused, run_batch


def test_force_gain_uncertainty_widens_identify(tmp_path: Path) -> None:
    runs = run_batch([
        (["synth", "--motion", "gait", "--out", "walks", "--water-content", "22%", "--repeats", "1",
          "--seed", "1", "--duration", "8s"], tmp_path),
        (["identify", "walks/w22_gait_r1.csv", "--json"], tmp_path),
        (["identify", "walks/w22_gait_r1.csv", "--json", "--force-gain-uncertainty", "10%"], tmp_path),
        (["identify", "walks/w22_gait_r1.csv", "--json", "--force-gain-uncertainty", "0%"], tmp_path),
        (["identify", "walks/w22_gait_r1.csv", "--force-gain-uncertainty", "80%"], tmp_path),
        (["identify", "walks/w22_gait_r1.csv", "--json", "--depth-noise", "0.05mm"], tmp_path),
        (["identify", "walks/w22_gait_r1.csv", "--depth-noise", "20mm"], tmp_path),
        (["fit", "walks", "--out", "bad.json", "--force-gain-uncertainty", "80%"], tmp_path),
        # 0% in other words: refused as 'must be greater than zero', though [0%, 50%) is what it takes
        (["identify", "walks/w22_gait_r1.csv", "--json", "--force-gain-uncertainty", "0 %"], tmp_path),
    ])
    assert runs[0].returncode == 0, runs[0].stderr
    default, ten, none = (json.loads(r.stdout) for r in runs[1:4])
    assert default["force_gain_uncertainty"] == 0.05 and none["gain_shift"] == 0.0
    assert ten["gain_shift"] > default["gain_shift"] > 0.0
    width = [d["interval"][1] - d["interval"][0] for d in (none, default, ten)]
    assert width[0] < width[1] < width[2]
    for d in (none, default, ten):
        assert d["interval"][0] <= 0.22 <= d["interval"][1]
        assert {"depth_offset_m", "force_lag_s", "discretisation_N", "rest_fraction"} <= set(d)
    assert_refused(runs[4], "--force-gain-uncertainty")
    given = json.loads(runs[5].stdout)
    assert given["depth_noise_m"] == pytest.approx(5e-5) and default["depth_noise_m"] < 5e-5
    assert given["interval"][0] <= 0.22 <= given["interval"][1]
    assert_refused(runs[6], "--depth-noise")  # the option, not the CSV file (its name was the message's subject)
    assert runs[6].stderr.strip().endswith("--depth-noise: '20mm' is beyond 10 mm (beyond it the depth tells "
                                           "nothing); expected 0mm to 10mm, e.g. 0.03mm"), runs[6].stderr
    assert_refused(runs[7], "--force-gain-uncertainty")
    assert not (tmp_path / "bad.json").exists()
    assert runs[8].returncode == 0, runs[8].stderr
    assert json.loads(runs[8].stdout) == none


def test_identify_reads_and_prints_a_gain_the_walk_determines(tmp_path: Path) -> None:
    """A gait walk whose force reads 5 % low (``synth --force-gain 0.95``): identify reads the gain (0.942) and the
    water content (21.96 % for 22 %), and says so in a line of its own; ``--force-gain-uncertainty 0%`` reads none."""
    runs = run_batch([
        (["synth", "--motion", "gait", "--out", "low", "--water-content", "22%", "--repeats", "1", "--seed", "1",
          "--duration", "8s", "--force-gain", "0.95"], tmp_path),
        (["identify", "low/w22_gait_r1.csv"], tmp_path),
        (["identify", "low/w22_gait_r1.csv", "--json"], tmp_path),
        (["identify", "low/w22_gait_r1.csv", "--force-gain-uncertainty", "0%"], tmp_path),
    ])
    assert all(r.returncode == 0 for r in runs), [r.stderr for r in runs]
    lines = runs[1].stdout.splitlines()
    assert lines[2].startswith("force gain read from the recording: 0.94") and len(lines) == 3
    read = json.loads(runs[2].stdout)
    # the sensor nuisances in a line of their own, as the JSON gives them (rounded)
    assert lines[1] == (f"sensor nuisances fitted with it: surface offset {read['depth_offset_m'] * 1e3:+.2f} +- "
                        f"{read['depth_offset_stderr_m'] * 1e3:.2f} mm (the model follows the depth plus it), force "
                        f"lag {read['force_lag_s'] * 1e3:.1f} +- {read['force_lag_stderr_s'] * 1e3:.1f} ms (a "
                        f"first-order low-pass), force bias {read['bias_N']:+.2f} +- {read['bias_stderr_N']:.2f} N")
    assert read["force_gain"] == pytest.approx(0.95, abs=0.01) and abs(read["water_content"] - 0.22) < 0.002
    assert "force gain read" not in runs[3].stdout
