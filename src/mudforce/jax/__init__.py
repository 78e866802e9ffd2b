"""The mud force for thousands to millions of feet in JAX: jit, vmap, lax.scan, grad (``pip install mudforce[jax]``).

Usage::

    import jax
    jax.config.update("jax_enable_x64", True)      # float64, if wanted
    import mudforce.jax as mj
    from mudforce import MudParameters

    params = mj.make_params(MudParameters.from_water_content(0.25))   # shared by every foot
    state = mj.init(4096)                                               # not started yet
    state, forces = mj.step(state, params, depths, 1e-3)                # forces [N], shape (4096,)

Everything here is a pure function over small pytrees (:class:`Params`,
:class:`State`), written element-wise with no Python control flow on values
and no host synchronisation, so it runs under :func:`jax.jit`,
:func:`jax.vmap` and :func:`jax.lax.scan` and on any backend (CPU, GPU,
TPU). Per-foot parameters (domain randomisation) are a batch axis of the
params pytree: :func:`make_params` with a sequence of mud parameter sets, or
any arrays that broadcast against the feet.

The step is the CPU stepper's (:mod:`mudforce._kernel`, ``docs/model.md``)
for the exact velocity rule (the branch is ``sign(v)``, ``v`` the
first-order-hold velocity of the step): the same state machine (FREE,
CONTACT, NECKED), the same transitions at a step's start, the touchdown at
the crossing instant, the Maxwell element in closed form (Eq. (3)), the
necking instant located inside the step in closed form (Eq. (9)), the
post-necking filter (Eq. (7)) advanced by its exact one-step transition
matrix and flushed to zero by its age. Simulated depths are exact inputs,
so the exact rule is the right one for them; a measured, noisy trajectory
needs the CPU stepper's smoothing velocity filters, which are not here.
Every foot computes every branch and ``jnp.where`` picks (array form);
guards keep the branches not taken free of NaN, also in gradients (the
"double where").

The physics is the shared layer's, :mod:`mudforce.model.equations`, the one
that the CPU stepper and the dynamics call: its plain-arithmetic functions
run here on jax arrays (``equations.array_form``, numba's ``.py_func``): the
branch stresses, Eqs. (2), (3), (7), (8), summed by ``total_stress``; the
drag, Eq. (5); the yield strain, the necking test and the mud's motion at
and after necking, Eqs. (9), (7); the rest band's forces and its blend over
a step. Three functions of the model are not plain arithmetic (numba's own
``pow``; ``math`` calls and branches) and have JAX-native versions here
under the same names: :func:`nonlinear_spring_stress` (Eq. (4)),
:func:`neck_filter_response` (Eq. (7)) and :func:`necking_time` (Eq. (9)).
Only their control flow (selects here, branches there) is written again:
the arithmetic and the thresholds inside are the shared layer's, the
spring's power excepted. So is the rest band's state rule
(:func:`rest_band`, :func:`branch_forces`), the array form of
:mod:`mudforce.engines.dynamics.rest_band`.

Differences from the CPU stepper, all below 1e-12 of the peak force in
float64 for steps ``dt >= 1e-4`` s whose length repeats to the bit or changes by more than 1e-9 relative
(``tests/jax``): the step-length constants (``exp(-dt/tau)``,
Eq. (7)'s transition matrix) are computed from each step's ``dt`` rather
than cached while ``dt`` stays within 1e-9 relative (so with a jittering
``dt`` this is the more exact of the two: sample times far from zero jitter ``dt`` in its last bits, and the
paper's protocol at t + 1e4 s differs by 8.0e-12 of the peak, every other step 1e-9 longer by 1.6e-10); the
nonlinear spring uses
``jnp.power`` instead of the CPU's branch-free power (both within an ulp
or so); XLA's ``exp``/``sin``/``log1p`` instead of libm's; and the Maxwell
step and Eq. (7)'s filter use the shared layer's increment forms with
``expm1`` (:func:`mudforce.model.equations.maxwell_strain_increment`,
:func:`~mudforce.model.equations.neck_filter_transition_increment`,
:func:`~mudforce.model.equations.neck_filter_update_increment`), equal to the
CPU's forms in exact arithmetic, which keep float32 within about 1e-6 of
float64 over a 10 s gait at 1 kHz (the CPU's forms lost 2.8e-5 there) and
change float64 only by rounding. Measured: float64 equals ``MudContacts``
to 6.3e-14 of the peak force (``tests/jax``'s gaits at 1 ms), 2.8e-13 at
0.1 ms. At shorter steps the two drift apart (1e-12 at 10 us, 1.6e-12 to
2.5e-11 at 2 ns), and the CPU is the one that is off: its Maxwell step
forms ``1 - exp(-dt/tau)`` from a rounded ``exp``, accurate only to
~``1e-16 tau/dt`` relative (the element's relaxation rate, and its strain
by that fraction of its swing), where ``expm1`` here keeps every digit
(JAX made to form it as the CPU does equals the CPU to 2.5e-16 at 2 ns;
docs/gpu.md).

dtype follows the parameters: :func:`make_params` makes JAX's default float
(float32 unless ``jax_enable_x64`` is on). This module never changes JAX's
configuration or the process environment: to keep JAX from taking most of
the GPU's memory at start-up, set ``XLA_PYTHON_CLIENT_PREALLOCATE=false``
before JAX is imported (``docs/gpu.md``).

Speed plumbing and physics are kept apart: the functions named after the
paper's equations and the contact transitions (``touchdown``,
``intrusion_step``, ``withdrawal_step``, ``necked_step``, ``leave_necked``)
are the model; :func:`step` only wires them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from collections.abc import Set as AbstractSet
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mudforce import _kernel
from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MIN_DT
from mudforce._kernel.layout import ContactMode
from mudforce._plumbing.deprecation import renamed_keywords, warn_renamed
from mudforce.errors import InputError, feet_count, holds_boolean, is_integer, number_within
from mudforce.model import equations as _eq
from mudforce.model import law3d as _law3d
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

__all__ = [
    "CONTACT",
    "FREE",
    "NECKED",
    "UNSTARTED",
    "Necking",
    "Params",
    "State",
    "StepConstants",
    "branch_forces",
    "drag_stress",
    "init",
    "intrusion_step",
    "leave_necked",
    "make_params",
    "maxwell_strain_increment",
    "mud_depth",
    "neck_filter_response",
    "neck_filter_transition",
    "neck_flush_age",
    "necked_step",
    "necking_time",
    "nonlinear_spring_stress",
    "params_from_water_content",
    "reset",
    "rest_band",
    "step",
    "step_constants",
    "stick_force",
    "touchdown",
    "withdrawal_step",
]

# contact states: the stepper's own codes (mudforce._kernel.layout.ContactMode, defined once), and a foot
# whose first sample is still to come
UNSTARTED = -1
FREE = int(ContactMode.FREE)
CONTACT = int(ContactMode.CONTACT)
NECKED = int(ContactMode.NECKED)

Array = Any  # a jax.Array (or anything jnp.asarray takes)

# ----------------------------------------------------------------------------- pytrees


class Params(NamedTuple):
    """Mud and foot constants, SI; each field a scalar (shared) or an array over feet (per foot).

    Fields: ``k_i`` [Pa/m], ``b_i`` [Pa s/m] (intrusion Maxwell element,
    Eqs. (2)-(3)); ``k_w`` [Pa/m], ``b_w`` [Pa s/m] (withdrawal);
    ``alpha`` [Pa], ``beta`` [-] (nonlinear spring, Eq. (4)); ``sigma_y``
    [Pa] (yield stress, Eq. (9)); ``zeta`` [-], ``omega_0`` [rad/s]
    (post-necking filter, Eq. (7)); ``rho_m`` [kg/m^3], ``lam`` [-] (drag,
    Eq. (5)); ``area`` [m^2] (``S``), ``width`` [m] (``H``, Eq. (4)).
    Derived constants (``tau = b / k``, the filter's flush age) are
    computed inside the step, so gradients with respect to these fields
    are complete.
    """

    k_i: Array
    b_i: Array
    k_w: Array
    b_w: Array
    alpha: Array
    beta: Array
    sigma_y: Array
    zeta: Array
    omega_0: Array
    rho_m: Array
    lam: Array
    area: Array
    width: Array


class State(NamedTuple):
    """Every foot's contact state; each field an array over feet.

    Fields: ``mode`` (int8: :data:`UNSTARTED`, :data:`FREE`,
    :data:`CONTACT`, :data:`NECKED`); ``depth`` ``z_i`` at the last sample
    [m], positive down; ``strain`` ``z_i - z_m`` [m] (CONTACT; at necking
    in NECKED); ``velocity`` the last step's velocity [m/s] (positive down);
    ``neck_age`` time since necking [s]; ``neck_v`` ``v_m0`` [m/s];
    ``neck_z`` ``z_m`` at necking [m]; ``neck_g``, ``neck_gi`` Eq. (7)'s
    ``g(age)`` [-] and its integral ``G(age)`` [s]. ``z_m`` itself is
    :func:`mud_depth`.
    """

    mode: Array
    depth: Array
    strain: Array
    velocity: Array
    neck_age: Array
    neck_v: Array
    neck_z: Array
    neck_g: Array
    neck_gi: Array


def _float_dtype(dtype: Any) -> Any:
    """``dtype`` as a JAX float dtype, float32 or float64, or JAX's default float for None (float64 with
    ``jax_enable_x64``, else float32); else InputError: an integer, boolean or complex dtype would hold the mud's
    constants and the states wrongly, float16 cannot hold the stiffnesses (~1e6 Pa/m: inf). The one dtype check of
    the 1-D and 3-D JAX steps and of MJX."""
    if dtype is None:
        return jnp.result_type(float)
    try:
        ftype = jnp.dtype(dtype)
    except TypeError:
        raise InputError(f"dtype must be float32 or float64 (or None: JAX's default float), got {dtype!r}") from None
    if ftype not in (jnp.dtype(jnp.float32), jnp.dtype(jnp.float64)):
        raise InputError(f"dtype must be float32 or float64 (or None: JAX's default float), got {ftype}")
    return ftype


def _real(value: Any, name: str, unit: str) -> Any:
    """``value`` as a JAX array (a tracer under ``jit`` as it is) if it holds real numbers, else InputError: checked
    when tracing, not inside ``jit`` (the 1-D and 3-D steps' inputs). ``jnp.asarray`` with a float dtype would read
    ``"0.01"`` as a number, ``True`` as 1 and drop a complex number's imaginary part."""
    if not isinstance(value, jax.Array):
        if isinstance(value, (list, tuple)) and holds_boolean(value):
            raise InputError(f"{name} must be real numbers [{unit}], got a sequence holding booleans "
                             "(True/False among the numbers)")
        try:
            value = jnp.asarray(value)
        except (TypeError, ValueError):  # strings, objects, None, ragged nesting
            raise InputError(f"{name} must be real numbers [{unit}], got {type(value).__name__} {value!r}") from None
        except OverflowError:  # a Python int beyond JAX's integers (10**400, or 2**31 without x64)
            what = "an integer" if isinstance(value, int) else f"a {type(value).__name__} holding an integer"
            raise InputError(f"{name} must be real numbers [{unit}], got {what} too large for JAX's integers "
                             "(write it as a float)") from None
    if not (jnp.issubdtype(value.dtype, jnp.integer) or jnp.issubdtype(value.dtype, jnp.floating)):
        raise InputError(f"{name} must be real numbers [{unit}], got dtype {value.dtype}")
    return value


def _state(state: Any) -> State:
    """``state`` if it is a :class:`State`, else InputError (checked when tracing)."""
    if not isinstance(state, State):
        raise InputError(f"state must be a mudforce.jax.State (init), got {type(state).__name__}")
    return state


def _over_feet(value: Any, name: str, feet: tuple[int, ...]) -> None:
    """Refuse ``value`` (a JAX array) whose shape does not broadcast to the feet's ``feet`` unchanged: one line
    (checked when tracing; a shape (n, 1) made every field of the state (n, n), (n + 1,) was JAX's TypeError)."""
    try:
        fits = jnp.broadcast_shapes(value.shape, feet) == feet
    except ValueError:
        fits = False
    if not fits:
        raise InputError(f"{name} must be one value or one per foot, shape {feet}, got shape {value.shape}")


def _feet(foot: Foot | Sequence[Foot] | None) -> list[Foot]:
    """``foot`` as a non-empty list of :class:`Foot` (None: the paper's); InputError otherwise."""
    if foot is None:
        return [Foot.paper()]
    if isinstance(foot, Foot):
        return [foot]
    feet = _listed(foot)
    if not feet or not all(isinstance(f, Foot) for f in feet):
        raise InputError(f"foot must be a Foot or a non-empty sequence of Foot, got {type(foot).__name__}")
    return feet


def _listed(value: Any) -> list[Any]:
    """``list(value)``, or ``[]`` for a value that is not iterable (a number, None) or has no order (a set, whose
    order is its hashes' and which merges equal entries; a mapping's keys): refused by the caller."""
    if isinstance(value, (AbstractSet, Mapping)):
        return []
    try:
        return list(value)
    except TypeError:
        return []


@renamed_keywords(mud="params")
def make_params(
    params: MudParameters | Sequence[MudParameters],
    n: int | None = None,
    foot: Foot | Sequence[Foot] | None = None,
    dtype: Any = None,
) -> Params:
    """The :class:`Params` pytree for one mud shared by all feet, or one per foot.

    The arguments are those of :class:`mudforce.MudContacts`, in its order ``(params, n, foot)``.

    Parameters
    ----------
    params : MudParameters or sequence of MudParameters
        One parameter set (scalar fields, broadcast to every foot) or one per
        foot (fields of shape ``(len(params),)``). (``mud=``: its deprecated name.)
    n : int, optional
        Number of feet: every field is broadcast to shape ``(n,)`` (per-foot
        arrays, e.g. to randomise them afterwards).
    foot : Foot or sequence of Foot, optional
        Foot geometry (area ``S`` [m^2], width ``H`` [m]); the paper's
        51 x 38 mm cuboid by default. A sequence gives one per foot.
    dtype : dtype, optional
        Float dtype; JAX's default float by default.
    """
    if isinstance(n, (Foot, Sequence)) or is_integer(foot):
        # the order before 0.2 was (mud, foot, n): a foot second, or a count third, is that order (a set of feet
        # third was read so too, and refused as a count n)
        warn_renamed("make_params(params, foot, n)", "make_params(params, n, foot), the order of MudContacts")
        n, foot = foot, n  # type: ignore[assignment]
    mud = params
    dt_ = _float_dtype(dtype)
    muds = [mud] if isinstance(mud, MudParameters) else _listed(mud)
    if not muds or not all(isinstance(m, MudParameters) for m in muds):
        raise InputError(f"make_params needs MudParameters or a non-empty sequence of them, got {type(mud).__name__}")
    feet = _feet(foot)
    per_foot = not isinstance(mud, MudParameters) or (foot is not None and not isinstance(foot, Foot))
    count = max(len(muds), len(feet))
    for name, seq in (("mud parameter sets", muds), ("feet", feet)):
        if len(seq) not in (1, count):
            raise InputError(f"got {len(seq)} {name} for {count} feet; give one or one per foot")
    if n is not None:
        n = feet_count(n)
        if per_foot and count != n:
            raise InputError(f"got {count} per-foot entries for n = {n} feet")
    values = np.array([m.as_array() for m in muds], dtype=np.float64)  # (count or 1, 11), PARAMETER_NAMES order
    geometry = np.array([[f.area, f.width] for f in feet], dtype=np.float64)
    columns = [values[:, i] for i in range(values.shape[1])] + [geometry[:, 0], geometry[:, 1]]
    shape: tuple[int, ...] = (n,) if n is not None else ((count,) if per_foot else ())
    fields = [jnp.asarray(np.broadcast_to(c if per_foot else c[0], shape), dtype=dt_) for c in columns]
    return Params(*fields)


def init(n: int, dtype: Any = None) -> State:
    """``n`` feet not started yet: the first :func:`step` of each sets its initial sample (and ignores ``dt``).

    ``dtype`` is the float dtype (JAX's default float by default); it should
    be the params'.
    """
    n = feet_count(n)
    dt_ = _float_dtype(dtype)
    # a buffer per field, so that the state can be donated (jax.jit(..., donate_argnums=...))
    return State(jnp.full((n,), UNSTARTED, dtype=jnp.int8), *(jnp.zeros((n,), dtype=dt_) for _ in range(8)))


def reset(state: State, mask: Array) -> State:
    """``state`` with the feet where ``mask`` (bool, shape ``(n,)``) is True set back to not started."""
    feet = _state(state).depth.shape
    _mask(mask, feet, "state's shape")  # reset3d's rule: "x" and 0.5 were True
    mask = jnp.asarray(mask, dtype=bool)
    fresh = init(state.depth.shape[0], state.depth.dtype)
    return State(*(jnp.where(mask, f, s) for f, s in zip(fresh, state, strict=True)))


def _mask(mask: Any, shape: tuple[int, ...], of: str) -> None:
    """Refuse a reset ``mask`` that is not a bool or bools of ``shape`` in one line (reset's and reset3d's rule,
    checked when tracing): "x" and 0.5 reset every foot, a ragged list ended in numpy's ValueError."""
    try:
        given = mask if isinstance(mask, jax.Array) else np.asarray(mask)
    except (TypeError, ValueError):  # ragged nesting
        raise InputError(f"mask must be a bool or bools of the {of} {shape}, got a ragged "
                         f"{type(mask).__name__}") from None
    if given.dtype != bool or given.shape not in ((), shape):
        raise InputError(f"mask must be a bool or bools of the {of} {shape}, got {given.dtype} of shape "
                         f"{given.shape}")


def mud_depth(state: State) -> Array:
    """``z_m`` [m], the mud's displacement under the foot (Eq. (3); Eq. (7) after necking); ``z_i`` when FREE."""
    _, necked = _necked_mud_motion(state.neck_v, state.neck_z, state.neck_g, state.neck_gi)
    return jnp.where(state.mode == NECKED, necked,
                     jnp.where(state.mode == CONTACT, state.depth - state.strain, state.depth))


# ----------------------------------------------------------------------------- the paper's equations
# The model's physics is mudforce.model.equations, the one layer that the CPU stepper
# (mudforce._kernel), the dynamics and this step all call. Its plain-arithmetic
# functions (+ - * /, abs, tuples) run here on jax arrays as numba's .py_func,
# operation for operation the arithmetic the CPU stepper compiles. Three of the
# model's functions are not plain arithmetic and have JAX-native versions below,
# under the same names: nonlinear_spring_stress (Eq. (4)), neck_filter_response
# (Eq. (7)) and necking_time (Eq. (9)).


def _shared(function: Any) -> Any:
    """A plain-arithmetic function of :mod:`mudforce.model.equations` on jax arrays (``equations.array_form``)."""
    return _eq.array_form(function)


#: Eq. (5): ``f_s = lambda rho_m v |v|`` [Pa] (:func:`mudforce.model.equations.drag_stress`).
drag_stress = _shared(_eq.drag_stress)
_drag_acts = _shared(_eq.drag_acts)  # Eq. (5)'s gate: below the surface, z_i > 0
_piece_midpoint_depth = _shared(_eq.piece_midpoint_depth)  # where a piece's drag gate is decided
#: Eq. (3) in closed form, in increment form for float32: ``e(h) = e(0) + (v tau - e(0)) growth`` [m],
#: ``growth = -expm1(-h / tau)`` (:func:`mudforce.model.equations.maxwell_strain_increment`).
maxwell_strain_increment = _shared(_eq.maxwell_strain_increment)
_intrusion_stress = _shared(_eq.intrusion_stress)  # Eqs. (2), (3): (k_m_i e, e / tau_i)
_relaxation_time = _shared(_eq.relaxation_time)  # Eq. (3): tau = b_m / k_m
_withdrawal_stress = _shared(_eq.withdrawal_stress)  # Eqs. (2), (3), (8): (k_m_w e, e / tau_w)
_necked_stress = _shared(_eq.necked_stress)  # Eq. (7): (b_m_w dz_m/dt, dz_m/dt)
_total_stress = _shared(_eq.total_stress)  # Eqs. (1), (8): f_e2 + (f_e1 + f_s), the one place the force is summed
_yield_strain = _shared(_eq.yield_strain)  # Eq. (9): e* = (-sigma_y - f_s) / k_m_w
_necking_velocity = _shared(_eq.necking_velocity)  # Eqs. (3), (7): v_m0 = e / tau_w
_necked_mud_motion = _shared(_eq.necked_mud_motion)  # Eq. (7): (v_m0 g, z_n + v_m0 G)
_neck_filter_closed_form = _shared(_eq.neck_filter_closed_form)  # Eq. (7): (decay (c - a s), decay s)
_neck_filter_response_increment = _shared(_eq.neck_filter_response_increment)  # Eq. (7): g(h) - 1
_neck_filter_transition_increment = _shared(_eq.neck_filter_transition_increment)  # Eq. (7): Phi - I
_neck_filter_update_increment = _shared(_eq.neck_filter_update_increment)  # Eq. (7): x + (Phi - I) x
_rest_band_forces = _shared(_eq.rest_band_forces)  # Eqs. (1)-(5) at rest: (S k_m_w e, S (k_m_i e + f_e2))
_post_necking_force = _shared(_eq.post_necking_force)  # Eq. (7) at rest: (S b_m_w v_m0 g, z_n + v_m0 G)
_rest_band_blend = _shared(_eq.rest_band_blend)  # the band for a step: (1 - w) F(start) + w F(end)
_neck_breaks = _shared(_eq.neck_breaks)  # Eq. (9): k_m_w e + f_s < -sigma_y, the necking test
_necking_fraction = _shared(_eq.necking_fraction)  # Eq. (9): t* = -tau_w log1p(this)
_neck_filter_sine_series = _shared(_eq.neck_filter_sine_series)  # Eq. (7): sin(x)/w_d near x = 0
_neck_filter_sinh_series = _shared(_eq.neck_filter_sinh_series)  # Eq. (7): sinh(x)/mu near x = 0
_neck_filter_slow_mode = _shared(_eq.neck_filter_slow_mode)  # Eq. (7): the overdamped slow mode alone
_SERIES_BELOW = _eq.NECK_FILTER_SERIES_BELOW  # Eq. (7)'s thresholds, the compiled response's
_SLOW_MODE_FROM = _eq.NECK_FILTER_SLOW_MODE_FROM


def _safe(cond: Array, x: Array, fill: float = 1.0) -> Array:
    """``x`` where ``cond``, else ``fill``: the inner half of the double ``where`` that keeps NaN out of gradients."""
    return jnp.where(cond, x, fill)


def nonlinear_spring_stress(alpha: Array, beta: Array, depth: Array, width: Array) -> Array:
    """Nonlinear spring stress ``f_e2 = alpha (max(z_i, 0) / H)^beta`` [Pa], Eq. (4).

    ``alpha`` [Pa], ``beta`` [-], ``depth`` ``z_i`` [m], ``width`` ``H`` [m].
    The array form of Eq. (4) that the 3-D law shares
    (:func:`mudforce.model.law3d.spring_stress` on JAX arrays, ``x ** beta``):
    the compiled :func:`mudforce.model.equations.nonlinear_spring_stress`
    cannot run on jax arrays, as its power is :func:`mudforce._plumbing.pow.power`,
    a branch-free ``pow`` built from numba intrinsics (bit casts, ``llvm.fma``)
    that only numba compiles (the two agree to within an ulp or so). The base
    is guarded at and above the surface so that the gradient there is 0, not NaN.
    """
    stress: Array = _law3d.spring_stress(jnp.asarray(depth), alpha, beta, width)  # the array form of Eq. (4)
    return stress


def neck_filter_response(age: Array, zeta: Array, omega_0: Array) -> tuple[Array, Array]:
    """Impulse response ``g`` [-] of Eq. (7)'s filter and its integral ``G`` [s].

    The filter is ``G_m(s) = s / (s^2 + 2 zeta omega_0 s + omega_0^2)``.

    ``age`` ``t - t_n`` [s] >= 0, ``zeta`` [-] > 0, ``omega_0`` [rad/s].
    JAX-native version of :func:`mudforce.model.equations.neck_filter_response`,
    which cannot run on jax arrays (``math.exp``/``sin``/``sqrt`` calls and
    branches on the damping regime): here the underdamped, critical and
    overdamped forms are all computed and selected, each guarded so that
    the others' NaN or overflow stays out of the result and its gradient.
    The arithmetic is the shared layer's, as in the compiled response
    (:func:`~mudforce.model.equations.neck_filter_closed_form`, the series
    near ``x = 0`` and the overdamped slow mode), and so are its thresholds
    (:data:`~mudforce.model.equations.NECK_FILTER_SERIES_BELOW`,
    :data:`~mudforce.model.equations.NECK_FILTER_SLOW_MODE_FROM`): only the
    control flow (select, not branch) is this one's. Returns ``(g, G)``.
    """
    a = zeta * omega_0
    decay = jnp.exp(-a * age)
    under = zeta < 1.0
    over = zeta > 1.0
    # underdamped: sin(x)/wd, x = wd age (age sinc(x) near 0)
    wd = omega_0 * jnp.sqrt(_safe(under, 1.0 - zeta * zeta))
    x = wd * age
    small = x <= _SERIES_BELOW
    s_over = jnp.where(small, _neck_filter_sine_series(age, x), jnp.sin(x) / _safe(~small, wd))
    g_u, i_u = _neck_filter_closed_form(decay, jnp.cos(x), s_over, a)
    # critically damped
    g_c, i_c = _neck_filter_closed_form(decay, 1.0, age, a)
    # overdamped: sinh and cosh overflow long before the product does: past mu age = 30 keep the slow mode
    mu = omega_0 * jnp.sqrt(_safe(over, zeta * zeta - 1.0))
    y = mu * age
    mid = y < _SLOW_MODE_FROM
    y_mid = _safe(mid, y, 0.0)
    y_small = y_mid <= _SERIES_BELOW
    sh_over = jnp.where(y_small, _neck_filter_sinh_series(age, y_mid), jnp.sinh(y_mid) / _safe(~y_small, mu))
    g_o_mid, i_o_mid = _neck_filter_closed_form(decay, jnp.cosh(y_mid), sh_over, a)
    g_o_slow, i_o_slow = _neck_filter_slow_mode(0.5 * jnp.exp(_safe(~mid, (mu - a) * age, 0.0)), a, mu)
    g_o = jnp.where(mid, g_o_mid, g_o_slow)
    i_o = jnp.where(mid, i_o_mid, i_o_slow)
    g = jnp.where(under, g_u, jnp.where(over, g_o, g_c))
    gi = jnp.where(under, i_u, jnp.where(over, i_o, i_c))
    return g, gi


def neck_filter_transition(dt: Array, zeta: Array, omega_0: Array) -> tuple[Array, Array, Array, Array]:
    """One step of ``dt`` [s] of Eq. (7)'s filter, exactly, as the transition matrix minus the identity.

    The filter is ``z'' + 2 zeta omega_0 z' + omega_0^2 z = 0``; with
    ``(g_d, G_d) = neck_filter_response(dt)`` its transition matrix is
    ``Phi = [[g_d + 2 zeta omega_0 G_d, G_d], [-omega_0^2 G_d, g_d]]``
    (:func:`mudforce.model.equations.neck_filter_transition`, the CPU stepper's
    cache): ``[G, g](t + dt) = Phi [G, g](t)``. Returns ``(Phi00 - 1, Phi01,
    Phi10, Phi11 - 1)`` (:func:`mudforce.model.equations.neck_filter_transition_increment`):
    the diagonal is within ``~omega_0 dt`` of 1, and ``g_d - 1`` is formed
    from ``expm1`` and ``cos x - 1 = -2 sin^2(x/2)``
    (:func:`mudforce.model.equations.neck_filter_response_increment`) so that it
    keeps its digits in float32 (``1 - g_d`` from a rounded ``g_d`` would
    keep three or four at 1 kHz); on long steps, where ``|g_d - 1| >= 1/4``,
    ``g_d - 1`` itself. The elementary functions (``expm1``,
    ``sin``, ``sinh``) are computed here, the arithmetic is the shared layer's.
    """
    a = zeta * omega_0
    em = jnp.expm1(-a * dt)
    decay = em + 1.0
    g_d, gi_d = neck_filter_response(dt, zeta, omega_0)
    under = zeta < 1.0
    over = zeta > 1.0
    wd = omega_0 * jnp.sqrt(_safe(under, 1.0 - zeta * zeta))
    x = wd * dt
    s_over = gi_d / decay  # sin(x)/wd, sinh(y)/mu or dt: the response's own
    cm1_u = -2.0 * jnp.sin(0.5 * x) ** 2
    mu = omega_0 * jnp.sqrt(_safe(over, zeta * zeta - 1.0))
    y = mu * dt
    mid = y < _SLOW_MODE_FROM
    y_mid = _safe(mid, y, 0.0)
    cm1_o = 2.0 * jnp.sinh(0.5 * y_mid) ** 2
    cm1 = jnp.where(under, cm1_u, jnp.where(over, cm1_o, 0.0))
    # g_d - 1 = decay (c - a s) - 1 = em (c - a s) + (c - 1) - a s, c = cos x, cosh y or 1
    d3 = _neck_filter_response_increment(em, cm1, s_over, a)
    # a long step (g_d - 1 not small: zeta omega_0 dt or the overdamped mu dt large): the
    # increment form's terms cancel there, and g_d - 1 keeps its digits
    direct = g_d - 1.0
    d3 = jnp.where((over & ~mid) | (jnp.abs(direct) >= 0.25), direct, d3)
    phi: tuple[Array, Array, Array, Array] = _neck_filter_transition_increment(zeta, omega_0, d3, gi_d)
    return phi


def neck_flush_age(zeta: Array, omega_0: Array) -> Array:
    """Age after necking [s] past which Eq. (7)'s response is below 1e-250 and set to zero.

    :func:`mudforce._kernel.neck_flush_age` itself (speed plumbing of the
    stepper's, not an equation of the paper), on JAX arrays.
    """
    flush: Array = _kernel.neck_flush_age(jnp.asarray(zeta), jnp.asarray(omega_0))  # the one source, on arrays
    return flush


def necking_time(strain: Array, velocity: Array, tau_w: Array, k_m_w: Array, drag: Array, sigma_y: Array,
                 length: Array, growth: Array) -> Array:
    """First instant [s] in a withdrawal interval at which the neck breaks, Eq. (9); ``-1`` if it does not.

    JAX-native version of :func:`mudforce.model.equations.necking_time`, which
    cannot run on jax arrays (branches, ``math.log1p``): the withdrawal
    stress ``k_m_w e(t) + f_s`` falls below ``-sigma_y`` (the shared
    :func:`mudforce.model.equations.neck_breaks`) at
    ``t* = -tau_w log1p((e* - e(0)) / (e(0) - v tau_w))`` (the shared
    :func:`mudforce.model.equations.necking_fraction`),
    ``e* = (-sigma_y - f_s) / k_m_w`` (the shared
    :func:`mudforce.model.equations.yield_strain`), clipped to ``[0, length]``;
    the strain at the interval's end is the shared
    :func:`mudforce.model.equations.maxwell_strain_increment`. ``strain`` ``e(0)``
    [m], ``velocity`` [m/s], ``tau_w`` [s], ``k_m_w`` [Pa/m], ``drag``
    [Pa], ``sigma_y`` [Pa], ``length`` [s], ``growth`` ``1 - exp(-length /
    tau_w)`` [-]. The root is differentiable in all of them (the event time
    moves with the parameters).
    """
    already = _neck_breaks(k_m_w, strain, drag, sigma_y)
    end = maxwell_strain_increment(strain, velocity, tau_w, growth)
    never = ~_neck_breaks(k_m_w, end, drag, sigma_y)
    root = ~already & ~never
    target = _yield_strain(k_m_w, sigma_y, drag)
    # off the root the fraction's denominator e(0) - v tau_w may be 0: a strain 1 m off keeps it finite
    e_root = _safe(root, strain, velocity * tau_w + 1.0)
    ratio = _necking_fraction(e_root, velocity, tau_w, target)
    t = -tau_w * jnp.log1p(_safe(root, jnp.maximum(ratio, -1.0), 0.0))
    t = jnp.clip(t, 0.0, length)
    return jnp.where(already, 0.0, jnp.where(never, -1.0, t))


# ----------------------------------------------------------------------------- the transitions


class StepConstants(NamedTuple):
    """What a step of ``dt`` needs besides the state: ``tau_i``, ``tau_w`` [s] (``b / k``),
    ``grow_i``, ``grow_w`` (``1 - exp(-dt / tau)`` [-]), ``phi`` (Eq. (7)'s one-step matrix
    minus the identity, :func:`neck_filter_transition`) and ``flush`` [s] (:func:`neck_flush_age`)."""

    tau_i: Array
    tau_w: Array
    grow_i: Array
    grow_w: Array
    phi: tuple[Array, Array, Array, Array]
    flush: Array


def step_constants(p: Params, dt: Array) -> StepConstants:
    """Constants of a step of ``dt`` [s]: ``tau = b/k``, ``1 - exp(-dt/tau)``, Eq. (7)'s one-step matrix, flush age."""
    tau_i = _relaxation_time(p.k_i, p.b_i)
    tau_w = _relaxation_time(p.k_w, p.b_w)
    return StepConstants(tau_i, tau_w, -jnp.expm1(-dt / tau_i), -jnp.expm1(-dt / tau_w),
                         neck_filter_transition(dt, p.zeta, p.omega_0), neck_flush_age(p.zeta, p.omega_0))


def leave_necked(mode: Array, z0: Array, zm: Array, strain: Array, d: Array
                 ) -> tuple[Array, Array, Array]:
    """NECKED and moving down at a step's start: CONTACT keeping ``z_m`` if ``z_i > 0``, else FREE.

    Returns ``(mode, z_m [m], strain [m])`` at the step's start (docs/model.md, state table).
    """
    leave = (mode == NECKED) & (d > 0.0)
    below = z0 > 0.0
    mode = jnp.where(leave, jnp.where(below, CONTACT, FREE), mode)
    strain = jnp.where(leave & below, z0 - zm, strain)
    zm = jnp.where(leave & ~below, z0, zm)
    return mode, zm, strain


def touchdown(mode: Array, z0: Array, z1: Array, v: Array, zm: Array, strain: Array
              ) -> tuple[Array, Array, Array, Array, Array]:
    """FREE and ending the step below the surface: CONTACT from the crossing instant, ``z_m = 0`` there.

    Returns ``(mode, start [s] into the step where CONTACT begins, z_i at
    that start [m], z_m [m], strain [m])``. A FREE foot that stays above
    has ``z_m = z_i``.
    """
    free = mode == FREE
    td = free & (z1 > 0.0)
    crossing = td & (z0 < 0.0)  # then v > 0
    start = jnp.where(crossing, -z0 / _safe(crossing, v), 0.0)
    mode = jnp.where(td, CONTACT, mode)
    zm = jnp.where(td, 0.0, jnp.where(free, z1, zm))
    z_start = jnp.where(td, 0.0, z0)
    strain = jnp.where(td, 0.0, strain)
    return mode, start, z_start, zm, strain


def intrusion_step(strain: Array, v: Array, dt: Array, start: Array, k: StepConstants) -> Array:
    """The intrusion/hold branch (``v >= 0``) from ``start`` [s] to the step's end: Eq. (3) with ``k_m_i, b_m_i``.

    Returns the strain [m].
    """
    growth = jnp.where(start == 0.0, k.grow_i, -jnp.expm1(-(dt - start) / k.tau_i))
    return maxwell_strain_increment(strain, v, k.tau_i, growth)


def _piece_drag(p: Params, z_a: Array, v: Array, length: Array) -> Array:
    """Drag stress [Pa], Eq. (5), over a withdrawal piece from depth ``z_a`` [m]; its midpoint decides if below."""
    return jnp.where(_drag_acts(_piece_midpoint_depth(z_a, v, length)), drag_stress(p.lam, p.rho_m, v), 0.0)


class Necking(NamedTuple):
    """What :func:`withdrawal_step` returns: whether the neck broke in the step (bool), the strain [m]
    at the step's end or at necking, and the necking data of :class:`State` (``neck_v`` [m/s],
    ``neck_z`` [m], ``neck_age`` [s], ``neck_g`` [-], ``neck_gi`` [s])."""

    necked: Array  # bool: the neck broke in this step
    strain: Array
    neck_v: Array
    neck_z: Array
    neck_age: Array
    neck_g: Array
    neck_gi: Array


def withdrawal_step(p: Params, k: StepConstants, strain: Array, v: Array, dt: Array, start: Array, z_start: Array,
                    z1: Array) -> Necking:
    """The withdrawal branch (``v < 0``) with necking inside the step, Eqs. (3), (5), (9) and (7).

    The drag acts only below the surface, so the step is split where it
    crosses the surface; in each piece the stress is monotone and the
    necking instant is :func:`necking_time`'s closed-form root. From that
    instant the mud moves as ``v_m0 g(t - t_n)`` (Eq. (7)), ``v_m0 = e / tau_w``.
    Returns the strain at the step's end (or at necking) and the necking data.
    """
    crosses = ((z_start > 0.0) != (z1 > 0.0)) & (v != 0.0)
    tc = start - z_start / _safe(crosses, v)
    split = jnp.where(crosses & (start < tc) & (tc < dt), tc, dt)
    two = split != dt
    # piece 1: [start, split]
    len1 = split - start
    fs1 = _piece_drag(p, z_start, v, len1)
    grow1 = jnp.where((start == 0.0) & ~two, k.grow_w, -jnp.expm1(-len1 / k.tau_w))
    tn1 = necking_time(strain, v, k.tau_w, p.k_w, fs1, p.sigma_y, len1, grow1)
    e1 = maxwell_strain_increment(strain, v, k.tau_w, grow1)
    # piece 2: [split, dt], from the surface (only when the step crosses it)
    len2 = dt - split
    z_a2 = jnp.where(two, 0.0, z1)
    fs2 = _piece_drag(p, z_a2, v, len2)
    grow2 = -jnp.expm1(-len2 / k.tau_w)
    tn2 = jnp.where(two, necking_time(e1, v, k.tau_w, p.k_w, fs2, p.sigma_y, len2, grow2), -1.0)
    e2 = jnp.where(two, maxwell_strain_increment(e1, v, k.tau_w, grow2), e1)
    neck1 = tn1 >= 0.0
    neck2 = ~neck1 & (tn2 >= 0.0)
    necked = neck1 | neck2
    tn = jnp.where(neck1, tn1, tn2)
    fs = jnp.where(neck1, fs1, fs2)
    e_at = jnp.where(neck1, strain, e1)  # strain at the piece's start
    t_a = jnp.where(neck1, start, split)
    z_a = jnp.where(neck1, z_start, z_a2)
    e_n = jnp.where(tn > 0.0, _yield_strain(p.k_w, p.sigma_y, fs), e_at)  # exactly on the yield surface
    offset = t_a + tn
    age = jnp.where(necked, dt - offset, 0.0)
    g, gi = neck_filter_response(age, p.zeta, p.omega_0)
    z_n = z_a + v * tn
    return Necking(necked, jnp.where(necked, e_n, e2), _necking_velocity(e_n, k.tau_w), z_n - e_n, age, g, gi)


def necked_step(k: StepConstants, age: Array, gi: Array, g: Array, dt: Array) -> tuple[Array, Array, Array]:
    """NECKED for a whole step: Eq. (7)'s filter advanced by its exact transition matrix; zero past the flush age.

    ``[G, g] += (Phi - I) [G, g]`` (:func:`neck_filter_transition`;
    :func:`mudforce.model.equations.neck_filter_update_increment`).

    Returns ``(age [s], G [s], g [-])``.
    """
    age = age + dt
    flushed = age > k.flush
    gi = jnp.where(flushed, 0.0, gi)
    g = jnp.where(flushed, 0.0, g)
    gi, g = _neck_filter_update_increment(*k.phi, gi, g)
    return age, gi, g


def _force(p: Params, k: StepConstants, mode: Array, d: Array, strain: Array, mud_velocity: Array, z1: Array,
           v: Array) -> Array:
    """The force [N] at a sample, Eqs. (1)-(8), as the CPU stepper's :func:`mudforce._kernel.sample_outputs`.

    The branch's stress (the shared :func:`mudforce.model.equations.intrusion_stress`,
    :func:`~mudforce.model.equations.withdrawal_stress` or
    :func:`~mudforce.model.equations.necked_stress`), the spring on the
    intrusion branch, the drag below the surface, summed by
    :func:`mudforce.model.equations.total_stress` and times the area. ``strain``
    ``z_i - z_m`` [m] (CONTACT), ``mud_velocity`` ``v_m0 g`` [m/s] (NECKED).
    """
    fs = jnp.where(_drag_acts(z1), drag_stress(p.lam, p.rho_m, v), 0.0)
    intr = (mode == CONTACT) & (d >= 0.0)
    fe1_i, _ = _intrusion_stress(p.k_i, k.tau_i, strain)
    fe1_w, _ = _withdrawal_stress(p.k_w, k.tau_w, strain)
    fe1_n, _ = _necked_stress(p.b_w, mud_velocity)
    fe1 = jnp.where(mode == CONTACT, jnp.where(d >= 0.0, fe1_i, fe1_w), fe1_n)
    fe2 = jnp.where(intr, nonlinear_spring_stress(p.alpha, p.beta, z1, p.width), 0.0)
    return jnp.where(mode == FREE, 0.0, _total_stress(fe1, fe2, fs) * p.area)


def step(state: State, params: Params, depths: Array, dt: Array) -> tuple[State, Array]:
    """Advance every foot to its next depth sample; returns ``(state, forces)``.

    Parameters
    ----------
    state : State
        The feet's state (:func:`init`).
    params : Params
        Mud and foot constants (:func:`make_params`), broadcasting against the feet.
    depths : array, shape (n,)
        Foot depths below the surface ``z_i`` [m], positive down.
    dt : float or array
        Time since the previous sample [s], within [1e-9, 1e3] (ignored by a foot's first
        step, which sets its initial sample: FREE at or above the surface,
        else CONTACT with relaxed mud ``z_m = z_i``).

    Returns
    -------
    state : State
    forces : array, shape (n,)
        Vertical mud force on each foot [N], positive up. A foot given a
        depth that is not finite or beyond +-100 m, or (after its first
        step) a ``dt`` outside [1e-9, 1e3] s, gets NaN and keeps its state.

    Pure and element-wise: use it under ``jax.jit``, ``jax.vmap``,
    ``jax.lax.scan`` and ``jax.grad``.
    """
    if not isinstance(params, Params):
        raise InputError(f"params must be a mudforce.jax.Params (make_params), got {type(params).__name__}")
    ftype = _state(state).depth.dtype
    feet = state.depth.shape
    z1 = jnp.asarray(_real(depths, "depths", "m"), dtype=ftype)
    dt = jnp.asarray(_real(dt, "dt", "s"), dtype=ftype)
    p = Params(*(jnp.asarray(_real(f, f"params.{k}", "SI"), dtype=ftype) for k, f in zip(Params._fields, params,
                                                                                             strict=True)))
    for name, value in (("depths", z1), ("dt", dt), *zip((f"params.{k}" for k in Params._fields), p, strict=True)):
        _over_feet(value, name, feet)
    first = state.mode == UNSTARTED
    # the steppers' bounds (mudforce.model.bounds), as step3d's: a depth of 1000 m gave 4.6e10 N, a step of
    # 1e-12 s a velocity of 1e9 m/s kept in the state, and 5000 s was taken
    dt_ok = (dt >= MIN_DT) & (dt <= MAX_DT)
    ok = (jnp.abs(z1) <= MAX_DEPTH) & (first | dt_ok)
    dts = _safe(dt_ok, dt)
    k = step_constants(p, dts)

    z0 = state.depth
    v = jnp.where(first, 0.0, (z1 - z0) / dts)  # first-order hold
    d = jnp.sign(v)  # the exact rule: intrusion branch for v >= 0

    # transitions at the step's start
    mode, zm, strain = leave_necked(state.mode, z0, mud_depth(state), state.strain, d)
    mode, start, z_start, zm, strain = touchdown(mode, z0, z1, v, zm, strain)

    # CONTACT: intrusion or withdrawal (with necking)
    contact = mode == CONTACT
    e_in = intrusion_step(strain, v, dts, start, k)
    neck = withdrawal_step(p, k, strain, v, dts, start, z_start, z1)
    withdrawing = contact & (d < 0.0)
    strain1 = jnp.where(contact, jnp.where(withdrawing, neck.strain, e_in), strain)
    mode1 = jnp.where(contact & ~withdrawing & (z1 <= 0.0), FREE, mode)  # ends on the intrusion branch above
    necks = withdrawing & neck.necked
    mode1 = jnp.where(necks, NECKED, mode1)

    # NECKED for the whole step
    was_necked = mode == NECKED
    age, gi, g = necked_step(k, state.neck_age, state.neck_gi, state.neck_g, dts)
    neck_age = jnp.where(necks, neck.neck_age, jnp.where(was_necked, age, state.neck_age))
    neck_g = jnp.where(necks, neck.neck_g, jnp.where(was_necked, g, state.neck_g))
    neck_gi = jnp.where(necks, neck.neck_gi, jnp.where(was_necked, gi, state.neck_gi))
    neck_v = jnp.where(necks, neck.neck_v, state.neck_v)
    neck_z = jnp.where(necks, neck.neck_z, state.neck_z)

    mud_velocity, _ = _necked_mud_motion(neck_v, neck_z, neck_g, neck_gi)
    force = _force(p, k, mode1, d, strain1, mud_velocity, z1, v)

    # a foot's first sample: FREE at or above the surface, else CONTACT with relaxed mud
    first_mode = jnp.where(z1 > 0.0, CONTACT, FREE)
    mode1 = jnp.where(first, first_mode, mode1)
    zero = jnp.zeros_like(z1)
    strain1 = jnp.where(first, zero, strain1)
    first_spring = nonlinear_spring_stress(p.alpha, p.beta, z1, p.width)  # relaxed: f_e1 = 0, and v = 0: f_s = 0
    first_force = jnp.where(z1 > 0.0, _total_stress(0.0, first_spring, 0.0) * p.area, 0.0)
    force = jnp.where(first, first_force, force)
    new = State(mode1.astype(jnp.int8), z1, strain1, v,
                jnp.where(first, zero, neck_age), jnp.where(first, zero, neck_v), jnp.where(first, zero, neck_z),
                neck_g, neck_gi)
    new = State(*(jnp.where(ok, a, b) for a, b in zip(new, state, strict=True)))
    return new, jnp.where(ok, force, jnp.nan)


# ----------------------------------------------------------------------------- sticking


def rest_band(params: Params, mode: Array, depth: Array, strain: Array, neck_force: Array) -> tuple[Array, Array]:
    """The force band ``(F_up, F_down)`` [N] that holds a foot at rest (:func:`mudforce.engines.dynamics.rest_band`).

    ``F_down = S (k_m_i e + alpha (z_i / H)^beta)`` (intrusion branch,
    ``v -> 0+``; 0 at or above the surface), ``F_up = S k_m_w e``
    (withdrawal branch, ``v -> 0-``), or the post-necking force
    ``neck_force`` [N] (Eq. (7)) when NECKED; ``(0, 0)`` when FREE or not
    started. ``depth`` ``z_i`` [m], ``strain`` ``e = z_i - z_m`` [m].
    A foot at rest sticks while the load it carries (positive down) lies
    in the band (docs/model.md, "Coupled with dynamics"). The two branch
    forces are the shared :func:`mudforce.model.equations.rest_band_forces`.
    """
    p = params
    spring = nonlinear_spring_stress(p.alpha, p.beta, depth, p.width)
    f_up_contact, f_down = _rest_band_forces(strain, spring, p.k_i, p.k_w, p.area)
    f_down = jnp.where(depth > 0.0, f_down, 0.0)
    f_up = jnp.where(mode == NECKED, neck_force, f_up_contact)
    active = (mode == CONTACT) | (mode == NECKED)
    return jnp.where(active, f_up, 0.0), jnp.where(active, f_down, 0.0)


def branch_forces(state: State, params: Params, dt: Array, weight: Array = 1.0) -> tuple[Array, Array, Array]:
    """The sticking band of every foot for the coming step of ``dt`` [s], and the drag; no state change.

    JAX port of :func:`mudforce.engines.dynamics.branch_forces`. Returns
    ``(f_up, f_down, drag)`` [N]: the band is ``(1 - weight)`` times the
    band at the step's start plus ``weight`` times the band at its
    predicted end, each bound the force of a trial step on its own branch
    (``F_down`` after moving at ``max(v, 0)`` on the intrusion branch,
    ``F_up`` after ``min(v, 0)`` on the withdrawal branch, ``v`` the last
    step's velocity); ``drag = S lambda rho_m v |v|`` (Eq. (5); 0 above
    the surface). The arithmetic is the shared layer's
    (:func:`mudforce.model.equations.post_necking_force`,
    :func:`~mudforce.model.equations.rest_band_blend`, Eq. (3)'s step);
    the control flow is the array form of the CPU's. ``weight = 1`` suits a semi-implicit Euler step. A FREE
    or unstarted foot gets ``(0, 0, 0)`` unless it touches down within the
    step (then the intrusion force at the predicted end, ``z_m = 0`` at the surface).
    """
    # checked when tracing, as step's inputs: a dt of "0.01" was parsed, a weight of 2 extrapolated the band, a
    # state of None ended in an AttributeError and a dt of shape (4,) for 3 feet in JAX's TypeError
    s = _state(state)
    if not isinstance(params, Params):
        raise InputError(f"params must be a mudforce.jax.Params (make_params), got {type(params).__name__}")
    ftype = s.depth.dtype
    p = Params(*(jnp.asarray(_real(f, f"params.{k}", "SI"), dtype=ftype) for k, f in zip(Params._fields, params,
                                                                                             strict=True)))
    dt = jnp.asarray(_real(dt, "dt", "s"), dtype=ftype)
    weight = _real(weight, "weight", "-")
    if not isinstance(weight, jax.core.Tracer):  # the MuJoCo adapter's and MJX's bound; a traced one is left to jit
        for value in np.unique(np.asarray(weight)).tolist():
            number_within(value, "weight", 0.0, 1.0, "-")
    weight = jnp.asarray(weight, dtype=ftype)
    for name, value in (("dt", dt), ("weight", weight), *zip((f"params.{k}" for k in Params._fields), p,
                                                             strict=True)):
        _over_feet(value, name, s.depth.shape)
    z = s.depth
    v = s.velocity
    mode = s.mode
    started = mode != UNSTARTED
    free = mode == FREE
    # FREE: touchdown within the step
    z1 = z + v * dt
    lo_t, hi_t = rest_band(p, jnp.full_like(mode, CONTACT), z1, jnp.where(z < 0.0, z1, z1 - z), 0.0)
    td = free & (z1 > 0.0) & (weight > 0.0)
    fu_free = jnp.where(td, weight * jnp.minimum(lo_t, hi_t), 0.0)
    fd_free = jnp.where(td, weight * hi_t, 0.0)
    # CONTACT and NECKED
    v_dn = jnp.maximum(v, 0.0)
    v_up = jnp.minimum(v, 0.0)
    z_dn = z + v_dn * dt
    z_up = z + v_up * dt
    g0, i0 = neck_filter_response(s.neck_age, p.zeta, p.omega_0)
    g1, i1 = neck_filter_response(s.neck_age + dt, p.zeta, p.omega_0)
    force0, zm0 = _post_necking_force(p.area, p.b_w, s.neck_v, s.neck_z, g0, i0)  # Eq. (7) now and at the end
    lo1_n, zm1 = _post_necking_force(p.area, p.b_w, s.neck_v, s.neck_z, g1, i1)
    lo0_n, hi0_n = rest_band(p, mode, z, z - zm0, force0)
    _, hi1_n = rest_band(p, mode, z_dn, z_dn - zm1, 0.0)
    tau_i = _relaxation_time(p.k_i, p.b_i)
    tau_w = _relaxation_time(p.k_w, p.b_w)
    e0 = z - mud_depth(s)
    lo0_c, hi0_c = rest_band(p, mode, z, e0, 0.0)
    e_dn = maxwell_strain_increment(e0, v_dn, tau_i, -jnp.expm1(-dt / tau_i))  # Eq. (3), each branch's trial step
    e_up = maxwell_strain_increment(e0, v_up, tau_w, -jnp.expm1(-dt / tau_w))
    _, hi1_c = rest_band(p, mode, z_dn, e_dn, 0.0)
    lo1_c, _ = rest_band(p, mode, z_up, e_up, 0.0)
    necked = mode == NECKED
    lo0 = jnp.where(necked, lo0_n, lo0_c)
    hi0 = jnp.where(necked, hi0_n, hi0_c)
    lo1 = jnp.where(necked, lo1_n, lo1_c)
    hi1 = jnp.where(necked, hi1_n, hi1_c)
    f_up = _rest_band_blend(weight, lo0, lo1)
    f_down = _rest_band_blend(weight, hi0, hi1)
    drag = jnp.where(_drag_acts(z), p.area * drag_stress(p.lam, p.rho_m, v), 0.0)
    inactive = ~started | free
    return (jnp.where(inactive, jnp.where(started, fu_free, 0.0), f_up),
            jnp.where(inactive, jnp.where(started, fd_free, 0.0), f_down),
            jnp.where(inactive, 0.0, drag))


def stick_force(f_up: Array, f_down: Array, drag: Array, f_stop: Array, velocity: Array) -> tuple[Array, Array]:
    """The mud force [N] of an implicit (Moreau-Jean) step, like dry friction: no chatter at rest.

    ``f_stop`` [N] is the upward force that would bring the foot to rest
    by the step's end (from the engine's effective mass); the force is
    ``f_stop`` clamped to the band ``[f_up, f_down]`` (:func:`branch_forces`),
    plus the drag. An inverted band (``f_down < f_up``, a large compressive
    strain with ``k_m_w > k_m_i``) allows no sticking: the force is the
    branch of the current motion (``velocity`` [m/s], positive down).
    Returns ``(force [N], stuck)``, ``stuck`` True where the clamp is
    inactive (the foot ends the step at rest).
    """
    ordered = f_down >= f_up
    clamped = jnp.clip(f_stop - drag, f_up, f_down)
    stuck = ordered & (f_stop - drag > f_up) & (f_stop - drag < f_down)
    inverted = jnp.where(velocity >= 0.0, f_down, f_up)
    return jnp.where(ordered, clamped, inverted) + drag, stuck


# Table I at a traced water content (domain randomisation under jit); imported last: it builds on Params
from mudforce.jax.domain import params_from_water_content  # noqa: E402
