"""identify's discretisation floor from a refined interpolation (issue 23, point 4): the model on the recording
against the model on a cubic spline of it through the samples.

The stepper takes the depth as linear between two samples. On a linear motion the spline is that line, so the
two agree to rounding; on a curved one their difference is the model's error at the data's rate to leading
order: it falls as the step squared, and it is most of the difference from the model on the true path.
"""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.estimation.calibration._recording_model import _force_and_band, _refined_run
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

Q = MudParameters.from_water_content(0.25)
FOOT = Foot.paper()


def _refined_force_and_band(t: np.ndarray, depth: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model of ``Q`` [N] run on a cubic spline of ``depth`` [m] through the samples ``t`` [s], no lag."""
    return _refined_run(t, depth, lambda tt, zz: _force_and_band(tt, zz, Q, FOOT, 0.0))


def _depth(t: np.ndarray) -> np.ndarray:
    """A descent that speeds up [m]: 2 mm in, then 30 mm/s^2 (curved, never turning)."""
    out: np.ndarray = 0.002 + 0.03 * t**2
    return out


def _difference(rate: float) -> tuple[float, float]:
    """(refined - recording, true path - recording) [N], largest over one second at ``rate`` [Hz]."""
    t = np.arange(0.0, 1.0 + 1e-9, 1.0 / rate)
    own = _force_and_band(t, _depth(t), Q, FOOT, 0.0)[0]
    ref = _refined_force_and_band(t, _depth(t))[0]
    fine = np.linspace(0.0, t[-1], 64 * (t.size - 1) + 1)
    true = _force_and_band(fine, _depth(fine), Q, FOOT, 0.0)[0][::64]
    return float(np.max(np.abs(ref - own))), float(np.max(np.abs(true - own)))


def test_linear_motion_has_no_discretisation_error() -> None:
    t = np.arange(0.0, 1.0 + 1e-9, 0.02)
    depth = 0.002 + 0.02 * t
    for own, ref in zip(_force_and_band(t, depth, Q, FOOT, 0.0), _refined_force_and_band(t, depth),
                        strict=True):
        np.testing.assert_allclose(ref, own, rtol=0.0, atol=1e-9)


def test_the_floor_is_second_order_and_tracks_the_true_error() -> None:
    coarse, true_coarse = _difference(50.0)
    fine, _ = _difference(100.0)
    assert coarse > 1e-4  # a real, if small, error on this gentle curve [N]
    assert coarse / fine == pytest.approx(4.0, rel=0.05)  # halving the step quarters it
    # the spline puts four steps in each: it sees 1 - 1/16 of the error to the true path
    assert coarse == pytest.approx(true_coarse * (1.0 - 1.0 / 16.0), rel=0.05)
