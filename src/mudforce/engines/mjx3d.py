"""The 3-D law in MJX: feet of any shape, the whole wrench, held in every direction (``pip install 'mudforce[mjx]'``).

Usage (one world; ``jax.vmap`` it over worlds, each with its own mud)::

    import mujoco
    from mujoco import mjx
    import mudforce.engines.mjx3d as mud3d
    from mudforce import MudParameters
    from mudforce.engines.mujoco import MudPatch

    model = mujoco.MjModel.from_xml_path("robot.xml")          # foot geoms: sphere, capsule, box, ...
    m = mjx.put_model(model)
    mud = mud3d.add_mud(model, ["toe_fl", "toe_fr", "toe_hl", "toe_hr"],
                        MudPatch(MudParameters.from_water_content(0.25)))
    d = mjx.make_data(m)
    state = mud3d.init(mud)
    d, state, forces = mud3d.step(m, d, state, mud)          # instead of mjx.step(m, d); forces (feet, 3) [N]

Per-world mud under ``jit``: ``mud3d.set_mud(mud, mudforce.jax.params_from_water_content(w))``
(``w`` traced) inside the function you ``vmap`` over worlds.

The feet and the patches are those of :class:`mudforce.engines.mujoco.MudAdapter3D`:
each foot's surface is its geom's (:func:`mudforce.model.shapes.from_mujoco_geom`;
a plane or height field, a name that is no geom, a body with several geoms is
a one-line :class:`~mudforce.errors.InputError`, never silently the paper's
cuboid), and a foot is in the first :class:`mudforce.engines.mujoco.MudPatch`
whose extent holds its geom's centre (a patch inside an earlier one misses
every foot and is refused). Each foot carries the 3-D law's state
(:func:`mudforce.jax.contact3d.step3d`, every element's paper state), stepped
on its geom's pose once per physics step.

How the force is applied (docs/engines3d.md, "Mud in 3-D in MJX")
-----------------------------------------------------------------
Each call of :func:`step` is one physics step with an implicit (Moreau-Jean)
treatment of what is set-valued at rest, like dry friction; the rows of
every foot of a world are solved together, through the world's inverse
inertia (:func:`mudforce.engines.mjx._joint_rows`, the 1-D MJX step's
projected Gauss-Seidel, here with three rows per foot):

1. ``mjx.forward`` computes the motion without the mud; each foot's geom
   pose (``geom_xpos``, the body's ``xquat`` times the geom's ``quat``) is
   committed to its 3-D state (:func:`mudforce.jax.contact3d.step3d`; a
   foot that was stuck and moved less than 0.1 um keeps its elements'
   depths, so that float32 rounding does not pick the paper's branch);
2. per foot, from its elements (the law's functions of
   :mod:`mudforce.model.law3d`): the **vertical band** ``[F_up, F_down]``,
   the sum of each element's band (:func:`mudforce.jax.branch_forces` on its
   1-D state, the band at the step's start: weight 0 as in
   :mod:`mudforce.engines.mjx`) times its downward-facing projection
   ``A_i max(-n_z, 0)``, and the vertical drag; the **sideways holds**
   along the foot's last horizontal motion ``u`` and across it, the law's
   lateral capacity (:func:`mudforce.model.law3d.lateral_capacity`) summed
   over the submerged elements; the **horizontal drag** (Eq. (5),
   :func:`mudforce.model.law3d.horizontal_drag`), explicit. The world's
   down direction decides, not the geom's local z;
3. three rows per foot through its geom's centre, world ``z``, ``u`` and
   ``v``: the vertical row's force is in ``[F_up, F_down] + drag``
   (:func:`mudforce.jax.stick_force`), a sideways row's in
   ``[-hold, hold]`` (a box, as the CPU adapter's two tendons); the rows of
   every foot are solved jointly for the forces that bring the stuck rows
   to rest by the step's end, the others at their bound; the forces and the
   explicit drag are added to ``qfrc_smooth`` (and ``M^-1 J^T f`` to
   ``qacc``), and the model's integrator (Euler or implicitfast) advances.

So a foot at rest under a load inside its band and holds ends every step at
rest, with no chatter; beyond them it moves against the band's edge and the
capacity. As in :class:`mudforce.engines.mujoco.MudAdapter3D`: the law's elastic
slip before yield is not reproduced (the foot does not deflect before it
slides), and the law's couple is not applied. *Ours:* the mud's force passes
through the geom's centre. Held at the contact point (the centroid of the
loaded area, below the centre), a sphere pushed sideways at its centre by half
its hold rolled in place without limit (68 rad/s after 0.3 s: nothing in three
rows at one point resists a rotation about it), and with only the sideways
rows at the centre an upright capsule tipped over; through the centre,
neither (a tilted foot gets no righting moment from the mud: neutral). The
CPU adapter documents the contact point, but for a geom at its body's origin
MuJoCo keeps its contact site at that origin (``site_sameframe``), so it too
holds such a foot at its centre. Unlike it: the band is taken at the step's
start (the CPU adapter commits a step late and takes it at the step's
predicted end; at 5 ms a 5 kg box (the paper's sole, W = 15 %) rests +2.2 % from
the exact drop here, +16 % there), and a rigid floor under the mud cannot be seen
under ``jit``: :func:`add_mud` warns when a foot can collide with a geom that
is not a foot. Contact constraints computed by ``mjx.forward`` do not respond
to the mud force within the step. The RK4 integrator is not supported.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

import mudforce.jax as mj
import mudforce.jax.contact3d as mj3
from mudforce._plumbing.optional import require
from mudforce.engines._checks import name_list
from mudforce.engines.dynamics.result import REST_SPEED
from mudforce.engines.mjx import _check_step_model, _free_motion, _integrate, _joint_rows, _mjx, _weight
from mudforce.engines.mujoco import MudPatch
from mudforce.engines.mujoco.adapter3d import (
    Drop3D,
    _drop_result,
    _drop_spec,
    _patch_list,
    check_drop_mass,
    check_drop_motion,
    compile_drop,
    foot_geom,
)
from mudforce.errors import InputError, is_integer, shown
from mudforce.model import law3d
from mudforce.model.bounds import bounded_depth
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.shapes import Shape, from_mujoco_geom

__all__ = ["Mud3D", "MudState3D", "add_mud", "init", "set_mud", "simulate_drop", "step"]

Array = Any
_HOLD = 1e-7  # [m]: a stuck foot's element that moved less than this in a step keeps its depth (float32 rounding)


class Mud3D(NamedTuple):
    """The feet and their mud in one world (a pytree: ``jax.vmap`` over worlds), made by :func:`add_mud`.

    Fields (``F`` feet, ``P`` patches, ``n`` elements per foot: every foot's element list padded to the
    longest with elements of zero area, which carry nothing):
    ``geoms``, ``bodies`` (F,) int32, each foot's geom and its body; ``centroids``, ``normals`` (F, n, 3)
    the elements in the geom's frame [m], [-]; ``areas`` (F, n) [m^2]; ``widths`` (F,) each foot's width
    ``H`` of Eq. (4) [m]; ``elements`` (:class:`mudforce.jax.Params`, fields (P, F)) each patch's mud on
    each foot's elements (unit area, width ``H``); ``lateral_stiffness`` (P, F) [Pa/m];
    ``surface_height`` (P,) [m], each patch's world ``z``; ``extents`` (P, 4) ``(xmin, xmax, ymin, ymax)``
    [m] (infinite for an unbounded patch).
    """

    geoms: Array
    bodies: Array
    centroids: Array
    normals: Array
    areas: Array
    widths: Array
    elements: mj.Params
    lateral_stiffness: Array
    surface_height: Array
    extents: Array


class MudState3D(NamedTuple):
    """The mud's state in one world, and what it did in the last step (a pytree: save it by keeping it).

    Fields (F feet): ``feet`` every foot's :class:`mudforce.jax.contact3d.State3D`; ``patch`` (F,) int32,
    the patch each foot is in (-1 none); ``position`` (F, 3) its geom's centre at the last commit [m];
    ``direction`` (F, 2) its last horizontal direction of motion ``u`` [-]; ``rows`` (F, 3) the forces of
    its vertical, ``u`` and across rows in the last step [N]; ``stuck`` (F, 3) bool, which rows held;
    ``force`` (F, 3) the mud's force on each foot in the last step, world frame [N] (rows and explicit
    drag: while stuck, the load it carries); ``band`` (F, 2) the vertical band ``(F_up, F_down)`` [N] and
    ``capacity`` (F, 2) the sideways holds along ``u`` and across it [N] of the last step;
    ``law_force``, ``law_torque`` (F, 3) the 3-D law's own wrench on the committed pose [N], [N m]
    (about the geom's centre); ``depth`` (F,) the lowest element's depth below its patch's surface [m]
    (NaN off every patch).
    """

    feet: mj3.State3D
    patch: Array
    position: Array
    direction: Array
    rows: Array
    stuck: Array
    force: Array
    band: Array
    capacity: Array
    law_force: Array
    law_torque: Array
    depth: Array


def _element_params(params: Any, widths: np.ndarray, dtype: Any) -> mj.Params:
    """A mud's :class:`mudforce.jax.Params` on each foot's elements (unit area, the foot's width): fields (F,).

    One mud for every foot: its fields scalars (the area and width aside, which are ignored). A field of one value
    per foot was taken too, so that a batch of as many worlds' muds as there are feet, given to :func:`set_mud`
    outside ``vmap``, became one world's feet's muds without a word (three worlds' water contents on three feet);
    per-world mud is :func:`set_mud` under ``vmap``, as the 1-D :func:`mudforce.engines.mjx.add_mud`'s.
    """
    if isinstance(params, MudParameters):
        params = mj.make_params(params, dtype=dtype)
    if not isinstance(params, mj.Params):
        raise InputError(f"the mud must be MudParameters or a mudforce.jax.Params, got {type(params).__name__}")
    n = len(widths)
    for name, f in zip(params._fields, params, strict=True):  # (static shapes: checked under jit and vmap alike)
        if name not in ("area", "width") and jnp.shape(f) != ():  # was JAX's broadcasting ValueError
            raise InputError(f"a mud's fields must be scalars (one mud for every foot), got {name} of shape "
                             f"{jnp.shape(f)}; vmap set_mud over worlds for a mud per world")
    ignored = jnp.ones((n,), dtype=dtype)  # the area and width given are the elements' (an area per world was
    # broadcast first, and raised JAX's ValueError)
    fields = [ignored if name in ("area", "width") else jnp.broadcast_to(jnp.asarray(f, dtype=dtype), (n,))
              for name, f in zip(params._fields, params, strict=True)]
    return mj.Params._make(fields)._replace(area=ignored, width=jnp.asarray(widths, dtype=dtype))


def _warn_floor(model: Any, gids: list[int]) -> None:
    """Warn once when a foot geom can collide with a geom that is not a foot (a rigid floor under the mud)."""
    mujoco = require("mujoco", "mjx", "mud in MJX")
    feet = set(gids)
    for g in gids:
        body = int(model.geom_bodyid[g])
        parent = int(model.body_parentid[body])
        for o in range(int(model.ngeom)):
            ob = int(model.geom_bodyid[o])
            if o in feet or ob in (body, parent) or int(model.body_parentid[ob]) == body:
                continue
            if (int(model.geom_contype[g]) & int(model.geom_conaffinity[o])) or \
                    (int(model.geom_contype[o]) & int(model.geom_conaffinity[g])):
                name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, o) or f"geom {o}"
                foot = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or f"geom {g}"
                warnings.warn(f"foot {foot!r} can collide with {name!r}: where that geom lies under the mud, a rigid "
                              "contact carries part of the foot's load; turn its collisions off there "
                              "(contype/conaffinity) (docs/engines3d.md)", RuntimeWarning, stacklevel=3)
                return


def add_mud(model: Any, feet: Sequence[str], patches: MudPatch | Sequence[MudPatch],
            shapes: Shape | Sequence[Shape] | None = None, *, resolution: float | None = None,
            dtype: Any = None) -> Mud3D:
    """Mud in 3-D under the named foot geoms of a compiled ``mujoco.MjModel``: the :class:`Mud3D` :func:`step` takes.

    Parameters
    ----------
    model : mujoco.MjModel
        The model (before ``mjx.put_model``); nothing is added to it.
    feet : sequence of str
        Foot geoms, or bodies with exactly one geom, of type sphere, capsule, cylinder, box, ellipsoid or mesh.
    patches : MudPatch or sequence of MudPatch
        The mud (:class:`mudforce.engines.mujoco.MudPatch`: ``params``, ``surface_height`` [m],
        ``extent`` [m]); a foot is in the first patch whose extent holds its geom's centre, and feels
        nothing outside every patch. Per-world mud: :func:`set_mud`.
    shapes : Shape or sequence of Shape, optional
        Each foot's surface in its geom's frame [m]; by default its geom's
        (:func:`mudforce.model.shapes.from_mujoco_geom` at ``resolution`` [m]).
    resolution : float, optional
        Element size of the shapes taken from the geoms [m].
    dtype : dtype, optional
        Float dtype (JAX's default float by default; MJX runs in float32 unless x64 is enabled).

    Raises
    ------
    InputError
        One line, for a foot that names no geom (or a body with several), a geom with no surface (a plane,
        a height field), a patch that misses every foot, or shapes that do not match the feet.
    """
    mujoco = require("mujoco", "mjx", "mud in MJX")
    if not isinstance(model, mujoco.MjModel):
        raise InputError(f"model must be a compiled mujoco.MjModel (before mjx.put_model), got "
                         f"{type(model).__name__}")
    names = name_list(feet)  # the adapters' rule and words: names (str), distinct
    plist = _patch_list(patches)
    heights = [bounded_depth(p.surface_height, "surface_height") for p in plist]  # MudAdapter3D's bound and words
    gids = [foot_geom(model, name) for name in names]
    if shapes is None:
        slist = [from_mujoco_geom(model, g, resolution=resolution) for g in gids]
    elif isinstance(shapes, Shape):
        slist = [shapes] * len(names)
    elif isinstance(shapes, Sequence) and all(isinstance(s, Shape) for s in shapes):
        slist = list(shapes)
    else:
        raise InputError(f"shapes must be a Shape, a sequence of Shape or None, got {type(shapes).__name__}")
    if len(slist) != len(names):
        raise InputError(f"got {len(slist)} shapes for {len(names)} feet")
    if any(s.width is None for s in slist):
        raise InputError("a foot's shape has no width H for Eq. (4); build it with a mudforce.model.shapes "
                         "constructor, which sets it")
    for s in slist:  # the width H of Eq. (4), checked as make_params3d checks it
        Foot(area=1.0, width=float(s.width), shape="element")  # type: ignore[arg-type]
    _warn_floor(model, gids)
    ftype = mj._float_dtype(dtype)  # float32 or float64 (int32 held the mud as garbage, "foo" a TypeError)
    n = max(s.n for s in slist)

    def padded(values: np.ndarray, fill_row: np.ndarray) -> np.ndarray:
        out = np.repeat(fill_row[None], n, axis=0)
        out[: len(values)] = values
        return out

    centroids = np.stack([padded(s.centroids, s.centroids[0]) for s in slist])
    normals = np.stack([padded(s.normals, s.normals[0]) for s in slist])
    areas = np.stack([padded(s.areas, np.zeros(())) for s in slist])
    widths = np.array([float(s.width) for s in slist if s.width is not None])
    per_patch = [_element_params(p.params, widths, ftype) for p in plist]
    elements = mj.Params(*(jnp.stack(f) for f in zip(*per_patch, strict=True)))
    big = math.inf
    extents = np.array([p.extent if p.extent is not None else (-big, big, -big, big) for p in plist])
    # a finite extent past float32's range holds every position, as the infinity it rounds to does: made that
    # infinity here, without numpy's overflow warning (1e300 in float32)
    extents = np.where(np.abs(extents) > float(np.finfo(ftype).max), np.copysign(big, extents), extents)
    return Mud3D(
        geoms=jnp.asarray(gids, dtype=jnp.int32),
        bodies=jnp.asarray([int(model.geom_bodyid[g]) for g in gids], dtype=jnp.int32),
        centroids=jnp.asarray(centroids, dtype=ftype), normals=jnp.asarray(normals, dtype=ftype),
        areas=jnp.asarray(areas, dtype=ftype), widths=jnp.asarray(widths, dtype=ftype), elements=elements,
        lateral_stiffness=jnp.stack([jnp.broadcast_to(jnp.asarray(p.params.k_m_w, dtype=ftype), (len(gids),))
                                     for p in plist]),
        surface_height=jnp.asarray(heights, dtype=ftype),
        extents=jnp.asarray(extents, dtype=ftype))


def set_mud(mud: Mud3D, params: Any, patch: int = 0) -> Mud3D:
    """``mud`` with patch ``patch``'s mud replaced by ``params``: per-world mud under ``jit`` and ``vmap``.

    ``params``: :class:`mudforce.MudParameters`, or a :class:`mudforce.jax.Params` with scalar fields
    (traced allowed), such as ``mudforce.jax.params_from_water_content(w)`` (its ``area`` and ``width``
    are ignored: the elements' are the feet's). The lateral stiffness becomes the mud's ``k_m_w``. A field that is
    not a scalar (a batch of worlds' muds outside ``vmap``, a mud per foot) is refused in one line.
    """
    if not isinstance(mud, Mud3D):
        raise InputError(f"mud must be a Mud3D (add_mud), got {type(mud).__name__}")
    count = mud.surface_height.shape[-1]
    if not is_integer(patch) or not 0 <= patch < count:  # not a bool: True was patch 1
        raise InputError(f"patch must be an index 0 to {count - 1}, got {shown(patch)}")
    patch = int(patch)
    dtype = mud.areas.dtype
    new = _element_params(params, mud.widths, dtype)
    elements = mj.Params(*(old.at[patch].set(f) for old, f in zip(mud.elements, new, strict=True)))
    return mud._replace(elements=elements, lateral_stiffness=mud.lateral_stiffness.at[patch].set(new.k_w))


def init(mud: Mud3D) -> MudState3D:
    """The mud's state at the start of an episode (no foot started: the first step sets each foot's pose)."""
    if not isinstance(mud, Mud3D):
        raise InputError(f"mud must be a Mud3D (add_mud), got {type(mud).__name__}")
    f, n = mud.areas.shape[-2], mud.areas.shape[-1]
    dtype = mud.areas.dtype
    one = mj.init(n, dtype)
    feet = mj3.State3D(mj.State(*(jnp.broadcast_to(x, (f, n)).copy() for x in one)),
                       jnp.zeros((f, n, 2), dtype=dtype), jnp.zeros((f, n, 3), dtype=dtype),
                       jnp.zeros((f,), dtype=bool))
    zeros3 = jnp.zeros((f, 3), dtype=dtype)
    return MudState3D(feet, jnp.full((f,), -1, dtype=jnp.int32), zeros3,
                      jnp.tile(jnp.asarray([1.0, 0.0], dtype=dtype), (f, 1)), zeros3,
                      jnp.zeros((f, 3), dtype=bool), zeros3, jnp.zeros((f, 2), dtype=dtype),
                      jnp.zeros((f, 2), dtype=dtype), zeros3, zeros3, jnp.full((f,), jnp.nan, dtype=dtype))


def _quat_mul(a: Array, b: Array) -> Array:
    """The product ``a b`` of quaternions ``(w, x, y, z)`` [-] (rows)."""
    aw, ax, ay, az = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    bw, bx, by, bz = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return jnp.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                      aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=-1)


class _Foot(NamedTuple):
    """One foot's share of a step (:func:`_prepare`): its band [N], holds [N], drags [N] (``drag_h``: the horizontal
    drag and the mid-band force's sideways part, applied explicitly) and depth [m]."""

    f_up: Array
    f_down: Array
    drag: Array
    hold_u: Array
    hold_v: Array
    drag_h: Array
    depth: Array


def _prepare(state: mj3.State3D, params: mj3.Params3D, position: Array, quaternion: Array, u: Array,
             velocity: Array, dt: Array, weight: Array, inside: Array) -> _Foot:
    """One foot's band, holds and drags for the coming step, from its committed state and pose.

    The sums over the elements of :mod:`mudforce.model.law3d`'s functions, as the CPU adapter's
    (:mod:`mudforce.engines.mujoco._step3d`) ``prepare``: ``u`` (2,) the last horizontal direction of motion,
    ``velocity`` (3,) the geom centre's over the last step [m/s]; ``inside`` whether the foot is in a patch.
    """
    e = params.elements
    up, down, drag = mj.branch_forces(state.elements, e, dt, weight)  # each element's band and drag [Pa]
    r = law3d.rotation(quaternion[0], quaternion[1], quaternion[2], quaternion[3])
    cb, nb = params.centroids, params.normals
    _, _, oz = law3d.rotate(r, cb[:, 0], cb[:, 1], cb[:, 2])
    nx, ny, nz = law3d.rotate(r, nb[:, 0], nb[:, 1], nb[:, 2])
    depth = law3d.element_depth(params.surface_height, position[2], oz)
    area = params.areas
    w = area * law3d.vertical_weight(nz)
    spring = law3d.spring_stress(depth, e.alpha, e.beta, e.width)
    ux, uy = u[0], u[1]
    wet = depth > 0.0

    def hold(dx: Array, dy: Array) -> Array:
        cap = law3d.lateral_capacity(e.sigma_y, law3d.shear_fraction(nx, ny, nz, dx, dy), spring,
                                     law3d.bearing_factor(nx, ny, nz, dx, dy))
        return jnp.sum(jnp.where(wet, area * cap, 0.0))

    gx, gy = law3d.horizontal_drag(e.lam * e.rho_m, 1.0, nx, ny, velocity[0], velocity[1])
    zero = jnp.zeros((), dtype=area.dtype)
    keep = inside  # off every patch: nothing

    def only(x: Array) -> Array:
        return jnp.where(keep, x, zero)

    f_up, f_down = jnp.sum(w * up), jnp.sum(w * down)
    # the mid-band force's sideways part (law3d.vertical_element_force), as the CPU adapter's: the elements' ends
    # turned by 3D-RFT's lean and summed, combined as the band's mid (an inverted band: the branch of the motion)
    lean = w * law3d.vertical_lean(nz)
    lx, ly = lean * nx, lean * ny
    inverted = f_down < f_up
    falling = velocity[2] <= 0.0
    ends = jnp.where(inverted, jnp.where(falling, down, up), 0.5 * up + 0.5 * down) + drag
    side_x, side_y = jnp.sum(lx * ends), jnp.sum(ly * ends)
    return _Foot(only(f_up), only(f_down), only(jnp.sum(w * drag)), only(hold(ux, uy)),
                 only(hold(-uy, ux)), jnp.stack([only(jnp.sum(jnp.where(wet, area * gx, 0.0)) + side_x),
                                                 only(jnp.sum(jnp.where(wet, area * gy, 0.0)) + side_y), zero]),
                 jnp.where(keep, jnp.max(depth), jnp.nan))


def _step_inputs(m: Any, d: Any, state: Any, mud: Any) -> None:
    """Refuse, when tracing, what :func:`step` cannot take, in one line, as :func:`mudforce.engines.mjx.step` does:
    a state or mud of another type (None: AttributeError), a state of another mud's feet (JAX's broadcasting
    errors), MuJoCo's model or data for MJX's, and a mud of another model where its geoms are known (not traced)."""
    if not isinstance(state, MudState3D):
        raise InputError(f"state must be a MudState3D (init(mud)), got {type(state).__name__}")
    if not isinstance(mud, Mud3D):
        raise InputError(f"mud must be a Mud3D (add_mud), got {type(mud).__name__}")
    _check_step_model(m, d, state.position.shape[-2:-1], mud.geoms, mud.bodies, "mud", "geom", "init(mud)")


def step(m: Any, d: Any, state: MudState3D, mud: Mud3D, weight: float = 0.0) -> tuple[Any, MudState3D, Array]:
    """One physics step of an MJX model with the 3-D mud on every foot; replaces ``mjx.step(m, d)``.

    Parameters
    ----------
    m, d : mjx.Model, mjx.Data
        The model and its data (Euler or implicitfast integrator).
    state : MudState3D
        The mud's state (:func:`init`).
    mud : Mud3D
        The feet and their mud (:func:`add_mud`, :func:`set_mud`).
    weight : float
        Where in the step the elements' bands are taken [-] (:func:`mudforce.jax.branch_forces`), in [0, 1]
        unless traced: 0 (default) at its start, as :func:`mudforce.engines.mjx.step`.

    Returns
    -------
    d : mjx.Data
        The data after the step.
    state : MudState3D
        The mud's state after the step (its ``force``: what the mud applied in the step).
    forces : array, shape (feet, 3)
        The mud's force on each foot during the step [N], world frame, z up.
    """
    # a number in [0, 1] unless traced, as mudforce.engines.mjx.step's: 2.0 and -5.0 extrapolated the band, NaN gave
    # no force at all (the foot fell through the mud), True and "0.5" were taken
    weight = _weight(weight)
    _step_inputs(m, d, state, mud)
    mjx = _mjx()
    if m.opt.integrator == mjx.IntegratorType.RK4:
        raise InputError("mudforce.engines.mjx3d supports the Euler and implicitfast integrators, not RK4")
    dt = m.opt.timestep
    d = mjx.forward(m, d)
    dtype = state.position.dtype
    nfeet = mud.geoms.shape[-1]
    feet_axis = jnp.arange(nfeet)
    pos = d.geom_xpos[mud.geoms].astype(dtype)
    quat = _quat_mul(d.xquat[mud.bodies], m.geom_quat[mud.geoms]).astype(dtype)
    quat = quat / jnp.linalg.norm(quat, axis=-1, keepdims=True)
    # which patch each foot is in: the first whose extent holds its geom's centre
    ext = mud.extents
    x, y = pos[:, 0], pos[:, 1]
    within = (ext[:, 0:1] <= x) & (x <= ext[:, 1:2]) & (ext[:, 2:3] <= y) & (y <= ext[:, 3:4])  # (P, F)
    patch = jnp.where(within.any(axis=0), jnp.argmax(within, axis=0), -1).astype(jnp.int32)
    inside = patch >= 0
    same = patch == state.patch
    k = jnp.maximum(patch, 0)
    stiffness = mud.lateral_stiffness[k, feet_axis]
    params = mj3.Params3D(mj.Params(*(f[k, feet_axis] for f in mud.elements)), mud.centroids, mud.normals,
                          mud.areas, mud.surface_height[k], stiffness, jnp.ones_like(stiffness))  # (bearing: 1)
    # commit the poses: a foot entering a patch (or leaving it) starts afresh; a stuck foot keeps its depths
    feet = mj3.reset3d(state.feet, ~same)
    hold = jnp.where(same & state.stuck[:, 0], _HOLD, 0.0).astype(dtype)
    dts = jnp.asarray(dt, dtype=dtype)
    feet, law_force, law_torque = jax.vmap(mj3.step3d, in_axes=(0, 0, 0, 0, None, 0))(feet, params, pos, quat,
                                                                                        dts, hold)
    feet = mj3.reset3d(feet, ~inside)
    law_force = jnp.where(inside[:, None], law_force, 0.0)
    law_torque = jnp.where(inside[:, None], law_torque, 0.0)
    velocity = jnp.where((same & inside)[:, None], (pos - state.position) / dts, 0.0)
    speed2 = velocity[:, 0] ** 2 + velocity[:, 1] ** 2
    moving = speed2 > REST_SPEED ** 2
    speed = jnp.sqrt(jnp.where(moving, speed2, 1.0))
    u = jnp.where(moving[:, None], velocity[:, :2] / speed[:, None], state.direction)
    foot = jax.vmap(_prepare, in_axes=(0, 0, 0, 0, 0, 0, None, None, 0))(
        feet, params, pos, quat, u, velocity, dts, jnp.asarray(weight, dtype=dtype), inside)
    # the rows: world z, u and across u
    zeros = jnp.zeros((nfeet,), dtype=dtype)
    ones = jnp.ones((nfeet,), dtype=dtype)
    dirs = jnp.stack([jnp.stack([zeros, zeros, ones], axis=-1),
                      jnp.stack([u[:, 0], u[:, 1], zeros], axis=-1),
                      jnp.stack([-u[:, 1], u[:, 0], zeros], axis=-1)], axis=1)  # (F, 3 rows, 3)

    def point_jacobian(point: Array, body: Array) -> Array:
        jacp, _ = mjx.jac(m, d, point, body)
        return jacp  # (nv, 3)

    # the rows act at each foot's geom centre: the mud's force passes through it (the law's couple is not applied)
    jacp = jax.vmap(point_jacobian)(pos.astype(d.qpos.dtype), mud.bodies)  # (F, nv, 3)
    jac = jnp.einsum("frk,fvk->frv", dirs.astype(jacp.dtype), jacp).reshape(3 * nfeet, -1)  # (3F, nv): z, u, across
    explicit = jnp.einsum("fvk,fk->v", jacp, foot.drag_h.astype(jacp.dtype))  # the horizontal drag, generalised
    qacc, minv_jt, v_free = _free_motion(m, d, dt, d.qfrc_smooth + d.qfrc_constraint + explicit, jac)
    lo = jnp.stack([foot.f_up, -foot.hold_u, -foot.hold_v], axis=-1).reshape(-1)
    hi = jnp.stack([foot.f_down, foot.hold_u, foot.hold_v], axis=-1).reshape(-1)
    drag = jnp.stack([foot.drag, zeros, zeros], axis=-1).reshape(-1)
    down = jnp.stack([-velocity[:, 2], zeros, zeros], axis=-1).reshape(-1)  # positive down: an inverted band's branch
    previous = jnp.where(same[:, None], state.rows, 0.0).reshape(-1)
    rows, stuck = _joint_rows((jac @ minv_jt).astype(dtype), (-v_free / dt).astype(dtype), lo, hi, drag, down,
                              previous)
    f = rows.astype(d.qacc.dtype)
    d = _integrate(m, d, d.qfrc_smooth + jac.T @ f + explicit, qacc + minv_jt @ f)
    rows = rows.reshape(nfeet, 3)
    force = jnp.einsum("fr,frk->fk", rows, dirs) + foot.drag_h
    new = MudState3D(feet, patch, pos, u, rows, stuck.reshape(nfeet, 3), force,
                     jnp.stack([foot.f_up, foot.f_down], axis=-1), jnp.stack([foot.hold_u, foot.hold_v], axis=-1),
                     law_force, law_torque, foot.depth)
    return d, new, force


def simulate_drop(mass: float, params: Any, shape: str, size: Sequence[float], *, duration: float = 2.0,
                  height: float = 0.0, tilt: float = 0.0, vx: float = 0.0, dt: float = 1e-3,
                  resolution: float | None = None, compiler_options: dict[str, Any] | None = None) -> Drop3D:
    """Drop a free foot geom into mud in MJX with :func:`step` (one jitted scan): a
    :class:`mudforce.engines.mujoco.adapter3d.Drop3D`, as :func:`mudforce.engines.mujoco.simulate_drop_3d` gives.

    Parameters
    ----------
    mass : float
        [kg], at least what the step resolves (as :func:`mudforce.engines.mujoco.simulate_drop_3d`'s:
        :func:`mudforce.engines.mujoco.adapter3d.check_drop_mass`), refused before the scan is compiled.
    params : MudParameters
        The mud.
    shape : str
        ``sphere``, ``capsule``, ``cylinder`` or ``box`` (MuJoCo's frame: a capsule's and cylinder's axis is z).
    size : sequence of float
        Full dimensions [m]: a sphere's diameter; a capsule's or cylinder's diameter and length (a capsule's
        between its caps' centres); a box's length, width and height.
    duration : float
        Simulated time [s], at least ``dt`` (at most 1e8 steps).
    height : float
        Release height of the lowest point above the surface [m], >= 0.
    tilt : float
        Rotation about the world x axis [rad].
    vx : float
        Initial horizontal velocity along x [m/s], within +-10
        (:data:`mudforce.engines.mujoco.adapter3d.MAX_DROP_VX`).
    dt : float
        Time step [s], > 0 (1 ms by default, as the CPU adapter's drop; docs/engines3d.md, "The time step").
    resolution : float, optional
        Element size of the foot's surface [m].
    compiler_options : dict, optional
        XLA's options for the scan's compilation (``jax.jit(...).lower(...).compile(compiler_options)``).

    Returns
    -------
    Drop3D
        One row a step: the pose MJX's data holds after the step (its start, as the CPU adapter's), the
        velocity after it, and the mud's force in it (float32 unless JAX's x64 is enabled).
    """
    mjx = _mjx()
    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    duration, vx, steps = check_drop_motion(duration, vx, dt)
    if compiler_options is not None and not (isinstance(compiler_options, Mapping)
                                             and all(isinstance(k, str) for k in compiler_options)):
        # (was JAX's AttributeError ('int' object has no attribute 'items') after the scan was traced)
        raise InputError(f"compiler_options must be a dict of XLA's compile options (name: value) or None, got "
                         f"{shown(compiler_options)}")
    spec = _drop_spec(mass, shape, size, height=height, tilt=tilt, dt=dt)
    model = compile_drop(spec)
    surface = from_mujoco_geom(model, 0, resolution=resolution)  # add_mud's own (shapes=None)
    check_drop_mass(mass, params, surface, float(tilt), float(dt))  # before the scan's compilation
    mud = add_mud(model, ["foot"], MudPatch(params), surface)
    m = mjx.put_model(model)
    d0 = mjx.make_data(m)
    d0 = d0.replace(qvel=d0.qvel.at[0].set(vx))

    def body(carry: tuple[Any, MudState3D], _: Any) -> tuple[tuple[Any, MudState3D], tuple[Array, ...]]:
        d, s = carry
        d, s, force = step(m, d, s, mud)
        return (d, s), (d.geom_xpos[0], d.geom_xmat[0], d.qvel[:3], force[0])

    def run(d: Any) -> tuple[Array, ...]:
        _, out = jax.lax.scan(body, (d, init(mud)), None, length=steps)
        return tuple(out)

    compiled = jax.jit(run).lower(d0).compile(compiler_options)
    pos, mat, vel, force = (np.asarray(x, dtype=np.float64) for x in compiled(d0))
    mujoco = require("mujoco", "mjx", "mud in MJX")
    data = mujoco.MjData(model)
    data.qvel[0] = vx
    mujoco.mj_forward(model, data)
    position = np.vstack([np.asarray(data.geom_xpos[0])[None], pos])
    rots = np.concatenate([np.asarray(data.geom_xmat[0]).reshape(1, 3, 3), mat.reshape(-1, 3, 3)])
    velocity = np.vstack([np.asarray(data.qvel[:3])[None], vel])
    forces = np.vstack([np.zeros((1, 3)), force])
    return _drop_result(shape, model.geom_size[0], float(dt), position, velocity, forces, rots, mass)
