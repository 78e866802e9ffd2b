"""Checks of what both MuJoCo adapters (1-D :mod:`mudforce.engines.mujoco`, 3-D
:mod:`mudforce.engines.mujoco.adapter3d`) take when they edit a spec: plumbing, no physics. (What MJX shares with
them, the feet's names and a drop's numbers, is in :mod:`mudforce.engines._checks`.)"""

from __future__ import annotations

from typing import Any

import numpy as np

from mudforce._plumbing.optional import require
from mudforce.errors import InputError

__all__ = ["check_model_data", "check_prefix", "mujoco_module", "read_only"]


def mujoco_module() -> Any:
    """The ``mujoco`` package, or a one-line error saying how to install it."""
    return require("mujoco", "mujoco", "the MuJoCo adapter")


def read_only(array: np.ndarray) -> np.ndarray:
    """A view of ``array`` that cannot be written through (it follows ``array``): what both adapters give out of
    the arrays they write in place."""
    view: np.ndarray = array.view()
    view.flags.writeable = False
    return view


def check_prefix(prefix: Any) -> str:
    """``prefix`` of the names the adapter adds to a spec, checked to be a str."""
    if not isinstance(prefix, str):
        raise InputError(f"prefix must be a str, got {type(prefix).__name__}")
    return prefix


#: Each of a model's sizes and an array of its MjData with that many rows: what :func:`check_model_data` compares.
_DATA_ROWS = (("nq", "qpos"), ("nv", "qvel"), ("na", "act"), ("nu", "ctrl"), ("nbody", "xpos"), ("njnt", "xanchor"),
              ("ngeom", "geom_xpos"), ("nsite", "site_xpos"), ("ncam", "cam_xpos"), ("nlight", "light_xpos"),
              ("ntendon", "ten_length"), ("nmocap", "mocap_pos"), ("neq", "eq_active"), ("nuserdata", "userdata"),
              ("nsensordata", "sensordata"))


def check_model_data(mj: Any, model: Any, data: Any) -> None:
    """Refuse ``model`` and ``data`` unless they are a ``mujoco.MjModel`` and an ``mujoco.MjData`` of its sizes (made
    by ``mujoco.MjData(model)``): MuJoCo steps a model with another's data without a word, and an adapter's compiled
    steps index its arrays by the model's ids."""
    if not isinstance(model, mj.MjModel) or not isinstance(data, mj.MjData):
        raise InputError(f"model and data must be a mujoco.MjModel and its mujoco.MjData, got "
                         f"{type(model).__name__} and {type(data).__name__}")
    for size, rows in _DATA_ROWS:
        if len(getattr(data, rows)) != getattr(model, size):
            raise InputError(f"data is not this model's mujoco.MjData: its {rows} has {len(getattr(data, rows))} "
                             f"rows, the model's {size} is {getattr(model, size)}; expected mujoco.MjData(model)")
