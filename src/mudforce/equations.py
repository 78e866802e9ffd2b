"""The paper's equations as small pure functions (compiled with numba).

Each function computes one equation of Chen, Yi & Shan (2024),
arXiv:2403.02617, in SI. They are scalar, side-effect free and callable
from Python as well as from the compiled stepper in :mod:`mudforce._kernel`.

Sign conventions (``../shared/MODEL.md``): depth ``z_i`` is positive
downward, below the undisturbed surface; a positive stress pushes the foot
up (resistance), a negative one pulls it down (suction).
"""

from __future__ import annotations

import math

from numba import njit

from mudforce._pow import power

__all__ = [
    "drag_stress",
    "maxwell_strain_step",
    "neck_filter_response",
    "necking_time",
    "nonlinear_spring_stress",
    "rest_band_forces",
    "viscoelastic_stress",
]


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


@njit(cache=True, nogil=True)
def maxwell_strain_step(strain: float, velocity: float, tau: float, decay: float) -> float:
    """Closed-form step of the Maxwell element, Eq. (3), under first-order hold.

    With ``e = z_i - z_m`` and ``b dz_m/dt + k z_m = k z_i`` (Eq. (3)), a
    foot moving at constant ``velocity`` over the step gives
    ``de/dt = v - e / tau``, so ``e(h) = v tau + (e(0) - v tau) exp(-h / tau)``.
    This is MODEL.md's ``z_m(t+dt)`` formula written for ``e``.

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
    The caller applies it only while the foot is below the surface (MODEL.md).
    """
    return lambda_ * rho_m * velocity * abs(velocity)


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
    a = zeta * omega_0
    decay = math.exp(-a * age)
    if zeta < 1.0:
        wd = omega_0 * math.sqrt(1.0 - zeta * zeta)
        x = wd * age
        # sin(x)/wd, evaluated as age*sinc(x) near x = 0 (zeta -> 1-)
        s_over = math.sin(x) / wd if x > 1e-6 else age * (1.0 - x * x / 6.0)
        return decay * (math.cos(x) - a * s_over), decay * s_over
    if zeta == 1.0:
        return decay * (1.0 - a * age), decay * age
    mu = omega_0 * math.sqrt(zeta * zeta - 1.0)
    x = mu * age
    if x < 30.0:
        sh_over = math.sinh(x) / mu if x > 1e-6 else age * (1.0 + x * x / 6.0)
        return decay * (math.cosh(x) - a * sh_over), decay * sh_over
    # large mu*age: cosh and sinh overflow long before the product does;
    # keep only the slow mode (the fast one is below exp(-60) of it)
    slow = 0.5 * math.exp((mu - a) * age)
    return slow * (1.0 - a / mu), slow / mu


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
    (suction only; MODEL.md). ``e(t)`` is monotone within the interval, so
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
    if k_m_w * strain + drag < -sigma_y:
        return 0.0
    # the strain at the interval's end exactly as the stepper computes it
    end = maxwell_strain_step(strain, velocity, tau_w, decay)
    if k_m_w * end + drag >= -sigma_y:
        return -1.0
    vt = velocity * tau_w
    target = (-sigma_y - drag) / k_m_w
    t = -tau_w * math.log1p((target - strain) / (strain - vt))
    if t < 0.0:
        return 0.0
    if t > length:
        return length
    return t


# ----------------------------------------------------------------------------- the foot at rest (dynamics)
@njit(cache=True, nogil=True)
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
