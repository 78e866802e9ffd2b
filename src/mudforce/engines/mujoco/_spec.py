"""Checks of what both MuJoCo adapters (1-D :mod:`mudforce.engines.mujoco`, 3-D
:mod:`mudforce.engines.mujoco.adapter3d`) take when they edit a spec: plumbing, no physics."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from mudforce._plumbing.optional import require
from mudforce.errors import InputError

__all__ = ["check_prefix", "mujoco_module", "name_list"]


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
