"""The online tracker's compiled update (speed plumbing): :func:`_track_step` steps every foot's bank of models on a
sample and updates its posterior in one compiled call, over arrays the classes of :mod:`mudforce.estimation.tracker`
hold; beside it the helpers they use to pack those arrays, restore a snapshot's step caches, refuse a sample out of
bounds and build the blur matrices. The contact physics is the kernel's (:mod:`mudforce._kernel`), the constants and
layout :mod:`mudforce.estimation._tracker_layout`'s; the statistics are set out in :mod:`mudforce.estimation.tracker`
and docs/tracking.md.
"""

from __future__ import annotations

import functools
import math
from typing import Any, cast

import numpy as np

from mudforce import _kernel as K
from mudforce._kernel.layout import N_RING, P_DEADBAND, P_WINDOW, R_HEAD, R_N, R_T, R_Z, RING, store_cache
from mudforce._kernel.transitions import step_cache
from mudforce._plumbing.jit import njit
from mudforce.engines.dynamics.rest_band import rest_band, rest_band_spread
from mudforce.errors import InputError
from mudforce.estimation._tracker_layout import (
    _A_ANCHOR,
    _A_ANCHOR_HIGH,
    _A_ANCHOR_LOW,
    _A_BIAS,
    _A_CLING,
    _A_CLING_N,
    _A_CLING_Z,
    _A_CLOCK,
    _A_CONTACT,
    _A_D2VAR,
    _A_DEL_L,
    _A_DEL_Y,
    _A_DHEAD,
    _A_DN,
    _A_DRING,
    _A_DRING_T,
    _A_DVAR,
    _A_FPREV,
    _A_HOLD,
    _A_HULL_HIGH,
    _A_HULL_LOW,
    _A_JUMP,
    _A_LAG,
    _A_LAG_A,
    _A_LAG_L,
    _A_LAG_SD,
    _A_LAG_Y,
    _A_LAG_Y2,
    _A_MISFIT,
    _A_MISFIT_T,
    _A_NFREE,
    _A_PPREV,
    _A_PSUB,
    _A_QUICK,
    _A_RUN,
    _A_RUN_MEAN,
    _A_RUN_QUIET,
    _A_RUN_SQ,
    _A_SINK,
    _A_STARTED,
    _A_TARE_EW,
    _A_TARE_PREV,
    _A_TARE_VAR0,
    _A_TURN,
    _A_VAR,
    _A_W_LAST,
    _A_Z2,
    _A_Z3,
    _A_ZN,
    _A_ZPREV,
    _BLUR_FACTORS,
    _C_BIAS0,
    _C_BLUR_REF,
    _C_DISC,
    _C_DOF,
    _C_FLOOR,
    _C_FREE_MEMORY,
    _C_GAIN,
    _C_HULL,
    _C_LAG,
    _C_LEAD,
    _C_LEVEL,
    _C_MARGIN,
    _C_MAX_DEPTH,
    _C_MISFIT,
    _C_MISFIT_RATIO,
    _C_OFFSET_RES,
    _C_OFFSET_TEMPER,
    _C_QUICK,
    _C_QUICK_OFF,
    _C_QUICK_ON,
    _C_QUICK_SINK,
    _C_QUICK_SINK_MAX,
    _C_RATE_GAIN,
    _C_REST,
    _C_REST_SPREAD,
    _C_ROBUST_DEADBAND,
    _C_ROBUST_WINDOW,
    _C_SETTLE,
    _C_SHALLOW,
    _C_SHALLOW_GAIN,
    _C_SMOOTH,
    _C_SUBSTEP,
    _C_TAU,
    _C_TEMP,
    _C_TEMPER,
    _CLING_SAMPLES,
    _CLING_SIGMAS,
    _DELAYS,
    _DEPTH_NOISE0,
    _DEPTH_NOISE_MEMORY,
    _END_REACH,
    _END_REACH_FROM,
    _G_HIGH,
    _G_LAG,
    _G_LOW,
    _G_MISFIT,
    _G_OFFSET,
    _HULL_HOLD,
    _HULL_JUMP,
    _HULL_WIDE,
    _LAG_LOG_PRIOR,
    _LAG_SPREAD_WIDENING,
    _LAG_WIDENING,
    _LAG_WIDENING_STEP,
    _LAGS,
    _LAGS_A,
    _LAGS_B,
    _MAX_SUBSTEPS,
    _MISFIT_CLIP,
    _MISFIT_MIN_CONTACT,
    _N_AUX,
    _N_BANK_LAGS,
    _N_DRING,
    _O_BIAS,
    _O_CHANGED,
    _O_HIGH,
    _O_LAG,
    _O_LAG_SD,
    _O_LOW,
    _O_MISFIT,
    _O_NOISE,
    _O_OFFSET,
    _O_OFFSET_SD,
    _O_PRED,
    _O_W,
    _QUICK_AFTER,
    _QUICK_DEADBAND,
    _QUICK_NOISE,
    _QUICK_WINDOW,
    _RATE_STEP,
    _REST_NOISE_EXCESS,
    _REST_NOISE_SIGMAS,
    _REST_SPAN,
    _SMOOTH_BEND,
    _SMOOTH_BEND_STEP,
    _SMOOTH_DEADBAND_SIGMAS,
    _SMOOTH_MAX_STEP,
    _SPARE_MASS,
    _SPARE_TURN,
    _TARE_MASS,
    _TARE_RUN,
    _TARE_RUN_AFTER,
    _TARE_RUN_OUT,
    _TARE_RUN_QUIET,
    _TARE_RUN_QUIET_BAND,
    _TARE_RUN_SPREAD,
    _TARE_SHORT,
    _TARE_SHORT_SIGMAS,
    _TARE_TAIL,
    MAX_FORCE,
)
from mudforce.estimation.nuisances import _lowpass_coefficients, _lowpass_step

__all__: list[str] = []

@njit(cache=True, nogil=True, error_model="numpy")
def _quantile(p: np.ndarray, edges: np.ndarray, q: float) -> float:
    """The ``q`` quantile of a posterior uniform within each cell ``[edges[g], edges[g + 1]]`` of mass ``p[g]``."""
    c = 0.0
    G = p.shape[0]
    for g in range(G):
        if c + p[g] >= q and p[g] > 0.0:
            return float(edges[g] + (q - c) / p[g] * (edges[g + 1] - edges[g]))
        c += p[g]
    return float(edges[G])


@njit(cache=True, nogil=True)
def _reach_share(half: float, dense: float) -> float:
    """How far [-] (0: not at all, 1: all the way) an interval's end moves toward the grid's, its tail there holding
    ``half`` [-] of the posterior and the interval as dense over the same width holding ``dense`` [-] (ours,
    :data:`_END_REACH`): all the way from that ratio's :data:`_END_REACH`, none below :data:`_END_REACH_FROM`, and
    in proportion between, so that a tail thinning across the threshold moves the end continuously."""
    if half >= _END_REACH * dense:
        return 1.0
    if half <= _END_REACH_FROM * dense:
        return 0.0
    return (half / dense - _END_REACH_FROM) / (_END_REACH - _END_REACH_FROM)


@njit(cache=True, nogil=True)
def _reach_ends(low: float, high: float, first: float, last: float, half: float) -> tuple[float, float]:
    """The interval ``[low, high]`` [-] with an end moved toward the grid's (``first``, ``last``) where the tail it
    leaves out there is dense beside the interval (ours, :func:`_reach_share`): each tail holds ``half`` of the
    posterior, the interval ``1 - 2 half``."""
    inside = (1.0 - 2.0 * half) / max(high - low, 1e-12)
    new_low = low - (low - first) * _reach_share(half, inside * (low - first))
    new_high = high + (last - high) * _reach_share(half, inside * (last - high))
    return new_low, new_high


@njit(cache=True, nogil=True, error_model="numpy")
def _blurred_quantiles(blur_t: np.ndarray, p: np.ndarray, q: np.ndarray, edges: np.ndarray, half: float
                       ) -> tuple[float, float, float]:
    """The median and the ``half``, ``1 - half`` quantiles [-] of ``blur_t.T @ p`` (written into the scratch ``q``).

    ``blur_t`` is the blur matrix transposed (:func:`_blur_matrix`'s ``B[g, h]`` at ``[h, g]``): each ``q[g]`` sums
    ``B[g, h] p[h]`` over ``h`` in order, as a row-by-row product does, but the cells of zero mass are skipped (adding
    ``+0.0`` changes no sum) and the inner loop runs over independent ``q[g]``, which the compiler vectorises (a
    row's dot product is one chain of dependent additions).
    """
    G = p.shape[0]
    for g in range(G):
        q[g] = 0.0
    for h in range(G):
        ph = p[h]
        if ph != 0.0:
            for g in range(G):
                q[g] += blur_t[h, g] * ph
    return _quantile(q, edges, 0.5), _quantile(q, edges, half), _quantile(q, edges, 1.0 - half)


@njit(cache=True, nogil=True)
def _cell_variance(nodes: np.ndarray, o: int, lowest: float) -> float:  # pragma: no cover
    """The variance [unit^2] of a value uniform over node ``o``'s cell (ours): the cell runs half-way to the next
    node on either side (nodes equal to it are the same node), as far on the side that has none as on the side that
    has one, and not below ``lowest``; 0 for a node alone. A posterior over a few hypotheses stands for a continuum,
    each node for its cell: its spread over the nodes alone read a 2-mm offset as -3.00 +- 0.05 mm on the
    sensor-chain bench. The reported spreads of the surface offset and the force lag hold it."""
    below = above = math.inf
    for p in range(nodes.shape[0]):
        d = nodes[p] - nodes[o]
        if 0.0 < d < above:
            above = d
        if 0.0 < -d < below:
            below = -d
    if below == math.inf and above == math.inf:
        return 0.0
    if below == math.inf:
        below = above
    if above == math.inf:
        above = below
    width = min(0.5 * below, nodes[o] - lowest) + 0.5 * above
    return float(width * width / 12.0)


#: Each lag hypothesis's cell variance [s^2] (:func:`_cell_variance`, none below 0): constants of :data:`_LAGS`,
#: computed once here (through the same function, uncompiled) and not at every sample by :func:`_lag_reading`.
_LAG_CELLS = np.array([cast(Any, _cell_variance).py_func(_LAGS, k, 0.0) for k in range(_LAGS.shape[0])])
#: ... and each delay hypothesis's, on the delays' own nodes with no delay among them (:data:`_DELAYS`).
_DELAY_NODES = np.concatenate(([0.0], _DELAYS))
_DELAY_CELLS = np.array([cast(Any, _cell_variance).py_func(_DELAY_NODES, k + 1, 0.0) for k in range(_DELAYS.shape[0])])


@njit(cache=True, nogil=True, error_model="numpy")
def _lag_reading(aux: np.ndarray, j: int, temper: float) -> tuple[float, float]:  # pragma: no cover
    """Foot ``j``'s force lag as reported [s] and its spread [s] (ours): the lag hypotheses' evidence
    (``aux[j, _A_LAG_L + k]``, tempered by ``temper`` as the bank's) under a flat prior, each hypothesis standing for
    its cell (:data:`_LAG_CELLS`: the spread holds the posterior's mean cell variance).

    The bank's own lag (``aux[j, _A_LAG]``, which low-passes the models' forces) keeps the prior
    :data:`_LAG_LOG_PRIOR`, which holds the water content steady while the evidence is young; under that prior the
    lag read a third to a half of a large one (a 20-ms delay as about 7 ms, 28 % of the sensor-chain bench's seed-22
    samples beyond three spreads; a 5-ms delay as none, 39 %). Without it: 4 and 15 %, and with the two hypotheses
    at 5 ms that only this reading reads (:data:`_N_BANK_LAGS`), 12 and 0.3 % (docs/estimation.md, "MudTracker's
    spreads"). Before any evidence it reads the hypotheses' mean with their whole spread."""
    top = -1e300
    for k in range(_LAGS.shape[0]):
        top = max(top, aux[j, _A_LAG_L + k] / temper)
    for k in range(_DELAYS.shape[0]):
        top = max(top, aux[j, _A_DEL_L + k] / temper)
    z = m1 = m2 = cells = 0.0
    for k in range(_LAGS.shape[0]):
        p = math.exp(aux[j, _A_LAG_L + k] / temper - top)
        z += p
        m1 += p * _LAGS[k]
        m2 += p * _LAGS[k] * _LAGS[k]
        cells += p * _LAG_CELLS[k]
    for k in range(_DELAYS.shape[0]):  # the pure delays beside them (_DELAYS), each its own mean delay
        p = math.exp(aux[j, _A_DEL_L + k] / temper - top)
        z += p
        m1 += p * _DELAYS[k]
        m2 += p * _DELAYS[k] * _DELAYS[k]
        cells += p * _DELAY_CELLS[k]
    mean = m1 / z
    return mean, math.sqrt(max(m2 / z - mean * mean, 0.0) + cells / z)


@njit(cache=True, nogil=True, error_model="numpy")
def _two_stages(e: float, c: float, e2: float, c2: float, s_old: float, y_old: float, f0: float,
                f1: float) -> tuple[float, float]:
    """A force through the force lag's two stages over one step, from ``f0`` to ``f1`` [N] (ours): the first stage's
    low-pass ``(e, c)`` (:func:`_lowpass_coefficients`; ``e = 0``: none) from its last output ``s_old`` [N], then the
    second's ``(e2, c2)`` from its last output ``y_old`` [N], its input going from ``s_old`` to the first's new
    output. Returns the two outputs ``(s1, y)`` [N]."""
    s1 = f1
    if e > 0.0:
        s1 = _lowpass_step(e, c, s_old, f0, f1)
    y = s1
    if e2 > 0.0:
        y = _lowpass_step(e2, c2, y_old, s_old, s1)
    return s1, y


@njit(cache=True, nogil=True, error_model="numpy")
def _lag_hypotheses(aux: np.ndarray, j: int, h: float, mean: float, first: bool | np.bool_, cache: np.ndarray) -> None:
    """Foot ``j``'s mean model force ``mean`` [N] after a (sub)step of ``h`` [s] through each lag hypothesis's first
    stage (:data:`_LAGS_A`) into ``aux[j, _A_LAG_Y + k]``, from the last (sub)step's ``aux[j, _A_PSUB]``, then its
    second (:data:`_LAGS_B`) into ``aux[j, _A_LAG_Y2 + k]`` (ours).

    ``cache`` (``1 + 4 * _N_LAGS`` entries) holds the step ``h`` its :func:`_lowpass_coefficients` are for (a pure
    function of ``h``: recomputed when it differs, the same numbers either way).
    """
    if cache[0] != h:
        for k in range(_LAGS.shape[0]):
            if _LAGS_A[k] > 0.0:
                cache[1 + 4 * k], cache[2 + 4 * k] = _lowpass_coefficients(h, _LAGS_A[k])
            if _LAGS_B[k] > 0.0:
                cache[3 + 4 * k], cache[4 + 4 * k] = _lowpass_coefficients(h, _LAGS_B[k])
        cache[0] = h
    for k in range(_LAGS.shape[0]):
        e = cache[1 + 4 * k] if not first and _LAGS_A[k] > 0.0 else 0.0  # (0: no stage, or the first sample)
        e2 = cache[3 + 4 * k] if not first and _LAGS_B[k] > 0.0 else 0.0
        aux[j, _A_LAG_Y + k], aux[j, _A_LAG_Y2 + k] = _two_stages(e, cache[2 + 4 * k], e2, cache[4 + 4 * k],
                                                                  aux[j, _A_LAG_Y + k], aux[j, _A_LAG_Y2 + k],
                                                                  aux[j, _A_PSUB], mean)
    # the delay hypotheses' ring (_DELAYS): the mean model's force at this (sub)step's time
    if first:
        aux[j, _A_CLOCK] = 0.0
        aux[j, _A_DN] = 0.0
        head = 0
    else:
        aux[j, _A_CLOCK] += h
        head = (int(aux[j, _A_DHEAD]) + 1) % _N_DRING
    aux[j, _A_DHEAD] = head
    aux[j, _A_DN] = min(aux[j, _A_DN] + 1.0, float(_N_DRING))
    aux[j, _A_DRING + head] = mean
    aux[j, _A_DRING_T + head] = aux[j, _A_CLOCK]


@njit(cache=True, nogil=True, error_model="numpy")
def _hypothesis_score(score: float, force: float, measured: float, base: float, misfit2: float, dof: float,
                      keep: float, weight: float) -> float:  # pragma: no cover
    """A force lag or delay hypothesis's log-likelihood [-] after one sample (ours): its last ``score`` forgotten by
    ``keep`` [-], plus ``weight`` [-] times the Student-t log-density (``dof`` [-]) of the tared ``measured`` force
    [N] about the mean model's ``force`` through the hypothesis [N], on the scale ``base + misfit2 * force^2``
    [N^2] (the noise, the tare's and the floor's variances, and the misfit's share of the force)."""
    r = measured - force
    s = base + misfit2 * force * force
    return keep * score + weight * (-0.5 * (dof + 1.0) * math.log1p(r * r / (dof * s)) - 0.5 * math.log(s))


@njit(cache=True, nogil=True, error_model="numpy")
def _delayed_forces(aux: np.ndarray, j: int, delays: np.ndarray, column: int) -> None:
    """Foot ``j``'s mean model force [N] each of ``delays`` [s] (ascending) before its last (sub)step, from the delay
    hypotheses' ring, into ``aux[j, column + k]`` (ours, :data:`_DELAYS`): linear between the two entries about that
    time, the oldest held where the ring reaches no further back; one walk back through the ring for them all."""
    head = int(aux[j, _A_DHEAD])
    held = int(aux[j, _A_DN])
    clock = aux[j, _A_CLOCK]
    d = 0
    newer = head
    for k in range(1, held):
        older = (head - k) % _N_DRING
        t_old = aux[j, _A_DRING_T + older]
        while d < delays.shape[0] and t_old <= clock - delays[d]:
            t_new = aux[j, _A_DRING_T + newer]
            u = (clock - delays[d] - t_old) / (t_new - t_old) if t_new > t_old else 1.0
            aux[j, column + d] = aux[j, _A_DRING + older] + u * (aux[j, _A_DRING + newer] - aux[j, _A_DRING + older])
            d += 1
        if d == delays.shape[0]:
            return
        newer = older
    for k in range(d, delays.shape[0]):
        aux[j, column + k] = aux[j, _A_DRING + newer]


@njit(cache=True, nogil=True, error_model="numpy")
def _lag_stages(aux: np.ndarray, j: int) -> tuple[float, float]:
    """Foot ``j``'s posterior mean force lag's two stages [s]: the first's, and the rest of the mean lag (ours)."""
    return aux[j, _A_LAG_A], max(aux[j, _A_LAG] - aux[j, _A_LAG_A], 0.0)


@njit(cache=True, nogil=True, error_model="numpy")
def _lagged_force(aux: np.ndarray, j: int, M: int, m: int, fg: float, e: float, c: float, e2: float,
                  c2: float) -> float:
    """Model ``m``'s force ``fg`` [N] of foot ``j`` through the force lag's two stages, its states in ``aux`` (ours):
    the first stage's low-pass ``(e, c)`` (:func:`_lowpass_coefficients`; ``e = 0``: none) from its output
    ``aux[j, _N_AUX + 3 M + m]`` and the previous force ``aux[j, _N_AUX + 2 M + m]``, then the second's ``(e2, c2)``
    from ``aux[j, _N_AUX + M + m]`` (the lagged force, returned and kept) and the first stage's last output."""
    stage = _N_AUX + 3 * M + m
    lagged = _N_AUX + M + m
    previous = _N_AUX + 2 * M + m
    s1, y = _two_stages(e, c, e2, c2, aux[j, stage], aux[j, lagged], aux[j, previous], fg)
    aux[j, stage] = s1
    aux[j, lagged] = y
    aux[j, previous] = fg
    return y


@njit(cache=True, nogil=True, error_model="numpy")
def _lag_substep(j: int, h: float, forces: np.ndarray, P: np.ndarray, aux: np.ndarray, G: int, NO: int,
                 cache: np.ndarray) -> None:
    """The force lag over a substep of ``h`` [s] that is not a sample's last, for foot ``j`` (ours): every model's
    force (``forces``, [N]) through the posterior mean lag's two stages (:func:`_lagged_force`), and the mean
    model's (under the posterior ``P`` before the sample) through each lag hypothesis, as :func:`_track_step` does
    at the sample."""
    M = NO * G
    base = j * M
    lag_a, lag_b = _lag_stages(aux, j)
    e, c = (0.0, 0.0) if lag_a <= 0.0 else _lowpass_coefficients(h, lag_a)
    e2, c2 = (0.0, 0.0) if lag_b <= 0.0 else _lowpass_coefficients(h, lag_b)
    mean = 0.0
    for m in range(M):
        fg = forces[base + m]
        _lagged_force(aux, j, M, m, fg, e, c, e2, c2)
        mean += P[j, m] * fg
    _lag_hypotheses(aux, j, h, mean, np.bool_(False), cache)  # (np.bool_: one compiled signature, see engine)
    aux[j, _A_PSUB] = mean


@njit(cache=True, nogil=True)
def _substeps(dt: float, cfg: np.ndarray) -> int:
    """The substeps [-] the bank takes over a sample interval ``dt`` [s]: ``round(dt / cfg[_C_SUBSTEP])``, 1 to
    :data:`_MAX_SUBSTEPS` (1 where ``cfg[_C_SUBSTEP]`` is 0: no substeps)."""
    if cfg[_C_SUBSTEP] <= 0.0:
        return 1
    return max(1, min(_MAX_SUBSTEPS, int(min(dt / cfg[_C_SUBSTEP], float(_MAX_SUBSTEPS)) + 0.5)))


@njit(cache=True, nogil=True, error_model="numpy")
def _smoothed(aux: np.ndarray, j: int, dt: float, cfg: np.ndarray) -> bool:
    """Whether foot ``j``'s bank steps on the depth's three-sample mean this sample, ``dt`` [s] after the last, and
    scores the force of the sample before (ours, :data:`_SMOOTH_NOISE`): three depths seen, ``dt`` at most
    :data:`_SMOOTH_MAX_STEP`, the depth noise measured online (before this sample) above ``cfg[_C_SMOOTH]`` [m], and
    beyond :data:`_SMOOTH_BEND_STEP` the motion's bend below the noise (:data:`_SMOOTH_BEND`)."""
    dvar = aux[j, _A_DVAR]
    return (aux[j, _A_ZN] >= 3.0 and dt <= _SMOOTH_MAX_STEP and dvar > cfg[_C_SMOOTH] * cfg[_C_SMOOTH]
            and (dt <= _SMOOTH_BEND_STEP or aux[j, _A_D2VAR] < _SMOOTH_BEND * dvar))


@njit(cache=True, nogil=True, error_model="numpy")
def _bank_depth(depth: float, aux: np.ndarray, j: int, smooth: bool) -> float:
    """The depth [m] foot ``j``'s bank steps on this sample: its ``depth`` [m], or with ``smooth``
    (:func:`_smoothed`) the mean of it and the two before it."""
    return (depth + aux[j, _A_ZPREV] + aux[j, _A_Z2]) / 3.0 if smooth else depth


@njit(cache=True, nogil=True, error_model="numpy")
def _rest_step(j: int, step: float, dt: float, ring: np.ndarray, M: int) -> tuple[float, float]:
    """The depth step [m] and its span [s] that foot ``j``'s rest test reads (ours, :data:`_REST_SPAN`): the
    sample's own ``step`` over ``dt`` [s] where ``dt`` is at least :data:`_REST_SPAN`, else the step from the
    newest depth the bank's ``ring`` holds at least that long before this sample's (the ring's depths are the ones
    the bank stepped on, each plus one surface offset, which the difference cancels), or the sample's own where the
    ring holds none so old (its first samples, or a branch rule of one step, which keeps no ring)."""
    if dt >= _REST_SPAN * (1.0 - 1e-9) or ring.shape[1] < N_RING:
        return step, dt
    r0 = j * M
    head = int(ring[r0, R_HEAD])
    held = int(ring[r0, R_N])
    t_head = ring[r0, R_T + head]
    for k in range(1, held):
        old = (head - k) % RING
        span = t_head - ring[r0, R_T + old]
        if span >= _REST_SPAN * (1.0 - 1e-9):
            return ring[r0, R_Z + head] - ring[r0, R_Z + old], span
    return step, dt


@njit(cache=True, nogil=True, error_model="numpy")
def _branch_rule(j: int, depth: float, dt: float, offsets: np.ndarray, aux: np.ndarray, ring: np.ndarray,
                 params: np.ndarray, cfg: np.ndarray, M: int) -> None:
    """Foot ``j``'s ``M`` bank rows take the quick branch rule (:data:`_QUICK_WINDOW`, :data:`_QUICK_DEADBAND`)
    or the noise-robust one (``cfg[_C_ROBUST_WINDOW]`` [steps], ``cfg[_C_ROBUST_DEADBAND]`` [m/s]); written only
    where it changes (ours). Quick after :data:`_QUICK_AFTER` of contact, while the depth noise measured online is
    within :data:`_QUICK_NOISE` times :data:`_DEPTH_NOISE0`, the ``depth`` [m] plus the largest surface offset is in
    the mud, its sinkage ``aux[j, _A_SINK]`` [m] is within ``cfg[_C_QUICK_SINK]`` to ``cfg[_C_QUICK_SINK_MAX]``, and
    it moves: the robust rule's secant up to this sample, ``dt`` [s] after the last, read from the bank's ``ring``,
    above ``cfg[_C_QUICK_ON]`` times the quick secant's noise (kept down to ``cfg[_C_QUICK_OFF]`` times it: the
    hysteresis's state is ``aux[j, _A_QUICK]``, so that a snapshot carries it).
    """
    r0 = j * M
    quick = (aux[j, _A_DVAR] <= (_QUICK_NOISE * _DEPTH_NOISE0) ** 2 and aux[j, _A_CONTACT] >= _QUICK_AFTER
             and depth > -offsets[offsets.shape[0] - 1] and ring.shape[1] >= N_RING
             and cfg[_C_QUICK_SINK] <= aux[j, _A_SINK] <= cfg[_C_QUICK_SINK_MAX])
    if quick:
        head = int(ring[r0, R_HEAD])
        old = (head - (int(cfg[_C_ROBUST_WINDOW]) - 1)) % RING
        span = ring[r0, R_T + head] + dt - ring[r0, R_T + old]
        speed = abs(depth + offsets[0] - ring[r0, R_Z + old]) / span if span > 0.0 else 0.0
        noise = math.sqrt(2.0 * aux[j, _A_DVAR]) / (2.0 * dt)  # the quick secant's [m/s]
        gate = cfg[_C_QUICK_OFF] if aux[j, _A_QUICK] != 0.0 else cfg[_C_QUICK_ON]
        quick = speed > gate * noise
    aux[j, _A_QUICK] = 1.0 if quick else 0.0
    window = _QUICK_WINDOW if quick else cfg[_C_ROBUST_WINDOW]
    deadband = _QUICK_DEADBAND if quick else cfg[_C_ROBUST_DEADBAND]
    if not quick and _smoothed(aux, j, dt, cfg):
        # the noise-robust rule's deadband held above its secant's noise on the depth's three-sample mean
        # (_SMOOTH_DEADBAND_SIGMAS), in quarter octaves above its own
        h = dt / _substeps(dt, cfg)  # the bank's step [s]
        wanted = _SMOOTH_DEADBAND_SIGMAS * math.sqrt(2.0 * aux[j, _A_DVAR] / 3.0) / (window * h)
        if wanted > deadband > 0.0:
            deadband *= 2.0 ** (math.ceil(4.0 * math.log2(wanted / deadband)) / 4.0)
    if params[r0, P_WINDOW] != window or params[r0, P_DEADBAND] != deadband:
        for m in range(M):
            params[r0 + m, P_WINDOW] = window
            params[r0 + m, P_DEADBAND] = deadband


@njit(cache=True, nogil=True, error_model="numpy")
def _track_step(dt: float, states: np.ndarray, ring: np.ndarray, params: np.ndarray, forces: np.ndarray,
                scratch: np.ndarray, index: np.ndarray, buf: np.ndarray, layout: np.ndarray) -> int:
    """One sample for every foot: step the bank, update each foot's posterior, write its estimate.

    The bank's arrays, then the tracker's own as views of one buffer ``buf`` (fewer arguments to pass in):
    ``layout[k]`` is ``(start, d0, d1, d2)`` of the ``k``-th of :data:`_PACKED` (``d1 = d2 = 0`` for 1-D,
    ``d2 = 0`` for 2-D), unpacked below under the names used here.

    ``depths``/``measured`` [m]/[N], shape (n,). The bank has ``n * NO * G``
    rows: foot ``j``'s model of grid water content ``g`` under the surface
    offset ``offsets[o]`` [m] (the model follows the depth plus it) in row
    ``(j * NO + o) * G + g``. ``P[j]`` is foot ``j``'s joint posterior over
    (offset, water content), ``log_prior`` the offsets' log prior [-],
    ``work`` scratch of ``G + NO`` entries, ``scored`` of ``NO * G``. ``aux[j, _N_AUX + m]``
    is the contact time [s] at which model ``m`` was last scored (see :data:`_SPARE_MASS`), ``aux[j, _N_AUX + M + m]``
    its force through the force lag's two stages [N], ``aux[j, _N_AUX + 2 M + m]`` its force at the previous sample
    [N] and ``aux[j, _N_AUX + 3 M + m]`` its force through the first stage [N];
    the bank is stepped in ``round(dt / cfg[_C_SUBSTEP])`` substeps (at least one). Returns the
    first foot whose sample is not finite (nothing is changed then), else -1.
    """
    a = layout[:, 0]
    d0 = layout[:, 1]
    d1 = layout[:, 2]
    d2 = layout[:, 3]
    zbuf = buf[a[0]:a[0] + d0[0]]
    depths = buf[a[1]:a[1] + d0[1]]
    measured = buf[a[2]:a[2] + d0[2]]
    edges = buf[a[3]:a[3] + d0[3]]
    L = buf[a[4]:a[4] + d0[4] * d1[4]].reshape((d0[4], d1[4]))
    P = buf[a[5]:a[5] + d0[5] * d1[5]].reshape((d0[5], d1[5]))
    aux = buf[a[6]:a[6] + d0[6] * d1[6]].reshape((d0[6], d1[6]))
    cfg = buf[a[7]:a[7] + d0[7]]
    blur = buf[a[8]:a[8] + d0[8] * d1[8] * d2[8]].reshape((d0[8], d1[8], d2[8]))
    Q = buf[a[9]:a[9] + d0[9]]
    out = buf[a[10]:a[10] + d0[10] * d1[10]].reshape((d0[10], d1[10]))
    scored = buf[a[11]:a[11] + d0[11]]
    offsets = buf[a[12]:a[12] + d0[12]]
    log_prior = buf[a[13]:a[13] + d0[13]]
    work = buf[a[14]:a[14] + d0[14]]
    guard = buf[a[15]:a[15] + d0[15] * d1[15]].reshape((d0[15], d1[15]))
    n = depths.shape[0]
    G = edges.shape[0] - 1
    M = P.shape[1]  # models per foot
    NO = M // G  # surface offset hypotheses
    H = L.shape[1] // M  # gain hypotheses
    marginal = work[:G]  # the water content's posterior
    evidence = work[G:G + NO]  # each offset's
    lag_cache = work[G + NO:]  # the lag hypotheses' low-pass coefficients and the step they are for
    # the models of an offset other than the most probable one, holding less than _SPARE_MASS of the posterior, are
    # scored on every `spare`-th sample only (in turn), each score standing for the contact time since the last
    spare = max(1, int(_SPARE_TURN * cfg[_C_TEMP] / dt + 0.5))
    for j in range(n):  # every sample checked before anything changes (False for NaN too)
        if not (abs(depths[j]) <= cfg[_C_MAX_DEPTH] and abs(measured[j]) <= MAX_FORCE):
            return j
    if cfg[_C_QUICK] != 0.0:
        # the bank's branch rule follows each foot's depth noise measured online (see _QUICK_WINDOW)
        for j in range(n):
            _branch_rule(j, depths[j], dt, offsets, aux, ring, params, cfg, M)
    # the bank is stepped at no more than cfg[_C_SUBSTEP] per step: a longer sample interval is cut into substeps,
    # the depth interpolated linearly between the samples (the model's discretisation at a low data rate)
    nsub = _substeps(dt, cfg) if aux[0, _A_STARTED] != 0.0 else 1
    for s in range(1, nsub + 1):
        u = s / nsub
        for j in range(n):
            smooth_j = _smoothed(aux, j, dt, cfg)  # a noisy depth: its three-sample mean, one sample behind
            z_now = _bank_depth(depths[j], aux, j, smooth_j)
            z_before = (aux[j, _A_ZPREV] + aux[j, _A_Z2] + aux[j, _A_Z3]) / 3.0 if smooth_j else aux[j, _A_ZPREV]
            zj = z_now if s == nsub else z_before + (z_now - z_before) * u
            for o in range(NO):
                zo = zj + offsets[o]
                for g in range(G):
                    zbuf[(j * NO + o) * G + g] = zo
        K.run_feet(states, ring, params, zbuf, dt / nsub, forces, scratch, index)
        if s < nsub:
            # the force lag runs on every substep's forces (exact for a force linear over a substep, not a sample):
            # the models' forces low-passed by the posterior mean lag, and the mean model's by each lag hypothesis;
            # the last substep's below, with the sample's scoring
            for j in range(n):
                _lag_substep(j, dt / nsub, forces, P, aux, G, NO, lag_cache)
    tau = cfg[_C_TAU]
    misfit2 = cfg[_C_MISFIT] * cfg[_C_MISFIT]
    floor2 = cfg[_C_FLOOR] * cfg[_C_FLOOR]
    dof = cfg[_C_DOF]
    # each sample counts as dt / correlation_time independent ones (at most one)
    weight = min(1.0, dt / cfg[_C_TEMP])
    half = 0.5 * (1.0 - cfg[_C_LEVEL])
    for j in range(n):
        base = j * M
        first = aux[j, _A_STARTED] == 0.0
        aux[j, _A_STARTED] = 1.0
        # the force of the sample the bank stands at: the one before where it steps on the depth's mean
        smooth = _smoothed(aux, j, dt, cfg)
        f = aux[j, _A_FPREV] if smooth else measured[j]
        # one-step-ahead prediction: the models' forces under the posterior before this sample
        pred = 0.0
        predl = 0.0  # the same of the models' forces low-passed by the force lag
        lag_a, lag_b = _lag_stages(aux, j)
        lagged = _N_AUX + M  # the first column of the models' low-passed forces
        h_sub = dt / nsub  # the last substep [s] (the sample's interval at 100 Hz)
        e_lag, c_lag = (0.0, 0.0) if (first or lag_a <= 0.0) else _lowpass_coefficients(h_sub, lag_a)
        e_lag2, c_lag2 = (0.0, 0.0) if (first or lag_b <= 0.0) else _lowpass_coefficients(h_sub, lag_b)
        tail = _TARE_TAIL * math.sqrt(max(aux[j, _A_VAR], floor2))  # [N]
        free = True  # every model says zero force: the sample says nothing of the mud
        tare = True  # every model of every surface offset that holds _TARE_MASS of the posterior says zero force
        clinging = False  # ... one of them says a force with its depth above the surface (_CLING_SIGMAS)
        z_bank = _bank_depth(depths[j], aux, j, smooth)  # the depth the bank stepped on [m]
        o_map = 0  # the most probable surface offset (before this sample)
        p_map = -1.0
        for o in range(NO):
            po = 0.0
            zero = True
            settled = True  # ... and their forces through the force lag within the tail's bound (_TARE_TAIL)
            for g in range(G):
                fg = forces[base + o * G + g]
                yl = _lagged_force(aux, j, M, o * G + g, fg, e_lag, c_lag, e_lag2, c_lag2)
                pred += P[j, o * G + g] * fg
                predl += P[j, o * G + g] * yl
                po += P[j, o * G + g]
                if fg != 0.0:
                    zero = False
                if abs(yl) > tail:
                    settled = False
            if not zero:
                free = False
            if (not zero or not settled) and po >= _TARE_MASS:
                tare = False
                if not zero and z_bank + offsets[o] <= 0.0:
                    clinging = True
            if po > p_map:
                p_map = po
                o_map = o
        out[j, _O_PRED] = predl + aux[j, _A_BIAS]
        if first:
            aux[j, _A_PPREV] = pred
            aux[j, _A_PSUB] = pred
        # the mean model's force low-passed by each lag hypothesis (every sample: a lag runs on into the swing)
        _lag_hypotheses(aux, j, h_sub, pred, first, lag_cache)
        # mud that may still cling to a foot above the surface: no tare until the depth has clearly come down
        if clinging:
            aux[j, _A_CLING] = 1.0
            aux[j, _A_CLING_Z] = z_bank
            aux[j, _A_CLING_N] = 0.0
        elif aux[j, _A_CLING] != 0.0:
            z_sd = math.sqrt(aux[j, _A_DVAR] / 3.0 if smooth else aux[j, _A_DVAR])
            down = z_bank - aux[j, _A_CLING_Z]
            if down > _CLING_SIGMAS * z_sd:
                aux[j, _A_CLING_N] += 1.0
                # two samples in a row, or one at twice the distance (at 20 Hz a swing comes down in two samples)
                if aux[j, _A_CLING_N] >= _CLING_SAMPLES or down > 2.0 * _CLING_SIGMAS * z_sd:
                    aux[j, _A_CLING] = 0.0
            else:
                aux[j, _A_CLING_N] = 0.0
        if aux[j, _A_CLING] != 0.0:
            tare = False
        if tare:
            # every model says zero force: the measurement is offset plus noise (tare)
            nfree = min(aux[j, _A_NFREE] + 1.0, cfg[_C_FREE_MEMORY])
            e = f - aux[j, _A_BIAS]
            var = aux[j, _A_VAR]
            if aux[j, _A_TARE_PREV] == 0.0:  # a new stretch of tare samples (_TARE_SHORT)
                aux[j, _A_TARE_EW] = 0.0
                aux[j, _A_TARE_VAR0] = var
            var0 = aux[j, _A_TARE_VAR0]
            clip = 16.0 * max(min(var, var0), floor2)  # 4 sigma, never below 4 floors (clean data: var -> 0)
            ew = aux[j, _A_TARE_EW] + (e - aux[j, _A_TARE_EW]) * min(1.0, dt / _TARE_SHORT)
            aux[j, _A_TARE_EW] = ew
            shifted = ew * ew > _TARE_SHORT_SIGMAS * _TARE_SHORT_SIGMAS * max(var0, floor2)
            # a run of samples beyond the clip is left out (its samples beyond _TARE_RUN_OUT of the clip) until it has
            # held _TARE_RUN of tare samples, then taken as a shift only if it scatters as the noise does (a force the
            # bank missed; taken clipped, it fed the spread, the clip grew with it, and the offset ran away)
            reject = False
            run = aux[j, _A_RUN]
            if run > 0.0:  # in a run
                if e * e <= _TARE_RUN_QUIET_BAND * clip:  # within 3 sigma
                    aux[j, _A_RUN_QUIET] += dt
                else:
                    aux[j, _A_RUN_QUIET] = 0.0
                if aux[j, _A_RUN_QUIET] >= _TARE_RUN_QUIET:  # quiet long enough: the run is over
                    aux[j, _A_RUN] = 0.0
                    aux[j, _A_RUN_QUIET] = 0.0
                else:
                    run += dt
                    aux[j, _A_RUN] = run
                    w_run = dt / run
                    aux[j, _A_RUN_MEAN] += (f - aux[j, _A_RUN_MEAN]) * w_run
                    aux[j, _A_RUN_SQ] += (f * f - aux[j, _A_RUN_SQ]) * w_run
                    if run - dt < _TARE_RUN:  # not yet taken as a shift
                        if run >= _TARE_RUN:  # judged: a step scatters about its own mean by about the noise
                            sd2 = aux[j, _A_RUN_SQ] - aux[j, _A_RUN_MEAN] ** 2
                            if sd2 > _TARE_RUN_SPREAD * _TARE_RUN_SPREAD * max(var, floor2):
                                aux[j, _A_RUN] = dt  # a force that varies: left out, judged again a second on
                                aux[j, _A_RUN_MEAN] = f
                                aux[j, _A_RUN_SQ] = f * f
                                reject = True
                        else:
                            reject = e * e > _TARE_RUN_OUT * clip  # beyond 2 sigma
            elif (e * e > clip or shifted) and aux[j, _A_NFREE] >= _TARE_RUN_AFTER:  # a run's first sample: clipped
                aux[j, _A_RUN] = dt
                aux[j, _A_RUN_QUIET] = 0.0
                aux[j, _A_RUN_MEAN] = f
                aux[j, _A_RUN_SQ] = f * f
            if not reject:
                aux[j, _A_NFREE] = nfree
                if nfree <= 1.0:
                    aux[j, _A_BIAS] = f
                else:
                    e2 = min(e * e, clip)
                    e_c = math.copysign(math.sqrt(e2), e)
                    aux[j, _A_BIAS] += e_c / nfree
                    # the running variance, from the residual against the offset before this sample
                    aux[j, _A_VAR] = var + (e2 * (nfree - 1.0) / nfree - var) / nfree
        aux[j, _A_TARE_PREV] = 1.0 if tare else 0.0
        if not free and not first:
            bias = aux[j, _A_BIAS]
            nfree = aux[j, _A_NFREE]
            var = aux[j, _A_VAR]
            # the offset's uncertainty: its prior spread before any tare, then var / n
            bias_var = cfg[_C_BIAS0] * cfg[_C_BIAS0] if nfree < 2.0 else var / nfree
            keep = math.exp(-dt / tau)
            c_prev = aux[j, _A_CONTACT]
            aux[j, _A_CONTACT] += dt
            c_now = aux[j, _A_CONTACT]
            turn = int(aux[j, _A_TURN])
            aux[j, _A_TURN] = float((turn + 1) % (spare * G))
            map_lo = o_map * G  # the most probable offset's models: always scored
            map_hi = map_lo + G
            aux[j, _A_HOLD] = max(aux[j, _A_HOLD] - dt, 0.0)
            # the force lag: each hypothesis scores the mean model's force low-passed by it (forgotten as the water
            # content's evidence, and tempered as the surface offsets': a wrong lag is a misfit at every change)
            top_k = -1e300
            for k in range(_LAGS.shape[0]):
                v = _hypothesis_score(aux[j, _A_LAG_L + k], aux[j, _A_LAG_Y2 + k], f - bias, var + bias_var + floor2,
                                      misfit2, dof, keep, weight)
                aux[j, _A_LAG_L + k] = v
                if k < _N_BANK_LAGS:
                    top_k = max(top_k, v / cfg[_C_OFFSET_TEMPER] + _LAG_LOG_PRIOR[k])
            _delayed_forces(aux, j, _DELAYS, _A_DEL_Y)
            for k in range(_DELAYS.shape[0]):  # the reported lag's pure delays, scored the same way
                aux[j, _A_DEL_L + k] = _hypothesis_score(aux[j, _A_DEL_L + k], aux[j, _A_DEL_Y + k], f - bias,
                                                         var + bias_var + floor2, misfit2, dof, keep, weight)
            zk = l1 = l2 = la = 0.0
            for k in range(_N_BANK_LAGS):
                pk = math.exp(aux[j, _A_LAG_L + k] / cfg[_C_OFFSET_TEMPER] + _LAG_LOG_PRIOR[k] - top_k)
                zk += pk
                l1 += pk * _LAGS[k]
                l2 += pk * _LAGS[k] * _LAGS[k]
                la += pk * _LAGS_A[k]
            aux[j, _A_LAG] = l1 / zk
            aux[j, _A_LAG_A] = la / zk
            aux[j, _A_LAG_SD] = math.sqrt(max(l2 / zk - (l1 / zk) ** 2, 0.0))
            # the lag's uncertainty, and an allowance cfg[_C_LAG]: the force's change over that time, in quadrature
            lag2 = (cfg[_C_LAG] ** 2 + aux[j, _A_LAG_SD] ** 2) * ((pred - aux[j, _A_PPREV]) / dt) ** 2
            # a foot at rest (moved less than the rest speed times the step) carries its load anywhere in
            # the rest band: each model's band [lo, hi] (its own force included), not its branch force
            # the depth noise, online: third differences (blind to any quadratic motion), each clipped at 3 sigma
            dvar = aux[j, _A_DVAR]
            if aux[j, _A_ZN] >= 3.0:
                d3 = depths[j] - 3.0 * aux[j, _A_ZPREV] + 3.0 * aux[j, _A_Z2] - aux[j, _A_Z3]
                w_noise = min(1.0, dt / _DEPTH_NOISE_MEMORY)
                aux[j, _A_DVAR] = dvar + (min(d3 * d3 / 20.0, 9.0 * dvar) - dvar) * w_noise
                # and the second differences', read the same way: the noise plus the motion's bend (_SMOOTH_BEND)
                d2 = depths[j] - 2.0 * aux[j, _A_ZPREV] + aux[j, _A_Z2]
                d2var = aux[j, _A_D2VAR]
                aux[j, _A_D2VAR] = d2var + (min(d2 * d2 / 6.0, 9.0 * d2var) - d2var) * w_noise
            excess = max(dvar - (_REST_NOISE_EXCESS * _DEPTH_NOISE0) ** 2, 0.0)
            step_z, span = _rest_step(j, depths[j] - aux[j, _A_ZPREV], dt, ring, M)
            rest = abs(step_z) <= cfg[_C_REST] * span + _REST_NOISE_SIGMAS * math.sqrt(2.0 * excess)
            # ... and its band's ends move with that noise on the depth the bank steps on (_REST_SPREAD)
            zsd = cfg[_C_REST_SPREAD] * math.sqrt(excess / 3.0 if smooth else excess) if rest else 0.0
            # the misfit statistic: the squared standardised residual of the posterior's mean model
            mis_r = 0.0
            mis_s2 = 0.0
            best = -1e300
            last_spared = -1.0  # the decay and weight of the last spared model scored, for the next of the same time
            keep_spared = weight_spared = 0.0
            r_last = s2_last = scale_last = ll = math.nan  # the last log-likelihood and its residual and scales
            due = turn % spare  # (turn + m) % spare, kept without a division per model
            for m in range(M):
                # a model of another offset than the most probable one, holding less than _SPARE_MASS, is scored on
                # its turn only (every `spare`-th sample), its score standing for the contact time since its last
                if m > 0:
                    due = due + 1 if due + 1 < spare else 0
                if not (due == 0 or P[j, m] >= _SPARE_MASS or (m >= map_lo and m < map_hi)):
                    scored[m] = 0.0
                    continue
                scored[m] = 1.0
                km = keep
                wm = weight
                last = aux[j, _N_AUX + m]
                if last != c_prev:  # not scored on the previous sample of contact: the time since stands for itself
                    if last != last_spared:
                        last_spared = last
                        keep_spared = math.exp(-(c_now - last) / tau)
                        weight_spared = (c_now - last) / cfg[_C_TEMP]
                    km = keep_spared
                    wm = weight_spared
                aux[j, _N_AUX + m] = c_now
                row = base + m
                lo = hi = aux[j, lagged + m]
                # how far the depth's noise moves the band's ends [N]: read where a residual lies beyond the band
                spread = False
                d_lo = d_hi = -1.0  # (not read yet)
                band_mode = 0
                band_depth = 0.0
                if rest:
                    st = K.load_state(states, row)
                    if st.mode != 0:  # not FREE (K.ContactMode.FREE)
                        up, down = rest_band(params[row], st.mode, st.depth, st.strain, forces[row])
                        lo = min(lo, up, down)
                        hi = max(hi, up, down)
                        spread = zsd > 0.0
                        band_mode = st.mode
                        band_depth = st.depth
                for h in range(H):  # gain hypotheses 1 - g, 1, 1 + g (just 1 when g = 0)
                    gain = 1.0 + (h - (H - 1) // 2) * cfg[_C_GAIN]
                    fg = gain * aux[j, lagged + m]
                    if rest:
                        fg = min(max(f - bias, gain * lo), gain * hi)
                    r = f - bias - fg
                    s2 = var + bias_var + floor2 + misfit2 * fg * fg + lag2
                    # beyond the band, the residual's scale takes its end's spread under the depth's noise
                    # (_REST_SPREAD; the normalisation not: the likelihood stays continuous at the band's end)
                    scale = s2
                    if r != 0.0 and spread:
                        if d_lo < 0.0:
                            d_lo, d_hi = rest_band_spread(params[row], band_mode, band_depth, zsd)
                        scale = s2 + (gain * (d_hi if r > 0.0 else d_lo)) ** 2
                    if h == (H - 1) // 2:
                        mis_r += P[j, m] * r
                        mis_s2 += P[j, m] * scale
                    if r != r_last or s2 != s2_last or scale != scale_last:  # else the same as the last (at rest
                        r_last = r  # within the band, FREE)
                        s2_last = s2
                        scale_last = scale
                        ll = -0.5 * (dof + 1.0) * math.log1p(r * r / (dof * scale)) - 0.5 * math.log(s2)
                    v = km * L[j, h * M + m] + ll * wm
                    L[j, h * M + m] = v
                    if v > best:
                        best = v
            # the flag's floor: the model's own discretisation error at the rate (ours, see _MISFIT_DISCRETISATION)
            mis_s2 += (cfg[_C_DISC] * (pred - aux[j, _A_PPREV])) ** 2
            # the misfit average over the last tau seconds of contact
            z2 = min(mis_r * mis_r / mis_s2, _MISFIT_CLIP)
            aux[j, _A_MISFIT_T] = min(aux[j, _A_MISFIT_T] + dt, tau)
            aux[j, _A_MISFIT] += (z2 - aux[j, _A_MISFIT]) * dt / aux[j, _A_MISFIT_T]
            # the joint posterior, the gain marginalised: a gain error cannot be told from stiffer mud,
            # so the interval spans what each gain hypothesis would read; tempered by the misfit (a scale mixture:
            # residuals larger than the scale explains make every sample that much weaker evidence); the surface
            # offsets' prior (never forgotten) added after the tempering
            inv = 1.0 / max(1.0, aux[j, _A_MISFIT] / cfg[_C_TEMPER])
            # each offset's evidence (the water content and gain summed over), as a log
            top = -1e300
            for o in range(NO):
                z = 0.0
                for g in range(G):
                    m = o * G + g
                    v = 0.0
                    if scored[m] != 0.0:  # a model not scored on this sample holds less than _SPARE_MASS: none
                        for h in range(H):
                            lv = L[j, h * M + m]
                            if lv < best - cfg[_C_LEAD]:  # a change of mud stays cfg[_C_LEAD] away (_MAX_LEAD)
                                lv = best - cfg[_C_LEAD]
                                L[j, h * M + m] = lv
                            v += math.exp((lv - best) * inv)
                    P[j, m] = v
                    z += v
                if z > 0.0:
                    for g in range(G):
                        P[j, o * G + g] /= z
                # the offsets' evidence tempered by _C_OFFSET_TEMPER: a wrong offset is a misfit that persists
                # for a whole stance, far longer than the correlation time, so its evidence counts that much less
                lz = math.log(z) / cfg[_C_OFFSET_TEMPER] + log_prior[o] if z > 0.0 else -math.inf
                evidence[o] = lz
                top = max(top, lz)
            total = 0.0
            for o in range(NO):
                evidence[o] = math.exp(evidence[o] - top)
                total += evidence[o]
            for o in range(NO):
                w_o = evidence[o] / total
                for g in range(G):
                    P[j, o * G + g] *= w_o
        # the water content's posterior: the joint one summed over the surface offsets; and the offset's moments
        om = 0.0
        o2 = 0.0
        oc = 0.0
        for g in range(G):
            marginal[g] = 0.0
        for o in range(NO):
            po = 0.0
            for g in range(G):
                po += P[j, o * G + g]
                marginal[g] += P[j, o * G + g]
            om += po * offsets[o]
            o2 += po * offsets[o] * offsets[o]
            oc += po * _cell_variance(offsets, o, -math.inf)
        out[j, _O_OFFSET] = om
        osd = math.sqrt(max(o2 - om * om, 0.0))
        if not free and not first:
            # the sinkage: the deepest depth plus the offset in contact, forgotten as the evidence is
            aux[j, _A_SINK] = max(aux[j, _A_SINK] * math.exp(-dt / tau), depths[j] + om)
        # the reported lag: what the force says (no prior), each hypothesis with its cell; the offset's spread below
        # holds its cell too (the grid stands for a continuum; the interval's shallow widening below holds the
        # offset's as _C_OFFSET_RES, the likelihood's scale the bank's lag's as _C_LAG)
        out[j, _O_LAG], out[j, _O_LAG_SD] = _lag_reading(aux, j, cfg[_C_OFFSET_TEMPER])
        out[j, _O_OFFSET_SD] = math.sqrt(osd * osd + oc)
        # ... and each spread holds what the twin bank reads: the branch rule is a model choice, and the nuisances take
        # up what a rule misses (a deep wet robot's 30-ms low-pass read as 45 ms on the first bank's rule; at 20 Hz
        # under a lag a -5 mm offset read as +2 to +3 mm with a 2.4-mm spread). The twin's offsets are the three
        # within 3 mm, so beyond them the offset's is wider than the first bank's own doubt; read within them it lost
        # the combined rows, whose drift takes the offset past 3 mm
        if not math.isnan(guard[j, _G_LOW]):
            out[j, _O_LAG_SD] = math.sqrt(out[j, _O_LAG_SD] ** 2 + (out[j, _O_LAG] - guard[j, _G_LAG]) ** 2)
            out[j, _O_OFFSET_SD] = math.sqrt(out[j, _O_OFFSET_SD] ** 2
                                             + (out[j, _O_OFFSET] - guard[j, _G_OFFSET]) ** 2)
        # ... and a lag beyond the allowance the water content and the offset the bank reads trade with, which its
        # hypotheses, scored on the bank's mean model, do not see (ours, _LAG_SPREAD_WIDENING)
        lag_beyond = max(out[j, _O_LAG] - cfg[_C_LAG], 0.0)
        if lag_beyond > 0.0:
            out[j, _O_LAG_SD] = math.sqrt(out[j, _O_LAG_SD] ** 2 + (_LAG_SPREAD_WIDENING * lag_beyond) ** 2)
        # ... and the part of a sample interval beyond one 10-ms step, which the substeps interpolate, as a uniform
        # spread: a lag under a sample is read through the model between two samples (ours; the interval's low-rate
        # widening for the water content). Read on dt itself, so a jittered clock does not make it jump
        interpolated = min(dt, _MAX_SUBSTEPS * _RATE_STEP) - _RATE_STEP
        if interpolated > 0.0 and not first:
            out[j, _O_LAG_SD] = math.sqrt(out[j, _O_LAG_SD] ** 2 + interpolated * interpolated / 12.0)
        # the fit's posterior blurred by the model discrepancy (Q = blur @ P): the change flag's
        w_mid, w_low, w_high = _blurred_quantiles(blur[0], marginal, Q, edges, half)
        settled = w_high - w_low <= cfg[_C_SETTLE]  # the plain blur's interval: settled (the change flag's)
        # the reported interval: that blur widened with the misfit, the smallest of _BLUR_FACTORS at or above the
        # square root of the misfit average's excess over its reference (a scale mixture, see _MISFIT_BLUR_REF),
        # and with a shallow sinkage (_SHALLOW_WIDENING), in quadrature
        excess = math.sqrt(max(1.0, aux[j, _A_MISFIT] / cfg[_C_BLUR_REF]))
        # a shallow sinkage: the surface offset's uncertainty (its posterior spread, and half the grid's step, which
        # an offset between two hypotheses is off by) is a large share of the depth the force is read at (ours)
        if cfg[_C_OFFSET_RES] > 0.0 and aux[j, _A_CONTACT] > 0.0:
            # (and, sample by sample, the depth noise measured online)
            depth_sd = math.sqrt(osd * osd + cfg[_C_OFFSET_RES] ** 2 + aux[j, _A_DVAR])
            shallow = cfg[_C_SHALLOW] * depth_sd / max(aux[j, _A_SINK], 1e-4)
            excess = math.sqrt(excess * excess + cfg[_C_SHALLOW_GAIN] ** 2 * max(shallow * shallow - 1.0, 0.0))
        # a low rate: the model between two samples is the model of an interpolated path (ours, _RATE_WIDENING)
        spans = int(min(dt / _RATE_STEP, float(_MAX_SUBSTEPS)) + 0.5)
        if spans > 1 and not first:
            excess = math.sqrt(excess * excess + cfg[_C_RATE_GAIN] ** 2 * (spans - 1.0))
        # a lagging force beyond the allowance: the lag's shape is read from the bank's few (ours, _LAG_WIDENING)
        lag_spans = max(aux[j, _A_LAG] - cfg[_C_LAG], 0.0) / _LAG_WIDENING_STEP
        if lag_spans > 0.0:
            excess = math.sqrt(excess * excess + (_LAG_WIDENING * lag_spans) ** 2)
        nb = _BLUR_FACTORS.shape[0]
        b = 0
        while b < nb - 1 and _BLUR_FACTORS[b] < excess:
            b += 1
        if b > 0:
            _, wide_low, wide_high = _blurred_quantiles(blur[b], marginal, Q, edges, half)
            # the hull of the two intervals: a wider blur near the grid's end, renormalised, can lift a side
            # mode's quantile; the estimate stays the fit's median (the widening is the interval's, not the fit's)
            w_low = min(w_low, wide_low)
            w_high = max(w_high, wide_high)
            # and of the same blur with the mass beyond the grid's ends piled on the end cells (ours, _blur_matrix's
            # pile): a posterior a few points inside an end then reaches that end
            _, wide_low, wide_high = _blurred_quantiles(blur[nb - 1 + b], marginal, Q, edges, half)
            w_low = min(w_low, wide_low)
            w_high = max(w_high, wide_high)
        if excess > _BLUR_FACTORS[nb - 1]:
            w_low = edges[0]
            w_high = edges[edges.shape[0] - 1]
        # an end of the interval that leaves out only the grid's end, where the posterior is about as dense as
        # within, reaches that end (ours, _END_REACH)
        w_low, w_high = _reach_ends(w_low, w_high, edges[0], edges[edges.shape[0] - 1], half)
        # the reported interval also holds the twin bank's, where one runs (``guard``; NaN where none does)
        if not math.isnan(guard[j, _G_LOW]):
            w_low = min(w_low, guard[j, _G_LOW])
            w_high = max(w_high, guard[j, _G_HIGH])
        # change flag: a settled estimate whose reported interval lies clear of the anchor's (ours, 2026-11-29: the
        # reported intervals, not the fit's plain ones, so that the flag never says more than the intervals do; and
        # the anchor's interval, not its point, so that a posterior flipping between two modes that the reported
        # interval spans at the anchor is not a change)
        changed = 0.0
        # (only once the offset has been tared: before, an estimate may still move with it)
        if settled and aux[j, _A_NFREE] >= 10.0:
            anchor = aux[j, _A_ANCHOR]
            if math.isnan(anchor) or aux[j, _A_HOLD] > 0.0:
                # the first settled estimate, or the estimate still settling after a flag: follow it
                aux[j, _A_ANCHOR] = w_mid
                aux[j, _A_ANCHOR_LOW] = w_low
                aux[j, _A_ANCHOR_HIGH] = w_high
            elif (aux[j, _A_ANCHOR_HIGH] < w_low - cfg[_C_MARGIN]
                  or aux[j, _A_ANCHOR_LOW] > w_high + cfg[_C_MARGIN]):
                changed = 1.0
                aux[j, _A_ANCHOR] = w_mid
                aux[j, _A_ANCHOR_LOW] = w_low
                aux[j, _A_ANCHOR_HIGH] = w_high
                aux[j, _A_HOLD] = tau
            elif w_low <= anchor <= w_high:
                # an interval that still holds the anchor narrows the anchor's (their intersection, which holds it)
                aux[j, _A_ANCHOR_LOW] = max(aux[j, _A_ANCHOR_LOW], w_low)
                aux[j, _A_ANCHOR_HIGH] = min(aux[j, _A_ANCHOR_HIGH], w_high)
        # the reported interval: the hull over about the last cfg[_C_HULL] seconds (_HULL_MEMORY), each end relaxing
        # toward the current one where that is narrower; through a change flag too (the flag reads the current
        # interval, and the estimate moves at once; the interval forgets in the hull's own time, so that a false
        # flag does not leave a narrow interval clear of the truth: 2026-12-02, a shallow robot's posterior flipping
        # between two modes flagged at the wet one and missed for 0.6 s when the hull started afresh there)
        if cfg[_C_HULL] > 0.0:
            h_low = aux[j, _A_HULL_LOW]
            h_high = aux[j, _A_HULL_HIGH]
            # a jump of the estimate (the posterior from one mode to another) holds the hull's ends for the hull's
            # own time of contact before they relax (_HULL_JUMP)
            if not first and abs(w_mid - aux[j, _A_W_LAST]) > _HULL_JUMP:
                aux[j, _A_JUMP] = cfg[_C_HULL]
            aux[j, _A_W_LAST] = w_mid
            # so does an interval that spans most of the grid in the stream's first seconds of contact (_HULL_HOLD)
            early_wide = (aux[j, _A_CONTACT] < _HULL_HOLD
                          and w_high - w_low > _HULL_WIDE * (edges[edges.shape[0] - 1] - edges[0]))
            if not first and h_low == h_low:  # (NaN: no interval yet)
                keep_hull = (1.0 if free or aux[j, _A_JUMP] > 0.0 or early_wide
                             else math.exp(-dt / cfg[_C_HULL]))  # (contact time)
                if h_low < w_low:
                    w_low = w_low + (h_low - w_low) * keep_hull
                if h_high > w_high:
                    w_high = w_high + (h_high - w_high) * keep_hull
            aux[j, _A_HULL_LOW] = w_low
            aux[j, _A_HULL_HIGH] = w_high
            if not free:
                aux[j, _A_JUMP] = max(aux[j, _A_JUMP] - dt, 0.0)
            # an end the hull relaxed to a sliver from the grid's reaches it too (_END_REACH on what is reported; the
            # hull keeps its own ends, else a reached end would be held there by the hull for good)
            w_low, w_high = _reach_ends(w_low, w_high, edges[0], edges[edges.shape[0] - 1], half)
        out[j, _O_W] = w_mid
        out[j, _O_LOW] = w_low
        out[j, _O_HIGH] = w_high
        out[j, _O_BIAS] = aux[j, _A_BIAS]
        out[j, _O_NOISE] = math.sqrt(aux[j, _A_VAR])
        out[j, _O_CHANGED] = changed
        # the misfit flag: this bank's average over its threshold, and the twin bank's flag raised too where one runs
        # (``guard[j, _G_MISFIT]``): the family holds both branch rules, as the reported interval does (_TWIN_WINDOW)
        out[j, _O_MISFIT] = 1.0 if (aux[j, _A_CONTACT] >= _MISFIT_MIN_CONTACT
                                    and aux[j, _A_MISFIT] > cfg[_C_MISFIT_RATIO]
                                    and (math.isnan(guard[j, _G_LOW]) or guard[j, _G_MISFIT] != 0.0)) else 0.0
        aux[j, _A_PPREV] = pred
        aux[j, _A_PSUB] = pred
        aux[j, _A_Z3] = aux[j, _A_Z2]
        aux[j, _A_Z2] = aux[j, _A_ZPREV]
        aux[j, _A_ZPREV] = depths[j]
        aux[j, _A_FPREV] = measured[j]
        aux[j, _A_ZN] = min(aux[j, _A_ZN] + 1.0, 3.0)
    return -1


@njit(cache=True, nogil=True)
def _track_pair(dt: float, t_states: np.ndarray, t_ring: np.ndarray, t_params: np.ndarray, t_forces: np.ndarray,
                t_scratch: np.ndarray, t_index: np.ndarray, t_buf: np.ndarray, t_layout: np.ndarray,
                states: np.ndarray, ring: np.ndarray, params: np.ndarray, forces: np.ndarray, scratch: np.ndarray,
                index: np.ndarray, buf: np.ndarray, layout: np.ndarray) -> int:
    """The twin bank's :func:`_track_step` (``t_``), its readings copied into the first bank's guard, then the first
    bank's, in one call (speed plumbing: the same arithmetic as the two calls and the copies between them from Python,
    without their dispatch). The twin's depths and forces are the first bank's, copied in first. Returns the first
    foot either bank refused (the twin checks first, and nothing has changed then), else -1."""
    a = layout[:, 0]
    d0 = layout[:, 1]
    d1 = layout[:, 2]
    ta = t_layout[:, 0]
    td0 = t_layout[:, 1]
    td1 = t_layout[:, 2]
    n = d0[_SLOT_DEPTHS]
    t_buf[ta[_SLOT_DEPTHS]:ta[_SLOT_DEPTHS] + n] = buf[a[_SLOT_DEPTHS]:a[_SLOT_DEPTHS] + n]
    t_buf[ta[_SLOT_FORCES]:ta[_SLOT_FORCES] + n] = buf[a[_SLOT_FORCES]:a[_SLOT_FORCES] + n]
    bad = _track_step(dt, t_states, t_ring, t_params, t_forces, t_scratch, t_index, t_buf, t_layout)
    if bad >= 0:
        return bad
    o, g = _SLOT_OUT, _SLOT_GUARD
    t_out = t_buf[ta[o]:ta[o] + td0[o] * td1[o]].reshape((td0[o], td1[o]))
    guard = buf[a[g]:a[g] + d0[g] * d1[g]].reshape((d0[g], d1[g]))
    for j in range(n):
        guard[j, _G_LOW] = t_out[j, _O_LOW]
        guard[j, _G_HIGH] = t_out[j, _O_HIGH]
        guard[j, _G_MISFIT] = t_out[j, _O_MISFIT]
        guard[j, _G_LAG] = t_out[j, _O_LAG]
        guard[j, _G_OFFSET] = t_out[j, _O_OFFSET]
    return _track_step(dt, states, ring, params, forces, scratch, index, buf, layout)


@njit(cache=True, nogil=True)
def _restore_step_cache(states: np.ndarray, params: np.ndarray, dts: np.ndarray) -> None:
    """Each row's step-length cache recomputed for the step length ``dts[j]`` [s] it was for (skipped unless > 0).

    The cache is a function of that length and the row's constants (:func:`~mudforce._kernel.transitions.step_cache`),
    so a restored tracker replays its snapshot bit for bit (a cache dropped instead is recomputed for the next step's
    length, which may differ from the cached one in the last bits).
    """
    for j in range(states.shape[0]):
        dt = dts[j]
        if dt > 0.0 and math.isfinite(dt):
            none = K.Cache(-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            store_cache(states, j, step_cache(none, K.load_params(params, j), dt))


def _check_bounds(depths: np.ndarray, forces: np.ndarray, max_depth: float, time: np.ndarray | None = None) -> None:
    """Refuse a depth beyond ``max_depth`` [m] or a force beyond :data:`MAX_FORCE` [N] in one line (NaN is left to
    the caller): :func:`track`'s check of a whole recording (``time``: its samples' times, named with the sample),
    and the words for a foot's sample :func:`_track_step` refused."""
    for name, values, bound, unit in (("depth", depths, max_depth, "m"), ("force", forces, MAX_FORCE, "N")):
        beyond = np.flatnonzero(np.abs(values) > bound)
        if beyond.size:
            j = int(beyond[0])
            where = f"of foot {j}" if time is None else f"at sample {j} ({float(time[j])!r} s)"
            raise InputError(f"{name} {where} must be within +-{bound:.6g} {unit}, got {float(values[j])!r}")


#: The tracker's own arrays packed for :func:`_track_step`, in its order.
_PACKED = ("_zbuf", "_depths", "_forces", "_edges", "_L", "_P", "_aux", "_cfg", "_blur", "_Q", "_out", "_scored",
           "depth_offsets", "_log_prior", "_work", "_guard")
#: The places in :data:`_PACKED` of the arrays :func:`_track_pair` copies between the two banks.
_SLOT_DEPTHS = _PACKED.index("_depths")
_SLOT_FORCES = _PACKED.index("_forces")
_SLOT_OUT = _PACKED.index("_out")
_SLOT_GUARD = _PACKED.index("_guard")


def _pack(owner: object) -> tuple[np.ndarray, np.ndarray]:
    """Copy ``owner``'s arrays named in :data:`_PACKED` into one buffer and rebind them to its views.

    Returns the buffer and its layout (see :func:`_track_step`).
    """
    arrays = [np.ascontiguousarray(getattr(owner, name), dtype=np.float64) for name in _PACKED]
    buf = np.zeros(sum(a.size for a in arrays), dtype=np.float64)
    layout = np.zeros((len(arrays), 4), dtype=np.int64)
    start = 0
    for k, (name, a) in enumerate(zip(_PACKED, arrays, strict=True)):
        view = buf[start:start + a.size].reshape(a.shape)
        view[...] = a
        layout[k, 0] = start
        layout[k, 1:1 + a.ndim] = a.shape
        setattr(owner, name, view)
        start += a.size
    return buf, layout


def _blur_matrix(grid: np.ndarray, edges: np.ndarray, sd: float, pile: bool = False) -> np.ndarray:
    """:func:`_blurred` (read-only), computed once per grid, edges, spread and ``pile`` in a process (speed plumbing:
    every tracker builds nine, ~60 ms of ``math.erf`` in Python, and a bench or a test suite builds thousands of
    trackers on the same grid)."""
    g, e = np.ascontiguousarray(grid, dtype=np.float64), np.ascontiguousarray(edges, dtype=np.float64)
    return _blur_once(g.tobytes(), e.tobytes(), float(sd), bool(pile))


@functools.lru_cache(maxsize=64)
def _blur_once(grid: bytes, edges: bytes, sd: float, pile: bool) -> np.ndarray:
    blur = _blurred(np.frombuffer(grid), np.frombuffer(edges), sd, pile)
    blur.flags.writeable = False
    return blur


def _blurred(grid: np.ndarray, edges: np.ndarray, sd: float, pile: bool = False) -> np.ndarray:
    """``B[g, h]``: the share of a normal of standard deviation ``sd`` [-] around ``grid[h]`` in cell ``g``.

    Each column is renormalised to the grid's range (the mass beyond its ends
    is put back in proportion); ``sd = 0`` gives the identity. With ``pile``
    the mass beyond an end is put on that end's cell instead (ours: the reported
    interval is also the hull of the widened blurs' piled twins, so that a
    posterior read a few points inside an end of the family reaches that end;
    in proportion, most of that mass went back to the cells nearer the
    estimate; piled alone, the other side moved in by up to 1.5 points).
    """
    G = grid.size
    if sd == 0.0:
        return np.eye(G)
    cdf = np.array([[0.5 * (1.0 + math.erf((e - w) / (sd * math.sqrt(2.0)))) for w in grid] for e in edges])
    if pile:  # the first cell from -inf, the last to +inf
        cdf[0] = 0.0
        cdf[-1] = 1.0
    blur = np.diff(cdf, axis=0)
    blur /= blur.sum(axis=0, keepdims=True)
    return np.ascontiguousarray(blur)

