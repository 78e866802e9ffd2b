"""Mud in 3-D: the force and torque on a foot of any shape moving in any way (:class:`MudContact3D`).

A foot is a :class:`mudforce.model.shapes.Shape` (a sole, sphere, capsule, box,
mesh, or a MuJoCo geom's), placed each step by a pose: the position of its
body origin [m] and a unit quaternion ``(w, x, y, z)`` (MuJoCo's order), in
a world frame with z up and the undisturbed mud surface at
``surface_height``. Each surface element carries the law of
:mod:`mudforce.model.law3d`: the paper's vertical law with its whole state on the
element's downward-facing projection, an elastic-then-yielding horizontal
resistance (shear capped by ``sigma_y``, bearing from 3D-RFT), and Eq. (5)'s
drag. The elements' velocities follow from consecutive poses (the exact
rule: each element's displacement over the step, first-order hold). The
law, the placing of the elements and the wrench's moments are
:mod:`mudforce.model.law3d`'s functions: :class:`MudContact3D` places its
elements with them on numpy arrays and runs the law over them compiled
(:func:`mudforce._kernel.step3d.element_forces`), and, from its second step
on, takes the same arithmetic in the same order compiled, the same bits
(:class:`MudContacts3D`'s compiled step of one foot,
:func:`mudforce._kernel.step3d.step_feet`, with every element's force and the
wrench summed in element order); :class:`MudContacts3D` has
them compiled in (:mod:`mudforce._kernel.step3d`) and
:mod:`mudforce.jax.contact3d` calls them on JAX arrays.

A flat sole (``shapes.sole(foot)``) moved straight up and down is exactly
the paper: the force equals :func:`mudforce.simulate`'s to rounding, with
no sideways force or torque (``tests/contact3d``).

What is the paper's and what is ours: :mod:`mudforce.model.law3d` and
docs/model.md, "Mud in 3-D".
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Mapping, Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
from numba import typeof
from numba import types as numba_types

from mudforce import _kernel as K
from mudforce._kernel import step3d as S3
from mudforce._kernel.addresses import address_table, entry_point
from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MAX_HORIZONTAL, MIN_DT, check_times
from mudforce._kernel.layout import STATE_NAMES
from mudforce.errors import (
    InputError,
    feet_count,
    is_integer,
    is_real,
    number_within,
    real_array,
    real_number,
    shown,
    true_or_false,
)
from mudforce.model import law3d
from mudforce.model.bounds import bounded_depth
from mudforce.model.foot import SIZE_RANGE, Foot
from mudforce.model.law3d import check_bearing_scale, check_lateral_stiffness
from mudforce.model.parameters import MudParameters
from mudforce.model.shapes import Shape
from mudforce.model.velocity import resolve_velocity_filter
from mudforce.steppers import many as vectorized
from mudforce.steppers.contact import _restore_rows, check_states
from mudforce.steppers.many import _FLOAT64, MudContacts, _chosen_feet, _param_rows, _plain

__all__ = ["ContactState3D", "ContactStates3D", "MudContact3D", "MudContacts3D", "Result3D", "Wrench", "simulate_3d"]

#: Most element forces :func:`simulate_3d` keeps with ``elements=True``, samples x elements [-]: 3 numbers each,
#: 2.4 GB (as many numbers as the engines' largest output, mudforce.model.bounds.MAX_OUTPUT_SAMPLES x 6 arrays / 3).
MAX_ELEMENT_SAMPLES = 200_000_000
#: :func:`simulate_3d` warns when every quaternion's w (its first component) is within this of 0 [-]: every pose
#: a half turn (within 11.5 degrees), as an upright foot's quaternions read in ROS's and scipy's (x, y, z, w) order.
HALF_TURN_W = 0.1


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
        The elements' 1-D states (:attr:`mudforce.steppers.many.MudContacts.state`).
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
    """The position [m] as a (3,) float64 array and the rotation matrix, refused if not 3 finite real numbers
    (x and y within +-:data:`~mudforce._kernel.bounds.MAX_HORIZONTAL`), or the quaternion not unit."""
    # (real_array's messages show no repr of the input: over lines for a 2-D array, ValueError for 10**5000)
    p = real_array(position, "position", "m", must="position must be 3 real numbers [m]")
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        got = f"shape {p.shape}" if p.shape != (3,) else repr(p.tolist())
        raise InputError(f"position must be 3 finite numbers [m], got {got}")
    if not (abs(p[0]) <= MAX_HORIZONTAL and abs(p[1]) <= MAX_HORIZONTAL):
        raise InputError(f"position x and y must be within +-{MAX_HORIZONTAL:g} m of the world origin, got "
                         f"{p.tolist()!r}")
    return p, law3d.rotation_matrix(quaternion)  # checked there (real, finite, 4 numbers, unit)


class MudContact3D:
    """A foot of any shape in mud, stepped one pose at a time (a control loop, an engine).

    Parameters
    ----------
    params : MudParameters
        The mud (e.g. ``MudParameters.from_water_content(0.25)``).
    shape : Shape
        The foot's surface (:mod:`mudforce.model.shapes`), body frame.
    surface_height : float
        Height of the undisturbed mud surface in the world frame [m].
    width : float, optional
        The intruder width ``H`` of Eq. (4) [m]; by default ``shape.width``.
    lateral_stiffness : float, optional
        Stiffness of the horizontal elastic slip [Pa/m]; by default the
        paper's withdrawal stiffness ``k_m_w`` (:mod:`mudforce.model.law3d`).
    bearing_scale : float, optional
        The sideways bearing's scale [-], within [0, 1e3]: 1 (the default) is
        3D-RFT's granular bearing as it is, 0 leaves the shear alone
        (:func:`mudforce.model.law3d.bearing_stress`; fitted by
        :func:`mudforce.estimation.calibration.fit3d.fit_3d`).

    Examples
    --------
    >>> import mudforce as mf
    >>> from mudforce.model import shapes
    >>> foot = mf.MudContact3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04))
    >>> w = foot.step([0.0, 0.0, 0.015], [1.0, 0.0, 0.0, 0.0], 0.0)
    >>> w = foot.step([0.0, 0.0, 0.010], [1.0, 0.0, 0.0, 0.0], 0.01)
    >>> bool(w.force[2] > 0.0)
    True
    """

    def __init__(self, params: MudParameters, shape: Shape, surface_height: float = 0.0, *,
                 width: float | None = None, lateral_stiffness: float | None = None,
                 bearing_scale: float | None = None) -> None:
        if not isinstance(params, MudParameters):
            raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
        if not isinstance(shape, Shape):
            raise InputError(f"shape must be a mudforce.model.shapes.Shape, got {type(shape).__name__}")
        self._params = params
        self._shape = shape
        self._surface_height = bounded_depth(surface_height, "surface_height")
        h = number_within(width, "width", *SIZE_RANGE, "m") if width is not None else shape.width  # named as given
        if h is None:
            raise InputError("this shape has no width H for Eq. (4); give width= [m] (or build the shape with "
                             "a mudforce.model.shapes constructor, which sets it)")
        # each element's paper state, stepped with a unit area so that the 1-D force is the stress [Pa]
        element = Foot(area=1.0, width=h, shape="element")  # checks H
        self._elements = MudContacts(params, shape.n, element, threads=1)
        self._width = element.width
        self._lateral_stiffness = check_lateral_stiffness(params.k_m_w if lateral_stiffness is None
                                                          else lateral_stiffness)
        self._bearing_scale = check_bearing_scale(1.0 if bearing_scale is None else bearing_scale)
        n = shape.n
        # the compiled step's arrays: MudContacts3D's layout for one foot (mudforce._kernel.step3d.step_feet), the
        # 1-D rows those of the elements' MudContacts, which the numpy step steps (one state, two steps)
        block = S3.new_block(np.array([0, n]))  # the step's own arrays in one (one argument, not five)
        el, self._foot, _, _, _ = S3.block_views(block)
        _fill_elements(el, shape)
        _fill_foot(self._foot[0], params, self._surface_height, self._width, self._lateral_stiffness,
                   self._bearing_scale, shape)
        self._slip = el[:, S3.E_SLIPX:S3.E_SLIPY + 1]  # views: the slips [m] and the world centroids at the last
        self._centroids = el[:, S3.E_CX:S3.E_CZ + 1]  # step [m] (the lanes' export, as the 1-D rows are: _rows)
        self._areas = np.array(shape.areas, dtype=np.float64)  # the areas [m^2] as the numpy step's compiled loop
        e = self._elements  # has them (writable, C-contiguous, as numba types them)
        self._block = block
        S3.lanes_from_rows(block, e._states)  # the elements' constants and fresh states into the compiled step's lanes
        # step_feet's arguments after the pose and dt, before the outputs
        self._kernel_args = (block, e._states, e.ring, e.params_array)
        self._n3 = (n, 3)
        self._fixed: Any = None  # the compiled step (MudContact3D._fixed_types), made on the first step
        self._entry: Any = None  # its one-foot form's entry point (S3.step_one), made with it
        self._pose_buffers = (np.zeros((1, 3)), np.zeros((1, 4)))  # where step_one copies the pose
        # the hot path's outputs, two sets taken in turn and reused only while no one else holds any part of one
        # (_output_set, _free): so a loop that keeps each step's Wrench until the next is stepped without making new
        # arrays, and a result that is kept is never written over
        self._spare, self._other = (_output_set(n, self._kernel_args, self._pose_buffers),
                                    _output_set(n, self._kernel_args, self._pose_buffers))
        self._misses = 0  # the hot path's steps since one last reused a set
        #: the last step's force on every element [N], world frame, shape (n, 3)
        self.element_forces = np.zeros((n, 3))

    # what the contact was made with: read-only (the compiled step holds them; a change would reach one path)
    @property
    def params(self) -> MudParameters:
        """The mud."""
        return self._params

    @property
    def shape(self) -> Shape:
        """The foot's surface, body frame."""
        return self._shape

    @property
    def surface_height(self) -> float:
        """Height of the undisturbed mud surface in the world frame [m]."""
        return self._surface_height

    @property
    def width(self) -> float:
        """The intruder width ``H`` of Eq. (4) [m]."""
        return self._width

    @property
    def lateral_stiffness(self) -> float:
        """Stiffness of the horizontal elastic slip [Pa/m]."""
        return self._lateral_stiffness

    @property
    def bearing_scale(self) -> float:
        """The sideways bearing's scale [-] (1: 3D-RFT's granular bearing)."""
        return self._bearing_scale

    @property
    def _started(self) -> bool:
        """Whether the contact has taken its first step."""
        return bool(self._foot[0, S3.F_STARTED] != 0.0)

    @_started.setter
    def _started(self, started: bool) -> None:
        self._foot[0, S3.F_STARTED] = 1.0 if started else 0.0

    # ------------------------------------------------------------------ state
    def _export_rows(self) -> None:
        """The compiled step's lanes into the elements' 1-D rows, slips and centroids, if a step has left them
        behind (:func:`mudforce._kernel.step3d.export_rows`): before anything reads them."""
        S3.export_rows(self._block, self._elements._states)

    def _import_rows(self) -> None:
        """The elements' 1-D rows, slips and centroids into the compiled step's lanes: after anything wrote them."""
        S3.lanes_from_rows(self._block, self._elements._states)

    @property
    def state(self) -> ContactState3D:
        """A copy of everything the contact remembers; assign one back to restore it (a state of another shape, whose
        centroids are not this one's turned and moved, is refused and nothing is changed)."""
        self._export_rows()
        return ContactState3D(self._elements.state, self._slip.copy(), self._centroids.copy(), self._started)

    @state.setter
    def state(self, saved: ContactState3D) -> None:
        if not isinstance(saved, ContactState3D):
            raise InputError(f"state must be a ContactState3D from .state, got {type(saved).__name__}")
        slip = real_array(saved.slip, "a state's slips", "m")  # refuses strings, complex, objects (as MudContacts3D)
        centroids = real_array(saved.centroids, "a state's centroids", "m")
        started = true_or_false(saved.started, "a state's started")
        n = self.shape.n
        if slip.shape != (n, 2) or centroids.shape != (n, 3):
            raise InputError(f"a state of this {n}-element foot has slips (n, 2) and centroids (n, 3), got "
                             f"{slip.shape} and {centroids.shape}")
        _check_saved_places(slip, centroids, _reach(self.shape))
        _check_saved_shapes(centroids, self._shape.centroids, np.array([0, n]), np.array([started]))
        elements = real_array(saved.elements, "a state's elements", "SI")
        rows = (n, K.N_STATE + self._elements.ring.shape[1])
        if elements.shape != rows:  # checked here, in elements' words (MudContacts' setter speaks of feet)
            raise InputError(f"a state of this {n}-element foot has element states of shape {rows}, got "
                             f"{elements.shape}")
        check_states(elements[:, :K.N_STATE], elements[:, K.N_STATE:], "a state", unit="element")
        # written as MudContacts' setter writes them (checked above once, in elements' words)
        self._export_rows()  # (the rows are all written below; the flag cleared)
        _restore_rows(self._elements._states, self._elements.ring, self._elements.params_array, elements)
        self._slip[:] = slip
        self._centroids[:] = centroids
        self._started = started
        self._import_rows()

    @property
    def modes(self) -> list[str]:
        """Each element's contact state: ``"FREE"``, ``"CONTACT"`` or ``"NECKED"``."""
        self._export_rows()
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
            Force [N] and torque about the body origin [N m], world frame. A later step reuses its arrays (and
            :attr:`element_forces`') only once no one holds any of them: kept results keep their values.
        """
        # compiled: MudContacts3D's step of one foot (S3.step_feet, through the same dispatcher of its compiled
        # code, typed by numba), with every element's force and the wrench summed in element order: the numpy step
        # below, its bits. The hot path takes float64 arrays and a float dt; _step_converted takes the first step
        # and other inputs; a step either refuses (having changed nothing) goes through the numpy step, which words
        # the error
        outputs = self._spare  # the outputs not returned last: reused if no one holds any part of them (_free)
        free = (_refs(outputs[6]) == _FREE_WRENCH and _refs(outputs[4]) == _FREE_VIEW
                and _refs(outputs[5]) == _FREE_VIEW and _refs(outputs[1]) == _FREE_EACH
                and _refs(outputs[0]) == _FREE_BLOCK)
        entry = self._entry
        # the hot path: float64 vectors (any strides) through step_one's entry point, into a free output set
        if (free and entry is not None and type(dt) is float and type(position) is _NDARRAY
                and type(quaternion) is _NDARRAY and position.dtype is _FLOAT64 and quaternion.dtype is _FLOAT64
                and position.ndim == 1 and quaternion.ndim == 1):
            if entry(position, quaternion, dt, outputs[8]) == _OK:
                self._misses = 0
                self.element_forces = outputs[1]
                self._spare, self._other = self._other, outputs
                return outputs[6]  # type: ignore[no-any-return]
            return self._step_numpy(position, quaternion, dt)  # refused for its values: the numpy step words it
        fixed = self._fixed
        if type(dt) is float and fixed is not None and type(position) is _NDARRAY and type(quaternion) is _NDARRAY:
            if free:
                self._misses = 0
            elif self._misses < 2 or self._misses % 32 == 31:  # held: left to its holder, a new set in its place
                self._misses += 1
                outputs = self._spare = _output_set(self._n3[0], self._kernel_args, self._pose_buffers)
            else:  # results kept step after step: new outputs alone, cheaper than a set (a set now and then, so
                self._misses += 1  # that the two sets are free again soon after they no longer are kept)
                forces, torques, each = _empty(_ONE3), _empty(_ONE3), _empty(self._n3)
                try:
                    code = fixed(position[None], quaternion[None], dt, *self._kernel_args, forces, torques, each)
                except TypeError:  # numba's "no matching definition": another type of argument
                    code = S3.BAD_SHAPE
                if code == _OK:
                    self.element_forces = each
                    return _new_tuple(Wrench, (forces[0], torques[0]))  # type: ignore[no-any-return]
                outputs = ()
            if outputs:
                if (position.dtype is _FLOAT64 and quaternion.dtype is _FLOAT64 and position.ndim == 1
                        and quaternion.ndim == 1):  # the types step_one's entry point takes (any strides)
                    code = self._entry(position, quaternion, dt, outputs[8])
                else:
                    try:
                        code = fixed(position[None], quaternion[None], dt, *outputs[7])  # the arguments after dt
                    except TypeError:  # numba's "no matching definition": another type of argument
                        code = S3.BAD_SHAPE
                if code == _OK:
                    self.element_forces = outputs[1]
                    self._spare, self._other = self._other, outputs
                    return outputs[6]  # type: ignore[no-any-return]
            if code != S3.BAD_SHAPE:  # refused for its values: the numpy step words the error
                return self._step_numpy(position, quaternion, dt)
        return self._step_converted(position, quaternion, dt)

    def _step_converted(self, position: Any, quaternion: Any, dt: Any) -> Wrench:
        """:meth:`step` for its first step and for inputs of other types: converted as the numpy step converts them
        (``np.asarray`` to float64, made C-contiguous and writable; a real ``dt`` as a float, any ``dt`` before the
        first step ignored), then the compiled step; what is not converted, or is refused, goes through the numpy
        step, which words the error. (So a contact stepped with lists, or from its first step, compiles nothing but
        the one step MudContacts3D compiles.)"""
        if self._fixed is None:
            self._fixed = self._fixed_types()
        try:  # real numbers only (a bool or complex array is refused by the numpy step, as there)
            p = np.array(real_array(position, "position", "m"), order="C")
            q = np.array(real_array(quaternion, "quaternion", "-"), order="C")
        except InputError:
            return self._step_numpy(position, quaternion, dt)
        if is_real(dt) and abs(dt) <= MAX_DT:  # (a Python int beyond float64: float() raised OverflowError)
            h = float(dt)
        elif not self._started:
            h = 1.0  # ignored by a first step (as the numpy step ignores it)
        else:
            return self._step_numpy(position, quaternion, dt)
        forces, torques, each = _empty(_ONE3), _empty(_ONE3), _empty(self._n3)
        try:
            code = self._fixed(p[None], q[None], h, *self._kernel_args, forces, torques, each)
        except TypeError:  # numba's "no matching definition": not one pose (a 2-D position, ...)
            code = S3.BAD_SHAPE
        if code != _OK:
            return self._step_numpy(position, quaternion, dt)
        self.element_forces = each
        return _new_tuple(Wrench, (forces[0], torques[0]))

    def _step_numpy(self, position: Any, quaternion: Any, dt: Any) -> Wrench:
        """:meth:`step` on numpy arrays, every argument checked (converted, or refused with a one-line error).

        The law's functions on the elements' columns, the reference that :meth:`step` takes compiled bit
        for bit; once it has stepped, :meth:`step` takes the compiled step.
        """
        p, rotation = _pose(position, quaternion)
        if self._started:
            if not is_real(dt) or not MIN_DT <= dt <= MAX_DT:  # compared as given: float() of 10**400 overflowed
                raise InputError(f"dt must be within [{MIN_DT:g}, {MAX_DT:g}] s after the first step, got {shown(dt)}")
            dt = float(dt)
        else:
            dt = 1.0  # ignored by the elements' first step
        shape = self.shape
        q = self.params
        self._export_rows()  # the elements' rows as the compiled step left them
        # the law of mudforce.model.law3d on the elements' columns (the functions the compiled step and JAX call)
        r = tuple(rotation.ravel().tolist())
        ox, oy, oz = law3d.rotate(r, *shape.centroids.T)
        nx, ny, nz = law3d.rotate(r, *shape.normals.T)
        wx, wy, wz = p[0] + ox, p[1] + oy, p[2] + oz
        depth = law3d.element_depth(self.surface_height, p[2], oz)
        if self._started:  # an element turned about at its depth is at rest, not moving by rounding
            depth = law3d.settle_depth(depth, self._elements.depths)  # the depths the elements were stepped to
        if not np.all(np.abs(depth) <= MAX_DEPTH):  # worded for the foot (the elements' stepper says "foot k")
            k = int(np.flatnonzero(~(np.abs(depth) <= MAX_DEPTH))[0])
            raise InputError(f"element {k} would be at depth {float(depth[k])!r} m, beyond +-{MAX_DEPTH:g} m of the "
                             f"surface (position {p.tolist()!r} [m]); the foot was not stepped")
        # the paper, element by element
        stress = self._elements.step(depth, dt)
        mx, my = wx - self._centroids[:, 0], wy - self._centroids[:, 1]
        if self._started:  # law3d.element_force and law3d.moment on every element, compiled (S3.element_forces)
            spring = law3d.bearing_stress(law3d.spring_stress(depth, q.alpha, q.beta, self.width), self.bearing_scale)
            out = np.empty((shape.n, 8))
            S3.element_forces(stress, spring, self._areas, nx, ny, nz, ox, oy, oz, depth, self._slip.copy(), mx, my,
                              1.0 / dt, self.lateral_stiffness, q.sigma_y, q.lambda_, q.rho_m, out)
            slip_x, slip_y = out[:, 0], out[:, 1]
            forces = out[:, 2:5]
            torques = out[:, 5:8]
        else:  # the first step: element_force's values without a last pose, without its arithmetic
            zero = np.zeros(shape.n)
            slip_x = slip_y = zero
            fx, fy, fz = law3d.vertical_element_force(stress, shape.areas, nx, ny, nz)
            fx, fy = zero + fx, zero + fy  # element_force's 0 + the vertical's sideways part (-0.0 becomes 0.0)
            forces = np.stack([fx, fy, fz], axis=1)
            torques = np.stack(law3d.moment(ox, oy, oz, fx, fy, fz), axis=1)
        self._slip[:, 0] = slip_x
        self._slip[:, 1] = slip_y
        self._centroids[:, 0] = wx
        self._centroids[:, 1] = wy
        self._centroids[:, 2] = wz
        self._started = True
        self._import_rows()  # the rows as this step left them, for the compiled step
        self.element_forces = forces
        if self._fixed is None:  # the 1-D stepper has compiled: the compiled step can be taken from now on
            self._fixed = self._fixed_types()
        return Wrench(forces.sum(axis=0), torques.sum(axis=0))

    def _fixed_types(self) -> Any:
        """The compiled step, compiled (or loaded from numba's cache) for this contact's arrays (MudContacts3D's
        types: the same compiled code), through MudContacts3D.step's dispatcher of it (:func:`_fixed_step`)."""
        pose = (np.zeros((1, 3)), np.zeros((1, 4)), 1.0)
        outputs = (np.zeros(_ONE3), np.zeros(_ONE3), np.zeros(self._n3))
        _dispatcher.compile(tuple(typeof(a) for a in (*pose, *self._kernel_args, *outputs)))
        self._entry = entry_point(S3.step_one, _ONE_POSE)
        return _fixed_step()

    def reset(self) -> None:
        """Forget the history: the next step is a first step, and :attr:`element_forces` is as before any step."""
        self._export_rows()  # (the centroids are kept)
        self._elements.reset()
        self._slip[:] = 0.0
        self._started = False
        self._import_rows()
        self.element_forces = np.zeros(self._n3)  # (a new array: a kept one keeps its values)

    def __repr__(self) -> str:
        return f"MudContact3D({self.shape!r}, surface_height={self.surface_height:g})"


@dataclass(frozen=True, eq=False)
class Result3D:
    """A 3-D simulation: the wrench at each pose (:func:`simulate_3d`).

    Its arrays are the caller's own: new arrays (``time`` a copy of the
    motion's), writable, shared with nothing; writing into one changes no
    other (nothing is computed from them on access, unlike
    :class:`~mudforce.SimulationResult`'s read-only stresses).

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
        from mudforce._plumbing.optional import require

        pd = require("pandas", "pandas", "Result3D.to_pandas")
        columns: dict[str, np.ndarray] = {"time_s": self.time}
        for k, axis in enumerate("xyz"):
            columns[f"force_{axis}_N"] = self.force[:, k]
        for k, axis in enumerate("xyz"):
            columns[f"torque_{axis}_N_m"] = self.torque[:, k]
        return pd.DataFrame(columns)


def simulate_3d(time: Any, positions: Any, quaternions: Any, params: MudParameters, shape: Shape, *,
                surface_height: float = 0.0, width: float | None = None, lateral_stiffness: float | None = None,
                bearing_scale: float | None = None,
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
        The foot's surface (:mod:`mudforce.model.shapes`).
    surface_height, width, lateral_stiffness, bearing_scale
        As for :class:`MudContact3D` ([m], [m], [Pa/m], [-]).
    elements : bool
        Also keep every element's force at every sample (``m n 3`` numbers).

    Returns
    -------
    Result3D

    Warns
    -----
    RuntimeWarning
        When every quaternion's w is within :data:`HALF_TURN_W` of 0 (every pose a half turn): an upright
        foot's quaternions in (x, y, z, w) order read so (the result is computed as given).
    """
    elements = true_or_false(elements, "elements")
    t = real_array(time, "time", "s")
    x = real_array(positions, "positions", "m")
    q = real_array(quaternions, "quaternions", "-")
    m = t.shape[0] if t.ndim == 1 else -1
    if m == 0 and x.shape == (0, 3) and q.shape == (0, 4):  # they agree: "must agree" said otherwise
        raise InputError("the motion is empty; expected at least one sample (time (m,), positions (m, 3) and "
                         "quaternions (m, 4), m >= 1)")
    if m < 1 or x.shape != (m, 3) or q.shape != (m, 4):
        raise InputError(f"time (m,), positions (m, 3) and quaternions (m, 4) must agree, got {t.shape}, "
                         f"{x.shape} and {q.shape}")
    check_times(t)
    contact = MudContact3D(params, shape, surface_height, width=width, lateral_stiffness=lateral_stiffness,
                           bearing_scale=bearing_scale)
    if elements and m * shape.n > MAX_ELEMENT_SAMPLES:  # before numpy is asked for them (a MemoryError, or swap)
        raise InputError(f"elements=True would keep {m} samples x {shape.n} elements = {m * shape.n:.3g} element "
                         f"forces ({m * shape.n * 24 / 1e9:.3g} GB), more than {MAX_ELEMENT_SAMPLES:.0e}; use fewer "
                         "samples or a coarser shape, or step a MudContact3D and keep its element_forces where needed")
    force = np.empty((m, 3))
    torque = np.empty((m, 3))
    per_element = np.empty((m, shape.n, 3)) if elements else None
    for k in range(m):
        try:
            wrench = contact.step(x[k], q[k], float(t[k] - t[k - 1]) if k else 0.0)
        except InputError as error:  # the pose's own words, with the sample it is at
            raise InputError(f"sample {k} (t = {float(t[k])!r} s): {error}") from None
        force[k] = wrench.force
        torque[k] = wrench.torque
        if per_element is not None:
            per_element[k] = contact.element_forces
    if np.all(np.abs(q[:, 0]) <= HALF_TURN_W):  # after the steps: a pose refused is not warned of
        warnings.warn(f"simulate_3d: every quaternion has w = q[0] within +-{HALF_TURN_W:g} (the foot turned half a "
                      f"turn at every sample, e.g. {q[0].tolist()!r}); if they are (x, y, z, w), as ROS and scipy "
                      "write them, give (w, x, y, z), MuJoCo's order: np.roll(q, 1, axis=1)", RuntimeWarning,
                      stacklevel=2)
    return Result3D(t.copy(), force, torque, per_element)


class ContactStates3D(NamedTuple):
    """Everything a :class:`MudContacts3D` remembers, for ``contacts.state = saved`` (rollouts, resets).

    The elements of all feet are concatenated, foot after foot (foot ``f``'s
    are rows ``contacts.element_slice(f)``).

    Attributes
    ----------
    elements : ndarray, shape (N, ...)
        The elements' 1-D states (rows as in :meth:`mudforce.steppers.many.MudContacts.snapshot`).
    slip : ndarray, shape (N, 2)
        The elements' horizontal elastic slips [m].
    centroids : ndarray, shape (N, 3)
        The elements' world centroids at the last step [m].
    started : ndarray of bool, shape (m,)
        Whether each foot has taken its first step.
    """

    elements: np.ndarray
    slip: np.ndarray
    centroids: np.ndarray
    started: np.ndarray


def _per_foot(value: Any, m: int | None, name: str, kind: type | tuple[type, ...], expected: str) -> list[Any] | None:
    """``value`` as a list of one item per foot if it is a sequence (not a ``kind`` itself), else None.

    ``expected`` words one item for the message (``"a MudParameters"``).
    """
    if isinstance(value, kind) or value is None or is_real(value):
        return None
    if isinstance(value, (str, bytes, Mapping, AbstractSet)):  # a mapping's keys, a set's order: not one per foot
        raise InputError(f"{name} must be {expected} or a sequence of them, one per foot, got {type(value).__name__}")
    try:
        items = list(value)
    except TypeError:
        raise InputError(f"{name} must be {expected} or a sequence of them, one per foot, "
                         f"got {type(value).__name__}") from None
    if m is not None and len(items) != m:
        raise InputError(f"got {len(items)} {name} for {m} feet; give one, or one per foot")
    return items


def _float_rows(value: Any, name: str, shape: tuple[int, int], unit: str) -> np.ndarray:
    """``value`` as a float64 array of ``shape`` (no copy if it is one), else a one-line InputError."""
    if type(value) is np.ndarray and value.dtype == np.float64 and value.shape == shape:  # (not a masked array)
        return value
    try:
        array = real_array(value, name, unit)
    except InputError:
        raise
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of real numbers of shape {shape} [{unit}]") from None
    if array.shape != shape:
        raise InputError(f"{name} must have shape {shape} [{unit}], got {array.shape}")
    return array


def _check_saved_places(slip: np.ndarray, centroids: np.ndarray, reach: float) -> None:
    """Refuse a saved state's slips [m] or world centroids [m] that no step could have left: not finite, or farther
    than :data:`~mudforce._kernel.bounds.MAX_HORIZONTAL` (plus the foot's ``reach`` [m], for the centroids)."""
    bound = MAX_HORIZONTAL + reach
    if not (np.all(np.abs(slip) <= MAX_HORIZONTAL) and np.all(np.abs(centroids) <= bound)):
        raise InputError(f"a state's slips must be finite and within +-{MAX_HORIZONTAL:g} m and its centroids "
                         f"within +-{bound:.6g} m (where a step can leave them)")


def _check_saved_shapes(centroids: np.ndarray, body: np.ndarray, starts: np.ndarray, started: np.ndarray) -> None:
    """Refuse a saved state whose world centroids [m] are not, for each foot that has started, its shape's body-frame
    centroids ``body`` [m] turned and moved: a state of another shape with as many elements (a 4 cm sphere's took an
    8 cm one's). Each step writes every element's world centroid ``p + R c`` (a foot that has not started holds no
    pose, and is not checked); the best rotation of each foot is Kabsch's (an SVD of its 3 x 3 cross-covariance), and
    the fit must hold within rounding (1024 ulps of the largest coordinate; a valid state's is within 8, a sphere
    0.1 um wider missed by 5e-8 m). ``starts`` are the feet's first element rows, then the total."""
    if not started.any():
        return
    tolerance = 1024.0 * np.finfo(np.float64).eps
    sizes = np.diff(starts)
    foot_of = np.repeat(np.arange(sizes.size), sizes)
    first = starts[:-1]
    world = centroids - (np.add.reduceat(centroids, first, axis=0) / sizes[:, None])[foot_of]
    shape = body - (np.add.reduceat(body, first, axis=0) / sizes[:, None])[foot_of]
    u, _, vt = np.linalg.svd(np.add.reduceat(shape[:, :, None] * world[:, None, :], first, axis=0))
    u[:, :, 2] *= np.where(np.linalg.det(u @ vt) < 0.0, -1.0, 1.0)[:, None]  # a rotation, not a reflection
    fit = np.einsum("ei,eij->ej", shape, (u @ vt)[foot_of])
    misses = np.maximum.reduceat(np.abs(fit - world).max(axis=1), first)
    scale = np.maximum.reduceat(np.abs(centroids).max(axis=1) + np.abs(body).max(axis=1), first)
    bad = np.flatnonzero(started & (misses > tolerance * scale))
    if bad.size:
        which = f" (foot {bad[0]})" if started.size > 1 else ""
        raise InputError(f"a state's centroids{which} are not this foot's shape turned and moved: a state of another "
                         "shape; expected a state taken from a contact of these shapes")


def _reach(shape: Shape) -> float:
    """The farthest element centroid of ``shape`` from its body origin [m] (step3d's ``F_REACH``)."""
    return float(np.sqrt((np.asarray(shape.centroids, dtype=np.float64) ** 2).sum(axis=1)).max(initial=0.0))


def _fill_foot(row: np.ndarray, params: MudParameters, surface_height: float, width: float, stiffness: float,
               bearing: float, shape: Shape) -> None:
    """One foot's row of the compiled step's foot table (step3d's ``F_*`` columns): the surface height [m], the
    width ``H`` of Eq. (4) [m], the lateral stiffness [Pa/m], the bearing scale [-], the mud's constants and the
    shape's reach [m]."""
    row[S3.F_SURFACE] = surface_height
    row[S3.F_WIDTH] = width
    row[S3.F_STIFFNESS] = stiffness
    row[S3.F_SIGMA_Y] = params.sigma_y
    row[S3.F_ALPHA] = params.alpha
    row[S3.F_BETA] = params.beta
    row[S3.F_LAMBDA] = params.lambda_
    row[S3.F_RHO] = params.rho_m
    row[S3.F_REACH] = _reach(shape)
    row[S3.F_BEARING] = bearing


def _fill_elements(rows: np.ndarray, shape: Shape) -> None:
    """One foot's rows of the compiled step's element table (step3d's ``E_*`` columns): the body-frame centroids
    [m], normals [-] and areas [m^2] of ``shape``."""
    rows[:, S3.E_CBX:S3.E_CBZ + 1] = shape.centroids
    rows[:, S3.E_NBX:S3.E_NBZ + 1] = shape.normals
    rows[:, S3.E_AREA] = shape.areas


def _writable_rows(a: Any, m: int) -> bool:
    """Whether ``a`` can receive (m, 3) float64 results in place."""
    return isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape == (m, 3) and bool(a.flags.writeable)


# :meth:`MudContacts3D.step`'s hot path, as module globals (one look-up each)
_NDARRAY = np.ndarray
_OK = S3.OK
_empty = np.empty
_step_feet = S3.step_feet
_dispatcher: Any = S3.step_feet  # (numba's dispatcher: its compiled versions)
# step_one's types: a pose of float64 vectors of any strides, a float dt, the address table
_ONE_POSE = (numba_types.Array(numba_types.float64, 1, "A"), numba_types.Array(numba_types.float64, 1, "A"),
             numba_types.float64, numba_types.Array(numba_types.int64, 1, "C"))
_fixed: list[Any] = [0, None]  # how many compiled versions _step_feet had, and S3.fixed_types of it then
_NO_EACH = np.zeros((0, 3))  # step_feet's ``each`` for MudContacts3D: no element's force, each foot's own order
_ONE3 = (1, 3)
_new_tuple = tuple.__new__


def _output_set(n: int, kernel_args: tuple[np.ndarray, ...], pose: tuple[np.ndarray, np.ndarray] | None = None
                ) -> tuple[Any, ...]:
    """Outputs of :meth:`MudContact3D.step`'s compiled step for ``n`` elements, in one (n + 2, 3) block: the
    block, every element's force [N] (n, 3), the foot's force and torque rows as the step writes them ((1, 3) each)
    and as the Wrench holds them ((3,) each), the Wrench [N], [N m], the compiled step's arguments after ``dt``
    (``kernel_args``, then the outputs) and, with the contact's ``pose`` buffers, the address table of its one-foot
    form (:func:`mudforce._kernel.step3d.step_one`: ``kernel_args``, ``pose``, the outputs)."""
    block = np.zeros((n + 2, 3))
    each, forces, torques = block[:n], block[n:n + 1], block[n + 1:]
    force, torque = block[n], block[n + 1]
    table = address_table((*kernel_args, *pose, forces, torques, each)) if pose is not None else None
    return (block, each, forces, torques, force, torque, _new_tuple(Wrench, (force, torque)),
            (*kernel_args, forces, torques, each), table)


_refs = sys.getrefcount


def _free(outputs: tuple[Any, ...]) -> tuple[int, int, int, int]:
    """The reference counts of ``outputs`` (:func:`_output_set`)' Wrench, force view, element forces and block, as
    :meth:`MudContact3D.step` reads them; counted on a set no one else holds (below), they are the counts of a free
    set on this Python: any other holder (the Wrench, its arrays, a view of them or their base, the element
    forces) adds one, and the set is not reused."""
    return _refs(outputs[6]), _refs(outputs[4]), _refs(outputs[1]), _refs(outputs[0])


def _free_pair(pair: tuple[np.ndarray, np.ndarray]) -> int:
    """The reference count of an array held by nothing but ``pair`` (:meth:`MudContacts3D.step`'s outputs), as
    the step reads it (see :func:`_free`)."""
    return _refs(pair[0])


_FREE_WRENCH, _FREE_VIEW, _FREE_EACH, _FREE_BLOCK = _free(_output_set(1, ()))
_FREE_ARRAY = _free_pair((np.zeros((1, 3)), np.zeros((1, 3))))


def _fixed_step() -> Any:
    """:func:`mudforce._kernel.step3d.fixed_types` of the compiled step (made again when numba has compiled more)."""
    if _fixed[0] != len(_dispatcher.overloads):
        _fixed[:] = [len(_dispatcher.overloads), S3.fixed_types(_dispatcher)]
    return _fixed[1]


class MudContacts3D:
    """Many feet of any shapes in mud, stepped together, one pose each per step (simulators, RL).

    Foot ``f`` is a :class:`MudContact3D` in all but speed: each step runs
    :mod:`mudforce.model.law3d`'s law through one compiled call for all feet
    (:mod:`mudforce._kernel.step3d`, which steps every element's paper
    state with the 1-D stepper's functions). The wrench of a foot equals
    :class:`MudContact3D`'s bit for bit (the same compiled step, summing
    the elements in element order) and does not depend on the other feet.

    Parameters
    ----------
    params : MudParameters or sequence of MudParameters
        The mud: one for all feet, or one per foot (domain randomisation).
    shapes : Shape or sequence of Shape
        The feet's surfaces (:mod:`mudforce.model.shapes`), body frame: one for
        all feet, or one per foot.
    n : int, optional
        Number of feet; by default the length of ``params`` or ``shapes``
        (needed when both are single).
    surface_heights : float or sequence of float
        Height of each foot's undisturbed mud surface, world frame [m].
    widths : float or sequence of float, optional
        The intruder width ``H`` of Eq. (4) [m]; by default each shape's width.
    lateral_stiffness : float or sequence of float, optional
        Stiffness of the horizontal elastic slip [Pa/m]; by default each
        mud's ``k_m_w``.
    bearing_scale : float or sequence of float, optional
        The sideways bearing's scale [-]; by default 1 (as for :class:`MudContact3D`).
    threads : int or None
        Step the feet in this many slices on numba's threads (at most one
        per foot); 1 (the default) steps them on the calling thread.
        ``None`` chooses as :class:`mudforce.MudContacts` does for as many
        feet as there are elements here (one slice per core above 1024
        elements per thread, with numba's OpenMP or TBB layer; else 1).
        The results do not depend on it. (Not the automatic choice by
        default: on the shared 2-core machine where it was written, two
        threads were never measured faster than one; docs/speed.md.)

    Examples
    --------
    >>> import numpy as np
    >>> import mudforce as mf
    >>> from mudforce.model import shapes
    >>> feet = mf.MudContacts3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04), 4)
    >>> quats = np.tile([1.0, 0.0, 0.0, 0.0], (4, 1))
    >>> forces, torques = feet.step(np.tile([0.0, 0.0, 0.015], (4, 1)), quats, 0.0)
    >>> forces, torques = feet.step(np.tile([0.0, 0.0, 0.010], (4, 1)), quats, 0.01)
    >>> bool((forces[:, 2] > 0.0).all())
    True
    """

    def __init__(self, params: MudParameters | Sequence[MudParameters], shapes: Shape | Sequence[Shape],
                 n: int | None = None, *, surface_heights: float | Sequence[float] = 0.0,
                 widths: float | Sequence[float] | None = None,
                 lateral_stiffness: float | Sequence[float] | None = None,
                 bearing_scale: float | Sequence[float] | None = None, threads: int | None = 1) -> None:
        m = None if n is None else feet_count(n)
        muds = _per_foot(params, m, "params", MudParameters, "a MudParameters")
        m = len(muds) if muds is not None and m is None else m
        feet = _per_foot(shapes, m, "shapes", Shape, "a mudforce.model.shapes.Shape")
        m = len(feet) if feet is not None and m is None else m
        if m is None:
            raise InputError("give n, the number of feet (params and shapes are one each)")
        if m < 1:
            raise InputError("give at least one foot")
        muds = muds if muds is not None else [params] * m
        feet = feet if feet is not None else [shapes] * m
        heights = _per_foot(surface_heights, m, "surface_heights", (), "a number [m]") or [surface_heights] * m
        given_widths = _per_foot(widths, m, "widths", (), "a number [m]") or [widths] * m
        stiffness = (_per_foot(lateral_stiffness, m, "lateral_stiffness", (), "a number [Pa/m]")
                     or [lateral_stiffness] * m)
        scales = _per_foot(bearing_scale, m, "bearing_scale", (), "a number [-]") or [bearing_scale] * m
        for f in range(m):
            if not isinstance(muds[f], MudParameters):
                raise InputError(f"params must be MudParameters (one, or one per foot), got {type(muds[f]).__name__}")
            if not isinstance(feet[f], Shape):
                raise InputError(f"shapes must be mudforce.model.shapes.Shape (one, or one per foot), got "
                                 f"{type(feet[f]).__name__}")
        self.n = m
        self.params: tuple[MudParameters, ...] = tuple(muds)
        self.shapes: tuple[Shape, ...] = tuple(feet)
        sizes = np.array([s.n for s in feet], dtype=np.int64)
        self._starts = np.zeros(m + 1, dtype=np.int64)
        np.cumsum(sizes, out=self._starts[1:])
        total = int(self._starts[-1])
        ft = np.zeros((m, S3.N_FOOT_COLUMNS))
        rows = np.empty((total, K.N_PARAMS))
        exact = resolve_velocity_filter("exact")
        made: dict[tuple[int, float], np.ndarray] = {}  # 1-D params rows already made, by mud and width
        for f in range(m):
            q, shape = muds[f], feet[f]
            h = bounded_depth(heights[f], "surface_height")
            w = (number_within(given_widths[f], "widths", *SIZE_RANGE, "m") if given_widths[f] is not None
                 else shape.width)
            if w is None:
                raise InputError("this shape has no width H for Eq. (4); give width= [m] (or build the shape with "
                                 "a mudforce.model.shapes constructor, which sets it)")
            foot = Foot(area=1.0, width=w, shape="element")
            k = check_lateral_stiffness(q.k_m_w if stiffness[f] is None else stiffness[f])
            bearing = check_bearing_scale(1.0 if scales[f] is None else scales[f])
            key = (id(q), float(foot.width))
            if key not in made:
                made[key] = _param_rows(q, 1, foot, exact)[0]
            rows[self._starts[f]:self._starts[f + 1]] = made[key]
            _fill_foot(ft[f], q, h, foot.width, k, bearing, shape)
        el = np.zeros((total, S3.N_ELEMENT_COLUMNS))
        for f, shape in enumerate(feet):
            _fill_elements(el[self._starts[f]:self._starts[f + 1]], shape)
        self._el = el
        self._ft = ft
        self._params_rows = rows
        self._states = K.new_states(total)
        self._ring = K.new_ring(total, 1)
        #: slices the feet are stepped in, one per thread (1: the calling thread only)
        self.threads = min(vectorized._resolve_threads(threads, total), m)
        self._chunks = np.empty(self.threads, dtype=np.int64)
        # the step's own arrays in one (one argument, not five): the elements, the feet, the lanes (every element's
        # state, field by field, four elements side by side: the compiled step's vectorised loops), the starts
        block = S3.new_block(self._starts)
        self._el, self._ft, _, _, _ = S3.block_views(block)
        self._el[:] = el
        self._ft[:] = ft
        self._block = block
        self._entries = S3.lane_entries(block)  # each element's place in the lanes
        self._follow_rows = False  # kernel_rows' views asked for: every step exports the rows
        S3.lanes_from_rows(block, self._states)  # the elements' constants and fresh states into the lanes
        # the compiled step's arguments after the poses and dt, before the outputs
        self._kernel_args = (block, self._states, self._ring, self._params_rows)
        # what step() reads on every call, in one attribute: the shape of the outputs, the compiled step's arguments
        # and the dispatcher of its hot path (None until the first step has compiled the step, and with threads)
        self._hot: tuple[tuple[int, int], tuple[np.ndarray, ...], Any] = ((m, 3), self._kernel_args, None)
        # step()'s outputs without out=: two pairs taken in turn, each reused only while no one holds either array
        self._spare, self._other = (np.zeros((m, 3)), np.zeros((m, 3))), (np.zeros((m, 3)), np.zeros((m, 3)))

    # ------------------------------------------------------------------ layout
    @property
    def n_elements(self) -> int:
        """The number of elements of all feet together."""
        return int(self._starts[-1])

    def element_slice(self, foot: int) -> slice:
        """The rows of foot ``foot``'s elements in :attr:`state`'s arrays."""
        if not is_integer(foot):  # not int(): 0.7 would be foot 0
            raise InputError(f"foot must be an integer index 0..{self.n - 1}, got {type(foot).__name__} {shown(foot)}")
        f = int(foot)
        if not -self.n <= f < self.n:
            raise InputError(f"foot index out of range 0..{self.n - 1}: {shown(foot)}")
        f %= self.n
        return slice(int(self._starts[f]), int(self._starts[f + 1]))

    def kernel_rows(self) -> tuple[np.ndarray, np.ndarray]:
        """Read-only views of the elements' 1-D state rows and constant rows (layout of :mod:`mudforce._kernel`).

        One row per element, foot after foot (:meth:`element_slice`); each
        element is stepped with a unit area, so a force computed from these
        rows (a rest band, :func:`mudforce.engines.dynamics.rest_band.branch_forces`)
        is the element's stress [Pa]. For engines that hold the feet in their
        own solver (:class:`mudforce.engines.mujoco.MudAdapter3D`); the views
        follow the feet as they are stepped (from the first call on, each step
        then writes the rows from the compiled step's lanes, where it keeps the
        states: a few ns an element).
        """
        self._follow_rows = True
        self._export_rows()
        states, rows = (a.view() for a in self._live_rows())
        states.flags.writeable = False
        rows.flags.writeable = False
        return states, rows

    def _live_rows(self) -> tuple[np.ndarray, np.ndarray]:
        """The elements' own state and constant rows, writable (what :meth:`kernel_rows` views): for the engines
        in this package that pass them to compiled code, which compiles once for writable arrays (the MuJoCo
        3-D adapter's rest band). They are the arrays the steps write their export to: call :meth:`_export_rows`
        after a step, before reading them."""
        return self._states, self._params_rows

    @property
    def _stress(self) -> np.ndarray:
        """The elements' paper stresses of the last step [Pa] (the 1-D stepper's force on a unit area), foot after
        foot: a copy, for the tests that hold them to the 1-D stepper's."""
        lanes = S3.block_views(self._block)[3]
        stress: np.ndarray = lanes[self._entries + S3.W_STRESS * S3.FIELD]
        return stress

    def _live_lanes(self) -> tuple[np.ndarray, np.ndarray]:
        """Where the compiled step keeps the elements' states (:mod:`mudforce._kernel.step3d`'s lanes, one flat
        array) and each element's place in them (:func:`mudforce._kernel.step3d.lane_entries`): for an engine
        that reads a few rows after a step and exports only those (:func:`mudforce._kernel.step3d.row_from_lanes`,
        the MuJoCo 3-D adapter's rest band)."""
        return S3.block_views(self._block)[3], self._entries

    def _export_rows(self) -> None:
        """The compiled step's lanes into the elements' 1-D rows and the element block's slips and centroids, if a
        step has left them behind (:func:`mudforce._kernel.step3d.export_rows`): before anything reads them."""
        S3.export_rows(self._block, self._states)

    def _import_rows(self) -> None:
        """The elements' 1-D rows, slips and centroids into the compiled step's lanes: after anything wrote them."""
        S3.lanes_from_rows(self._block, self._states)

    @property
    def surface_heights(self) -> np.ndarray:
        """Each foot's surface height [m] (a copy)."""
        heights: np.ndarray = self._ft[:, S3.F_SURFACE].copy()
        return heights

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> ContactStates3D:
        """A copy of everything the feet remember; assign one back to restore it (a state of other shapes, whose
        centroids are not these ones' turned and moved, is refused and nothing is changed)."""
        self._export_rows()
        el = self._el
        return ContactStates3D(np.hstack((self._states, self._ring)),
                               el[:, S3.E_SLIPX:S3.E_SLIPY + 1].copy(), el[:, S3.E_CX:S3.E_CZ + 1].copy(),
                               self._ft[:, S3.F_STARTED] != 0.0)

    @state.setter
    def state(self, saved: ContactStates3D) -> None:
        if not isinstance(saved, ContactStates3D):
            raise InputError(f"state must be a ContactStates3D from .state, got {type(saved).__name__}")
        total = self.n_elements
        elements = real_array(saved.elements, "a state's elements", "SI")
        slip = real_array(saved.slip, "a state's slips", "m")
        centroids = real_array(saved.centroids, "a state's centroids", "m")
        try:
            started = np.asarray(saved.started)
        except (TypeError, ValueError):  # ragged nesting (numpy's ValueError, "inhomogeneous shape")
            raise InputError(f"a state's started must be an array of bool of shape ({self.n},), got "
                             f"{type(saved.started).__name__} of rows of different lengths") from None
        width = K.N_STATE + self._ring.shape[1]
        if (elements.shape != (total, width) or slip.shape != (total, 2) or centroids.shape != (total, 3)
                or started.shape != (self.n,) or started.dtype != np.bool_):
            raise InputError(f"a state of these {self.n} feet ({total} elements) has elements ({total}, {width}), "
                             f"slips ({total}, 2), centroids ({total}, 3) and started ({self.n},) bool, got "
                             f"{elements.shape}, {slip.shape}, {centroids.shape} and {started.shape} {started.dtype}")
        _check_saved_places(slip, centroids, float(self._ft[:, S3.F_REACH].max()))
        _check_saved_shapes(centroids, self._el[:, S3.E_CBX:S3.E_CBZ + 1], self._starts, started)
        check_states(elements[:, :K.N_STATE], elements[:, K.N_STATE:], "a state", unit="element")  # row: element
        self._export_rows()  # (the rows are all written below; the flag cleared)
        _restore_rows(self._states, self._ring, self._params_rows, elements)  # a replay is the same bits
        self._el[:, S3.E_SLIPX:S3.E_SLIPY + 1] = slip
        self._el[:, S3.E_CX:S3.E_CZ + 1] = centroids
        self._ft[:, S3.F_STARTED] = started
        self._import_rows()

    @property
    def modes(self) -> list[str]:
        """Each element's contact state (all feet, foot after foot): ``"FREE"``, ``"CONTACT"`` or ``"NECKED"``."""
        self._export_rows()
        return [STATE_NAMES[int(v)] for v in K.state_column(self._states, "mode")]

    # ------------------------------------------------------------------ step
    def step(self, positions: Any, quaternions: Any, dt: float, *,
             out: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Move every foot to its pose and return the mud's forces and torques on them.

        Every input is checked before any foot moves: a refused step leaves
        every foot exactly as it was.

        Parameters
        ----------
        positions : array_like, shape (n, 3)
            The body origins in the world frame [m], z up.
        quaternions : array_like, shape (n, 4)
            The orientations ``(w, x, y, z)`` [-], unit (within 1e-6; normalised).
        dt : float
            Time since the previous poses [s], within [1e-9, 1e3]; ignored
            while no foot has started (a foot's first step after creation
            or :meth:`reset` ignores it).
        out : (ndarray, ndarray), optional
            Two writable float64 arrays of shape (n, 3) to receive the
            forces and torques (no allocation).

        Returns
        -------
        forces : ndarray, shape (n, 3)
            Force on each foot [N], world frame; ``[:, 2] > 0`` pushes up.
        torques : ndarray, shape (n, 3)
            Torque on each foot about its body origin [N m], world frame. Without ``out``, a later step reuses
            these arrays only once no one holds either of them: kept results keep their values.
        """
        ps, args, fixed = self._hot
        # the hot path: the compiled step through a dispatcher that takes only float64 C-contiguous arrays (of
        # writable outputs) and a float dt, typed by numba in C; what the types do not say (the shapes, the poses'
        # values, dt's bounds) the compiled step checks before anything moves. Anything else, or a step it
        # refuses, goes through _step_checked's checks, which convert it or word the error.
        spare = None
        # (one array twice, or two views of one base: to _step_checked, which refuses them where they overlap)
        if (type(out) is tuple and len(out) == 2 and out[0] is not out[1]
                and ((base := getattr(out[0], "base", None)) is None or base is not getattr(out[1], "base", None))):
            forces, torques = out
        elif out is None:  # the output pair not returned last, reused if no one holds either array (MudContact3D's)
            spare = self._spare
            if not (_refs(spare[0]) == _FREE_ARRAY and _refs(spare[1]) == _FREE_ARRAY):
                spare = self._spare = (_empty(ps), _empty(ps))  # held: left to its holder, new ones made
            forces, torques = spare
        else:
            return self._step_checked(positions, quaternions, dt, out)
        # (plain arrays only, as MudContact3D's hot path: numba's dispatcher takes a masked array as its data, masked
        # values and all)
        if type(dt) is float and fixed is not None and type(positions) is _NDARRAY and type(quaternions) is _NDARRAY:
            try:
                code = fixed(positions, quaternions, dt, *args, forces, torques, _NO_EACH)
            except TypeError:  # numba's "no matching definition": another type of argument
                code = S3.BAD_SHAPE
            if code == _OK:
                if spare is not None:
                    self._spare, self._other = self._other, spare
                if self._follow_rows:  # kernel_rows' views follow the feet
                    self._export_rows()
                return forces, torques
        return self._step_checked(positions, quaternions, dt, out)

    def _step_checked(self, positions: Any, quaternions: Any, dt: Any,
                      out: tuple[np.ndarray, np.ndarray] | None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`step` with every argument checked in Python (converted, or refused with a one-line error)."""
        ps, qs, threaded = (self.n, 3), (self.n, 4), self.threads > 1
        args = self._kernel_args
        p, q = positions, quaternions
        if not (type(p) is _NDARRAY and p.dtype is _FLOAT64 and p.shape == ps):
            p = _float_rows(positions, "positions", ps, "m")
        if not (type(q) is _NDARRAY and q.dtype is _FLOAT64 and q.shape == qs):
            q = _float_rows(quaternions, "quaternions", qs, "-")
        if type(dt) is not float:
            dt = real_number(dt, "dt")
        if out is not None:
            pair: tuple[Any, Any] = out if type(out) is tuple and len(out) == 2 else (None, None)
            if not (_writable_rows(pair[0], self.n) and _writable_rows(pair[1], self.n)):
                raise InputError(f"out must be a tuple of two writable float64 arrays of shape ({self.n}, 3)")
            # the torques would overwrite the forces (exactly: the column halves of one (n, 6) block do not overlap,
            # though their bounds do)
            if np.shares_memory(pair[0], pair[1]):
                raise InputError("out's two arrays share memory; expected two separate arrays, forces and torques")
        # the compiled step's one version takes C-contiguous, aligned, writable arrays: others are copied (numba
        # would compile another version of the step for them, for seconds); so are the results into such an out
        p, q = _plain(p), _plain(q)
        if out is not None and _plain(out[0]) is out[0] and _plain(out[1]) is out[1]:
            forces, torques = out
        else:
            forces, torques = _empty(ps), _empty(ps)
        if threaded and not vectorized._forked:
            with vectorized._launch_lock:
                code = S3.step_feet_threads(p, q, dt, *args, forces, torques, _NO_EACH, self._chunks)
        else:
            code = _step_feet(p, q, dt, *args, forces, torques, _NO_EACH)
            if self._hot[2] is None:  # compiled now: the hot path can take the same code
                self._hot = (ps, args, _fixed_step())
        if code != _OK:
            self._refuse(code, p, q, dt)
        if out is not None and forces is not out[0]:
            out[0][...] = forces
            out[1][...] = torques
            forces, torques = out
        if self._follow_rows:  # kernel_rows' views follow the feet
            self._export_rows()
        return forces, torques

    def _refuse(self, code: int, p: np.ndarray, q: np.ndarray, dt: float) -> None:
        """The one-line InputError for a step :func:`mudforce._kernel.step3d.step_feet` refused (nothing moved)."""
        if code == S3.BAD_DT:
            raise InputError(f"dt must be within [{MIN_DT:g}, {MAX_DT:g}] s once a foot has started, got {dt!r}; "
                             "no foot was stepped")
        if not 0 <= code < self.n:  # pragma: no cover - the 1-D stepper refuses nothing step_feet lets through
            raise InputError("the step was refused; no foot was stepped")
        try:
            _pose(p[code], q[code])
        except InputError as error:
            raise InputError(f"foot {code}: {error}; no foot was stepped") from None
        raise InputError(f"foot {code}: an element would be beyond +-{MAX_DEPTH:g} m of the surface "
                         f"(position {p[code].tolist()!r} [m]); no foot was stepped")

    def reset(self, feet: Any = None) -> None:
        """Forget the history of some feet (all by default): their next step is a first step.

        Parameters
        ----------
        feet : int, sequence of int, or boolean mask of shape (n,), optional
            Which feet to reset.
        """
        fresh = K.new_states(1)[0]
        chosen = _chosen_feet(feet, self.n)  # (a nested [[0]] refused there, as for MudContacts)
        self._export_rows()  # the other feet's rows as they are
        for f in chosen.tolist():
            lo, hi = int(self._starts[f]), int(self._starts[f + 1])
            self._states[lo:hi] = fresh
            self._el[lo:hi, S3.E_SLIPX:S3.E_SLIPY + 1] = 0.0
            self._ft[f, S3.F_STARTED] = 0.0
        self._import_rows()

    def __len__(self) -> int:
        return self.n

    def __repr__(self) -> str:
        return f"MudContacts3D(n={self.n}, elements={self.n_elements}, threads={self.threads})"
