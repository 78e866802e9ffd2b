"""The one compiled stepper that every path (batch, streaming, vectorised) runs.

Structure
---------
Two pure functions are the model: :func:`advance` takes a foot's state
(a :class:`State` value), its step-length cache (:class:`Cache`), its
constants (:class:`Params`) and the next depth sample, and returns the new
state plus what the sample's outputs need; :func:`sample_outputs` turns
that into the force and its components. Every path is a loop around them:

* :func:`step` (streaming, MuJoCo, the built-in engine) loads a foot's row
  of ``states``, advances it, stores it, and writes all outputs to
  ``out[:, k]``;
* :func:`run_feet` (``MudContacts``) does that for every foot, writing
  only the forces;
* :func:`run_batch_compact` (``simulate``) keeps the state in registers
  through the whole trajectory and writes the force, the contact state and
  ``z_m``;
* :func:`run_batch` (calibration, and ``simulate``'s other outputs on
  demand) writes every output of every sample.

:func:`sample_outputs` is :func:`stress_parts` (every stress but the
nonlinear spring's) plus the spring, summed by :func:`total_force`.
For the exact velocity rule, the steps in which nothing happens (the
contact state stays, no surface crossing, no necking, the step length the
cached one: most steps at a constant rate) go through :func:`quiet_step`,
which does what :func:`advance` does for them without its bookkeeping;
:func:`run_feet` and :func:`run_batch` try it first for each foot or
sample (:func:`advance_quick`), and :func:`run_batch_compact` runs it in a
loop of its own (:func:`glide`). The streaming :func:`step`
always runs :func:`advance`, so the tests that compare batch and many feet
with streaming bit for bit check :func:`quiet_step` against it.
:func:`run_feet` and :func:`run_batch_compact` set the feet or samples on
the spring aside and compute their forces in one vectorised pass
(:func:`spring_pass`); the spring's power (:func:`mudforce._pow.power`)
gives the same bits there as in a single call, so every path agrees.

Layout
------
A foot's state is one row of a float64 array ``states[j, :]`` (indices
``S_*`` below: the state proper, then the cache); its constants are one
row of ``params[j, :]`` (``P_*``); the history of its smoothing velocity
filter is one row of ``ring[j, :]`` (``R_*``; only read and written when
the filter's window is > 1, so exact filters pass a ring with no columns).
Outputs are column-major: ``out[O_FORCE, k]`` is sample ``k``'s force, so
a batch's arrays are contiguous rows.

Why: the state row holds only what every step reads (20 doubles), so the
states of thousands of feet stay in cache; the ring (132 doubles) would
otherwise be most of it. State as values rather than array elements lets
the batch loop keep it in registers (array stores could alias the outputs,
so the compiler would otherwise reload every field on every sample); the
mode is an int in the value and a float only in the row, so no conversion
sits on the batch loop's loop-carried path. The Maxwell extension
``z_i - z_m`` is carried whole, not rebuilt from ``z_m``, which shortens
that path too.

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
from typing import Any, NamedTuple, TypeVar

import numpy as np
from numba import njit, prange

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


def _compiled(inline: str = "never", **overrides: Any) -> Callable[[_F], _F]:
    """``numba.njit`` for the stepper: cached, releases the GIL, no reference counting, IEEE division.

    ``_nrt=False``: the stepper allocates nothing, and without numba's
    reference counting its array arguments cost no atomic increments per
    call (a 2-3x difference per sample). ``error_model="numpy"``: a
    division is a division, without Python's check for a zero divisor,
    which is a branch that keeps loops from vectorising (the stepper
    validates its inputs before it divides by them). ``inline="always"`` compiles a
    function into each caller's loop. ``overrides`` replace these options
    (the MuJoCo adapter's per-step functions keep the GIL, for one). Typed
    so that the compiled functions keep their signatures for mypy.
    """
    options: dict[str, Any] = {"cache": True, "nogil": True, "_nrt": False, "error_model": "numpy", "inline": inline,
                               **overrides}
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
P_NECK_FLUSH = 17  # age after necking [s] past which Eq. (7)'s filter response is flushed to zero
N_PARAMS = 18

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
S_STRAIN = 12  # z_i - z_m at the last sample in CONTACT [m] (carried whole: z_m is rounded)
# a cache of what the step length allows to precompute (not state: recomputed when missing)
S_CACHE_DT = 13  # step length the cached values are for
S_CACHE_DECAY_I = 14  # exp(-dt / tau_i)
S_CACHE_DECAY_W = 15  # exp(-dt / tau_w)
S_CACHE_PHI = 16  # 4 entries: transition matrix of Eq. (7)'s filter over one step
N_STATE = S_CACHE_PHI + 4
N_CORE = S_CACHE_DT  # the state proper: columns 0 .. N_CORE - 1

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
    row[P_NECK_FLUSH] = neck_flush_age(row[P_ZETA], row[P_OMEGA_0])
    return row


def neck_flush_age(zeta: float, omega_0: float) -> float:
    """The age after necking [s] at which Eq. (7)'s filter response has decayed below 1e-250 [-].

    Its slowest mode decays as ``exp(-r t)``, ``r = zeta omega_0`` up to
    critical damping and ``omega_0 (zeta - sqrt(zeta^2 - 1))`` beyond
    (written ``omega_0 / (zeta + sqrt(zeta^2 - 1))``, which does not cancel).
    Past ``ln(1e250) / r`` the stepper sets the response to zero: it is
    nothing physically, and left alone it would go on into subnormal
    numbers, which are slow. Deciding by the age rather than by the values
    keeps the test off the filter update's chain of dependent operations.
    """
    rate = zeta * omega_0 if zeta <= 1.0 else omega_0 / (zeta + math.sqrt(zeta * zeta - 1.0))
    return 250.0 * math.log(10.0) / rate


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
    return sign(velocity)


@_compiled(inline="always")
def sign(velocity: float) -> float:
    """``sign(v)``: ``+1``, ``-1``, or ``0`` for ``v == 0`` (the exact rule's branch direction)."""
    # written so that it compiles to selects rather than branches: across
    # many feet the sign of the motion is unpredictable
    return (1.0 if velocity > 0.0 else 0.0) - (1.0 if velocity < 0.0 else 0.0)


class State(NamedTuple):
    """A foot's state as values: columns ``0 .. N_CORE - 1`` of a state row, in the order of the ``S_*`` indices."""

    started: float
    mode: int
    time: float
    depth: float
    mud: float
    neck_age: float
    neck_v: float
    neck_z: float
    direction: float
    velocity: float
    neck_g: float
    neck_gi: float
    strain: float


class Cache(NamedTuple):
    """What a constant step length lets a foot precompute: columns ``S_CACHE_*`` of a state row."""

    dt: float
    decay_i: float
    decay_w: float
    phi0: float
    phi1: float
    phi2: float
    phi3: float


class Params(NamedTuple):
    """A foot's constants as values (the fields of a params row, in the order of the ``P_*`` indices)."""

    k_i: float
    b_i: float
    k_w: float
    b_w: float
    alpha: float
    beta: float
    sigma_y: float
    zeta: float
    omega_0: float
    rho_m: float
    lam: float
    area: float
    width: float
    window: float
    deadband: float
    tau_i: float
    tau_w: float
    neck_flush: float


@_compiled(inline="always")
def load_state(states: np.ndarray, j: int) -> State:
    """Row ``j`` of ``states`` as a :class:`State`."""
    r = states[j]
    return State(r[0], int(r[1]), r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12])


@_compiled(inline="always")
def store_state(states: np.ndarray, j: int, s: State) -> None:
    """Write ``s`` to row ``j`` of ``states``."""
    r = states[j]
    r[0] = s.started
    r[1] = float(s.mode)
    r[2] = s.time
    r[3] = s.depth
    r[4] = s.mud
    r[5] = s.neck_age
    r[6] = s.neck_v
    r[7] = s.neck_z
    r[8] = s.direction
    r[9] = s.velocity
    r[10] = s.neck_g
    r[11] = s.neck_gi
    r[12] = s.strain


@_compiled(inline="always")
def load_cache(states: np.ndarray, j: int) -> Cache:
    """The step-length cache of row ``j`` of ``states``."""
    r = states[j]
    return Cache(r[13], r[14], r[15], r[16], r[17], r[18], r[19])


@_compiled(inline="always")
def store_cache(states: np.ndarray, j: int, c: Cache) -> None:
    """Write the step-length cache ``c`` to row ``j`` of ``states``."""
    r = states[j]
    r[13] = c.dt
    r[14] = c.decay_i
    r[15] = c.decay_w
    r[16] = c.phi0
    r[17] = c.phi1
    r[18] = c.phi2
    r[19] = c.phi3


@_compiled(inline="always")
def load_params(params: np.ndarray, j: int) -> Params:
    """Row ``j`` of ``params`` as :class:`Params`."""
    r = params[j]
    return Params(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12], r[13], r[14],
                  r[15], r[16], r[17])


@_compiled(inline="always")
def neck_filter_step(c: Cache, p: Params, age: float, gi: float, g: float) -> tuple[float, float]:
    """``(G, g)`` of Eq. (7)'s filter one whole step later, at ``age`` [s]: its exact discrete-time update.

    The transition matrix is the cache's; past :func:`neck_flush_age` the
    response is zero.
    """
    if age > p.neck_flush:
        gi = 0.0
        g = 0.0
    return c.phi0 * gi + c.phi1 * g, c.phi2 * gi + c.phi3 * g


@_compiled(inline="always")
def neck_motion(neck_v: float, neck_z: float, g: float, gi: float) -> tuple[float, float]:
    """After necking the mud moves as ``v_m0 g(t - t_n)``, Eq. (7): ``(dz_m/dt [m/s], z_m [m])``."""
    return neck_v * g, neck_z + neck_v * gi


@_compiled(inline="always")
def piece_drag(p: Params, z_a: float, v: float, length: float) -> float:
    """Drag stress [Pa], Eq. (5), over a withdrawal piece of ``length`` [s] from depth ``z_a`` [m] at ``v`` [m/s].

    The drag acts while the foot is below the surface; a piece does not
    cross it, so its midpoint decides.
    """
    z_mid = z_a + 0.5 * v * length
    return drag_stress(p.lam, p.rho_m, v) if z_mid > 0.0 else 0.0


@_compiled(inline="always")
def advance(s: State, c: Cache, p: Params, ring: np.ndarray, j: int, depth: float, dt: float
            ) -> tuple[State, Cache, bool, float, float, float, float, float]:
    """The state machine: foot state ``s`` at the last sample -> state at ``depth`` [m] after ``dt`` [s].

    A pure function of its arguments except for the velocity filter's
    history ``ring[j]`` (read and written only for filter windows > 1).

    ``c`` holds what the step length allows to precompute; it is refreshed
    when ``dt`` differs from the one it was made for by more than 1e-9
    relative.

    Returns ``(state, cache, ok, d, x, neck_offset, vhat, v)``: the new
    state and cache;
    ``ok`` False for a refused sample (non-finite depth, ``dt`` not finite
    and > 0, a window > 1 without a ring row of ``N_RING`` columns), with
    the state unchanged; the branch direction ``d`` (+1 down, -1 up, 0 rest);
    ``x``, the Maxwell extension ``z_i - z_m`` [m] in CONTACT or the mud
    velocity ``v_m0 g`` [m/s] in NECKED (what :func:`sample_outputs` needs);
    the time from the step's start to necking [s] (NaN if the neck did not
    break in this step); the branch velocity estimate [m/s]; and the
    first-order-hold velocity [m/s] (both 0 at the first sample). The first
    call on a fresh state sets the initial sample and ignores ``dt``.
    """
    nan = math.nan
    if not math.isfinite(depth):
        return s, c, False, 0.0, 0.0, nan, 0.0, 0.0
    window = int(p.window)
    if window > 1 and ring.shape[1] < N_RING:
        return s, c, False, 0.0, 0.0, nan, 0.0, 0.0  # no room for the filter's history (arrays are not bounds-checked)

    if s.started == 0.0:
        # MODEL.md: a trajectory that starts below the surface starts in
        # CONTACT with relaxed mud (z_m = z_i); otherwise FREE.
        if window > 1:
            ring[j, R_HEAD] = 0.0
            ring[j, R_N] = 1.0
            ring[j, R_Z] = depth
            ring[j, R_T] = 0.0
        first_mode = CONTACT if depth > 0.0 else FREE
        s0 = State(1.0, first_mode, 0.0, depth, depth, 0.0, 0.0, 0.0, 0.0, 0.0, s.neck_g, s.neck_gi, 0.0)
        return s0, c, True, 0.0, 0.0, nan, 0.0, 0.0

    if not (dt > 0.0) or not math.isfinite(dt):
        return s, c, False, 0.0, 0.0, nan, 0.0, 0.0

    z0 = s.depth
    z1 = depth
    v = (z1 - z0) / dt  # first-order hold: constant velocity over the step
    t1 = s.time + dt

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
    d = _direction(vhat, s.direction, p.deadband)

    tau_i = p.tau_i
    tau_w = p.tau_w
    # decays for a full step, reused while the step length stays the same to
    # 1e-9 relative: sample times k/rate carry rounding of one ulp of t (1e-13 s
    # at t = 1000 s), which would otherwise miss the cache on most steps. The
    # cached decay is then off by at most ~1e-9 relative, which the Maxwell
    # element forgets (it is contractive): far below the model's accuracy.
    if abs(dt - c.dt) > 1e-9 * dt:
        # transition matrix of z'' + 2 zeta omega_0 z' + omega_0^2 z = 0 over dt:
        # [G, g](t + dt) = [[g_d + 2a G_d, G_d], [-omega_0^2 G_d, g_d]] [G, g](t)
        g_d, gi_d = neck_filter_response(dt, p.zeta, p.omega_0)
        c = Cache(dt, math.exp(-dt / tau_i), math.exp(-dt / tau_w), g_d + 2.0 * p.zeta * p.omega_0 * gi_d, gi_d,
                  -p.omega_0 * p.omega_0 * gi_d, g_d)

    strain_start = s.strain
    mode = s.mode
    zm = s.mud
    neck_offset = nan
    neck_age = s.neck_age
    neck_v = s.neck_v
    neck_z = s.neck_z
    neck_g = s.neck_g
    neck_gi = s.neck_gi

    # --- transitions at the start of the step
    if mode == NECKED and d > 0.0:
        if z0 > 0.0:
            mode = CONTACT  # keeps z_m
            strain_start = z0 - zm
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
            strain_start = 0.0
        else:
            zm = z1

    x = 0.0
    strain = strain_start
    if mode == CONTACT:
        if d >= 0.0:
            # intrusion / hold branch, Eqs. (2)-(3) with k_m_i, b_m_i
            decay = c.decay_i if start == 0.0 else math.exp(-(dt - start) / tau_i)
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
            k_w = p.k_w
            sigma_y = p.sigma_y
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
                fs = piece_drag(p, z_a, v, length)
                if t_a == 0.0 and t_b == dt:
                    decay = c.decay_w
                else:
                    decay = math.exp(-length / tau_w)
                tn = necking_time(strain, v, tau_w, k_w, fs, sigma_y, length, decay)
                if tn >= 0.0:
                    if tn > 0.0:
                        strain = (-sigma_y - fs) / k_w  # exactly on the yield surface
                    z_n = z_a + v * tn
                    mode = NECKED
                    neck_offset = t_a + tn
                    neck_v = strain / tau_w  # v_m0 = dz_m/dt = (z_i - z_m)/tau_w
                    neck_z = z_n - strain
                    neck_age = dt - neck_offset
                    neck_g, neck_gi = neck_filter_response(neck_age, p.zeta, p.omega_0)
                    break
                strain = maxwell_strain_step(strain, v, tau_w, decay)
                t_a = t_b
                z_a = 0.0 if piece == 0 and pieces == 2 else z1
            if mode == CONTACT:
                zm = z1 - strain
        x = strain
    elif mode == NECKED:
        neck_age += dt
        neck_gi, neck_g = neck_filter_step(c, p, neck_age, neck_gi, neck_g)
    if mode == NECKED:
        x, zm = neck_motion(neck_v, neck_z, neck_g, neck_gi)

    s1 = State(1.0, mode, t1, z1, zm, neck_age, neck_v, neck_z, d, vhat, neck_g, neck_gi, strain)
    return s1, c, True, d, x, neck_offset, vhat, v


@_compiled(inline="always")
def quiet_step(s: State, c: Cache, p: Params, depth: float, dt: float
               ) -> tuple[bool, State, float, float, float]:
    """:func:`advance` for a step in which nothing happens; ``ok`` False if something does.

    Nothing happens in a step when the state has started, its length is
    the cached one (so the cached decays apply), the contact state stays
    what it was, and no surface crossing or necking falls inside it: most
    steps of a trajectory sampled at a constant rate, and of feet stepped
    together. For those this does exactly what :func:`advance` does,
    through the same functions, without its bookkeeping; the loops call
    :func:`advance` for the others. Only for the exact velocity rule
    (:func:`exact_rule`), which the caller checks.

    Returns ``(ok, state, d, x, v)`` as :func:`advance` returns them (the
    state is meaningless when ``ok`` is False).
    """
    z0 = s.depth
    v = (depth - z0) / dt
    d = sign(v)
    # inside this tolerance the step length is certainly the cache's by
    # advance's test (1e-9 relative), and finite and > 0
    ok = (abs(dt - c.dt) <= 0.5e-9 * c.dt) & (abs(depth) < math.inf) & (s.started != 0.0)
    mode = s.mode
    strain = s.strain
    age = s.neck_age
    g = s.neck_g
    gi = s.neck_gi
    x = 0.0
    if mode == FREE:
        ok = ok & (depth <= 0.0)  # else touchdown
        zm = depth
    elif mode == NECKED:
        ok = ok & (d <= 0.0)  # else NECKED ends
        age += dt
        gi, g = neck_filter_step(c, p, age, gi, g)
        x, zm = neck_motion(s.neck_v, s.neck_z, g, gi)
    else:
        if d >= 0.0:
            ok = ok & (depth > 0.0)  # else FREE at the step's end
            strain = maxwell_strain_step(strain, v, p.tau_i, c.decay_i)
        else:
            # one piece (no surface crossing) in which the neck holds
            fs = piece_drag(p, z0, v, dt)
            tn = necking_time(strain, v, p.tau_w, p.k_w, fs, p.sigma_y, dt, c.decay_w)
            ok = ok & ((z0 > 0.0) == (depth > 0.0)) & (tn < 0.0)
            strain = maxwell_strain_step(strain, v, p.tau_w, c.decay_w)
        x = strain
        zm = depth - strain
    return ok, State(1.0, mode, s.time + dt, depth, zm, age, s.neck_v, s.neck_z, d, v, g, gi, strain), d, x, v


@_compiled(inline="always")
def exact_rule(p: Params) -> bool:
    """True for the exact velocity rule (filter window <= 1, no deadband): the branch direction is ``sign(v)``."""
    return int(p.window) <= 1 and not (p.deadband > 0.0)


@_compiled(inline="always")
def advance_quick(s: State, c: Cache, p: Params, ring: np.ndarray, j: int, depth: float, dt: float
                  ) -> tuple[State, Cache, bool, float, float, float, float, float]:
    """:func:`advance`, through :func:`quiet_step` when nothing happens in the step: the same results, sooner."""
    if exact_rule(p):
        ok, s1, d, x, v = quiet_step(s, c, p, depth, dt)
        if ok:
            return s1, c, True, d, x, math.nan, v, v
    return advance(s, c, p, ring, j, depth, dt)


@_compiled(inline="always")
def stress_parts(p: Params, mode: int, d: float, x: float, z1: float, v: float
                 ) -> tuple[float, float, float, bool]:
    """A sample's stresses but the nonlinear spring's, from what :func:`advance` returned.

    ``mode`` is the sample's contact state, ``d`` the branch direction,
    ``x`` the Maxwell extension [m] (CONTACT) or mud velocity [m/s]
    (NECKED), ``z1`` the depth [m] and ``v`` the first-order-hold velocity
    [m/s]. Returns ``(f_e1, f_s [Pa], dz_m/dt [m/s], spring)``: Eqs. (2),
    (5) and (7); ``spring`` is True where the nonlinear spring, Eq. (4),
    acts (CONTACT on the intrusion branch), which :func:`sample_outputs`
    evaluates at once and the loops over many samples or feet in one
    vectorised pass (:func:`spring_pass`).
    """
    if mode == FREE:
        return 0.0, 0.0, v, False
    fs = drag_stress(p.lam, p.rho_m, v) if z1 > 0.0 else 0.0
    if mode == CONTACT:
        if d >= 0.0:
            return p.k_i * x, fs, x / p.tau_i, True
        return p.k_w * x, fs, x / p.tau_w, False
    # after necking the visco-elastic stress is the damper's: b_m_w dz_m/dt
    return p.b_w * x, fs, x, False


@_compiled(inline="always")
def total_force(fe2: float, rest: float, area: float) -> float:
    """The force [N], Eqs. (1) and (8), from the spring stress ``fe2``, ``rest = f_e1 + f_s`` [Pa] and the area [m^2].

    Every path sums in this order, so that they agree bit for bit.
    """
    return (fe2 + rest) * area


@_compiled(inline="always")
def sample_outputs(p: Params, mode: int, d: float, x: float, z1: float, v: float
                   ) -> tuple[float, float, float, float, float]:
    """The force and its parts at a sample, from what :func:`advance` returned (see :func:`stress_parts`).

    Returns ``(force [N], f_e1, f_e2, f_s [Pa], dz_m/dt [m/s])``: Eqs. (2),
    (4), (5), (7) and (8) times the area.
    """
    fe1, fs, mud_velocity, spring = stress_parts(p, mode, d, x, z1, v)
    fe2 = nonlinear_spring_stress(p.alpha, p.beta, z1, p.width) if spring else 0.0
    return total_force(fe2, fe1 + fs, p.area), fe1, fe2, fs, mud_velocity


# rows of the scratch block of the deferred spring pass: one column per sample or foot on the spring
SP_DEPTH = 0  # z_i [m]
SP_WIDTH = 1  # H [m]
SP_ALPHA = 2  # alpha [Pa]
SP_BETA = 3  # beta [-]
SP_REST = 4  # f_e1 + f_s [Pa]; the pass overwrites it with the force [N]
SP_AREA = 5  # area [m^2]
N_SPRING = 6


def new_spring_scratch(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A scratch block for ``n`` samples or feet on the spring, and its int64 index of where each force goes."""
    return np.empty((N_SPRING, n), dtype=np.float64), np.empty(n, dtype=np.int64)


@_compiled()
def spring_pass(scratch: np.ndarray, index: np.ndarray, m: int, forces: np.ndarray) -> None:
    """The forces [N] of the first ``m`` columns of ``scratch`` into ``forces[index[i]]``.

    Each is the nonlinear spring, Eq. (4), plus the rest of the stress,
    times the area. Computed in a loop with no branches over contiguous
    rows, which the compiler vectorises (the spring's power is most of a
    step's arithmetic, and vectorised it costs a fraction of a scalar
    call), then scattered to where each force goes.
    """
    z = scratch[SP_DEPTH]
    w = scratch[SP_WIDTH]
    a = scratch[SP_ALPHA]
    b = scratch[SP_BETA]
    rest = scratch[SP_REST]
    area = scratch[SP_AREA]
    for i in range(m):
        rest[i] = total_force(nonlinear_spring_stress(a[i], b[i], z[i], w[i]), rest[i], area[i])
    for i in range(m):
        forces[index[i]] = rest[i]


@_compiled(inline="always")
def _write(out: np.ndarray, k: int, force: float, fe1: float, fe2: float, fs: float,
           mud: float, mud_velocity: float, velocity: float, mode: float, neck_offset: float) -> None:
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
def _advance_row(states: np.ndarray, ring: np.ndarray, j: int, params: np.ndarray, depth: float, dt: float
                 ) -> tuple[bool, Params, State, float, float, float, float, float]:
    """:func:`advance` foot ``j`` in place: load its rows, step, store (unless refused).

    Returns ``(ok, params, state, d, x, neck_offset, vhat, v)`` as :func:`advance` does.
    """
    p = load_params(params, j)
    c = load_cache(states, j)
    s, c1, ok, d, x, neck_offset, vhat, v = advance(load_state(states, j), c, p, ring, j, depth, dt)
    if ok:
        store_state(states, j, s)
        if c1.dt != c.dt:
            store_cache(states, j, c1)
    return ok, p, s, d, x, neck_offset, vhat, v


@_compiled(inline="always")
def step(states: np.ndarray, ring: np.ndarray, j: int, params: np.ndarray, depth: float, dt: float,
         out: np.ndarray, k: int) -> float:
    """Advance foot ``j`` to the next sample ``depth`` [m] after ``dt`` [s].

    Row ``j`` of ``states``, ``params`` and ``ring`` are the foot's; writes
    the sample's outputs to column ``out[:, k]`` and returns the force [N].
    The first call on a fresh state sets the initial sample and ignores
    ``dt``. Returns NaN, changing nothing, for a non-finite depth or a
    ``dt`` that is not finite and > 0, and for a filter window > 1 without
    a ring row of ``N_RING`` columns (:func:`new_ring`).
    """
    ok, p, s, d, x, neck_offset, vhat, v = _advance_row(states, ring, j, params, depth, dt)
    if not ok:
        return math.nan
    force, fe1, fe2, fs, mud_velocity = sample_outputs(p, s.mode, d, x, s.depth, v)
    _write(out, k, force, fe1, fe2, fs, s.mud, mud_velocity, vhat, float(s.mode), neck_offset)
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
    """Run foot 0 over a whole trajectory into ``out[:, k]``; returns the index of a bad sample or -1.

    The state stays in registers through the loop (a :class:`State` value)
    and is stored to ``states[0]`` at the end (or before a bad sample).
    Each step is :func:`advance_quick`.
    """
    s = load_state(states, 0)
    c = load_cache(states, 0)
    p = load_params(params, 0)
    n = time.shape[0]
    bad = -1
    for k in range(n):
        dt = time[k] - time[k - 1] if k > 0 else 0.0
        s1, c, ok, d, x, neck_offset, vhat, v = advance_quick(s, c, p, ring, 0, depth[k], dt)
        if not ok:
            bad = k
            break
        s = s1
        force, fe1, fe2, fs, mud_velocity = sample_outputs(p, s.mode, d, x, s.depth, v)
        _write(out, k, force, fe1, fe2, fs, s.mud, mud_velocity, vhat, float(s.mode), neck_offset)
    store_state(states, 0, s)
    store_cache(states, 0, c)
    return bad


@_compiled(inline="always")
def defer_spring(scratch: np.ndarray, index: np.ndarray, m: int, k: int, depth: float, rest: float,
                 forces: np.ndarray) -> int:
    """Set sample ``k`` (depth [m], ``rest = f_e1 + f_s`` [Pa]) aside for the spring pass; returns the new count.

    The block's constant rows (width, alpha, beta, area) are the caller's
    to fill; a full block is passed (:func:`spring_pass`) into ``forces``.
    """
    index[m] = k
    scratch[SP_DEPTH, m] = depth
    scratch[SP_REST, m] = rest
    m += 1
    if m == scratch.shape[1]:
        spring_pass(scratch, index, m, forces)
        m = 0
    return m


@_compiled(inline="always")
def glide(time: np.ndarray, depth: np.ndarray, k: int, s: State, c: Cache, p: Params, mode_out: np.ndarray,
          mud_out: np.ndarray, force_out: np.ndarray, scratch: np.ndarray, index: np.ndarray, m: int
          ) -> tuple[State, int, int]:
    """:func:`quiet_step` over samples ``k, k+1, ...`` (``k >= 1``) while nothing happens; returns ``(s, k, m)``.

    Writes what :func:`run_batch_compact` writes for those samples and
    returns the state after them, the index of the first sample in which
    something happens (or ``n``) and the spring block's new count ``m``.
    A loop of its own, apart from :func:`advance`'s (with which it would
    share registers), and one copy of it per contact state, which the
    state stays in (so the compiler drops the other states' code from it).
    """
    if s.mode == FREE:
        return _glide_in(FREE, time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m)
    if s.mode == CONTACT:
        return _glide_in(CONTACT, time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m)
    return _glide_in(NECKED, time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m)


@_compiled(inline="always")
def _glide_in(mode: int, time: np.ndarray, depth: np.ndarray, k: int, s: State, c: Cache, p: Params,
              mode_out: np.ndarray, mud_out: np.ndarray, force_out: np.ndarray, scratch: np.ndarray,
              index: np.ndarray, m: int) -> tuple[State, int, int]:
    """:func:`glide` for a state in contact state ``mode`` (a constant at each call site)."""
    n = time.shape[0]
    s = State(s.started, mode, s.time, s.depth, s.mud, s.neck_age, s.neck_v, s.neck_z, s.direction, s.velocity,
              s.neck_g, s.neck_gi, s.strain)  # the mode as the constant it is here
    while k < n:
        ok, s1, d, x, v = quiet_step(s, c, p, depth[k], time[k] - time[k - 1])
        if not ok:
            break
        s = s1
        mode_out[k] = mode
        mud_out[k] = s.mud
        fe1, fs, _, spring = stress_parts(p, mode, d, x, s.depth, v)
        if spring:
            m = defer_spring(scratch, index, m, k, s.depth, fe1 + fs, force_out)
        else:
            force_out[k] = total_force(0.0, fe1 + fs, p.area)
        k += 1
    return s, k, m


@_compiled()
def run_batch_compact(time: np.ndarray, depth: np.ndarray, states: np.ndarray, ring: np.ndarray,
                      params: np.ndarray, mode_out: np.ndarray, mud_out: np.ndarray, neck_index: np.ndarray,
                      neck_offset: np.ndarray, counts: np.ndarray, force_out: np.ndarray, scratch: np.ndarray,
                      index: np.ndarray) -> int:
    """Run foot 0 over a whole trajectory: the force [N], the contact state (int8) and ``z_m`` [m] per sample.

    Neckings go to ``neck_index[:counts[0]]`` (sample) and ``neck_offset``
    (time into the step [s]): those arrays are written only at neckings.
    The other outputs are :func:`run_batch`'s to give (``simulate`` runs it
    when they are asked for): this loop writes about a third of its
    memory traffic, which bounds the batch's speed. Steps in which nothing
    happens go through :func:`glide`, the others through :func:`advance`.
    The nonlinear spring's samples are collected in ``scratch``
    (:func:`new_spring_scratch`, any width >= 1) and their forces computed
    a block at a time (:func:`spring_pass`). Returns the index of a bad
    sample or -1.
    """
    s = load_state(states, 0)
    c = load_cache(states, 0)
    p = load_params(params, 0)
    n = time.shape[0]
    exact = exact_rule(p)  # the rule glide() follows
    necks = 0
    bad = -1
    scratch[SP_WIDTH] = p.width
    scratch[SP_ALPHA] = p.alpha
    scratch[SP_BETA] = p.beta
    scratch[SP_AREA] = p.area
    m = 0
    k = 0
    wait = 0  # samples to step before trying glide() again: it backs off where steps vary in length
    backoff = 0
    while k < n:
        if exact and k > 0 and wait == 0:
            k0 = k
            s, k, m = glide(time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m)
            if k == n:
                break
            backoff = min(2 * backoff + 1, 64) if k == k0 else 0
            wait = backoff
        elif wait > 0:
            wait -= 1
        dt = time[k] - time[k - 1] if k > 0 else 0.0
        s1, c, ok, d, x, offset, _, v = advance(s, c, p, ring, 0, depth[k], dt)
        if not ok:
            bad = k
            break
        s = s1
        mode_out[k] = s.mode
        mud_out[k] = s.mud
        fe1, fs, _, spring = stress_parts(p, s.mode, d, x, s.depth, v)
        if spring:
            m = defer_spring(scratch, index, m, k, s.depth, fe1 + fs, force_out)
        else:
            force_out[k] = total_force(0.0, fe1 + fs, p.area)
        if offset == offset:
            neck_index[necks] = k
            neck_offset[necks] = offset
            necks += 1
        k += 1
    spring_pass(scratch, index, m, force_out)
    store_state(states, 0, s)
    store_cache(states, 0, c)
    counts[0] = necks
    return bad


@_compiled()
def run_feet(states: np.ndarray, ring: np.ndarray, params: np.ndarray, depths: np.ndarray, dt: float,
             forces: np.ndarray, scratch: np.ndarray, index: np.ndarray) -> int:
    """One step of every foot (row ``j`` of ``states``/``ring``/``params``); the forces [N] into ``forces[j]``.

    Each foot's step is :func:`advance_quick`'s.
    The feet on the nonlinear spring are collected in ``scratch`` and
    ``index`` (:func:`new_spring_scratch` for as many feet) and their
    forces computed in one vectorised pass (:func:`spring_pass`) after the
    loop. Returns the first foot refused (left unchanged, its force not
    written) or -1.
    """
    bad = -1
    m = 0
    for j in range(depths.shape[0]):
        # advance_quick, written out: a foot that takes quiet_step stores only
        # its state, on a path of its own (through _advance_row's shared
        # store it was 10-15 % slower)
        p = load_params(params, j)
        ok = False
        if exact_rule(p):
            ok, s, d, x, v = quiet_step(load_state(states, j), load_cache(states, j), p, depths[j], dt)
            if ok:
                store_state(states, j, s)
        if not ok:
            ok, p, s, d, x, _, _, v = _advance_row(states, ring, j, params, depths[j], dt)
            if not ok:
                if bad < 0:
                    bad = j
                continue
        fe1, fs, _, spring = stress_parts(p, s.mode, d, x, s.depth, v)
        if spring:
            index[m] = j
            scratch[SP_DEPTH, m] = s.depth
            scratch[SP_WIDTH, m] = p.width
            scratch[SP_ALPHA, m] = p.alpha
            scratch[SP_BETA, m] = p.beta
            scratch[SP_REST, m] = fe1 + fs
            scratch[SP_AREA, m] = p.area
            m += 1
        else:
            forces[j] = total_force(0.0, fe1 + fs, p.area)
    spring_pass(scratch, index, m, forces)
    return bad


def new_feet_scratch(n: int, slices: int) -> tuple[np.ndarray, np.ndarray]:
    """Scratch blocks for :func:`run_feet_threads`: one :func:`new_spring_scratch` per slice of ``n`` feet."""
    width = -(-n // slices)
    return np.empty((slices, N_SPRING, width), dtype=np.float64), np.empty((slices, width), dtype=np.int64)


@_compiled(parallel=True)
def run_feet_threads(states: np.ndarray, ring: np.ndarray, params: np.ndarray, depths: np.ndarray, dt: float,
                     forces: np.ndarray, scratch: np.ndarray, index: np.ndarray, chunks: np.ndarray) -> int:
    """:func:`run_feet` on ``chunks.shape[0]`` contiguous slices of the feet, on numba's threads.

    The feet are independent, so the results are those of :func:`run_feet`
    bit for bit, whatever the number of slices. ``scratch`` and ``index``
    hold one block per slice (:func:`new_feet_scratch`); ``chunks`` (int64,
    one per slice) receives each slice's first refused foot or -1. Returns
    the first foot refused or -1.
    """
    n = depths.shape[0]
    m = chunks.shape[0]
    for c in prange(m):
        lo = n * c // m
        hi = n * (c + 1) // m
        b = run_feet(states[lo:hi], ring[lo:hi], params[lo:hi], depths[lo:hi], dt, forces[lo:hi], scratch[c], index[c])
        chunks[c] = b + lo if b >= 0 else -1
    for c in range(m):
        if chunks[c] >= 0:
            return int(chunks[c])
    return -1
