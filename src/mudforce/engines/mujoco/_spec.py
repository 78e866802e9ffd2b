"""Checks of what both MuJoCo adapters (1-D :mod:`mudforce.engines.mujoco`, 3-D
:mod:`mudforce.engines.mujoco.adapter3d`) take when they edit a spec: plumbing, no physics. (What MJX shares with
them, the feet's names and a drop's numbers, is in :mod:`mudforce.engines._checks`.)"""

from __future__ import annotations

from typing import Any

from mudforce._plumbing.optional import require
from mudforce.errors import InputError

__all__ = ["check_prefix", "mujoco_module"]


def mujoco_module() -> Any:
    """The ``mujoco`` package, or a one-line error saying how to install it."""
    return require("mujoco", "mujoco", "the MuJoCo adapter")


def check_prefix(prefix: Any) -> str:
    """``prefix`` of the names the adapter adds to a spec, checked to be a str."""
    if not isinstance(prefix, str):
        raise InputError(f"prefix must be a str, got {type(prefix).__name__}")
    return prefix
