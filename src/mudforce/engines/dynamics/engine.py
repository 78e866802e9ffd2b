"""The built-in engine: a foot of mass ``m`` dropped into mud, integrated event-driven (:func:`simulate_foot`).

``m d^2 z_i/dt^2 = m g + F_applied(t) - F_mud`` with ``F_mud`` the model's
force on the branch of the current :class:`~mudforce.engines.dynamics.result.Phase`
(Eqs. (1)-(9)) and sticking at rest inside the rest band
(:func:`~mudforce.engines.dynamics.rest_band.rest_band`). Between events the motion
is a smooth ODE in ``(z_i, dz_i/dt, e)``, integrated with classical
Runge-Kutta (RK4) on a fixed sub-step ``h``; every branch change (velocity
through zero), touchdown, necking (Eq. (9)), surface crossing (the drag
switches off) and the end of sticking is located by bisection to 1e-14 s
and the phase switched there (:mod:`mudforce.engines.dynamics` explains the method
and its error). A stuck foot does not move at all: no chatter, no ratcheting.

Every equation and rule is the physics layer's (:mod:`mudforce.model.equations`:
the branch stresses and their one sum, the Maxwell element as a rate, the
drag's gate, the necking test and velocity, Eq. (7)'s response; the rest
band through :mod:`mudforce.engines.dynamics.rest_band`). What is written here
is this engine's own control flow: the phases, the events and their
bisection, and the RK4 integration between them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mudforce._kernel import ContactMode, params_from_row, params_row
from mudforce._plumbing.deprecation import warn_renamed
from mudforce._plumbing.jit import njit
from mudforce.engines._checks import check_finite_output, check_foot, check_mass, check_params
from mudforce.engines.dynamics.rest_band import necked_force, rest_band
from mudforce.engines.dynamics.result import GRAVITY, FootResult, Phase
from mudforce.errors import InputError, finite_number, is_real, number_within, positive_int, real_array, shown
from mudforce.io.tables import COLUMN_LIMITS
from mudforce.model.bounds import MAX_DEPTH, MIN_DT, bounded_depth, check_gravity, check_step, max_samples
from mudforce.model.equations import (
    intrusion_stress,
    maxwell_strain_rate,
    neck_breaks,
    neck_filter_response,
    necked_mud_motion,
    necked_stress,
    necking_velocity,
    nonlinear_spring_stress,
    submerged_drag_stress,
    total_stress,
    withdrawal_stress,
)
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.velocity import VelocityFilter

__all__ = ["simulate_foot"]

# aux layout (per foot): necking data and whether a stuck foot is necked
A_TN = 0  # necking instant t_n [s]
A_VM0 = 1  # mud velocity at necking v_m0 [m/s]
A_ZN = 2  # z_m at necking [m]
A_STUCK_NECKED = 3  # 1.0 when STUCK after necking
N_AUX = 4

_EVENT_TOL = 1e-14  # [s]
_MAX_EVENTS_PER_STEP = 32


@njit(cache=True, nogil=True)
def _interp(x: float, xp: np.ndarray, fp: np.ndarray) -> float:
    """``np.interp(x, xp, fp)`` for one ``x`` and ``xp`` strictly increasing (2 or more points), to the bit.

    Speed plumbing, not physics: numpy's arithmetic (``arr_interp`` in its ``compiled_base.c``, which numba's
    ``np.interp`` copies) without numba's general ``np.interp``, whose compile took about 4 s of every cold
    start of the engine for this one scalar call. ``tests/engines/test_dynamics.py`` checks it against
    ``np.interp``.
    """
    n = xp.shape[0]
    if x != x:  # NaN in, NaN out
        return x
    if x < xp[0]:
        return float(fp[0])
    if x >= xp[n - 1]:  # numpy: past the end, fp[-1]; at the last point, fp[-1] too
        return float(fp[n - 1])
    lo, hi = 0, n - 1  # xp[lo] <= x < xp[hi]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xp[mid] <= x:
            lo = mid
        else:
            hi = mid
    if xp[lo] == x:
        return float(fp[lo])
    slope: float = (fp[lo + 1] - fp[lo]) / (xp[lo + 1] - xp[lo])
    y: float = slope * (x - xp[lo]) + fp[lo]
    if y != y:  # numpy: NaN one way, try the other
        y = slope * (x - xp[lo + 1]) + fp[lo + 1]
        if y != y and fp[lo] == fp[lo + 1]:
            y = fp[lo]
    return y


@njit(cache=True, nogil=True)
def _load(t: float, mg: float, tp: np.ndarray, fp: np.ndarray) -> float:
    """Load the mud must carry, ``m g + F_applied(t)`` [N], positive down."""
    if tp.shape[0] == 0:
        return mg
    if tp.shape[0] == 1:
        return float(mg + fp[0])
    return float(mg + _interp(t, tp, fp))


@njit(cache=True, nogil=True)
def _neck(p: np.ndarray, aux: np.ndarray, t: float) -> tuple[float, float]:
    """Post-necking force [N] (Eq. (7), damper stress times area) and ``z_m`` [m] at time ``t``."""
    return necked_force(p, aux[A_VM0], aux[A_ZN], t - aux[A_TN])


@njit(cache=True, nogil=True)
def _mud_force(phase: int, t: float, z: float, v: float, e: float, p: np.ndarray, aux: np.ndarray,
               load: float) -> float:
    """Mud force on the foot [N], positive up, in each phase (STUCK: the reaction ``load``).

    The branch stresses and their sum are the equations', as in the stepper
    (:func:`mudforce._kernel.sample_outputs`): the branch's ``f_e1`` (Eqs. (2), (7)), the spring
    on the intrusion branch (Eq. (4)), the drag below the surface (Eq. (5)), summed by
    :func:`mudforce.model.equations.total_stress` and times the area.
    """
    q = params_from_row(p)
    area = q.area
    fs = submerged_drag_stress(q.lam, q.rho_m, v, z)
    if phase == Phase.INTRUSION:
        fe1, _ = intrusion_stress(q.k_i, q.tau_i, e)
        return float(area * total_stress(fe1, nonlinear_spring_stress(q.alpha, q.beta, z, q.width), fs))
    if phase == Phase.WITHDRAWAL:
        fe1, _ = withdrawal_stress(q.k_w, q.tau_w, e)
        return float(area * total_stress(fe1, 0.0, fs))
    if phase == Phase.NECKED:
        g, g_int = neck_filter_response(t - aux[A_TN], q.zeta, q.omega_0)
        fe1, _ = necked_stress(q.b_w, necked_mud_motion(aux[A_VM0], aux[A_ZN], g, g_int)[0])
        return float(area * total_stress(fe1, 0.0, fs))
    if phase == Phase.STUCK:
        return load
    return 0.0


@njit(cache=True, nogil=True)
def _rhs(phase: int, t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, m: float, mg: float,
         tp: np.ndarray, fp: np.ndarray, dy: np.ndarray) -> None:
    """Time derivative of ``y = (z_i, dz_i/dt, e)`` [m, m/s, m] in a phase (Eqs. (1)-(5), (7))."""
    z = y[0]
    v = y[1]
    e = y[2]
    q = params_from_row(p)
    if phase == Phase.STUCK:
        dy[0] = 0.0
        dy[1] = 0.0
        # Filippov: at rest the Maxwell element relaxes on the intrusion branch, Eq. (3)
        dy[2] = 0.0 if aux[A_STUCK_NECKED] != 0.0 else maxwell_strain_rate(0.0, intrusion_stress(q.k_i, q.tau_i, e)[1])
        return
    load = _load(t, mg, tp, fp)
    force = _mud_force(phase, t, z, v, e, p, aux, load)
    dy[0] = v
    dy[1] = (load - force) / m
    if phase == Phase.INTRUSION:
        dy[2] = maxwell_strain_rate(v, intrusion_stress(q.k_i, q.tau_i, e)[1])
    elif phase == Phase.WITHDRAWAL:
        dy[2] = maxwell_strain_rate(v, withdrawal_stress(q.k_w, q.tau_w, e)[1])
    else:
        dy[2] = 0.0


@njit(cache=True, nogil=True)
def _rk4(phase: int, t: float, y: np.ndarray, h: float, p: np.ndarray, aux: np.ndarray, m: float, mg: float,
         tp: np.ndarray, fp: np.ndarray, work: np.ndarray, out: np.ndarray) -> None:
    """One classical Runge-Kutta step of length ``h`` [s] from ``y`` into ``out``."""
    k1 = work[0]
    k2 = work[1]
    k3 = work[2]
    k4 = work[3]
    tmp = work[4]
    _rhs(phase, t, y, p, aux, m, mg, tp, fp, k1)
    for i in range(3):
        tmp[i] = y[i] + 0.5 * h * k1[i]
    _rhs(phase, t + 0.5 * h, tmp, p, aux, m, mg, tp, fp, k2)
    for i in range(3):
        tmp[i] = y[i] + 0.5 * h * k2[i]
    _rhs(phase, t + 0.5 * h, tmp, p, aux, m, mg, tp, fp, k3)
    for i in range(3):
        tmp[i] = y[i] + h * k3[i]
    _rhs(phase, t + h, tmp, p, aux, m, mg, tp, fp, k4)
    for i in range(3):
        out[i] = y[i] + h * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0


@njit(cache=True, nogil=True)
def _band(t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, necked: bool | np.bool_) -> tuple[float, float]:
    """``(F_up, F_down)`` [N] of a foot at rest at time ``t`` (necked or in contact)."""
    if necked:
        f_neck, zm = _neck(p, aux, t)
        # (.value: the mode as the int64 every other caller passes, one compiled signature, not one more per enum)
        return rest_band(p, ContactMode.NECKED.value, y[0], y[0] - zm, f_neck)
    return rest_band(p, ContactMode.CONTACT.value, y[0], y[2], 0.0)


@njit(cache=True, nogil=True)
def _event(phase: int, t0: float, y0: np.ndarray, t1: float, y1: np.ndarray, p: np.ndarray, aux: np.ndarray,
           mg: float, tp: np.ndarray, fp: np.ndarray) -> int:
    """Which event (if any) happened between ``(t0, y0)`` and ``(t1, y1)``: 0 none, else a code.

    1 velocity through zero (a stop), 2 touchdown or surface crossing,
    3 necking (Eq. (9)), 4 sticking ends downward, 5 sticking ends upward.
    """
    if phase == Phase.FREE:
        return 2 if (y1[0] > 0.0) else 0
    if phase == Phase.INTRUSION:
        return 1 if y1[1] < 0.0 else 0
    if phase == Phase.STUCK:
        load = _load(t1, mg, tp, fp)
        f_up, f_down = _band(t1, y1, p, aux, aux[A_STUCK_NECKED] != 0.0)
        if load > f_down:
            return 4
        if load < f_up:
            return 5
        return 0
    if y1[1] > 0.0:  # WITHDRAWAL or NECKED: moving up until now
        return 1
    if (y0[0] > 0.0) != (y1[0] > 0.0):
        return 2
    if phase == Phase.WITHDRAWAL:
        q = params_from_row(p)
        if neck_breaks(q.k_w, y1[2], submerged_drag_stress(q.lam, q.rho_m, y1[1], y1[0]), q.sigma_y):
            return 3
    return 0


@njit(cache=True, nogil=True)
def _decide_at_rest(t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, mg: float, tp: np.ndarray,
                    fp: np.ndarray, necked: bool | np.bool_) -> Phase:
    """Filippov's choice for a foot at rest: slide down, slide up, or stick. Sets ``y``, returns the phase.

    (Its callers pass ``np.bool_(False)``, not ``False``: numba types a constant as a literal and compiles a
    callee once more for it; speed plumbing, the same bits.)
    """
    y[1] = 0.0
    load = _load(t, mg, tp, fp)
    f_up, f_down = _band(t, y, p, aux, necked)
    if load > f_down:
        if y[0] <= 0.0:
            y[2] = 0.0
            return Phase.FREE  # docs/model.md: the intrusion branch above the surface is FREE
        if necked:
            _, zm = _neck(p, aux, t)
            y[2] = y[0] - zm  # NECKED -> CONTACT keeps z_m
        return Phase.INTRUSION
    if load < f_up:
        return Phase.NECKED if necked else Phase.WITHDRAWAL
    aux[A_STUCK_NECKED] = 1.0 if necked else 0.0
    return Phase.STUCK


@njit(cache=True, nogil=True)
def _apply_event(code: int, phase: Phase, t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, mg: float,
                 tp: np.ndarray, fp: np.ndarray) -> Phase:
    """The phase after an event located at ``(t, y)``."""
    if phase == Phase.FREE:  # touchdown: CONTACT from the crossing, with z_m = 0 there (docs/model.md)
        y[2] = y[0]
        if y[1] > 0.0:
            return Phase.INTRUSION
        return _decide_at_rest(t, y, p, aux, mg, tp, fp, np.bool_(False))
    if phase == Phase.STUCK:
        necked = aux[A_STUCK_NECKED] != 0.0
        aux[A_STUCK_NECKED] = 0.0
        if code == 4:
            if y[0] <= 0.0:
                y[2] = 0.0
                return Phase.FREE
            if necked:
                _, zm = _neck(p, aux, t)
                y[2] = y[0] - zm
            return Phase.INTRUSION
        return Phase.NECKED if necked else Phase.WITHDRAWAL
    if code == 1:
        if phase == Phase.NECKED and y[0] <= 0.0:
            y[1] = 0.0
            y[2] = 0.0
            return Phase.FREE  # NECKED moving down above the surface: FREE (docs/model.md)
        return _decide_at_rest(t, y, p, aux, mg, tp, fp, phase == Phase.NECKED)
    if code == 3:  # necking inside the step, Eq. (9): v_m0 = dz_m/dt = e / tau_w
        aux[A_TN] = t
        aux[A_VM0] = necking_velocity(y[2], params_from_row(p).tau_w)
        aux[A_ZN] = y[0] - y[2]
        return Phase.NECKED
    return phase  # a surface crossing only restarts the step (the drag switches there)


@njit(cache=True, nogil=True)
def _integrate(p: np.ndarray, m: float, gravity: float, z0: float, v0: float, t_out: np.ndarray, substeps: int,
               tp: np.ndarray, fp: np.ndarray, depth: np.ndarray, velocity: np.ndarray, force: np.ndarray,
               phase_out: np.ndarray, strain_out: np.ndarray) -> int:
    """Event-driven RK4 over the output times; returns the number of events located."""
    mg = m * gravity
    aux = np.zeros(N_AUX)
    y = np.array([z0, v0, 0.0])
    ytry = np.empty(3)
    ylo = np.empty(3)
    work = np.empty((5, 3))
    t = t_out[0]
    if z0 > 0.0:
        # a foot that starts below the surface starts in CONTACT with relaxed mud (docs/model.md)
        if v0 > 0.0:
            phase = Phase.INTRUSION
        elif v0 < 0.0:
            phase = Phase.WITHDRAWAL
        else:
            phase = _decide_at_rest(t, y, p, aux, mg, tp, fp, np.bool_(False))
    else:
        phase = Phase.FREE
    events = 0
    n = t_out.shape[0]
    for k in range(n):
        target = t_out[k]
        while k > 0 and t < target:
            h_full = (t_out[k] - t_out[k - 1]) / substeps
            h = min(h_full, target - t)
            if target - (t + h) < 1e-12 * h_full:
                h = target - t
            count = 0
            while True:
                _rk4(phase, t, y, h, p, aux, m, mg, tp, fp, work, ytry)
                code = _event(phase, t, y, t + h, ytry, p, aux, mg, tp, fp)
                if code == 0 or count >= _MAX_EVENTS_PER_STEP:
                    break
                # bisection for the earliest instant at which the event has happened
                lo = 0.0
                hi = h
                for _ in range(200):
                    if hi - lo <= _EVENT_TOL:
                        break
                    mid = 0.5 * (lo + hi)
                    _rk4(phase, t, y, mid, p, aux, m, mg, tp, fp, work, ylo)
                    c = _event(phase, t, y, t + mid, ylo, p, aux, mg, tp, fp)
                    if c != 0:
                        hi = mid
                        code = c
                        for i in range(3):
                            ytry[i] = ylo[i]
                    else:
                        lo = mid
                t += hi  # ytry holds the state at t + hi
                for i in range(3):
                    y[i] = ytry[i]
                phase = _apply_event(code, phase, t, y, p, aux, mg, tp, fp)
                events += 1
                count += 1
                h = h - hi
                if h <= 0.0:
                    break
            if h > 0.0 and (code == 0 or count >= _MAX_EVENTS_PER_STEP):
                t += h
                for i in range(3):
                    y[i] = ytry[i]
        depth[k] = y[0]
        velocity[k] = y[1]
        strain_out[k] = y[2]
        load = _load(t, mg, tp, fp)
        force[k] = _mud_force(phase, t, y[0], y[1], y[2], p, aux, load)
        phase_out[k] = phase
    return events


def simulate_foot(
    mass: float,
    params: MudParameters,
    foot: Foot | None = None,
    *,
    duration: float = 8.0,
    dt: float = 1e-3,
    substeps: int = 10,
    height: float = 0.0,
    velocity0: float = 0.0,
    applied_force: Any = None,
    gravity: float = GRAVITY,
    depth0: float | None = None,
) -> FootResult:
    """Simulate a one-degree-of-freedom foot of mass ``m`` falling into mud (the built-in engine).

    ``m d^2 z_i/dt^2 = m g + F_applied(t) - F_mud``, with ``F_mud`` the
    model's force (Eqs. (1)-(9)) and sticking at rest (:mod:`mudforce.engines.dynamics`),
    integrated event-driven with RK4.

    Parameters
    ----------
    mass : float
        Foot mass [kg]; at least ``S max(k_m_i, k_m_w) h^2`` for the RK4 sub-step
        ``h = dt / substeps`` (about 3e-5 kg for Table I's muds, the paper's foot
        and ``h = 0.1 ms``), so that the step resolves the foot's oscillation on
        the mud (``h sqrt(S k_m / m) <= 1``).
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry (area ``S`` [m^2], width ``H`` [m]); the paper's 51 x 38 mm cuboid by default.
    duration : float
        Simulated time [s], at least ``dt``; at most 1e8 output samples (``duration / dt``).
    dt : float
        Output sampling interval [s], within [1e-9, 1000] (:data:`mudforce.steppers.simulation.MIN_DT`,
        :data:`~mudforce.steppers.simulation.MAX_DT`).
    substeps : int
        RK4 steps per output interval (default 10: ``h = 0.1 ms`` for ``dt = 1 ms``); at most ``dt / 1e-9``
        (a sub-step of at least :data:`~mudforce.steppers.simulation.MIN_DT`).
    height : float
        Release height of the foot's bottom above the mud surface [m], positive up (as everywhere a drop
        starts: :func:`mudforce.engines.mujoco.simulate_drop`, :func:`mudforce.engines.mjx.simulate_drop`,
        :func:`mudforce.references.drop.exact_drop`); negative starts it that far inside fresh mud. Within
        +-100 m (:data:`mudforce.steppers.simulation.MAX_DEPTH`).
    velocity0 : float
        Initial velocity [m/s], positive down.
    applied_force : float, or (times, forces) arrays, optional
        Extra force on the foot [N], positive DOWN (pushing it into the mud);
        a pair of arrays is interpolated linearly in time [s] (held outside).
    gravity : float
        Gravitational acceleration [m/s^2], positive down, within [0, 1e4] (about 1000 g, beyond the geotechnical
        centrifuges that test muds). A negative one is refused (MuJoCo's sign, ``-9.81``, given by habit threw the
        foot up): an upward load is a negative ``applied_force``; zero leaves the applied force alone.
    depth0 : float, optional
        Deprecated: the initial depth [m], positive down; ``height = -depth0``.

    Returns
    -------
    FootResult

    Raises
    ------
    InputError
        For any input of the wrong type or outside the bounds above, and if
        the solution is not finite anyway (a custom mud or applied force the
        step cannot follow): the first sample time where it is not is named.
    """
    params = check_params(params)
    foot = check_foot(foot)
    duration = finite_number(duration, "duration", "s", positive=True)
    dt = finite_number(dt, "dt", "s", positive=True)
    gravity = check_gravity(gravity)
    if depth0 is not None:  # deprecated in 0.2, for height (positive up, as every drop's start)
        warn_renamed("simulate_foot(depth0=...)", "simulate_foot(height=-depth0)")
        if height != 0.0:
            raise InputError("give height [m] only (depth0 is its deprecated, negated form)")
        z0 = bounded_depth(depth0, "depth0", of=" of the mud surface")
    else:  # the stepper's bound on a depth, as every other path refuses it
        z0 = 0.0 - bounded_depth(height, "height", of=" of the mud surface")  # (0.0 - 0.0 is +0.0)
    # a recording's velocity bound (mudforce.io.tables.COLUMN_LIMITS): 1e6 m/s left the foot 27 km up after 2 s
    most = COLUMN_LIMITS["velocity"]
    velocity0 = number_within(finite_number(velocity0, "velocity0", "m/s"), "velocity0", -most, most, "m/s")
    substeps = positive_int(substeps, "substeps")
    check_step(dt)  # as naive_drop: dt = 1e308 then 10**400 substeps raised OverflowError
    if substeps > dt / MIN_DT:  # (int against float, exact: dt / 10**400 raised OverflowError)
        raise InputError(f"substeps must be an integer in [1, {math.floor(dt / MIN_DT + 1e-9):d}] (an RK4 "
                         f"sub-step dt / substeps of at least {MIN_DT:g} s, the shortest step accepted), got "
                         f"{shown(substeps)}")
    mass = check_mass(mass, params, foot, dt / substeps, "RK4 sub-step")
    n = max_samples(duration, dt)
    p = params_row(params, foot, VelocityFilter.exact())
    tp, fp = _profile(applied_force)
    t_out = np.arange(n) * dt
    depth = np.empty(n)
    velocity = np.empty(n)
    force = np.empty(n)
    phase = np.empty(n, dtype=np.int8)
    strain = np.empty(n)
    events = _integrate(p, mass, gravity, z0, velocity0, t_out, substeps, tp, fp,
                        depth, velocity, force, phase, strain)
    check_finite_output("built-in", t_out, depth, velocity, force)
    beyond = np.flatnonzero(np.abs(depth) > MAX_DEPTH)
    if beyond.size:  # the model's depth bound, as every path refuses a depth (a foot thrown 1 km up was returned)
        k = int(beyond[0])
        raise InputError(f"the built-in engine's foot leaves the model's depth bound (+-{MAX_DEPTH:g} m of the mud "
                         f"surface) at t = {t_out[k]:g} s (depth {depth[k]:.4g} m); use a smaller initial speed or "
                         "applied force, or a shorter duration")
    return FootResult(t_out, depth, velocity, force, phase, mass, gravity, "builtin", int(events), strain)


def _profile(applied_force: Any) -> tuple[np.ndarray, np.ndarray]:
    if applied_force is None:
        return np.empty(0), np.empty(0)
    if is_real(applied_force):  # (float() of 10**400 raised OverflowError)
        return np.zeros(1), np.array([finite_number(applied_force, "applied force", "N")])
    # a pair of arrays of real numbers (np.ascontiguousarray parsed strings, "01" was times 0 and 1 s, and read
    # booleans as 0 and 1)
    if not (isinstance(applied_force, (tuple, list)) or (isinstance(applied_force, np.ndarray)
                                                         and applied_force.ndim == 2)) or len(applied_force) != 2:
        raise InputError("applied_force must be a number [N] or a pair (times [s], forces [N])")
    tp = np.ascontiguousarray(real_array(applied_force[0], "applied_force times", "s"))
    fp = np.ascontiguousarray(real_array(applied_force[1], "applied_force forces", "N"))
    if tp.ndim != 1 or tp.shape != fp.shape or tp.size == 0:
        raise InputError("applied_force times and forces must be 1-D arrays of the same, non-zero length")
    with np.errstate(over="ignore"):  # times 1e308 s apart: their step is inf, the slope of the force 0
        steps = np.diff(tp)
    if not (np.isfinite(tp).all() and np.isfinite(fp).all() and np.isfinite(steps).all()) or np.any(steps <= 0.0):
        raise InputError("applied_force times must be finite and strictly increasing (steps within float64's range, "
                         "+-1.8e308 s), forces finite")
    return tp, fp


