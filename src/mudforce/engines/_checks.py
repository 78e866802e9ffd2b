"""Checks of the dynamics' inputs and outputs, shared by the built-in engine, the naive drop and MuJoCo.

Each raises :class:`mudforce.errors.InputError` with one line naming the
problem and what is expected, for bad values and bad types alike.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mudforce.errors import InputError, finite_number
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

__all__ = ["check_finite_output", "check_foot", "check_mass", "check_params", "min_stable_mass"]

def check_params(params: Any) -> MudParameters:
    """``params`` if it is a :class:`MudParameters`, else InputError."""
    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    return params


def check_foot(foot: Any) -> Foot:
    """``foot`` if it is a :class:`Foot`, the paper's cuboid if ``None``, else InputError."""
    if foot is None:
        return Foot.paper()
    if not isinstance(foot, Foot):
        raise InputError(f"foot must be a Foot (or None for the paper's cuboid), got {type(foot).__name__}")
    return foot


def min_stable_mass(params: MudParameters, foot: Foot, step: float) -> float:
    """Lightest foot [kg] whose motion a time step of ``step`` [s] resolves: ``m = S max(k_m_i, k_m_w) h^2``.

    A foot of mass ``m`` on the Maxwell spring (Eq. (2)) oscillates at
    ``omega = sqrt(S k_m / m)``; an explicit step ``h`` follows it only
    while ``h omega <= 1`` (RK4 loses stability at 2.8, a semi-implicit
    step at 2; below that it is inaccurate).
    """
    return foot.area * max(params.k_m_i, params.k_m_w) * step * step


def check_mass(mass: Any, params: MudParameters, foot: Foot, step: float, what: str) -> float:
    """``mass`` [kg] as a float if it is a finite number of at least :func:`min_stable_mass`, else InputError.

    ``what`` names the step in the message (``"RK4 sub-step"``, ``"MuJoCo time step"``).
    """
    m = finite_number(mass, "mass", "kg", positive=True)
    lightest = min_stable_mass(params, foot, step)
    if m < lightest:
        raise InputError(f"mass {m:g} kg is too light for a {what} of {step:g} s in this mud: the step resolves "
                         f"the foot's oscillation on the mud only from {lightest:.3g} kg (h sqrt(S k_m / m) <= 1); "
                         "use a heavier foot or a shorter step")
    return m


def check_finite_output(engine: str, time: np.ndarray, *arrays: np.ndarray) -> None:
    """InputError naming the first sample time [s] at which any of ``arrays`` is not finite (a diverged solution)."""
    bad = np.zeros(time.shape, dtype=bool)
    for a in arrays:
        bad |= ~np.isfinite(a)
    if bad.any():
        k = int(np.argmax(bad))
        raise InputError(f"the {engine} engine's solution is not finite from t = {time[k]:g} s: the inputs are "
                         "outside what its step can resolve (a lighter foot, a stiffer mud or a longer step "
                         "than it can follow); use a heavier foot or a shorter step")
