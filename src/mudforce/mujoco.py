"""MuJoCo adapter: mud patches under named feet of any MuJoCo model (``pip install 'mudforce[mujoco]'``).

Usage::

    import mujoco
    from mudforce.mujoco import MudPatch, MudAdapter, add_mud

    spec = mujoco.MjSpec.from_file("robot.xml")
    add_mud(spec, ["left_foot", "right_foot"])        # before compiling
    model = spec.compile()
    data = mujoco.MjData(model)
    mud = MudAdapter(model, data, ["left_foot", "right_foot"],
                     MudPatch(MudParameters.from_water_content(0.25)))
    for _ in range(1000):
        data.ctrl[:] = controller(data)
        mud.step()                                   # instead of mujoco.mj_step

How the force is applied, and why
---------------------------------
The mud force is set-valued at rest (:mod:`mudforce.dynamics`): a foot at
rest carries any load between the withdrawal-branch force ``F_up`` and the
intrusion-branch force ``F_down``. That is dry friction centred on the
mid-band force, so the adapter lets MuJoCo's own constraint solver handle it,
with the whole robot's dynamics, contacts and actuators in the same solve:

* :func:`add_mud` adds, per foot, a site at the foot's bottom (the contact
  point), an anchor site on the world body and a spatial tendon from the
  anchor down to that site. Before every step the adapter moves the anchor
  (its ``model.site_pos``) 1 m straight above the foot, so the tendon's
  direction is the world vertical at the contact point and its velocity is
  the foot's vertical velocity.
* Each step the adapter sets the tendon's ``frictionloss`` to the band's
  half-width ``(F_down - F_up) / 2`` and applies the mid-band force
  ``(F_up + F_down) / 2`` plus the drag (Eq. (5)) upward at the contact
  point through ``xfrc_applied`` (force and the matching torque about the
  body's centre of mass; added for the step and taken back after it). Moving down, the friction saturates and the total
  is ``F_down``; moving up, ``F_up``; at rest the solver finds the force that
  holds the foot (implicitly, with the foot's effective mass in the whole
  multibody), so there is no chatter and no ratcheting.
* After the step the adapter commits the foot's new depth to its contact
  state (:class:`mudforce.vectorized.MudContacts`' compiled stepper). The
  branch comes from the step's velocity with a deadband of
  :data:`STICK_VELOCITY`: MuJoCo's friction constraint is soft, so a stuck
  foot creeps by a few micrometres per second, and the deadband makes that
  count as rest, where the Maxwell element relaxes with the intrusion
  parameters (MODEL.md). The band half-width keeps the solver's friction
  stiff (``solref_friction``, ``solimp_friction`` set by :func:`add_mud`).

Why not ``mj_applyFT``/``xfrc_applied`` alone: an explicit force cannot
stop a foot; it overshoots zero velocity every step and chatters between the
branches (:func:`mudforce.dynamics.naive_drop`). Why not a joint's
``frictionloss``: a foot's vertical motion is rarely a single joint; the
tendon makes the same constraint available for any body in any model.

The errors: the band is taken from the mud state at the step's start
(first order in the time step), and the friction constraint's softness
lets a stuck foot creep (``impedance 0.9999``, time constant two steps).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import typeof, types
from numba.extending import intrinsic
from numba.np.numpy_support import carray  # numba.carray

from mudforce import _kernel as K
from mudforce._optional import require
from mudforce.dynamics import branch_forces
from mudforce.errors import InputError
from mudforce.foot import Foot
from mudforce.parameters import MudParameters
from mudforce.simulation import params_row
from mudforce.velocity import VelocityFilter

__all__ = ["ANCHOR_HEIGHT", "STICK_VELOCITY", "MudAdapter", "MudPatch", "add_mud", "drop_spec", "simulate_drop"]

#: Height of the tendon anchor above the foot [m].
ANCHOR_HEIGHT = 1.0
#: Foot speed below which a step counts as rest for the branch choice [m/s] (deadband of the kernel).
STICK_VELOCITY = 1e-4
_SOLREF_FRICTION = (1e-9, 1.0)  # a tiny time constant: MuJoCo raises it to its minimum, 2 time steps
_SOLIMP_FRICTION = (0.9999, 0.9999, 0.001, 0.5, 2.0)


def _mujoco() -> Any:
    return require("mujoco", "mujoco", "the MuJoCo adapter")


@dataclass(frozen=True)
class MudPatch:
    """A horizontal patch of mud.

    Parameters
    ----------
    params : MudParameters
        Mud parameters.
    height : float
        World height ``z`` of the undisturbed mud surface [m].
    extent : (xmin, xmax, ymin, ymax), optional
        Horizontal extent [m]; unbounded if omitted. A foot outside every
        patch feels no mud and its contact state is reset.
    """

    params: MudParameters
    height: float = 0.0
    extent: tuple[float, float, float, float] | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.params, MudParameters):
            raise InputError(f"a MudPatch needs MudParameters, got {type(self.params).__name__}")
        if not math.isfinite(self.height):
            raise InputError(f"patch height must be finite [m], got {self.height!r}")
        if self.extent is not None:
            x0, x1, y0, y1 = (float(v) for v in self.extent)
            if not (x0 < x1 and y0 < y1):
                raise InputError(f"patch extent must be (xmin, xmax, ymin, ymax) with min < max [m], got {self.extent}")


def _names(prefix: str, foot: str) -> tuple[str, str, str]:
    """Names of a foot's contact site, anchor site and tendon."""
    return f"{prefix}site_{foot}", f"{prefix}anchor_site_{foot}", f"{prefix}tendon_{foot}"


def _bottom_offset(geom: Any) -> list[float]:
    """The bottom of a geom in its body's frame, assuming the geom's local z is up [m]."""
    mj = _mujoco()
    size = np.asarray(geom.size, dtype=float)
    kind = geom.type
    if kind == mj.mjtGeom.mjGEOM_BOX or kind == mj.mjtGeom.mjGEOM_ELLIPSOID:
        depth = size[2]
    elif kind == mj.mjtGeom.mjGEOM_SPHERE:
        depth = size[0]
    elif kind == mj.mjtGeom.mjGEOM_CAPSULE:
        depth = size[1] + size[0]
    elif kind == mj.mjtGeom.mjGEOM_CYLINDER:
        depth = size[1]
    else:
        depth = 0.0
    pos = np.asarray(geom.pos, dtype=float)
    quat = np.asarray(geom.quat, dtype=float)
    down = np.zeros(3)
    mj.mju_rotVecQuat(down, np.array([0.0, 0.0, -depth]), quat / np.linalg.norm(quat))
    return [float(v) for v in pos + down]


def add_mud(spec: Any, feet: Sequence[str], *, points: Sequence[Sequence[float]] | None = None,
            prefix: str = "mud_") -> None:
    """Prepare a model for mud contact under the named feet (edit an ``mujoco.MjSpec`` before compiling).

    Parameters
    ----------
    spec : mujoco.MjSpec
        The model being built.
    feet : sequence of str
        Names of foot geoms or bodies. For a geom the contact point is the
        bottom of the geom (box, sphere, capsule, cylinder, ellipsoid, local
        z up); for a body it is the body's origin unless ``points`` says otherwise.
    points : sequence of (x, y, z), optional
        Contact points in each foot body's frame [m], overriding the above.
    prefix : str
        Prefix of the names of the added sites and tendons.
    """
    _mujoco()
    if isinstance(feet, str):
        feet = [feet]
    if points is not None and len(points) != len(feet):
        raise InputError(f"got {len(points)} contact points for {len(feet)} feet")
    for i, name in enumerate(feet):
        geom = spec.geom(name)
        body = spec.body(name)
        if geom is not None:
            body = geom.parent
            point = _bottom_offset(geom)
        elif body is not None:
            point = [0.0, 0.0, 0.0]
        else:
            raise InputError(f"the model has no geom or body named {name!r}")
        if points is not None:
            point = [float(v) for v in points[i]]
        site_name, anchor_site, tendon_name = _names(prefix, name)
        body.add_site(name=site_name, pos=point, size=[0.002, 0.0, 0.0])
        # the anchor is a site of the world body that the adapter moves through model.site_pos:
        # its world position is then exactly site_pos, as a mocap body's would be, without the
        # cost of an extra body in every step (~5% of a small robot's step)
        spec.worldbody.add_site(name=anchor_site, pos=[0.0, 0.0, ANCHOR_HEIGHT], size=[0.002, 0.0, 0.0])
        tendon = spec.add_tendon(name=tendon_name)
        tendon.wrap_site(anchor_site)
        tendon.wrap_site(site_name)
        tendon.frictionloss = 0.0
        tendon.solref_friction = list(_SOLREF_FRICTION)
        tendon.solimp_friction = list(_SOLIMP_FRICTION)


# The compiled functions here use the stepper's options (K._compiled) except that the per-step
# ones keep the GIL (releasing and taking it back would cost more than it frees), and those that
# build ``carray`` views need numba's reference counting (``_nrt=True``); the workers, which
# allocate nothing, run without it (counting the array views they take costs ~25% of their time).


# rows of the adapter's integer array (ints) and work array
_I_SITE, _I_BODY, _I_TENDON, _I_ANCHOR = 0, 1, 2, 3
_W_UP, _W_DOWN, _W_DRAG, _W_MID, _W_TX, _W_TY, _W_LAST = 0, 1, 2, 3, 4, 5, 6
# conf: dt [s], band weight [-], commit flag, then per foot: surface [m], xmin, xmax, ymin, ymax [m]
_C_DT, _C_WEIGHT, _C_COMMIT, _C_FOOT = 0, 1, 2, 3


@K._compiled(nogil=False)
def _commit_and_prepare(states: np.ndarray, params: np.ndarray, out: np.ndarray, ints: np.ndarray,
                        conf: np.ndarray, work: np.ndarray, site_xpos: np.ndarray, xipos: np.ndarray,
                        xfrc: np.ndarray, site_pos: np.ndarray, frictionloss: np.ndarray) -> None:
    """After a MuJoCo step: commit each foot's depth; before the next: band, forces, anchors.

    Forces [N], torques [N m], positions [m], ``conf[_C_DT]`` [s]. Called
    through :func:`_after_step` (one argument from Python, see there).
    """
    n = ints.shape[1]
    dt = conf[_C_DT]
    commit = conf[_C_COMMIT] != 0.0
    ring = states[:, :0]  # the adapter's velocity filter has window 1: no history to keep
    for j in range(n):
        # take back the force applied for the step just taken (see _apply_mud)
        body = ints[_I_BODY, j]
        xfrc[body, 2] -= work[_W_MID, j]
        xfrc[body, 3] -= work[_W_TX, j]
        xfrc[body, 4] -= work[_W_TY, j]
        work[_W_LAST, j] = work[_W_MID, j]
        site = ints[_I_SITE, j]
        g = conf[_C_FOOT + 5 * j: _C_FOOT + 5 * j + 5]
        x = site_xpos[site, 0]
        y = site_xpos[site, 1]
        inside = g[1] <= x <= g[2] and g[3] <= y <= g[4]
        depth = g[0] - site_xpos[site, 2]
        if not inside:
            states[j, :] = 0.0
            states[j, K.S_CACHE_DT] = -1.0
        elif commit or states[j, K.S_STARTED] == 0.0:
            K.step(states, ring, j, params, depth, dt, out, j)
    branch_forces(states, params, dt, conf[_C_WEIGHT], work[_W_UP], work[_W_DOWN], work[_W_DRAG])
    for j in range(n):
        lo = work[_W_UP, j]
        hi = work[_W_DOWN, j]
        if hi >= lo:
            mid = 0.5 * (lo + hi) + work[_W_DRAG, j]
            half = 0.5 * (hi - lo)
        else:
            # an inverted band (large compressive strain, k_m_w > k_m_i): no sticking
            # is possible in between; use the branch of the current motion
            mid = (hi if states[j, K.S_VELOCITY] >= 0.0 else lo) + work[_W_DRAG, j]
            half = 0.0
        frictionloss[ints[_I_TENDON, j]] = half
        body = ints[_I_BODY, j]
        site = ints[_I_SITE, j]
        # the force for the next step, at the sole; torque about the centre of mass:
        # r x (0, 0, F) = (r_y F, -r_x F, 0)
        rx = site_xpos[site, 0] - xipos[body, 0]
        ry = site_xpos[site, 1] - xipos[body, 1]
        work[_W_MID, j] = mid
        work[_W_TX, j] = ry * mid
        work[_W_TY, j] = -rx * mid
        a = ints[_I_ANCHOR, j]
        site_pos[a, 0] = site_xpos[site, 0]
        site_pos[a, 1] = site_xpos[site, 1]
        site_pos[a, 2] = site_xpos[site, 2] + ANCHOR_HEIGHT


@K._compiled(nogil=False)
def _apply_mud(xfrc: np.ndarray, ints: np.ndarray, work: np.ndarray) -> None:
    """Add the mud force [N] and torque [N m] to ``xfrc_applied`` for one step (taken back after it)."""
    for j in range(ints.shape[1]):
        body = ints[_I_BODY, j]
        xfrc[body, 2] += work[_W_MID, j]
        xfrc[body, 3] += work[_W_TX, j]
        xfrc[body, 4] += work[_W_TY, j]


# The per-step calls take a single argument, an int64 table of the addresses and shapes of the
# arrays they work on, because from Python every argument costs: numba's dispatcher spends
# ~0.15 us per array resolving types, and even its compiled entry point ~0.05 us per array
# unboxing it; with one small argument a call costs ~0.1 us. Slot k of the table is
# (address, rows, columns) of array k (columns 1 for 1-D arrays). All are C-contiguous
# float64 except the int64 ``ints``. The adapter keeps every array alive and never replaces
# one, and MuJoCo's buffers do not move for the life of the model and data.
_T_STATES, _T_PARAMS, _T_OUT, _T_INTS, _T_CONF, _T_WORK = 0, 1, 2, 3, 4, 5
_T_SITE_XPOS, _T_XIPOS, _T_XFRC, _T_SITE_POS, _T_FRICTIONLOSS = 6, 7, 8, 9, 10
_N_TABLE = 11


def _voidptr_typing(typingctx: Any, address: Any) -> Any:
    """Typing and code of :data:`_voidptr`."""
    if not isinstance(address, types.Integer):
        return None

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.inttoptr(args[0], context.get_value_type(types.voidptr))

    return types.voidptr(address), codegen


#: In compiled code, the raw pointer at an integer address (numba has no public cast from an integer to a pointer).
_voidptr: Any = intrinsic(_voidptr_typing)


# views of the arrays in slot k of a table (no copies; carray builds an array on the memory as is)
@K._compiled(inline="always", nogil=False, _nrt=True)
def _f64_1d(table: np.ndarray, k: int) -> np.ndarray:
    return carray(_voidptr(table[3 * k]), table[3 * k + 1], np.float64)


@K._compiled(inline="always", nogil=False, _nrt=True)
def _f64_2d(table: np.ndarray, k: int) -> np.ndarray:
    return carray(_voidptr(table[3 * k]), (table[3 * k + 1], table[3 * k + 2]), np.float64)


@K._compiled(inline="always", nogil=False, _nrt=True)
def _i64_2d(table: np.ndarray, k: int) -> np.ndarray:
    return carray(_voidptr(table[3 * k]), (table[3 * k + 1], table[3 * k + 2]), np.int64)


@K._compiled(nogil=False, _nrt=True)
def _before_step(table: np.ndarray) -> None:
    """:func:`_apply_mud` on the arrays in ``table`` (slots ``_T_*``)."""
    _apply_mud(_f64_2d(table, _T_XFRC), _i64_2d(table, _T_INTS), _f64_2d(table, _T_WORK))


@K._compiled(nogil=False, _nrt=True)
def _after_step(table: np.ndarray) -> None:
    """:func:`_commit_and_prepare` on the arrays in ``table`` (slots ``_T_*``)."""
    _commit_and_prepare(_f64_2d(table, _T_STATES), _f64_2d(table, _T_PARAMS), _f64_2d(table, _T_OUT),
                        _i64_2d(table, _T_INTS), _f64_1d(table, _T_CONF), _f64_2d(table, _T_WORK),
                        _f64_2d(table, _T_SITE_XPOS), _f64_2d(table, _T_XIPOS), _f64_2d(table, _T_XFRC),
                        _f64_2d(table, _T_SITE_POS), _f64_1d(table, _T_FRICTIONLOSS))


def _address_table(arrays: Sequence[np.ndarray]) -> np.ndarray:
    """The table of :func:`_before_step`/:func:`_after_step` for ``arrays`` in slot order."""
    table = np.zeros(3 * _N_TABLE, dtype=np.int64)
    for k, a in enumerate(arrays):
        # the compiled side trusts these (a wrong one would be read as garbage, or written over)
        expected = np.int64 if k == _T_INTS else np.float64
        if a.dtype != expected or not a.flags.c_contiguous or not a.flags.writeable or a.ndim not in (1, 2):
            raise RuntimeError(f"array {k} of the MuJoCo adapter is not a writeable C-contiguous "
                               f"{np.dtype(expected)} array of 1 or 2 dimensions")
        table[3 * k] = a.ctypes.data
        table[3 * k + 1] = a.shape[0]
        table[3 * k + 2] = a.shape[1] if a.ndim == 2 else 1
    return table


def _direct(fn: Any, table: np.ndarray) -> Any:
    """``fn``'s compiled code for a table, callable without numba's dispatcher (or ``fn`` itself).

    ``Dispatcher.compile`` (which also loads from numba's cache) returns
    the compiled entry point; calling it skips the dispatcher's type
    resolution, ~0.2 us per call, most of the adapter's overhead per step.
    """
    entry = fn.compile((typeof(table),))
    return entry if callable(entry) else fn


class MudAdapter:
    """Mud under named feet of a MuJoCo model prepared with :func:`add_mud`; one contact state per foot.

    Parameters
    ----------
    model : mujoco.MjModel
        Compiled from a spec that :func:`add_mud` prepared for these feet.
    data : mujoco.MjData
        Its data. During :meth:`step` the adapter adds the mud force to
        ``xfrc_applied`` of the foot bodies and takes it back afterwards, so
        between steps ``xfrc_applied`` holds only the user's forces (set or
        clear them freely). It owns ``model.site_pos`` of its anchor sites
        and ``model.tendon_frictionloss`` of its tendons.
    feet : sequence of str
        The names given to :func:`add_mud`.
    patches : MudPatch or sequence of MudPatch
        One patch for all feet or one per foot.
    foot : Foot or sequence of Foot, optional
        Contact area and width per foot [m^2, m]; the paper's cuboid by default.
    prefix : str
        As given to :func:`add_mud`.

    Notes
    -----
    Call :meth:`step` instead of ``mujoco.mj_step``. The force on foot ``j``
    applied during the next step is ``forces[j]`` plus the tendon friction
    the solver finds; :attr:`contact_forces` is the total in the last step.
    """

    def __init__(self, model: Any, data: Any, feet: Sequence[str], patches: MudPatch | Sequence[MudPatch],
                 foot: Foot | Sequence[Foot] | None = None, *, prefix: str = "mud_") -> None:
        mj = _mujoco()
        self._mj = mj
        self.model = model
        self.data = data
        if isinstance(feet, str):
            feet = [feet]
        self.feet = list(feet)
        n = len(self.feet)
        plist = [patches] * n if isinstance(patches, MudPatch) else list(patches)
        if len(plist) != n:
            raise InputError(f"got {len(plist)} patches for {n} feet")
        flist = [foot or Foot.paper()] * n if foot is None or isinstance(foot, Foot) else list(foot)
        self.patches = plist
        vf = VelocityFilter(1, STICK_VELOCITY)
        self._params = np.array([params_row(p.params, f, vf) for p, f in zip(plist, flist, strict=True)])
        big = 1e300
        conf = [0.0, 1.0, 0.0]
        for p in plist:
            conf += [p.height, *(p.extent if p.extent is not None else (-big, big, -big, big))]
        self._conf = np.array(conf, dtype=np.float64)
        self._conf[_C_DT] = float(model.opt.timestep)
        ints = []
        for name in self.feet:
            site_name, anchor_site, tendon_name = _names(prefix, name)
            sid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_SITE, site_name)
            tid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_TENDON, tendon_name)
            aid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_SITE, anchor_site)
            if sid < 0 or tid < 0 or aid < 0:
                raise InputError(f"foot {name!r} was not prepared: call add_mud(spec, [{name!r}, ...]) "
                                 "before compiling")
            ints.append((sid, int(model.site_bodyid[sid]), tid, aid))
        self._ints = np.ascontiguousarray(np.array(ints, dtype=np.int64).T)
        self._tendons = self._ints[_I_TENDON]
        self._states = K.new_states(n)
        self._out = np.zeros((K.N_OUT, n))
        self._work = np.zeros((7, n))
        # views into MuJoCo's buffers (fixed for the life of model and data); holding them keeps
        # model and data alive. The table has the raw addresses of these and the arrays above,
        # which are therefore never replaced, only written in place.
        self._arrays = (self._states, self._params, self._out, self._ints, self._conf, self._work,
                        data.site_xpos, data.xipos, data.xfrc_applied, model.site_pos, model.tendon_frictionloss)
        self._table = _address_table(self._arrays)
        self._after = _direct(_after_step, self._table)
        # what step() needs, in one attribute: each lookup there is a measurable part of its cost
        self._step_args = (_direct(_before_step, self._table), self._after, self._table, mj.mj_step, model, data)
        self.reset()

    @property
    def states(self) -> np.ndarray:
        """The feet's contact states, one row each (layout of :mod:`mudforce._kernel`; the live array)."""
        return self._states

    @property
    def params(self) -> np.ndarray:
        """The feet's mud and foot constants, one row each (layout of :mod:`mudforce._kernel`; the live array)."""
        return self._params

    def reset(self) -> None:
        """Forget all contact histories and prepare the next step from the current ``data`` (runs ``mj_forward``)."""
        self._work[:] = 0.0
        self._states[:] = K.new_states(len(self.feet))
        self._mj.mj_forward(self.model, self.data)
        self._conf[_C_COMMIT] = 0.0
        self._prepare()
        self._conf[_C_COMMIT] = 1.0

    @property
    def weight(self) -> float:
        """Weight of the predicted end-of-step band (:func:`mudforce.dynamics.branch_forces`); 1 by default."""
        return float(self._conf[_C_WEIGHT])

    @weight.setter
    def weight(self, value: float) -> None:
        self._conf[_C_WEIGHT] = float(value)

    def _prepare(self) -> None:
        self._after(self._table)

    def step(self, nstep: int = 1) -> None:
        """Advance the simulation ``nstep`` MuJoCo steps with the mud forces."""
        before, after, table, mj_step, model, data = self._step_args
        while nstep > 0:  # not range(): making one costs ~0.2 us, a few per cent of a small robot's step
            before(table)
            mj_step(model, data)
            after(table)
            nstep -= 1

    @property
    def forces(self) -> np.ndarray:
        """Mid-band force plus drag [N] that the coming step applies at each foot (a copy)."""
        return np.array(self._work[_W_MID], dtype=np.float64)

    @property
    def depths(self) -> np.ndarray:
        """Each foot's depth below its patch's surface at the last step [m] (positive down)."""
        return np.array(self._states[:, K.S_DEPTH], dtype=np.float64)

    @property
    def modes(self) -> list[str]:
        """Each foot's contact state (FREE, CONTACT, NECKED)."""
        return [K.STATE_NAMES[int(m)] for m in self._states[:, K.S_MODE]]

    @property
    def band(self) -> tuple[np.ndarray, np.ndarray]:
        """The band ``(F_up, F_down)`` [N] applied in the coming step (copies)."""
        return self._work[_W_UP].copy(), self._work[_W_DOWN].copy()

    @property
    def contact_forces(self) -> np.ndarray:
        """The vertical mud force on each foot in the last step [N], positive up.

        The mid-band force the adapter applied plus the tendon friction the
        solver found (``efc_force`` of the foot's friction row): while the
        foot sticks this is the load it carries; while it moves, the branch force.
        """
        mj = self._mj
        total: np.ndarray = np.array(self._work[_W_LAST], dtype=np.float64)
        d = self.data
        rows = np.flatnonzero(np.asarray(d.efc_type) == int(mj.mjtConstraint.mjCNSTR_FRICTION_TENDON))
        ids = np.asarray(d.efc_id)[rows]
        frc = np.asarray(d.efc_force)[rows]
        for j, tid in enumerate(self._tendons):
            hit = np.flatnonzero(ids == tid)
            if hit.size:
                # the tendon shortens as the foot rises: an upward push is a negative tendon force
                total[j] -= float(frc[hit[0]])
        return total


def drop_spec(mass: float, foot: Foot | None = None, *, height: float = 0.0, timestep: float = 1e-3,
              thickness: float = 0.025) -> Any:
    """A MuJoCo model (spec) of the drop: a cuboid foot on a vertical slide joint above mud at ``z = 0``.

    Parameters
    ----------
    mass : float
        Foot mass [kg].
    foot : Foot, optional
        The foot; its bottom face is ``sqrt(area) x sqrt(area)`` unless it is
        the paper's 51 x 38 mm cuboid (the default), which is kept as is.
    height : float
        Release height of the foot's bottom above the surface [m].
    timestep : float
        MuJoCo time step [s].
    thickness : float
        Foot height [m] (the paper's 25 mm); irrelevant to the vertical dynamics.
    """
    mj = _mujoco()
    foot = Foot.paper() if foot is None else foot
    if foot == Foot.paper():
        lx, ly = 0.051, 0.038
    else:
        lx = ly = math.sqrt(foot.area)
    spec = mj.MjSpec()
    spec.modelname = "mudforce_drop"
    spec.option.timestep = timestep
    spec.option.gravity = [0.0, 0.0, -9.81]
    body = spec.worldbody.add_body(name="foot", pos=[0.0, 0.0, height + 0.5 * thickness])
    body.add_joint(name="drop", type=mj.mjtJoint.mjJNT_SLIDE, axis=[0.0, 0.0, 1.0])
    body.add_geom(name="sole", type=mj.mjtGeom.mjGEOM_BOX, size=[0.5 * lx, 0.5 * ly, 0.5 * thickness],
                  mass=mass, contype=0, conaffinity=0)
    add_mud(spec, ["sole"])
    return spec


def simulate_drop(mass: float, params: MudParameters, foot: Foot | None = None, *, duration: float = 8.0,
                  height: float = 0.0, timestep: float = 1e-3) -> Any:
    """Drop a cuboid foot into mud in MuJoCo with :class:`MudAdapter`; returns a :class:`mudforce.dynamics.FootResult`.

    The phase of each sample is FREE or NECKED from the contact state, else
    STUCK when the foot's speed is below :data:`STICK_VELOCITY`, else
    INTRUSION (moving down) or WITHDRAWAL (moving up). The force is the total
    the solver applied: mid-band force plus the tendon's friction [N].
    """
    from mudforce.dynamics import FREE as PH_FREE
    from mudforce.dynamics import INTRUSION, NECKED, STUCK, WITHDRAWAL, FootResult

    mj = _mujoco()
    foot = Foot.paper() if foot is None else foot
    model = drop_spec(mass, foot, height=height, timestep=timestep).compile()
    data = mj.MjData(model)
    adapter = MudAdapter(model, data, ["sole"], MudPatch(params), foot)
    n = math.floor(duration / timestep + 1e-9) + 1
    time = np.arange(n) * timestep
    depth = np.empty(n)
    velocity = np.empty(n)
    force = np.zeros(n)
    phase = np.empty(n, dtype=np.int8)
    depth[0] = -height
    velocity[0] = 0.0
    phase[0] = PH_FREE
    for k in range(1, n):
        adapter.step()
        depth[k] = adapter.states[0, K.S_DEPTH]
        velocity[k] = -float(data.qvel[0])
        force[k] = adapter.contact_forces[0]
        mode = int(adapter.states[0, K.S_MODE])
        if mode == K.FREE:
            phase[k] = PH_FREE
        elif mode == K.NECKED:
            phase[k] = NECKED
        elif abs(velocity[k]) <= STICK_VELOCITY:
            phase[k] = STUCK
        else:
            phase[k] = INTRUSION if velocity[k] > 0.0 else WITHDRAWAL
    return FootResult(time, depth, velocity, force, phase, float(mass), 9.81, "mujoco", 0, np.full(n, np.nan))
