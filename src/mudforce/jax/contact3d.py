"""Mud in 3-D in JAX: a foot of any shape under jit, vmap, lax.scan and grad (``pip install mudforce[jax]``).

Usage::

    import jax
    jax.config.update("jax_enable_x64", True)      # float64, if wanted
    import mudforce.jax.contact3d as mj3
    from mudforce import MudParameters
    from mudforce.model import shapes

    shape = shapes.sphere(0.04)
    params = mj3.make_params3d(MudParameters.from_water_content(0.25), shape)
    state = mj3.init3d(shape)                                   # not started yet
    state, force, torque = mj3.step3d(state, params, position, quaternion, dt)

:func:`step3d` is :meth:`mudforce.steppers.contact3d.MudContact3D.step` as a pure
function of small pytrees (:class:`Params3D`, :class:`State3D`): the same
law (:mod:`mudforce.model.law3d`, whose functions it calls with
``xp=jax.numpy``: one law, not a port), each element's paper stress from
the 1-D JAX step (:func:`mudforce.jax.step`, one row per element, unit
area, the exact velocity rule: MudContact3D's elements), and the same
wiring: world centroids ``c = p + R c_b``, normals ``n = R n_b``, depths
``h - c_z``; vertical force ``sigma_i A_i max(-n_z, 0)``; per submerged
element an elastic-perfectly-plastic horizontal slip with 3D-RFT bearing
and Eq. (5)'s drag; torque about the body origin. The law's
functions are the very ones MudContact3D and the compiled step call
(:mod:`mudforce.model.law3d` writes each once, for floats, numpy, JAX and
numba). Measured equal to MudContact3D to 1e-12 of the peak force in float64 (``tests/jax/test_jax_contact3d.py``;
the differences are rounding: XLA's reductions and products, and those of
the 1-D step, :mod:`mudforce.jax`).

Many feet, many worlds: :func:`jax.vmap` over a leading axis of the state,
the params (one mud per foot: :func:`make_params3d` with a sequence) and the
poses; time: :func:`jax.lax.scan`. Gradients (:func:`jax.grad`) with respect
to poses and parameters are finite: every square root and quotient that can
meet 0 is guarded (the "double where", :mod:`mudforce.model.law3d`). They are the
gradients of a piecewise-smooth law: across an event (an element touching
down, necking, a slip starting to yield) the force jumps in slope or value,
and the gradient is that of the side the point is on.

Bad input cannot raise inside ``jit``: as :func:`mudforce.jax.step` does for
a foot's depth, a step given a position that is not finite, a quaternion
that is not finite or whose norm is farther than 1e-6 from 1, a ``dt``
outside ``[1e-9, 1e3]`` s after the first step, or a pose that puts an
element deeper or higher than 100 m, returns NaN force and torque and leaves
the state exactly as it was (MudContact3D refuses the same inputs with an
:class:`~mudforce.errors.InputError`). Wrong array shapes are known when
tracing, and raise :class:`~mudforce.errors.InputError` then.

dtype follows the state (:func:`init3d`; JAX's default float, float64 only
with ``jax_enable_x64``). Like :mod:`mudforce.jax`, this module never
changes JAX's configuration.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mudforce import jax as mj
from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MAX_HORIZONTAL, MIN_DT
from mudforce.errors import InputError, feet_count
from mudforce.model import law3d
from mudforce.model.bounds import bounded_depth
from mudforce.model.foot import Foot
from mudforce.model.law3d import check_bearing_scale, check_lateral_stiffness
from mudforce.model.parameters import MudParameters
from mudforce.model.shapes import Shape

__all__ = ["Params3D", "State3D", "init3d", "make_params3d", "reset3d", "step3d"]

Array = Any  # a jax.Array (or anything jnp.asarray takes)


class Params3D(NamedTuple):
    """A foot's shape and mud, SI: what :func:`step3d` needs besides the state and the pose.

    Fields: ``elements`` the elements' 1-D parameters (:class:`mudforce.jax.Params`,
    unit area, width ``H`` of Eq. (4) [m]); ``centroids`` (n, 3) [m] and
    ``normals`` (n, 3) [-] of the elements in the body frame; ``areas`` (n,)
    [m^2]; ``surface_height`` [m], the undisturbed mud surface in the world
    frame (z up); ``lateral_stiffness`` [Pa/m], the horizontal slip's ``k``; ``bearing_scale`` [-], the sideways
    bearing's scale (:func:`mudforce.model.law3d.bearing_stress`).
    With one mud per foot (:func:`make_params3d` given a sequence) every
    field has a leading axis over the feet, for :func:`jax.vmap`.
    """

    elements: mj.Params
    centroids: Array
    normals: Array
    areas: Array
    surface_height: Array
    lateral_stiffness: Array
    bearing_scale: Array


class State3D(NamedTuple):
    """Everything a foot remembers (:class:`mudforce.steppers.contact3d.ContactState3D`'s content, as a pytree).

    Fields: ``elements`` the elements' 1-D states (:class:`mudforce.jax.State`,
    one per element); ``slip`` (n, 2) the horizontal elastic slips [m];
    ``centroids`` (n, 3) the world centroids at the last step [m];
    ``started`` (bool) whether the foot has taken its first step.
    """

    elements: mj.State
    slip: Array
    centroids: Array
    started: Array


def _shape(shape: Any) -> Shape:
    if not isinstance(shape, Shape):
        raise InputError(f"shape must be a mudforce.model.shapes.Shape, got {type(shape).__name__}")
    return shape


def make_params3d(mud: MudParameters | Sequence[MudParameters], shape: Shape, surface_height: float = 0.0, *,
                  width: float | None = None, lateral_stiffness: float | None = None,
                  bearing_scale: float | None = None, dtype: Any = None) -> Params3D:
    """The :class:`Params3D` of a foot of ``shape`` in ``mud`` (checked as
    :class:`~mudforce.steppers.contact3d.MudContact3D`).

    Parameters
    ----------
    mud : MudParameters or sequence of MudParameters
        One mud (fields without a batch axis), or one per foot: every field
        then has a leading axis of ``len(mud)``, to :func:`jax.vmap` over.
    shape : Shape
        The foot's surface (:mod:`mudforce.model.shapes`), body frame.
    surface_height : float
        Height of the undisturbed mud surface in the world frame [m].
    width : float, optional
        The intruder width ``H`` of Eq. (4) [m]; by default ``shape.width``.
    lateral_stiffness : float, optional
        Stiffness of the horizontal elastic slip [Pa/m]; by default each
        mud's withdrawal stiffness ``k_m_w`` (:mod:`mudforce.model.law3d`).
    bearing_scale : float, optional
        The sideways bearing's scale [-], within [0, 1e3]; by default 1 (3D-RFT's granular bearing).
    dtype : dtype, optional
        Float dtype; JAX's default float by default.
    """
    shape = _shape(shape)
    per_foot = not isinstance(mud, MudParameters)
    muds = [mud] if isinstance(mud, MudParameters) else list(mud) if isinstance(mud, Sequence) else []
    if not muds or not all(isinstance(m, MudParameters) for m in muds):
        raise InputError("make_params3d needs MudParameters or a non-empty sequence of them")
    height = bounded_depth(surface_height, "surface_height")
    h = width if width is not None else shape.width
    if h is None:
        raise InputError("this shape has no width H for Eq. (4); give width= [m] (or build the shape with "
                         "a mudforce.model.shapes constructor, which sets it)")
    foot = Foot(area=1.0, width=h, shape="element")  # checks H; the elements' force is their stress [Pa]
    if lateral_stiffness is None:
        stiffness = np.array([m.k_m_w for m in muds])
    else:
        stiffness = np.full(len(muds), check_lateral_stiffness(lateral_stiffness))  # MudContact3D's check and bound
    bearing = np.full(len(muds), check_bearing_scale(1.0 if bearing_scale is None else bearing_scale))
    ftype = mj._float_dtype(dtype)
    elements = mj.make_params(muds if per_foot else muds[0], foot=foot, dtype=ftype)
    batch: tuple[int, ...] = (len(muds),) if per_foot else ()

    def leaf(value: Any) -> Array:
        value = np.asarray(value, dtype=np.float64)
        return jnp.asarray(np.broadcast_to(value, batch + value.shape), dtype=ftype)

    return Params3D(
        elements=mj.Params(*(jnp.broadcast_to(f, batch) for f in elements)),
        centroids=leaf(shape.centroids), normals=leaf(shape.normals), areas=leaf(shape.areas),
        surface_height=leaf(height),
        lateral_stiffness=jnp.asarray(stiffness if per_foot else stiffness[0], dtype=ftype),
        bearing_scale=jnp.asarray(bearing if per_foot else bearing[0], dtype=ftype))


def init3d(shape: Shape, batch: int | None = None, dtype: Any = None) -> State3D:
    """A foot of ``shape`` not started yet (``batch`` of them: a leading axis on every field, for :func:`jax.vmap`).

    The first :func:`step3d` sets the pose and ignores ``dt``. ``dtype`` is
    the float dtype (JAX's default float by default); it should be the
    params'.
    """
    n = _shape(shape).n
    ftype = mj._float_dtype(dtype)
    lead: tuple[int, ...] = () if batch is None else (feet_count(batch, "batch (the number of feet)"),)
    one = mj.init(n, ftype)
    # a buffer per field, so that the state can be donated (jax.jit(..., donate_argnums=...))
    return State3D(mj.State(*(jnp.broadcast_to(f, lead + f.shape).copy() for f in one)),
                   jnp.zeros((*lead, n, 2), dtype=ftype), jnp.zeros((*lead, n, 3), dtype=ftype),
                   jnp.zeros(lead, dtype=bool))


def reset3d(state: State3D, mask: Array = True) -> State3D:
    """``state`` with the feet where ``mask`` is True set back to not started (the next step is a first step).

    ``mask`` is a bool of the state's batch shape (``state.started.shape``),
    or a single bool for all.
    """
    if not isinstance(state, State3D):
        raise InputError(f"state must be a State3D (init3d), got {type(state).__name__}")
    mj._mask(mask, state.started.shape, "state's batch shape")
    mask = jnp.broadcast_to(jnp.asarray(mask), state.started.shape)
    batch = state.started.ndim

    def pick(fresh_value: Array, old: Array) -> Array:
        m = jnp.reshape(mask, mask.shape + (1,) * (old.ndim - batch))
        return jnp.where(m, fresh_value, old)

    fresh = State3D(
        mj.State(*(jnp.full_like(f, mj.UNSTARTED) if i == 0 else jnp.zeros_like(f)
                   for i, f in enumerate(state.elements))),
        jnp.zeros_like(state.slip), state.centroids, jnp.zeros_like(state.started))
    out: State3D = jax.tree.map(pick, fresh, state)
    return out


def step3d(state: State3D, params: Params3D, position: Array, quaternion: Array,
           dt: Array, hold: Array | None = None) -> tuple[State3D, Array, Array]:
    """Move the foot to a pose; returns ``(state, force, torque)``: the mud's wrench, world frame.

    Parameters
    ----------
    state : State3D
        The foot's state (:func:`init3d`).
    params : Params3D
        Its shape and mud (:func:`make_params3d`).
    position : array, shape (3,)
        The body origin in the world frame [m], z up.
    quaternion : array, shape (4,)
        The body's orientation ``(w, x, y, z)`` [-] (MuJoCo's order), unit
        within 1e-6 (normalised).
    dt : float or array
        Time since the previous pose [s], within [1e-9, 1e3]; ignored on
        the first step.
    hold : float or array, optional
        An element whose depth changed by at most this since the last step
        keeps its last depth [m] (it is at rest). For an engine that holds
        a stuck foot still to its own rounding (float32 MJX:
        :mod:`mudforce.engines.mjx3d`); by default only the rounding of
        the pose itself (:func:`mudforce.model.law3d.settle_depth`).

    Returns
    -------
    state : State3D
    force : array, shape (3,)
        Force on the foot [N]; ``force[2] > 0`` pushes it up.
    torque : array, shape (3,)
        Torque on the foot about its body origin [N m].

    Bad input (module docstring) gives NaN force and torque and the state
    unchanged. Pure: use it under ``jax.jit``, ``jax.vmap`` (a leading
    axis on the state, params and pose), ``jax.lax.scan`` and ``jax.grad``.
    """
    if not isinstance(state, State3D):
        raise InputError(f"state must be a State3D (init3d), got {type(state).__name__}")
    if not isinstance(params, Params3D):
        raise InputError(f"params must be a Params3D (make_params3d), got {type(params).__name__}")
    ftype = state.slip.dtype
    n = state.slip.shape[-2] if state.slip.ndim == 2 else -1
    p = jnp.asarray(mj._real(position, "position", "m"), dtype=ftype)
    q = jnp.asarray(mj._real(quaternion, "quaternion", "-"), dtype=ftype)
    if p.shape != (3,) or q.shape != (4,):
        raise InputError(f"position must be 3 numbers [m] and the quaternion 4 (w, x, y, z), got shapes {p.shape} "
                         f"and {q.shape} (jax.vmap over many feet)")
    if n < 1 or params.centroids.shape != (n, 3) or state.centroids.shape != (n, 3):
        raise InputError(f"state and params must be of one foot of the same shape: slips {state.slip.shape}, "
                         f"centroids {state.centroids.shape} and {params.centroids.shape}")
    dt = jnp.asarray(mj._real(dt, "dt", "s"), dtype=ftype)
    if dt.shape != ():
        raise InputError(f"dt must be one number [s] (jax.vmap over many feet), got shape {dt.shape}")
    if hold is not None:
        hold = jnp.asarray(mj._real(hold, "hold", "m"), dtype=ftype)
        if hold.shape not in ((), (n,)):
            raise InputError(f"hold must be one number [m] or one per element ({n},), got shape {hold.shape}")
        # where known when tracing (not a traced value): inf held every element still (a foot that never sinks),
        # NaN and negative ones held none, silently
        if not isinstance(hold, jax.core.Tracer) and not bool(jnp.all((hold >= 0.0) & jnp.isfinite(hold))):
            raise InputError(f"hold must be finite and >= 0 [m], got {np.asarray(hold).tolist()!r}")
    e = mj.Params(*(jnp.asarray(f, dtype=ftype) for f in params.elements))
    body_centroids = jnp.asarray(params.centroids, dtype=ftype)
    body_normals = jnp.asarray(params.normals, dtype=ftype)
    areas = jnp.asarray(params.areas, dtype=ftype)
    k = jnp.asarray(params.lateral_stiffness, dtype=ftype)
    started = state.started

    # what MudContact3D refuses, found here without raising: the step is then not taken
    norm = jnp.sqrt(jnp.sum(q * q))
    pose_ok = (jnp.all(jnp.isfinite(p)) & jnp.all(jnp.isfinite(q)) & (jnp.abs(norm - 1.0) <= law3d.QUATERNION_TOLERANCE)
               & (jnp.abs(p[0]) <= MAX_HORIZONTAL) & (jnp.abs(p[1]) <= MAX_HORIZONTAL))
    dt_ok = (dt >= MIN_DT) & (dt <= MAX_DT)
    dts = jnp.where(dt_ok, dt, 1.0)  # the double where: a first step's ignored dt puts no NaN in a gradient
    # the law of mudforce.model.law3d on the elements' columns (the functions MudContact3D and the compiled
    # step call): placing, the paper per element, the horizontal law, the moments
    qs = jnp.where(pose_ok, q, jnp.asarray([1.0, 0.0, 0.0, 0.0], dtype=ftype))  # rotation() normalises
    r = law3d.rotation(qs[0], qs[1], qs[2], qs[3])
    ox, oy, oz = law3d.rotate(r, body_centroids[:, 0], body_centroids[:, 1], body_centroids[:, 2])
    nx, ny, nz = law3d.rotate(r, body_normals[:, 0], body_normals[:, 1], body_normals[:, 2])
    centroids = jnp.stack([p[0] + ox, p[1] + oy, p[2] + oz], axis=1)
    height = jnp.asarray(params.surface_height, dtype=ftype)
    depth = law3d.element_depth(height, p[2], oz)
    # an element turned about at its depth is at rest, not moving by rounding (MudContact3D.step's rule)
    depth = jnp.where(started, law3d.settle_depth(depth, state.elements.depth), depth)
    if hold is not None:  # an engine's stuck foot: still to its own rounding
        still = started & (jnp.abs(depth - state.elements.depth) <= hold)
        depth = jnp.where(still, state.elements.depth, depth)
    ok = pose_ok & (~started | dt_ok) & jnp.all(jnp.abs(depth) <= MAX_DEPTH)

    # the paper, element by element
    elements, stress = mj.step(state.elements, e, depth, dts)
    sx, sy = state.slip[:, 0], state.slip[:, 1]
    mx, my = centroids[:, 0] - state.centroids[:, 0], centroids[:, 1] - state.centroids[:, 1]
    spring = law3d.bearing_stress(law3d.spring_stress(depth, e.alpha, e.beta, e.width),
                                  jnp.asarray(params.bearing_scale, dtype=ftype))
    slip_x, slip_y, fx, fy, fz = law3d.element_force(stress, spring, areas, nx, ny, nz, depth, sx, sy, mx, my,
                                                     1.0 / dts, started, k, e.sigma_y, e.lam, e.rho_m)
    slip = jnp.stack([slip_x, slip_y], axis=1)
    force = jnp.stack([fx.sum(), fy.sum(), fz.sum()])
    torque = jnp.stack([t.sum() for t in law3d.moment(ox, oy, oz, fx, fy, fz)])

    new = State3D(elements, slip, centroids, jnp.ones_like(started))
    kept: State3D = jax.tree.map(lambda a, b: jnp.where(ok, a, b), new, state)
    return kept, jnp.where(ok, force, jnp.nan), jnp.where(ok, torque, jnp.nan)
