"""The one compiled stepper that every path (batch, streaming, vectorised) runs.

Layout
------
A foot's state is one row of a float64 array ``states[j, :]`` (indices
``S_*`` below); its constants are one row of ``params[j, :]`` (``P_*``);
the history of its smoothing velocity filter is one row of ``ring[j, :]``
(``R_*``; only read and written when the filter's window is > 1, so exact
filters pass a ring with no columns); each step writes column ``k`` of
``out[:, k]`` (rows ``O_*``). Everything works on 2-D arrays and row or
column indices so that the same function serves one foot (streaming,
batch) and many (vectorised) without copies.

Why this layout: the state row holds only what every step reads (19
doubles), so the states of thousands of feet stay in cache; the ring
(132 doubles) would otherwise be most of it. The outputs are column-major
so that the batch result's arrays (force, states, ...) are contiguous rows
of ``out``: post-processing them reads 8 bytes per sample, not a 72-byte
stride.

The step (``../shared/MODEL.md``)
---------------------------------
From sample ``k-1`` to ``k`` the input depth is linear in time. The step
picks the motion direction ``d`` (intrusion branch for ``d >= 0``), applies
the state machine's transitions at its start (NECKED -> CONTACT/FREE when
moving down), enters CONTACT at the surface-crossing instant from FREE,
advances the Maxwell element in closed form, locates the necking instant
inside the step in closed form, and continues in closed form after it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np
from numba import njit

from mudforce import _cache
from mudforce.equations import (
    drag_stress,
    maxwell_strain_step,
    neck_filter_response,
    necking_time,
    nonlinear_spring_stress,
)

# drop numba cache files made from an older version of this file or of equations.py
_cache.refresh()

__all__: list[str] = []

_F = TypeVar("_F", bound=Callable[..., Any])


def _compiled(inline: str = "never") -> Callable[[_F], _F]:
    """``numba.njit`` for the stepper: cached, releases the GIL, no reference counting.

    ``_nrt=False``: the stepper allocates nothing, and without numba's
    reference counting its array arguments cost no atomic increments per
    call (a 2-3x difference per sample). ``inline="always"`` compiles a
    function into each caller's loop.
    """
    options: dict[str, Any] = {"cache": True, "nogil": True, "_nrt": False, "inline": inline}
    decorator: Callable[[_F], _F] = njit(**options)
    return decorator

# contact states
FREE = 0
CONTACT = 1
NECKED = 2
STATE_NAMES = ("FREE", "CONTACT", "NECKED")

# params row
P_K_I = 0
P_B_I = 1
P_K_W = 2
P_B_W = 3
P_ALPHA = 4
P_BETA = 5
P_SIGMA_Y = 6
P_ZETA = 7
P_OMEGA_0 = 8
P_RHO_M = 9
P_LAMBDA = 10
P_AREA = 11
P_WIDTH = 12
P_WINDOW = 13
P_DEADBAND = 14
P_TAU_I = 15
P_TAU_W = 16
N_PARAMS = 17

# state row
S_STARTED = 0
S_MODE = 1
S_TIME = 2  # time since the first sample [s]
S_DEPTH = 3  # z_i at the last sample [m]
S_MUD = 4  # z_m at the last sample [m]
S_NECK_AGE = 5  # time since necking [s]
S_NECK_V = 6  # v_m0, mud velocity at necking [m/s]
S_NECK_Z = 7  # z_m at necking [m]
S_DIRECTION = 8  # -1 up, 0 rest, +1 down
S_VELOCITY = 9  # velocity estimate at the last sample [m/s]
S_NECK_G = 10  # g(age): normalised mud velocity after necking, Eq. (7)
S_NECK_GI = 11  # G(age) = integral of g [s]
S_CACHE_DT = 12  # step length the cached decays are for (a cache, not state)
S_CACHE_DECAY_I = 13
S_CACHE_DECAY_W = 14
S_CACHE_PHI = 15  # 4 entries: transition matrix of Eq. (7)'s filter over one cached step (a cache)
N_STATE = S_CACHE_PHI + 4

# ring row: the smoothing differentiator's last samples (for filter windows > 1)
RING = 65  # holds window + 1 samples, so windows up to 64 steps
MAX_WINDOW = RING - 1
R_N = 0  # number of samples held
R_HEAD = 1  # index of the newest sample
R_Z = 2  # RING depths [m]
R_T = R_Z + RING  # RING times [s]
N_RING = R_T + RING

# output rows (``out`` is column-major: ``out[O_FORCE, k]`` is sample k's force)
O_FORCE = 0
O_F_E1 = 1
O_F_E2 = 2
O_F_S = 3
O_MUD = 4
O_MUD_VELOCITY = 5
O_VELOCITY = 6
O_STATE = 7
O_NECK_OFFSET = 8  # time from the step's start to necking [s], NaN if none
N_OUT = 9


def make_params(values: np.ndarray, area: float, width: float, window: int, deadband: float) -> np.ndarray:
    """One params row from the 11 model values [SI], the foot and the velocity filter."""
    row = np.empty(N_PARAMS, dtype=np.float64)
    row[:11] = values
    row[P_AREA] = area
    row[P_WIDTH] = width
    row[P_WINDOW] = float(window)
    row[P_DEADBAND] = float(deadband)
    row[P_TAU_I] = row[P_B_I] / row[P_K_I]
    row[P_TAU_W] = row[P_B_W] / row[P_K_W]
    return row


def new_states(n: int) -> np.ndarray:
    """``n`` fresh state rows (not started: the first step sets the initial sample)."""
    states = np.zeros((n, N_STATE), dtype=np.float64)
    states[:, S_CACHE_DT] = -1.0
    return states


def ring_width(window: int) -> int:
    """Columns of a ring row for a velocity filter of ``window`` steps: none for ``window <= 1``."""
    return N_RING if window > 1 else 0


def new_ring(n: int, window: int) -> np.ndarray:
    """``n`` ring rows for a velocity filter of ``window`` steps (the first step fills them)."""
    return np.zeros((n, ring_width(window)), dtype=np.float64)


def new_out(n: int) -> np.ndarray:
    """Outputs of ``n`` samples or feet: ``N_OUT`` contiguous rows of ``n`` (column ``k`` per step)."""
    return np.empty((N_OUT, n), dtype=np.float64)


@_compiled()
def _direction(velocity: float, previous: float, deadband: float) -> float:
    """Motion direction from a velocity estimate, with a Schmitt-trigger deadband.

    ``+1`` moving down, ``-1`` moving up, ``0`` at rest. With ``deadband = 0``
    this is exactly ``sign(v)`` with ``0`` for ``v == 0`` (the paper's
    ``sign(0) = +1`` then selects the intrusion branch). With a deadband the
    direction changes when ``|v|`` exceeds it and keeps a direction until
    ``|v|`` falls below half of it.
    """
    if deadband > 0.0:
        if velocity > deadband:
            return 1.0
        if velocity < -deadband:
            return -1.0
        if previous < 0.0 and velocity < -0.5 * deadband:
            return -1.0
        if previous > 0.0 and velocity > 0.5 * deadband:
            return 1.0
        return 0.0
    # sign(v), written so that it compiles to selects rather than branches:
    # across many feet the sign of the motion is unpredictable
    return (1.0 if velocity > 0.0 else 0.0) - (1.0 if velocity < 0.0 else 0.0)


@_compiled()
def _write(out: np.ndarray, k: int, force: float, fe1: float, fe2: float, fs: float,
           mud: float, mud_velocity: float, velocity: float, mode: int, neck_offset: float) -> None:
    out[O_FORCE, k] = force
    out[O_F_E1, k] = fe1
    out[O_F_E2, k] = fe2
    out[O_F_S, k] = fs
    out[O_MUD, k] = mud
    out[O_MUD_VELOCITY, k] = mud_velocity
    out[O_VELOCITY, k] = velocity
    out[O_STATE, k] = mode
    out[O_NECK_OFFSET, k] = neck_offset


@_compiled(inline="always")
def step(states: np.ndarray, ring: np.ndarray, j: int, params: np.ndarray, depth: float, dt: float,
         out: np.ndarray, k: int) -> float:
    """Advance foot ``j`` to the next sample ``depth`` [m] after ``dt`` [s].

    Writes the sample's outputs to column ``out[:, k]`` and returns the
    force [N]. The first call on a fresh state sets the initial sample and
    ignores ``dt``. Returns NaN, changing nothing, for a non-finite depth
    or a ``dt`` that is not finite and > 0, and for a filter window > 1
    without a ring row of ``N_RING`` columns (:func:`new_ring`).
    """
    if not math.isfinite(depth):
        return math.nan
    area = params[j, P_AREA]
    width = params[j, P_WIDTH]
    window = int(params[j, P_WINDOW])
    if window > 1 and ring.shape[1] < N_RING:
        return math.nan  # no room for the filter's history (arrays are not bounds-checked)

    if states[j, S_STARTED] == 0.0:
        # MODEL.md: a trajectory that starts below the surface starts in
        # CONTACT with relaxed mud (z_m = z_i); otherwise FREE.
        states[j, S_STARTED] = 1.0
        states[j, S_TIME] = 0.0
        states[j, S_DEPTH] = depth
        states[j, S_MUD] = depth
        states[j, S_DIRECTION] = 0.0
        states[j, S_VELOCITY] = 0.0
        states[j, S_NECK_AGE] = 0.0
        states[j, S_NECK_V] = 0.0
        states[j, S_NECK_Z] = 0.0
        if window > 1:
            ring[j, R_HEAD] = 0.0
            ring[j, R_N] = 1.0
            ring[j, R_Z] = depth
            ring[j, R_T] = 0.0
        if depth > 0.0:
            states[j, S_MODE] = CONTACT
            fe2 = nonlinear_spring_stress(params[j, P_ALPHA], params[j, P_BETA], depth, width)
            first: float = fe2 * area
            _write(out, k, first, 0.0, fe2, 0.0, depth, 0.0, 0.0, CONTACT, math.nan)
            return first
        states[j, S_MODE] = FREE
        _write(out, k, 0.0, 0.0, 0.0, 0.0, depth, 0.0, 0.0, FREE, math.nan)
        return 0.0

    if not (dt > 0.0) or not math.isfinite(dt):
        return math.nan

    z0 = states[j, S_DEPTH]
    z1 = depth
    v = (z1 - z0) / dt  # first-order hold: constant velocity over the step
    t1 = states[j, S_TIME] + dt

    # --- velocity estimate for the branch choice (MODEL.md "Measured trajectories")
    if window <= 1:
        vhat = v
    else:
        head = (int(ring[j, R_HEAD]) + 1) % RING
        ring[j, R_Z + head] = z1
        ring[j, R_T + head] = t1
        n = min(int(ring[j, R_N]) + 1, window + 1)
        old = (head - (n - 1)) % RING
        ring[j, R_HEAD] = head
        ring[j, R_N] = n
        vhat = (z1 - ring[j, R_Z + old]) / (t1 - ring[j, R_T + old])
    d = _direction(vhat, states[j, S_DIRECTION], params[j, P_DEADBAND])

    tau_i = params[j, P_TAU_I]
    tau_w = params[j, P_TAU_W]
    # decays for a full step, reused while the step length stays the same to
    # 1e-9 relative: sample times k/rate carry rounding of one ulp of t (1e-13 s
    # at t = 1000 s), which would otherwise miss the cache on most steps. The
    # cached decay is then off by at most ~1e-9 relative, which the Maxwell
    # element forgets (it is contractive): far below the model's accuracy.
    if abs(dt - states[j, S_CACHE_DT]) > 1e-9 * dt:
        states[j, S_CACHE_DT] = dt
        states[j, S_CACHE_DECAY_I] = math.exp(-dt / tau_i)
        states[j, S_CACHE_DECAY_W] = math.exp(-dt / tau_w)
        # transition matrix of z'' + 2 zeta omega_0 z' + omega_0^2 z = 0 over dt:
        # [G, g](t + dt) = [[g_d + 2a G_d, G_d], [-omega_0^2 G_d, g_d]] [G, g](t)
        g_d, gi_d = neck_filter_response(dt, params[j, P_ZETA], params[j, P_OMEGA_0])
        states[j, S_CACHE_PHI] = g_d + 2.0 * params[j, P_ZETA] * params[j, P_OMEGA_0] * gi_d
        states[j, S_CACHE_PHI + 1] = gi_d
        states[j, S_CACHE_PHI + 2] = -params[j, P_OMEGA_0] * params[j, P_OMEGA_0] * gi_d
        states[j, S_CACHE_PHI + 3] = g_d

    mode = int(states[j, S_MODE])
    zm = states[j, S_MUD]
    neck_offset = math.nan
    lam = params[j, P_LAMBDA]
    rho = params[j, P_RHO_M]

    # --- transitions at the start of the step
    if mode == NECKED and d > 0.0:
        if z0 > 0.0:
            mode = CONTACT  # keeps z_m
        else:
            mode = FREE
            zm = z0

    start = 0.0  # time into the step at which CONTACT begins
    z_start = z0
    if mode == FREE:
        if z1 > 0.0:
            # touchdown: CONTACT from the crossing instant, with z_m = 0 there
            start = -z0 / v if z0 < 0.0 else 0.0
            mode = CONTACT
            zm = 0.0
            z_start = 0.0
        else:
            zm = z1

    strain = 0.0
    if mode == CONTACT:
        strain = z_start - zm
        if d >= 0.0:
            # intrusion / hold branch, Eqs. (2)-(3) with k_m_i, b_m_i
            decay = states[j, S_CACHE_DECAY_I] if start == 0.0 else math.exp(-(dt - start) / tau_i)
            strain = maxwell_strain_step(strain, v, tau_i, decay)
            if z1 <= 0.0:
                mode = FREE  # a step ending on the intrusion branch above the surface
                zm = z1
            else:
                zm = z1 - strain
        else:
            # withdrawal branch with k_m_w, b_m_w; necking per Eq. (9).
            # The drag acts only while z_i > 0, so the step is split where it
            # crosses the surface; in each piece the stress is monotone.
            k_w = params[j, P_K_W]
            sigma_y = params[j, P_SIGMA_Y]
            split = dt
            if (z_start > 0.0) != (z1 > 0.0) and v != 0.0:
                tc = start - z_start / v
                if start < tc < dt:
                    split = tc
            t_a = start
            z_a = z_start
            pieces = 1 if split == dt else 2
            for piece in range(pieces):
                t_b = split if piece == 0 else dt
                length = t_b - t_a
                z_mid = z_a + 0.5 * v * length
                fs = drag_stress(lam, rho, v) if z_mid > 0.0 else 0.0
                if t_a == 0.0 and t_b == dt:
                    decay = states[j, S_CACHE_DECAY_W]
                else:
                    decay = math.exp(-length / tau_w)
                tn = necking_time(strain, v, tau_w, k_w, fs, sigma_y, length, decay)
                if tn >= 0.0:
                    if tn > 0.0:
                        strain = (-sigma_y - fs) / k_w  # exactly on the yield surface
                    z_n = z_a + v * tn
                    mode = NECKED
                    neck_offset = t_a + tn
                    states[j, S_NECK_V] = strain / tau_w  # v_m0 = dz_m/dt = (z_i - z_m)/tau_w
                    states[j, S_NECK_Z] = z_n - strain
                    states[j, S_NECK_AGE] = dt - neck_offset
                    g0, gi0 = neck_filter_response(states[j, S_NECK_AGE], params[j, P_ZETA], params[j, P_OMEGA_0])
                    states[j, S_NECK_G] = g0
                    states[j, S_NECK_GI] = gi0
                    break
                strain = maxwell_strain_step(strain, v, tau_w, decay)
                t_a = t_b
                z_a = 0.0 if piece == 0 and pieces == 2 else z1
            if mode == CONTACT:
                zm = z1 - strain
    elif mode == NECKED:
        # a whole step after necking: the filter's exact discrete-time update
        # (its transition matrix is cached for the step length)
        states[j, S_NECK_AGE] += dt
        gi0 = states[j, S_NECK_GI]
        g0 = states[j, S_NECK_G]
        if abs(gi0) + abs(g0) < 1e-250:
            # fully decayed: flush to zero before the update reaches subnormal
            # numbers, which are slow (the filter's response tends to 0 anyway)
            gi0 = 0.0
            g0 = 0.0
        states[j, S_NECK_GI] = states[j, S_CACHE_PHI] * gi0 + states[j, S_CACHE_PHI + 1] * g0
        states[j, S_NECK_G] = states[j, S_CACHE_PHI + 2] * gi0 + states[j, S_CACHE_PHI + 3] * g0

    # --- outputs at the sample
    fs_end = drag_stress(lam, rho, v) if z1 > 0.0 else 0.0
    if mode == FREE:
        fe1 = 0.0
        fe2 = 0.0
        fs_out = 0.0
        mud_velocity = v
    elif mode == CONTACT:
        fs_out = fs_end
        if d >= 0.0:
            fe1 = params[j, P_K_I] * strain
            fe2 = nonlinear_spring_stress(params[j, P_ALPHA], params[j, P_BETA], z1, width)
            mud_velocity = strain / tau_i
        else:
            fe1 = params[j, P_K_W] * strain
            fe2 = 0.0
            mud_velocity = strain / tau_w
    else:
        # after necking the visco-elastic stress is the damper's: b_m_w dz_m/dt
        v_m0 = states[j, S_NECK_V]
        mud_velocity = v_m0 * states[j, S_NECK_G]
        zm = states[j, S_NECK_Z] + v_m0 * states[j, S_NECK_GI]
        fe1 = params[j, P_B_W] * mud_velocity
        fe2 = 0.0
        fs_out = fs_end

    force: float = (fe1 + fe2 + fs_out) * area
    states[j, S_MODE] = mode
    states[j, S_DEPTH] = z1
    states[j, S_MUD] = zm
    states[j, S_TIME] = t1
    states[j, S_DIRECTION] = d
    states[j, S_VELOCITY] = vhat
    _write(out, k, force, fe1, fe2, fs_out, zm, mud_velocity, vhat, mode, neck_offset)
    return force


# rows of a stream buffer: the state, the params, the ring, then the outputs in column 0
_STREAM_STATE, _STREAM_PARAMS, _STREAM_RING, _STREAM_OUT = 0, 1, 2, 3


def new_stream_buffer(params_row: np.ndarray) -> np.ndarray:
    """One array holding a single foot's state, constants, ring and outputs (see :func:`stream_parts`)."""
    width = max(N_STATE, N_PARAMS, ring_width(int(params_row[P_WINDOW])))
    buf = np.zeros((_STREAM_OUT + N_OUT, width), dtype=np.float64)
    buf[_STREAM_STATE, :N_STATE] = new_states(1)[0]
    buf[_STREAM_PARAMS, :N_PARAMS] = params_row
    return buf


def stream_parts(buf: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Views ``(states, params, out, ring)`` of a stream buffer, shaped as :func:`step` takes them.

    Plain slicing (no reshapes, which cost a library call each in compiled
    code), run both from Python and compiled into :func:`stream_step`.
    """
    states = buf[_STREAM_STATE:_STREAM_STATE + 1, :N_STATE]
    params = buf[_STREAM_PARAMS:_STREAM_PARAMS + 1, :N_PARAMS]
    ring = buf[_STREAM_RING:_STREAM_RING + 1, :N_RING if buf.shape[1] >= N_RING else 0]
    out = buf[_STREAM_OUT:, 0:1]
    return states, params, out, ring


_stream_parts = _compiled(inline="always")(stream_parts)


@_compiled()
def stream_step(buf: np.ndarray, depth: float, dt: float) -> float:
    """:func:`step` for one foot packed by :func:`new_stream_buffer` (one argument: less call overhead)."""
    states, params, out, ring = _stream_parts(buf)
    force: float = step(states, ring, 0, params, depth, dt, out, 0)
    return force


@_compiled()
def run_batch(time: np.ndarray, depth: np.ndarray, states: np.ndarray, ring: np.ndarray, params: np.ndarray,
              out: np.ndarray) -> int:
    """Run foot 0 over a whole trajectory into ``out[:, k]``; returns the index of a bad sample or -1."""
    n = time.shape[0]
    for k in range(n):
        dt = time[k] - time[k - 1] if k > 0 else 0.0
        f = step(states, ring, 0, params, depth[k], dt, out, k)
        if f != f:
            return k
    return -1


@_compiled()
def run_feet(states: np.ndarray, ring: np.ndarray, params: np.ndarray, depths: np.ndarray, dt: float,
             out: np.ndarray) -> int:
    """One step of every foot (row ``j`` of ``states``/``ring``/``params``, column ``j`` of ``out``).

    Returns the first foot refused (left unchanged, its outputs not written) or -1.
    """
    bad = -1
    for j in range(depths.shape[0]):
        f = step(states, ring, j, params, depths[j], dt, out, j)
        if f != f and bad < 0:
            bad = j
    return bad
