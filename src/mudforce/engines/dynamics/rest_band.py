"""The rest band of a foot, from its contact state: the forces that can hold it at rest.

A foot at rest in the mud carries any load (positive down) between the
withdrawal-branch force ``F_up`` and the intrusion-branch force ``F_down``
(:func:`mudforce.model.equations.rest_band_forces`, Eqs. (1)-(5) at ``dz_i/dt = 0``).
:func:`rest_band` applies the contact state machine to that (FREE above the
surface, the post-necking force of Eq. (7) after necking) for one foot;
:func:`branch_forces` gives every foot of a batch its band for the coming
time step, which is what a time-stepping simulator (the MuJoCo adapter)
needs. The band's arithmetic is the physics layer's
(:func:`~mudforce.model.equations.rest_band_forces`,
:func:`~mudforce.model.equations.post_necking_force`,
:func:`~mudforce.model.equations.rest_band_blend`); only the control flow
(which bound applies in which state) is written here, scalar, and again
on arrays in :func:`mudforce.jax.rest_band` and :func:`mudforce.jax.branch_forces`.
The built-in engine (:mod:`mudforce.engines.dynamics.engine`) calls
:func:`rest_band` at each instant it decides whether a foot at rest sticks.
"""

from __future__ import annotations

import math

import numpy as np

from mudforce._kernel import ContactMode, load_cache, load_state, params_from_row
from mudforce._kernel.layout import FREE, N_PARAMS, N_STATE, S_DEPTH, S_MODE, S_STARTED, S_VELOCITY
from mudforce._plumbing.jit import njit
from mudforce.errors import InputError
from mudforce.model.equations import (
    maxwell_strain_step,
    neck_filter_response,
    nonlinear_spring_stress,
    post_necking_force,
    rest_band_blend,
    rest_band_depth_spread,
    rest_band_forces,
    submerged_drag_stress,
)

__all__ = ["band_middle", "branch_forces", "branch_forces_row", "necked_force", "rest_band", "rest_band_spread"]


@njit(cache=True, nogil=True)
def necked_force(p: np.ndarray, v_m0: float, z_n: float, age: float) -> tuple[float, float]:
    """The post-necking force [N] and the mud's position ``z_m`` [m] at ``age`` [s] after necking, Eq. (7).

    :func:`mudforce.model.equations.post_necking_force` (``S b_m_w dz_m/dt``, ``dz_m/dt = v_m0 g``,
    ``z_m = z_n + v_m0 G``) at the response of :func:`mudforce.model.equations.neck_filter_response`.

    Parameters
    ----------
    p : ndarray
        One params row of :mod:`mudforce._kernel`.
    v_m0 : float
        Mud velocity at necking [m/s].
    z_n : float
        ``z_m`` at necking [m].
    age : float
        Time since necking ``t - t_n`` [s].
    """
    q = params_from_row(p)
    g, g_int = neck_filter_response(age, q.zeta, q.omega_0)
    force, mud = post_necking_force(q.area, q.b_w, v_m0, z_n, g, g_int)
    return force, mud


@njit(cache=True, nogil=True)
def rest_band(p: np.ndarray, mode: int, depth: float, strain: float, neck_force: float) -> tuple[float, float]:
    """The force band ``(F_up, F_down)`` [N] of a foot at rest (:func:`mudforce.model.equations.rest_band_forces`).

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
    if mode == ContactMode.FREE:
        return 0.0, 0.0
    q = params_from_row(p)
    spring = nonlinear_spring_stress(q.alpha, q.beta, depth, q.width)  # 0 above the surface
    f_up, f_down = rest_band_forces(strain, spring, q.k_i, q.k_w, q.area)
    if depth <= 0.0:
        f_down = 0.0  # above the surface the intrusion branch is FREE (docs/model.md)
    if mode == ContactMode.NECKED:
        return neck_force, f_down
    return f_up, f_down


@njit(cache=True, nogil=True)
def rest_band_spread(p: np.ndarray, mode: int, depth: float, depth_sd: float) -> tuple[float, float]:
    """How far a depth error moves :func:`rest_band`'s ends: ``(dF_up, dF_down)`` [N] (ours).

    :func:`mudforce.model.equations.rest_band_depth_spread` under the contact state machine: nothing when FREE
    or for an error of 0; ``dF_down`` 0 where the depth and its error keep the foot above the surface (the
    intrusion branch FREE); ``dF_up`` 0 after necking (the post-necking force of Eq. (7) does not depend on
    the foot's depth).

    Parameters
    ----------
    p : ndarray
        One params row of :mod:`mudforce._kernel`.
    mode : int
        Kernel contact state: 0 FREE, 1 CONTACT, 2 NECKED.
    depth : float
        Foot depth ``z_i`` [m], positive down.
    depth_sd : float
        The depth's error (a standard deviation) [m].
    """
    if mode == ContactMode.FREE or not depth_sd > 0.0:
        return 0.0, 0.0
    q = params_from_row(p)
    below = nonlinear_spring_stress(q.alpha, q.beta, depth - depth_sd, q.width)  # 0 above the surface
    above = nonlinear_spring_stress(q.alpha, q.beta, depth + depth_sd, q.width)
    d_up, d_down = rest_band_depth_spread(depth_sd, below, above, q.k_i, q.k_w, q.area)
    if depth + depth_sd <= 0.0:
        d_down = 0.0
    if mode == ContactMode.NECKED:
        d_up = 0.0
    return d_up, d_down


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
    :func:`mudforce.model.equations.maxwell_strain_step`). ``weight = 0`` is
    explicit (the band lags a step); ``1`` (used by the MuJoCo adapter) is
    consistent with a semi-implicit Euler step, whose position update uses
    the new velocity. A foot that has not started, or is FREE, gets ``0, 0``
    unless it touches down within the step.

    The decays ``exp(-dt / tau)`` of Eq. (3) are the ones the stepper cached
    in the state for its last step when that step was ``dt`` long (the
    adapter's case: a fixed time step), else computed here.
    """
    n = states.shape[0]
    # (compiled code reads without bounds checks: a short output or row would be written or read past its end)
    if (states.shape[1] < N_STATE or params.shape[0] < n or params.shape[1] < N_PARAMS or f_up.shape[0] < n
            or f_down.shape[0] < n or drag.shape[0] < n):
        raise InputError("branch_forces needs kernel state rows, and params rows, f_up, f_down and drag of at least "
                         "as many rows (the layout of mudforce._kernel)")
    for j in range(n):
        f_up[j], f_down[j], drag[j] = branch_forces_row(states, params, j, dt, weight, True)


@njit(cache=True, nogil=True, inline="always")
def band_middle(up: float, down: float, drag: float, inverted: bool, falling: bool) -> float:
    """The force an engine applies explicitly for a band [N] (the MuJoCo adapters, 1-D and 3-D): its middle plus the
    drag, or on an inverted band (``down < up``: no sticking is possible in between) the end of the motion's branch
    (``falling``: the down end, read only where ``inverted``) plus the drag. ``up``, ``down``, ``drag`` [N]: the
    band's ends and drag (:func:`branch_forces_row`), or sums of their parts (the 3-D adapter's sideways ones)."""
    if inverted:
        return (down if falling else up) + drag
    return 0.5 * (up + down) + drag


@njit(cache=True, nogil=True, inline="always")
def branch_forces_row(states: np.ndarray, params: np.ndarray, j: int, dt: float, weight: float,
                      start: bool) -> tuple[float, float, float]:
    """:func:`branch_forces` of row ``j`` alone: ``(f_up, f_down, drag)`` [N] (inlined into its callers).

    ``start=False`` leaves out the band at the step's start (0 in its place), which only
    ``weight = 1`` allows: ``rest_band_blend(1, a, b)`` is ``0 a + b``, which differs from
    ``0 + b`` at most in the sign of a zero (for a finite ``a``), and a sum that starts at ``+0``
    does not see that sign (the MuJoCo 3-D adapter's sums over elements,
    :mod:`mudforce.engines.mujoco._step3d`). Same arithmetic otherwise.
    """
    if states[j, S_STARTED] == 0.0 or states[j, S_MODE] == FREE:
        # (the two columns read directly: most rows of a 3-D foot are FREE, and this skips the rest of the row)
        z = states[j, S_DEPTH]
        v = states[j, S_VELOCITY]
        if states[j, S_STARTED] != 0.0 and z + v * dt > 0.0 and weight > 0.0:
            # touchdown within the step: the intrusion force at the predicted end, z_m = 0 at the surface
            z1 = z + v * dt
            lo, hi = rest_band(params[j], ContactMode.CONTACT.value, z1, z1 if z < 0.0 else z1 - z, 0.0)
            return weight * min(lo, hi), weight * hi, 0.0
        return 0.0, 0.0, 0.0
    s = load_state(states, j)
    p = params[j]
    q = params_from_row(p)
    mode = s.mode
    z = s.depth
    v = s.velocity
    # each bound is its own branch's force at the predicted end of the step:
    # down with v >= 0 on the intrusion branch, up with v <= 0 on the withdrawal branch
    v_dn = max(v, 0.0)
    v_up = min(v, 0.0)
    z_dn = z + v_dn * dt  # (the withdrawal bound does not depend on the depth it ends at: no z_up)
    lo0 = hi0 = 0.0
    if mode == ContactMode.NECKED:
        if start:
            force0, zm0 = necked_force(p, s.neck_v, s.neck_z, s.neck_age)
            lo0, hi0 = rest_band(p, mode, z, z - zm0, force0)
        lo1, zm1 = necked_force(p, s.neck_v, s.neck_z, s.neck_age + dt)
        _, hi1 = rest_band(p, mode, z_dn, z_dn - zm1, 0.0)
    else:
        e0 = z - s.mud
        if start:
            lo0, hi0 = rest_band(p, mode, z, e0, 0.0)
        tau_i = q.tau_i
        tau_w = q.tau_w
        cache = load_cache(states, j)
        if cache.dt == dt:
            decay_i = cache.decay_i
            decay_w = cache.decay_w
        else:
            decay_i = math.exp(-dt / tau_i)
            decay_w = math.exp(-dt / tau_w)
        e_dn = maxwell_strain_step(e0, v_dn, tau_i, decay_i)
        e_up = maxwell_strain_step(e0, v_up, tau_w, decay_w)
        _, hi1 = rest_band(p, mode, z_dn, e_dn, 0.0)
        # rest_band's F_up of a foot in CONTACT, the withdrawal branch: S k_m_w e, with no spring (Eq. (4) enters
        # F_down only), so the spring is not computed for it
        lo1, _ = rest_band_forces(e_up, 0.0, q.k_i, q.k_w, q.area)
    return (rest_band_blend(weight, lo0, lo1), rest_band_blend(weight, hi0, hi1),
            q.area * submerged_drag_stress(q.lam, q.rho_m, v, z))
