"""An independent, slow, high-accuracy solution of the model, for the tests.

This module re-implements ``docs/model.md`` from its text, without
calling or copying the compiled stepper (:mod:`mudforce._kernel`) or the
closed forms in :mod:`mudforce.model.equations`, so that the tests can catch bugs
in either. Every ODE is integrated numerically with
:func:`scipy.integrate.solve_ivp` at tight tolerances, and every instant
inside a step (surface crossing, necking) is an integrator *event*:

- Maxwell element, Eq. (3): ``b dz_m/dt + k z_m = k z_i`` with ``z_i``
  linear in time between two samples (first-order hold), on the intrusion
  (``k_m_i, b_m_i``) or withdrawal (``k_m_w, b_m_w``) branch.
- Necking, Eq. (9) as docs/model.md reads it: the first instant of a withdrawal
  at which ``k_m_w (z_i - z_m) + f_s < -sigma_y`` (suction only). The drag
  ``f_s`` of Eq. (5) acts only while ``z_i > 0``, so the withdrawal step is
  cut at the surface crossing (a second event).
- After necking, Eq. (7): the lumped mass-spring-damper
  ``z'' + 2 zeta omega_0 z' + omega_0^2 z = 0`` with ``z(t_n) = 0`` and
  ``z'(t_n) = v_m0`` (the mud velocity just before necking) is integrated
  numerically; ``z_m = z_m(t_n) + z`` and ``f_e1 = b_m_w z'``.

The FREE / CONTACT / NECKED state machine, the branch rule (the step's
velocity ``v = (z_k - z_{k-1}) / dt``, intrusion branch for ``v >= 0``) and
the per-sample outputs follow docs/model.md's "Conventions" section. Only the
exact (noise-free) branch rule is implemented.

It is pure Python and slow (a few hundred microseconds per sample): use it on
short trajectories (100 Hz, up to a few thousand samples).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp

from mudforce._kernel.layout import ContactMode
from mudforce.errors import InputError, real_array
from mudforce.model.bounds import check_depths, check_times
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

__all__ = ["CONTACT", "FREE", "NECKED", "ReferenceResult", "reference_simulate"]

# The contact state codes are the stepper's (mudforce._kernel.layout.ContactMode, defined once): labels only,
# so that results compare; nothing of the stepper's arithmetic is used here.
#: Contact state code: foot out of the mud, no force.
FREE = int(ContactMode.FREE)
#: Contact state code: Maxwell element attached (intrusion, hold or withdrawal branch).
CONTACT = int(ContactMode.CONTACT)
#: Contact state code: the neck has broken, the mud rings down, Eq. (7).
NECKED = int(ContactMode.NECKED)

_RTOL = 1e-12  # relative tolerance of every integration [-]
_ATOL = 1e-15  # absolute tolerance of every integration [m] or [m/s]


@dataclass(frozen=True, eq=False)
class ReferenceResult:
    """The reference solution at the input samples.

    Attributes
    ----------
    time : ndarray
        Sample times [s].
    force : ndarray
        Total force on the foot ``(f_e1 + f_e2 + f_s) * S`` [N], positive up, Eq. (1)/(8).
    mud_displacement : ndarray
        Mud displacement ``z_m`` [m] (equal to ``z_i`` while FREE).
    state : ndarray of int8
        Contact state per sample: 0 FREE, 1 CONTACT, 2 NECKED.
    necking_times : ndarray
        Instants at which the neck broke [s], Eq. (9).
    necking_forces : ndarray
        Force [N] at each necking instant (on the withdrawal branch, just
        before the break); ``-sigma_y * S`` unless the neck broke at the
        start of a step on a jump of the drag.
    """

    time: NDArray[np.float64]
    force: NDArray[np.float64]
    mud_displacement: NDArray[np.float64]
    state: NDArray[np.int8]
    necking_times: NDArray[np.float64]
    necking_forces: NDArray[np.float64]


class _Event:
    """A terminal ``solve_ivp`` event ``fun(t, y) = 0`` crossed in ``direction``."""

    def __init__(self, fun: Callable[[float, NDArray[np.float64]], float], direction: float) -> None:
        self.fun = fun
        self.terminal = True
        self.direction = direction

    def __call__(self, t: float, y: NDArray[np.float64]) -> float:
        return self.fun(t, y)


def _solve(
    fun: Callable[[float, NDArray[np.float64]], Any],
    span: tuple[float, float],
    y0: list[float],
    stiffness: float,
    events: list[_Event] | None = None,
    dense: bool = False,
) -> Any:
    """``solve_ivp`` at the module's tolerances; implicit (Radau) if the span is stiff.

    ``stiffness`` is the fastest rate of the ODE [1/s].
    """
    length = span[1] - span[0]
    method = "Radau" if stiffness * length > 200.0 else "DOP853"
    sol = solve_ivp(
        fun,
        span,
        y0,
        method=method,
        rtol=_RTOL,
        atol=_ATOL,
        events=events,
        dense_output=dense,
        first_step=min(length, 0.25 / stiffness) if stiffness > 0.0 else length,
    )
    if sol.status < 0:  # pragma: no cover - the ODEs are linear and smooth
        raise RuntimeError(f"reference integration failed: {sol.message}")
    return sol


class _NeckDecay:
    """Numerical solution of the post-necking mass-spring-damper, Eq. (7).

    ``z'' + 2 zeta omega_0 z' + omega_0^2 z = 0``, ``z(0) = 0``,
    ``z'(0) = v_m0`` [m/s], over ages ``0 .. horizon`` [s]; :meth:`at`
    returns ``(z, z')`` [m, m/s] at an age.
    """

    def __init__(self, v_m0: float, zeta: float, omega_0: float, horizon: float) -> None:
        self.v_m0 = v_m0
        self.horizon = horizon
        self.sol: Any = None
        if horizon > 0.0:
            c = 2.0 * zeta * omega_0
            w2 = omega_0 * omega_0

            def rhs(t: float, y: NDArray[np.float64]) -> list[float]:
                return [float(y[1]), float(-c * y[1] - w2 * y[0])]

            fastest = zeta * omega_0 + omega_0 * np.sqrt(abs(zeta * zeta - 1.0))
            self.sol = _solve(rhs, (0.0, horizon), [0.0, v_m0], float(fastest), dense=True)

    def at(self, age: float) -> tuple[float, float]:
        if age <= 0.0 or self.sol is None:
            return 0.0, self.v_m0
        y = self.sol.sol(min(age, self.horizon))
        return float(y[0]), float(y[1])


def reference_simulate(
    time: ArrayLike,
    depth: ArrayLike,
    params: MudParameters,
    foot: Foot | None = None,
) -> ReferenceResult:
    """Reference solution of the model for a sampled trajectory (docs/model.md, exact branch rule).

    Parameters
    ----------
    time : array_like
        Sample times [s], strictly increasing.
    depth : array_like
        Foot depth ``z_i`` below the undisturbed surface [m], positive down;
        linear in time between samples.
    params : MudParameters
        Mud parameters [SI].
    foot : Foot, optional
        Foot geometry (area ``S`` [m^2], width ``H`` [m]); the paper's
        51 x 38 mm cuboid by default.

    Returns
    -------
    ReferenceResult
    """
    if not isinstance(params, MudParameters):  # (its fields are read below: AttributeError)
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    if foot is not None and not isinstance(foot, Foot):
        raise InputError(f"foot must be a Foot (or None for the paper's cuboid), got {type(foot).__name__}")
    t = real_array(time, "time", "s")
    z = real_array(depth, "depth", "m")
    if t.ndim != 1 or t.shape != z.shape or t.size == 0:
        raise InputError(f"time and depth must be non-empty 1-D arrays of the same length, got shapes {t.shape} and "
                         f"{z.shape}")
    # simulate's bounds and words (model.bounds): a depth of 100.5 m, a step of 1e-12 s or 2000 s and a time of
    # 2e9 s were solved, where the model refuses them
    check_depths(z)
    check_times(t)
    foot = Foot.paper() if foot is None else foot
    p = params
    area = foot.area
    width = foot.width
    k_i, b_i, k_w, b_w = p.k_m_i, p.b_m_i, p.k_m_w, p.b_m_w
    lam_rho = p.lambda_ * p.rho_m
    t_last = float(t[-1])

    def spring(zi: float) -> float:
        """Eq. (4): ``alpha (max(z_i, 0) / H)^beta`` [Pa]."""
        return p.alpha * (zi / width) ** p.beta if zi > 0.0 else 0.0

    def drag(v: float, zi: float) -> float:
        """Eq. (5) with docs/model.md's rule: ``sign(v) lambda rho v^2`` [Pa] while ``z_i > 0``."""
        return lam_rho * v * abs(v) if zi > 0.0 else 0.0

    n = t.size
    force = np.zeros(n)
    mud = np.zeros(n)
    state = np.zeros(n, dtype=np.int8)
    neck_times: list[float] = []
    neck_forces: list[float] = []

    # --- first sample: CONTACT with relaxed mud below the surface, else FREE
    mode = CONTACT if z[0] > 0.0 else FREE
    zm = float(z[0])
    force[0] = spring(float(z[0])) * area
    mud[0] = zm
    state[0] = mode
    t_n = 0.0  # necking instant [s]
    zm_n = 0.0  # z_m at necking [m]
    decay: _NeckDecay | None = None

    for k in range(1, n):
        t0, t1 = float(t[k - 1]), float(t[k])
        z0, z1 = float(z[k - 1]), float(z[k])
        dt = t1 - t0
        v = (z1 - z0) / dt  # first-order hold [m/s]
        intrusion = v >= 0.0  # the paper's sign(0) = +1

        def zi_at(s: float, z0: float = z0, v: float = v) -> float:
            """Foot depth [m] at local time ``s`` [s] into the step."""
            return z0 + v * s

        # --- transitions at the start of the step
        if mode == NECKED and v > 0.0:
            if z0 > 0.0:
                mode = CONTACT  # keeps z_m
            else:
                mode = FREE
                zm = z0
        s_start = 0.0
        if mode == FREE and z1 > 0.0:
            # touchdown: CONTACT from the crossing instant, with z_m = 0 there
            s_start = -z0 / v if z0 < 0.0 else 0.0
            mode = CONTACT
            zm = 0.0

        fe1 = 0.0
        if mode == FREE:
            zm = z1
        elif mode == CONTACT and intrusion:
            # Eq. (3) on the intrusion branch
            if dt - s_start > 0.0:
                zm = _maxwell(zi_at, s_start, dt, zm, k_i, b_i, [])[1]
            if z1 <= 0.0:
                mode = FREE  # a step ending on the intrusion branch above the surface
                zm = z1
            else:
                fe1 = k_i * (z1 - zm)
        elif mode == CONTACT:
            # Eq. (3) on the withdrawal branch, watching Eq. (9); cut at the surface
            s_a = 0.0
            in_mud = z0 > 0.0
            necked_at: float | None = None
            while True:
                fs = -lam_rho * v * v if in_mud else 0.0
                stress = k_w * (zi_at(s_a) - zm) + fs
                if stress < -p.sigma_y:
                    necked_at = s_a
                    neck_forces.append(stress * area)
                    break
                if s_a >= dt:
                    break

                def yield_margin(s: float, y: NDArray[np.float64], fs: float = fs) -> float:
                    return k_w * (zi_at(s) - float(y[0])) + fs + p.sigma_y

                events = [_Event(yield_margin, -1.0)]
                if in_mud:
                    events.append(_Event(lambda s, y: zi_at(s), -1.0))
                s_b, zm_b, which = _maxwell(zi_at, s_a, dt, zm, k_w, b_w, events)
                zm = zm_b
                s_a = s_b
                if which == 0:
                    necked_at = s_b
                    neck_forces.append(-p.sigma_y * area)
                    break
                if which == 1:
                    in_mud = False
                    continue
                break
            if necked_at is None:
                fe1 = k_w * (z1 - zm)
            else:
                t_n = t0 + necked_at
                neck_times.append(t_n)
                zm_n = zm
                # v_m0 = dz_m/dt just before necking, from Eq. (3): (k/b)(z_i - z_m)
                v_m0 = k_w / b_w * (zi_at(necked_at) - zm)
                decay = _NeckDecay(v_m0, p.zeta, p.omega_0, t_last - t_n)
                mode = NECKED

        if mode == NECKED:
            assert decay is not None
            zd, vd = decay.at(t1 - t_n)
            zm = zm_n + zd
            fe1 = b_w * vd  # docs/model.md: after necking f_e1 = b_m_w dz_m/dt

        if mode == FREE:
            force[k] = 0.0
        else:
            fe2 = spring(z1) if (mode == CONTACT and intrusion) else 0.0
            force[k] = (fe1 + fe2 + drag(v, z1)) * area
        mud[k] = zm
        state[k] = mode

    return ReferenceResult(
        time=t.copy(),
        force=force,
        mud_displacement=mud,
        state=state,
        necking_times=np.array(neck_times, dtype=np.float64),
        necking_forces=np.array(neck_forces, dtype=np.float64),
    )


def _maxwell(
    zi_at: Callable[[float], float],
    s_a: float,
    s_b: float,
    zm: float,
    k: float,
    b: float,
    events: list[_Event],
) -> tuple[float, float, int | None]:
    """Integrate Eq. (3), ``b dz_m/dt + k z_m = k z_i(s)``, from ``s_a`` to ``s_b`` [s].

    Returns the stop time [s], ``z_m`` there [m] and the index of the
    terminal event that stopped it (``None`` if it reached ``s_b``).
    """
    rate = k / b  # 1 / tau [1/s]

    def rhs(s: float, y: NDArray[np.float64]) -> list[float]:
        return [rate * (zi_at(s) - float(y[0]))]

    sol = _solve(rhs, (s_a, s_b), [zm], rate, events=events or None)
    if sol.status == 1:
        hits = [(float(te[0]), i) for i, te in enumerate(sol.t_events) if te.size]
        s_hit, which = min(hits)
        for te, ye in zip(sol.t_events, sol.y_events, strict=True):
            if te.size and float(te[0]) == s_hit:
                return s_hit, float(ye[0][0]), which
    return float(sol.t[-1]), float(sol.y[0, -1]), None
