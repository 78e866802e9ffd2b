"""The physics of one step: the contact state machine's transitions and the dispatcher :func:`advance`.

From sample ``k-1`` to ``k`` the input depth is linear in time (first-order
hold, docs/model.md). :func:`advance` checks the sample, estimates the
branch velocity, and then goes through the model's table:

========  ====================================  =======================================
state     in the step                           leaves it by
========  ====================================  =======================================
FREE      :func:`free_step` (``z_m = z_i``)     :func:`touchdown` (crossing ``z_i = 0``)
CONTACT   :func:`intrusion_step` (``d >= 0``)    ending above the surface: FREE
CONTACT   :func:`withdrawal_step` (``d < 0``)    :func:`neck` (suction past ``-sigma_y``)
NECKED    :func:`necked_step`                   :func:`leave_necked` (moving down again)
========  ====================================  =======================================

The transitions at a step's start come first (NECKED -> CONTACT/FREE, then
FREE -> CONTACT from the crossing instant), then the step in the state
reached, in closed form. Every formula is a function of
:mod:`mudforce.model.equations`; this module only decides which applies when.
The dispatchers (:func:`advance`, :func:`quiet_step`, :func:`advance_quick`)
and the output helpers are compiled ``inline="always"``, into each loop that
calls them. The transitions and the per-state steps are ordinary compiled
functions, which LLVM inlines into the dispatchers on its own (the same
speed, measured with ``benchmarks/bench_core.py``): numba's own inlining
copies and re-processes a callee's IR at every site, nested, and with every
transition inlined that way the kernel's cold compile took twice as long
(about 80 s of CPU against 37 s for the 1-D paths the tests use). Two
exceptions, through numba's inlining cost models: :func:`sign` is
numba-inlined where :func:`quiet_step` calls it, and only there
(:func:`_in_quiet_step`), and :func:`_moved`, :func:`free_step` and
:func:`necked_step` into the full-output batch loop only
(:func:`_in_full_output_loop`): ``run_batch_compact`` then takes about 4
instructions a sample fewer, ``run_batch`` about 16, and no other loop's
compile changes (docs/speed.md, "Issue 19 point 4").

:func:`quiet_step` is :func:`advance` for the steps in which nothing
happens (most steps at a constant rate); it must give the same bits, which
the tests check. :func:`stress_parts` and :func:`sample_outputs` turn a
sample's state into the force and its parts.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple, cast

import numpy as np

from mudforce._kernel.layout import (
    CONTACT,
    FREE,
    N_RING,
    NECKED,
    R_HEAD,
    R_N,
    R_T,
    R_Z,
    RING,
    Cache,
    Params,
    State,
    _compiled,
)
from mudforce.model.equations import (
    intrusion_stress,
    maxwell_strain_step,
    neck_filter_response,
    neck_filter_transition,
    neck_filter_update,
    necked_mud_motion,
    necked_stress,
    necking_time,
    necking_velocity,
    nonlinear_spring_stress,
    piece_midpoint_depth,
    submerged_drag_stress,
    total_stress,
    withdrawal_stress,
    yield_strain,
)

__all__ = [
    "Step",
    "advance",
    "advance_quick",
    "exact_rule",
    "first_sample",
    "free_step",
    "intrusion_step",
    "leave_necked",
    "neck",
    "necked_step",
    "quiet_step",
    "sample_outputs",
    "stress_parts",
    "total_force",
    "touchdown",
    "withdrawal_general",
    "withdrawal_step",
]


class Step(NamedTuple):
    """What :func:`advance` returns for one sample."""

    state: State  #: the state at the sample (its ``direction`` and ``velocity`` are the branch's)
    cache: Cache  #: the step-length cache, refreshed if ``dt`` changed
    ok: bool  #: False for a refused sample: ``state`` and ``cache`` are then the unchanged input
    neck_offset: float  #: time from the step's start to necking [s], NaN if the neck did not break
    velocity: float  #: the first-order-hold velocity over the step [m/s] (0 at the first sample)


# ---------------------------------------------------------------- the branch velocity
def _in_quiet_step(expr: Any, caller: Any, callee: Any) -> bool:
    """numba's inlining cost model: numba-inline a call where it is written in :func:`quiet_step`, not elsewhere.

    numba asks it at every call site (``expr``, with the IR of the function being compiled and of the
    callee): only the sites whose source lines are :func:`quiet_step`'s are inlined, so that the glide
    loops get the callee's IR while :func:`advance` keeps a plain call (which LLVM inlines). Speed
    plumbing: docs/speed.md, "Issue 19 point 4".
    """
    first, last, filename = _QUIET_STEP_LINES
    return bool(expr.loc.filename == filename and first <= expr.loc.line <= last)


def _in_full_output_loop(expr: Any, caller: Any, callee: Any) -> bool:
    """numba's inlining cost model: numba-inline a call into the full-output batch loop only.

    ``caller`` is the IR of the function being compiled (the outermost one, into which :func:`advance`
    is inlined): the calibration loop ``run_batch_compiled`` gets the callee's IR, every other loop a
    plain call (which LLVM inlines), and so their compile stays as it was. Speed plumbing: docs/speed.md,
    "Issue 19 point 4".
    """
    return bool(caller.func_id.func_name == "run_batch_compiled")


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


@_compiled(inline=_in_quiet_step)
def sign(velocity: float) -> float:
    """``sign(v)``: ``+1``, ``-1``, or ``0`` for ``v == 0`` (the exact rule's branch direction)."""
    # written so that it compiles to selects rather than branches: across
    # many feet the sign of the motion is unpredictable
    return (1.0 if velocity > 0.0 else 0.0) - (1.0 if velocity < 0.0 else 0.0)


@_compiled()
def ring_start(ring: np.ndarray, j: int, depth: float) -> None:
    """Start the velocity filter's history ``ring[j]`` (a ring buffer) at the first sample ``depth`` [m]."""
    ring[j, R_HEAD] = 0.0
    ring[j, R_N] = 1.0
    ring[j, R_Z] = depth
    ring[j, R_T] = 0.0


@_compiled()
def ring_velocity(ring: np.ndarray, j: int, window: int, depth: float, time: float) -> float:
    """Add the sample ``(time [s], depth [m])`` to ``ring[j]``; the secant over the last ``window`` steps [m/s].

    docs/model.md, "Measured trajectories": the smoothing differentiator of
    :mod:`mudforce.model.velocity`.
    """
    head = (int(ring[j, R_HEAD]) + 1) % RING
    ring[j, R_Z + head] = depth
    ring[j, R_T + head] = time
    n = min(int(ring[j, R_N]) + 1, window + 1)
    old = (head - (n - 1)) % RING
    ring[j, R_HEAD] = head
    ring[j, R_N] = n
    v: float = (depth - ring[j, R_Z + old]) / (time - ring[j, R_T + old])
    return v


@_compiled()
def step_cache(c: Cache, p: Params, dt: float) -> Cache:
    """The decays and Eq. (7)'s transition matrix for a step of ``dt`` [s]: ``c`` if it is for that length.

    Reused while the step length stays the same to 1e-9 relative: sample
    times k/rate carry rounding of one ulp of t (1e-13 s at t = 1000 s),
    which would otherwise miss the cache on most steps. The cached decay is
    then off by at most ~1e-9 relative, which the Maxwell element forgets
    (it is contractive): far below the model's accuracy.
    """
    if abs(dt - c.dt) > 1e-9 * dt:
        g_d, gi_d = neck_filter_response(dt, p.zeta, p.omega_0)
        phi0, phi1, phi2, phi3 = neck_filter_transition(p.zeta, p.omega_0, g_d, gi_d)
        return Cache(dt, math.exp(-dt / p.tau_i), math.exp(-dt / p.tau_w), phi0, phi1, phi2, phi3)
    return c


# ---------------------------------------------------------------- the transitions
# the modes _moved is given, as int64 values: numba types a global int as a literal type of its own value, and
# compiled _moved once per mode (one compiled signature now, the state's int64 mode)
_FREE, _CONTACT = np.int64(FREE), np.int64(CONTACT)


@_compiled(inline=_in_full_output_loop)
def _moved(s: State, mode: int, mud: float, strain: float) -> State:
    """``s`` with a new contact state, ``z_m`` [m] and extension ``z_i - z_m`` [m]."""
    return State(s.started, mode, s.time, s.depth, mud, s.neck_age, s.neck_v, s.neck_z, s.direction, s.velocity,
                 s.neck_g, s.neck_gi, strain)


@_compiled()
def first_sample(s: State, depth: float) -> State:
    """The state at the first sample ``depth`` [m]: CONTACT, relaxed (``z_m = z_i``), below the surface, else FREE."""
    mode = CONTACT if depth > 0.0 else FREE
    return State(1.0, mode, 0.0, depth, depth, 0.0, 0.0, 0.0, 0.0, 0.0, s.neck_g, s.neck_gi, 0.0)


@_compiled()
def leave_necked(s: State) -> State:
    """NECKED -> CONTACT (keeping ``z_m``) if the foot is below the surface at the step's start, else FREE.

    Taken when the foot moves down again (docs/model.md's table).
    """
    z0 = s.depth
    if z0 > 0.0:
        return _moved(s, _CONTACT, s.mud, z0 - s.mud)
    return _moved(s, _FREE, z0, s.strain)


@_compiled()
def touchdown(s: State, v: float) -> tuple[State, float]:
    """FREE -> CONTACT from the instant the foot crosses the surface, with ``z_m = 0`` there.

    ``s`` is at the step's start (depth ``z0``), the foot moving at ``v``
    [m/s] and below the surface at the step's end. Returns the state in
    CONTACT at the crossing (depth 0, relaxed) and the time from the
    step's start to the crossing [s].
    """
    z0 = s.depth
    start = -z0 / v if z0 < 0.0 else 0.0
    return _moved(s, _CONTACT, 0.0, 0.0), start


@_compiled(inline=_in_full_output_loop)
def free_step(s: State, z1: float) -> State:
    """A step in FREE that stays above the surface (``z1 <= 0`` [m]): the mud surface follows the foot."""
    return _moved(s, _FREE, z1, s.strain)


@_compiled()
def intrusion_step(s: State, c: Cache, p: Params, z1: float, v: float, dt: float, start: float) -> State:
    """CONTACT on the intrusion (or hold) branch from ``start`` [s] into the step to its end at ``z1`` [m].

    The Maxwell element with ``k_m_i, b_m_i``, Eqs. (2)-(3), in closed form
    (:func:`mudforce.model.equations.maxwell_strain_step`). A step that ends
    above the surface ends in FREE (docs/model.md's table).
    """
    decay = c.decay_i if start == 0.0 else math.exp(-(dt - start) / p.tau_i)
    strain = maxwell_strain_step(s.strain, v, p.tau_i, decay)
    if z1 <= 0.0:
        return _moved(s, _FREE, z1, strain)
    return _moved(s, _CONTACT, z1 - strain, strain)


@_compiled()
def neck(s: State, p: Params, strain: float, z_n: float, offset: float, dt: float) -> State:
    """CONTACT -> NECKED at ``offset`` [s] into a step of ``dt`` [s], the foot at ``z_n`` [m], Eq. (9).

    ``strain`` is ``z_i - z_m`` at necking [m]. The mud then moves with the
    velocity ``v_m0`` it had, decaying by Eq. (7) (:func:`neck_filter_response`
    over the rest of the step).
    """
    neck_v = necking_velocity(strain, p.tau_w)
    neck_z = z_n - strain
    age = dt - offset
    g, gi = neck_filter_response(age, p.zeta, p.omega_0)
    _, mud = necked_mud_motion(neck_v, neck_z, g, gi)
    return State(s.started, NECKED, s.time, s.depth, mud, age, neck_v, neck_z, s.direction, s.velocity, g, gi,
                 strain)


@_compiled(inline="always")
def withdrawal_step(s: State, c: Cache, p: Params, z_start: float, z1: float, v: float, dt: float, start: float
                    ) -> tuple[State, float]:
    """:func:`withdrawal_general`, with its most common case compiled into the caller (speed plumbing).

    The common case: a whole step on the withdrawal branch (``start == 0``), on one side of the surface,
    that does not neck. There :func:`withdrawal_general` takes one piece with the step's cached decay and
    makes the same calls in the same order, so the bits are the same; any other step goes to it. Inlining
    all of it into every loop costs about 13 s of numba compile (docs/speed.md, "Cold compile"), and
    leaving all of it a call made the calibration loop about 5 % slower.
    """
    if start == 0.0 and (z_start > 0.0) == (z1 > 0.0):
        fs = piece_drag(p, z_start, v, dt)
        tn = necking_time(s.strain, v, p.tau_w, p.k_w, fs, p.sigma_y, dt, c.decay_w)
        if tn < 0.0:
            strain = maxwell_strain_step(s.strain, v, p.tau_w, c.decay_w)
            return _moved(s, _CONTACT, z1 - strain, strain), math.nan
    return withdrawal_general(s, c, p, z_start, z1, v, dt, start)


@_compiled()
def withdrawal_general(s: State, c: Cache, p: Params, z_start: float, z1: float, v: float, dt: float, start: float
                       ) -> tuple[State, float]:
    """CONTACT on the withdrawal branch from ``start`` [s] (depth ``z_start`` [m]) to the step's end at ``z1``.

    The Maxwell element with ``k_m_w, b_m_w``; the neck breaks at the
    first instant the suction passes ``-sigma_y``, Eq. (9), located in
    closed form (:func:`mudforce.model.equations.necking_time`), and the step
    goes on in NECKED (:func:`neck`). The drag acts only while ``z_i > 0``,
    so the step is split where it crosses the surface; in each piece the
    stress is monotone. Returns the state at the step's end and the time
    from the step's start to necking [s] (NaN if none).
    """
    tau_w = p.tau_w
    split = dt
    if (z_start > 0.0) != (z1 > 0.0) and v != 0.0:
        tc = start - z_start / v
        if start < tc < dt:
            split = tc
    t_a = start
    z_a = z_start
    strain = s.strain
    pieces = 1 if split == dt else 2
    for piece in range(pieces):
        t_b = split if piece == 0 else dt
        length = t_b - t_a
        fs = piece_drag(p, z_a, v, length)
        if t_a == 0.0 and t_b == dt:
            decay = c.decay_w
        else:
            decay = math.exp(-length / tau_w)
        tn = necking_time(strain, v, tau_w, p.k_w, fs, p.sigma_y, length, decay)
        if tn >= 0.0:
            if tn > 0.0:
                strain = yield_strain(p.k_w, p.sigma_y, fs)  # exactly on the yield surface
            return neck(s, p, strain, z_a + v * tn, t_a + tn, dt), t_a + tn
        strain = maxwell_strain_step(strain, v, tau_w, decay)
        t_a = t_b
        z_a = 0.0 if piece == 0 and pieces == 2 else z1
    return _moved(s, _CONTACT, z1 - strain, strain), math.nan


@_compiled()
def piece_drag(p: Params, z_a: float, v: float, length: float) -> float:
    """Drag stress [Pa], Eq. (5), over a withdrawal piece of ``length`` [s] from depth ``z_a`` [m] at ``v`` [m/s].

    The drag acts while the foot is below the surface; a piece does not
    cross it, so its midpoint decides
    (:func:`mudforce.model.equations.piece_midpoint_depth`).
    """
    return submerged_drag_stress(p.lam, p.rho_m, v, piece_midpoint_depth(z_a, v, length))


@_compiled()
def neck_filter_step(c: Cache, p: Params, age: float, gi: float, g: float) -> tuple[float, float]:
    """``(G, g)`` of Eq. (7)'s filter one whole step later, at ``age`` [s]: its exact discrete-time update.

    The transition matrix is the cache's; past
    :func:`mudforce._kernel.layout.neck_flush_age` the response is zero.
    """
    if age > p.neck_flush:
        gi = 0.0
        g = 0.0
    return neck_filter_update(c.phi0, c.phi1, c.phi2, c.phi3, gi, g)


@_compiled(inline=_in_full_output_loop)
def necked_step(s: State, c: Cache, p: Params, dt: float) -> State:
    """A whole step in NECKED: the mud decays by Eq. (7), one step of its exact discrete update."""
    age = s.neck_age + dt
    gi, g = neck_filter_step(c, p, age, s.neck_gi, s.neck_g)
    _, mud = necked_mud_motion(s.neck_v, s.neck_z, g, gi)
    return State(s.started, NECKED, s.time, s.depth, mud, age, s.neck_v, s.neck_z, s.direction, s.velocity, g, gi,
                 s.strain)


# ---------------------------------------------------------------- the dispatcher
@_compiled(inline="always")
def advance(s: State, c: Cache, p: Params, ring: np.ndarray, j: int, depth: float, dt: float) -> Step:
    """The state machine: foot state ``s`` at the last sample -> state at ``depth`` [m] after ``dt`` [s].

    A pure function of its arguments except for the velocity filter's
    history ``ring[j]`` (read and written only for filter windows > 1).
    ``c`` holds what the step length allows to precompute
    (:func:`step_cache`). Refuses (``ok`` False, state unchanged) a
    non-finite depth, a ``dt`` not finite and > 0, and a window > 1
    without a ring row of ``N_RING`` columns. The first call on a fresh
    state sets the initial sample and ignores ``dt``.
    """
    nan = math.nan
    window = int(p.window)
    if not math.isfinite(depth):
        return Step(s, c, False, nan, 0.0)
    if window > 1 and ring.shape[1] < N_RING:
        return Step(s, c, False, nan, 0.0)  # no room for the filter's history (arrays are not bounds-checked)
    if s.started == 0.0:
        if window > 1:
            ring_start(ring, int(j), depth)  # int(j): see ring_velocity's call below
        return Step(first_sample(s, depth), c, True, nan, 0.0)
    if not (dt > 0.0) or not math.isfinite(dt):
        return Step(s, c, False, nan, 0.0)

    z1 = depth
    v = (z1 - s.depth) / dt  # first-order hold: constant velocity over the step
    t1 = s.time + dt
    # int(j): one compiled signature of the ring's functions, int64, whether the caller's row is a variable or
    # a constant 0 (numba types a constant as a literal type of its own)
    vhat = v if window <= 1 else ring_velocity(ring, int(j), window, z1, t1)
    d = _direction(vhat, s.direction, p.deadband)
    c = step_cache(c, p, dt)

    # transitions at the step's start
    if s.mode == NECKED and d > 0.0:
        s = leave_necked(s)
    start = 0.0  # time into the step at which CONTACT begins
    z_start = s.depth
    if s.mode == FREE:
        if z1 > 0.0:
            s, start = touchdown(s, v)
            z_start = 0.0
        else:
            s = free_step(s, z1)
    # the step in the state reached
    neck_offset = nan
    if s.mode == CONTACT:
        if d >= 0.0:
            s = intrusion_step(s, c, p, z1, v, dt, start)
        else:
            s, neck_offset = withdrawal_step(s, c, p, z_start, z1, v, dt, start)
    elif s.mode == NECKED:
        s = necked_step(s, c, p, dt)

    end = State(1.0, s.mode, t1, z1, s.mud, s.neck_age, s.neck_v, s.neck_z, d, vhat, s.neck_g, s.neck_gi, s.strain)
    return Step(end, c, True, neck_offset, v)


@_compiled(inline="always")
def quiet_step(s: State, c: Cache, p: Params, depth: float, dt: float) -> Step:
    """:func:`advance` for a step in which nothing happens; ``ok`` False if something does.

    Nothing happens in a step when the state has started, its length is
    the cached one (so the cached decays apply), the contact state stays
    what it was, and no surface crossing or necking falls inside it: most
    steps of a trajectory sampled at a constant rate, and of feet stepped
    together. For those this does exactly what :func:`advance` does,
    through the same functions, without its bookkeeping; the loops call
    :func:`advance` for the others. Only for the exact velocity rule
    (:func:`exact_rule`), which the caller checks. The state is
    meaningless when ``ok`` is False (the loops then call :func:`advance`).
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
    if mode == FREE:
        ok = ok & (depth <= 0.0)  # else touchdown
        zm = depth
    elif mode == NECKED:
        ok = ok & (d <= 0.0)  # else NECKED ends
        age += dt
        gi, g = neck_filter_step(c, p, age, gi, g)
        _, zm = necked_mud_motion(s.neck_v, s.neck_z, g, gi)
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
        zm = depth - strain
    s1 = State(1.0, mode, s.time + dt, depth, zm, age, s.neck_v, s.neck_z, d, v, g, gi, strain)
    return Step(s1, c, ok, math.nan, v)


_QUIET_STEP_CODE = cast(Any, quiet_step).py_func.__code__
# quiet_step's source lines, for _in_quiet_step
_QUIET_STEP_LINES = (_QUIET_STEP_CODE.co_firstlineno,
                     max(line for _, _, line in _QUIET_STEP_CODE.co_lines() if line is not None),
                     _QUIET_STEP_CODE.co_filename)


@_compiled(inline="always")
def exact_rule(p: Params) -> bool:
    """True for the exact velocity rule (filter window <= 1, no deadband): the branch direction is ``sign(v)``."""
    return int(p.window) <= 1 and not (p.deadband > 0.0)


@_compiled(inline="always")
def advance_quick(s: State, c: Cache, p: Params, ring: np.ndarray, j: int, depth: float, dt: float) -> Step:
    """:func:`advance`, through :func:`quiet_step` when nothing happens in the step: the same results, sooner."""
    if exact_rule(p):
        r = quiet_step(s, c, p, depth, dt)
        if r.ok:
            return r
    return advance(s, c, p, ring, j, depth, dt)


# ---------------------------------------------------------------- a sample's force
@_compiled(inline="always")
def stress_parts(p: Params, s: State, v: float) -> tuple[float, float, float, bool]:
    """A sample's stresses but the nonlinear spring's, from its state ``s`` and the step's velocity ``v`` [m/s].

    Returns ``(f_e1, f_s [Pa], dz_m/dt [m/s], spring)``: the branch's
    stress (:func:`mudforce.model.equations.intrusion_stress`,
    :func:`~mudforce.model.equations.withdrawal_stress`,
    :func:`~mudforce.model.equations.necked_stress`) and the drag, Eq. (5), while
    below the surface; ``spring`` is True where the nonlinear spring,
    Eq. (4), acts (CONTACT on the intrusion branch), which
    :func:`sample_outputs` evaluates at once and the loops over many
    samples or feet in one vectorised pass.
    """
    if s.mode == FREE:
        return 0.0, 0.0, v, False
    fs = submerged_drag_stress(p.lam, p.rho_m, v, s.depth)
    if s.mode == CONTACT:
        if s.direction >= 0.0:
            fe1, mud_velocity = intrusion_stress(p.k_i, p.tau_i, s.strain)
            return fe1, fs, mud_velocity, True
        fe1, mud_velocity = withdrawal_stress(p.k_w, p.tau_w, s.strain)
        return fe1, fs, mud_velocity, False
    fe1, mud_velocity = necked_stress(p.b_w, necked_mud_motion(s.neck_v, s.neck_z, s.neck_g, s.neck_gi)[0])
    return fe1, fs, mud_velocity, False


@_compiled(inline="always")
def total_force(fe1: float, fe2: float, fs: float, area: float) -> float:
    """The force [N]: :func:`mudforce.model.equations.total_stress` of the stresses [Pa] times the area [m^2],
    Eq. (1)."""
    return total_stress(fe1, fe2, fs) * area


@_compiled(inline="always")
def sample_outputs(p: Params, s: State, v: float) -> tuple[float, float, float, float, float]:
    """The force and its parts at a sample (see :func:`stress_parts`).

    Returns ``(force [N], f_e1, f_e2, f_s [Pa], dz_m/dt [m/s])``: Eqs. (2),
    (4), (5), (7) and (8) times the area. The spring goes through
    :func:`mudforce.model.equations.nonlinear_spring_stress`, as on every path.
    """
    fe1, fs, mud_velocity, spring = stress_parts(p, s, v)
    fe2 = nonlinear_spring_stress(p.alpha, p.beta, s.depth, p.width) if spring else 0.0
    return total_force(fe1, fe2, fs, p.area), fe1, fe2, fs, mud_velocity
