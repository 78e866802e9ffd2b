"""The MuJoCo adapter in 3-D: the whole mud wrench on feet of any shape, held in every direction.

Usage::

    spec = mujoco.MjSpec.from_file("robot.xml")
    add_mud_3d(spec, ["toe_fl", "toe_fr", "toe_hl", "toe_hr"])     # before compiling
    model = spec.compile(); data = mujoco.MjData(model)
    mud = MudAdapter3D(model, data, ["toe_fl", "toe_fr", "toe_hl", "toe_hr"],
                       MudPatch(MudParameters.from_water_content(0.25)))
    mud.step()                                                     # instead of mujoco.mj_step

Each foot's surface is its geom's (:func:`mudforce.model.shapes.from_mujoco_geom`)
unless ``shapes=`` says otherwise; a geom with no surface (a plane, a height
field) is refused, never silently the paper's cuboid. The feet's states are
the 3-D law's (:class:`mudforce.steppers.contact3d.MudContacts3D`, one per
patch), stepped on each foot geom's pose after every MuJoCo step.

How the force is applied (docs/engines3d.md)
--------------------------------------------
As in the 1-D adapter (:mod:`mudforce.engines.mujoco`), the parts of the
force that are set-valued at rest go to MuJoCo's constraint solver as
friction on spatial tendons, so that every stuck foot of the model is held
jointly with the whole multibody, without chatter; the rest is applied
explicitly through ``xfrc_applied`` (added for the step, taken back after).

* **Vertically**, the rest band ``[F_up, F_down]`` of the foot is the sum,
  over its elements, of each element's band
  (:func:`mudforce.engines.dynamics.rest_band.branch_forces_row` on its 1-D state, a
  stress) times its downward-facing projection ``A_i max(-n_z, 0)``
  (:func:`mudforce.model.law3d.vertical_weight`): the mid-band force plus the
  drag is applied, and half the band's width is the friction of a vertical
  tendon. The world's down direction decides, not the geom's local z. The
  mid-band force's sideways part (each element's share turned by
  :func:`mudforce.model.law3d.vertical_lean`, as the law turns its vertical
  force) is applied explicitly with it. *An approximation:* a foot held
  within its band gets the sideways part of the band's middle, not of the
  force it is held at (at most the lean, about a third, times half the
  band apart; 0 for a symmetric foot).
* **Sideways**, the foot is held rigidly up to the law's lateral capacity
  (:func:`mudforce.model.law3d.lateral_capacity` summed over the submerged
  elements) and slides against it beyond: the friction of two horizontal
  tendons, one along the foot's last horizontal motion ``u``, one across
  it, each with the capacity in its direction. The horizontal drag
  (:func:`mudforce.model.law3d.horizontal_drag`) is applied explicitly.
  *Ours, an approximation of the law:* the law's elastic slip before yield
  (at most ``sigma_y / k``, 1.7 to 11 mm for Table I) is not reproduced:
  the engine foot does not deflect before it slides. An explicit elastic
  slip would ring undamped (the law has no sideways damping) and, at the
  stiffness ``k_m_w S``, would need steps of about a millisecond.
* All of it acts at the foot's **contact point**, the centroid of its
  submerged downward-facing area (the lowest element when none is): a
  site the adapter moves there before every step, with the three tendons'
  anchors 1 m above it and 1 m away along ``u`` and across it. (For a
  geom at its body's origin MuJoCo keeps that site at the origin,
  ``site_sameframe``, so such a foot is held at its geom's centre:
  docs/engines3d.md says why that is left so.)

After each MuJoCo step the feet's new poses are committed to their 3-D
states (:attr:`law_forces`, :attr:`law_torques`: the law's own wrench on the
poses taken), and the next step's bands, capacities, contact points and
anchors are prepared.

A **rigid floor** under the mud (a geom the feet collide with) carries
part of the load while the mud holds the rest: the adapter warns once per
foot when a foot in the mud touches a geom that is not a foot.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from mudforce.engines._checks import MAX_NSTEP, check_mass, drop_numbers, name_list, step_count
from mudforce.engines.dynamics.result import GRAVITY, REST_SPEED
from mudforce.engines.mujoco._spec import check_model_data, check_prefix, compiled_copy, geom_frame, mujoco_module
from mudforce.engines.mujoco._spec import read_only as _read_only
from mudforce.engines.mujoco._step import ANCHOR_HEIGHT
from mudforce.engines.mujoco._step3d import (
    C_ALPHA,
    C_BETA,
    C_LAM_RHO,
    C_SIGMA_Y,
    C_SURFACE,
    C_WIDTH,
    N_FOOT_CONSTANTS,
    add_wrench,
    feet_bands,
    gather_poses,
    mat2quat_address,
    place_anchors,
    prepare,
    scratch,
)
from mudforce.errors import InputError, finite_number, number_within, shown, true_or_false
from mudforce.model.shapes import Shape, from_mujoco_geom
from mudforce.steppers.contact3d import ContactStates3D, MudContacts3D

__all__ = ["DROP_SHAPES", "SUPPORTED_GEOMS", "AdapterState3D", "Drop3D", "MudAdapter3D", "add_mud_3d", "drop_model_3d",
           "foot_geom", "simulate_drop_3d"]

#: The adapter's own arrays that :attr:`MudAdapter3D.state` saves, by attribute name (what the next step reads: the
#: feet's patches, last horizontal directions, last poses, the coming step's wrench and anchors' directions and the
#: last ones, the bands and holds, the constants of each foot's patch and the law's last wrench).
_STATE_ARRAYS = ("_patch", "_u", "_last_pos", "_applied", "_dirs", "_last_applied", "_last_dirs", "_velocity_z",
                 "_band", "_capacity", "_bands", "_const", "_law_forces", "_law_torques", "_pos", "_mats", "_quats")


class AdapterState3D(NamedTuple):
    """Everything a :class:`MudAdapter3D` remembers between steps, for ``adapter.state = saved`` (rollouts, resets).

    Save and restore MuJoCo's own state with it (``mujoco.mj_getState`` / ``mj_setState`` with
    ``mjSTATE_INTEGRATION``): the two together replay a rollout bit for bit.

    Attributes
    ----------
    contacts : tuple of ContactStates3D
        Each patch's feet (:attr:`mudforce.MudContacts3D.state`).
    arrays : tuple of ndarray
        The adapter's own arrays (the feet's patches, last poses and directions, the coming step's wrench [N],
        [N m], bands [N] and holds [N]), in its own order: a snapshot, not to be edited.
    model_rows : tuple of ndarray
        The rows of MuJoCo's model the adapter writes each step: its sites' local positions [m] and its tendons'
        friction (the holds [N]).
    patch_changed : bool
        Whether a foot changed patch at the last step.
    """

    contacts: tuple[ContactStates3D, ...]
    arrays: tuple[np.ndarray, ...]
    model_rows: tuple[np.ndarray, np.ndarray]
    patch_changed: bool

#: MuJoCo geom types a foot's surface can be taken from (:func:`mudforce.model.shapes.from_mujoco_geom`).
SUPPORTED_GEOMS = ("sphere", "capsule", "cylinder", "box", "ellipsoid", "mesh")
_SOLREF_FRICTION = (1e-9, 1.0)  # as the 1-D adapter: MuJoCo raises it to its minimum, 2 time steps
_SOLIMP_FRICTION = (0.9999, 0.9999, 0.001, 0.5, 2.0)


def _names(prefix: str, foot: str) -> dict[str, str]:
    """Names of a foot's contact site, its three anchors and three tendons (z: vertical, u, v: horizontal)."""
    return {"site": f"{prefix}site_{foot}", "anchor_z": f"{prefix}anchor_site_{foot}",
            "anchor_u": f"{prefix}anchor_u_{foot}", "anchor_v": f"{prefix}anchor_v_{foot}",
            "tendon_z": f"{prefix}tendon_{foot}", "tendon_u": f"{prefix}tendon_u_{foot}",
            "tendon_v": f"{prefix}tendon_v_{foot}"}


def _kind_name(mj: Any, kind: int) -> str:
    return str(mj.mjtGeom(kind).name).removeprefix("mjGEOM_").lower()


def _spec_geom(spec: Any, name: str) -> Any:
    """The geom a foot name gives in a spec (a geom's name, or a body's with exactly one geom), else InputError."""
    mj = mujoco_module()
    geom = spec.geom(name)
    if geom is None:
        body = spec.body(name)
        if body is None:
            raise InputError(f"foot {name!r} names no geom: the model has no geom or body named {name!r}")
        geoms = list(body.geoms)
        if len(geoms) != 1:
            raise InputError(f"foot {name!r} is a body with {len(geoms)} geoms: name its foot geom")
        geom = geoms[0]
    kind = _kind_name(mj, int(geom.type))
    if kind not in SUPPORTED_GEOMS:
        raise InputError(f"foot {name!r} is a geom of type {kind}, which has no surface for the 3-D law; expected "
                         f"one of {', '.join(SUPPORTED_GEOMS)} (or give shapes=)")
    return geom


def foot_geom(model: Any, name: str) -> int:
    """The id of a foot's geom in a compiled model: a geom's name, or a body's with exactly one geom.

    Raises
    ------
    InputError
        For a name that is neither, or a body with no geom or several.
    """
    mj = mujoco_module()
    gid = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_GEOM, name))
    if gid >= 0:
        return gid
    bid = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, name))
    if bid < 0:
        raise InputError(f"foot {name!r} names no geom: the model has no geom or body named {name!r}")
    geoms = [int(g) for g in np.flatnonzero(model.geom_bodyid == bid)]
    if len(geoms) != 1:
        raise InputError(f"foot {name!r} is a body with {len(geoms)} geoms: name its foot geom")
    return geoms[0]


def add_mud_3d(spec: Any, feet: Sequence[str], *, prefix: str = "mud_") -> None:
    """Prepare a model for 3-D mud contact under the named feet (edit an ``mujoco.MjSpec`` before compiling).

    Adds, per foot, a contact site on the foot's body, three anchor sites on
    the world body and three spatial tendons from them to the contact site
    (vertical, and two horizontal), which :class:`MudAdapter3D` moves and
    loads every step. Every foot is checked before the spec is changed.

    Parameters
    ----------
    spec : mujoco.MjSpec
        The model being built.
    feet : sequence of str
        Foot geoms, or bodies with exactly one geom, of type sphere, capsule,
        cylinder, box, ellipsoid or mesh.
    prefix : str
        Prefix of the names of the added sites and tendons.
    """
    mj = mujoco_module()
    if not isinstance(spec, mj.MjSpec):
        raise InputError(f"spec must be a mujoco.MjSpec (edited before compiling), got {type(spec).__name__}")
    feet = name_list(feet)
    check_prefix(prefix)
    geoms = [_spec_geom(spec, name) for name in feet]
    taken = [n for name in feet for n in _names(prefix, name).values()
             if spec.site(n) is not None or spec.tendon(n) is not None]
    if taken:
        raise InputError(f"the model already has {taken[0]!r}: add_mud_3d was called twice for a foot (or use "
                         "another prefix=)")
    compiled = compiled_copy(spec)  # compiled once, if a turned foot asks for it (before any site is added below)
    for name, geom in zip(feet, geoms, strict=True):
        n = _names(prefix, name)
        # at the geom's centre: a fromto geom's pos is unset in the spec, and a site left at its body's origin is
        # kept there by MuJoCo (site_sameframe), where the holds then acted, away from the foot
        centre, _, _ = geom_frame(geom, compiled)
        geom.parent.add_site(name=n["site"], pos=[float(v) for v in centre], size=[0.002, 0.0, 0.0])
        for anchor, tendon in (("anchor_z", "tendon_z"), ("anchor_u", "tendon_u"), ("anchor_v", "tendon_v")):
            spec.worldbody.add_site(name=n[anchor], pos=[0.0, 0.0, ANCHOR_HEIGHT], size=[0.002, 0.0, 0.0])
            t = spec.add_tendon(name=n[tendon])
            t.wrap_site(n[anchor])
            t.wrap_site(n["site"])
            t.frictionloss = 0.0
            t.solref_friction = list(_SOLREF_FRICTION)
            t.solimp_friction = list(_SOLIMP_FRICTION)


def _patch_list(patches: Any) -> list[Any]:
    from mudforce.engines.mujoco import MudPatch

    if isinstance(patches, MudPatch):
        return [patches]
    if (isinstance(patches, Sequence) and not isinstance(patches, str) and patches
            and all(isinstance(p, MudPatch) for p in patches)):
        plist = list(patches)
    else:
        raise InputError(f"patches must be a MudPatch or a non-empty sequence of MudPatch, got {shown(patches)}")
    big = math.inf
    boxes = [p.extent if p.extent is not None else (-big, big, -big, big) for p in plist]
    for k, (x0, x1, y0, y1) in enumerate(boxes):
        for j in range(k):  # a foot is in the first patch that contains it: a patch inside an earlier one is never
            a0, a1, b0, b1 = boxes[j]
            if a0 <= x0 and x1 <= a1 and b0 <= y0 and y1 <= b1:
                raise InputError(f"patch {k} lies inside patch {j}, which comes first: it misses every foot; "
                                 "order the patches, or drop it")
    return plist


class MudAdapter3D:
    """Mud in 3-D under named feet of a MuJoCo model prepared with :func:`add_mud_3d`.

    Parameters
    ----------
    model : mujoco.MjModel
        Compiled from a spec that :func:`add_mud_3d` prepared for these feet.
    data : mujoco.MjData
        Its data. During :meth:`step` the adapter adds the mud's explicit
        force to ``xfrc_applied`` of the foot bodies and takes it back
        afterwards (user forces there are kept). It owns ``model.site_pos``
        of its sites and ``model.tendon_frictionloss`` of its tendons.
    feet : sequence of str
        The names given to :func:`add_mud_3d`.
    patches : MudPatch or sequence of MudPatch
        The mud: one patch, or several regions shared by all feet (a foot
        is in the first patch whose extent holds its geom's centre; outside
        every patch it feels no mud and its state is reset). A patch that
        lies inside an earlier one can hold no foot and is refused.
    shapes : Shape or sequence of Shape, optional
        Each foot's surface in its geom's frame [m]; by default the geom's
        own (:func:`mudforce.model.shapes.from_mujoco_geom`, at ``resolution``).
    resolution : float, optional
        Element size of the shapes taken from the geoms [m].
    prefix : str
        As given to :func:`add_mud_3d`.

    Attributes
    ----------
    feet : tuple of str
        The feet's names, in the order of every per-foot array.
    shapes : tuple of Shape
        Each foot's surface.
    """

    def __init__(self, model: Any, data: Any, feet: Sequence[str], patches: Any,
                 shapes: Shape | Sequence[Shape] | None = None, *, resolution: float | None = None,
                 prefix: str = "mud_") -> None:
        mj = mujoco_module()
        check_model_data(mj, model, data)  # (another model's data was stepped without a word)
        names = name_list(feet)
        if not isinstance(prefix, str):
            raise InputError(f"prefix must be a str, got {type(prefix).__name__}")
        plist = _patch_list(patches)
        n = len(names)
        gids = [foot_geom(model, name) for name in names]
        if shapes is None:
            slist = [from_mujoco_geom(model, g, resolution=resolution) for g in gids]
        elif isinstance(shapes, Shape):
            slist = [shapes] * n
        elif isinstance(shapes, Sequence) and all(isinstance(s, Shape) for s in shapes):
            slist = list(shapes)
        else:
            raise InputError(f"shapes must be a Shape, a sequence of Shape or None, got {type(shapes).__name__}")
        if len(slist) != n:
            raise InputError(f"got {len(slist)} shapes for {n} feet")
        ids = []
        for name in names:
            found = {}
            for key, full in _names(prefix, name).items():
                kind = mj.mjtObj.mjOBJ_TENDON if key.startswith("tendon") else mj.mjtObj.mjOBJ_SITE
                found[key] = int(mj.mj_name2id(model, kind, full))
            if min(found.values()) < 0:
                raise InputError(f"foot {name!r} was not prepared: call add_mud_3d(spec, [{name!r}, ...]) "
                                 "before compiling")
            ids.append(found)
        # everything checked: build
        self._mj = mj
        self.model = model
        self.data = data
        self.feet: tuple[str, ...] = tuple(names)
        self.shapes: tuple[Shape, ...] = tuple(slist)
        self.patches = tuple(plist)
        self._gids = np.array(gids, dtype=np.int64)
        self._bodies = np.array([int(model.geom_bodyid[g]) for g in gids], dtype=np.int64)
        self._sites = np.array([i["site"] for i in ids], dtype=np.int64)
        self._anchors = np.array([[i["anchor_z"], i["anchor_u"], i["anchor_v"]] for i in ids], dtype=np.int64)
        self._tendons = np.array([[i["tendon_z"], i["tendon_u"], i["tendon_v"]] for i in ids], dtype=np.int64)
        self._written_sites = np.concatenate([self._sites, self._anchors.ravel()])  # the model rows it writes
        self._contacts = [MudContacts3D(p.params, list(slist), n, surface_heights=p.surface_height) for p in plist]
        # the feet's own state and constant rows (they follow the feet as they are stepped), not kernel_rows()'s
        # read-only views: one compiled signature of prepare's rest band, the writable rows the 1-D adapter passes
        self._rows = [c._live_rows() for c in self._contacts]
        # where the 3-D step keeps their states: the band exports the rows it reads (_step3d.foot_band)
        self._lanes = [c._live_lanes() for c in self._contacts]
        # one patch with no extent holds every foot at every step: no feet enter or leave it (a fast path)
        self._everywhere = len(plist) == 1 and plist[0].extent is None
        sizes = [s.n for s in slist]
        self._foot_of = np.repeat(np.arange(n), sizes)
        self._cb = np.vstack([s.centroids for s in slist])
        self._nb = np.vstack([s.normals for s in slist])
        self._area = np.concatenate([s.areas for s in slist])
        self._width = np.array([float(s.width) if s.width is not None else np.nan for s in slist])
        self._starts = np.concatenate(([0], np.cumsum(sizes)))
        self._scratch = scratch(max(sizes))  # prepare's: a foot's submerged elements side by side
        # the band (F_up, F_down) and drag [N] of feet in all patches but one, then their sideways parts (x, y)
        self._bands = np.zeros((n, 9))
        self._patch_const = np.zeros((len(plist), N_FOOT_CONSTANTS))
        for k, p in enumerate(plist):
            q = p.params
            self._patch_const[k, [C_SURFACE, C_SIGMA_Y, C_ALPHA, C_BETA, C_LAM_RHO]] = (
                p.surface_height, q.sigma_y, q.alpha, q.beta, q.lambda_ * q.rho_m)
        self._const = np.zeros((n, N_FOOT_CONSTANTS))
        self._const[:, C_WIDTH] = self._width
        self._velocity_z = np.zeros(n)
        self._band = np.zeros((2, n))
        self._pos = np.zeros((n, 3))
        self._mats = np.zeros((n, 9))
        self._quats = np.zeros((n, 4))
        self._patch_changed = True  # whether a foot changed patch at the last commit (then _const is refilled)
        self._u = np.tile([1.0, 0.0], (n, 1))  # each foot's last direction of horizontal motion
        self._last_pos = np.zeros((n, 3))
        self._last_applied = np.zeros((n, 6))
        self._last_dirs = np.zeros((n, 3, 3))
        self._applied = np.zeros((n, 6))  # the explicit force [N] and torque about the COM [N m] of the coming step
        self._dirs = np.zeros((n, 3, 3))  # unit vectors from contact point to each anchor (z, u, v)
        self._patch = np.full(n, -1, dtype=np.int64)
        # MuJoCo's arrays and options read every step, taken once (views: its buffers do not move for the life of
        # the model and data; a property read builds a new view each time, ~0.2 us, and model.opt ~1 us)
        self._opt = model.opt
        self._geom_xpos, self._geom_xmat = data.geom_xpos, data.geom_xmat
        self._site_xpos = data.site_xpos
        self._xipos, self._xpos, self._xmat = data.xipos, data.xpos, data.xmat
        self._site_pos, self._frictionloss = model.site_pos, model.tendon_frictionloss
        self._mat2quat = mat2quat_address(mj)  # MuJoCo's mju_mat2Quat, called from compiled code (0: not found)
        self._foot_rows = [(self._quats[f], self._mats[f]) for f in range(n)]  # each foot's quaternion and matrix
        self._submerged = np.zeros(n, dtype=bool)
        self._warned: set[str] = set()
        self._law_forces = np.zeros((n, 3))  # law_forces, law_torques, capacity: written in place by each step
        self._law_torques = np.zeros((n, 3))
        self._capacity = np.zeros((n, 2))
        self.reset()

    # ---------------------------------------------------------------- stepping
    def reset(self) -> None:
        """Forget every foot's history and prepare the next step from the current ``data`` (runs ``mj_forward``)."""
        for c in self._contacts:
            c.reset()
        self._applied[:] = 0.0
        self._patch[:] = -1
        self._mj.mj_forward(self.model, self.data)
        self._last_pos[:] = self.data.geom_xpos[self._gids]
        dt = float(self._opt.timestep)
        self._commit(dt, first=True)
        self._prepare(dt)

    def step(self, nstep: int = 1) -> None:
        """Advance the simulation ``nstep`` MuJoCo steps with the mud's wrench and holds."""
        if nstep.__class__ is not int or not 1 <= nstep <= MAX_NSTEP:  # 0 and -1 refused, not taken as no step
            nstep = step_count(nstep)
        mj, model, data = self._mj, self.model, self.data
        xfrc = data.xfrc_applied
        dt = float(self._opt.timestep)
        for _ in range(nstep):
            add_wrench(xfrc, self._bodies, self._applied, 1.0)
            mj.mj_step(model, data)
            add_wrench(xfrc, self._bodies, self._applied, -1.0)
            if data.ncon:
                self._check_floor()
            # the step's wrench and directions become the last ones; _prepare rewrites every entry of the others
            self._last_applied, self._applied = self._applied, self._last_applied
            self._last_dirs, self._dirs = self._dirs, self._last_dirs
            self._commit(dt, first=False)
            self._prepare(dt)

    def _poses(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        d = self.data
        pos = np.array(d.geom_xpos[self._gids])
        mats = np.array(d.geom_xmat[self._gids]).reshape(-1, 3, 3)
        quats = np.empty((len(self.feet), 4))
        for f in range(len(self.feet)):
            self._mj.mju_mat2Quat(quats[f], mats[f].ravel())
        return pos, mats, quats

    def _commit(self, dt: float, *, first: bool) -> None:
        """Step each patch's feet to their poses (their first step when ``first``); reset the feet outside it."""
        pos, quats = self._pos, self._quats
        # data.geom_xpos[gids] in place, and the quaternions by MuJoCo's mju_mat2Quat
        gather_poses(self._geom_xpos, self._geom_xmat, self._gids, pos, self._mats, quats, self._mat2quat)
        if not self._mat2quat:  # its C function not found: through the binding
            mat2quat = self._mj.mju_mat2Quat
            for quat, mat in self._foot_rows:
                mat2quat(quat, mat)
        if self._everywhere:  # every foot in the one patch, always: no masks, the wrench written in place
            self._patch_changed = bool(self._patch[0] != 0)
            self._patch[:] = 0
            try:
                self._contacts[0].step(pos, quats, dt, out=(self._law_forces, self._law_torques))
            except InputError:
                self._law_forces[:] = 0.0
                self._law_torques[:] = 0.0
                raise
            return
        n = len(self.feet)
        where = np.full(n, -1, dtype=np.int64)
        for k, p in enumerate(self.patches):
            if p.extent is None:
                inside = where < 0
            else:
                x0, x1, y0, y1 = p.extent
                inside = (where < 0) & (x0 <= pos[:, 0]) & (pos[:, 0] <= x1) & (y0 <= pos[:, 1]) & (pos[:, 1] <= y1)
            where[inside] = k
        self._law_forces[:] = 0.0
        self._law_torques[:] = 0.0
        for k, c in enumerate(self._contacts):
            mine = where == k
            entering = mine & (self._patch != k)
            if entering.any() and not first:
                c.reset(entering)  # a foot entering this patch starts afresh in it
            if mine.any():
                forces, torques = c.step(pos, quats, dt)
                self._law_forces[mine] = forces[mine]
                self._law_torques[mine] = torques[mine]
            leaving = ~mine & (self._patch == k)
            if leaving.any():
                c.reset(leaving)
        self._patch = where
        self._patch_changed = True

    def _prepare(self, dt: float) -> None:
        """The next step's bands, holds, contact points, anchors and explicit wrench (compiled: ``_step3d.prepare``,
        ``_step3d.place_anchors``)."""
        pos, mats = self._pos, self._mats
        # the bands of the feet in the first patch that holds any are computed in prepare, the others' here
        k_band = 0
        if not self._everywhere:
            k_band = -1
            for k in range(len(self._contacts)):
                if (self._patch == k).any():
                    if k_band < 0:
                        k_band = k
                    else:
                        states, rows = self._rows[k]
                        feet_bands(states, rows, dt, self._patch, k, self._starts, mats, self._nb, self._area,
                                   self._bands, *self._lanes[k])
        states, rows = self._rows[max(k_band, 0)]
        const = self._const
        if self._patch_changed:
            for f in range(len(self.feet)):
                k = int(self._patch[f])
                if k >= 0:
                    const[f, :C_WIDTH] = self._patch_const[k, :C_WIDTH]  # the width is the foot's
        prepare(pos, mats, self._last_pos, dt, self._starts, self._cb, self._nb, self._area, self._patch, const,
                states, rows, k_band, self._bands, self._velocity_z, self._u, self._xipos, self._xpos, self._xmat,
                self._bodies, self._sites, self._tendons, self._site_pos, self._frictionloss, REST_SPEED, self._band,
                self._capacity, self._applied, self._dirs, self._scratch, *self._lanes[max(k_band, 0)])
        # the anchors, 1 m from the contact site along the tendons' directions, where the next step's constraints
        # will see the site: at the current qpos, with the local position prepare gave it. After mj_step the
        # positions in data are those of the state the step started from (the feet's poses are committed from
        # them, on purpose: docs/engines3d.md), and anchored there the sideways tendons leant by the step's
        # vertical motion over their 1 m, their stiff friction (the sideways hold) turning vertical motion into a
        # sideways force: up to 1.6 N on a sphere dropped straight, which pushed it 4-6 um aside. mj_kinematics
        # also keeps the site where MuJoCo keeps it (at the body's origin or centre of mass, site_sameframe)
        self._mj.mj_kinematics(self.model, self.data)
        place_anchors(self._site_xpos, self._sites, self._anchors, self._dirs, self._site_pos, ANCHOR_HEIGHT)

    def _check_floor(self) -> None:
        """Warn once per foot that touches a geom that is not a foot while it is in the mud."""
        d = self.data
        pairs = np.asarray(d.contact.geom)[: d.ncon]
        for f, g in enumerate(self._gids):
            name = self.feet[f]
            if name in self._warned or self._patch[f] < 0 or not self._band[1, f] > 0.0:
                continue
            hit = pairs[(pairs == g).any(axis=1)]
            others = [int(o) for o in hit.ravel() if o != g and o not in self._gids]
            if others:
                other = self._mj.mj_id2name(self.model, self._mj.mjtObj.mjOBJ_GEOM, others[0]) or f"geom {others[0]}"
                self._warned.add(name)
                warnings.warn(f"foot {name!r} touches {other!r} while in the mud: a rigid contact carries part of "
                              "its load; turn that geom's collisions off under the mud (contype/conaffinity) "
                              "(docs/engines3d.md)", RuntimeWarning, stacklevel=3)

    # ---------------------------------------------------------------- state
    @property
    def state(self) -> AdapterState3D:
        """A snapshot of everything the adapter remembers (read-only copies); assign one back to restore it.

        Restore MuJoCo's own state with it (``mj_setState``, ``mjSTATE_INTEGRATION``): the next steps then replay
        the saved rollout bit for bit. A state of another adapter (other feet, shapes or patches) is refused in one
        line and nothing is changed.
        """
        arrays = tuple(_frozen(getattr(self, name)) for name in _STATE_ARRAYS)
        rows = (_frozen(self._site_pos[self._written_sites]), _frozen(self._frictionloss[self._tendons.ravel()]))
        return AdapterState3D(tuple(c.state for c in self._contacts), arrays, rows, bool(self._patch_changed))

    @state.setter
    def state(self, saved: AdapterState3D) -> None:
        if not isinstance(saved, AdapterState3D):
            raise InputError(f"state must be an AdapterState3D from MudAdapter3D.state, got {type(saved).__name__}")
        mine = self.state  # (its contacts' states restore them if a later one is refused)
        # (its parts are tuples: len() of None or a number raised TypeError)
        shapes_ok = (all(isinstance(part, (tuple, list)) for part in (saved.contacts, saved.arrays, saved.model_rows))
                     and len(saved.contacts) == len(mine.contacts) and len(saved.arrays) == len(mine.arrays)
                     and len(saved.model_rows) == 2
                     and all(isinstance(a, np.ndarray) and a.shape == b.shape and a.dtype == b.dtype
                             for a, b in zip((*saved.arrays, *saved.model_rows), (*mine.arrays, *mine.model_rows),
                                             strict=True)))
        if not shapes_ok:
            raise InputError("a state of this adapter is an AdapterState3D taken from an adapter of the same feet, "
                             "shapes and patches; got one of another")
        if not all(np.all(np.isfinite(a)) for a in (*saved.arrays, *saved.model_rows) if a.dtype.kind == "f"):
            raise InputError("a state of this adapter holds only finite numbers; got NaN or an infinity")
        patch_changed = true_or_false(saved.patch_changed, "a state's patch_changed")
        if not np.all((saved.arrays[0] >= -1) & (saved.arrays[0] < len(self._contacts))):
            raise InputError(f"a state's patches must be -1 (none) or 0 to {len(self._contacts) - 1}")
        # each foot's constants (its patch's mud and surface, its own width) are this adapter's: an adapter over
        # another mud was taken, and its constants stepped with this one's contacts
        patch, const = saved.arrays[0], saved.arrays[_STATE_ARRAYS.index("_const")]
        inside = patch >= 0
        if not (np.array_equal(const[inside, :C_WIDTH], self._patch_const[patch[inside], :C_WIDTH])
                and np.array_equal(const[:, C_WIDTH], self._width, equal_nan=True)):
            raise InputError("a state of this adapter is one taken from an adapter of the same feet, shapes and "
                             "patches; got one of another mud, surface or foot width")
        # the contacts last: each refuses a bad state without changing anything, and a refusal of a later one must
        # leave the earlier ones as they were
        try:
            for c, s in zip(self._contacts, saved.contacts, strict=True):
                c.state = s
        except (InputError, TypeError, AttributeError) as error:
            for c, s in zip(self._contacts, mine.contacts, strict=True):
                c.state = s
            raise InputError(f"a state of this adapter's patches was refused: {error}") from None
        for name, value in zip(_STATE_ARRAYS, saved.arrays, strict=True):
            getattr(self, name)[...] = value
        self._site_pos[self._written_sites] = saved.model_rows[0]
        self._frictionloss[self._tendons.ravel()] = saved.model_rows[1]
        self._patch_changed = patch_changed

    # ---------------------------------------------------------------- outputs
    # (read-only views of the adapter's own arrays, which each step writes in place: they follow the steps, and a
    # write through them, which changed what the adapter reported and saved in its state, is refused)
    @property
    def law_forces(self) -> np.ndarray:
        """The law's force on each foot at the last committed pose [N], world frame, shape (n, 3) (a read-only
        view)."""
        return _read_only(self._law_forces)

    @property
    def law_torques(self) -> np.ndarray:
        """The law's torque on each foot about its geom's centre at the last committed pose [N m], shape (n, 3) (a
        read-only view)."""
        return _read_only(self._law_torques)

    @property
    def band(self) -> tuple[np.ndarray, np.ndarray]:
        """The vertical band ``(F_up, F_down)`` of the coming step [N], each of shape (n,) (read-only views)."""
        return _read_only(self._band[0]), _read_only(self._band[1])

    @property
    def capacity(self) -> np.ndarray:
        """The sideways holds along ``u`` and across it of the coming step [N], shape (n, 2) (a read-only view)."""
        return _read_only(self._capacity)

    @property
    def contact_forces(self) -> np.ndarray:
        """The mud's force on each foot in the last step [N], world frame, shape (n, 3).

        The explicit force the adapter applied plus the tendons' friction the
        solver found: while a foot sticks, the load it carries; while it moves,
        the branch force and the sideways capacity.
        """
        mj = self._mj
        d = self.data
        total: np.ndarray = np.array(self._last_applied[:, :3], dtype=np.float64)
        rows = np.flatnonzero(np.asarray(d.efc_type) == int(mj.mjtConstraint.mjCNSTR_FRICTION_TENDON))
        ids = np.asarray(d.efc_id)[rows]
        frc = np.asarray(d.efc_force)[rows]
        for f in range(len(self.feet)):
            for axis in range(3):
                hit = np.flatnonzero(ids == self._tendons[f, axis])
                if hit.size:  # the tendon shortens as the foot moves toward its anchor
                    total[f] -= float(frc[hit[0]]) * self._last_dirs[f, axis]
        return total

    @property
    def depths(self) -> np.ndarray:
        """Depth of each foot's lowest element centroid below its patch's surface [m] (positive down; NaN outside)."""
        pos, mats, _ = self._poses()
        fo = self._foot_of
        cz = pos[fo, 2] + np.einsum("ej,ej->e", mats[fo, 2, :], self._cb)
        out = np.full(len(self.feet), np.nan)
        for f in range(len(self.feet)):
            k = self._patch[f]
            if k >= 0:
                lo, hi = self._starts[f], self._starts[f + 1]
                out[f] = self.patches[k].surface_height - float(cz[lo:hi].min())
        return out

    def __repr__(self) -> str:
        return f"MudAdapter3D(feet={list(self.feet)}, patches={len(self.patches)})"


#: Geom types of :func:`simulate_drop_3d` and their MuJoCo ``size`` from full dimensions [m].
DROP_SHAPES = ("sphere", "capsule", "cylinder", "box")


def _lowest(kind: str, size: np.ndarray, rot: np.ndarray) -> float:
    """How far the lowest point of a geom lies below its centre [m] (exact, from its world rotation ``rot``)."""
    column = rot[2]  # the world z of each geom axis
    if kind == "sphere":
        return float(size[0])
    if kind == "capsule":
        return float(size[0] + size[1] * abs(column[2]))
    if kind == "cylinder":
        return float(size[0] * math.sqrt(max(0.0, 1.0 - column[2] ** 2)) + size[1] * abs(column[2]))
    return float(np.abs(column) @ size[:3])  # box


@dataclass(frozen=True, eq=False)
class Drop3D:
    """A 3-D drop in MuJoCo (:func:`simulate_drop_3d`): one row per step.

    Attributes
    ----------
    time : ndarray, shape (m,)
        [s].
    position : ndarray, shape (m, 3)
        The geom's centre [m], world frame, z up.
    velocity : ndarray, shape (m, 3)
        Its velocity [m/s].
    depth : ndarray, shape (m,)
        Depth of the geom's lowest point below the surface [m], positive down.
    force : ndarray, shape (m, 3)
        The mud's force on the foot [N] (:attr:`MudAdapter3D.contact_forces`).
    tilt : ndarray, shape (m,)
        Angle between the geom's z axis and the world's [rad].
    mass : float
        [kg].
    """

    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    tilt: np.ndarray
    mass: float

    def speed(self, last: float = 0.5) -> float:
        """Mean speed of the centre over the last ``last`` seconds [m/s] (a creep rate at rest; ``last`` > 0 [s])."""
        k = self.time >= self.time[-1] - finite_number(last, "last", "s", positive=True)  # as FootResult's
        span = self.time[k][-1] - self.time[k][0]
        return float(np.linalg.norm(self.position[k][-1] - self.position[k][0]) / span) if span > 0 else 0.0

    def force_std(self, last: float = 0.5) -> float:
        """Largest standard deviation of a force component over the last ``last`` seconds [N] (``last`` > 0 [s])."""
        k = self.time >= self.time[-1] - finite_number(last, "last", "s", positive=True)  # as FootResult's
        return float(self.force[k].std(axis=0).max())


def drop_model_3d(mass: float, shape: str, size: Sequence[float], *, height: float = 0.0, tilt: float = 0.0,
                  dt: float = 1e-3) -> Any:
    """A compiled model of a free foot geom above mud at ``z = 0``, prepared with :func:`add_mud_3d` (foot ``"foot"``).

    Parameters: as :func:`_drop_spec` ([kg], -, [m], [m], [rad], [s]).
    """
    spec = _drop_spec(mass, shape, size, height=height, tilt=tilt, dt=dt)
    add_mud_3d(spec, ["foot"])
    return compile_drop(spec)


def compile_drop(spec: Any) -> Any:
    """``spec.compile()`` of a drop's :func:`_drop_spec`, MuJoCo's refusal (a two-line ValueError: a mass whose
    inertia is below its mjMINVAL, ...) as one-line InputError."""
    try:
        return spec.compile()
    except ValueError as error:
        words = " ".join(str(error).split())
        raise InputError(f"MuJoCo refused the drop's model ({words}); expected a foot of physical mass and size, "
                         "e.g. 2 kg and 40 mm") from None


#: Fastest sideways release of a drop, ``|vx|`` [m/s]: 10 m/s, as ``mudforce drop --vx``. Faster, the mud tumbles the
#: foot so fast that a step turns it by a large angle, and the bands the engines take from each element's depth
#: and velocity at the step's start, extrapolated along a straight line, are wrong: at 1 ms in W = 25 % a 40 mm
#: sphere of 2 kg at 100 m/s spun 2 rad a step and came to rest 7 mm above the surface with the mud carrying its
#: weight (the law's own force there 0; a cylinder and a capsule alike), a 5 kg box at 50 m/s made MuJoCo's state
#: unstable (1e300 m/s too, which MuJoCo reset with a warning, the drop returned as if the foot had not moved
#: sideways); at 10 m/s the turn is at most 0.12 rad a step and no foot is held above the surface (in the drops
#: tried: sphere, box, capsule, cylinder; 1 and 5 ms; W = 15 and 25 %). The bound was a recording's velocity
#: bound, 1000 m/s.
MAX_DROP_VX = 10.0


def check_drop_motion(duration: Any, vx: Any, dt: Any) -> tuple[float, float, int]:
    """A drop's ``duration`` [s], ``vx`` [m/s] and number of steps (``floor(duration / dt)``, the 1-D drops' samples
    less one: the last step within the duration), else InputError: ``duration / dt`` at most
    :data:`~mudforce.model.bounds.MAX_OUTPUT_SAMPLES` steps (1e300 s asked numpy for an array too large to make), and
    ``|vx|`` within :data:`MAX_DROP_VX`."""
    from mudforce.model.bounds import check_step, max_samples

    duration = finite_number(duration, "duration", "s", positive=True)
    vx = finite_number(vx, "vx", "m/s")
    if abs(vx) > MAX_DROP_VX:
        raise InputError(f"vx must be within +-{MAX_DROP_VX:g} m/s (a foot's sideways speed), got {vx!r}")
    dt = finite_number(dt, "dt", "s", positive=True)
    check_step(dt)  # before the count: a step of 1e-300 s is named as such, not as too many samples
    steps = max_samples(duration, dt) - 1
    return duration, vx, steps


def check_drop_mass(mass: float, params: Any, shape: Shape, tilt: float, dt: float) -> float:
    """A drop's ``mass`` [kg], at least what its step ``dt`` [s] resolves on the foot's ``shape`` released at ``tilt``
    (checked by :func:`_drop_spec`) [rad], else InputError: the 1-D drops' :func:`~mudforce.engines._checks.check_mass`
    with ``S`` the shape's downward-facing projection ``sum A_i max(-n_z, 0)`` at its release pose (its horizontal
    projection; a flat sole's area, as the 1-D drops'). Lighter, a box's flat sole bounced off the mud at 1 ms steps
    (1.5 g: 38 um above the surface at rest, the mud pushing 2.9 times its weight) and a micro-gram foot was flung
    metres up (MJX: 872 m in 0.3 s, without a word)."""
    c, s = math.cos(tilt), math.sin(tilt)
    nz = shape.normals @ np.array([0.0, s, c])  # each normal's world z: _drop_spec's rotation about x
    return check_mass(mass, params, float(shape.areas @ np.maximum(-nz, 0.0)), dt, "MuJoCo time step")


def _drop_spec(mass: float, shape: str, size: Sequence[float], *, height: float = 0.0, tilt: float = 0.0,
              dt: float = 1e-3) -> Any:
    """The ``mujoco.MjSpec`` of a free foot geom ``"foot"`` above mud at ``z = 0`` (no collisions; not prepared).

    Parameters
    ----------
    mass : float
        [kg], > 0.
    shape : str
        ``sphere``, ``capsule``, ``cylinder`` or ``box`` (MuJoCo's frame: a capsule's and cylinder's axis is z).
    size : sequence of float
        Full dimensions [m]: a sphere's diameter; a capsule's or cylinder's diameter and length (a capsule's
        between its caps' centres); a box's length, width and height.
    height : float
        Release height of the lowest point above the surface [m], within [0, 100].
    tilt : float
        Rotation about the world x axis [rad], within [-pi, pi].
    dt : float
        Time step [s], within the steppers' [1e-9, 1000].
    """
    mj = mujoco_module()
    from mudforce.model.foot import SIZE_RANGE

    mass, height, dt = drop_numbers(mass, height, dt)
    tilt = number_within(tilt, "tilt", -math.pi, math.pi, "rad")  # as --tilt's +-180 deg (1e308 rad was taken)
    if not isinstance(shape, str) or shape not in DROP_SHAPES:  # (an array's `in` raised numpy's ValueError)
        raise InputError(f"shape must be one of {', '.join(DROP_SHAPES)}, got {shown(shape)}")
    needs = {"sphere": 1, "capsule": 2, "cylinder": 2, "box": 3}[shape]
    # 0.04: TypeError, and a 0-d array's iteration too
    if (isinstance(size, (str, bytes)) or not isinstance(size, (Sequence, np.ndarray))
            or (isinstance(size, np.ndarray) and size.ndim != 1)):
        raise InputError(f"size must be a sequence of {needs} number(s) [m] for a {shape}, got "
                         f"{type(size).__name__} {shown(size)}")
    dims = [number_within(v, "size", *SIZE_RANGE, "m") for v in size]  # the shapes' bounds (5e-8 m: MuJoCo's error)
    if len(dims) != needs:
        raise InputError(f"a {shape} needs {needs} dimension(s) [m], got {len(dims)}")
    half = np.array([0.5 * dims[0], 0.5 * dims[1] if needs > 1 else 0.0, 0.5 * dims[2] if needs > 2 else 0.0])
    rot = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(tilt), -math.sin(tilt)], [0.0, math.sin(tilt), math.cos(tilt)]])
    spec = mj.MjSpec()
    spec.modelname = f"mudforce_drop_{shape}"
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -GRAVITY]
    z = height + _lowest(shape, half, rot)
    body = spec.worldbody.add_body(name="body", pos=[0.0, 0.0, z],
                                   quat=[math.cos(0.5 * tilt), math.sin(0.5 * tilt), 0.0, 0.0])
    body.add_freejoint()
    kind = getattr(mj.mjtGeom, f"mjGEOM_{shape.upper()}")
    body.add_geom(name="foot", type=kind, size=list(half), mass=mass, contype=0, conaffinity=0)
    return spec


def simulate_drop_3d(mass: float, params: Any, shape: str, size: Sequence[float], *, duration: float = 2.0,
                     height: float = 0.0, tilt: float = 0.0, vx: float = 0.0, dt: float = 1e-3,
                     resolution: float | None = None) -> Drop3D:
    """Drop a free foot geom into mud in MuJoCo with :class:`MudAdapter3D`: a :class:`Drop3D`.

    Parameters
    ----------
    mass, shape, size, height, tilt, dt
        As for :func:`drop_model_3d` ([kg], -, [m], [m], [rad], [s]); the mass at least what the step resolves,
        ``S max(k_m_i, k_m_w) dt^2`` with ``S`` the foot's horizontal projection at its release
        (:func:`check_drop_mass`: about 2.3 g for the paper's sole upright, 1.5 g for a 40 mm sphere, at 1 ms in
        W = 25 %).
    params : MudParameters
        The mud.
    duration : float
        Simulated time [s], at least ``dt`` (at most 1e8 steps).
    vx : float
        Initial horizontal velocity along x [m/s], within +-10 (:data:`MAX_DROP_VX`).
    resolution : float, optional
        Element size of the foot's surface [m].
    """
    mj = mujoco_module()
    from mudforce.engines.mujoco import MudPatch

    duration, vx, steps = check_drop_motion(duration, vx, dt)
    model = drop_model_3d(mass, shape, size, height=height, tilt=tilt, dt=dt)
    patch = MudPatch(params)
    surface = from_mujoco_geom(model, 0, resolution=resolution)  # the adapter's own (shapes=None)
    check_drop_mass(mass, patch.params, surface, float(tilt), float(dt))
    data = mj.MjData(model)
    data.qvel[0] = vx
    mud = MudAdapter3D(model, data, ["foot"], patch, surface)
    position = np.empty((steps + 1, 3))
    velocity = np.empty((steps + 1, 3))
    force = np.zeros((steps + 1, 3))
    rots = np.empty((steps + 1, 3, 3))
    for k in range(steps + 1):
        if k:
            mud.step()
            force[k] = mud.contact_forces[0]
        rots[k] = np.asarray(data.geom_xmat[0]).reshape(3, 3)
        position[k] = data.geom_xpos[0]
        velocity[k] = data.qvel[:3]
    return _drop_result(shape, model.geom_size[0], dt, position, velocity, force, rots, mass)


def _drop_result(shape: str, half: Any, dt: float, position: np.ndarray, velocity: np.ndarray, force: np.ndarray,
                rots: np.ndarray, mass: float) -> Drop3D:
    """A :class:`Drop3D` from the samples of a drop (one row a step): ``half`` the geom's MuJoCo size [m],
    ``dt`` [s], ``position``, ``velocity``, ``force`` (m, 3) [m, m/s, N], ``rots`` (m, 3, 3) world rotations."""
    size = np.asarray(half, dtype=float)
    depth = np.array([-(position[k, 2] - _lowest(shape, size, rots[k])) for k in range(len(rots))])
    tilt = np.arccos(np.clip(rots[:, 2, 2], -1.0, 1.0))
    return Drop3D(np.arange(len(rots)) * dt, position, velocity, depth, force, tilt, float(mass))


def _frozen(a: np.ndarray) -> np.ndarray:
    """A read-only copy of ``a``."""
    out = np.array(a, copy=True)
    out.setflags(write=False)
    return out
