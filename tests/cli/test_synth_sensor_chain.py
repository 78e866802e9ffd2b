"""mudforce synth's sensor-chain options (--depth-offset, --drift, --force-lag, --force-gain with --rate): what
they write, that --seed reproduces it, that dataset.json records them, and one-line refusals of bad values."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from mudforce.estimation.calibration import load_dataset
from mudforce_cli_harness import assert_refused, run_batch

CLEAN = ["--force-noise", "0N", "--depth-noise", "0mm", "--bias", "0N", "--velocities", "20mm/s", "--repeats", "1",
         "--hold", "1s"]
ROBOT = ["--motion", "gait", "--duration", "8s", "--repeats", "1", "--rate", "50Hz", "--seed", "4",
         "--depth-offset", "-2mm", "--drift", "2mm/60s", "--force-lag", "lowpass:10ms,delay:5ms", "--force-gain", "+5%"]

BAD = [
    (["--force-lag", "fast"], ("--force-lag", "delay:5ms")),
    (["--force-lag", "delay:1ms,delay:2ms"], ("--force-lag", "each kind once")),
    (["--force-lag", "delay:2s"], ("--force-lag delay", "[0, 1] s")),
    (["--force-lag", "10"], ("--force-lag", "'10'", "low-pass", "has no unit")),
    # a time that is read but out of range was "cannot read 'delay:-5ms' ... as a delay time"
    (["--force-lag", "delay:-5ms"], ("--force-lag: 'delay:-5ms' in 'delay:-5ms' is no delay time ('-5ms' must not be "
                                     "negative)", "delay:5ms")),
    (["--force-gain", "3"], ("--force-gain", "[0.5, 2]")),
    (["--force-gain", "-60%"], ("--force-gain", "0.4")),
    (["--force-gain", "abc"], ("--force-gain", "+5%")),
    (["--depth-offset", "200mm"], ("--depth-offset", "[-0.1, 0.1] m")),
    (["--drift", "2mm/0.5s"], ("--drift (the time after /)", "[1, 3600] s")),
    (["--drift", "2mm/"], ("--drift",)),
    (["--motion", "gait", "--jitter", "0.3", "--force-gain", "1.05"], ("--jitter", "regular clock")),
    (["--motion", "gait", "--duration", "3600s", "--drift", "100mm/1s"], ("--drift", "100 m")),
]


def test_synth_writes_the_sensor_chain_reproducibly_and_records_it(tmp_path: Path) -> None:
    cases = [
        (["synth", "--out", "robot_a", *ROBOT], tmp_path),
        (["synth", "--out", "robot_b", *ROBOT], tmp_path),
        (["synth", "--out", "plain", *CLEAN], tmp_path),
        (["synth", "--out", "offset", *CLEAN, "--depth-offset", "2mm"], tmp_path),
        (["synth", "--out", "gain", *CLEAN, "--force-gain", "1.05"], tmp_path),
        *[(["synth", "--out", f"bad{i}", *argv], tmp_path) for i, (argv, _) in enumerate(BAD)],
    ]
    runs = run_batch(cases)
    for run in runs[:5]:
        assert run.returncode == 0, run.stderr
    for run, (_, words) in zip(runs[5:], BAD, strict=True):
        assert_refused(run, *words)
    assert not any((tmp_path / f"bad{i}").exists() for i in range(len(BAD)))

    a, b = tmp_path / "robot_a", tmp_path / "robot_b"
    assert sorted(p.name for p in a.iterdir()) == sorted(p.name for p in b.iterdir())
    assert all((a / p.name).read_bytes() == (b / p.name).read_bytes() for p in a.iterdir())
    chain = json.loads((a / "dataset.json").read_text())["synthetic"]["sensor_chain"]
    assert chain == {"depth_offset_m": -0.002, "drift_m": 0.002, "drift_time_s": 60.0, "force_delay_s": 0.005,
                     "force_lowpass_s": 0.01, "force_gain": 1.05, "fine_rate_Hz": 2000.0}
    trial = load_dataset(a).trials[0]
    assert trial.time.size == 401 and np.allclose(np.diff(trial.time), 0.02, rtol=0, atol=1e-9)

    plain, offset, gain = (load_dataset(tmp_path / n).trials[0] for n in ("plain", "offset", "gain"))
    assert "sensor_chain" not in json.loads((tmp_path / "plain" / "dataset.json").read_text())["synthetic"]
    # the same fine model sampled at 100 Hz: the offset shifts every depth, the gain scales every force
    assert offset.time.size == gain.time.size and np.array_equal(offset.time, gain.time)
    n = offset.time.size
    np.testing.assert_allclose(offset.depth - gain.depth, 0.002, rtol=0, atol=2e-9)
    np.testing.assert_allclose(gain.force, 1.05 * offset.force, rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(plain.time[:n], offset.time, rtol=0, atol=1e-9)  # the same clock as without a chain
    np.testing.assert_allclose(plain.force[:n], offset.force, rtol=0, atol=1e-6)
