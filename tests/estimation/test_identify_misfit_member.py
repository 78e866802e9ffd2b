"""identify's misfit flag reads the statistic at the member of the interval that explains the data best (issue 23,
point 4): each residual over its own floor, the force bias re-profiled under those weights.

The recording (tests/estimation/data/robot_bound_dry_seed1.csv) is the sensor-chain bench's robot 4 of seed 1: the
front-left foot of the MuJoCo quadruped (``mudforce.motions.quadruped``, gait ``bound``, a 50 mm disc) in dry mud,
W = 16.12 %, with the vertical force MuJoCo applied, through ``SensorChain(force_noise=0.2, depth_noise=3e-5,
force_bias=...)`` at 100 Hz: 10 s. Least squares reads 19.91 % (a few samples whose floor is tens of newtons, a
stuck foot read on a branch, pull it; covered by the interval [15.00, 28.35]); at that estimate the samples whose
floor is the force noise read the pull as misfit, 2.85 floors, and the flag fired. The statistic at its smallest
over the interval: 0.86 at 16.14 %, not flagged; F = k z along the same samples is (measured 2.96).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mudforce.estimation.calibration import Identification, identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.identify import _bias_reprofiled
from mudforce.model.foot import Foot

TRUTH = 0.161183
DATA = Path(__file__).parent / "data" / "robot_bound_dry_seed1.csv"
FOOT = Foot.disc(0.05)


@pytest.fixture(scope="module")
def recording() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t, z, f = np.loadtxt(DATA, delimiter=",", skiprows=1, unpack=True)
    return t, z, f


@pytest.fixture(scope="module")
def clean(recording: tuple[np.ndarray, np.ndarray, np.ndarray]) -> Identification:
    return identify_water_content(Trial("robot.csv", TRUTH, *recording), FOOT)


def test_the_bias_is_reprofiled_under_the_statistics_weights() -> None:
    """Every sample inside its cap: the re-profiled bias is the weighted mean, and the statistic its closed form."""
    rng = np.random.default_rng(3)
    model = rng.uniform(-20.0, 60.0, 200)
    variance = rng.uniform(0.04, 4.0, 200)
    r0 = 0.8 + np.sqrt(variance) * rng.uniform(-1.0, 1.0, 200)  # a bias of 0.8 N, every sample within 1.8 floors
    none = np.zeros(200, dtype=bool)
    d = np.sum(r0 / variance) / np.sum(1.0 / variance)
    expected = np.mean((r0 - d) ** 2 / variance)
    got = _bias_reprofiled(model, model, model, model - r0, none, variance, none)
    assert got == pytest.approx(expected, rel=1e-12)
    assert got < np.mean(r0**2 / variance)


def test_samples_out_of_the_mud_are_never_given_up() -> None:
    """Every sample 10 floors off: capped, none moves the bias (the statistic stays at its cap, 25); read as out of
    the mud (the model's force nil) they set it, and the statistic is their scatter about their mean."""
    variance = np.ones(50)
    r0 = 10.0 + np.linspace(-0.5, 0.5, 50)
    zero, none, every = np.zeros(50), np.zeros(50, dtype=bool), np.ones(50, dtype=bool)
    assert _bias_reprofiled(zero, zero, zero, zero - r0, none, variance, none) == 25.0
    expected = np.mean((r0 - np.mean(r0)) ** 2)
    assert _bias_reprofiled(zero, zero, zero, zero - r0, none, variance, every) == pytest.approx(expected, rel=1e-9)


def test_a_stuck_foot_that_pulls_the_estimate_is_not_another_mud(clean: Identification) -> None:
    assert clean.water_content == pytest.approx(0.1991, abs=5e-4)  # least squares, as before this change
    assert clean.low <= TRUTH <= clean.high
    assert abs(clean.misfit_water_content - TRUTH) < 0.002  # measured 16.14 % for 16.12 %
    assert not clean.model_misses_data and clean.misfit_ratio < 1.0  # measured 0.86 (2.85 at the estimate)
    assert clean.to_dict()["misfit_water_content"] == clean.misfit_water_content


def test_a_granular_law_along_the_same_samples_is_flagged(recording: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
    t, z, f = recording
    inside = np.maximum(z, 0.0)
    kz = np.max(f) / np.max(inside) * inside + 0.2 * np.random.default_rng(4).standard_normal(z.size)
    res = identify_water_content(Trial("kz.csv", TRUTH, t, z, kz), FOOT)
    assert res.model_misses_data and res.misfit_ratio > 2.5  # measured 2.96
    assert res.low <= res.misfit_water_content <= res.high
