"""Mud under the feet of MJX models, for a batch of worlds on a GPU (``pip install 'mudforce[mjx]'``).

Usage (one world; ``jax.vmap`` it over worlds, each with its own mud)::

    import mujoco
    from mujoco import mjx
    import mudforce.engines.mjx as mud

    model = mujoco.MjModel.from_xml_path("hopper.xml")        # a site at each foot's sole
    m = mjx.put_model(model)
    patch = mud.add_mud(model, ["foot_sole"], MudParameters.from_water_content(0.25))
    d = mjx.make_data(m)
    state = mud.init(patch)
    for _ in range(1000):                                       # or jax.lax.scan
        d, state, forces = mud.step(m, d, state, patch)         # instead of mjx.step(m, d)

How the force is applied, and why
---------------------------------
The mud force is set-valued at rest (:mod:`mudforce.engines.dynamics`): a foot at
rest carries any load between the withdrawal-branch force ``F_up`` and the
intrusion-branch force ``F_down``. Each call of :func:`step` is one physics
step (a substep of an environment's control step) with an implicit
(Moreau-Jean) treatment of that band, like dry friction:

1. ``mjx.forward`` computes the motion without the mud force; the foot's
   depth at the start of the step is committed to its contact state
   (:func:`mudforce.jax.step`, the exact velocity rule);
2. the band for the coming step (:func:`mudforce.jax.branch_forces`, by
   default with ``weight = 0``: the band at the step's start, just
   committed; see :func:`step`) and the force ``F_stop`` that would bring the sole to
   rest by the step's end, from the sole's vertical Jacobian ``j`` and the
   joint-space inertia ``M``: ``F_stop = -v_free / (dt j M^-1 j^T)``;
3. the force is ``F_stop`` clamped to the band plus the drag
   (:func:`mudforce.jax.stick_force`), applied at the sole: ``j^T F`` is
   added to ``qfrc_smooth`` and ``M^-1 j^T F`` to ``qacc``, and the
   model's integrator (Euler or implicitfast) advances the state. With
   Euler, ``M`` includes the joint damping that Euler integrates
   implicitly (``M + dt D``), so a stuck sole ends the step at rest; with
   implicitfast only that damping part of its implicit terms is included.

Inside the band the sole ends the step at rest (to rounding), with no
chatter and no ratcheting; the next commit then sees exactly no motion
(a stuck foot's committed depth is held), so the Maxwell element relaxes
on the intrusion branch, as the model says. Outside the band the force is
the branch's. The force is applied on every physics step, so an
environment that takes several substeps per control step gets mud on
each. The feet of one world are solved together: with ``J`` the feet's
vertical Jacobians, ``J M^-1 J^T f = -v_free / dt`` for the stuck feet,
each force inside its band, the others at the band's edge they are pushed
to (a box-constrained problem, as for dry friction; projected Gauss-Seidel,
each foot's rule :func:`mudforce.jax.stick_force` given the others'
forces, then the stuck feet's forces solved exactly). Redundant feet (four
on one rigid body) share the load by the least norm. Taking each foot
alone, as 0.2's first MJX step did, let a 100 kg box on four soles sink
6 mm/s at 5 ms while every foot reported itself stuck. Contact
constraints computed by ``mjx.forward`` do not respond to the mud force
within the step (an error first order in ``dt``, as the band's own lag is).

Patches are horizontal and unbounded: each foot has a mud surface at ``surface_height``
(world ``z`` [m]); a foot above it is FREE. The RK4 integrator is not
supported (it calls the forward dynamics four times per step).
"""

from __future__ import annotations

import contextlib
import io
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

import mudforce.jax as mj
from mudforce._plumbing.deprecation import module_getattr as _deprecated_getattr
from mudforce._plumbing.deprecation import renamed_keywords, warn_renamed
from mudforce._plumbing.optional import require
from mudforce.engines._checks import check_foot, check_mass, check_params, drop_numbers, drop_thickness, name_list
from mudforce.errors import InputError, finite_number, number_within, real_array
from mudforce.model.bounds import bounded_depth, max_samples
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

if TYPE_CHECKING:
    from mudforce.engines.dynamics.result import FootResult

__all__ = ["MudPatch", "MudState", "add_mud", "drop_model", "init", "simulate_drop", "step"]

# renamed in 0.2 (docs/api.md): the names the MuJoCo adapter uses for the same concepts
__getattr__ = _deprecated_getattr(__name__, {
    "Patch": ("mudforce.engines.mjx.MudPatch", "mudforce.engines.mjx:MudPatch"),
    "Contact": ("mudforce.engines.mjx.MudState", "mudforce.engines.mjx:MudState"),
    "make_patch": ("mudforce.engines.mjx.add_mud (feet= for sites=, params= for mud=)",
                   "mudforce.engines.mjx:_make_patch"),
})

Array = Any
_HOLD = 1e-7  # [m]: a stuck sole that moved less than this in a step is committed as not having moved


def _mjx() -> Any:
    """``mujoco.mjx``, imported without the lines it prints about optional backends it did not find."""
    with contextlib.redirect_stdout(io.StringIO()):  # "Failed to import warp: ..." on stdout
        return require("mujoco.mjx", "mjx", "mud in MJX")


class MudPatch(NamedTuple):
    """Where the mud acts and what it is, for one world; a pytree (``jax.vmap`` over worlds).

    The MJX form of :class:`mudforce.engines.mujoco.MudPatch`, made by :func:`add_mud`.

    Fields: ``sites`` (int32, shape ``(feet,)``) the MuJoCo site at each
    sole; ``bodies`` (int32) the body each site is on; ``surface_height`` [m]
    the mud surface's world ``z`` under each foot (``.height`` is its
    deprecated name, kept for one release); ``params`` the
    :class:`mudforce.jax.Params` of each foot (fields of shape ``(feet,)``,
    or ``(worlds, feet)`` for a batch of worlds with their own mud).
    """

    sites: Array
    bodies: Array
    surface_height: Array
    params: mj.Params

    @property
    def height(self) -> Array:
        """Deprecated: :attr:`surface_height` [m]."""
        warn_renamed("mudforce.engines.mjx.MudPatch.height", "MudPatch.surface_height")
        return self.surface_height


class MudState(NamedTuple):
    """The mud's state in one world: every foot's :class:`mudforce.jax.State`, whether stuck, its last force [N].

    The MJX form of :attr:`mudforce.engines.mujoco.MudAdapter.state` (a pytree: save it by keeping it).
    """

    state: mj.State
    stuck: Array
    force: Array


@renamed_keywords(height="surface_height")
def add_mud(model: Any, feet: Sequence[str], params: MudParameters | Sequence[MudParameters],
            foot: Foot | Sequence[Foot] | None = None, *, surface_height: float | Sequence[float] = 0.0,
            dtype: Any = None) -> MudPatch:
    """Mud under the named feet of a compiled ``mujoco.MjModel``: the :class:`MudPatch` that :func:`step` takes.

    The MJX counterpart of :func:`mudforce.engines.mujoco.add_mud` (which prepares a
    spec for :class:`mudforce.engines.mujoco.MudAdapter`); MJX needs nothing added to
    the model, only a site at each sole.

    Parameters
    ----------
    model : mujoco.MjModel
        The model (before ``mjx.put_model``).
    feet : sequence of str
        Names of the sites at the feet's soles (the contact points).
    params : MudParameters or sequence of MudParameters
        One mud for every foot, or one per foot. For per-world mud, make
        one patch per world and stack them (:func:`jax.tree_util.tree_map`
        with ``jnp.stack``), or replace ``params`` with batched arrays.
    foot : Foot or sequence of Foot, optional
        Sole geometry (area [m^2], width [m]); the paper's 51 x 38 mm cuboid by default.
    surface_height : float or sequence of float
        World ``z`` of the mud surface under each foot [m] (``height=`` is its deprecated name).
    dtype : dtype, optional
        Float dtype (JAX's default float by default; MJX runs in float32 unless x64 is enabled).
    """
    mujoco = require("mujoco", "mjx", "mud in MJX")
    if not isinstance(model, mujoco.MjModel):
        raise InputError(f"model must be a compiled mujoco.MjModel, got {type(model).__name__}")
    names = name_list(feet)  # MuJoCo's add_mud's rule: distinct names (one site twice was two feet there)
    ids = []
    for name in names:
        sid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name)
        if sid < 0:
            # MuJoCo's add_mud takes foot geoms and bodies: say so where the name is one (it said only 'no site')
            kind = next((k for k, obj in (("a body", mujoco.mjtObj.mjOBJ_BODY), ("a geom", mujoco.mjtObj.mjOBJ_GEOM))
                         if mujoco.mj_name2id(model, obj, name) >= 0), None)
            what = f"{name!r} is {kind}, not a site" if kind else f"no site named {name!r} in the model"
            raise InputError(f"{what}; MJX's add_mud takes sites at the soles (the contact points): add a site at "
                             "each sole")
        ids.append(sid)
    n = len(ids)
    # one height or one per foot, real numbers (np.asarray took True as 1 m and parsed "0.01"), each within the
    # steppers' depth bound as MuJoCo's MudPatch's (1e12 m was taken; 1e39 m became inf in float32; a height per
    # foot of another length raised numpy's ValueError)
    given = real_array(surface_height, "surface_height", "m")
    if given.shape not in ((), (n,)):
        raise InputError(f"surface_height must be one height [m] or one per foot ({n}), got shape {given.shape}")
    heights = np.broadcast_to(given, (n,))
    for height in heights.tolist():
        bounded_depth(height, "surface_height")
    dt_ = mj._float_dtype(dtype)
    if foot is not None:
        mj._feet(foot)  # a Foot or Foots (5 was read as make_params' deprecated order: 5 feet)
    per_foot = not isinstance(params, MudParameters) or (foot is not None and not isinstance(foot, Foot))
    jparams = mj.make_params(params, n=n if not per_foot else None, foot=foot, dtype=dt_)
    count = jparams.k_i.shape[0] if jparams.k_i.ndim else 1
    if count not in (1, n):  # was JAX's broadcasting ValueError
        raise InputError(f"got {count} per-foot entries (mud parameter sets or feet) for {n} sites; give one or "
                         "one per site")
    jparams = mj.Params(*(jnp.broadcast_to(f, (n,)) for f in jparams))
    return MudPatch(jnp.asarray(ids, dtype=jnp.int32), jnp.asarray(model.site_bodyid[ids], dtype=jnp.int32),
                    jnp.asarray(heights, dtype=dt_), jparams)


def _make_patch(model: Any, sites: Sequence[str], mud: MudParameters | Sequence[MudParameters],
                foot: Foot | Sequence[Foot] | None = None, *, height: float | Sequence[float] = 0.0,
                dtype: Any = None) -> MudPatch:
    """Deprecated: :func:`add_mud` (``sites`` is now ``feet``, ``mud`` is now ``params``)."""
    return add_mud(model, sites, mud, foot, surface_height=height, dtype=dtype)


def init(patch: MudPatch) -> MudState:
    """The mud's state at the start of an episode (no foot started: the first step sets each foot's sample)."""
    if not isinstance(patch, MudPatch):  # was an AttributeError
        raise InputError(f"patch must be a MudPatch (add_mud), got {type(patch).__name__}")
    n = patch.sites.shape[-1]
    dtype = patch.surface_height.dtype
    return MudState(mj.init(n, dtype), jnp.zeros((n,), dtype=bool), jnp.zeros((n,), dtype=dtype))


def _sole_kinematics(m: Any, d: Any, patch: MudPatch) -> tuple[Array, Array, Array]:
    """Depths [m] (positive down), vertical Jacobians (feet, nv) and upward sole velocities [m/s]."""
    mjx = _mjx()
    points = d.site_xpos[patch.sites]

    def jz(point: Array, body: Array) -> Array:
        jacp, _ = mjx.jac(m, d, point, body)
        return jacp[:, 2]

    jac = jax.vmap(jz)(points, patch.bodies)
    return patch.surface_height - points[:, 2], jac, jac @ d.qvel


def _free_motion(m: Any, d: Any, dt: float, qfrc: Array, jac: Array) -> tuple[Array, Array, Array]:
    """The step without mud: ``qacc`` from the generalised force ``qfrc``, ``M^-1 J^T`` of the rows ``jac``
    (rows, nv), and the rows' velocities at the step's end [m/s].

    ``M`` includes the joint damping that Euler integrates implicitly (``M + dt D``), so that a row held at
    rest by the mud ends the step at rest (the module's docstring). Shared by :func:`step` and
    :func:`mudforce.engines.mjx3d.step`.
    """
    mjx = _mjx()
    mass = mjx.full_m(m, d)
    if not m.opt.disableflags & mjx.DisableBit.EULERDAMP:
        mass = mass + jnp.diag(dt * m.dof_damping)
    qacc = jnp.linalg.solve(mass, qfrc)
    minv_jt = jnp.linalg.solve(mass, jac.T)  # (nv, rows)
    return qacc, minv_jt, jac @ (d.qvel + dt * qacc)


def _integrate(m: Any, d: Any, qfrc_smooth: Array, qacc: Array) -> Any:
    """``d`` with the mud's generalised force in ``qfrc_smooth`` and its ``qacc``, advanced by the model's
    integrator (Euler or implicitfast). Shared by :func:`step` and :func:`mudforce.engines.mjx3d.step`."""
    mjx = _mjx()
    d = d.replace(qfrc_smooth=qfrc_smooth, qacc=qacc)
    if m.opt.integrator == mjx.IntegratorType.EULER:
        return mjx.euler(m, d)
    return mjx.implicit(m, d)


_SWEEPS = 24  # projected Gauss-Seidel sweeps over the feet before the exact solve on the stuck set


def _joint_forces(delassus: Array, target: Array, f_up: Array, f_down: Array, drag: Array, feet: mj.State,
                  previous: Array) -> tuple[Array, Array]:
    """Every foot's vertical mud force [N] for one step, the feet of the world solved together; and which are stuck.

    :func:`_joint_rows` with one row per foot (its vertical band, drag and velocity); an unstarted foot
    gets 0 (its band is ``(0, 0)``, its drag 0).
    """
    unstarted = feet.mode == mj.UNSTARTED
    return _joint_rows(delassus, target, f_up, f_down, drag, feet.velocity,
                       jnp.where(unstarted, 0.0, previous).astype(delassus.dtype))


def _joint_rows(delassus: Array, target: Array, lo: Array, hi: Array, drag: Array, velocity: Array,
                previous: Array) -> tuple[Array, Array]:
    """The force [N] of every row of a world's mud, solved together, and which rows are stuck.

    A row is a direction in which the mud holds a foot: the vertical row of a foot (the band
    ``[lo, hi] = [F_up, F_down]``, its ``drag``, the foot's ``velocity`` [m/s] positive down, which picks the
    branch of an inverted band) or, in 3-D (:mod:`mudforce.engines.mjx3d`), a sideways row (the band
    ``[-hold, hold]``, drag 0). ``delassus`` (rows, rows) is ``J M^-1 J^T`` [1/kg], the velocity each unit
    force gives every row in a step of ``dt`` per ``dt``; ``target`` = ``-v_free / dt`` [m/s^2], so that
    ``delassus @ f = target`` brings every row to rest by the step's end. The result is the box-constrained
    solution (a mixed linear complementarity problem, as for dry friction): a stuck row's force is inside
    its band ``[lo, hi] + drag`` and the row ends the step at rest; any other row's force is at the band's
    edge its motion pushes it to (or its branch force for an inverted band), each row's rule being
    :func:`mudforce.jax.stick_force` given the others' forces. Found by projected Gauss-Seidel from
    ``previous`` (the last step's forces), then the stuck rows' forces solved exactly (Tikhonov-regularised
    by ``eps^(3/4)`` of the diagonal, so that redundant rows, four feet on one rigid body, share the load
    by the least weighted norm instead of failing on a singular matrix). A row that nothing moves (a zero
    diagonal) gets 0.
    """
    n = delassus.shape[0]
    dtype = delassus.dtype
    diag = jnp.diagonal(delassus)
    live = diag > 0.0
    pivot = jnp.where(live, diag, 1.0)

    def row(i: Array, f: Array) -> tuple[Array, Array]:
        f_stop = (target[i] - delassus[i] @ f + diag[i] * f[i]) / pivot[i]  # stop row i, the others' f given
        fi, si = mj.stick_force(lo[i], hi[i], drag[i], f_stop, velocity[i])
        return jnp.where(live[i], fi, 0.0), si & live[i]

    def sweep(_: int, f: Array) -> Array:
        return jax.lax.fori_loop(0, n, lambda i, f: f.at[i].set(row(i, f)[0]), f)

    f = jax.lax.fori_loop(0, _SWEEPS, sweep, jnp.asarray(previous, dtype=dtype))
    held = jax.vmap(lambda i: row(i, f)[1])(jnp.arange(n))
    # the stuck rows exactly at rest: delassus[S, S] f[S] = target[S] - delassus[S, ~S] f[~S]
    eps = jnp.finfo(dtype).eps ** 0.75
    both = held[:, None] & held[None, :]
    a = jnp.where(both, delassus, 0.0) + jnp.diag(jnp.where(held, eps, 1.0) * pivot)
    rhs = jnp.where(held, target - jnp.where(held[None, :], 0.0, delassus) @ f, pivot * f)
    solved = jnp.linalg.solve(a, rhs)
    low, high = lo + drag, hi + drag
    stuck = held & (solved > low) & (solved < high)
    return jnp.where(held, jnp.clip(solved, low, high), f), stuck


def _weight(weight: Any) -> Any:
    """:func:`step`'s ``weight`` [-] if it is traced, else as a float in [0, 1] (the MuJoCo adapter's bound), else
    InputError: 2.0 extrapolated the band, NaN gave NaN forces, True and "0.5" were taken."""
    if isinstance(weight, jax.core.Tracer):
        return weight
    value = np.asarray(weight)[()] if isinstance(weight, jax.Array) else weight
    return number_within(value, "weight", 0.0, 1.0, "-")


def _step_inputs(m: Any, d: Any, state: Any, patch: Any) -> None:
    """Refuse, when tracing, what :func:`step` cannot take, in one line: a state or patch of another type (a
    mudforce.jax.State, None: AttributeError), a state of another patch's feet (1 foot for 2 sites: 'depths must
    be one value or one per foot', 2 for 1: JAX's TypeError from dot_general), MuJoCo's model or data for MJX's
    ('MjModel' object has no attribute 'impl')."""
    if not isinstance(state, MudState):
        raise InputError(f"state must be a MudState (init(patch)), got {type(state).__name__}")
    if not isinstance(patch, MudPatch):
        raise InputError(f"patch must be a MudPatch (add_mud), got {type(patch).__name__}")
    # a patch of another model, where its sites are known (not traced): a site beyond the model's ended in JAX's
    # TypeError ('Slice size at index 0 in gather op is out of range'), another body's site was taken
    _check_step_model(m, d, state.state.depth.shape[-1:], patch.sites, patch.bodies, "patch", "site", "init(patch)")


def _check_step_model(m: Any, d: Any, feet: tuple[int, ...], ids: Any, bodies: Any, what: str, kind: str,
                     init: str) -> None:
    """The checks MJX's steps (1-D and 3-D) share, each in one line: a state of ``feet`` (its shape's last axis)
    for another mud's ``ids`` (sites or geoms, ``kind``, on ``bodies``), MuJoCo's model or data for MJX's, and ids
    that are not this model's (beyond its count, or on other bodies) where they are known (not traced)."""
    count = ids.shape[-1:]
    if feet != count:
        n = feet[0] if feet else 0
        raise InputError(f"the state has {n} {'foot' if n == 1 else 'feet'} and the {what} "
                         f"{count[0] if count else 0}: a state of another {what}? (make it with {init})")
    mujoco = require("mujoco", "mjx", "mud in MJX")
    for name, value, cls in (("m", m, mujoco.MjModel), ("d", d, mujoco.MjData)):
        if isinstance(value, cls):
            raise InputError(f"{name} must be MJX's (mjx.put_model(model), mjx.make_data(m)), got "
                             f"mujoco.{cls.__name__}")
    total, body_of = getattr(m, f"n{kind}", None), getattr(m, f"{kind}_bodyid", None)
    if (isinstance(total, int) and isinstance(body_of, np.ndarray)
            and not isinstance(ids, jax.core.Tracer) and not isinstance(bodies, jax.core.Tracer)):
        own, on = np.asarray(ids), np.asarray(bodies)
        if own.size and ((own < 0).any() or (own >= total).any() or (body_of[own] != on).any()):
            raise InputError(f"the {what}'s {kind}s {own.tolist()} (on bodies {on.tolist()}) are not this model's "
                             f"({total} {kind}s): a {what} of another model? (add_mud(model, ...) with the model m "
                             "was put from)")


@renamed_keywords(contact="state")
def step(m: Any, d: Any, state: MudState, patch: MudPatch, weight: float = 0.0) -> tuple[Any, MudState, Array]:
    """One physics step of an MJX model with the mud force on every foot; replaces ``mjx.step(m, d)``.

    Parameters
    ----------
    m, d : mjx.Model, mjx.Data
        The model and its data (Euler or implicitfast integrator).
    state : MudState
        The mud's state (:func:`init`; ``contact=`` is its deprecated name).
    patch : MudPatch
        The feet and their mud (:func:`add_mud`).
    weight : float
        Where in the step the band is taken [-] (:func:`mudforce.jax.branch_forces`):
        0 (default) at its start, 1 at its predicted end. The depth is
        committed from this step's own ``mjx.forward``, so the start's band
        is current; it matched the exact drop best (rest depth +0.01 to
        +0.07 %, against -3 to +3 % with 1, the CPU MuJoCo adapter's choice,
        whose commit lags a step; docs/gpu.md).

    Returns
    -------
    d : mjx.Data
        The data after the step.
    state : MudState
        The mud's state after the step.
    forces : array, shape (feet,)
        The vertical mud force applied on each sole during the step [N], positive up.
    """
    mjx = _mjx()
    _step_inputs(m, d, state, patch)
    weight = _weight(weight)
    if m.opt.integrator == mjx.IntegratorType.RK4:
        raise InputError("mudforce.engines.mjx supports the Euler and implicitfast integrators, not RK4")
    dt = m.opt.timestep
    d = mjx.forward(m, d)
    depth, jac, _ = _sole_kinematics(m, d, patch)
    feet = state.state  # every foot's mudforce.jax.State
    dtype = feet.depth.dtype
    depth = depth.astype(dtype)
    # commit the depth reached by the last step; a stuck sole ended it at rest, up to rounding, which is
    # dropped (else the sign of a 1e-18 m/s residue would pick the branch); one that moved is committed as is
    held = state.stuck & (feet.mode != mj.UNSTARTED) & (jnp.abs(depth - feet.depth) <= _HOLD)
    committed = jnp.where(held, feet.depth, depth)
    feet, _ = mj.step(feet, patch.params, committed, jnp.asarray(dt, dtype))
    # the band for the coming step and the force that would stop the sole within it
    f_up, f_down, drag = mj.branch_forces(feet, patch.params, dt, weight)
    # the velocity the integrator will give: Euler integrates joint damping implicitly, (M + dt D) qacc = qfrc
    qacc, minv_jt, v_free = _free_motion(m, d, dt, d.qfrc_smooth + d.qfrc_constraint, jac)  # v_free: up, no mud
    if jac.shape[0] == 1:  # one foot: its effective mass 1 / (j M^-1 j^T) is the whole story
        w = jnp.einsum("fv,vf->f", jac, minv_jt)  # 1 / effective mass of the sole [1/kg]
        f_stop = (-v_free / (dt * w)).astype(dtype)
        force, stuck = mj.stick_force(f_up, f_down, drag, f_stop, feet.velocity)
        force = jnp.where(feet.mode == mj.UNSTARTED, 0.0, force)
    else:  # several feet: held together, through the world's inverse inertia
        force, stuck = _joint_forces((jac @ minv_jt).astype(dtype), (-v_free / dt).astype(dtype), f_up, f_down,
                                     drag, feet, state.force)
    stuck = stuck & ((feet.mode == mj.CONTACT) | (feet.mode == mj.NECKED))
    f = force.astype(d.qacc.dtype)
    d = _integrate(m, d, d.qfrc_smooth + jac.T @ f, qacc + minv_jt @ f)
    return d, MudState(feet, stuck, force), force


# ----------------------------------------------------------------------------- the drop (mudforce drop --engine mjx)


@renamed_keywords(timestep="dt")
def drop_model(mass: float, foot: Foot | None = None, *, height: float = 0.0, dt: float = 1e-3,
               thickness: float = 0.025) -> Any:
    """A compiled ``mujoco.MjModel`` of the drop: a cuboid foot on a vertical slide joint, a site ``sole`` below.

    The same model and arguments as :func:`mudforce.engines.mujoco.drop_model`, refused alike: ``mass`` [kg],
    > 0; ``height`` [m] of the sole above the mud surface at ``z = 0``, in [0, 100]; ``dt`` [s] the
    time step (MuJoCo's ``opt.timestep``; ``timestep=`` is its deprecated name here), within [1e-9, 1000];
    ``thickness`` [m], within [1e-6, 100]. The foot's bottom face is the paper's 51 x 38 mm, or
    ``sqrt(area)`` square for another foot.
    """
    mujoco = require("mujoco", "mjx", "mud in MJX")
    mass, height, timestep = drop_numbers(mass, height, dt)  # MuJoCo's drop_model's checks and words
    thickness = drop_thickness(thickness)
    foot = check_foot(foot)
    lx, ly = (0.051, 0.038) if foot == Foot.paper() else (math.sqrt(foot.area),) * 2
    xml = f"""
<mujoco model="mudforce_drop_mjx">
  <option timestep="{timestep!r}" gravity="0 0 -9.81" integrator="Euler"/>
  <worldbody>
    <body name="foot" pos="0 0 {height + 0.5 * thickness!r}">
      <joint name="drop" type="slide" axis="0 0 1"/>
      <geom name="box" type="box" size="{0.5 * lx!r} {0.5 * ly!r} {0.5 * thickness!r}" mass="{mass!r}"
            contype="0" conaffinity="0"/>
      <site name="sole" pos="0 0 {-0.5 * thickness!r}"/>
    </body>
  </worldbody>
</mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


@renamed_keywords(timestep="dt")
def simulate_drop(mass: float, params: MudParameters, foot: Foot | None = None, *, duration: float = 8.0,
                  height: float = 0.0, dt: float = 1e-3, weight: float = 0.0) -> FootResult:
    """Drop a cuboid foot into mud in MJX with :func:`step`; returns a :class:`mudforce.engines.dynamics.FootResult`.

    One jitted ``lax.scan`` over the steps. The phase of each sample is
    FREE or NECKED from the contact state, STUCK while the sole is held in
    the band, else INTRUSION (moving down) or WITHDRAWAL (moving up). The
    force is the mud force applied during the step that ends at the sample [N].
    The arguments are those of :func:`mudforce.engines.mujoco.simulate_drop`, refused alike: ``mass`` [kg]
    (at least ``S max(k_m_i, k_m_w) dt^2``, the lightest foot the step resolves), ``duration`` [s],
    ``height`` [m] of the sole above the surface, ``dt`` [s] the time step (``timestep=`` is its deprecated
    name here); ``weight`` [-] of the predicted end-of-step band.
    """
    timestep = dt
    from mudforce.engines.dynamics.result import FootResult, Phase

    PH_FREE, INTRUSION, WITHDRAWAL, STUCK, NECKED = (Phase.FREE, Phase.INTRUSION, Phase.WITHDRAWAL, Phase.STUCK,
                                                     Phase.NECKED)

    mjx = _mjx()  # first: a clear error if MJX is missing
    params = check_params(params)
    weight = _weight(weight)
    mass, height, timestep = drop_numbers(mass, height, timestep)  # drop_model's checks, in its order
    foot = check_foot(foot)
    # the lightest foot the step resolves, as MuJoCo's simulate_drop: 1e-9 kg ended 1000 km above the mud
    mass = check_mass(mass, params, foot, timestep, "MuJoCo time step")
    model = drop_model(mass, foot, height=height, dt=timestep)
    n = max_samples(finite_number(duration, "duration", "s", positive=True), timestep)
    m = mjx.put_model(model)
    patch = add_mud(model, ["sole"], params, foot)

    def body(carry: tuple[Any, MudState], _: Any) -> tuple[tuple[Any, MudState], tuple[Array, ...]]:
        d, c = carry
        d, c, f = step(m, d, c, patch, weight)
        return (d, c), (d.qpos[0], d.qvel[0], f[0], c.state.mode[0], c.stuck[0], c.state.strain[0])

    run = jax.jit(lambda d: jax.lax.scan(body, (d, init(patch)), None, length=n - 1)[1])
    qpos, qvel, force, mode, stuck, strain = (np.asarray(a) for a in run(mjx.make_data(m)))
    depth = np.concatenate(([-height], -(qpos.astype(np.float64) - 0.0) - height))
    velocity = np.concatenate(([0.0], -qvel.astype(np.float64)))
    force = np.concatenate(([0.0], force.astype(np.float64)))
    phase = np.empty(n, dtype=np.int8)
    phase[0] = PH_FREE
    mode = mode.astype(np.int64)
    moving = np.where(velocity[1:] > 0.0, INTRUSION, WITHDRAWAL)
    phase[1:] = np.where(mode == mj.FREE, PH_FREE, np.where(mode == mj.NECKED, NECKED,
                                                               np.where(stuck, STUCK, moving)))
    strain_out = np.concatenate(([np.nan], np.where(mode == mj.CONTACT, strain.astype(np.float64), np.nan)))
    time = np.arange(n) * timestep
    return FootResult(time, depth, velocity, force, phase, mass, 9.81, "mjx", 0, strain_out)
