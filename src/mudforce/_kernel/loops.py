"""Speed plumbing: the loops that run the step of :mod:`~mudforce._kernel.transitions` over samples and feet.

Nothing here is physics: every loop calls :func:`~mudforce._kernel.transitions.advance`
(or :func:`~mudforce._kernel.transitions.quiet_step`, which gives the same
bits) and :func:`~mudforce._kernel.transitions.stress_parts`, and differs
only in what it writes where:

* :func:`step` (streaming, MuJoCo, the built-in engine) loads a foot's row
  of ``states``, advances it, stores it, and writes all outputs to
  ``out[:, k]``; :func:`stream_step` is it for one foot packed in one array;
* :func:`run_feet` (``MudContacts``) does that for every foot, writing
  only the forces; :func:`run_feet_threads` on slices of the feet;
* :func:`run_batch_compact` (``simulate``) keeps the state in registers
  through the whole trajectory and writes the force, the contact state and
  ``z_m``; the steps in which nothing happens go through :func:`glide`;
* :func:`run_batch` (calibration, and ``simulate``'s other outputs on
  demand) writes every output of every sample, from any sample on.

:func:`run_feet` and :func:`run_batch_compact` set the feet or samples on
the spring aside and compute their forces in one vectorised pass
(:func:`spring_pass`); the spring's power (:func:`mudforce._plumbing.pow.power`)
gives the same bits there as in a single call, so every path agrees.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MIN_DT, out_of_bounds
from mudforce._kernel.layout import (
    CONTACT,
    FREE,
    N_OUT,
    N_PARAMS,
    N_RING,
    N_STATE,
    NECKED,
    O_F_E1,
    O_F_E2,
    O_F_S,
    O_FORCE,
    O_MUD,
    O_MUD_VELOCITY,
    O_NECK_OFFSET,
    O_STATE,
    O_VELOCITY,
    P_WINDOW,
    S_STARTED,
    Cache,
    Params,
    State,
    _compiled,
    load_cache,
    load_params,
    load_state,
    new_states,
    ring_width,
    store_cache,
    store_state,
)
from mudforce._kernel.transitions import (
    Step,
    advance,
    advance_quick,
    exact_rule,
    quiet_step,
    sample_outputs,
    stress_parts,
    total_force,
)
from mudforce.model.equations import nonlinear_spring_stress

__all__ = [
    "N_SPRING",
    "advance_row",
    "foot_force_or_defer",
    "glide",
    "new_feet_scratch",
    "new_spring_scratch",
    "new_stream_buffer",
    "run_batch",
    "run_batch_compact",
    "run_batch_compiled",
    "run_feet",
    "run_feet_threads",
    "spring_pass",
    "step",
    "stream_parts",
    "stream_step",
]

# rows of the scratch block of the deferred spring pass: one column per sample or foot on the spring
SP_DEPTH = 0  # z_i [m]
SP_WIDTH = 1  # H [m]
SP_ALPHA = 2  # alpha [Pa]
SP_BETA = 3  # beta [-]
SP_F_E1 = 4  # f_e1 [Pa]; the pass overwrites it with the force [N]
SP_AREA = 5  # area [m^2]
SP_F_S = 6  # f_s [Pa]
N_SPRING = 7


def new_spring_scratch(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A scratch block for ``n`` samples or feet on the spring, and its int64 index of where each force goes."""
    return np.empty((N_SPRING, n), dtype=np.float64), np.empty(n, dtype=np.int64)


@_compiled()
def spring_pass(scratch: np.ndarray, index: np.ndarray, m: int, forces: np.ndarray) -> None:
    """The forces [N] of the first ``m`` columns of ``scratch`` into ``forces[index[i]]``.

    Each is the nonlinear spring, Eq. (4), plus the rest of the stress,
    times the area (:func:`~mudforce._kernel.transitions.total_force`).
    Computed in a loop with no branches over contiguous rows, which the
    compiler vectorises (the spring's power is most of a step's
    arithmetic, and vectorised it costs a fraction of a scalar call), then
    scattered to where each force goes.
    """
    z = scratch[SP_DEPTH]
    w = scratch[SP_WIDTH]
    a = scratch[SP_ALPHA]
    b = scratch[SP_BETA]
    fe1 = scratch[SP_F_E1]
    fs = scratch[SP_F_S]
    area = scratch[SP_AREA]
    for i in range(m):
        fe1[i] = total_force(fe1[i], nonlinear_spring_stress(a[i], b[i], z[i], w[i]), fs[i], area[i])
    for i in range(m):
        forces[index[i]] = fe1[i]


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
def _write_sample(out: np.ndarray, k: int, p: Params, r: Step) -> float:
    """Every output of the sample ``r`` (what :func:`advance` returned) into ``out[:, k]``; returns the force [N]."""
    s = r.state
    force, fe1, fe2, fs, mud_velocity = sample_outputs(p, s, r.velocity)
    _write(out, k, force, fe1, fe2, fs, s.mud, mud_velocity, s.velocity, float(s.mode), r.neck_offset)
    return force


@_compiled(inline="always")
def _advance_row(states: np.ndarray, ring: np.ndarray, j: int, params: np.ndarray, depth: float, dt: float
                 ) -> tuple[Step, Params]:
    """:func:`advance` foot ``j`` in place: load its rows, step, store (unless refused); returns the step and params."""
    p = load_params(params, j)
    c = load_cache(states, j)
    r = advance(load_state(states, j), c, p, ring, j, depth, dt)
    if r.ok:
        store_state(states, j, r.state)
        if r.cache.dt != c.dt:
            store_cache(states, j, r.cache)
    return r, p


@_compiled()
def advance_row(states: np.ndarray, ring: np.ndarray, j: int, params: np.ndarray, depth: float, dt: float) -> Step:
    """:func:`_advance_row` as a call of its own, without the params: the state machine compiled once.

    Speed plumbing. The loops over samples and feet (:func:`run_batch_compact`,
    :func:`run_batch_compiled`, :func:`run_feet`) compile :func:`advance` into
    their own loops. The paths where a call costs nothing next to their own
    work share this one copy instead, each of which compiled the whole state
    machine into itself before (a few seconds of compile each, on every cold
    start): :func:`step` (so the streaming step, the 1-D MuJoCo adapter's step
    and a direct call of it), and the 3-D step's elements that do not take the
    quiet step (~1 % of a walk's element-steps, where ~1,000 instructions
    inlined into the element loop would also crowd the quiet steps'
    registers). Every caller passes C-contiguous float64 rows, so that it is
    compiled once.
    """
    r, _ = _advance_row(states, ring, j, params, depth, dt)
    return r


@_compiled(inline="always")
def step(states: np.ndarray, ring: np.ndarray, j: int, params: np.ndarray, depth: float, dt: float,
         out: np.ndarray, k: int) -> float:
    """Advance foot ``j`` to the next sample ``depth`` [m] after ``dt`` [s].

    Row ``j`` of ``states``, ``params`` and ``ring`` are the foot's; writes
    the sample's outputs to column ``out[:, k]`` and returns the force [N].
    The first call on a fresh state sets the initial sample and ignores
    ``dt``. Returns NaN, changing nothing, for a non-finite depth or a
    ``dt`` that is not finite and > 0, and for a filter window > 1 without
    a ring row of ``N_RING`` columns (:func:`~mudforce._kernel.layout.new_ring`).
    """
    r = advance_row(states, ring, int(j), params, depth, dt)  # (a call: see advance_row; int(j): not a literal 0)
    if not r.ok:
        return math.nan
    return _write_sample(out, k, load_params(params, j), r)


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
    """:func:`step` for one foot packed by :func:`new_stream_buffer` (one argument: less call overhead).

    Also returns NaN, changing nothing, for a depth beyond +-``MAX_DEPTH``
    and, once started, a ``dt`` outside [``MIN_DT``, ``MAX_DT``]
    (:mod:`~mudforce._kernel.bounds`): ``MudContact.step`` refuses those,
    and checking them here costs nothing, where Python would pay for it on
    every call.
    """
    _, _, out, _ = _stream_parts(buf)
    # the state's, the params' and the ring's whole rows (C-contiguous, where stream_parts' column slices are not:
    # the one compiled signature of advance_row and of the ring's functions that every other caller passes; the
    # columns past a row's own are never read); the ring's N_RING columns for a window > 1 (new_stream_buffer),
    # and fewer than N_RING otherwise, which advance refuses for a window > 1 as it does the slice's 0
    states = buf[_STREAM_STATE:_STREAM_STATE + 1]
    params = buf[_STREAM_PARAMS:_STREAM_PARAMS + 1]
    ring = buf[_STREAM_RING:_STREAM_RING + 1]
    if not -MAX_DEPTH <= depth <= MAX_DEPTH:  # False for NaN
        return math.nan
    if states[0, S_STARTED] != 0.0 and not MIN_DT <= dt <= MAX_DT:
        return math.nan
    force: float = step(states, ring, 0, params, depth, dt, out, 0)
    return force


def run_batch(time: np.ndarray, depth: np.ndarray, states: np.ndarray, ring: np.ndarray, params: np.ndarray,
              out: np.ndarray, first: int = 0) -> int:
    """:func:`run_batch_compiled` through one compiled specialisation (speed plumbing, not physics).

    numba compiles a function once per argument type: a read-only trajectory (a result's own arrays), a
    writable one, ``first`` given or left out were three compilations of the largest loop (about 6 s each,
    on every cold start). Here the trajectory is always passed read-only (a view: no copy) and ``first`` as
    an integer, so there is one.
    """
    return run_batch_compiled(_read_only(time), _read_only(depth), states, ring, params, out, int(first))


def _read_only(array: np.ndarray) -> np.ndarray:
    view: np.ndarray = array.view()
    view.flags.writeable = False
    return view


@_compiled()
def run_batch_compiled(time: np.ndarray, depth: np.ndarray, states: np.ndarray, ring: np.ndarray,
                       params: np.ndarray, out: np.ndarray, first: int) -> int:
    """Run foot 0 over samples ``first, first + 1, ...`` of a trajectory into ``out[:, k - first]``.

    Returns the index of a bad sample or -1. With ``first > 0`` the state
    must hold sample ``first - 1`` (e.g. a copy of the state another run
    stopped at, to rerun only the tail under other constants: then
    :func:`~mudforce._kernel.layout.forget_cache` it). The state stays in
    registers through the loop (a :class:`State` value) and is stored to
    ``states[0]`` at the end (or before a bad sample). Each step is
    :func:`~mudforce._kernel.transitions.advance_quick`.
    """
    s = load_state(states, 0)
    c = load_cache(states, 0)
    p = load_params(params, 0)
    n = time.shape[0]
    bad = -1
    for k in range(first, n):
        dt = time[k] - time[k - 1] if k > 0 else 0.0
        r = advance_quick(s, c, p, ring, 0, depth[k], dt)
        if not r.ok:
            bad = k
            break
        s = r.state
        c = r.cache
        _write_sample(out, k - first, p, r)
    store_state(states, 0, s)
    store_cache(states, 0, c)
    return bad


@_compiled(inline="always")
def foot_force_or_defer(scratch: np.ndarray, index: np.ndarray, m: int, j: int, p: Params, s: State, velocity: float,
                        forces: np.ndarray) -> int:
    """Foot ``j``'s force [N] into ``forces[j]``, or, when it has the spring of Eq. (4), its column set aside
    (with its own constants) for the one :func:`spring_pass` after all feet; returns the new count.

    ``p`` the foot's :class:`Params`, ``s`` its new state, ``velocity`` the branch velocity [m/s].
    """
    fe1, fs, _, spring = stress_parts(p, s, velocity)
    if spring:
        index[m] = j
        scratch[SP_DEPTH, m] = s.depth
        scratch[SP_WIDTH, m] = p.width
        scratch[SP_ALPHA, m] = p.alpha
        scratch[SP_BETA, m] = p.beta
        scratch[SP_F_E1, m] = fe1
        scratch[SP_F_S, m] = fs
        scratch[SP_AREA, m] = p.area
        return m + 1
    forces[j] = total_force(fe1, 0.0, fs, p.area)
    return m


@_compiled(inline="always")
def defer_spring(scratch: np.ndarray, index: np.ndarray, m: int, k: int, depth: float, fe1: float, fs: float,
                 forces: np.ndarray) -> int:
    """Set sample ``k`` (depth [m], ``f_e1``, ``f_s`` [Pa]) aside for the spring pass; returns the new count.

    The block's constant rows (width, alpha, beta, area) are the caller's
    to fill; a full block is passed (:func:`spring_pass`) into ``forces``.
    """
    index[m] = k
    scratch[SP_DEPTH, m] = depth
    scratch[SP_F_E1, m] = fe1
    scratch[SP_F_S, m] = fs
    m += 1
    if m == scratch.shape[1]:
        spring_pass(scratch, index, m, forces)
        m = 0
    return m


@_compiled(inline="always")
def _within_bounds(time: np.ndarray, depth: np.ndarray, k: int) -> bool:
    """Sample ``k``'s time and depth, and the step before it, within :mod:`~mudforce._kernel.bounds` (False for NaN)."""
    return not out_of_bounds(time[k], depth[k], time[k] - time[k - 1] if k > 0 else MIN_DT)


@_compiled(inline="always")
def glide(time: np.ndarray, depth: np.ndarray, k: int, s: State, c: Cache, p: Params, mode_out: np.ndarray,
          mud_out: np.ndarray, force_out: np.ndarray, scratch: np.ndarray, index: np.ndarray, m: int,
          time_out: np.ndarray, depth_out: np.ndarray) -> tuple[State, int, int]:
    """:func:`quiet_step` over samples ``k, k+1, ...`` (``k >= 1``) while nothing happens; returns ``(s, k, m)``.

    Writes what :func:`run_batch_compact` writes for those samples and
    returns the state after them, the index of the first sample in which
    something happens (or ``n``) and the spring block's new count ``m``.
    A loop of its own, apart from :func:`advance`'s (with which it would
    share registers), and one copy of it per contact state, which the
    state stays in (so the compiler drops the other states' code from it).
    """
    if s.mode == FREE:
        return _glide_in(FREE, time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m,
                         time_out, depth_out)
    if s.mode == CONTACT:
        return _glide_in(CONTACT, time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m,
                         time_out, depth_out)
    return _glide_in(NECKED, time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m,
                     time_out, depth_out)


@_compiled(inline="always")
def _glide_in(mode: int, time: np.ndarray, depth: np.ndarray, k: int, s: State, c: Cache, p: Params,
              mode_out: np.ndarray, mud_out: np.ndarray, force_out: np.ndarray, scratch: np.ndarray,
              index: np.ndarray, m: int, time_out: np.ndarray, depth_out: np.ndarray) -> tuple[State, int, int]:
    """:func:`glide` for a state in contact state ``mode`` (a constant at each call site)."""
    n = time.shape[0]
    copy = time_out.shape[0] == n
    s = State(s.started, mode, s.time, s.depth, s.mud, s.neck_age, s.neck_v, s.neck_z, s.direction, s.velocity,
              s.neck_g, s.neck_gi, s.strain)  # the mode as the constant it is here
    while k < n:
        if copy and not _within_bounds(time, depth, k):
            break  # run_batch_compact refuses it
        r = quiet_step(s, c, p, depth[k], time[k] - time[k - 1])
        if not r.ok:
            break
        s = r.state
        if copy:
            time_out[k] = time[k]
            depth_out[k] = depth[k]
        mode_out[k] = mode
        mud_out[k] = s.mud
        fe1, fs, _, spring = stress_parts(p, s, r.velocity)
        if spring:
            m = defer_spring(scratch, index, m, k, s.depth, fe1, fs, force_out)
        else:
            force_out[k] = total_force(fe1, 0.0, fs, p.area)
        k += 1
    return s, k, m


@_compiled()
def run_batch_compact(time: np.ndarray, depth: np.ndarray, states: np.ndarray, ring: np.ndarray,
                      params: np.ndarray, mode_out: np.ndarray, mud_out: np.ndarray, neck_index: np.ndarray,
                      neck_offset: np.ndarray, counts: np.ndarray, force_out: np.ndarray, scratch: np.ndarray,
                      index: np.ndarray, time_out: np.ndarray, depth_out: np.ndarray) -> int:
    """Run foot 0 over a whole trajectory: the force [N], the contact state (int8) and ``z_m`` [m] per sample.

    Neckings go to ``neck_index[:counts[0]]`` (sample) and ``neck_offset``
    (time into the step [s]): those arrays are written only at neckings.
    The other outputs are :func:`run_batch`'s to give (``simulate`` runs it
    when they are asked for): this loop writes about a third of its
    memory traffic, which bounds the batch's speed. Steps in which nothing
    happens go through :func:`glide`, the others through :func:`advance`.
    The nonlinear spring's samples are collected in ``scratch``
    (:func:`new_spring_scratch`, any width >= 1) and their forces computed
    a block at a time (:func:`spring_pass`). ``time_out`` and ``depth_out``
    receive a copy of ``time`` and ``depth`` if they have their length
    (reading them costs nothing more here than in a copy of its own;
    pass empty arrays for none); the samples are then also held to the
    bounds of :mod:`~mudforce._kernel.bounds` (``simulate``'s promise,
    checked here rather than in a pass of its own), a sample out of bounds
    ending the loop as a refused one does. Returns the index of a bad
    sample or -1.
    """
    s = load_state(states, 0)
    c = load_cache(states, 0)
    p = load_params(params, 0)
    n = time.shape[0]
    copy = time_out.shape[0] == n
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
            s, k, m = glide(time, depth, k, s, c, p, mode_out, mud_out, force_out, scratch, index, m, time_out,
                            depth_out)
            if k == n:
                break
            backoff = min(2 * backoff + 1, 64) if k == k0 else 0
            wait = backoff
        elif wait > 0:
            wait -= 1
        if copy and not _within_bounds(time, depth, k):
            bad = k
            break
        dt = time[k] - time[k - 1] if k > 0 else 0.0
        r = advance(s, c, p, ring, 0, depth[k], dt)
        if not r.ok:
            bad = k
            break
        s = r.state
        c = r.cache
        if copy:
            time_out[k] = time[k]
            depth_out[k] = depth[k]
        mode_out[k] = s.mode
        mud_out[k] = s.mud
        fe1, fs, _, spring = stress_parts(p, s, r.velocity)
        if spring:
            m = defer_spring(scratch, index, m, k, s.depth, fe1, fs, force_out)
        else:
            force_out[k] = total_force(fe1, 0.0, fs, p.area)
        offset = r.neck_offset
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

    Each foot's step is :func:`~mudforce._kernel.transitions.advance_quick`'s.
    The feet on the nonlinear spring are collected in ``scratch`` and
    ``index`` (:func:`new_spring_scratch` for as many feet) and their
    forces computed in one vectorised pass (:func:`spring_pass`) after the
    loop. Returns the first foot refused (left unchanged, its force not
    written) or -1.
    """
    bad = -1
    # an int64 from the start: a constant 0 is a literal type of its own, which numba's first pass of type inference
    # compiled spring_pass for before the loop's count made it int64 (one compiled signature now)
    m = np.int64(0)
    for j in range(depths.shape[0]):
        # advance_quick, written out: a foot that takes quiet_step stores only
        # its state, on a path of its own (through _advance_row's shared
        # store it was 10-15 % slower)
        p = load_params(params, j)
        ok = False
        if exact_rule(p):
            r = quiet_step(load_state(states, j), load_cache(states, j), p, depths[j], dt)
            ok = r.ok
            if ok:
                store_state(states, j, r.state)
        if not ok:
            r, p = _advance_row(states, ring, j, params, depths[j], dt)
            if not r.ok:
                if bad < 0:
                    bad = j
                continue
        m = foot_force_or_defer(scratch, index, m, j, p, r.state, r.velocity, forces)
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
