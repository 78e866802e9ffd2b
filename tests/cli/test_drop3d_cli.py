"""`mudforce drop --shape/--tilt/--vx`: a free foot of any shape through the 3-D MuJoCo adapter; `--engine mjx`
(1-D and 3-D) rests at the exact drop's depth; an unknown engine is refused."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mujoco")

from mudforce_cli_harness import assert_refused, run_batch

BASE = ["drop", "--engine", "mujoco", "--mass", "5kg", "--water-content", "20%", "--duration", "0.15s"]


def test_drop_with_a_shape_tilt_and_sideways_velocity_and_its_refusals(tmp_path: Path) -> None:
    runs = run_batch([
        ([*BASE, "--shape", "sphere:40mm", "--vx", "50mm/s", "--out", "s.csv"], tmp_path),
        ([*BASE, "--shape", "box:50mmx40mmx20mm", "--tilt", "10deg", "--out", "b.csv"], tmp_path),
        # a disc was called "cylinder" in the summary: it is simulated as one, and named as asked
        (["drop", "--engine", "mujoco", "--mass", "5kg", "--water-content", "20%", "--duration", "5ms", "--shape",
          "disc:50mmx5mm", "--out", "d.csv"], tmp_path),
        ([*BASE, "--shape", "cone:40mm", "--out", "x.csv"], tmp_path),
        ([*BASE, "--shape", "capsule:30mm", "--out", "x.csv"], tmp_path),
        ([*BASE, "--shape", "sphere:40mm", "--tilt", "steep", "--out", "x.csv"], tmp_path),
        ([*BASE, "--tilt", "10", "--out", "x.csv"], tmp_path),
        (["drop", "--mass", "5kg", "--water-content", "20%", "--shape", "sphere:40mm", "--out", "x.csv"], tmp_path),
        (["drop", "--engine", "warp", "--mass", "1kg", "--water-content", "20%", "--out", "x.csv"], tmp_path),
        # below the shapes' 0.1 mm: MuJoCo's error about inertia, wrapped as "the input could not be processed"
        ([*BASE, "--shape", "sphere:0.05um", "--out", "x.csv"], tmp_path),
        ([*BASE, "--shape", "box:50mmx40mmx0.01mm", "--out", "x.csv"], tmp_path),
        # float() took "1_0" as 10 degrees (and other scripts' digits); every other number read is plain ASCII
        ([*BASE, "--shape", "sphere:40mm", "--tilt", "1_0", "--out", "x.csv"], tmp_path),
        # a tilt that underflows was read as 0 degrees without a word, where --vx 1e-400mm/s is refused
        ([*BASE, "--shape", "sphere:40mm", "--tilt", "1e-400", "--out", "x.csv"], tmp_path),
        # a NaN was "outside -180 to 180 degrees": it is no angle at all
        ([*BASE, "--shape", "sphere:40mm", "--tilt", "nan", "--out", "x.csv"], tmp_path),
        ([*BASE, "--shape", "sphere:40mm", "--tilt", "-inf", "--out", "x.csv"], tmp_path),
    ])
    sphere, box, disc = runs[0], runs[1], runs.pop(2)
    assert sphere.returncode == 0 and "mujoco 3-D sphere: depth" in sphere.stdout, sphere.stderr
    assert box.returncode == 0 and "mujoco 3-D box" in box.stdout, box.stderr
    assert disc.returncode == 0 and disc.stdout.startswith("mujoco 3-D disc: depth"), (disc.stdout, disc.stderr)
    rows = (tmp_path / "s.csv").read_text().splitlines()
    assert rows[0] == "time_s,x_m,y_m,z_m,depth_m,vx_m_s,vz_m_s,force_x_N,force_y_N,force_z_N,tilt_deg"
    assert len(rows) == 152
    assert rows[1].split(",")[4] == "0"  # the start's depth was written '-0'
    last = [float(v) for v in rows[-1].split(",")]
    assert 0.0 < last[1] < 0.01  # slid forward a little, then held by the mud
    assert last[4] > 0.0 and last[9] == pytest.approx(5.0 * 9.81, rel=0.02)
    assert float((tmp_path / "b.csv").read_text().splitlines()[1].split(",")[-1]) == pytest.approx(10.0)
    for run, word in zip(runs[2:], ("KIND:SIZE", "2 size", "--tilt", "need --shape", "--engine mujoco", "mjx",
                                    "--shape: '0.05um' is smaller than 0.1 mm",
                                    "--shape: '50mmx40mmx0.01mm' is smaller than 0.1 mm",
                                    "--tilt: '1_0' is not an angle in degrees",
                                    "--tilt: '1e-400' is too small (at least 2.23e-308 degrees, or 0)",
                                    "--tilt: 'nan' is not a finite number; expected an angle within -180 to 180",
                                    "--tilt: '-inf' is not a finite number"), strict=True):
        assert_refused(run, word)
    assert not (tmp_path / "x.csv").exists()


def test_drop_with_a_shape_in_mjx_and_its_refusals(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``--engine mjx --shape``: the same foot through mudforce.engines.mjx3d (one compile, XLA's light options);
    and without ``--shape`` the 1-D mudforce.engines.mjx drop, which rests at the exact drop's depth without
    chatter (in the same subprocess: jax and MuJoCo imported once)."""
    pytest.importorskip("mujoco.mjx")
    from jax_compile import light_env

    monkeypatch.setenv("XLA_FLAGS", light_env()["XLA_FLAGS"])  # the harness passes this process's environment on
    mjx = ["drop", "--engine", "mjx", "--mass", "2kg", "--water-content", "20%", "--duration", "0.1s"]
    runs = run_batch([
        ([*mjx, "--shape", "sphere:40mm", "--tilt", "5", "--vx", "20mm/s", "--out", "m.csv"], tmp_path),
        ([*mjx, "--shape", "sphere:40mm", "--vx", "fast", "--out", "x.csv"], tmp_path),
        ([*mjx, "--shape", "sphere:40mm", "--tilt", "200", "--out", "x.csv"], tmp_path),
        ([*mjx, "--shape", "sphere:40mm", "--plot", "x.png", "--out", "x.csv"], tmp_path),
        ([*mjx[:3], "0.5kg", *mjx[4:], "--shape", "sphere:40mm", "--out", "x.csv"], tmp_path),
        (["drop", "--engine", "mjx", "--mass", "10kg", "--water-content", "20%", "--duration", "3s", "--out", "d.csv"],
         tmp_path),
    ])
    run = runs[0]
    assert run.returncode == 0 and "mjx 3-D sphere: depth" in run.stdout, run.stderr
    rows = (tmp_path / "m.csv").read_text().splitlines()
    assert rows[0] == "time_s,x_m,y_m,z_m,depth_m,vx_m_s,vz_m_s,force_x_N,force_y_N,force_z_N,tilt_deg"
    assert len(rows) == 102
    first, last = [float(v) for v in rows[1].split(",")], [float(v) for v in rows[-1].split(",")]
    assert first[5] == pytest.approx(0.02) and first[10] == pytest.approx(5.0)
    assert 0.0 < last[1] < 0.01 and last[9] == pytest.approx(2.0 * 9.81, rel=0.02)  # held, carrying m g
    assert last[4] == pytest.approx(10.7e-3, rel=0.05)  # tests/engines/test_drops3d.py: the exact drop, 10.74 mm
    for run, word in zip(runs[1:5], ("--vx", "--tilt", "--plot", "--mass"), strict=True):
        assert_refused(run, word)
    assert not (tmp_path / "x.csv").exists()
    # the 1-D engine (was tests/engines/test_mjx_drop.py's own subprocess)
    from mudforce.engines.dynamics import exact_drop
    from mudforce.model.parameters import MudParameters

    drop = runs[5]
    assert drop.returncode == 0, drop.stderr
    assert "mjx: rest depth" in drop.stdout
    with (tmp_path / "d.csv").open() as handle:
        table = list(csv.DictReader(handle))
    t = np.array([float(r["time_s"]) for r in table])
    z = np.array([float(r["depth_m"]) for r in table])
    f = np.array([float(r["force_N"]) for r in table])
    exact = exact_drop(10.0, MudParameters.from_water_content(0.20), duration=3.0)
    assert abs(z[-1] / exact.rest_depth - 1.0) <= 0.05
    assert np.std(f[t >= t[-1] - 1.0]) <= 0.02 * 10.0 * 9.81
    assert {r["state"] for r in table[-1000:]} == {"STUCK"}
