"""Checks of what both MuJoCo adapters (1-D :mod:`mudforce.engines.mujoco`, 3-D
:mod:`mudforce.engines.mujoco.adapter3d`) take when they edit a spec: plumbing, no physics."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from mudforce._plumbing.optional import require
from mudforce.errors import InputError, finite_number, number_within
from mudforce.model.bounds import MAX_DEPTH, bounded_depth, check_step

__all__ = ["check_prefix", "drop_numbers", "drop_thickness", "mujoco_module", "name_list"]


def mujoco_module() -> Any:
    """The ``mujoco`` package, or a one-line error saying how to install it."""
    return require("mujoco", "mujoco", "the MuJoCo adapter")


def name_list(feet: Any) -> list[str]:
    """``feet`` (one name or a sequence of names) as a list of distinct strings, else InputError."""
    if isinstance(feet, str):
        return [feet]
    if not isinstance(feet, Sequence) or not feet or not all(isinstance(f, str) for f in feet):
        raise InputError(f"feet must be a name or a non-empty sequence of names (str), got {feet!r}")
    if len(set(feet)) != len(feet):
        raise InputError(f"feet must be distinct names, got {list(feet)}")
    return list(feet)


def check_prefix(prefix: Any) -> str:
    """``prefix`` of the names the adapter adds to a spec, checked to be a str."""
    if not isinstance(prefix, str):
        raise InputError(f"prefix must be a str, got {type(prefix).__name__}")
    return prefix


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
