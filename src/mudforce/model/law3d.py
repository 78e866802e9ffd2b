"""The 3-D law per surface element: what is the paper's and what is ours (docs/model.md, "Mud in 3-D").

The paper (Chen, Yi & Shan 2024) gives the vertical force on a flat sole
moved straight up and down. A robot's foot is a sphere, capsule or box that
also slides, tilts and twists. :class:`mudforce.steppers.contact3d.MudContact3D`
puts a law on every surface element of a :class:`mudforce.model.shapes.Shape`;
this module holds that law's pieces as small pure functions on arrays of
elements (one row each, world frame, z up, SI). The compiled 1-D stepper
supplies each element's paper stress; everything here is vectorised array
code.

One law, two array libraries
----------------------------
Every function takes the array library as a keyword, ``xp``: numpy by
default (:class:`mudforce.steppers.contact3d.MudContact3D`, the reference), or
``jax.numpy`` (:mod:`mudforce.jax.contact3d`, the same law under ``jit``, ``vmap``,
``lax.scan`` and ``grad``). The operations are the same either way; with
numpy the results are those the functions gave before they took ``xp``, bit
for bit. Where a square root or a quotient meets 0 (a slip or a direction of
zero length, an element at or above the surface) the argument is guarded
first (the "double where"), so that the branch not taken puts no NaN into a
gradient; with numpy the guard changes no value. Only
:func:`rotation_matrix` checks its input (numpy); :func:`quaternion_matrix`
is its unchecked arithmetic, for traced values.

The law, element by element
---------------------------
* **Vertical: the paper, on the downward-facing projection.** Each element
  carries the paper's whole state (Maxwell strain, suction, necking, the
  post-necking decay), stepped by the 1-D stepper on the element's own
  depth below the surface, so a tilted foot pulled out peels element by
  element. Its stress ``sigma_i`` (Eq. (8), positive up) acts on its
  horizontal projection facing down: vertical force
  ``sigma_i A_i max(-n_z, 0)`` (:func:`vertical_weight`). A flat sole moved
  vertically is exactly the paper. *Ours:* the projection (an element
  facing up, or a vertical wall, carries no vertical paper stress), and the
  per-element state (the paper has one state for the whole foot).
* **Horizontal: elastic, then yielding.** Each submerged element carries a
  horizontal elastic slip ``s_i`` [m]; its traction is ``-k s_i``, with
  ``k`` the paper's withdrawal stiffness ``k_m_w`` by default
  (:func:`lateral_return_map`). When ``k |s_i|`` reaches the element's
  capacity in that direction (:func:`lateral_capacity`), the slip stops
  growing: the element flows at its capacity, dissipating. A foot at rest
  under a small sideways load therefore holds (it deflects by
  ``load / (k S)``, without creep), and a sliding foot meets its capacity.
  The capacity is the sum of
  - **shear** along the face, capped by the paper's yield stress:
    ``sigma_y |s_t|``, with ``s_t`` the part of the slip direction in the
    element's plane (:func:`shear_fraction`). *Ours:* the paper's
    ``sigma_y`` is the yield stress of the neck in tension; we take the
    same stress as mud's yield in shear;
  - **bearing** of the faces that lead the slip, from 3D-RFT
    (Agarwal, Goldman & Kamrin 2023, :mod:`mudforce.model.granular`): the
    granular law's stress against the slip direction, per unit of what it
    gives a flat plate pushed down, times the paper's rate-independent
    depth stress, the nonlinear spring ``alpha (z/H)^beta`` of Eq. (4)
    (:func:`bearing_factor`). *Ours:* the spring as the medium's depth
    stress (3D-RFT's ``xi |z|``), and 3D-RFT's orientation dependence,
    measured for granular media, carried over to mud.
* **Horizontal drag**, Eq. (5)'s ``lambda rho_m v^2`` on the leading
  elements' projection against the horizontal velocity
  (:func:`horizontal_drag`): it always opposes the motion. The vertical
  drag is the paper's, inside ``sigma_i``.
* Only elements below the surface are loaded (the paper's FREE above it;
  an element that leaves the mud forgets its slip).

No 3-D mud measurements exist: the horizontal law and every *ours* above
are assumptions, stated so that they can be tested and fitted when data
come. The parameters beyond the paper are the lateral stiffness (default
``k_m_w``, from Table I) and the 3D-RFT coefficients (published); nothing
else is new.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mudforce.errors import InputError
from mudforce.model.granular import rft3d_alpha

__all__ = [
    "FLAT_PLATE_ALPHA",
    "ROUNDING_DEPTH",
    "bearing_factor",
    "horizontal_drag",
    "lateral_capacity",
    "lateral_return_map",
    "quaternion_matrix",
    "rotation_matrix",
    "settle_depth",
    "shear_fraction",
    "spring_stress",
    "vertical_weight",
]

#: 3D-RFT's generic vertical stress on a flat plate facing down and pushed down [-] (the bearing's unit).
FLAT_PLATE_ALPHA: float = float(rft3d_alpha(np.array([[0.0, 0.0, -1.0]]), np.array([[0.0, 0.0, -1.0]]))[0, 2])

#: A quaternion whose norm is within this of 1 is normalised; farther, refused [-].
QUATERNION_TOLERANCE = 1e-6

Array = Any  # a numpy array, or a jax array with xp=jax.numpy


def rotation_matrix(quaternion: Any) -> np.ndarray:
    """The rotation matrix of a unit quaternion ``(w, x, y, z)`` (MuJoCo's order) [-], shape (3, 3).

    A quaternion whose norm is within :data:`QUATERNION_TOLERANCE` of 1 is
    normalised; ``(1, 0, 0, 0)`` gives the identity exactly.
    """
    try:
        q = np.asarray(quaternion, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"a quaternion must be 4 finite numbers (w, x, y, z), got {quaternion!r}") from None
    if q.shape != (4,) or not np.all(np.isfinite(q)):
        raise InputError(f"a quaternion must be 4 finite numbers (w, x, y, z), got {quaternion!r}")
    norm = math.sqrt(float(q @ q))
    if abs(norm - 1.0) > QUATERNION_TOLERANCE:
        raise InputError(f"a quaternion must have norm 1 (within {QUATERNION_TOLERANCE:g}), got norm {norm:.9g}")
    if norm != 1.0:
        q = q / norm
    out: np.ndarray = quaternion_matrix(q.tolist())  # Python floats: the same arithmetic, faster
    return out


def quaternion_matrix(quaternion: Array, *, xp: Any = np) -> Array:
    """The rotation matrix of a quaternion ``(w, x, y, z)`` already of norm 1 [-], shape (3, 3); unchecked.

    The arithmetic of :func:`rotation_matrix`, which checks and normalises
    first; this one is for traced values (``xp=jax.numpy``), whose caller
    normalises and guards them (:mod:`mudforce.jax.contact3d`).
    """
    w, x, y, z = quaternion[0], quaternion[1], quaternion[2], quaternion[3]
    return xp.asarray([
        [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
        [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
        [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
    ])


#: A change of an element's depth up to this [m] between steps is the rounding of a pose, not motion.
ROUNDING_DEPTH = 1e-13


def settle_depth(depth: Array, previous: Array, *, xp: Any = np) -> Array:
    """Each element's depth [m], or its previous depth where the two differ by rounding only.

    An element that stays at its depth while the foot turns about it gets
    a depth that moves by a few 1e-18 m from the rounding of the rotation;
    the paper's branch follows the sign of that motion (Eq. (8)), and a
    false withdrawal drops the nonlinear spring (tens of newtons). A change
    of at most :data:`ROUNDING_DEPTH` (0.1 pm a step, 1e-10 m/s at 1 kHz)
    is therefore no change: the element is at rest. *Ours* (the paper's
    foot does not turn).

    Parameters
    ----------
    depth, previous : array
        The elements' depths now and at the last step [m].
    """
    return xp.where(xp.abs(depth - previous) <= ROUNDING_DEPTH, previous, depth)


def vertical_weight(normals: Array, *, xp: Any = np) -> Array:
    """The share of each element's area that carries the paper's vertical stress, ``max(-n_z, 0)`` [-].

    Its horizontal projection facing down: 1 for a sole, 0 for a wall or an
    upward-facing element. ``normals`` (n, 3) [-]; ``xp`` the array library.
    """
    return xp.maximum(-normals[:, 2], 0.0)


def spring_stress(depth: Array, alpha: Any, beta: Any, width: Any, *, xp: Any = np) -> Array:
    """The nonlinear spring ``alpha (z/H)^beta`` of Eq. (4) at each element's depth [Pa], 0 above the surface.

    Parameters
    ----------
    depth : ndarray
        Element depths below the surface [m].
    alpha : float
        Spring coefficient [Pa], Eq. (4).
    beta : float
        Spring exponent [-], Eq. (4).
    width : float
        Intruder width ``H`` [m], Eq. (4).
    xp : module
        The array library (numpy, or jax.numpy).
    """
    below = depth > 0.0
    base = xp.where(below, depth, width) / width  # 1 at and above the surface: no NaN in a gradient there
    return xp.where(below, alpha * base ** beta, 0.0)


def _length(rows: Array, xp: Any) -> Array:
    """``|row|`` of each row, its square root guarded at 0 (the double where) [-]."""
    square = xp.einsum("ij,ij->i", rows, rows)
    some = square > 0.0
    return xp.where(some, xp.sqrt(xp.where(some, square, 1.0)), 0.0)


def shear_fraction(normals: Array, direction: Array, *, xp: Any = np) -> Array:
    """``|s - (s.n) n|`` for a unit horizontal slip direction ``s`` (rows) [-]: 1 along a face, 0 straight into it.

    ``normals`` and ``direction`` (n, 3) [-]; ``xp`` the array library.
    """
    along = direction - xp.einsum("ij,ij->i", direction, normals)[:, None] * normals
    return _length(along, xp)


def bearing_factor(normals: Array, direction: Array, *, xp: Any = np) -> Array:
    """3D-RFT's resistance of each element to motion along ``direction``, per a flat plate's pushed down [-].

    ``max(0, -alpha(n, s) . s) / FLAT_PLATE_ALPHA`` on the elements that lead
    the motion (``n . s > 0``), 0 on the others; ``alpha`` is
    :func:`mudforce.model.granular.rft3d_alpha`. A wall facing the motion gets
    about 0.26, a flat plate pushed down 1. ``normals`` and ``direction``
    (n, 3) [-]; ``xp`` the array library.
    """
    alpha = rft3d_alpha(normals, direction, xp=xp)
    against = xp.maximum(-xp.einsum("ij,ij->i", alpha, direction), 0.0)
    leading = xp.einsum("ij,ij->i", normals, direction) > 0.0
    return xp.where(leading, against / FLAT_PLATE_ALPHA, 0.0)


def lateral_capacity(sigma_y: Any, shear: Array, spring: Array, bearing: Array) -> Array:
    """The horizontal stress an element can carry before it flows [Pa]: ``sigma_y shear + spring bearing``.

    Parameters
    ----------
    sigma_y : float
        Yield stress [Pa], Eq. (9) (taken as the yield in shear).
    shear : ndarray
        :func:`shear_fraction` [-].
    spring : ndarray
        :func:`spring_stress` [Pa].
    bearing : ndarray
        :func:`bearing_factor` [-].

    Plain arithmetic: the same on numpy and jax arrays.
    """
    return sigma_y * shear + spring * bearing


def lateral_return_map(slip: Array, stiffness: Any, capacity: Array, *, xp: Any = np) -> tuple[Array, Array]:
    """Elastic-perfectly-plastic update of the elements' horizontal slips: ``(slip, traction)``.

    Parameters
    ----------
    slip : ndarray, shape (n, 2)
        Trial slips [m]: the last slips plus this step's horizontal displacements.
    stiffness : float
        Lateral stiffness ``k`` [Pa/m].
    capacity : ndarray, shape (n,)
        :func:`lateral_capacity` in each trial slip's direction [Pa].
    xp : module
        The array library (numpy, or jax.numpy).

    Returns
    -------
    slip : ndarray, shape (n, 2)
        The slips kept [m]: the trial where ``k |slip| <= capacity``, else
        scaled back to ``capacity / k`` (the rest flowed).
    traction : ndarray, shape (n, 2)
        The horizontal stress on each element [Pa], ``-k slip``.
    """
    size = _length(slip, xp)
    limit = capacity / stiffness
    scale = xp.where(size > limit, limit / xp.where(size > 0.0, size, 1.0), 1.0)
    kept = slip * scale[:, None]
    return kept, -stiffness * kept


def horizontal_drag(lambda_: Any, rho_m: Any, normals: Array, velocity: Array, *, xp: Any = np) -> Array:
    """Eq. (5) against the horizontal motion on the leading projection: ``-lambda rho (n.u)_+ u`` [Pa], (n, 2).

    Its size is ``lambda rho |u|^2 (n.u/|u|)_+``: the paper's drag on the part
    of the element that faces the motion.

    Parameters
    ----------
    lambda_ : float
        Drag scaling factor [-], Eq. (5).
    rho_m : float
        Mud density [kg/m^3].
    normals : ndarray, shape (n, 3)
        Outward unit normals [-].
    velocity : ndarray, shape (n, 2)
        Horizontal element velocities [m/s].
    xp : module
        The array library (numpy, or jax.numpy).
    """
    facing = xp.maximum(xp.einsum("ij,ij->i", normals[:, :2], velocity), 0.0)
    return -(lambda_ * rho_m) * facing[:, None] * velocity
