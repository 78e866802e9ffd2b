"""Mud in 3-D: the force and torque on a foot of any shape moving in any way (:class:`MudContact3D`).

A foot is a :class:`mudforce.shapes.Shape` (a sole, sphere, capsule, box,
mesh, or a MuJoCo geom's), placed each step by a pose: the position of its
body origin [m] and a unit quaternion ``(w, x, y, z)`` (MuJoCo's order), in
a world frame with z up and the undisturbed mud surface at
``surface_height``. Each surface element carries the law of
:mod:`mudforce.law3d`: the paper's vertical law with its whole state on the
element's downward-facing projection, an elastic-then-yielding horizontal
resistance (shear capped by ``sigma_y``, bearing from 3D-RFT), and Eq. (5)'s
drag. The elements' velocities follow from consecutive poses (the exact
rule: each element's displacement over the step, first-order hold).

A flat sole (``shapes.sole(foot)``) moved straight up and down is exactly
the paper: the force equals :func:`mudforce.simulate`'s to rounding, with
no sideways force or torque (``tests/contact3d``).

What is the paper's and what is ours: :mod:`mudforce.law3d` and
docs/model.md, "Mud in 3-D".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from mudforce import law3d
from mudforce.errors import InputError, finite_number, is_real
from mudforce.foot import Foot
from mudforce.parameters import MudParameters
from mudforce.shapes import Shape
from mudforce.simulation import MAX_DEPTH, MAX_DT, MIN_DT
from mudforce.vectorized import MudContacts

__all__ = ["ContactState3D", "MudContact3D", "Result3D", "Wrench", "simulate_3d"]


class Wrench(NamedTuple):
    """The mud's force and torque on a foot, world frame (z up).

    Attributes
    ----------
    force : ndarray, shape (3,)
        Force on the foot [N]; ``force[2] > 0`` pushes it up.
    torque : ndarray, shape (3,)
        Torque on the foot about its body origin [N m].
    """

    force: np.ndarray
    torque: np.ndarray


class ContactState3D(NamedTuple):
    """Everything a :class:`MudContact3D` remembers, for ``contact.state = saved`` (rollouts, resets).

    Attributes
    ----------
    elements : ndarray
        The elements' 1-D states (:attr:`mudforce.vectorized.MudContacts.state`).
    slip : ndarray, shape (n, 2)
        The elements' horizontal elastic slips [m].
    centroids : ndarray, shape (n, 3)
        The elements' world centroids at the last step [m].
    started : bool
        Whether the contact has taken its first step.
    """

    elements: np.ndarray
    slip: np.ndarray
    centroids: np.ndarray
    started: bool


def _pose(position: Any, quaternion: Any) -> tuple[np.ndarray, np.ndarray]:
    """The position [m] as a (3,) float64 array and the rotation matrix, refused if not finite or not unit."""
    try:
        p = np.asarray(position, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"position must be 3 numbers [m], got {position!r}") from None
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise InputError(f"position must be 3 finite numbers [m], got {position!r}")
    try:
        rotation = law3d.rotation_matrix(quaternion)
    except InputError:
        raise
    except (TypeError, ValueError):
        raise InputError(f"a quaternion must be 4 finite numbers (w, x, y, z), got {quaternion!r}") from None
    return p, rotation


class MudContact3D:
    """A foot of any shape in mud, stepped one pose at a time (a control loop, an engine).

    Parameters
    ----------
    params : MudParameters
        The mud (e.g. ``MudParameters.from_water_content(0.25)``).
    shape : Shape
        The foot's surface (:mod:`mudforce.shapes`), body frame.
    surface_height : float
        Height of the undisturbed mud surface in the world frame [m].
    width : float, optional
        The intruder width ``H`` of Eq. (4) [m]; by default ``shape.width``.
    lateral_stiffness : float, optional
        Stiffness of the horizontal elastic slip [Pa/m]; by default the
        paper's withdrawal stiffness ``k_m_w`` (:mod:`mudforce.law3d`).

    Examples
    --------
    >>> import mudforce as mf
    >>> from mudforce import shapes
    >>> foot = mf.MudContact3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04))
    >>> w = foot.step([0.0, 0.0, 0.015], [1.0, 0.0, 0.0, 0.0], 0.0)
    >>> w = foot.step([0.0, 0.0, 0.010], [1.0, 0.0, 0.0, 0.0], 0.01)
    >>> bool(w.force[2] > 0.0)
    True
    """

    def __init__(self, params: MudParameters, shape: Shape, surface_height: float = 0.0, *,
                 width: float | None = None, lateral_stiffness: float | None = None) -> None:
        if not isinstance(params, MudParameters):
            raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
        if not isinstance(shape, Shape):
            raise InputError(f"shape must be a mudforce.shapes.Shape, got {type(shape).__name__}")
        self.params = params
        self.shape = shape
        self.surface_height = finite_number(surface_height, "surface_height", "m")
        if abs(self.surface_height) > MAX_DEPTH:
            raise InputError(f"surface_height must be within +-{MAX_DEPTH:g} m, got {surface_height!r}")
        h = width if width is not None else shape.width
        if h is None:
            raise InputError("this shape has no width H for Eq. (4); give width= [m] (or build the shape with "
                             "a mudforce.shapes constructor, which sets it)")
        # each element's paper state, stepped with a unit area so that the 1-D force is the stress [Pa]
        self._elements = MudContacts(params, shape.n, Foot(area=1.0, width=h, shape="element"), threads=1)
        self.width = float(Foot(area=1.0, width=h).width)  #: H of Eq. (4) [m]
        k = params.k_m_w if lateral_stiffness is None else lateral_stiffness
        if not is_real(k) or not math.isfinite(k) or k <= 0.0:
            raise InputError(f"lateral_stiffness must be finite and > 0 [Pa/m], got {lateral_stiffness!r}")
        self.lateral_stiffness = float(k)
        self._slip = np.zeros((shape.n, 2))
        self._centroids = np.zeros((shape.n, 3))
        self._started = False
        #: the last step's force on every element [N], world frame, shape (n, 3)
        self.element_forces = np.zeros((shape.n, 3))

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> ContactState3D:
        """A copy of everything the contact remembers; assign one back to restore it."""
        return ContactState3D(self._elements.state, self._slip.copy(), self._centroids.copy(), self._started)

    @state.setter
    def state(self, saved: ContactState3D) -> None:
        if not isinstance(saved, ContactState3D):
            raise InputError(f"state must be a ContactState3D from .state, got {type(saved).__name__}")
        slip = np.asarray(saved.slip, dtype=np.float64)
        centroids = np.asarray(saved.centroids, dtype=np.float64)
        n = self.shape.n
        if slip.shape != (n, 2) or centroids.shape != (n, 3):
            raise InputError(f"a state of this {n}-element foot has slips (n, 2) and centroids (n, 3), got "
                             f"{slip.shape} and {centroids.shape}")
        if not (np.all(np.isfinite(slip)) and np.all(np.isfinite(centroids))):
            raise InputError("a state's slips and centroids must be finite")
        self._elements.state = saved.elements  # validated; refuses without changing anything
        self._slip = slip.copy()
        self._centroids = centroids.copy()
        self._started = bool(saved.started)

    @property
    def modes(self) -> list[str]:
        """Each element's contact state: ``"FREE"``, ``"CONTACT"`` or ``"NECKED"``."""
        return self._elements.modes

    # ------------------------------------------------------------------ step
    def step(self, position: Any, quaternion: Any, dt: float) -> Wrench:
        """Move the foot to a pose and return the mud's wrench on it.

        Every input is checked before anything changes: a refused step
        leaves the contact exactly as it was.

        Parameters
        ----------
        position : array_like, shape (3,)
            The body origin in the world frame [m], z up.
        quaternion : array_like, shape (4,)
            The body's orientation ``(w, x, y, z)`` [-], unit (within 1e-6;
            normalised).
        dt : float
            Time since the previous pose [s], within [1e-9, 1e3]; ignored on
            the first step.

        Returns
        -------
        Wrench
            Force [N] and torque about the body origin [N m], world frame.
        """
        p, rotation = _pose(position, quaternion)
        if self._started:
            if not is_real(dt) or not MIN_DT <= float(dt) <= MAX_DT:
                raise InputError(f"dt must be within [{MIN_DT:g}, {MAX_DT:g}] s after the first step, got {dt!r}")
            dt = float(dt)
        else:
            dt = 1.0  # ignored by the elements' first step
        shape = self.shape
        offsets = shape.centroids @ rotation.T
        centroids = p + offsets
        normals = shape.normals @ rotation.T
        depth = self.surface_height - centroids[:, 2]
        if self._started:  # an element turned about at its depth is at rest, not moving by rounding
            depth = law3d.settle_depth(depth, self._elements.depths)  # the depths the elements were stepped to
        # the paper, element by element (refuses a depth out of bounds before any element moves)
        stress = self._elements.step(depth, dt)
        q = self.params
        forces = np.zeros((shape.n, 3))
        forces[:, 2] = stress * shape.areas * law3d.vertical_weight(normals)
        below = depth > 0.0
        moved = centroids[:, :2] - self._centroids[:, :2]
        trial = np.where(below[:, None], self._slip + moved, 0.0)
        if self._started and trial.any():
            size = np.sqrt(np.einsum("ij,ij->i", trial, trial))
            direction = np.zeros((shape.n, 3))
            direction[:, :2] = trial / np.where(size > 0.0, size, 1.0)[:, None]
            capacity = law3d.lateral_capacity(
                q.sigma_y, law3d.shear_fraction(normals, direction),
                law3d.spring_stress(depth, q.alpha, q.beta, self.width), law3d.bearing_factor(normals, direction))
            slip, traction = law3d.lateral_return_map(trial, self.lateral_stiffness, capacity)
            drag = law3d.horizontal_drag(q.lambda_, q.rho_m, normals, moved / dt)
            forces[:, :2] = (traction + np.where(below[:, None], drag, 0.0)) * shape.areas[:, None]
        else:  # nothing moved sideways and nothing is loaded sideways (the paper's own case): no sums to do
            slip = np.zeros((shape.n, 2))
        self._slip = slip
        self._centroids = centroids
        self._started = True
        self.element_forces = forces
        return Wrench(forces.sum(axis=0), np.cross(offsets, forces).sum(axis=0))

    def reset(self) -> None:
        """Forget the history: the next step is a first step."""
        self._elements.reset()
        self._slip[:] = 0.0
        self._started = False

    def __repr__(self) -> str:
        return f"MudContact3D({self.shape!r}, surface_height={self.surface_height:g})"


@dataclass(frozen=True, eq=False)
class Result3D:
    """A 3-D simulation: the wrench at each pose (:func:`simulate_3d`).

    Attributes
    ----------
    time : ndarray, shape (m,)
        Sample times [s].
    force : ndarray, shape (m, 3)
        Force on the foot [N], world frame, z up.
    torque : ndarray, shape (m, 3)
        Torque about the body origin [N m], world frame.
    element_forces : ndarray, shape (m, n, 3) or None
        Each element's force [N], when asked for.
    """

    time: np.ndarray
    force: np.ndarray
    torque: np.ndarray
    element_forces: np.ndarray | None = field(default=None, repr=False)

    def to_pandas(self) -> Any:
        """A pandas DataFrame with columns ``time_s``, ``force_{x,y,z}_N``, ``torque_{x,y,z}_N_m``."""
        from mudforce._optional import require

        pd = require("pandas", "pandas", "Result3D.to_pandas")
        columns: dict[str, np.ndarray] = {"time_s": self.time}
        for k, axis in enumerate("xyz"):
            columns[f"force_{axis}_N"] = self.force[:, k]
        for k, axis in enumerate("xyz"):
            columns[f"torque_{axis}_N_m"] = self.torque[:, k]
        return pd.DataFrame(columns)


def simulate_3d(time: Any, positions: Any, quaternions: Any, params: MudParameters, shape: Shape, *,
                surface_height: float = 0.0, width: float | None = None, lateral_stiffness: float | None = None,
                elements: bool = False) -> Result3D:
    """The mud's wrench on a foot following a prescribed motion (poses sampled in time).

    Parameters
    ----------
    time : array_like, shape (m,)
        Sample times [s], strictly increasing.
    positions : array_like, shape (m, 3)
        The body origin at each sample [m], world frame, z up.
    quaternions : array_like, shape (m, 4)
        The orientation at each sample, ``(w, x, y, z)`` [-], unit.
    params : MudParameters
        The mud.
    shape : Shape
        The foot's surface (:mod:`mudforce.shapes`).
    surface_height, width, lateral_stiffness
        As for :class:`MudContact3D` ([m], [m], [Pa/m]).
    elements : bool
        Also keep every element's force at every sample (``m n 3`` numbers).

    Returns
    -------
    Result3D
    """
    try:
        t = np.asarray(time, dtype=np.float64)
        x = np.asarray(positions, dtype=np.float64)
        q = np.asarray(quaternions, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("time, positions and quaternions must be arrays of real numbers") from None
    m = t.shape[0] if t.ndim == 1 else -1
    if m < 1 or x.shape != (m, 3) or q.shape != (m, 4):
        raise InputError(f"time (m,), positions (m, 3) and quaternions (m, 4) must agree, got {t.shape}, "
                         f"{x.shape} and {q.shape}")
    contact = MudContact3D(params, shape, surface_height, width=width, lateral_stiffness=lateral_stiffness)
    force = np.empty((m, 3))
    torque = np.empty((m, 3))
    per_element = np.empty((m, shape.n, 3)) if elements else None
    for k in range(m):
        wrench = contact.step(x[k], q[k], float(t[k] - t[k - 1]) if k else 0.0)
        force[k] = wrench.force
        torque[k] = wrench.torque
        if per_element is not None:
            per_element[k] = contact.element_forces
    return Result3D(t.copy(), force, torque, per_element)
