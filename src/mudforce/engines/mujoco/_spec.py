"""Checks of what both MuJoCo adapters (1-D :mod:`mudforce.engines.mujoco`, 3-D
:mod:`mudforce.engines.mujoco.adapter3d`) take when they edit a spec: plumbing, no physics. (What MJX shares with
them, the feet's names and a drop's numbers, is in :mod:`mudforce.engines._checks`.)"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import numpy as np

from mudforce._plumbing.optional import require
from mudforce.errors import InputError

__all__ = ["check_model_data", "check_prefix", "compiled_copy", "geom_frame", "mujoco_module", "read_only"]


def mujoco_module() -> Any:
    """The ``mujoco`` package, or a one-line error saying how to install it."""
    return require("mujoco", "mujoco", "the MuJoCo adapter")


def read_only(array: np.ndarray) -> np.ndarray:
    """A view of ``array`` that cannot be written through (it follows ``array``): what both adapters give out of
    the arrays they write in place."""
    view: np.ndarray = array.view()
    view.flags.writeable = False
    return view


def compiled_copy(spec: Any) -> Callable[[], Any]:
    """A compiled copy of ``spec`` (a ``mujoco.MjModel``), compiled on its first call and kept: what
    :func:`geom_frame` reads a turned geom's frame from, once per call of an ``add_mud``, whatever its feet."""
    return functools.cache(lambda: spec.copy().compile())


def geom_frame(geom: Any, compiled: Callable[[], Any] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A spec geom's position [m], quaternion [-] and MuJoCo size [m] in its body's frame, as compiling gives them.

    For a geom given by ``fromto`` (a capsule, cylinder, box or ellipsoid between two points: MJCF's usual legs) the
    spec's ``pos`` and ``quat`` are unset until the model is compiled: its centre is then the two points' midpoint,
    its local z runs from the second to the first (``mju_quatZ2Vec``) and its half-length along it (``size[1]``;
    ``size[2]`` for a box or ellipsoid, whose ``size[1]`` is then ``size[0]``) is half their distance. A geom
    turned by ``euler``, ``axisangle``, ``xyaxes`` or ``zaxis``, or placed in a ``<frame>``, keeps ``quat`` (and a
    ``pos`` relative to its frame) unset too, and what compiling makes of them depends on the compiler's angle unit
    and Euler sequence: its frame is read from the model ``compiled()`` gives (:func:`compiled_copy`; a named
    primitive; a box turned 90 degrees by ``euler`` had its bottom taken 15 mm too high). Otherwise its ``pos``,
    ``quat`` and ``size`` as given (copies).
    """
    mj = mujoco_module()
    turned = geom.alt.type != mj.mjtOrientation.mjORIENTATION_QUAT or getattr(geom, "frame", None) is not None
    if turned and compiled is not None and geom.name and geom.type != mj.mjtGeom.mjGEOM_MESH:
        g = compiled().geom(geom.name)
        return (np.array(g.pos, dtype=float), np.array(g.quat, dtype=float), np.array(g.size, dtype=float))
    pos, quat, size = (np.array(v, dtype=float) for v in (geom.pos, geom.quat, geom.size))
    ends = np.array(geom.fromto, dtype=float)
    if np.isnan(ends[0]):  # (MuJoCo's mark of no fromto)
        return pos, quat, size
    axis = ends[:3] - ends[3:]  # (MuJoCo's local z runs from the second point to the first)
    mj.mju_quatZ2Vec(quat, axis)
    half = 0.5 * float(np.linalg.norm(axis))
    if geom.type in (mj.mjtGeom.mjGEOM_BOX, mj.mjtGeom.mjGEOM_ELLIPSOID):  # a square section of side size[0]
        size[1:] = size[0], half
    else:
        size[1] = half
    return 0.5 * (ends[:3] + ends[3:]), quat, size


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
