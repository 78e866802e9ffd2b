"""The 3-D law per surface element: what is the paper's and what is ours (docs/model.md, "Mud in 3-D").

The paper (Chen, Yi & Shan 2024) gives the vertical force on a flat sole
moved straight up and down. A robot's foot is a sphere, capsule or box that
also slides, tilts and twists. :class:`mudforce.contact3d.MudContact3D`
puts a law on every surface element of a :class:`mudforce.shapes.Shape`;
this module holds that law's pieces as small pure functions on arrays of
elements (one row each, world frame, z up, SI). The compiled 1-D stepper
supplies each element's paper stress; everything here is vectorised numpy.

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
    (Agarwal, Goldman & Kamrin 2023, :mod:`mudforce.granular`): the
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
from mudforce.granular import rft3d_alpha

__all__ = [
    "FLAT_PLATE_ALPHA",
    "bearing_factor",
    "horizontal_drag",
    "lateral_capacity",
    "lateral_return_map",
    "rotation_matrix",
    "shear_fraction",
    "spring_stress",
    "vertical_weight",
]

#: 3D-RFT's generic vertical stress on a flat plate facing down and pushed down [-] (the bearing's unit).
FLAT_PLATE_ALPHA: float = float(rft3d_alpha(np.array([[0.0, 0.0, -1.0]]), np.array([[0.0, 0.0, -1.0]]))[0, 2])

#: A quaternion whose norm is within this of 1 is normalised; farther, refused [-].
QUATERNION_TOLERANCE = 1e-6


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
    w, x, y, z = (float(v) for v in q)
    return np.array([
        [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
        [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
        [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
    ])


def vertical_weight(normals: np.ndarray) -> np.ndarray:
    """The share of each element's area that carries the paper's vertical stress, ``max(-n_z, 0)`` [-].

    Its horizontal projection facing down: 1 for a sole, 0 for a wall or an
    upward-facing element.
    """
    out: np.ndarray = np.maximum(-normals[:, 2], 0.0)
    return out


def spring_stress(depth: np.ndarray, alpha: float, beta: float, width: float) -> np.ndarray:
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
    """
    below = np.maximum(depth, 0.0)
    out: np.ndarray = alpha * (below / width) ** beta
    return np.where(depth > 0.0, out, 0.0)


def shear_fraction(normals: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """``|s - (s.n) n|`` for a unit horizontal slip direction ``s`` (rows) [-]: 1 along a face, 0 straight into it."""
    along = direction - np.einsum("ij,ij->i", direction, normals)[:, None] * normals
    out: np.ndarray = np.sqrt(np.einsum("ij,ij->i", along, along))
    return out


def bearing_factor(normals: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """3D-RFT's resistance of each element to motion along ``direction``, per a flat plate's pushed down [-].

    ``max(0, -alpha(n, s) . s) / FLAT_PLATE_ALPHA`` on the elements that lead
    the motion (``n . s > 0``), 0 on the others; ``alpha`` is
    :func:`mudforce.granular.rft3d_alpha`. A wall facing the motion gets
    about 0.26, a flat plate pushed down 1.
    """
    alpha = rft3d_alpha(normals, direction)
    against = np.maximum(-np.einsum("ij,ij->i", alpha, direction), 0.0)
    leading = np.einsum("ij,ij->i", normals, direction) > 0.0
    out: np.ndarray = np.where(leading, against / FLAT_PLATE_ALPHA, 0.0)
    return out


def lateral_capacity(sigma_y: float, shear: np.ndarray, spring: np.ndarray, bearing: np.ndarray) -> np.ndarray:
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
    """
    out: np.ndarray = sigma_y * shear + spring * bearing
    return out


def lateral_return_map(slip: np.ndarray, stiffness: float, capacity: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Elastic-perfectly-plastic update of the elements' horizontal slips: ``(slip, traction)``.

    Parameters
    ----------
    slip : ndarray, shape (n, 2)
        Trial slips [m]: the last slips plus this step's horizontal displacements.
    stiffness : float
        Lateral stiffness ``k`` [Pa/m].
    capacity : ndarray, shape (n,)
        :func:`lateral_capacity` in each trial slip's direction [Pa].

    Returns
    -------
    slip : ndarray, shape (n, 2)
        The slips kept [m]: the trial where ``k |slip| <= capacity``, else
        scaled back to ``capacity / k`` (the rest flowed).
    traction : ndarray, shape (n, 2)
        The horizontal stress on each element [Pa], ``-k slip``.
    """
    size = np.sqrt(np.einsum("ij,ij->i", slip, slip))
    limit = capacity / stiffness
    scale = np.where(size > limit, limit / np.where(size > 0.0, size, 1.0), 1.0)
    kept = slip * scale[:, None]
    return kept, -stiffness * kept


def horizontal_drag(lambda_: float, rho_m: float, normals: np.ndarray, velocity: np.ndarray) -> np.ndarray:
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
    """
    facing = np.maximum(np.einsum("ij,ij->i", normals[:, :2], velocity), 0.0)
    out: np.ndarray = -(lambda_ * rho_m) * facing[:, None] * velocity
    return out
