"""The paper's equations as small pure functions (compiled with numba): the model's one physics layer.

Each function computes one equation of Chen, Yi & Shan (2024),
arXiv:2403.02617, in SI. They are scalar, side-effect free and callable
from Python as well as from the compiled stepper in :mod:`mudforce._kernel`,
which assembles the force only through them: the branch stresses
(:func:`intrusion_stress`, :func:`withdrawal_stress`, :func:`necked_stress`)
summed by :func:`total_stress`, the Maxwell element's step
(:func:`maxwell_strain_step`), the neck (:func:`yield_strain`,
:func:`necking_time`, :func:`necking_velocity`) and Eq. (7)'s filter
(:func:`neck_filter_response`, :func:`neck_filter_transition`,
:func:`neck_filter_update`, :func:`necked_mud_motion`). To change the
model, change it here.

Plain arithmetic, for other array libraries
-------------------------------------------
The functions marked *plain arithmetic* use only ``+ - * /``, ``abs``,
comparisons and tuples: no ``math`` calls, no branches, no calls to
compiled functions other than this module's plain-arithmetic ones.
Exponentials and the impulse response come in as arguments
(``decay = exp(-h / tau)``, ``(g, G)`` of :func:`neck_filter_response`),
computed once by the caller. So the undecorated Python function, numba's
``.py_func``, runs them on whole arrays of any library with those
operators, e.g. ``array_form(maxwell_strain_step)(e, v, tau, decay)`` on JAX
arrays, giving the compiled stepper's arithmetic, operation for operation.
They are compiled ``inline="always"`` with numba's IEEE division
(``error_model="numpy"``), so in the stepper they cost what the expression
costs. The nonlinear spring, Eq. (4), is the exception: its power goes
through :func:`mudforce._plumbing.pow.power`, which every compiled path calls (via
:func:`nonlinear_spring_stress`) so that all paths agree bit for bit; other
array libraries compute it themselves and pass ``f_e2`` in.

A few plain-arithmetic functions at the end of the module are other
forms of the stepper's, equal in exact arithmetic, that keep their
digits in float32: :func:`maxwell_strain_increment`,
:func:`neck_filter_response_increment`,
:func:`neck_filter_transition_increment`,
:func:`neck_filter_update_increment`. The JAX step
(:mod:`mudforce.jax`) calls them; the compiled stepper keeps its own
forms, whose bits the tests pin.

Functions that are not plain arithmetic (``math`` calls, branches:
:func:`neck_filter_response`, :func:`necking_time`,
:func:`nonlinear_spring_stress`) are scalar control flow around plain
arithmetic of this module (:func:`neck_filter_closed_form`,
:func:`necking_fraction`, :func:`neck_breaks`, ...) and its named
thresholds (:data:`NECK_FILTER_SERIES_BELOW`,
:data:`NECK_FILTER_SLOW_MODE_FROM`); the JAX step writes the same
control flow on arrays around the same arithmetic. Only the control flow
is written twice.

A plain-arithmetic function may call others of this module: their
Python forms are then called in turn (:func:`array_form`).

Sign conventions (docs/model.md): depth ``z_i`` is positive downward,
below the undisturbed surface; a positive stress pushes the foot up
(resistance), a negative one pulls it down (suction).
"""

from __future__ import annotations

import functools
import math
import types
from collections.abc import Callable
from typing import Any, TypeVar

from mudforce._plumbing import cache as _cache
from mudforce._plumbing.jit import njit
from mudforce._plumbing.pow import power

_cache.install()  # numba's cache keyed on the shared sources' content (see mudforce._plumbing.cache)

__all__ = [
    "NECK_FILTER_SERIES_BELOW",
    "NECK_FILTER_SLOW_MODE_FROM",
    "array_form",
    "drag_acts",
    "drag_stress",
    "intrusion_stress",
    "maxwell_strain_increment",
    "maxwell_strain_rate",
    "maxwell_strain_step",
    "neck_breaks",
    "neck_filter_closed_form",
    "neck_filter_response",
    "neck_filter_response_increment",
    "neck_filter_sine_series",
    "neck_filter_sinh_series",
    "neck_filter_slow_mode",
    "neck_filter_transition",
    "neck_filter_transition_increment",
    "neck_filter_update",
    "neck_filter_update_increment",
    "necked_mud_motion",
    "necked_stress",
    "necking_fraction",
    "necking_time",
    "necking_velocity",
    "nonlinear_spring_stress",
    "piece_midpoint_depth",
    "post_necking_force",
    "relaxation_time",
    "rest_band_blend",
    "rest_band_depth_spread",
    "rest_band_forces",
    "submerged_drag_stress",
    "total_stress",
    "viscoelastic_stress",
    "withdrawal_stress",
    "yield_strain",
]

_F = TypeVar("_F", bound=Callable[..., Any])


def _arithmetic(function: _F) -> _F:
    """``numba.njit`` for the plain-arithmetic functions (see the module): inlined, IEEE division; typed for mypy."""
    options: dict[str, Any] = {"cache": True, "nogil": True, "inline": "always", "error_model": "numpy"}
    decorator: Callable[[_F], _F] = njit(**options)
    return decorator(function)


def array_form(function: Callable[..., Any]) -> Callable[..., Any]:
    """A plain-arithmetic function of this module as Python (numba's ``.py_func``), for whole arrays.

    The same operations on numpy or JAX arrays as the compiled function on
    scalars (see the module), e.g. ``array_form(drag_stress)(lam, rho, v)``.
    A plain-arithmetic function that calls others of this module (e.g.
    :func:`post_necking_force`) calls their array forms in turn: its
    Python is rebound to them, so that it is written once for both.
    """
    python: Callable[..., Any] = getattr(function, "py_func", function)
    return _composed(python)


@functools.cache
def _composed(python: Callable[..., Any]) -> Callable[..., Any]:
    """``python`` with the compiled functions of this module that it names replaced by their array forms."""
    code = getattr(python, "__code__", None)
    scope: dict[str, Any] = getattr(python, "__globals__", {})
    if code is None or scope is not globals():
        return python
    calls = {name: array_form(scope[name]) for name in code.co_names
             if getattr(getattr(scope.get(name), "py_func", None), "__module__", None) == __name__}
    if not calls:
        return python
    rebound = types.FunctionType(code, {**scope, **calls}, python.__name__, python.__defaults__, python.__closure__)
    rebound.__doc__ = python.__doc__
    return rebound


@njit(cache=True, nogil=True)
def viscoelastic_stress(k_m: float, strain: float) -> float:
    """Visco-elastic (Maxwell) stress ``f_e1 = k_m (z_i - z_m)`` [Pa], Eq. (2).

    Parameters
    ----------
    k_m : float
        Maxwell stiffness of the active branch (``k_m_i`` or ``k_m_w``) [Pa/m].
    strain : float
        Element extension ``z_i - z_m`` [m].
    """
    return k_m * strain


@_arithmetic
def maxwell_strain_rate(velocity: float, mud_velocity: float) -> float:
    """Eq. (3) as a rate: ``de/dt = dz_i/dt - dz_m/dt`` [m/s], with ``dz_m/dt = e / tau`` on a branch.

    For an integrator of the coupled dynamics (the built-in engine); the
    sampled paths step Eq. (3) in closed form (:func:`maxwell_strain_step`).
    Plain arithmetic (see the module).

    Parameters
    ----------
    velocity : float
        Foot velocity ``dz_i/dt`` [m/s].
    mud_velocity : float
        Mud velocity ``dz_m/dt`` [m/s] (the second value of :func:`intrusion_stress` or
        :func:`withdrawal_stress`).
    """
    return velocity - mud_velocity


@njit(cache=True, nogil=True)
def relaxation_time(k_m: float, b_m: float) -> float:
    """Relaxation time of a Maxwell branch ``tau = b_m / k_m`` [s], Eq. (3).

    Parameters
    ----------
    k_m : float
        Maxwell stiffness of the branch [Pa/m], Eq. (2).
    b_m : float
        Maxwell damping of the branch [Pa s/m], Eq. (2).
    """
    return b_m / k_m


@njit(cache=True, nogil=True)
def maxwell_strain_step(strain: float, velocity: float, tau: float, decay: float) -> float:
    """Closed-form step of the Maxwell element, Eq. (3), under first-order hold.

    With ``e = z_i - z_m`` and ``b dz_m/dt + k z_m = k z_i`` (Eq. (3)), a
    foot moving at constant ``velocity`` over the step gives
    ``de/dt = v - e / tau``, so ``e(h) = v tau + (e(0) - v tau) exp(-h / tau)``.
    This is docs/model.md's ``z_m(t+dt)`` formula written for ``e``.
    Plain arithmetic (see the module).

    Parameters
    ----------
    strain : float
        ``e(0) = z_i - z_m`` at the start of the step [m].
    velocity : float
        Foot velocity ``dz_i/dt`` over the step [m/s] (positive down).
    tau : float
        Relaxation time ``b_m / k_m`` of the active branch [s].
    decay : float
        ``exp(-h / tau)`` for the step length ``h`` [-].

    Returns
    -------
    float
        ``e(h)`` [m].
    """
    # written as e(0) decay + v tau (1 - decay) so that a loop carrying e
    # waits for one multiply and one add per step, not three operations
    return strain * decay + velocity * tau * (1.0 - decay)


@njit(cache=True, nogil=True, inline="always")  # inlined: the loops vectorise over it
def nonlinear_spring_stress(alpha: float, beta: float, depth: float, width: float) -> float:
    """Nonlinear spring stress ``f_e2 = alpha (max(z_i, 0) / H)^beta`` [Pa], Eq. (4).

    Parameters
    ----------
    alpha : float
        Spring stiffness [Pa].
    beta : float
        Exponent in (0, 1] [-].
    depth : float
        Foot depth ``z_i`` [m]; zero stress at or above the surface.
    width : float
        Intruder width ``H`` [m].
    """
    if depth <= 0.0:
        return 0.0
    return float(alpha * power(depth / width, beta))


@njit(cache=True, nogil=True)
def drag_stress(lambda_: float, rho_m: float, velocity: float) -> float:
    """Velocity-squared drag ``f_s = sign(v) lambda rho_m v^2`` [Pa], Eq. (5).

    Parameters
    ----------
    lambda_ : float
        Drag scaling factor [-].
    rho_m : float
        Mud density [kg/m^3].
    velocity : float
        Foot velocity ``dz_i/dt`` [m/s] (positive down).

    Notes
    -----
    The paper's ``sign(0) = +1`` makes no difference here: ``v^2 = 0``.
    It acts only while the foot is below the surface (:func:`drag_acts`,
    :func:`submerged_drag_stress`; docs/model.md).
    """
    return lambda_ * rho_m * velocity * abs(velocity)


@_arithmetic
def drag_acts(depth: float) -> bool:
    """Whether the drag of Eq. (5) acts: only while the foot is below the surface, ``z_i > 0`` (docs/model.md).

    The one statement of the drag's gate; :func:`submerged_drag_stress`
    applies it in the compiled paths, ``where(drag_acts(z), ...)`` on
    arrays. Plain arithmetic (see the module).

    Parameters
    ----------
    depth : float
        Depth ``z_i`` [m] at which the drag is evaluated, positive down.
    """
    return depth > 0.0


@njit(cache=True, nogil=True, inline="always")
def submerged_drag_stress(lambda_: float, rho_m: float, velocity: float, depth: float) -> float:
    """The drag stress [Pa] of Eq. (5) where it acts (:func:`drag_acts`), else 0.

    Parameters
    ----------
    lambda_ : float
        Drag scaling factor [-].
    rho_m : float
        Mud density [kg/m^3].
    velocity : float
        Foot velocity ``dz_i/dt`` [m/s] (positive down).
    depth : float
        Depth ``z_i`` [m] at which the drag is evaluated, positive down.
    """
    return drag_stress(lambda_, rho_m, velocity) if drag_acts(depth) else 0.0


@_arithmetic
def piece_midpoint_depth(depth: float, velocity: float, length: float) -> float:
    """The depth [m] at the middle of a piece of a step, where the drag's gate is decided (ours).

    A step of the sampled paths is split where the foot crosses the surface,
    so no piece crosses it and its midpoint ``z_a + v length / 2`` tells
    whether the drag of Eq. (5) acts over it (:func:`drag_acts`), robustly
    for a piece that starts or ends on the surface. Plain arithmetic (see the module).

    Parameters
    ----------
    depth : float
        Depth ``z_a`` [m] at the piece's start, positive down.
    velocity : float
        Foot velocity over the piece [m/s].
    length : float
        The piece's length [s].
    """
    return depth + 0.5 * velocity * length


#: Eq. (7)'s response (:func:`neck_filter_response`): below this ``x = w_d t`` (or ``mu t``) ``sin(x) / w_d``
#: (``sinh(x) / mu``) is its series ``t (1 -+ x^2 / 6)`` [-] (ours: the division loses digits as ``x -> 0``).
NECK_FILTER_SERIES_BELOW = 1e-6
#: Eq. (7)'s overdamped response: from ``mu t`` this large on, only its slow mode is kept
#: (:func:`neck_filter_slow_mode`) [-] (ours: ``cosh``, ``sinh`` overflow long before the product does).
NECK_FILTER_SLOW_MODE_FROM = 30.0


@njit(cache=True, nogil=True)
def neck_filter_response(age: float, zeta: float, omega_0: float) -> tuple[float, float]:
    """Impulse response of the post-necking filter ``G_m(s)``, Eq. (7), and its integral.

    ``G_m(s) = s / (s^2 + 2 zeta omega_0 s + omega_0^2)`` is the velocity
    response of the lumped mass-spring-damper ``z'' + 2 zeta omega_0 z' +
    omega_0^2 z = 0`` with ``z(0) = 0, z'(0) = 1`` (Section II-B of the paper).

    Parameters
    ----------
    age : float
        Time since necking ``t - t_n`` [s], >= 0.
    zeta : float
        Damping ratio [-], any value > 0 (underdamped, critical, overdamped).
    omega_0 : float
        Natural frequency [rad/s].

    Returns
    -------
    g : float
        Normalised mud velocity ``dz_m/dt / v_m0`` [-]; ``g(0) = 1``, ``g -> 0``.
    G : float
        Normalised mud displacement since necking ``(z_m - z_m(t_n)) / v_m0`` [s].
    """
    # The scalar control flow (a branch per regime); the JAX step's computes every regime and
    # selects (mudforce.jax.neck_filter_response). The arithmetic and the thresholds are shared.
    a = zeta * omega_0
    decay = math.exp(-a * age)
    if zeta < 1.0:
        wd = omega_0 * math.sqrt(1.0 - zeta * zeta)
        x = wd * age
        # sin(x)/wd, evaluated as age*sinc(x) near x = 0 (zeta -> 1-)
        s_over = math.sin(x) / wd if x > NECK_FILTER_SERIES_BELOW else neck_filter_sine_series(age, x)
        return neck_filter_closed_form(decay, math.cos(x), s_over, a)
    if zeta == 1.0:
        return neck_filter_closed_form(decay, 1.0, age, a)
    mu = omega_0 * math.sqrt(zeta * zeta - 1.0)
    x = mu * age
    if x < NECK_FILTER_SLOW_MODE_FROM:
        sh_over = math.sinh(x) / mu if x > NECK_FILTER_SERIES_BELOW else neck_filter_sinh_series(age, x)
        return neck_filter_closed_form(decay, math.cosh(x), sh_over, a)
    # large mu*age: cosh and sinh overflow long before the product does;
    # keep only the slow mode (the fast one is below exp(-60) of it)
    return neck_filter_slow_mode(0.5 * math.exp((mu - a) * age), a, mu)


@_arithmetic
def neck_filter_sine_series(age: float, x: float) -> float:
    """``sin(x) / w_d`` [s] near ``x = w_d t = 0``: ``t (1 - x^2 / 6)``, Eq. (7)'s underdamped response (ours).

    Used below :data:`NECK_FILTER_SERIES_BELOW`. Plain arithmetic (see the module).

    Parameters
    ----------
    age : float
        Time since necking ``t`` [s].
    x : float
        ``w_d t`` [-], ``w_d = omega_0 sqrt(1 - zeta^2)``.
    """
    return age * (1.0 - x * x / 6.0)


@_arithmetic
def neck_filter_sinh_series(age: float, x: float) -> float:
    """``sinh(x) / mu`` [s] near ``x = mu t = 0``: ``t (1 + x^2 / 6)``, Eq. (7)'s overdamped response (ours).

    Used below :data:`NECK_FILTER_SERIES_BELOW`. Plain arithmetic (see the module).

    Parameters
    ----------
    age : float
        Time since necking ``t`` [s].
    x : float
        ``mu t`` [-], ``mu = omega_0 sqrt(zeta^2 - 1)``.
    """
    return age * (1.0 + x * x / 6.0)


@_arithmetic
def neck_filter_slow_mode(slow: float, rate: float, mu: float) -> tuple[float, float]:
    """Eq. (7)'s overdamped response ``(g, G)`` by its slow mode alone (ours), past :data:`NECK_FILTER_SLOW_MODE_FROM`.

    ``g = slow (1 - a / mu)``, ``G = slow / mu`` with ``slow = exp((mu - a) t) / 2``: the fast mode is below
    ``exp(-60)`` of it there. Plain arithmetic (see the module).

    Parameters
    ----------
    slow : float
        ``exp((mu - a) t) / 2`` [-].
    rate : float
        ``a = zeta omega_0`` [1/s].
    mu : float
        ``omega_0 sqrt(zeta^2 - 1)`` [1/s].

    Returns
    -------
    g : float
        [-].
    G : float
        [s].
    """
    return slow * (1.0 - rate / mu), slow / mu


@_arithmetic
def neck_filter_closed_form(decay: float, c: float, s_over: float, rate: float) -> tuple[float, float]:
    """Eq. (7)'s impulse response ``g`` and its integral ``G`` from the elementary functions of the age.

    With ``a = zeta omega_0`` (``rate``) the response of
    :func:`neck_filter_response` at age ``t`` is, in each damping regime,
    ``g = exp(-a t) (c - a s)``, ``G = exp(-a t) s`` with
    ``(c, s) = (cos x, sin(x) / w_d)`` (``x = w_d t``, underdamped),
    ``(1, t)`` (critical) or ``(cosh y, sinh(y) / mu)`` (``y = mu t``,
    overdamped). This is the arithmetic that combines them, the same
    operations as :func:`neck_filter_response`'s; the caller computes
    ``decay = exp(-a t)``, ``c`` and ``s``. Both responses call it: the
    compiled :func:`neck_filter_response` (a branch per regime) and the
    JAX step's (:func:`mudforce.jax.neck_filter_response`, which computes
    every regime and selects). Plain arithmetic (see the module).

    Parameters
    ----------
    decay : float
        ``exp(-zeta omega_0 t)`` [-].
    c : float
        ``cos x``, ``1`` or ``cosh y`` [-].
    s_over : float
        ``sin(x) / w_d``, ``t`` or ``sinh(y) / mu`` [s].
    rate : float
        ``a = zeta omega_0`` [1/s].

    Returns
    -------
    g : float
        ``g(t)`` [-].
    G : float
        ``G(t)`` [s].
    """
    return decay * (c - rate * s_over), decay * s_over


@njit(cache=True, nogil=True)
def necking_time(
    strain: float,
    velocity: float,
    tau_w: float,
    k_m_w: float,
    drag: float,
    sigma_y: float,
    length: float,
    decay: float,
) -> float:
    """First instant in a withdrawal interval at which the neck breaks, Eq. (9).

    The withdrawal stress is ``f(t) = k_m_w e(t) + f_s`` with ``e(t)`` from
    :func:`maxwell_strain_step`. The neck breaks when ``f < -sigma_y``
    (suction only; docs/model.md). ``e(t)`` is monotone within the interval, so
    the root is unique and has the closed form
    ``t* = -tau_w log((e* - v tau_w) / (e(0) - v tau_w))``,
    ``e* = (-sigma_y - f_s) / k_m_w``.

    Parameters
    ----------
    strain : float
        ``z_i - z_m`` at the interval's start [m].
    velocity : float
        Foot velocity over the interval [m/s] (negative: withdrawing).
    tau_w : float
        ``b_m_w / k_m_w`` [s].
    k_m_w : float
        Withdrawal stiffness [Pa/m].
    drag : float
        Drag stress ``f_s`` over the interval [Pa], Eq. (5) (0 above the surface).
    sigma_y : float
        Yield stress [Pa].
    length : float
        Interval length [s].
    decay : float
        ``exp(-length / tau_w)`` [-].

    Returns
    -------
    float
        Time from the interval's start to necking [s], in ``[0, length]``,
        or ``-1.0`` if the neck does not break within the interval.
    """
    if neck_breaks(k_m_w, strain, drag, sigma_y):
        return 0.0
    # the strain at the interval's end exactly as the stepper computes it
    end = maxwell_strain_step(strain, velocity, tau_w, decay)
    if not neck_breaks(k_m_w, end, drag, sigma_y):
        return -1.0
    target = yield_strain(k_m_w, sigma_y, drag)
    t = -tau_w * math.log1p(necking_fraction(strain, velocity, tau_w, target))
    if t < 0.0:
        return 0.0
    if t > length:
        return length
    return t


@_arithmetic
def necking_fraction(strain: float, velocity: float, tau_w: float, target: float) -> float:
    """``(e* - e(0)) / (e(0) - v tau_w)`` [-]: the necking instant is ``t* = -tau_w log1p(this)``, Eq. (9).

    From :func:`maxwell_strain_step`'s ``e(t) = v tau_w + (e(0) - v tau_w) exp(-t / tau_w)`` set to
    ``e* =`` :func:`yield_strain`. Plain arithmetic (see the module); :func:`necking_time` clips the root.

    Parameters
    ----------
    strain : float
        ``e(0) = z_i - z_m`` at the interval's start [m].
    velocity : float
        Foot velocity over the interval [m/s].
    tau_w : float
        ``b_m_w / k_m_w`` [s].
    target : float
        The yield strain ``e*`` [m] (:func:`yield_strain`).
    """
    return (target - strain) / (strain - velocity * tau_w)


@_arithmetic
def neck_breaks(k_m_w: float, strain: float, drag: float, sigma_y: float) -> bool:
    """Whether the neck yields, Eq. (9): the withdrawal stress ``k_m_w e + f_s`` is below ``-sigma_y``.

    Suction only (docs/model.md); the one statement of the necking test.
    Plain arithmetic (see the module).

    Parameters
    ----------
    k_m_w : float
        Withdrawal stiffness [Pa/m].
    strain : float
        Maxwell strain ``e = z_i - z_m`` [m].
    drag : float
        Drag stress ``f_s`` [Pa], Eq. (5) (0 above the surface).
    sigma_y : float
        Yield stress [Pa].
    """
    return k_m_w * strain + drag < -sigma_y


@_arithmetic
def yield_strain(k_m_w: float, sigma_y: float, drag: float) -> float:
    """The extension ``z_i - z_m`` [m] at which the withdrawal stress is ``-sigma_y``, Eq. (9).

    ``k_m_w e* + f_s = -sigma_y``: the neck breaks there (docs/model.md).
    Plain arithmetic (see the module).

    Parameters
    ----------
    k_m_w : float
        Withdrawal stiffness [Pa/m].
    sigma_y : float
        Yield stress [Pa].
    drag : float
        Drag stress ``f_s`` [Pa], Eq. (5).
    """
    return (-sigma_y - drag) / k_m_w


@_arithmetic
def necking_velocity(strain: float, tau_w: float) -> float:
    """``v_m0 = dz_m/dt = (z_i - z_m) / tau_w`` [m/s], the mud velocity at necking, Eqs. (3), (7).

    Plain arithmetic (see the module).

    Parameters
    ----------
    strain : float
        ``z_i - z_m`` at necking [m].
    tau_w : float
        ``b_m_w / k_m_w`` [s].
    """
    return strain / tau_w


@_arithmetic
def intrusion_stress(k_m_i: float, tau_i: float, strain: float) -> tuple[float, float]:
    """The intrusion (and hold) branch's visco-elastic stress and mud velocity, Eqs. (2), (3).

    Plain arithmetic (see the module). The branch's force adds the spring,
    Eq. (4), and the drag, Eq. (5): :func:`total_stress`.

    Parameters
    ----------
    k_m_i : float
        Intrusion stiffness [Pa/m].
    tau_i : float
        ``b_m_i / k_m_i`` [s].
    strain : float
        ``z_i - z_m`` [m].

    Returns
    -------
    f_e1 : float
        ``k_m_i (z_i - z_m)`` [Pa], Eq. (2).
    mud_velocity : float
        ``dz_m/dt = (z_i - z_m) / tau_i`` [m/s], Eq. (3).
    """
    return k_m_i * strain, strain / tau_i


@_arithmetic
def withdrawal_stress(k_m_w: float, tau_w: float, strain: float) -> tuple[float, float]:
    """The withdrawal branch's visco-elastic stress and mud velocity before necking, Eqs. (2), (3), (8).

    As :func:`intrusion_stress` with the withdrawal constants; the branch
    has no spring (``f_e2 = 0``). Plain arithmetic (see the module).

    Returns
    -------
    f_e1 : float
        ``k_m_w (z_i - z_m)`` [Pa].
    mud_velocity : float
        ``dz_m/dt = (z_i - z_m) / tau_w`` [m/s].
    """
    return k_m_w * strain, strain / tau_w


@_arithmetic
def necked_stress(b_m_w: float, mud_velocity: float) -> tuple[float, float]:
    """After necking the visco-elastic stress is the damper's, ``f_e1 = b_m_w dz_m/dt`` (Eq. (7) and docs/model.md).

    This keeps the force continuous at necking (``b_m_w v_m0 = k_m_w (z_i -
    z_m)`` there). No spring. Plain arithmetic (see the module).

    Parameters
    ----------
    b_m_w : float
        Withdrawal damping [Pa s/m].
    mud_velocity : float
        ``dz_m/dt = v_m0 g(t - t_n)`` [m/s] (:func:`necked_mud_motion`).

    Returns
    -------
    f_e1 : float
        [Pa].
    mud_velocity : float
        ``dz_m/dt`` [m/s], as given.
    """
    return b_m_w * mud_velocity, mud_velocity


@_arithmetic
def total_stress(f_e1: float, f_e2: float, f_s: float) -> float:
    """The mud stress ``f_m = f_e1 + f_e2 + f_s`` [Pa], Eqs. (1), (8); times the area it is the force.

    Summed as ``f_e2 + (f_e1 + f_s)``: every path of the stepper sums in
    this order (the spring's samples are set aside and added last), so
    that they agree bit for bit. ``f_e2 = 0.0`` off the intrusion branch.
    Plain arithmetic (see the module).
    """
    return f_e2 + (f_e1 + f_s)


@_arithmetic
def necked_mud_motion(v_m0: float, z_n: float, g: float, gi: float) -> tuple[float, float]:
    """After necking the mud moves as ``dz_m/dt = v_m0 g(t - t_n)``, Eq. (7).

    Plain arithmetic (see the module).

    Parameters
    ----------
    v_m0 : float
        Mud velocity at necking [m/s] (:func:`necking_velocity`).
    z_n : float
        ``z_m`` at necking [m].
    g, gi : float
        ``g(t - t_n)`` [-] and its integral ``G(t - t_n)`` [s]
        (:func:`neck_filter_response` or :func:`neck_filter_update`).

    Returns
    -------
    mud_velocity : float
        ``dz_m/dt`` [m/s].
    mud : float
        ``z_m = z_n + v_m0 G`` [m].
    """
    return v_m0 * g, z_n + v_m0 * gi


@_arithmetic
def neck_filter_transition(zeta: float, omega_0: float, g_h: float, gi_h: float
                           ) -> tuple[float, float, float, float]:
    """The exact one-step transition matrix of Eq. (7)'s filter over a step ``h``.

    ``g`` and ``G`` (:func:`neck_filter_response`) solve ``z'' + 2 zeta
    omega_0 z' + omega_0^2 z = 0`` (``G = z``, ``g = z'``), so
    ``[G, g](t + h) = [[g_h + 2 zeta omega_0 G_h, G_h], [-omega_0^2 G_h, g_h]] [G, g](t)``
    with ``(g_h, G_h)`` the response at age ``h``. Plain arithmetic (see
    the module).

    Parameters
    ----------
    zeta : float
        Damping ratio [-].
    omega_0 : float
        Natural frequency [rad/s].
    g_h, gi_h : float
        ``neck_filter_response(h, zeta, omega_0)`` [-], [s].

    Returns
    -------
    tuple of float
        ``(phi0, phi1, phi2, phi3)``, the matrix by rows, for
        :func:`neck_filter_update`.
    """
    return g_h + 2.0 * zeta * omega_0 * gi_h, gi_h, -omega_0 * omega_0 * gi_h, g_h


@_arithmetic
def neck_filter_update(phi0: float, phi1: float, phi2: float, phi3: float, gi: float, g: float
                       ) -> tuple[float, float]:
    """``(G, g)`` of Eq. (7)'s filter one step later: the matrix of :func:`neck_filter_transition` times ``(G, g)``.

    Plain arithmetic (see the module).
    """
    return phi0 * gi + phi1 * g, phi2 * gi + phi3 * g


# ----------------------------------------------------------------------------- the foot at rest (dynamics)
@_arithmetic
def rest_band_forces(strain: float, spring_stress: float, k_m_i: float, k_m_w: float,
                     area: float) -> tuple[float, float]:
    """The rest band ``(F_up, F_down)`` [N]: the forces that hold a foot at rest below the surface.

    With the foot at rest (``dz_i/dt = 0``) the model's force (Eq. (1)) is
    set-valued: its two one-sided limits are the branch forces

    * ``F_up = S k_m_w e``: the withdrawal branch as ``v -> 0-``, Eq. (2) with ``k_m_w``;
    * ``F_down = S (k_m_i e + f_e2)``: the intrusion branch as ``v -> 0+``,
      Eq. (2) with ``k_m_i`` plus the nonlinear spring, Eq. (4);

    and the drag of Eq. (5) vanishes at ``v = 0``. A foot at rest sticks
    while the load it carries (positive down) lies in ``[F_up, F_down]``
    (``docs/model.md``, "Coupled with dynamics"). The caller applies the
    state machine: above the surface ``F_down = 0`` (FREE), and after necking
    ``F_up`` is the post-necking force of Eq. (7) instead.

    Plain arithmetic (the spring stress comes in precomputed), so that
    ``rest_band_forces.py_func`` also works on arrays (a JAX step).

    Parameters
    ----------
    strain : float
        Maxwell strain ``e = z_i - z_m`` [m], Eq. (2) (from :func:`maxwell_strain_step`, Eq. (3)).
    spring_stress : float
        Nonlinear spring stress ``f_e2`` [Pa] at the foot's depth, Eq. (4) (:func:`nonlinear_spring_stress`).
    k_m_i : float
        Intrusion-branch Maxwell stiffness [Pa/m].
    k_m_w : float
        Withdrawal-branch Maxwell stiffness [Pa/m].
    area : float
        Foot contact area ``S`` [m^2].

    Returns
    -------
    (float, float)
        ``F_up`` and ``F_down`` [N], positive up (resisting).
    """
    return area * k_m_w * strain, area * (k_m_i * strain + spring_stress)


@_arithmetic
def rest_band_depth_spread(depth_sd: float, spring_below: float, spring_above: float, k_m_i: float, k_m_w: float,
                           area: float) -> tuple[float, float]:
    """How far a depth error moves the rest band's ends: ``(dF_up, dF_down)`` [N] (ours, from Eqs. (2) and (4)).

    A depth read ``depth_sd`` off moves the Maxwell strain ``e = z_i - z_m`` by as much (the mud's ``z_m``
    follows the foot through the dashpot, not at once) and the spring with the depth: ``F_up = S k_m_w e``
    (:func:`rest_band_forces`) by ``S k_m_w depth_sd``, and ``F_down = S (k_m_i e + f_e2)`` by
    ``S (k_m_i depth_sd + (f_e2(z_i + depth_sd) - f_e2(z_i - depth_sd)) / 2)``: the spring's change as a
    central secant, as its slope is unbounded at the surface (Eq. (4) with ``beta < 1``). The MudTracker
    adds these to a residual's scale beyond the band where its depth is noisy. Plain arithmetic (see the module).

    Parameters
    ----------
    depth_sd : float
        The depth's error (a standard deviation) [m], at least 0.
    spring_below, spring_above : float
        Nonlinear spring stress ``f_e2`` [Pa], Eq. (4), at ``z_i - depth_sd`` and ``z_i + depth_sd``
        (:func:`nonlinear_spring_stress`).
    k_m_i, k_m_w, area : float
        The intrusion- and withdrawal-branch Maxwell stiffnesses [Pa/m] and the foot's contact area ``S`` [m^2],
        as :func:`rest_band_forces` takes them.
    """
    return area * k_m_w * depth_sd, area * (k_m_i * depth_sd + 0.5 * (spring_above - spring_below))


@_arithmetic
def post_necking_force(area: float, b_m_w: float, v_m0: float, z_n: float, g: float, gi: float
                       ) -> tuple[float, float]:
    """The post-necking force ``S f_e1`` [N] and the mud's ``z_m`` [m], Eq. (7): a necked foot's ``F_up``.

    ``f_e1 = b_m_w dz_m/dt`` (:func:`necked_stress`) with the mud moving as
    ``dz_m/dt = v_m0 g``, ``z_m = z_n + v_m0 G`` (:func:`necked_mud_motion`).
    The rest band's upward limit after necking (:func:`rest_band_forces`);
    without drag, as at rest. Plain arithmetic (see the module).

    Parameters
    ----------
    area : float
        Foot contact area ``S`` [m^2].
    b_m_w : float
        Withdrawal damping [Pa s/m].
    v_m0 : float
        Mud velocity at necking [m/s] (:func:`necking_velocity`).
    z_n : float
        ``z_m`` at necking [m].
    g, gi : float
        ``g(t - t_n)`` [-] and ``G(t - t_n)`` [s] of :func:`neck_filter_response`.

    Returns
    -------
    force : float
        ``S b_m_w v_m0 g`` [N], positive up.
    mud : float
        ``z_m`` [m].
    """
    mud_velocity, mud = necked_mud_motion(v_m0, z_n, g, gi)
    return area * necked_stress(b_m_w, mud_velocity)[0], mud


@_arithmetic
def rest_band_blend(weight: float, at_start: float, at_end: float) -> float:
    """A bound of the rest band for a coming time step [N]: ``(1 - weight) F(start) + weight F(end)`` (ours).

    ``F(end)`` is the bound after a trial step on its own branch (docs/model.md,
    "Coupled with dynamics"); ``weight = 0`` is explicit (the band lags a
    step), ``1`` suits a semi-implicit Euler step. Plain arithmetic (see the module).

    Parameters
    ----------
    weight : float
        Weight of the step's predicted end [-], in ``[0, 1]``.
    at_start, at_end : float
        The bound (``F_up`` or ``F_down``) at the step's start and at its predicted end [N].
    """
    return (1.0 - weight) * at_start + weight * at_end


# ----------------------------------------------------------------------------- forms for float32 (the JAX step)
# Plain-arithmetic forms of Eqs. (3) and (7) that hold their digits in float32. The
# compiled CPU stepper keeps its own forms above (its bits must not move); the JAX step
# (mudforce.jax) calls these through .py_func, in float32 and float64 alike. Each equals
# its CPU counterpart in exact arithmetic; tests/model/test_float32_forms.py checks that
# they agree to a few ulp in float64 and that these are the more accurate in float32.
@_arithmetic
def maxwell_strain_increment(strain: float, velocity: float, tau: float, growth: float) -> float:
    """:func:`maxwell_strain_step` (Eq. (3) in closed form) in increment form: ``e(h) = e(0) + (v tau - e(0)) growth``.

    ``growth = 1 - exp(-h / tau)``, which the caller computes as
    ``-expm1(-h / tau)``. In exact arithmetic this is
    ``maxwell_strain_step(e, v, tau, 1 - growth)``. Used by the JAX step
    (:mod:`mudforce.jax`) because of float32: there ``1 - exp(-h/tau)``
    formed from a rounded ``exp(-h/tau)`` at ``h/tau ~ 1e-3`` keeps only
    about four digits, which biases the element's relaxation rate by up to
    3e-5 (2.8e-5 of the peak force over a 10 s gait at 1 kHz), while
    ``expm1`` keeps them all. In float64 the two forms agree to a few ulp.
    Plain arithmetic (see the module).

    Parameters
    ----------
    strain : float
        ``e(0) = z_i - z_m`` at the start of the step [m].
    velocity : float
        Foot velocity ``dz_i/dt`` over the step [m/s] (positive down).
    tau : float
        Relaxation time ``b_m / k_m`` of the active branch [s].
    growth : float
        ``1 - exp(-h / tau) = -expm1(-h / tau)`` for the step length ``h`` [-].

    Returns
    -------
    float
        ``e(h)`` [m].
    """
    return strain + (velocity * tau - strain) * growth


@_arithmetic
def neck_filter_response_increment(decay_m1: float, c_m1: float, s_over: float, rate: float) -> float:
    """``g(h) - 1`` of Eq. (7)'s response over a step ``h``, from ``exp(-a h) - 1`` and ``c - 1``.

    ``g(h) = exp(-a h) (c - a s)`` (:func:`neck_filter_closed_form`), so
    ``g(h) - 1 = (e - 1)(c - a s) + (c - 1) - a s``, with ``e - 1 = expm1(-a h)``
    and ``c - 1 = -2 sin^2(x/2)`` (underdamped), ``0`` (critical) or
    ``2 sinh^2(y/2)`` (overdamped) passed in. At a short step ``g(h)`` is
    within ``~omega_0 h`` of 1, and ``g(h) - 1`` formed from a rounded
    ``g(h)`` keeps only three or four digits in float32 at 1 kHz; this form
    keeps them all. Used by the JAX step (:mod:`mudforce.jax`) for
    :func:`neck_filter_transition_increment`. Plain arithmetic (see the module).

    Parameters
    ----------
    decay_m1 : float
        ``exp(-zeta omega_0 h) - 1`` [-].
    c_m1 : float
        ``cos x - 1``, ``0`` or ``cosh y - 1`` [-].
    s_over : float
        ``sin(x) / w_d``, ``h`` or ``sinh(y) / mu`` [s].
    rate : float
        ``a = zeta omega_0`` [1/s].

    Returns
    -------
    float
        ``g(h) - 1`` [-].
    """
    return decay_m1 * (c_m1 + 1.0 - rate * s_over) + c_m1 - rate * s_over


@_arithmetic
def neck_filter_transition_increment(zeta: float, omega_0: float, g_h_m1: float, gi_h: float
                                     ) -> tuple[float, float, float, float]:
    """Eq. (7)'s one-step transition matrix minus the identity: :func:`neck_filter_transition` less ``I``.

    ``Phi - I = [[g_h - 1 + 2 zeta omega_0 G_h, G_h], [-omega_0^2 G_h, g_h - 1]]``,
    taking ``g_h - 1`` (:func:`neck_filter_response_increment`) rather than
    ``g_h``: the diagonal of ``Phi`` is within ``~omega_0 h`` of 1, so in
    float32 ``Phi`` itself would keep only its first few digits of the
    step's change. Used, with :func:`neck_filter_update_increment`, by the
    JAX step (:mod:`mudforce.jax`); equal to ``neck_filter_transition``
    minus the identity in exact arithmetic. Plain arithmetic (see the module).

    Parameters
    ----------
    zeta : float
        Damping ratio [-].
    omega_0 : float
        Natural frequency [rad/s].
    g_h_m1, gi_h : float
        ``g(h) - 1`` [-] and ``G(h)`` [s] of :func:`neck_filter_response`.

    Returns
    -------
    tuple of float
        ``(phi0 - 1, phi1, phi2, phi3 - 1)``, the rows of ``Phi - I``.
    """
    return g_h_m1 + 2.0 * zeta * omega_0 * gi_h, gi_h, -omega_0 * omega_0 * gi_h, g_h_m1


@_arithmetic
def neck_filter_update_increment(d0: float, phi1: float, phi2: float, d3: float, gi: float, g: float
                                 ) -> tuple[float, float]:
    """``(G, g)`` of Eq. (7)'s filter one step later as ``x + (Phi - I) x``: :func:`neck_filter_update`, increment form.

    ``(d0, phi1, phi2, d3)`` is :func:`neck_filter_transition_increment`.
    Used by the JAX step (:mod:`mudforce.jax`), for float32 (see there);
    equal to :func:`neck_filter_update` in exact arithmetic. Plain
    arithmetic (see the module).

    Parameters
    ----------
    d0, phi1, phi2, d3 : float
        ``Phi - I`` by rows [-], [s], [1/s], [-].
    gi, g : float
        ``G`` [s] and ``g`` [-] now.

    Returns
    -------
    (float, float)
        ``G`` [s] and ``g`` [-] one step later.
    """
    return gi + (d0 * gi + phi1 * g), g + (phi2 * gi + d3 * g)
