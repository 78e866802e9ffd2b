"""identify with the depth noise given (issue 23, point 7: what a robot should log): used in place of the estimate,
reported, and refused in one line when it makes no sense."""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration import Trial, identify_water_content
from mudforce.estimation.calibration.preprocess import prepare_trial
from mudforce.motions.gait import walk

W = 0.24


@pytest.fixture(scope="module")
def trial() -> Trial:
    w = walk(W, seed=3, duration=4.0, force_noise=0.2, depth_noise=3e-5, bias=0.4)
    return Trial("walk", W, w.time, w.depth, w.force)


def test_given_depth_noise_is_used_and_reported(trial: Trial) -> None:
    given = identify_water_content(trial, depth_noise=5e-5)
    assert given.depth_noise == 5e-5 and given.to_dict()["depth_noise_m"] == 5e-5
    assert given.low <= W <= given.high and abs(given.water_content - W) < 0.005
    # estimated (a walk that does not ring: the estimate is the noise), or given; a prepared trial holds its own
    assert prepare_trial(trial).depth_noise == pytest.approx(3e-5, rel=0.3)
    prepared = prepare_trial(trial, depth_noise=5e-5)
    assert prepared.depth_noise == 5e-5
    with pytest.raises(InputError, match="already holds its depth noise"):
        identify_water_content(prepared, depth_noise=5e-5)


@pytest.mark.parametrize("bad", [-1e-5, 0.02, float("nan")])
def test_bad_depth_noise_is_refused(trial: Trial, bad: float) -> None:
    with pytest.raises(InputError, match="depth noise must be between 0 and 10 mm") as info:
        prepare_trial(trial, depth_noise=bad)
    assert "\n" not in str(info.value)
    assert np.isfinite(trial.depth).all()  # the trial is left as it was
