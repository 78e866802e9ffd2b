"""identify's depth noise from the record's quietest stretches (issue 23, point 4): a foot that rings between the
samples is motion, not sensor noise; the misfit flag stays quiet on it and still fires off the family."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration import Trial, identify_water_content
from mudforce.estimation.calibration.branches import (
    QUIET_FINE_MIN_SAMPLES,
    QUIET_FINE_ORDER,
    QUIET_FINE_RATIO,
    QUIET_FINE_SCALE,
    QUIET_FINE_WINDOW,
    QUIET_MIN_WINDOWS,
    QUIET_ORDER,
    QUIET_QUANTILE,
    QUIET_SCALE,
    QUIET_WINDOW,
    estimate_force_noise,
    estimate_quiet_noise,
)
from mudforce.estimation.calibration.preprocess import noise_floor, prepare_trial
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import gait
from mudforce.motions.sensor_chain import SensorChain, apply
from mudforce.steppers.simulation import simulate

W = 0.25
DEPTH_NOISE = 3e-5  # [m] the chain's
FOOT = Foot.paper()


def test_the_quantile_reads_white_noise_right() -> None:
    """On white noise alone the quiet quantile reads the noise (its scale is what it reads there); the estimate is
    then the whole record's, which it is not more than 1.5 times below."""
    from mudforce.estimation.calibration.branches import _unit_differences

    rng = np.random.default_rng(7)
    t = np.arange(200_000) * 0.01
    values = np.abs(_unit_differences(t, rng.normal(size=t.size), QUIET_ORDER))
    windows = values.size // QUIET_WINDOW
    levels = np.median(values[:windows * QUIET_WINDOW].reshape(windows, QUIET_WINDOW), axis=1) / 0.6744897501960817
    assert float(np.quantile(levels, QUIET_QUANTILE)) == pytest.approx(QUIET_SCALE, rel=0.01)


def test_the_finer_quantile_reads_white_noise_right() -> None:
    """The finer reading's scale is what its quantile of sliding windows' levels reads on white noise."""
    from mudforce.estimation.calibration.branches import _unit_differences

    rng = np.random.default_rng(9)
    t = np.arange(200_000) * 0.05
    values = np.abs(_unit_differences(t, rng.normal(size=t.size), QUIET_FINE_ORDER))
    levels = np.median(np.lib.stride_tricks.sliding_window_view(values, QUIET_FINE_WINDOW), axis=1)
    assert float(np.quantile(levels, QUIET_QUANTILE)) / 0.6744897501960817 == pytest.approx(QUIET_FINE_SCALE,
                                                                                            rel=0.01)


def test_the_finer_reading_never_takes_white_noise_low() -> None:
    """On white noise of the fewest samples it reads (and more), the finer reading is never taken: it would have to
    read under a third of the whole estimate (200 seeded records of each length)."""
    rng = np.random.default_rng(10)
    for n in (QUIET_FINE_MIN_SAMPLES, 600, 3000):
        t = np.cumsum(rng.uniform(0.04, 0.06, n))
        for _ in range(200):
            z = 3e-5 * rng.normal(size=n)
            assert estimate_quiet_noise(t, z) == estimate_force_noise(t, z)


def test_a_robot_at_20_hz_reads_its_stances_not_its_swings() -> None:
    """A MuJoCo trot at 20 Hz: a stance lasts five samples between swings of centimetres, every window of fifth
    differences holds a swing, and the whole record read 1.44 mm for 0.03 mm of noise; the finer reading reads the
    stances, and identify's interval holds the truth (it held it before too, read from 1.4 mm)."""
    pytest.importorskip("mujoco")
    from mudforce.motions.quadruped import ROBOT_FOOT, robot_walk

    run = robot_walk("trot", W, seed=3, duration=10.0)
    chain = SensorChain(force_noise=0.2, depth_noise=DEPTH_NOISE, force_bias=0.4, rate=20.0)
    tt, zz, ff = apply(run.time, run.depth, run.force_contact, chain, 5)
    whole = estimate_force_noise(tt, zz)
    read = estimate_quiet_noise(tt, zz)
    assert whole > 30 * DEPTH_NOISE  # measured 1.44 mm
    assert whole > QUIET_FINE_RATIO * read and DEPTH_NOISE < read < 5 * DEPTH_NOISE  # measured 0.097 mm
    res = identify_water_content(Trial("trot", W, tt, zz, ff), ROBOT_FOOT)
    assert res.depth_noise == read
    assert res.unresolved_depth == pytest.approx(np.sqrt(whole**2 - read**2), rel=1e-12)
    assert res.low <= W <= res.high  # measured 25.03 % [23.12, 27.76]
    # too few samples for the finer reading: the whole record's estimate, as before
    short = QUIET_FINE_MIN_SAMPLES - 1
    assert estimate_quiet_noise(tt[:short], zz[:short]) == estimate_force_noise(tt[:short], zz[:short])


def test_stationary_noise_keeps_the_whole_estimate_bit_for_bit() -> None:
    rng = np.random.default_rng(8)
    # 0.3 mm of white noise on a smooth swing, jittered stamps: stationary, so the whole record's estimate, exactly
    t = np.cumsum(rng.uniform(0.007, 0.013, 2000))
    z = 0.02 * np.sin(2.0 * np.pi * 1.3 * t) + 3e-4 * rng.normal(size=t.size)
    assert estimate_quiet_noise(t, z) == estimate_force_noise(t, z) == pytest.approx(3e-4, rel=0.1)
    # half the record ten times noisier: the quiet half's noise (within its scatter), not the median's mixture
    z2 = z + np.where(t > t[1000], 3e-3, 0.0) * rng.normal(size=t.size)
    assert estimate_force_noise(t, z2) > 2 * 3e-4  # the median of the mixture: 0.72 mm
    # (the quantile then sits in the quiet half's lower fifth: measured 0.42 mm)
    assert 3e-4 < estimate_quiet_noise(t, z2) < 1.6 * 3e-4
    # too few windows for a low quantile: the whole record's estimate
    short = QUIET_MIN_WINDOWS * QUIET_WINDOW + QUIET_ORDER - 1
    assert estimate_quiet_noise(t[:short], z2[:short]) == estimate_force_noise(t[:short], z2[:short])


@pytest.fixture(scope="module")
def ringing() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A 10-s gait whose foot rings every 0.6 s (an 11-Hz bounce of 2 mm, decaying in 0.12 s), at 2 kHz: time
    [s], depth [m], the model's force [N] and a granular law's ``F = k z`` [N] along it."""
    path = gait(5, duration=10.0, rate=2000.0)
    t, z = path.time, path.depth.copy()
    for k in np.searchsorted(t, np.arange(0.3, 10.0, 0.6)):
        s = t[k:] - t[k]
        z[k:] += 0.002 * np.sin(2.0 * np.pi * 11.0 * s) * np.exp(-s / 0.12)
    f = np.asarray(simulate(t, z, MudParameters.from_water_content(W), FOOT, velocity_filter="exact").force)
    kz = float(np.max(f)) / float(np.max(z)) * np.maximum(z, 0.0)
    return t, z, f, kz


def _at_50_hz(t: np.ndarray, z: np.ndarray, f: np.ndarray) -> Trial:
    chain = SensorChain(force_noise=0.2, depth_noise=DEPTH_NOISE, force_bias=0.3, rate=50.0)
    tt, zz, ff = apply(t, z, f, chain, 11)
    return Trial("ringing", W, tt, zz, ff)


def test_a_ringing_foot_at_50_hz_reads_its_noise_and_is_not_flagged(
        ringing: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    t, z, f, _ = ringing
    trial = _at_50_hz(t, z, f)
    # the whole record's differences read the ringing as noise (measured 0.092 mm); its quietest stretches do not
    assert estimate_force_noise(trial.time, trial.depth) > 2.5 * DEPTH_NOISE
    prepared = prepare_trial(trial, depth_noise_from="quiet")
    assert DEPTH_NOISE / 2.0 < prepared.depth_noise < 2.0 * DEPTH_NOISE  # measured 0.048 mm
    whole = estimate_force_noise(trial.time, trial.depth)
    assert prepared.unresolved_depth == pytest.approx(np.sqrt(whole**2 - prepared.depth_noise**2), rel=1e-12)
    res = identify_water_content(trial, FOOT)
    assert res.depth_noise == prepared.depth_noise and res.unresolved_depth == prepared.unresolved_depth
    assert res.to_dict()["unresolved_depth_m"] == prepared.unresolved_depth
    # given, the noise is the robot's, and nothing is left unresolved
    assert prepare_trial(trial, depth_noise=DEPTH_NOISE, depth_noise_from="quiet").unresolved_depth == 0.0
    assert not res.model_misses_data and res.misfit_ratio < 1.25  # measured 1.03 (1.17 from the whole)
    assert res.low <= W <= res.high and abs(res.water_content - W) < 0.005


def test_off_the_family_on_the_same_ringing_path_is_still_flagged(
        ringing: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    t, z, _, kz = ringing
    res = identify_water_content(_at_50_hz(t, z, kz), FOOT)
    assert res.model_misses_data and res.misfit_ratio > 2.5  # measured 3.47


def test_the_unresolved_motion_enters_the_floor_as_depth_noise_would() -> None:
    """noise_floor carries the unresolved motion through the model's sensitivity to the depth, in quadrature with
    the white noise: the same floor as the whole estimate as depth noise."""
    w = gait(2, duration=3.0, rate=100.0)
    trial = Trial("g", W, w.time, w.depth, np.zeros_like(w.depth) + 0.1)
    prepared = prepare_trial(trial, protocol=False, depth_noise=4e-5)

    def force_at(depth: np.ndarray) -> np.ndarray:
        out: np.ndarray = 1e4 * np.maximum(depth, 0.0) ** 1.5
        return out

    split = replace(prepared, depth_noise=3e-5, unresolved_depth=4e-5 * np.sqrt(1.0 - (3.0 / 4.0) ** 2))
    np.testing.assert_allclose(noise_floor(split, prepared.force, force_at),
                               noise_floor(prepared, prepared.force, force_at), rtol=1e-12, atol=0.0)


def test_an_unknown_rule_is_refused_in_one_line() -> None:
    w = gait(2, duration=1.0, rate=100.0)
    trial = Trial("g", W, w.time, w.depth, np.ones_like(w.depth))
    with pytest.raises(InputError, match='depth_noise_from must be "all" or "quiet", got \'some\'') as info:
        prepare_trial(trial, depth_noise_from="some")
    assert "\n" not in str(info.value)
