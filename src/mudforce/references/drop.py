"""An independent, high-accuracy solution of a foot dropped into mud, for the tests (:func:`exact_drop`).

Like :mod:`mudforce.references.trajectory` (the model on a prescribed trajectory), this
re-implements the model from ``docs/model.md`` without the compiled stepper
(:mod:`mudforce._kernel`) or the built-in engine (:mod:`mudforce.engines.dynamics`),
so that the tests can catch bugs in either: each phase of the hybrid system
(free fall, intrusion, withdrawal, after necking) is an ODE integrated with
SciPy's DOP853 to tight tolerances, its end located as an integrator event,
and sticking is solved in closed form. It shares with the stepper only the
post-necking filter's impulse response
(:func:`mudforce.model.equations.neck_filter_response`, Eq. (7)), itself tested
against a numerical integration. It is pure Python and slow (tens of
milliseconds per phase).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mudforce.errors import InputError, finite_number
from mudforce.model.equations import neck_filter_response
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

__all__ = ["GRAVITY", "ExactDrop", "exact_drop"]

#: Standard gravity [m/s^2] (the same value as :data:`mudforce.engines.dynamics.GRAVITY`).
GRAVITY = 9.81


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
    implementation independent of :func:`mudforce.engines.dynamics.simulate_foot` (different
    integrator, closed-form sticking), used to check it.

    Parameters
    ----------
    mass : float
        Foot mass [kg], > 0.
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry; the paper's cuboid by default.
    duration : float
        Time span [s], > 0.
    height : float
        Release height of the foot's bottom above the surface [m], >= 0.
    dt : float
        Grid of the dense output [s], > 0 (at most 1e8 points).
    gravity : float
        [m/s^2], > 0 (the foot must fall).
    rtol : float
        Relative tolerance of DOP853, > 0.

    Notes
    -----
    A rebound that breaks the neck (Eq. (9)) continues with the closed-form
    post-necking force (Eq. (7)) until the foot stops again; there it sinks
    again on the intrusion branch with the necked mud's ``z_m`` (docs/model.md),
    or sticks, the band's ends then found by a 1 ms scan and Brent's method.
    """
    from scipy.integrate import solve_ivp

    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    if foot is None:
        foot = Foot.paper()
    elif not isinstance(foot, Foot):
        raise InputError(f"foot must be a Foot (or None for the paper's cuboid), got {type(foot).__name__}")
    mass = finite_number(mass, "mass", "kg", positive=True)
    duration = finite_number(duration, "duration", "s", positive=True)
    height = finite_number(height, "height", "m", nonnegative=True)
    dt = finite_number(dt, "dt", "s", positive=True)
    gravity = finite_number(gravity, "gravity", "m/s^2", positive=True)
    rtol = finite_number(rtol, "rtol", "-", positive=True)
    if not duration / dt < 1e8:
        raise InputError(f"duration / dt = {duration / dt:.3g} is too many output points (at most 1e8)")
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
