"""The mud model coupled with rigid-body dynamics: sticking, a built-in engine, the exact drop.

When the foot's motion is simulated rather than prescribed, the force law is
set-valued at zero velocity (``../shared/MODEL.md``, "Coupled with
dynamics"): moving down the mud resists on the intrusion branch, moving up
on the withdrawal branch, and a foot at rest can carry any load between the
two. This module implements that as a hybrid system.

The foot at rest: the sticking band
------------------------------------
With the Maxwell strain ``e = z_i - z_m`` [m] and the foot at rest at depth
``z_i > 0``, the two one-sided limits of the force (Eqs. (1)-(5) with
``dz_i = 0``, so no drag) are

    F_down = S (k_m_i e + alpha (z_i / H)^beta)     intrusion branch, v -> 0+
    F_up   = S k_m_w e                              withdrawal branch, v -> 0-

The foot sticks while the load it must carry, ``L = m g + F_applied``
(positive down), lies in ``[F_up, F_down]``; the contact force is then
``L`` itself (a reaction, like static friction), and the Maxwell element
relaxes with the intrusion parameters, ``de/dt = -e / tau_i`` (Filippov's
solution; ``sign(0) = +1`` in the paper). The foot slides down once
``L > F_down`` and up once ``L < F_up``. After necking (NECKED) the upward
limit is the post-necking force ``b_m_w v_m0 g(t - t_n)`` (Eq. (7)) and the
downward limit the intrusion force with the necked mud's ``z_m``.

Two ways to solve it, and their errors
--------------------------------------
* Event-driven (:func:`simulate_foot`, the built-in engine): between events
  the motion is a smooth ODE in ``(z_i, dz_i/dt, e)``, integrated with
  classical Runge-Kutta (RK4) on a fixed sub-step ``h``; every branch change
  (velocity through zero), touchdown, necking (Eq. (9)), surface crossing
  (the drag switches off) and the end of sticking is located by bisection
  to 1e-14 s and the phase switched there. The error is RK4's ``O(h^4)``
  inside phases plus the event tolerance; at rest the foot stays exactly
  at rest (no chatter, no ratcheting: a stuck foot does not move at all).
  Near touchdown the nonlinear spring ``z^beta`` is not smooth, which costs
  a little accuracy near touchdown: about 1e-5 of the depth for ``h = 0.1 ms``.
* Time-stepping (:class:`mudforce.mujoco.MudAdapter`): a simulator with a
  fixed step ``dt`` cannot locate events; it treats the band like dry
  friction in an implicit (Moreau-Jean) step: the force is the clamp of
  the force that stops the foot within the step to ``[F_up, F_down]``, with
  the band taken from the mud state at the step's start. The foot sticks
  in one step, never overshoots the band, and does not chatter; the error
  is first order in ``dt`` (the band lags one step, and a stop inside a
  step is resolved at the step's end).

A naive explicit coupling (branch from the sign of the last velocity) puts
the full intrusion force on a foot that has just stopped, throws it up onto
the withdrawal branch, then drops it back: it chatters every step, and as
the intrusion branch carries the weight only on the way down, it ratchets
the foot deeper. :func:`naive_drop` reproduces that for comparison.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numba import njit

from mudforce import _kernel as K
from mudforce.equations import drag_stress, neck_filter_response, nonlinear_spring_stress
from mudforce.errors import InputError, positive_int
from mudforce.foot import Foot
from mudforce.parameters import MudParameters
from mudforce.simulation import params_row
from mudforce.velocity import VelocityFilter

__all__ = [
    "GRAVITY",
    "PHASE_NAMES",
    "ExactDrop",
    "FootResult",
    "branch_forces",
    "exact_drop",
    "naive_drop",
    "rest_band",
    "simulate_foot",
]

#: Standard gravity [m/s^2] (MuJoCo's default ``0 0 -9.81``).
GRAVITY = 9.81

# phases of the coupled foot
FREE = 0
INTRUSION = 1
WITHDRAWAL = 2
STUCK = 3
NECKED = 4
#: Phase names, indexed by the codes in :attr:`FootResult.phase`.
PHASE_NAMES: tuple[str, ...] = ("FREE", "INTRUSION", "WITHDRAWAL", "STUCK", "NECKED")

# aux layout (per foot): necking data and whether a stuck foot is necked
A_TN = 0  # necking instant t_n [s]
A_VM0 = 1  # mud velocity at necking v_m0 [m/s]
A_ZN = 2  # z_m at necking [m]
A_STUCK_NECKED = 3  # 1.0 when STUCK after necking
N_AUX = 4

_EVENT_TOL = 1e-14  # [s]
_MAX_EVENTS_PER_STEP = 32


# ----------------------------------------------------------------------------- band at rest
@njit(cache=True, nogil=True)
def rest_band(p: np.ndarray, mode: int, depth: float, strain: float, neck_force: float) -> tuple[float, float]:
    """The force band ``(F_up, F_down)`` [N] of a foot at rest (see the module docstring).

    Parameters
    ----------
    p : ndarray
        One params row of :mod:`mudforce._kernel` (mud parameters in SI, area ``S`` [m^2], width ``H`` [m]).
    mode : int
        Kernel contact state: 0 FREE, 1 CONTACT, 2 NECKED.
    depth : float
        Foot depth ``z_i`` [m], positive down.
    strain : float
        Maxwell strain ``e = z_i - z_m`` [m], Eq. (2).
    neck_force : float
        Post-necking force ``S b_m_w v_m0 g(t - t_n)`` [N], Eq. (7) (used when NECKED).

    Returns
    -------
    (float, float)
        ``F_up`` (withdrawal branch, ``v -> 0-``) and ``F_down`` (intrusion
        branch, ``v -> 0+``) [N], positive up. Above the surface the
        intrusion branch is FREE (0 N); FREE gives ``(0, 0)``.
    """
    area = p[K.P_AREA]
    if mode == K.FREE:
        return 0.0, 0.0
    f_down = 0.0
    if depth > 0.0:
        f_down = area * (p[K.P_K_I] * strain + nonlinear_spring_stress(p[K.P_ALPHA], p[K.P_BETA], depth,
                                                                      p[K.P_WIDTH]))
    if mode == K.NECKED:
        return neck_force, f_down
    return area * p[K.P_K_W] * strain, f_down


@njit(cache=True, nogil=True)
def branch_forces(states: np.ndarray, params: np.ndarray, dt: float, weight: float, f_up: np.ndarray,
                  f_down: np.ndarray, drag: np.ndarray) -> None:
    """Sticking band of every foot for the coming step, from its kernel state (no commit).

    For row ``j`` of ``states``/``params`` (the layout of :mod:`mudforce._kernel`),
    writes the band ``[f_up[j], f_down[j]]`` [N] of :func:`rest_band` to use
    over a step of ``dt`` [s], and the drag force ``drag[j] = S lambda rho_m v|v|``
    [N] at the last step's velocity ``v`` (Eq. (5), positive up for a foot
    moving down; zero above the surface).

    The band is ``(1 - weight)`` times the band at the step's start plus
    ``weight`` times the band at the step's predicted end, where each bound
    is the force a trial step on a copy of the state would give on its own
    branch: ``F_down`` after moving at ``max(v, 0)`` on the intrusion branch,
    ``F_up`` after moving at ``min(v, 0)`` on the withdrawal branch (the
    Maxwell strain advanced in closed form, Eq. (3)). ``weight = 0`` is
    explicit (the band lags a step); ``1`` (used by the MuJoCo adapter) is
    consistent with a semi-implicit Euler step, whose position update uses
    the new velocity. A foot that has not started, or is FREE, gets ``0, 0``
    unless it touches down within the step.
    """
    for j in range(states.shape[0]):
        s = states[j]
        p = params[j]
        mode = int(s[K.S_MODE])
        z = s[K.S_DEPTH]
        v = s[K.S_VELOCITY]
        area = p[K.P_AREA]
        if s[K.S_STARTED] == 0.0 or mode == K.FREE:
            f_up[j] = 0.0
            f_down[j] = 0.0
            drag[j] = 0.0
            if s[K.S_STARTED] != 0.0 and z + v * dt > 0.0 and weight > 0.0:
                # touchdown within the step: the intrusion force at the predicted end, z_m = 0 at the surface
                z1 = z + v * dt
                lo, hi = rest_band(p, K.CONTACT, z1, z1 if z < 0.0 else z1 - z, 0.0)
                f_down[j] = weight * hi
                f_up[j] = weight * min(lo, hi)
            continue
        # each bound is its own branch's force at the predicted end of the step:
        # down with v >= 0 on the intrusion branch, up with v <= 0 on the withdrawal branch
        v_dn = max(v, 0.0)
        v_up = min(v, 0.0)
        z_dn = z + v_dn * dt
        z_up = z + v_up * dt
        if mode == K.NECKED:
            g0, i0 = neck_filter_response(s[K.S_NECK_AGE], p[K.P_ZETA], p[K.P_OMEGA_0])
            g1, i1 = neck_filter_response(s[K.S_NECK_AGE] + dt, p[K.P_ZETA], p[K.P_OMEGA_0])
            vm = s[K.S_NECK_V]
            lo0, hi0 = rest_band(p, mode, z, z - (s[K.S_NECK_Z] + vm * i0), area * p[K.P_B_W] * vm * g0)
            zm1 = s[K.S_NECK_Z] + vm * i1
            _, hi1 = rest_band(p, mode, z_dn, z_dn - zm1, 0.0)
            lo1 = area * p[K.P_B_W] * vm * g1
        else:
            e0 = z - s[K.S_MUD]
            lo0, hi0 = rest_band(p, mode, z, e0, 0.0)
            # Eq. (3) in closed form (maxwell_strain_step) on each branch
            tau_i = p[K.P_TAU_I]
            tau_w = p[K.P_TAU_W]
            e_dn = v_dn * tau_i + (e0 - v_dn * tau_i) * math.exp(-dt / tau_i)
            e_up = v_up * tau_w + (e0 - v_up * tau_w) * math.exp(-dt / tau_w)
            _, hi1 = rest_band(p, mode, z_dn, e_dn, 0.0)
            lo1, _ = rest_band(p, mode, z_up, e_up, 0.0)
        f_up[j] = (1.0 - weight) * lo0 + weight * lo1
        f_down[j] = (1.0 - weight) * hi0 + weight * hi1
        drag[j] = area * drag_stress(p[K.P_LAMBDA], p[K.P_RHO_M], v) if z > 0.0 else 0.0


# ----------------------------------------------------------------------------- the built-in engine
@njit(cache=True, nogil=True)
def _load(t: float, mg: float, tp: np.ndarray, fp: np.ndarray) -> float:
    """Load the mud must carry, ``m g + F_applied(t)`` [N], positive down."""
    if tp.shape[0] == 0:
        return mg
    if tp.shape[0] == 1:
        return float(mg + fp[0])
    return float(mg + np.interp(t, tp, fp))


@njit(cache=True, nogil=True)
def _neck(p: np.ndarray, aux: np.ndarray, t: float) -> tuple[float, float]:
    """Post-necking force [N] (Eq. (7), damper stress times area) and ``z_m`` [m] at time ``t``."""
    g, g_int = neck_filter_response(t - aux[A_TN], p[K.P_ZETA], p[K.P_OMEGA_0])
    return p[K.P_AREA] * p[K.P_B_W] * aux[A_VM0] * g, aux[A_ZN] + aux[A_VM0] * g_int


@njit(cache=True, nogil=True)
def _mud_force(phase: int, t: float, z: float, v: float, e: float, p: np.ndarray, aux: np.ndarray,
               load: float) -> float:
    """Mud force on the foot [N], positive up, in each phase (STUCK: the reaction ``load``)."""
    area = p[K.P_AREA]
    fs = drag_stress(p[K.P_LAMBDA], p[K.P_RHO_M], v) if z > 0.0 else 0.0
    if phase == INTRUSION:
        return float(area * (p[K.P_K_I] * e + nonlinear_spring_stress(p[K.P_ALPHA], p[K.P_BETA], z, p[K.P_WIDTH])
                             + fs))
    if phase == WITHDRAWAL:
        return float(area * (p[K.P_K_W] * e + fs))
    if phase == NECKED:
        f_neck, _ = _neck(p, aux, t)
        return float(f_neck + area * fs)
    if phase == STUCK:
        return load
    return 0.0


@njit(cache=True, nogil=True)
def _rhs(phase: int, t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, m: float, mg: float,
         tp: np.ndarray, fp: np.ndarray, dy: np.ndarray) -> None:
    """Time derivative of ``y = (z_i, dz_i/dt, e)`` [m, m/s, m] in a phase (Eqs. (1)-(5), (7))."""
    z = y[0]
    v = y[1]
    e = y[2]
    if phase == STUCK:
        dy[0] = 0.0
        dy[1] = 0.0
        # Filippov: at rest the Maxwell element relaxes on the intrusion branch, Eq. (3)
        dy[2] = 0.0 if aux[A_STUCK_NECKED] != 0.0 else -e / p[K.P_TAU_I]
        return
    load = _load(t, mg, tp, fp)
    force = _mud_force(phase, t, z, v, e, p, aux, load)
    dy[0] = v
    dy[1] = (load - force) / m
    if phase == INTRUSION:
        dy[2] = v - e / p[K.P_TAU_I]
    elif phase == WITHDRAWAL:
        dy[2] = v - e / p[K.P_TAU_W]
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
def _band(t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, necked: bool) -> tuple[float, float]:
    """``(F_up, F_down)`` [N] of a foot at rest at time ``t`` (necked or in contact)."""
    if necked:
        f_neck, zm = _neck(p, aux, t)
        return rest_band(p, K.NECKED, y[0], y[0] - zm, f_neck)
    return rest_band(p, K.CONTACT, y[0], y[2], 0.0)


@njit(cache=True, nogil=True)
def _event(phase: int, t0: float, y0: np.ndarray, t1: float, y1: np.ndarray, p: np.ndarray, aux: np.ndarray,
           mg: float, tp: np.ndarray, fp: np.ndarray) -> int:
    """Which event (if any) happened between ``(t0, y0)`` and ``(t1, y1)``: 0 none, else a code.

    1 velocity through zero (a stop), 2 touchdown or surface crossing,
    3 necking (Eq. (9)), 4 sticking ends downward, 5 sticking ends upward.
    """
    if phase == FREE:
        return 2 if (y1[0] > 0.0) else 0
    if phase == INTRUSION:
        return 1 if y1[1] < 0.0 else 0
    if phase == STUCK:
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
    if phase == WITHDRAWAL:
        fs = drag_stress(p[K.P_LAMBDA], p[K.P_RHO_M], y1[1]) if y1[0] > 0.0 else 0.0
        if p[K.P_K_W] * y1[2] + fs < -p[K.P_SIGMA_Y]:
            return 3
    return 0


@njit(cache=True, nogil=True)
def _decide_at_rest(t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, mg: float, tp: np.ndarray,
                    fp: np.ndarray, necked: bool) -> int:
    """Filippov's choice for a foot at rest: slide down, slide up, or stick. Sets ``y``, returns the phase."""
    y[1] = 0.0
    load = _load(t, mg, tp, fp)
    f_up, f_down = _band(t, y, p, aux, necked)
    if load > f_down:
        if y[0] <= 0.0:
            y[2] = 0.0
            return FREE  # MODEL.md: the intrusion branch above the surface is FREE
        if necked:
            _, zm = _neck(p, aux, t)
            y[2] = y[0] - zm  # NECKED -> CONTACT keeps z_m
        return INTRUSION
    if load < f_up:
        return NECKED if necked else WITHDRAWAL
    aux[A_STUCK_NECKED] = 1.0 if necked else 0.0
    return STUCK


@njit(cache=True, nogil=True)
def _apply_event(code: int, phase: int, t: float, y: np.ndarray, p: np.ndarray, aux: np.ndarray, mg: float,
                 tp: np.ndarray, fp: np.ndarray) -> int:
    """The phase after an event located at ``(t, y)``."""
    if phase == FREE:  # touchdown: CONTACT from the crossing, with z_m = 0 there (MODEL.md)
        y[2] = y[0]
        if y[1] > 0.0:
            return INTRUSION
        return _decide_at_rest(t, y, p, aux, mg, tp, fp, False)
    if phase == STUCK:
        necked = aux[A_STUCK_NECKED] != 0.0
        aux[A_STUCK_NECKED] = 0.0
        if code == 4:
            if y[0] <= 0.0:
                y[2] = 0.0
                return FREE
            if necked:
                _, zm = _neck(p, aux, t)
                y[2] = y[0] - zm
            return INTRUSION
        return NECKED if necked else WITHDRAWAL
    if code == 1:
        if phase == NECKED and y[0] <= 0.0:
            y[1] = 0.0
            y[2] = 0.0
            return FREE  # NECKED moving down above the surface: FREE (MODEL.md)
        return _decide_at_rest(t, y, p, aux, mg, tp, fp, phase == NECKED)
    if code == 3:  # necking inside the step, Eq. (9): v_m0 = dz_m/dt = e / tau_w
        aux[A_TN] = t
        aux[A_VM0] = y[2] / p[K.P_TAU_W]
        aux[A_ZN] = y[0] - y[2]
        return NECKED
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
        # a foot that starts below the surface starts in CONTACT with relaxed mud (MODEL.md)
        if v0 > 0.0:
            phase = INTRUSION
        elif v0 < 0.0:
            phase = WITHDRAWAL
        else:
            phase = _decide_at_rest(t, y, p, aux, mg, tp, fp, False)
    else:
        phase = FREE
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


@dataclass(frozen=True, eq=False)
class FootResult:
    """A simulated foot in mud: one entry per output sample.

    Attributes
    ----------
    time : ndarray
        Sample times [s].
    depth : ndarray
        Foot depth ``z_i`` [m], positive down.
    velocity : ndarray
        Foot velocity ``dz_i/dt`` [m/s], positive down.
    force : ndarray
        Mud force on the foot [N], positive up (while STUCK: the load carried).
    phase : ndarray of int8
        Codes into :data:`PHASE_NAMES`: FREE, INTRUSION, WITHDRAWAL, STUCK, NECKED.
    mass : float
        Foot mass [kg].
    gravity : float
        Gravity [m/s^2].
    engine : str
        ``"builtin"`` or ``"mujoco"``.
    events : int
        Number of located events (builtin engine; 0 otherwise).
    strain : ndarray
        Maxwell strain ``z_i - z_m`` [m] (NaN where an engine does not report it).
    """

    time: np.ndarray
    depth: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    phase: np.ndarray
    mass: float
    gravity: float = GRAVITY
    engine: str = "builtin"
    events: int = 0
    strain: np.ndarray = field(default_factory=lambda: np.empty(0))

    @property
    def phase_names(self) -> list[str]:
        """Each sample's phase as a name."""
        return [PHASE_NAMES[int(c)] for c in self.phase]

    @property
    def rest_depth(self) -> float:
        """Depth at the last sample [m]."""
        return float(self.depth[-1])

    def force_std(self, last: float = 1.0) -> float:
        """Standard deviation of the force over the last ``last`` seconds [N]."""
        sel = self.time >= self.time[-1] - last - 1e-12
        return float(np.std(self.force[sel]))

    def to_csv(self, path: str | os.PathLike[str]) -> None:
        """Write ``time_s, depth_m, velocity_m_s, force_N, state`` as CSV, atomically."""
        from mudforce.io import atomic_open

        names = self.phase_names
        with atomic_open(path, "w") as handle:
            handle.write("time_s,depth_m,velocity_m_s,force_N,state\n")
            for i in range(self.time.size):
                handle.write(f"{self.time[i]:.9g},{self.depth[i] + 0.0:.12g},{self.velocity[i] + 0.0:.12g},"
                             f"{self.force[i]:.12g},{names[i]}\n")

    def plot(self, path: str | os.PathLike[str] | None = None, *, title: str | None = None) -> Any:
        """Depth, velocity and force over time, phases shaded (needs matplotlib); saved as PNG if ``path``."""
        from mudforce._optional import require

        require("matplotlib", "plot", "plotting")
        from matplotlib.figure import Figure

        fig = Figure(figsize=(8.0, 7.0))
        axes = fig.subplots(3, 1, sharex=True)
        colours = {"INTRUSION": "#cfe3f7", "WITHDRAWAL": "#fbd9b5", "STUCK": "#d5efd0", "NECKED": "#f3c6c6"}
        series = ((self.depth * 1e3, "depth [mm]"), (self.velocity * 1e3, "velocity [mm/s]"),
                  (self.force, "mud force [N]"))
        change = np.flatnonzero(np.diff(self.phase.astype(np.int64))) + 1
        starts = np.concatenate(([0], change))
        ends = np.concatenate((change, [self.phase.size - 1]))
        for ax, (data, label) in zip(axes, series, strict=True):
            for s, e in zip(starts, ends, strict=True):
                colour = colours.get(PHASE_NAMES[int(self.phase[s])])
                if colour is not None:
                    ax.axvspan(self.time[s], self.time[e], color=colour, lw=0)
            ax.plot(self.time, data, color="k", lw=1.0)
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        from matplotlib.patches import Patch

        shown = {PHASE_NAMES[int(c)] for c in np.unique(self.phase)}
        handles = [Patch(color=c, label=name) for name, c in colours.items() if name in shown]
        if handles:
            axes[0].legend(handles=handles, loc="lower right", fontsize="small")
        axes[2].axhline(self.mass * self.gravity, color="#c0392b", lw=0.8, ls="--", label="m g")
        axes[2].legend(loc="lower right")
        axes[2].set_xlabel("time [s]")
        fig.suptitle(title or f"{self.mass:g} kg foot dropped in mud ({self.engine} engine)")
        if path is not None:
            from mudforce.io import atomic_open

            with atomic_open(path, "wb") as handle:
                fig.savefig(handle, format="png", dpi=100, metadata={"Software": None})
        return fig


def _check_positive(name: str, value: float, unit: str) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise InputError(f"{name} must be finite and > 0 [{unit}], got {value!r}")
    return value


def simulate_foot(
    mass: float,
    params: MudParameters,
    foot: Foot | None = None,
    *,
    duration: float = 8.0,
    dt: float = 1e-3,
    substeps: int = 10,
    depth0: float = 0.0,
    velocity0: float = 0.0,
    applied_force: Any = None,
    gravity: float = GRAVITY,
) -> FootResult:
    """Simulate a one-degree-of-freedom foot of mass ``m`` falling into mud (the built-in engine).

    ``m d^2 z_i/dt^2 = m g + F_applied(t) - F_mud``, with ``F_mud`` the
    model's force (Eqs. (1)-(9)) and sticking at rest (module docstring),
    integrated event-driven with RK4.

    Parameters
    ----------
    mass : float
        Foot mass [kg], > 0.
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry (area ``S`` [m^2], width ``H`` [m]); the paper's 51 x 38 mm cuboid by default.
    duration : float
        Simulated time [s].
    dt : float
        Output sampling interval [s].
    substeps : int
        RK4 steps per output interval (default 10: ``h = 0.1 ms`` for ``dt = 1 ms``).
    depth0 : float
        Initial depth of the foot's bottom [m]; negative is above the surface (a drop height).
    velocity0 : float
        Initial velocity [m/s], positive down.
    applied_force : float, or (times, forces) arrays, optional
        Extra force on the foot [N], positive DOWN (pushing it into the mud);
        a pair of arrays is interpolated linearly in time [s] (held outside).
    gravity : float
        Gravitational acceleration [m/s^2].

    Returns
    -------
    FootResult
    """
    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    mass = _check_positive("mass", mass, "kg")
    duration = _check_positive("duration", duration, "s")
    dt = _check_positive("dt", dt, "s")
    if not math.isfinite(gravity) or not math.isfinite(depth0) or not math.isfinite(velocity0):
        raise InputError("gravity [m/s^2], depth0 [m] and velocity0 [m/s] must be finite")
    substeps = positive_int(substeps, "substeps")
    foot = Foot.paper() if foot is None else foot
    p = params_row(params, foot, VelocityFilter.exact())
    tp, fp = _profile(applied_force)
    n = math.floor(duration / dt + 1e-9) + 1
    t_out = np.arange(n) * dt
    depth = np.empty(n)
    velocity = np.empty(n)
    force = np.empty(n)
    phase = np.empty(n, dtype=np.int8)
    strain = np.empty(n)
    events = _integrate(p, mass, float(gravity), float(depth0), float(velocity0), t_out, int(substeps), tp, fp,
                        depth, velocity, force, phase, strain)
    return FootResult(t_out, depth, velocity, force, phase, mass, float(gravity), "builtin", int(events), strain)


def _profile(applied_force: Any) -> tuple[np.ndarray, np.ndarray]:
    if applied_force is None:
        return np.empty(0), np.empty(0)
    if isinstance(applied_force, (int, float, np.floating, np.integer)) and not isinstance(applied_force, bool):
        value = float(applied_force)
        if not math.isfinite(value):
            raise InputError(f"applied force must be finite [N], got {applied_force!r}")
        return np.zeros(1), np.array([value])
    try:
        times, forces = applied_force
        tp = np.ascontiguousarray(times, dtype=np.float64)
        fp = np.ascontiguousarray(forces, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("applied_force must be a number [N] or a pair (times [s], forces [N])") from None
    if tp.ndim != 1 or tp.shape != fp.shape or tp.size == 0:
        raise InputError("applied_force times and forces must be 1-D arrays of the same, non-zero length")
    if not (np.isfinite(tp).all() and np.isfinite(fp).all()) or (tp.size > 1 and np.any(np.diff(tp) <= 0.0)):
        raise InputError("applied_force times must be finite and strictly increasing, forces finite")
    return tp, fp


# ----------------------------------------------------------------------------- naive coupling
@njit(cache=True, nogil=True)
def _naive(states: np.ndarray, params: np.ndarray, m: float, g: float, z0: float, dt: float, n: int,
           depth: np.ndarray, force: np.ndarray) -> None:
    out = np.empty((K.N_OUT, 1))
    ring = states[:, :0]  # the exact velocity filter keeps no history
    z = z0
    v = 0.0
    f = K.step(states, ring, 0, params, z, dt, out, 0)
    for k in range(n):
        v += dt * (g - f / m)  # semi-implicit Euler, force from the last sample's branch
        z += dt * v
        f = K.step(states, ring, 0, params, z, dt, out, 0)
        depth[k] = z
        force[k] = f


def naive_drop(mass: float, params: MudParameters, foot: Foot | None = None, *, duration: float = 8.0,
               dt: float = 1e-3, gravity: float = GRAVITY) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The naive explicit coupling the module docstring warns about: ``(time [s], depth [m], force [N])``.

    Each step integrates ``m dv/dt = m g - F`` with the force the streaming
    model returned for the previous sample; the branch follows the sign of
    the last step's velocity. For comparison only: it chatters and ratchets.
    """
    foot = Foot.paper() if foot is None else foot
    p = params_row(params, foot, VelocityFilter.exact())[None, :]
    n = round(duration / dt)
    depth = np.empty(n)
    force = np.empty(n)
    _naive(K.new_states(1), p, float(mass), float(gravity), 0.0, float(dt), n, depth, force)
    return (np.arange(1, n + 1) * dt, depth, force)


# ----------------------------------------------------------------------------- exact drop
@dataclass(frozen=True)
class ExactDrop:
    """The exact (event-driven, high-accuracy) solution of a drop under constant load.

    Attributes
    ----------
    events : list of (float, str, float, float, float)
        ``(time [s], new phase, depth [m], velocity [m/s], strain [m])`` at each phase change.
    time, depth, velocity, force : ndarray
        Dense output on the requested grid [s, m, m/s, N].
    rest_depth : float
        Depth at the end of the requested duration [m].
    final_depth : float
        Depth where the foot comes to rest for good [m] (if it does within ``horizon``).
    """

    events: list[tuple[float, str, float, float, float]]
    time: np.ndarray
    depth: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    rest_depth: float
    final_depth: float


def exact_drop(
    mass: float,
    params: MudParameters,
    foot: Foot | None = None,
    *,
    duration: float = 8.0,
    height: float = 0.0,
    dt: float = 1e-3,
    gravity: float = GRAVITY,
    rtol: float = 1e-11,
) -> ExactDrop:
    """The drop's exact solution, phase by phase, with SciPy's DOP853 and event location.

    The foot falls freely from ``height``, sinks on the
    intrusion branch until it stops (event ``dz_i/dt = 0``); there it
    sticks if the withdrawal-branch force ``S k_m_w e`` is at most ``m g``,
    and otherwise rebounds on the withdrawal branch. While stuck the Maxwell
    strain relaxes in closed form, ``e(t) = e_s exp(-(t - t_s) / tau_i)``,
    and the foot sinks again when the intrusion force falls to ``m g``, at
    ``e* = (m g / S - alpha (z / H)^beta) / k_m_i``, i.e. after
    ``tau_i ln(e_s / e*)``; if ``e* <= 0`` it stays for good. This is an
    implementation independent of :func:`simulate_foot` (different
    integrator, closed-form sticking), used to check it.

    Parameters
    ----------
    mass : float
        Foot mass [kg].
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry; the paper's cuboid by default.
    duration : float
        Time span [s].
    height : float
        Release height of the foot's bottom above the surface [m], >= 0.
    dt : float
        Grid of the dense output [s].
    gravity : float
        [m/s^2].
    rtol : float
        Relative tolerance of DOP853.

    Notes
    -----
    A rebound that breaks the neck (Eq. (9)) continues with the closed-form
    post-necking force (Eq. (7)) until the foot stops again; there it sinks
    again on the intrusion branch with the necked mud's ``z_m`` (MODEL.md),
    or sticks, the band's ends then found by a 1 ms scan and Brent's method.
    """
    from scipy.integrate import solve_ivp

    foot = Foot.paper() if foot is None else foot
    q = params
    area, width = foot.area, foot.width
    load = mass * gravity
    tau_i = q.b_m_i / q.k_m_i
    tau_w = q.b_m_w / q.k_m_w
    lr = q.lambda_ * q.rho_m

    def spring(z: float) -> float:
        return float(q.alpha * (max(z, 0.0) / width) ** q.beta)

    def neck(tt: float, nk: tuple[float, float, float]) -> tuple[float, float]:
        """Post-necking force [N] and z_m [m], Eq. (7)."""
        g, g_int = neck_filter_response(tt - nk[0], q.zeta, q.omega_0)
        return area * q.b_m_w * nk[1] * g, nk[2] + nk[1] * g_int

    nk = (0.0, 0.0, 0.0)  # (t_n, v_m0, z_m at necking)

    def force(ph: str, tt: float, z: float, v: float, e: float) -> float:
        drag = lr * v * abs(v) if z > 0.0 else 0.0
        if ph == "INTRUSION":
            return area * (q.k_m_i * e + spring(z) + drag)
        if ph == "WITHDRAWAL":
            return area * (q.k_m_w * e + drag)
        if ph == "NECKED":
            return neck(tt, nk)[0] + area * drag
        return 0.0

    def make_rhs(ph: str) -> Any:
        tau = tau_i if ph == "INTRUSION" else tau_w

        def rhs(tt: float, y: np.ndarray) -> list[float]:
            de = y[1] - y[2] / tau if ph in ("INTRUSION", "WITHDRAWAL") else 0.0
            return [y[1], (load - force(ph, tt, y[0], y[1], y[2])) / mass, de]

        return rhs

    def event(fn: Any, direction: float) -> Any:
        fn.terminal = True
        fn.direction = direction
        return fn

    stop_down = event(lambda _t, y: y[1], -1.0)
    stop_up = event(lambda _t, y: y[1], 1.0)
    necking = event(lambda t_, y: force("WITHDRAWAL", t_, y[0], y[1], y[2]) / area + q.sigma_y, -1.0)
    surface = event(lambda _t, y: y[0], 0.0)
    touchdown = event(lambda _t, y: y[0], 1.0)
    phase_events = {"FREE": [touchdown], "INTRUSION": [stop_down], "WITHDRAWAL": [stop_up, necking, surface],
                    "NECKED": [stop_up, surface]}

    def band(tt: float, z: float, e: float, necked: bool) -> tuple[float, float]:
        if necked:
            e = z - neck(tt, nk)[1]
        f_down = area * (q.k_m_i * e + spring(z)) if z > 0.0 else 0.0
        return (neck(tt, nk)[0] if necked else area * q.k_m_w * e), f_down

    def at_rest(tt: float, z: float, e: float, necked: bool) -> tuple[str, float]:
        f_up, f_down = band(tt, z, e, necked)
        if load > f_down * (1.0 + 1e-12):
            if z <= 0.0:
                return "FREE", 0.0
            return "INTRUSION", (z - neck(tt, nk)[1]) if necked else e
        if load < f_up:
            return ("NECKED" if necked else "WITHDRAWAL"), e
        return ("STUCK_NECKED" if necked else "STUCK"), e

    pieces: list[tuple[float, float, Any]] = []  # (t0, t1, callable t -> (z, v, F))
    events: list[tuple[float, str, float, float, float]] = []
    t = 0.0
    y = np.array([-float(height), 0.0, 0.0])
    phase = "FREE"
    events.append((t, phase, float(y[0]), 0.0, 0.0))
    final = math.nan
    horizon = duration
    guard = 0
    while t < horizon and guard < 10000:
        guard += 1
        if phase in phase_events:
            sol = solve_ivp(make_rhs(phase), (t, horizon), y, method="DOP853", rtol=rtol, atol=1e-14,
                            events=phase_events[phase], dense_output=True)
            t1 = float(sol.t[-1])

            def piece(tt: np.ndarray, dense: Any = sol.sol, ph: str = phase, nk_: Any = nk) -> tuple[
                    np.ndarray, np.ndarray, np.ndarray]:
                nonlocal nk
                saved, nk = nk, nk_
                yy = dense(tt)
                ff = np.array([force(ph, a, b, c, d) for a, b, c, d in zip(tt, yy[0], yy[1], yy[2], strict=True)])
                nk = saved
                return yy[0], yy[1], ff

            pieces.append((t, t1, piece))
            y = sol.y[:, -1].copy()
            t = t1
            if sol.status != 1:
                break
            code = next(i for i, te in enumerate(sol.t_events) if te.size)
            events_here = phase_events[phase]
            ev = events_here[code]
            if ev is touchdown:
                y[0] = max(y[0], 0.0)
                y[2] = 0.0  # z_m = 0 at the crossing
                phase = "INTRUSION"
            elif ev is surface:
                # the drag switches at the surface; step just past it so that the event does not fire again
                y[0] = math.copysign(1e-15, y[1]) if y[1] != 0.0 else y[0]
            elif ev is necking:
                nk = (t, float(y[2]) / tau_w, float(y[0] - y[2]))
                phase = "NECKED"
            else:  # a stop
                y[1] = 0.0
                if phase == "NECKED" and y[0] <= 0.0:
                    phase, y[2] = "FREE", 0.0
                else:
                    phase, e_new = at_rest(t, float(y[0]), float(y[2]), phase == "NECKED")
                    y[2] = e_new
            events.append((t, phase, float(y[0]), float(y[1]), float(y[2])))
        elif phase == "STUCK":  # closed form
            z, e_s = float(y[0]), float(y[2])
            e_star = (load / area - spring(z)) / q.k_m_i
            t_s = t
            if e_star <= 0.0:
                t_end = math.inf
            else:
                t_end = t + tau_i * math.log(e_s / e_star) if e_star < e_s else t
            stop = min(t_end, horizon)

            def stuck(tt: np.ndarray, z: float = z) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
                return np.full_like(tt, z), np.zeros_like(tt), np.full_like(tt, load)

            pieces.append((t_s, stop, stuck))
            if t_end == math.inf:
                final = z
                t = horizon
                break
            t = stop
            y = np.array([z, 0.0, e_s * math.exp(-(stop - t_s) / tau_i)])
            if stop < t_end:
                break
            y[2] = min(e_star, e_s)
            phase = "INTRUSION"
            events.append((t, phase, z, 0.0, float(y[2])))
        else:  # STUCK_NECKED: the band moves with the necked mud; find its end by scanning + brentq
            from scipy.optimize import brentq

            z = float(y[0])

            def slack(tt: float, z: float = z) -> float:
                f_up, f_down = band(tt, z, 0.0, True)
                return min(f_down - load, load - f_up)

            t_s = t
            t_end = math.inf
            step = 1e-3
            ta = t
            while ta < horizon:
                tb = min(ta + step, horizon)
                if slack(tb) < 0.0:
                    t_end = brentq(slack, ta, tb, xtol=1e-15)
                    break
                ta = tb

            def stuck_n(tt: np.ndarray, z: float = z) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
                return np.full_like(tt, z), np.zeros_like(tt), np.full_like(tt, load)

            stop = min(t_end, horizon)
            pieces.append((t_s, stop, stuck_n))
            t = stop
            if t_end == math.inf:
                break
            t = t_end + 1e-13
            f_down = band(t, z, 0.0, True)[1]
            if load > f_down:
                phase, e_new = "INTRUSION", z - neck(t, nk)[1]
            else:
                phase, e_new = "NECKED", 0.0
            y = np.array([z, 0.0, e_new])
            events.append((t, phase, z, 0.0, e_new))
    if guard >= 10000:
        raise RuntimeError(f"exact_drop: more than 10000 phases before t = {t:g} s")
    n = math.floor(duration / dt + 1e-9) + 1
    grid = np.arange(n) * dt
    depth = np.empty(n)
    vel = np.empty(n)
    frc = np.empty(n)
    for t0, t1, fn in pieces:
        sel = (grid >= t0) & (grid <= t1)
        if sel.any():
            zz, vv, ff = fn(grid[sel])
            depth[sel], vel[sel], frc[sel] = zz, vv, ff
    zend, _, _ = pieces[-1][2](np.array([min(duration, pieces[-1][1])]))
    return ExactDrop(events, grid, depth, vel, frc, float(zend[0]), float(final))
