"""identify's misfit flag means off-family (issue 23, point 4): quiet on clean in-family walks,
raised on a granular law F = k z and on a mud with alpha x2 and sigma_y x0.3 along the same path."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mudforce.estimation.calibration import identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import Walk, walk
from mudforce.steppers.simulation import simulate

CASES = ((1, 0.18), (2, 0.24), (3, 0.30))


@pytest.fixture(scope="module")
def walks() -> list[Walk]:
    """Three clean 10-s walks at 50 Hz (0.2 N force noise, 30 um depth noise)."""
    return [walk(w, seed=seed, duration=10.0, rate=50.0) for seed, w in CASES]


def _identify(wk: Walk, force: np.ndarray) -> tuple[bool, float]:
    res = identify_water_content(Trial("walk.csv", float(wk.water_content[0]), wk.time, wk.depth, force))
    return res.model_misses_data, res.misfit_ratio


def test_quiet_on_clean_in_family_walks(walks: list[Walk]) -> None:
    """In family the RMSE is the noise: the ratio is near 1 (measured 0.80-0.93; 0.68-0.78 since it is read at the
    best member, the depth offset and force lag refitted there) and nothing is flagged."""
    for wk in walks:
        flagged, ratio = _identify(wk, wk.force)
        assert not flagged and 0.6 < ratio < 1.1


def test_fires_on_a_granular_law(walks: list[Walk]) -> None:
    """F = k z with k matching the peak, the same noise: flagged on every walk (measured ratio >= 28 before each
    sample's square was capped at 25, so that the ratio is at most 5; then >= 3.6; read at the best member, the
    depth offset and force lag refitted there, >= 3.49)."""
    rng = np.random.default_rng(7)
    for wk in walks:
        z = np.maximum(wk.depth_true, 0.0)
        force = np.max(wk.force_true) / np.max(z) * z + 0.2 * rng.standard_normal(z.size)
        flagged, ratio = _identify(wk, force)
        assert flagged and ratio > 3.0


def test_fires_on_a_mud_outside_table_one(walks: list[Walk]) -> None:
    """alpha x2 and sigma_y x0.3 along the same path: flagged on every walk (measured ratio >= 8 uncapped, >= 3.8
    with each sample's square capped at 25; 2.61, 3.49 and 3.68 read at the best member, the depth offset and force
    lag refitted there)."""
    rng = np.random.default_rng(8)
    for wk in walks:
        q = wk.params[0]
        odd = dataclasses.replace(q, alpha=2.0 * q.alpha, sigma_y=0.3 * q.sigma_y)
        force = np.asarray(simulate(wk.time, wk.depth_true, odd, Foot.paper(), velocity_filter="exact").force)
        flagged, ratio = _identify(wk, force + 0.2 * rng.standard_normal(force.size))
        assert flagged and ratio > 2.5


def test_a_local_discretisation_error_does_not_mask_an_off_family_mud() -> None:
    """At 100 Hz (seed 2) the half-rate model leaves the data's for a few strides (disc. error ~5 N RMS).

    Added to one global floor it hid this off-family mud (ratio 0.69, silent); each sample weighed by
    its own floor, the mud is flagged.
    """
    wk = walk(0.24, seed=2, duration=10.0, rate=100.0)
    q = MudParameters.from_water_content(0.24)
    odd = dataclasses.replace(q, alpha=2.0 * q.alpha, sigma_y=0.3 * q.sigma_y)
    force = np.asarray(simulate(wk.time, wk.depth_true, odd, Foot.paper(), velocity_filter="exact").force)
    res = identify_water_content(Trial("walk.csv", 0.24, wk.time, wk.depth,
                                       force + 0.2 * np.random.default_rng(2).standard_normal(force.size)))
    assert res.discretisation > 1.0
    # measured 3.95 (each sample capped at 5 floors); 2.71 read at the best member, offset and lag refitted there
    assert res.model_misses_data and res.misfit_ratio > 2.5
