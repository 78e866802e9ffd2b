"""Trials of any motion: which branch each step is on, the denoised depth, and the force noise.

The model switches between its intrusion and withdrawal branches (Eq. (8))
on the sign of each step's velocity, and at every switch in the mud the
force jumps by the whole nonlinear spring ``f_e2 S`` (Eq. (4)): tens to
hundreds of newtons, from one sample to the next. On a robot's foot
(touchdowns, stances that sway, partial withdrawals and re-pushes,
lift-offs) the velocity crosses zero many times, often slowly, where the
depth noise hides its sign. One misassigned sample costs tens of newtons.

Two independent pieces of evidence settle each step's branch
(:func:`label_branches`):

* the measured depth: step ``k`` moves by ``d_k = z_k - z_{k-1}`` with
  noise ``sqrt(2) sigma_z``, so ``P(true step >= 0) = Phi(d_k / (sqrt(2) sigma_z))``;
* the measured force: a switch shows as a jump of the first difference of
  the force away from its local trend (a median of the neighbouring
  differences), of either sign (``f_e2`` vanishes or returns, and
  ``k_w`` differs from ``k_i``). Its log-likelihood ratio ``j^2 / (2 sigma_j^2)`` is capped
  at :data:`JUMP_REWARD_CAP` and every switch costs :data:`SWITCH_COST`
  (a 6-sigma jump); a real pair of switches (a sway up and back down in
  stance, invisible in the depth) is found from the force alone. The
  force's steep onset at touchdown (``z^beta``) is not a switch: jumps in
  the first few samples in the mud earn nothing.

A two-state Viterbi pass finds the most likely branch sequence. The depth
the model follows (:func:`denoise_depth`) is then the least-squares fit to
the measured depth that is monotone within each run of equal branch
(isotonic regression, pool-adjacent-violators), nudged so that every step's
sign is its branch: the model with the paper's exact branch rule then
switches at the labelled samples and its Maxwell element sees a depth less
noisy than the measured one.

:func:`estimate_force_noise` measures the force noise from the data alone,
as the median absolute value of normalised third divided differences of
the force (which annihilate any quadratic trend, on any time grid); the
model's jumps touch only a few of them, so a bad fit cannot inflate it.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.special import log_ndtr

from mudforce._plumbing.jit import njit
from mudforce.model.velocity import NOISE_FLOOR_M

__all__ = [
    "CREEP_SAMPLES",
    "CREEP_SIGMAS",
    "CUT",
    "JUMP_REWARD_CAP",
    "QUIET_FINE_MIN_SAMPLES",
    "QUIET_FINE_ORDER",
    "QUIET_FINE_RATIO",
    "QUIET_FINE_SCALE",
    "QUIET_FINE_WINDOW",
    "QUIET_MIN_WINDOWS",
    "QUIET_ORDER",
    "QUIET_QUANTILE",
    "QUIET_RATIO",
    "QUIET_SCALE",
    "QUIET_WINDOW",
    "SWITCH_COST",
    "corner_preserving_smooth",
    "creep_withdrawals",
    "denoise_depth",
    "estimate_force_noise",
    "estimate_quiet_noise",
    "label_branches",
    "rest_steps",
]

#: The label of an intrusion step that cuts off a suction out of the mud (:func:`label_branches`) [-].
CUT = 2
#: Largest log-likelihood ratio one force jump contributes to a branch switch [-].
JUMP_REWARD_CAP = 50.0
#: Prior cost of one branch switch, in log-likelihood [-] (a 6-sigma jump pays for it).
SWITCH_COST = 18.0
#: Half-width of the neighbourhood whose median first difference is a step's force trend [samples].
_TREND_HALF_WIDTH = 2
#: Level change [standard errors] that confirms a force jump as a switch [-].
_LEVEL_SIGMAS = 4.0
#: Steps after the foot enters the mud in which a force jump is the touchdown's onset, not a switch [-].
_TOUCHDOWN_SAMPLES = 5
#: Samples the force must stay at its free level after a suction cut off out of the mud (:func:`_cut_steps`) [-].
_CUT_HOLD = 3
#: How near the free level [force noises] each of those samples must be [-] (ours): four, where three missed a cut in
#: about one recording in ten (each of three samples beyond three noises with chance 0.27 %, more with the noise
#: estimated a little low, over a dozen lift-offs a recording; the sensor-chain bench's MuJoCo run 2 of seed 70, 10 s
#: at 100 Hz, read a cut suction's third sample 3.1 noises off, and the model then clung to the raised foot at
#: 20-30 N through its swing: fit's misfit 2.8 times its floor). The force before the cut is more than six noises off.
_CUT_SETTLED = 4.0
#: Fewest selected third differences :func:`estimate_force_noise` takes the noise from [-] (the median of fewer
#: would scatter by more than 25 %; it is taken only where it differs from the whole by a factor over 1.5).
_NOISE_WINDOWS = 20
#: Log-likelihood a suction cut off out of the mud gives its upward switch [-]: more than any depth step can take away.
_CUT_REWARD = 1000.0
#: How steeply a standing foot's depth must fall (it rises) before a withdrawal, in standard errors of the slope
#: of :func:`creep_withdrawals`' hinge, for it to read a slow withdrawal there [-] (ours: the best hinge through
#: a still stance's white noise read at most 3.5 of them in 587 draws of 16-1000 samples).
CREEP_SIGMAS = 5.0
#: Fewest samples of such a stretch :func:`creep_withdrawals` reads [-] (ours).
CREEP_SAMPLES = 16
#: Order of the divided differences :func:`estimate_quiet_noise` reads the noise from [-] (ours).
QUIET_ORDER = 5
#: Differences per window whose median is one noise level in :func:`estimate_quiet_noise` [-] (ours).
QUIET_WINDOW = 8
#: The quantile of the windows' noise levels :func:`estimate_quiet_noise` takes [-] (ours: the quietest tenth).
QUIET_QUANTILE = 0.1
#: What that quantile reads on unit white noise [-]: measured, the mean over 2e5 samples of N(0, 1) (seeded),
#: 0.4894 (0.50 at 500 samples; ``tests/estimation/test_quiet_noise.py`` checks it).
QUIET_SCALE = 0.4894
#: Fewest windows :func:`estimate_quiet_noise` takes a quantile of [-] (485 samples: 10 s at 50 Hz); below, the whole
#: record's noise (on white noise the quantile's scatter is then 14 %, so the ratio below is 2.4 of its deviations).
QUIET_MIN_WINDOWS = 60
#: How much more the whole record's noise must read than the quiet stretches' for :func:`estimate_quiet_noise` to
#: take the quiet one [-] (ours, as :data:`_NOISE_WINDOWS`'s factor in :func:`estimate_force_noise`).
QUIET_RATIO = 1.5
#: Order of the differences of :func:`estimate_quiet_noise`'s finer reading [-] (ours): second differences, blind
#: to a constant speed (a foot creeping through a stance) and spanning three samples, so that a stance of five
#: samples (a quarter of a second at 20 Hz) holds a whole window.
QUIET_FINE_ORDER = 2
#: Differences per sliding window of the finer reading [-] (ours; a window at every sample, not cut end to end).
QUIET_FINE_WINDOW = 3
#: What the finer reading's quantile (:data:`QUIET_QUANTILE`) reads on unit white noise [-]: measured, the mean
#: over ten seeded draws of 2e5 samples of N(0, 1), 0.3455 (0.002 between draws; 0.347 at 3000 samples, 0.349 at
#: 600; ``tests/estimation/test_identify_quiet_noise.py`` checks it).
QUIET_FINE_SCALE = 0.3455
#: How much more the quiet estimate must read than the finer one for :func:`estimate_quiet_noise` to take the finer
#: [-] (ours: the finer reading scatters by 12 % on 600 samples of white noise, so a third of the other is far
#: beyond its scatter; on the sensor-chain bench's recordings it is taken at 20 Hz only, where a robot's stances
#: last five samples between swings of centimetres; chosen on seeds 22 and 48 and written down before seeds 31, 41
#: and 47 were read).
QUIET_FINE_RATIO = 3.0
#: Fewest samples :func:`estimate_quiet_noise` takes the finer reading on [-] (ours: 6 s at 20 Hz; on white noise
#: its 0.1 % quantile over 4000 seeded draws of this many samples reads 0.44 of the noise, so it never falls
#: under a third of a whole estimate of the noise; at 80 samples 5 in 10 000 do).
QUIET_FINE_MIN_SAMPLES = 120


def estimate_force_noise(time: np.ndarray, force: np.ndarray, where: np.ndarray | None = None) -> float:
    """Standard deviation of white noise on a sampled force [N] (or any signal), independent of any model.

    The third divided difference over four consecutive samples, scaled to
    unit norm, annihilates any quadratic in time and has the noise's
    standard deviation for white noise; its median absolute value / 0.6745
    is a robust estimate that the force's jumps (a few samples each) do not
    move. Zero for fewer than 8 samples.

    Parameters
    ----------
    time : ndarray
        Sample times [s], strictly increasing (any spacing).
    force : ndarray
        Measured force [N].
    where : ndarray of bool, optional
        Samples where the signal is known to be simple (e.g. the foot clear of the mud, where the force
        is the sensor's bias and its noise): when the estimate over all differences exceeds 1.5 times
        the one over the differences whose four samples are all selected and within three noises of
        the selected samples' most frequent level (at least :data:`_NOISE_WINDOWS` of them; the level
        and the noise refined together three times), the signal elsewhere has structure between its
        samples that the median cannot ignore (a robot's foot in the mud flicking between the rest
        band's edges), and the selected estimate is returned.
    """
    t = np.asarray(time, dtype=np.float64)
    f = np.asarray(force, dtype=np.float64)
    if f.size < 8:
        return 0.0
    values = np.abs(_third_differences(t, f))
    noise = _sigma(values)
    if where is not None:
        sel = np.asarray(where, dtype=bool)
        full = _all_four(sel)
        if int(np.count_nonzero(full)) >= _NOISE_WINDOWS:
            selected = _sigma(values[full])
            # the selected samples at their most frequent level only (clear of the mud a suction may still decay)
            for _ in range(3):
                level = _free_level(f[sel], selected)
                full = _all_four(sel & (np.abs(f - level) < 3.0 * selected))
                if int(np.count_nonzero(full)) < _NOISE_WINDOWS:
                    break
                selected = min(selected, _sigma(values[full]))
            if noise > 1.5 * selected:  # the rest of the signal is not smooth between its samples
                return selected
    return noise


def estimate_quiet_noise(time: np.ndarray, signal: np.ndarray) -> float:
    """Standard deviation of white noise on a sampled signal [same unit as ``signal``], from its quietest stretches.

    Ours, for a depth whose motion the sampling does not resolve everywhere: a robot foot rings and bounces after
    each impact, and at 50-100 Hz that motion reads as noise to :func:`estimate_force_noise` (2-60 times the true
    depth noise). White noise is the same in every stretch of the record; motion is not. So the unit-norm divided
    differences of order :data:`QUIET_ORDER` (blind to any polynomial of degree 4) are cut into windows of
    :data:`QUIET_WINDOW`, each window's noise level is its median absolute value / 0.6745, and the estimate is the
    :data:`QUIET_QUANTILE` quantile of the windows' levels, over what that quantile reads on white noise alone
    (:data:`QUIET_SCALE`): on stationary white noise it reads the noise (within about 14 % at 60 windows, 7 % at
    250), on a record whose motion rings in most windows the noise of its quietest tenth. It is taken only when
    :func:`estimate_force_noise` (the same noise over all differences) reads more than :data:`QUIET_RATIO` times
    as much: the record is then not stationary white noise, and the excess is motion. Otherwise, and below
    :data:`QUIET_MIN_WINDOWS` windows (where a low quantile scatters too much), that estimate itself, bit for bit:
    a record of white noise on a motion the rate resolves reads as before, and the scatter of a low quantile never
    reads its noise low.

    At a low rate a robot's foot may not rest for a whole window of fifth differences (13 samples: 0.65 s at
    20 Hz, where a stance lasts five samples between swings of centimetres), and every window reads motion (1.8
    to 19 mm for 0.03 mm on the sensor-chain bench's MuJoCo robots at 20 Hz). A finer reading is then taken: the
    same quantile of the levels of second differences (:data:`QUIET_FINE_ORDER`) in sliding windows of
    :data:`QUIET_FINE_WINDOW`, over what it reads on white noise (:data:`QUIET_FINE_SCALE`), where the estimate above
    reads more than :data:`QUIET_FINE_RATIO` times as much (0.05-0.4 mm on those robots; never at 50 Hz or above
    on the bench's recordings), on records of :data:`QUIET_FINE_MIN_SAMPLES` or more (also below
    :data:`QUIET_MIN_WINDOWS`' windows: its sliding windows scatter less). A foot that never rests still reads its
    motion.

    Parameters
    ----------
    time : ndarray
        Sample times [s], strictly increasing (any spacing).
    signal : ndarray
        The sampled signal, e.g. a depth [m].
    """
    t = np.asarray(time, dtype=np.float64)
    z = np.asarray(signal, dtype=np.float64)
    whole = estimate = estimate_force_noise(t, z)
    windows = (z.size - QUIET_ORDER) // QUIET_WINDOW
    if windows >= QUIET_MIN_WINDOWS:
        values = np.abs(_unit_differences(t, z, QUIET_ORDER))[:windows * QUIET_WINDOW].reshape(windows, QUIET_WINDOW)
        levels = np.median(values, axis=1) / 0.6744897501960817
        quiet = float(np.quantile(levels, QUIET_QUANTILE)) / QUIET_SCALE
        estimate = quiet if whole > QUIET_RATIO * quiet else whole
    if z.size < QUIET_FINE_MIN_SAMPLES:
        return estimate
    fine_values = np.abs(_unit_differences(t, z, QUIET_FINE_ORDER))
    fine_levels = np.median(np.lib.stride_tricks.sliding_window_view(fine_values, QUIET_FINE_WINDOW), axis=1)
    fine = float(np.quantile(fine_levels, QUIET_QUANTILE)) / 0.6744897501960817 / QUIET_FINE_SCALE
    return fine if estimate > QUIET_FINE_RATIO * fine else estimate


def _sigma(values: np.ndarray) -> float:
    """The standard deviation of white noise from the absolute values of its unit-norm differences [same]."""
    return float(np.median(values) / 0.6744897501960817)


def _all_four(mask: np.ndarray) -> np.ndarray:
    """Whether each four consecutive samples (one third difference's) are all in ``mask`` (``n - 3`` values)."""
    return np.asarray(mask[:-3] & mask[1:-2] & mask[2:-1] & mask[3:], dtype=bool)


def _third_differences(t: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Third divided differences of ``f`` over each four consecutive samples, scaled to unit norm [same as f]."""
    return _unit_differences(t, f, 3)


def _unit_differences(t: np.ndarray, f: np.ndarray, order: int) -> np.ndarray:
    """Divided differences of ``f`` of ``order`` over each ``order + 1`` consecutive samples, scaled to unit norm
    (``n - order`` values) [same as f]: white noise of standard deviation ``sigma`` gives ``sigma`` on any time grid,
    and any polynomial in time of degree below ``order`` gives zero."""
    n = f.size - order
    coef = np.ones((n, order + 1))
    for i in range(order + 1):
        for j in range(order + 1):
            if i != j:
                coef[:, i] = coef[:, i] / (t[i:i + n] - t[j:j + n])
    coef /= np.sqrt(np.sum(coef**2, axis=1))[:, None]
    values: np.ndarray = np.sum(coef * np.column_stack([f[i:i + n] for i in range(order + 1)]), axis=1)
    return values


def _jump_statistic(time: np.ndarray, force: np.ndarray, noise: float) -> np.ndarray:
    """Each step's force jump in units of its scatter (``n - 1`` values) [-]: sharp, for locating switches.

    The step's force difference minus the local trend (the median force
    rate of the neighbouring steps times the step's duration, so that
    jittered time stamps make no jumps), over the larger of the noise's
    ``sqrt(2) noise`` and a robust local scatter of the neighbours' jumps.
    """
    d = np.diff(force)
    dt = np.diff(time)
    m = d.size
    if m < 3:
        return np.zeros(m)
    h = _TREND_HALF_WIDTH
    rate = d / dt
    padded = np.concatenate([np.full(h, np.nan), rate, np.full(h, np.nan)])
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * h + 1)
    trend = np.nanmedian(np.delete(windows, h, axis=1), axis=1)
    if m > 2 * h:
        # the first and last h steps (ours): the truncated window holds only 2 or 3 neighbours, and a switch among
        # them moves their median by half its jump, so the step beside a switch at the record's end read as an
        # opposite switch and the pair was folded back (a walk ending in a sway's turn: docs/calibration.md). The
        # 2h nearest steps on the record's side are no cure alone: where a descent stops at the end, their trend
        # is the descent's, and the stop reads as a jump. A jump there must stand out from both trends: the one
        # nearer the step's own rate counts
        for k in (*range(h), *range(m - h, m)):
            a = min(max(k - h, 0), m - 2 * h - 1)
            inward = float(np.median(np.delete(rate[a:a + 2 * h + 1], k - a)))
            if not abs(rate[k] - trend[k]) <= abs(rate[k] - inward):
                trend[k] = inward
    jump = d - np.where(np.isfinite(trend), trend, 0.0) * dt
    wide = 4 * h
    padded = np.concatenate([np.full(wide, np.nan), np.abs(jump), np.full(wide, np.nan)])
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * wide + 1)
    local = 1.4826 * np.nanmedian(np.delete(windows, wide, axis=1), axis=1)
    scale = np.maximum(np.where(np.isfinite(local), local, 0.0), math.sqrt(2.0) * noise)
    scale = np.maximum(scale, 1e-9 * max(1.0, float(np.max(np.abs(force)))))
    out: np.ndarray = jump / scale
    return out


def _line_at(tw: np.ndarray, fw: np.ndarray, at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares lines through windows ``(tw, fw)`` evaluated at ``at``; and their variance factor."""
    tm = tw.mean(axis=1)
    tc = tw - tm[:, None]
    sxx = np.maximum(np.sum(tc**2, axis=1), 1e-300)
    slope = np.sum(tc * fw, axis=1) / sxx
    h = tw.shape[1]
    return fw.mean(axis=1) + slope * (at - tm), 1.0 / h + (at - tm) ** 2 / sxx


def _level_change(time: np.ndarray, force: np.ndarray, noise: float) -> np.ndarray:
    """Each step's force level change in units of its standard error (``n - 1`` values) [-].

    The jump of step ``k`` (samples ``k`` to ``k + 1``) is the difference,
    at the step's midpoint, between a straight line through the
    :data:`_TREND_HALF_WIDTH` + 1 samples ending at ``k`` and one through
    those starting at ``k + 1``: a level jump counts, a kink (a change of
    slope, e.g. where a descent stops) does not, and jittered time stamps
    do not matter. Its scale is the larger of the noise's and a robust
    local scatter of the jumps (fast motions, curvature).
    """
    t = np.asarray(time, dtype=np.float64)
    f = np.asarray(force, dtype=np.float64)
    m = f.size - 1
    h = _TREND_HALF_WIDTH + 1
    if m < 2 * h:
        return np.full(max(m, 0), np.nan)
    tw = np.lib.stride_tricks.sliding_window_view(t, h)
    fw = np.lib.stride_tricks.sliding_window_view(f, h)
    jump = np.full(m, np.nan)  # NaN: too near an end to tell
    var = np.ones(m)
    k = np.arange(h - 1, m - h + 1)  # steps with full windows on both sides
    mid = 0.5 * (t[k] + t[k + 1])
    left, vl = _line_at(tw[k - h + 1], fw[k - h + 1], mid)
    right, vr = _line_at(tw[k + 1], fw[k + 1], mid)
    jump[k] = right - left
    var[k] = vl + vr
    base = noise * np.sqrt(var)
    wide = 4 * h
    padded = np.concatenate([np.full(wide, np.nan), np.abs(jump) / np.sqrt(var), np.full(wide, np.nan)])
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * wide + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN windows near the ends
        local = 1.4826 * np.nanmedian(np.delete(windows, wide, axis=1), axis=1) * np.sqrt(var)
    scale = np.maximum(np.where(np.isfinite(local), local, 0.0), base)
    scale = np.maximum(scale, 1e-9 * max(1.0, float(np.max(np.abs(f)))))
    out: np.ndarray = jump / scale
    return out


def _free_level(force: np.ndarray, noise: float) -> float:
    """The force a free foot reads [N] (the sensor's bias), from the samples out of the mud (ours).

    The most frequent level: the median of the samples in the most populated
    bin of width four noises (a suction decaying after a neck spreads over
    many bins, a free foot's constant bias fills one), widened by half a bin
    on each side. On a foot that is rarely free the median of all would be a
    suction, not the free level.
    """
    lo, hi = float(np.min(force)), float(np.max(force))
    width = max(4.0 * noise, (hi - lo) / 1000.0, 1e-9 * max(1.0, abs(lo), abs(hi)))  # at most 1000 bins
    bins = max(math.ceil((hi - lo) / width), 1)
    counts, edges = np.histogram(force, bins=bins, range=(lo, lo + bins * width))
    k = int(np.argmax(counts))
    near = force[(force >= edges[k] - 0.5 * width) & (force <= edges[k + 1] + 0.5 * width)]
    return float(np.median(near))


def _cut_steps(depth: np.ndarray, force: np.ndarray, jump: np.ndarray, depth_noise: float,
               force_noise: float) -> np.ndarray:
    """Steps out of the mud where the force jumps back to its free level: a suction cut off (``n - 1`` values) [-].

    Out of the mud the model's force is zero (plus the sensor's bias) except
    while clinging mud still pulls (a withdrawal before necking) or a broken
    neck's suction decays (ours: ``docs/model.md``, the contact state
    machine); both end at the first step that goes down, and nothing else
    out of the mud makes the force jump. A downward step there can be far
    below the depth noise (a foot turning over at the top of a lift, or
    ringing between the samples), so the force alone shows it: a sharp jump
    (:func:`_jump_statistic` beyond 4) from a force more than six noises off
    the free level (:func:`_free_level`) to within :data:`_CUT_SETTLED` noises
    of it, where it stays for the next :data:`_CUT_HOLD` samples.
    """
    z = np.asarray(depth, dtype=np.float64)
    f = np.asarray(force, dtype=np.float64)
    out_of_mud = z <= 3.0 * depth_noise
    m = jump.size
    cut = np.zeros(m, dtype=bool)
    if m == 0 or not np.any(out_of_mud):
        return cut
    off = np.abs(f - _free_level(f[out_of_mud], force_noise))
    settled = (off < _CUT_SETTLED * force_noise) & out_of_mud
    held = np.ones(m, dtype=bool)  # samples k+1 .. k+_CUT_HOLD at the free level (as far as the record goes)
    for i in range(1, _CUT_HOLD + 1):
        held[: m - i + 1] &= settled[i:m + 1]
    cut[:] = (out_of_mud[:-1] & out_of_mud[1:] & (np.abs(jump) > 4.0) & (off[:-1] > 6.0 * force_noise) & held)
    return cut


@njit(cache=True)
def _viterbi(plus: np.ndarray, minus: np.ndarray, down: np.ndarray, up: np.ndarray, start_minus: float) -> np.ndarray:
    """Most likely two-state path: ``plus/minus`` per-step scores, ``down/up`` switch scores at each step."""
    n = plus.size
    back = np.zeros((n, 2), dtype=np.int8)
    sp = plus[0]
    sm = minus[0] + start_minus
    for k in range(1, n):
        # state +: stay + or come from - (an upward switch at step k)
        stay_p = sp
        from_m = sm + up[k]
        # state -: stay - or come from + (a downward switch at step k)
        stay_m = sm
        from_p = sp + down[k]
        if stay_p >= from_m:
            np_, back[k, 0] = stay_p + plus[k], 0
        else:
            np_, back[k, 0] = from_m + plus[k], 1
        if stay_m > from_p:
            nm, back[k, 1] = stay_m + minus[k], 1
        else:
            nm, back[k, 1] = from_p + minus[k], 0
        sp, sm = np_, nm
    path = np.empty(n, dtype=np.int8)  # 0: +, 1: -
    s = 0 if sp >= sm else 1
    for k in range(n - 1, -1, -1):
        path[k] = s
        s = back[k, s]
    return path


def label_branches(time: np.ndarray, depth: np.ndarray, force: np.ndarray, *,
                   depth_noise: float, force_noise: float) -> np.ndarray:
    """Each step's branch: +1 (intrusion: the foot goes down or rests) or -1 (withdrawal).

    Parameters
    ----------
    time : ndarray
        Sample times [s] (``n``), strictly increasing.
    depth : ndarray
        Measured depth [m], positive down.
    force : ndarray
        Measured force [N].
    depth_noise : float
        Standard deviation of the depth noise [m]; at or below 1 nm the
        steps' own signs are used (the paper's exact rule).
    force_noise : float
        Standard deviation of the force noise [N].

    Returns
    -------
    ndarray of int8, ``n - 1`` values
        The branch of the step from sample ``k`` to ``k + 1``; :data:`CUT` (an intrusion step) where
        the step cuts off a suction out of the mud (:func:`_cut_steps`): the foot is free after it.
    """
    z = np.asarray(depth, dtype=np.float64)
    d = np.diff(z)
    if depth_noise <= NOISE_FLOOR_M or d.size == 0:
        return np.where(d >= 0.0, 1, -1).astype(np.int8)
    scale = math.sqrt(2.0) * depth_noise
    plus = log_ndtr(d / scale)
    minus = log_ndtr(-d / scale)
    force = np.asarray(force, dtype=np.float64)
    jump = _jump_statistic(np.asarray(time, dtype=np.float64), force, force_noise)
    # a switch jumps either way: down as f_e2 vanishes, or up where k_w (z_i - z_m) outweighs it
    reward = np.minimum(0.5 * jump**2, JUMP_REWARD_CAP)
    # ... and only where the force's level changes (a kink, where a fast descent stops, is no switch)
    level = np.abs(_level_change(np.asarray(time, dtype=np.float64), force, force_noise))
    level[np.isnan(level)] = np.inf  # near the ends the level cannot be checked: the jump alone decides
    # out of the mud, a suction cut off by a downward step: evidence for an upward switch only
    cut = _cut_steps(z, force, jump, depth_noise, force_noise)
    # decisive: the model cannot cut a suction otherwise, however fast the foot rises over the step (it went down
    # between the samples)
    cut_reward = np.where(cut, _CUT_REWARD, 0.0)
    confirmed = level > _LEVEL_SIGMAS
    confirmed[1:] |= level[:-1] > _LEVEL_SIGMAS
    confirmed[:-1] |= level[1:] > _LEVEL_SIGMAS
    reward[~confirmed] = 0.0
    # the force's onset at touchdown (z^beta) is not a switch: no reward for
    # jumps out of the mud or within a few samples of entering it; but a drop of the force there is no onset:
    # a fast foot can reverse one or two samples after touchdown (a withdrawal switch between the samples)
    inside = z > 3.0 * depth_noise
    entered = np.flatnonzero(inside[1:] & ~inside[:-1])
    out = ~(inside[:-1] & inside[1:])
    onset = np.zeros_like(out)
    for i in entered:
        onset[i:i + _TOUCHDOWN_SAMPLES] = True
    down_reward = np.where(out | (onset & (jump >= 0.0)), 0.0, reward)
    reward[out | onset] = 0.0
    # a downward switch (to withdrawal) clear of the mud changes nothing in the model (the foot is free there once
    # any step has gone down), so it costs nothing: a cut suction is then not held back by the lift that follows
    down = down_reward - SWITCH_COST
    down[(z[:-1] < -3.0 * depth_noise) & (z[1:] < -3.0 * depth_noise)] = 0.0
    path = _viterbi(plus, minus, down, np.maximum(reward, cut_reward) - SWITCH_COST, -0.5 * SWITCH_COST)
    labels = np.where(path == 0, 1, -1).astype(np.int8)
    # a run of one or two steps that the depth does not support is a kink of the force, not two switches
    # (but a suction cut off out of the mud is a switch: a downward motion between the samples)
    change = np.flatnonzero(np.diff(labels) != 0) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [labels.size]])
    for a, b in zip(starts[1:-1], ends[1:-1], strict=True):
        if b - a <= 2 and np.all(labels[a] * d[a:b] < 2.0 * scale) and not np.any(cut[a:b]):
            labels[a:b] = -labels[a]
    labels[cut & (labels > 0)] = CUT
    return labels


def creep_withdrawals(time: np.ndarray, depth: np.ndarray, labels: np.ndarray, depth_noise: float) -> np.ndarray:
    """``labels`` with the slow withdrawals in the mud that the depth noise hides step by step set to -1 [-].

    The model's branch is the sign of each step (the paper's exact rule): a foot that rises by a micrometre a
    step is on the withdrawal branch, and the force drops there from the intrusion branch's to the withdrawal
    branch's. A standing foot often creeps up so: a robot's weight shifts, and its foot rises by a fraction of a
    millimetre a second, steps far below the depth noise at a high rate (0.4 um a step at 1 kHz under 30 um of
    noise), which :func:`label_branches` reads step by step as rest on the intrusion branch, until the foot
    lifts clearly. The model then withdraws from the wrong depth at the wrong time, and its suction after that
    is off by newtons (issue 23; a MuJoCo robot's stances at 1 kHz). Read together, the samples show the creep:
    for each run of intrusion steps in the mud that ends in a withdrawal step, a least-squares hinge through the
    run's depth (flat, then a straight line up from a corner at one of its samples: :func:`rest_steps`' hinge
    upside down); if the line rises by more than :data:`CREEP_SIGMAS` standard errors of its slope (white noise
    of ``depth_noise``) over at least :data:`CREEP_SAMPLES` samples, the foot was withdrawing from the corner on,
    and those steps are withdrawal steps (ours).

    Parameters
    ----------
    time : ndarray
        Sample times [s] (``n``), strictly increasing.
    depth : ndarray
        Measured depth [m], positive down.
    labels : ndarray
        Each step's branch (``n - 1`` values) from :func:`label_branches`.
    depth_noise : float
        Standard deviation of the depth noise [m]; at or below 1 nm the labels are returned as they are (the
        steps' own signs are then the branch).
    """
    lab: np.ndarray = np.asarray(labels, dtype=np.int8).copy()
    if depth_noise <= NOISE_FLOOR_M or lab.size == 0:
        return lab
    t = np.asarray(time, dtype=np.float64)
    z = np.asarray(depth, dtype=np.float64)
    intrusion = np.concatenate([[0], (lab == 1).astype(np.int8), [0]])
    edges = np.flatnonzero(np.diff(intrusion))
    for a, b in zip(edges[::2], edges[1::2], strict=True):  # steps a .. b-1, samples a .. b
        if b >= lab.size or lab[b] != -1 or b - a + 1 < CREEP_SAMPLES or not np.all(z[a:b + 1] > 0.0):
            continue
        a = max(a, b - _HINGE_SAMPLES)  # a long stance: the creep, if any, is near its end
        # the depth flat, then falling along a line from a corner at some sample (the hinge of rest_steps, upside down)
        ssr, slope, srr = _hinge_fit(t[a:b + 1], -z[a:b + 1], t[a:b])
        k = int(np.argmin(ssr))
        if b - (a + k) + 1 >= CREEP_SAMPLES and slope[k] > CREEP_SIGMAS * depth_noise / math.sqrt(srr[k]):
            lab[a + k:b] = -1
    return lab


@njit(cache=True)
def _pava(y: np.ndarray) -> np.ndarray:
    """Least-squares nondecreasing fit to ``y`` (pool adjacent violators)."""
    n = y.size
    level = np.empty(n)
    weight = np.empty(n)
    count = np.empty(n, dtype=np.int64)
    top = 0
    for i in range(n):
        level[top] = y[i]
        weight[top] = 1.0
        count[top] = 1
        top += 1
        while top > 1 and level[top - 2] > level[top - 1]:
            w = weight[top - 2] + weight[top - 1]
            level[top - 2] = (level[top - 2] * weight[top - 2] + level[top - 1] * weight[top - 1]) / w
            weight[top - 2] = w
            count[top - 2] += count[top - 1]
            top -= 1
    out = np.empty(n)
    i = 0
    for b in range(top):
        for _ in range(count[b]):
            out[i] = level[b]
            i += 1
    return out


@njit(cache=True)
def _enforce(iso: np.ndarray, labels: np.ndarray, first: float, eps: float) -> np.ndarray:
    """Follow ``iso`` while every step keeps its label's sign (``>= eps`` for +1, 0 for 0, ``<= -eps`` for -1)."""
    out = np.empty(iso.size)
    out[0] = first
    for k in range(1, iso.size):
        step = iso[k] - out[k - 1]
        if labels[k - 1] == 0:
            out[k] = out[k - 1]
        elif labels[k - 1] > 0:
            out[k] = out[k - 1] + max(step, eps)
        else:
            out[k] = out[k - 1] + min(step, -eps)
    return out


def corner_preserving_smooth(time: np.ndarray, depth: np.ndarray, width: int = 9, degree: int = 2) -> np.ndarray:
    """Local polynomial smoothing that does not round corners [m].

    Every window of ``width`` consecutive samples gets a least-squares
    polynomial of ``degree``; each sample takes the value, at its time, of
    the window containing it whose fit has the smallest residual. A window
    that straddles a corner (a touchdown, a stop, a reversal) fits badly and
    is passed over in favour of one on a single side of it (the idea of
    essentially non-oscillatory schemes). Returns ``depth`` itself when it
    has fewer than ``width`` samples.
    """
    t = np.asarray(time, dtype=np.float64)
    z = np.asarray(depth, dtype=np.float64)
    n = z.size
    if n < width:
        same: np.ndarray = z.copy()
        return same
    tw = np.lib.stride_tricks.sliding_window_view(t, width)
    zw = np.lib.stride_tricks.sliding_window_view(z, width)
    centre = tw.mean(axis=1, keepdims=True)
    span = np.maximum(tw[:, -1:] - tw[:, :1], 1e-300)
    x = (tw - centre) / span
    basis = np.stack([x**p for p in range(degree + 1)], axis=2)  # windows x width x (degree+1)
    q, r = np.linalg.qr(basis)
    coef = np.linalg.solve(r, np.einsum("wkp,wk->wp", q, zw)[..., None])[..., 0]
    fitted = np.einsum("wkp,wp->wk", basis, coef)
    ssr = np.sum((zw - fitted) ** 2, axis=1)
    windows = ssr.size
    # for sample i, windows starting at i - width + 1 .. i (those that exist)
    starts = np.arange(n)[:, None] - np.arange(width)[None, :]
    valid = (starts >= 0) & (starts < windows)
    cost = np.where(valid, ssr[np.clip(starts, 0, windows - 1)], np.inf)
    pick = np.argmin(cost, axis=1)
    w = starts[np.arange(n), pick]
    pos = np.arange(n) - w
    out: np.ndarray = fitted[w, pos]
    return out


def denoise_depth(depth: np.ndarray, labels: np.ndarray, time: np.ndarray | None = None,
                  noise: float = math.inf) -> np.ndarray:
    """The depth the model follows [m]: monotone within each run of equal branch, each step's sign its label.

    Within each run of steps with the same label, the least-squares
    nondecreasing (intrusion) or decreasing (withdrawal) fit to the measured
    depth (first smoothed by :func:`corner_preserving_smooth` when ``time``
    is given); then a forward pass keeps every step's sign (a withdrawal step
    moves up, and an intrusion step down, by at least 1e-12 m; a rest step
    not at all), so that the paper's exact branch rule reproduces
    ``labels`` (rest matters: it keeps a broken neck's decay going).

    Parameters
    ----------
    depth : ndarray
        Measured depth [m] (``n`` samples).
    labels : ndarray
        Branch of each step (``n - 1`` values of +1, :data:`CUT`, 0 (rest) or -1), from
        :func:`label_branches` and :func:`rest_steps`.
    time : ndarray, optional
        Sample times [s]; given, the depth is smoothed first.
    noise : float, optional
        The depth noise [m]: the smoothing moves no sample by more than three times this (ours). A
        departure beyond that is not noise but a motion the local quadratics cannot follow (a robot
        foot's impact, a vibration between a few samples), and rounding it off would change the
        branch the model takes there.
    """
    z = np.asarray(depth, dtype=np.float64)
    if time is not None:
        z = z + np.clip(corner_preserving_smooth(time, z) - z, -3.0 * noise, 3.0 * noise)
    given = np.asarray(labels, dtype=np.int8)
    lab = np.where(given < 0, -1, 1).astype(np.int8)  # rest steps (0) belong to the intrusion runs
    iso = np.empty_like(z)
    if z.size == 0:
        return iso
    # run j covers samples start..end (the first run includes sample 0)
    change = np.flatnonzero(np.diff(lab) != 0) + 1  # step indices where a new run begins
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [lab.size]])
    for a, b in zip(starts, ends, strict=True):
        lo = 0 if a == 0 else a + 1
        seg = z[lo:b + 1]
        iso[lo:b + 1] = _pava(seg) if lab[a] > 0 else -_pava(-seg)
    if lab.size == 0:
        iso[:] = z
    eps = 1e-12
    # a suction cut off out of the mud: the step starts and ends clear of the surface, so that the model is free
    # after it (a downward step that ended in the mud would keep the mud clinging)
    cuts = np.flatnonzero(given == CUT)
    iso[cuts] = np.minimum(iso[cuts], -2.0 * eps)
    out: np.ndarray = _enforce(iso, given, float(iso[0]), eps)
    return out


def rest_steps(time: np.ndarray, depth: np.ndarray, labels: np.ndarray, depth_noise: float,
               force: np.ndarray | None = None, force_noise: float = 0.0) -> np.ndarray:
    """``labels`` with the intrusion steps where the foot is at rest out of the mud set to 0 [-].

    At rest (the paper's ``dz = 0``) the model keeps a broken neck's decay
    going, while any downward motion ends it (``docs/model.md``); the
    isotonic depth would otherwise creep down through noise. In the mud
    rest and downward motion are the same intrusion branch, so only steps
    out of the mud are considered. Each run of intrusion steps out of the
    mud (a swing's apex, then its descent) gets a least-squares hinge: flat,
    then a straight line down, with the corner at any instant (a grid of a
    tenth of a step); the steps before the one that contains the corner
    are at rest, unless the line does not go down significantly (then all
    are). Given the force, a clear jump of it within a step of the corner
    (a broken neck's decay cut off) places the start to the sample, and a
    suction cut off earlier in the run (:func:`_cut_steps`: the force back
    at its free level) starts the descent there, however flat the depth.
    """
    lab: np.ndarray = np.asarray(labels, dtype=np.int8).copy()
    t = np.asarray(time, dtype=np.float64)
    z = np.asarray(depth, dtype=np.float64)
    if lab.size == 0:
        return lab
    out = (z[:-1] < 0.0) & (z[1:] < 0.0)
    if depth_noise <= NOISE_FLOOR_M:  # noise-free: the steps' own signs, zero included
        lab[(lab > 0) & (np.diff(z) == 0.0)] = 0
        return lab
    jump = cut = None
    if force is not None:
        f = np.asarray(force, dtype=np.float64)
        jump = _jump_statistic(t, f, force_noise)
        cut = _cut_steps(z, f, jump, depth_noise, force_noise)
    candidate = (lab > 0) & out
    edges = np.flatnonzero(np.diff(np.concatenate([[0], candidate.astype(np.int8), [0]])))
    for a, b in zip(edges[::2], edges[1::2], strict=True):  # steps a .. b-1, samples a .. b
        first = _hinge_start(t[a:b + 1], z[a:b + 1], depth_noise)
        cuts = np.flatnonzero(cut[a:b]) if cut is not None else np.zeros(0, dtype=np.int64)
        if cuts.size and (first is None or cuts[0] < first):  # a suction cut off: the descent starts there
            lab[a:a + int(cuts[0])] = 0
            continue
        if first is None:
            lab[a:b] = 0
            continue
        first += a
        if jump is not None:
            near = np.arange(max(first - 1, a), min(first + 2, b))
            if near.size:
                k = int(near[np.argmax(np.abs(jump[near]))])
                if abs(jump[k]) > 6.0:
                    first = k
        lab[a:first] = 0
    return lab


#: Longest stretch of samples a hinge is fitted to [-] (a longer run uses its last samples).
_HINGE_SAMPLES = 1500


def _hinge_start(t: np.ndarray, z: np.ndarray, noise: float) -> int | None:
    """The step where a flat-then-descending depth starts to descend (index into the steps); None if it never does."""
    n = t.size
    if n < 3:
        return 0
    offset = max(n - _HINGE_SAMPLES, 0)
    if offset:  # a long run: the corner, if any, is near its end; a descent all along starts at the beginning
        found = _hinge_start(t[offset:], z[offset:], noise)
        return None if found is None else (0 if found == 0 else offset + found)
    # coarse: a corner at each sample; fine: tenths of a step around the best
    best = _hinge_fit(t, z, t[:-1])
    k = int(np.argmin(best[0]))
    taus = np.linspace(t[max(k - 1, 0)], t[min(k + 1, n - 1)], 21)
    ssr, slope, srr = _hinge_fit(t, z, taus)
    i = int(np.argmin(ssr))
    se = noise / math.sqrt(srr[i]) if srr[i] > 0 else math.inf
    if not slope[i] > 3.0 * se:
        return None
    return min(max(int(np.searchsorted(t, taus[i], side="right")) - 1, 0), n - 2)


def _hinge_fit(t: np.ndarray, z: np.ndarray, taus: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Residual sum of squares, slope and ramp spread of ``z ~ a + b max(t - tau, 0)`` for each ``tau``."""
    ramp = np.maximum(t[None, :] - taus[:, None], 0.0)  # taus x samples
    rc = ramp - ramp.mean(axis=1, keepdims=True)
    srr = np.sum(rc**2, axis=1)
    zc = z - z.mean()
    slope = np.where(srr > 0, (rc @ zc) / np.where(srr > 0, srr, 1.0), 0.0)
    ssr = np.sum(zc**2) - slope**2 * srr
    return ssr, slope, srr
