"""MuJoCo adapter: mud patches under named feet of any MuJoCo model (``pip install 'mudforce[mujoco]'``).

Usage::

    import mujoco
    from mudforce.engines.mujoco import MudPatch, MudAdapter, add_mud

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
The mud force is set-valued at rest (:mod:`mudforce.engines.dynamics`): a foot at
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
  state (:class:`mudforce.steppers.many.MudContacts`' compiled stepper). The
  branch comes from the step's velocity with a deadband of
  :data:`STICK_VELOCITY`: MuJoCo's friction constraint is soft, so a stuck
  foot creeps by a few micrometres per second, and the deadband makes that
  count as rest, where the Maxwell element relaxes with the intrusion
  parameters (docs/model.md). The band half-width keeps the solver's friction
  stiff (``solref_friction``, ``solimp_friction`` set by :func:`add_mud`).

Why not ``mj_applyFT``/``xfrc_applied`` alone: an explicit force cannot
stop a foot; it overshoots zero velocity every step and chatters between the
branches (:func:`mudforce.engines.dynamics.naive_drop`). Why not a joint's
``frictionloss``: a foot's vertical motion is rarely a single joint; the
tendon makes the same constraint available for any body in any model.

The errors: the band is the one predicted for the step's end (each bound a
trial step on its own branch, :attr:`MudAdapter.weight`), first order in the
time step, and the friction constraint's softness
lets a stuck foot creep (``impedance 0.9999``, time constant two steps).
With ``integrator="implicitfast"`` MuJoCo's constraint solve does not see the
damping the integrator makes implicit, so where a joint's damping over a step
is a good part of its inertia (stiff servos on light legs, no armature) a
servo's jump can make the friction row push the foot the way it moves: for a
step or two the force lies inside the band while the foot moves
(docs/dynamics.md, "MuJoCo"). Give the joints their actuators' armature.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mudforce import _kernel as K
from mudforce._kernel import params_row
from mudforce._plumbing.deprecation import renamed_keywords, warn_renamed
from mudforce.engines._checks import (
    MAX_NSTEP,
    check_finite_output,
    check_foot,
    check_mass,
    check_params,
    drop_numbers,
    drop_thickness,
    name_list,
    step_count,
)
from mudforce.engines.dynamics.result import GRAVITY, REST_SPEED, FootResult, Phase
from mudforce.engines.mujoco import _fast as fast
from mudforce.engines.mujoco._spec import check_model_data
from mudforce.engines.mujoco._spec import check_prefix as _check_prefix
from mudforce.engines.mujoco._spec import compiled_copy as _compiled_copy
from mudforce.engines.mujoco._spec import geom_frame as _geom_frame
from mudforce.engines.mujoco._spec import mujoco_module as _mujoco
from mudforce.engines.mujoco._spec import read_only as _read_only
from mudforce.engines.mujoco._step import ANCHOR_HEIGHT, C_COMMIT, C_DT, C_WEIGHT, I_TENDON, W_DOWN, W_LAST, W_MID, W_UP
from mudforce.engines.mujoco.adapter3d import MudAdapter3D, add_mud_3d, simulate_drop_3d
from mudforce.errors import InputError, finite_number, number_within, real_array, shown
from mudforce.model.bounds import MAX_DEPTH, bounded_depth, max_samples
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.velocity import VelocityFilter

__all__ = [
    "ANCHOR_HEIGHT", "STICK_VELOCITY", "MudAdapter", "MudAdapter3D", "MudPatch", "add_mud", "add_mud_3d", "drop_model",
    "foot_of", "simulate_drop", "simulate_drop_3d",
]

#: Foot speed at or below which a step counts as rest for the branch choice [m/s] (deadband of the kernel).
STICK_VELOCITY = REST_SPEED
_SOLREF_FRICTION = (1e-9, 1.0)  # a tiny time constant: MuJoCo raises it to its minimum, 2 time steps
_SOLIMP_FRICTION = (0.9999, 0.9999, 0.001, 0.5, 2.0)


@dataclass(frozen=True, init=False)
class MudPatch:
    """A horizontal patch of mud.

    Parameters
    ----------
    params : MudParameters
        Mud parameters.
    surface_height : float
        World height ``z`` of the undisturbed mud surface [m], within +-100 m
        (:data:`mudforce.steppers.simulation.MAX_DEPTH`) (the name
        :class:`mudforce.steppers.contact3d.MudContact3D` uses; ``height=``
        is its deprecated name, kept for one release: a drop's ``height``
        is the release height above the surface).
    extent : (xmin, xmax, ymin, ymax), optional
        Horizontal extent [m]; unbounded if omitted. A foot outside every
        patch feels no mud and its contact state is reset.
    """

    params: MudParameters
    surface_height: float
    extent: tuple[float, float, float, float] | None

    def __init__(self, params: MudParameters, surface_height: float | None = None,
                 extent: tuple[float, float, float, float] | None = None, *, height: float | None = None) -> None:
        if height is not None:
            if surface_height is not None:
                raise InputError("MudPatch: give surface_height= only (height= is its deprecated name)")
            warn_renamed("MudPatch(height=...)", "MudPatch(surface_height=...)")
            surface_height = height
        object.__setattr__(self, "params", params)
        object.__setattr__(self, "surface_height", 0.0 if surface_height is None else surface_height)
        object.__setattr__(self, "extent", extent)
        self.__post_init__()

    def __post_init__(self) -> None:
        if not isinstance(self.params, MudParameters):
            raise InputError(f"a MudPatch needs MudParameters, got {type(self.params).__name__}")
        # the steppers' bound on a depth, as MudAdapter3D's contacts refuse it (1e300 was a force of 2e164 N here)
        object.__setattr__(self, "surface_height", bounded_depth(self.surface_height, "patch surface_height"))
        if self.extent is not None:
            extent = self.extent
            # a sequence of four (a dict's keys or a set's members were the bounds; a generator was checked, then
            # kept exhausted), kept as a tuple of floats: later edits of a list do not reach the checked patch
            if not (isinstance(extent, (tuple, list)) or (isinstance(extent, np.ndarray) and extent.ndim == 1)) \
                    or len(extent) != 4:
                raise InputError(f"patch extent must be (xmin, xmax, ymin, ymax) [m], got {shown(extent)}")
            x0, x1, y0, y1 = (finite_number(v, "patch extent", "m") for v in extent)
            if not (x0 < x1 and y0 < y1):
                raise InputError(f"patch extent must be (xmin, xmax, ymin, ymax) with min < max [m], got "
                                 f"{shown((x0, x1, y0, y1))}")
            object.__setattr__(self, "extent", (x0, x1, y0, y1))

    @property
    def height(self) -> float:
        """Deprecated: :attr:`surface_height` [m]."""
        warn_renamed("MudPatch.height", "MudPatch.surface_height")
        return self.surface_height


def _names(prefix: str, foot: str) -> tuple[str, str, str]:
    """Names of a foot's contact site, anchor site and tendon."""
    return f"{prefix}site_{foot}", f"{prefix}anchor_site_{foot}", f"{prefix}tendon_{foot}"


def _bottom_offset(geom: Any, compiled: Callable[[], Any] | None = None) -> list[float]:
    """The lowest point of a geom with its body upright, in the body's frame [m]: its support point along the body's
    -z (a box's lowest corner or edge's middle, a capsule's lower cap, a cylinder's rim; for a geom whose local z is
    up, the middle of its bottom, as before). A geom turned by its quaternion, ``euler``, ``axisangle`` or a
    ``<frame>`` (:func:`~mudforce.engines.mujoco._spec.geom_frame`): a box turned 90 degrees about y had its bottom
    taken 15 mm too high (along its local z, now sideways), or, read from the spec, along the body's z unturned."""
    mj = _mujoco()
    pos, quat, size = _geom_frame(geom, compiled)
    kind = geom.type
    flat = np.zeros(9)
    mj.mju_quat2Mat(flat, quat / np.linalg.norm(quat))
    rot = flat.reshape(3, 3)
    down = -rot[2]  # the body's -z in the geom's frame
    down[np.abs(down) < 1e-9] = 0.0  # a flat bottom's rounding (1e-17) must not pick a corner over its middle
    if kind == mj.mjtGeom.mjGEOM_BOX:
        local = np.sign(down) * size[:3]
    elif kind == mj.mjtGeom.mjGEOM_ELLIPSOID:
        scaled = size[:3] * down
        local = size[:3] * scaled / np.linalg.norm(scaled)
    elif kind == mj.mjtGeom.mjGEOM_SPHERE:
        local = size[0] * down
    elif kind == mj.mjtGeom.mjGEOM_CAPSULE:
        local = np.array([0.0, 0.0, np.sign(down[2]) * size[1]]) + size[0] * down
    elif kind == mj.mjtGeom.mjGEOM_CYLINDER:
        across = math.hypot(down[0], down[1])
        rim = size[0] * np.array([down[0], down[1], 0.0]) / across if across > 0.0 else np.zeros(3)
        local = rim + np.array([0.0, 0.0, np.sign(down[2]) * size[1]])
    else:
        local = np.zeros(3)
    return [float(v) for v in pos + rot @ local]


def add_mud(spec: Any, feet: Sequence[str], *, points: Sequence[Sequence[float]] | None = None,
            prefix: str = "mud_") -> None:
    """Prepare a model for mud contact under the named feet (edit an ``mujoco.MjSpec`` before compiling).

    Parameters
    ----------
    spec : mujoco.MjSpec
        The model being built.
    feet : sequence of str
        Names of foot geoms or bodies. For a geom the contact point is the
        lowest point of the geom with its body upright (box, sphere, capsule, cylinder, ellipsoid, turned
        as the model turns it); for a body it is the body's origin unless ``points`` says otherwise.
    points : sequence of (x, y, z), optional
        Contact points in each foot body's frame [m], overriding the above; each coordinate within +-100 m.
    prefix : str
        Prefix of the names of the added sites and tendons.
    """
    mj = _mujoco()
    if not isinstance(spec, mj.MjSpec):
        raise InputError(f"spec must be a mujoco.MjSpec (edited before compiling), got {type(spec).__name__}")
    feet = name_list(feet)
    prefix = _check_prefix(prefix)
    chosen: list[list[float]] | None = None
    if points is not None:
        try:  # each point an array of numbers: a set's members (in set order) or a dict's keys were taken
            rows = [real_array(point, "contact point", "m") for point in points]
        except TypeError:
            raise InputError("points must be a sequence of (x, y, z) contact points [m]") from None
        if any(row.ndim != 1 for row in rows):
            raise InputError("points must be a sequence of (x, y, z) contact points [m]")
        # within the steppers' depth bound of the body's origin (a point 1e308 m away was taken)
        chosen = [[number_within(v, "contact point", -MAX_DEPTH, MAX_DEPTH, "m") for v in row.tolist()]
                  for row in rows]
        if len(chosen) != len(feet) or any(len(point) != 3 for point in chosen):
            raise InputError(f"points must be one (x, y, z) [m] per foot: got {len(chosen)} for {len(feet)} feet")
    # every foot is checked before the spec is changed: a refused call leaves it as it was
    found = []
    compiled = _compiled_copy(spec)  # compiled once, if a turned foot asks for it
    for i, name in enumerate(feet):
        geom = spec.geom(name)
        body = spec.body(name)
        if geom is not None:
            body = geom.parent
            point = _bottom_offset(geom, compiled)
        elif body is not None:
            point = [0.0, 0.0, 0.0]
        else:
            raise InputError(f"the model has no geom or body named {name!r}")
        taken = [n for n in _names(prefix, name) if spec.site(n) is not None or spec.tendon(n) is not None]
        if taken:  # was MuJoCo's ValueError "repeated name", with the feet before it already changed
            raise InputError(f"the model already has {taken[0]!r}: add_mud was called twice for a foot (or use "
                             "another prefix=)")
        found.append((name, body, point if chosen is None else chosen[i]))
    for name, body, point in found:
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


def foot_of(model: Any, name: str) -> Foot:
    """The flat foot (:class:`~mudforce.model.foot.Foot`) of a foot geom: its footprint on a horizontal surface.

    The 1-D model loads a flat sole; a geom gets the sole of its outline seen
    from below in its own frame (the contact follows the world's down
    direction, so a geom is assumed upright there):

    * sphere: a disc of its diameter;
    * capsule, cylinder: a disc of its diameter if its axis is vertical in
      its body, else a rectangle (its length, the capsule's caps included,
      by its diameter);
    * box: a rectangle of its two horizontal sides (the shorter is ``H``);
    * ellipsoid: an ellipse of its two horizontal semi-axes (``H`` the shorter diameter);
    * mesh: the rectangle of its vertices' x and y extents.

    Parameters
    ----------
    model : mujoco.MjModel
        The compiled model.
    name : str
        A geom's name, or a body's with exactly one geom.

    Raises
    ------
    InputError
        For a name that is neither, a body with no geom or several, or a geom
        of another type (plane, height field): give ``foot=`` then.
    """
    mj = _mujoco()
    gid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_GEOM, name)
    if gid < 0:
        bid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, name)
        if bid < 0:
            raise InputError(f"the model has no geom or body named {name!r}")
        geoms = [int(g) for g in np.flatnonzero(model.geom_bodyid == bid)]
        if len(geoms) != 1:
            raise InputError(f"foot {name!r} is a body with {len(geoms)} geoms: name its foot geom, or give "
                             "foot= (a mudforce.Foot per foot) for its sole")
        gid = geoms[0]
    kind = int(model.geom_type[gid])
    size = [float(v) for v in model.geom_size[gid]]
    quat = np.asarray(model.geom_quat[gid], dtype=float)
    axis = np.zeros(3)
    mj.mju_rotVecQuat(axis, np.array([0.0, 0.0, 1.0]), quat / np.linalg.norm(quat))
    types = mj.mjtGeom
    if kind == types.mjGEOM_SPHERE:
        return Foot.disc(2.0 * size[0])
    if kind in (types.mjGEOM_CAPSULE, types.mjGEOM_CYLINDER):
        if abs(axis[2]) >= math.sqrt(0.5):
            return Foot.disc(2.0 * size[0])
        caps = 2.0 * size[0] if kind == types.mjGEOM_CAPSULE else 0.0
        return Foot.cuboid(2.0 * size[1] + caps, 2.0 * size[0])
    if kind == types.mjGEOM_BOX:
        return Foot.cuboid(*sorted((2.0 * size[0], 2.0 * size[1]), reverse=True))
    if kind == types.mjGEOM_ELLIPSOID:
        a, b = size[0], size[1]
        return Foot(area=math.pi * a * b, width=2.0 * min(a, b), shape=f"ellipse {2e3 * a:g}x{2e3 * b:g} mm")
    if kind == types.mjGEOM_MESH:
        mesh, nmesh = int(model.geom_dataid[gid]), int(model.nmesh)
        if not 0 <= mesh < nmesh:  # a geom_dataid written by hand: -1 was the model's last mesh, 3 an IndexError
            expected = f"a mesh id 0 to {nmesh - 1}" if nmesh else "a mesh, and the model has none"
            raise InputError(f"foot {name!r} is a mesh geom of mesh id {mesh} (geom_dataid); expected {expected}")
        start, count = int(model.mesh_vertadr[mesh]), int(model.mesh_vertnum[mesh])
        extent = np.ptp(np.asarray(model.mesh_vert[start:start + count]), axis=0)
        return Foot.cuboid(*sorted((float(extent[0]), float(extent[1])), reverse=True))
    try:
        kind_name = mj.mjtGeom(kind).name
    except ValueError:  # a geom_type written by hand after compiling: was mjtGeom's ValueError (Invalid int value)
        raise InputError(f"foot {name!r} has geom_type {kind}, which is no MuJoCo geom type; expected sphere, capsule, "
                         "cylinder, box, ellipsoid or mesh (mujoco.mjtGeom), or give foot= (a mudforce.Foot per foot)"
                         ) from None
    raise InputError(f"foot {name!r} is a geom of type {kind_name}, which has no sole: give foot= "
                     "(a mudforce.Foot per foot)")


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
        Contact area and width per foot [m^2, m]; by default each foot's
        own, from its geom (:func:`foot_of`: a sphere's disc, a box's
        rectangle, ...); a foot with no geom to take it from is refused.
    prefix : str
        As given to :func:`add_mud`.

    Attributes
    ----------
    feet : tuple of str
        The feet's names, in the order of every per-foot array.
    patches : tuple of MudPatch
        Each foot's patch.
    state : ndarray
        A snapshot of the feet's contact states (kernel layout); assign one to restore.
    params : ndarray
        A read-only view of the feet's constants (kernel layout).

    Notes
    -----
    Call :meth:`step` instead of ``mujoco.mj_step``. The force on foot ``j``
    applied during the next step is ``forces[j]`` plus the tendon friction
    the solver finds; :attr:`contact_forces` is the total in the last step.
    """

    def __init__(self, model: Any, data: Any, feet: Sequence[str], patches: MudPatch | Sequence[MudPatch],
                 foot: Foot | Sequence[Foot] | None = None, *, prefix: str = "mud_") -> None:
        mj = _mujoco()
        check_model_data(mj, model, data)  # (another model's data was stepped without a word)
        self._mj = mj
        self.model = model
        self.data = data
        self.feet: tuple[str, ...] = tuple(name_list(feet))
        prefix = _check_prefix(prefix)
        n = len(self.feet)
        if isinstance(patches, MudPatch):
            plist = [patches] * n
        elif isinstance(patches, Sequence) and all(isinstance(p, MudPatch) for p in patches):
            plist = list(patches)
        else:
            raise InputError(f"patches must be a MudPatch or a sequence of MudPatch, got {type(patches).__name__}")
        if len(plist) != n:
            raise InputError(f"got {len(plist)} patches for {n} feet")
        if foot is None:  # each foot's own sole, from its geom; never silently the paper's cuboid
            flist = [foot_of(model, name) for name in self.feet]
        elif isinstance(foot, Foot):
            flist = [foot] * n
        elif isinstance(foot, Sequence) and all(isinstance(f, Foot) for f in foot):
            flist = list(foot)
        else:
            raise InputError(f"foot must be a Foot, a sequence of Foot or None, got {type(foot).__name__}")
        if len(flist) != n:
            raise InputError(f"got {len(flist)} feet's geometry (Foot) for {n} feet")
        self.patches: tuple[MudPatch, ...] = tuple(plist)
        vf = VelocityFilter(1, STICK_VELOCITY)
        self._params = np.array([params_row(p.params, f, vf) for p, f in zip(plist, flist, strict=True)])
        big = 1e300
        conf = [0.0, 1.0, 0.0]
        for p in plist:
            conf += [p.surface_height, *(p.extent if p.extent is not None else (-big, big, -big, big))]
        self._conf = np.array(conf, dtype=np.float64)
        self._conf[C_DT] = float(model.opt.timestep)
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
        self._tendon_ids = self._ints[I_TENDON].tolist()  # each foot's tendon, as Python ints (contact_forces)
        self._friction_tendon = int(mj.mjtConstraint.mjCNSTR_FRICTION_TENDON)
        self._states = K.new_states(n)
        self._out = K.new_out(n)  # the stepper's outputs: written by each step, read by nobody
        self._out[:] = 0.0
        self._work = np.zeros((7, n))
        # views into MuJoCo's buffers (fixed for the life of model and data); holding them keeps
        # model and data alive. The table has the raw addresses of these and the arrays above,
        # which are therefore never replaced, only written in place.
        self._arrays = (self._states, self._params, self._out, self._ints, self._conf, self._work,
                        data.site_xpos, data.xipos, data.xfrc_applied, model.site_pos, model.tendon_frictionloss)
        self._table = fast.address_table(self._arrays)
        self._after = fast.direct(fast.after_step, self._table)
        # what step() needs, in one attribute: each lookup there is a measurable part of its cost
        before = fast.direct(fast.before_step, self._table)
        self._step_args = (before, self._after, self._table, mj.mj_step, model, data)
        self.reset()

    @property
    def state(self) -> np.ndarray:
        """A snapshot of the feet's contact states (a read-only copy), one row each; assign one back to restore.

        Rows in the layout of :mod:`mudforce._kernel`, as :attr:`mudforce.MudContacts.state`
        (the adapter's filter keeps no history). Restoring validates the rows as
        strictly as fresh ones (a refused one changes nothing) and prepares the
        next step's band from the current ``data`` (runs ``mj_forward``), as
        :meth:`reset` does; save and restore MuJoCo's own state
        (``mujoco.mj_getState``/``mj_setState``) with it.
        """
        snapshot: np.ndarray = self._states.copy()
        snapshot.setflags(write=False)
        return snapshot

    @state.setter
    def state(self, value: np.ndarray) -> None:
        from mudforce.steppers.contact import check_states

        n = len(self.feet)
        # real numbers only (np.asarray parsed strings, read booleans as 0 and 1 and dropped imaginary parts)
        arr = real_array(value, f"a state of {n} feet (from MudAdapter.state)", "SI")
        if arr.shape != self._states.shape:
            raise InputError(f"a state of {n} feet has shape {self._states.shape}, got {arr.shape}")
        check_states(arr, np.empty((n, 0)), "a state")
        self._states[:] = arr
        K.forget_cache(self._states)
        # as reset: the last step's force was taken back after it, and the coming one is prepared from the state (the
        # preparation takes back the force in work: the coming step's, never applied, was taken from xfrc_applied)
        self._work[:] = 0.0
        self._mj.mj_forward(self.model, self.data)
        self._conf[C_COMMIT] = 0.0
        self._prepare()
        self._conf[C_COMMIT] = 1.0

    @property
    def states(self) -> np.ndarray:
        """Deprecated: a read-only view of the live state rows; use :attr:`state`."""
        warn_renamed("MudAdapter.states", "MudAdapter.state")
        return _read_only(self._states)

    @property
    def params(self) -> np.ndarray:
        """The feet's mud and foot constants, one row each (layout of :mod:`mudforce._kernel`; a read-only view).

        Set them through the patches given to the constructor (a new adapter).
        """
        return _read_only(self._params)

    def reset(self) -> None:
        """Forget all contact histories and prepare the next step from the current ``data`` (runs ``mj_forward``)."""
        self._work[:] = 0.0
        self._states[:] = K.new_states(len(self.feet))
        self._mj.mj_forward(self.model, self.data)
        self._conf[C_COMMIT] = 0.0
        self._prepare()
        self._conf[C_COMMIT] = 1.0

    @property
    def weight(self) -> float:
        """Weight of the predicted end-of-step band (:func:`mudforce.engines.dynamics.branch_forces`); 1 by default."""
        return float(self._conf[C_WEIGHT])

    @weight.setter
    def weight(self, value: float) -> None:
        w = finite_number(value, "weight", "-")
        if not 0.0 <= w <= 1.0:
            raise InputError(f"weight must be in [0, 1] [-], got {shown(value)}")
        self._conf[C_WEIGHT] = w

    def _prepare(self) -> None:
        self._after(self._table)

    def step(self, nstep: int = 1) -> None:
        """Advance the simulation ``nstep`` MuJoCo steps with the mud forces."""
        before, after, table, mj_step, model, data = self._step_args
        if nstep.__class__ is not int or not 1 <= nstep <= MAX_NSTEP:  # (~20 ns of a ~1 us step; 0, -1 refused)
            nstep = step_count(nstep)
        while nstep > 0:  # not range(): making one costs ~0.2 us, a few per cent of a small robot's step
            before(table)
            mj_step(model, data)
            after(table)
            nstep -= 1

    @property
    def forces(self) -> np.ndarray:
        """Mid-band force plus drag [N] that the coming step applies at each foot (a copy)."""
        return np.array(self._work[W_MID], dtype=np.float64)

    @property
    def depths(self) -> np.ndarray:
        """Each foot's depth below its patch's surface at the last step [m] (positive down)."""
        return np.array(K.state_column(self._states, "depth"), dtype=np.float64)

    @property
    def modes(self) -> list[str]:
        """Each foot's contact state (FREE, CONTACT, NECKED)."""
        return [K.STATE_NAMES[int(m)] for m in K.state_column(self._states, "mode")]

    @property
    def band(self) -> tuple[np.ndarray, np.ndarray]:
        """The band ``(F_up, F_down)`` [N] applied in the coming step (copies)."""
        return self._work[W_UP].copy(), self._work[W_DOWN].copy()

    @property
    def contact_forces(self) -> np.ndarray:
        """The vertical mud force on each foot in the last step [N], positive up.

        The mid-band force the adapter applied plus the tendon friction the
        solver found (``efc_force`` of the foot's friction row): while the
        foot sticks this is the load it carries; while it moves, the branch force.
        """
        total: np.ndarray = np.array(self._work[W_LAST], dtype=np.float64)
        d = self.data
        rows = np.flatnonzero(np.asarray(d.efc_type) == self._friction_tendon)
        # each tendon's first friction row (a dict of the few rows: one pass, not one search a foot)
        first: dict[int, float] = {}
        for tid, frc in zip(np.asarray(d.efc_id)[rows].tolist(), np.asarray(d.efc_force)[rows].tolist(),
                            strict=True):
            first.setdefault(tid, frc)
        for j, tid in enumerate(self._tendon_ids):
            if tid in first:
                # the tendon shortens as the foot rises: an upward push is a negative tendon force
                total[j] -= first[tid]
        return total


def _drop_spec(mass: float, foot: Foot | None, height: float, dt: float, thickness: float) -> Any:
    mj = _mujoco()
    mass, height, dt = drop_numbers(mass, height, dt)
    foot = check_foot(foot)
    thickness = drop_thickness(thickness)
    if foot == Foot.paper():
        lx, ly = 0.051, 0.038
    else:
        lx = ly = math.sqrt(foot.area)
    spec = mj.MjSpec()
    spec.modelname = "mudforce_drop"
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -GRAVITY]
    body = spec.worldbody.add_body(name="foot", pos=[0.0, 0.0, height + 0.5 * thickness])
    body.add_joint(name="drop", type=mj.mjtJoint.mjJNT_SLIDE, axis=[0.0, 0.0, 1.0])
    body.add_geom(name="sole", type=mj.mjtGeom.mjGEOM_BOX, size=[0.5 * lx, 0.5 * ly, 0.5 * thickness],
                  mass=mass, contype=0, conaffinity=0)
    add_mud(spec, ["sole"])
    return spec


@renamed_keywords(timestep="dt")
def drop_model(mass: float, foot: Foot | None = None, *, height: float = 0.0, dt: float = 1e-3,
               thickness: float = 0.025) -> Any:
    """A compiled ``mujoco.MjModel`` of the drop: a cuboid foot on a vertical slide joint above mud at ``z = 0``.

    The foot's geom ``sole`` is prepared with :func:`add_mud` (feet ``["sole"]``).
    The same model as :func:`mudforce.engines.mjx.drop_model`, with the same arguments.

    Parameters
    ----------
    mass : float
        Foot mass [kg], > 0 (:func:`simulate_drop` states the least its time step resolves).
    foot : Foot, optional
        The foot; its bottom face is ``sqrt(area) x sqrt(area)`` unless it is
        the paper's 51 x 38 mm cuboid (the default), which is kept as is.
    height : float
        Release height of the foot's bottom above the surface [m], in [0, 100].
    dt : float
        Time step [s], within [1e-9, 1000] (MuJoCo's ``opt.timestep``; ``timestep=`` is its deprecated name here).
    thickness : float
        Foot height [m], within [1e-6, 100] (the paper's 25 mm); irrelevant to the vertical dynamics.
    """
    return _drop_spec(mass, foot, height, dt, thickness).compile()


def drop_spec(mass: float, foot: Foot | None = None, *, height: float = 0.0, timestep: float = 1e-3,
              thickness: float = 0.025) -> Any:
    """Deprecated: the ``mujoco.MjSpec`` of :func:`drop_model` (which returns the compiled model)."""
    warn_renamed("mudforce.engines.mujoco.drop_spec",
                 "mudforce.engines.mujoco.drop_model (compiled; dt= for timestep=)")
    return _drop_spec(mass, foot, height, timestep, thickness)


@renamed_keywords(timestep="dt")
def simulate_drop(mass: float, params: MudParameters, foot: Foot | None = None, *, duration: float = 8.0,
                  height: float = 0.0, dt: float = 1e-3) -> FootResult:
    """Drop a cuboid foot into mud in MuJoCo with :class:`MudAdapter`; returns a
    :class:`mudforce.engines.dynamics.FootResult`.

    The phase of each sample is FREE or NECKED from the contact state, else
    STUCK when the foot's speed is at most :data:`STICK_VELOCITY`, else
    INTRUSION (moving down) or WITHDRAWAL (moving up). The force is the total
    the solver applied: mid-band force plus the tendon's friction [N].

    Parameters
    ----------
    mass : float
        Foot mass [kg]; at least ``S max(k_m_i, k_m_w) dt^2`` (about
        3e-3 kg for Table I's muds, the paper's foot and 1 ms steps), so that
        the step resolves the foot's oscillation on the mud. Lighter than
        about 1 kg the result is rough: MuJoCo's soft friction lets the foot
        creep some 10-20 um, a large part of a light foot's rest depth.
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry; the paper's 51 x 38 mm cuboid by default.
    duration : float
        Simulated time [s], at least ``dt`` (at most 1e8 steps).
    height : float
        Release height of the foot's bottom above the surface [m], in [0, 100].
    dt : float
        Time step [s], > 0 (MuJoCo's ``opt.timestep``; ``timestep=`` is its deprecated name here); also the
        output sampling interval.

    Raises
    ------
    InputError
        For any input of the wrong type or outside the bounds above, and if
        the solution is not finite anyway (the first such sample time is named).
    """
    mj = _mujoco()
    params = check_params(params)
    foot = check_foot(foot)
    duration = finite_number(duration, "duration", "s", positive=True)
    height = bounded_depth(height, "height", of=" of the mud surface")  # simulate_foot's bound: 1e12 m was taken
    height = finite_number(height, "height", "m", nonnegative=True)
    dt = finite_number(dt, "dt", "s", positive=True)
    mass = check_mass(mass, params, foot, dt, "MuJoCo time step")
    n = max_samples(duration, dt)
    model = _drop_spec(mass, foot, height, dt, 0.025).compile()
    data = mj.MjData(model)
    adapter = MudAdapter(model, data, ["sole"], MudPatch(params), foot)
    state = adapter._states[0]  # the live row (this function only reads it)
    live_depth = K.state_column(state, "depth")  # views of its fields, which follow the adapter
    live_mode = K.state_column(state, "mode")
    time = np.arange(n) * dt
    depth = np.empty(n)
    velocity = np.empty(n)
    force = np.zeros(n)
    phase = np.empty(n, dtype=np.int8)
    depth[0] = -height
    velocity[0] = 0.0
    phase[0] = Phase.FREE
    for k in range(1, n):
        adapter.step()
        depth[k] = live_depth
        velocity[k] = -float(data.qvel[0])
        force[k] = adapter.contact_forces[0]
        mode = int(live_mode)
        if mode == K.ContactMode.FREE:
            phase[k] = Phase.FREE
        elif mode == K.ContactMode.NECKED:
            phase[k] = Phase.NECKED
        elif abs(velocity[k]) <= STICK_VELOCITY:
            phase[k] = Phase.STUCK
        else:
            phase[k] = Phase.INTRUSION if velocity[k] > 0.0 else Phase.WITHDRAWAL
    check_finite_output("MuJoCo", time, depth, velocity, force)
    return FootResult(time, depth, velocity, force, phase, mass, GRAVITY, "mujoco", 0, np.full(n, np.nan))
