"""is_protocol's floor: the least RMS of a depth about any rise-then-fall, and the same answers as the corner search.

:func:`_unimodal_rms` lets :func:`is_protocol` turn a gait away without :func:`fit_motion`'s corner search (speed
plumbing: an identify of a 30-s gait spent a fifth of its time there). It must be a floor: every motion the search
accepts rises and then falls, so its RMS residual is at least the floor, and a trial the floor turns away is one the
search turns away too.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import isotonic_regression

from mudforce.errors import InputError
from mudforce.estimation.calibration import fit_motion
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.preprocess import _increasing_sse, _unimodal_rms, is_protocol
from mudforce.estimation.calibration.synth import synthesize
from mudforce.model.velocity import estimate_depth_noise
from mudforce.motions.gait import gait


def _sse(z: np.ndarray, increasing: bool = True) -> float:
    """Sum of squares about scipy's isotonic regression (an independent solver)."""
    if z.size == 0:
        return 0.0
    return float(np.sum((z - isotonic_regression(z, increasing=increasing).x) ** 2))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=0, max_size=40))
def test_the_prefix_sums_of_squares_are_scipys_isotonic_regression(values: list[float]) -> None:
    z = np.array(values, dtype=float)
    got = _increasing_sse(z)
    want = np.array([_sse(z[:k]) for k in range(z.size + 1)])
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0, allow_nan=False), min_size=1, max_size=30))
def test_the_floor_is_the_best_rise_then_fall(values: list[float]) -> None:
    z = np.array(values, dtype=float)
    best = min(_sse(z[:k]) + _sse(z[k:], increasing=False) for k in range(z.size + 1))
    assert _unimodal_rms(z) == pytest.approx(np.sqrt(best / z.size), rel=1e-9, abs=1e-12)


def _corner_search(trial: Trial) -> object:
    """is_protocol as it was before the floor: the corner search, then the residual against the depth noise."""
    try:
        motion = fit_motion(trial.time, trial.depth, name=trial.name)
    except InputError:
        return None
    noise = estimate_depth_noise(trial.time, trial.depth)
    return None if motion.depth_noise > 1.5 * noise + 1e-7 else motion


@pytest.mark.parametrize("rate", [50.0, 1000.0])
@pytest.mark.parametrize("depth_noise", [3e-5, 1e-3])
def test_protocols_lie_above_the_floor_and_are_recognised_as_before(rate: float, depth_noise: float) -> None:
    for trial in synthesize(seed=3, depth_noise=depth_noise, repeats=1, rate=rate,
                            water_contents=(0.2,), velocities=(0.01, 0.03)).trials:
        before = _corner_search(trial)
        assert before is not None
        assert is_protocol(trial) == before
        assert _unimodal_rms(trial.depth) <= before.depth_noise  # type: ignore[attr-defined]


@pytest.mark.parametrize("seed", [1, 2])
def test_a_gait_is_turned_away_by_the_floor_as_by_the_search(seed: int) -> None:
    path = gait(seed, duration=8.0, rate=100.0)
    depth = path.depth + np.random.default_rng(seed).normal(0.0, 3e-5, path.depth.size)
    trial = Trial("gait", 0.25, path.time, depth, np.zeros_like(depth))
    assert _corner_search(trial) is None
    assert is_protocol(trial) is None
    assert _unimodal_rms(depth) > 10.0 * estimate_depth_noise(trial.time, depth)
