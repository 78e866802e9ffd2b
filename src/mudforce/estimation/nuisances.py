"""What a robot's sensor chain does to a recording that the estimators allow for, shared by the offline
(:mod:`mudforce.estimation.calibration.identify`) and online (:mod:`mudforce.estimation.tracker`) estimators.

A light module (no scipy): the tracker imports it without the calibration package. The force lag's first-order
low-pass (:func:`_lowpass_coefficients`, :func:`_lowpass_step`) is written here once for both: identify's model of a
recording and the tracker's hypotheses step it (the sensor chain's corruption, :mod:`mudforce.motions.sensor_chain`,
keeps its own, the truth the two are tested against).
"""

from __future__ import annotations

import math

import numpy as np

from mudforce._plumbing.jit import njit
from mudforce.errors import InputError, is_real, shown

__all__ = ["DEFAULT_FORCE_GAIN_UNCERTAINTY", "REST_SPEED", "check_force_gain_uncertainty"]

#: Default uncertainty of the force sensor's gain [-] (5 %): a gain error reads as stiffer or softer mud, so its
#: water-content shift widens the interval (identify's about the gain it reads where the recording determines one).
DEFAULT_FORCE_GAIN_UNCERTAINTY = 0.05
#: A step in the mud slower than this counts as the foot at rest [m/s] (5 mm/s): its force is a band, not a branch.
REST_SPEED = 0.005


def check_force_gain_uncertainty(g: float) -> None:
    """Refuse a force gain uncertainty ``g`` [-] outside [0, 0.5) in one line (identify's and fit's check)."""
    if not is_real(g) or not 0.0 <= g < 0.5:  # a string or None raised TypeError, False read as 0
        raise InputError(f"force gain uncertainty must be in [0, 0.5) (e.g. 0.05 for 5 %), got {shown(g)}")


def check_force_varies(force: np.ndarray, where: str, what: str, context: str = "") -> None:
    """Refuse a ``force`` [N] the same in every sample in one line (identify's and track's check): a force column that
    reads one value throughout (a sensor unplugged, the wrong column) carries nothing to read a water content from.
    ``where``: the message's prefix (a trial's ``"name: "``); ``what``: the recording's noun; ``context``: said after
    the value."""
    if force.size and not np.any(force != force[0]):
        raise InputError(f"{where}the force is the same in every sample ({float(force[0]):.3g} N){context}: the {what} "
                         "carries no force to identify a water content from (is the column right?)")


@njit(cache=True, nogil=True, error_model="numpy")
def _lowpass_coefficients(dt: float, lag: float) -> tuple[float, float]:
    """``(e, c)`` of :func:`_lowpass_step` for a step of ``dt`` [s] and a lag ``lag`` > 0 [s]:
    ``e = exp(-dt / lag)``, ``c = (1 - e) lag / dt`` (the latter through ``expm1``)."""
    return math.exp(-dt / lag), -math.expm1(-dt / lag) * lag / dt


@njit(cache=True, nogil=True, error_model="numpy")
def _lowpass_step(e: float, c: float, y0: float, f0: float, f1: float) -> float:
    """One step of the first-order low-pass ``lag y' + y = F`` (the force lag, ours), exact for a force linear over
    the step from ``f0`` to ``f1`` [N]: ``y1 = e y0 + (1 - c) f1 - (e - c) f0`` [N], with ``(e, c)`` of
    :func:`_lowpass_coefficients`."""
    return e * y0 + (1.0 - c) * f1 - (e - c) * f0
