"""The rest band of a foot, from its contact state: the forces that can hold it at rest.

A foot at rest in the mud carries any load (positive down) between the
withdrawal-branch force ``F_up`` and the intrusion-branch force ``F_down``
(:func:`mudforce.equations.rest_band_forces`, Eqs. (1)-(5) at ``dz_i/dt = 0``).
:func:`rest_band` applies the contact state machine to that (FREE above the
surface, the post-necking force of Eq. (7) after necking) for one foot;
:func:`branch_forces` gives every foot of a batch its band for the coming
time step, which is what a time-stepping simulator (the MuJoCo adapter)
needs. The built-in engine (:mod:`mudforce.dynamics.engine`) calls
:func:`rest_band` at each instant it decides whether a foot at rest sticks.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mudforce import _kernel as K
from mudforce.equations import (
    drag_stress,
    maxwell_strain_step,
    neck_filter_response,
    nonlinear_spring_stress,
    rest_band_forces,
)

__all__ = ["branch_forces", "rest_band"]


@njit(cache=True, nogil=True)
def rest_band(p: np.ndarray, mode: int, depth: float, strain: float, neck_force: float) -> tuple[float, float]:
    """The force band ``(F_up, F_down)`` [N] of a foot at rest (:func:`mudforce.equations.rest_band_forces`).

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
    if mode == K.FREE:
        return 0.0, 0.0
    spring = nonlinear_spring_stress(p[K.P_ALPHA], p[K.P_BETA], depth, p[K.P_WIDTH])  # 0 above the surface
    f_up, f_down = rest_band_forces(strain, spring, p[K.P_K_I], p[K.P_K_W], p[K.P_AREA])
    if depth <= 0.0:
        f_down = 0.0  # above the surface the intrusion branch is FREE (docs/model.md)
    if mode == K.NECKED:
        return neck_force, f_down
    return f_up, f_down


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
    Maxwell strain advanced in closed form, Eq. (3),
    :func:`mudforce.equations.maxwell_strain_step`). ``weight = 0`` is
    explicit (the band lags a step); ``1`` (used by the MuJoCo adapter) is
    consistent with a semi-implicit Euler step, whose position update uses
    the new velocity. A foot that has not started, or is FREE, gets ``0, 0``
    unless it touches down within the step.

    The decays ``exp(-dt / tau)`` of Eq. (3) are the ones the stepper cached
    in the state for its last step when that step was ``dt`` long (the
    adapter's case: a fixed time step), else computed here.
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
            tau_i = p[K.P_TAU_I]
            tau_w = p[K.P_TAU_W]
            if s[K.S_CACHE_DT] == dt:
                decay_i = s[K.S_CACHE_DECAY_I]
                decay_w = s[K.S_CACHE_DECAY_W]
            else:
                decay_i = math.exp(-dt / tau_i)
                decay_w = math.exp(-dt / tau_w)
            e_dn = maxwell_strain_step(e0, v_dn, tau_i, decay_i)
            e_up = maxwell_strain_step(e0, v_up, tau_w, decay_w)
            _, hi1 = rest_band(p, mode, z_dn, e_dn, 0.0)
            lo1, _ = rest_band(p, mode, z_up, e_up, 0.0)
        f_up[j] = (1.0 - weight) * lo0 + weight * lo1
        f_down[j] = (1.0 - weight) * hi0 + weight * hi1
        drag[j] = area * drag_stress(p[K.P_LAMBDA], p[K.P_RHO_M], v) if z > 0.0 else 0.0
