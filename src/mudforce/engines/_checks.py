"""Checks of the engines' inputs and outputs, shared by the built-in engine, the naive drop, MuJoCo and MJX.

Each raises :class:`mudforce.errors.InputError` with one line naming the
problem and what is expected, for bad values and bad types alike.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from mudforce.errors import InputError, finite_number, number_within, positive_int, shown
from mudforce.model.bounds import MAX_DEPTH, bounded_depth, check_step
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

__all__ = ["MAX_NSTEP", "check_finite_output", "check_foot", "check_mass",
           "check_params", "drop_numbers", "drop_thickness", "min_stable_mass", "name_list",
           "step_count"]


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


def min_stable_mass(params: MudParameters, foot: Foot | float, step: float) -> float:
    """Lightest foot [kg] whose motion a time step of ``step`` [s] resolves: ``m = S max(k_m_i, k_m_w) h^2``.

    A foot of mass ``m`` on the Maxwell spring (Eq. (2)) oscillates at
    ``omega = sqrt(S k_m / m)``; an explicit step ``h`` follows it only
    while ``h omega <= 1`` (RK4 loses stability at 2.8, a semi-implicit
    step at 2; below that it is inaccurate).

    ``foot``: a :class:`Foot` (``S`` its area), or a 3-D foot's loaded area ``S`` [m^2] itself: the 3-D law puts
    each element on the paper's spring over its downward-facing projection ``A_i max(-n_z, 0)``
    (:func:`mudforce.model.law3d.vertical_weight`), so its stiffest is ``k_m`` times their sum, the foot's
    horizontal projection (a flat sole's whole area once it is wet).
    """
    area = foot.area if isinstance(foot, Foot) else foot
    return area * max(params.k_m_i, params.k_m_w) * step * step


def check_mass(mass: Any, params: MudParameters, foot: Foot | float, step: float, what: str) -> float:
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


def name_list(feet: Any) -> list[str]:
    """``feet`` (one name or a sequence of names) as a list of distinct strings, else InputError."""
    if isinstance(feet, str):
        return [feet]
    if not isinstance(feet, Sequence) or not feet or not all(isinstance(f, str) for f in feet):
        raise InputError(f"feet must be a name or a non-empty sequence of names (str), got {shown(feet)}")
    if len(set(feet)) != len(feet):
        raise InputError(f"feet must be distinct names, got {shown(list(feet))}")
    return list(feet)


def drop_numbers(mass: Any, height: Any, dt: Any) -> tuple[float, float, float]:
    """A drop model's ``mass`` [kg] (> 0), release ``height`` [m] (>= 0, within the steppers' depth bound) and
    step ``dt`` [s] (within the steppers' [MIN_DT, MAX_DT]) as floats, else InputError: both adapters' drops refuse
    the same numbers (a release 1e12 m up and a step of 1e-300 s were taken)."""
    mass = finite_number(mass, "mass", "kg", positive=True)
    height = finite_number(bounded_depth(height, "height", of=" of the mud surface"), "height", "m", nonnegative=True)
    dt = finite_number(dt, "dt", "s", positive=True)
    check_step(dt)
    return mass, height, dt


def drop_thickness(thickness: Any) -> float:
    """A drop foot's ``thickness`` [m] as a float within [1e-6, :data:`~mudforce.model.bounds.MAX_DEPTH`], else
    InputError: the steppers' bound on a length (a foot 1e-12 m thick ended in MuJoCo's ValueError), for both
    1-D drop models (MuJoCo's and MJX's)."""
    return number_within(finite_number(thickness, "thickness", "m", positive=True), "thickness", 1e-6, MAX_DEPTH,
                         "m")


#: Most MuJoCo steps one adapter call takes [-]: MuJoCo's C int, as ``mujoco.mj_step``'s own ``nstep`` (beyond it
#: mj_step raises TypeError; the adapters' Python loop took 10**30 and ran for ever).
MAX_NSTEP = 2**31 - 1


def step_count(nstep: Any) -> int:
    """An adapter's ``nstep`` as an int in [1, :data:`MAX_NSTEP`] (not bool), else InputError."""
    count = positive_int(nstep, "nstep")
    if count > MAX_NSTEP:
        raise InputError(f"nstep must be at most {MAX_NSTEP} (MuJoCo's mj_step takes a C int), got {shown(count)}")
    return count
