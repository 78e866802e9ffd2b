"""The model along a recording as identify reads it: its force through a force sensor's lag, and the rest band.

:func:`_force_and_band` runs the paper's model (the exact rule) along the recorded depth and gives, at each sample,
the force and the band ``[F_up, F_down]`` a foot at rest may carry (Eq. (2)-(3)'s edges at the stepper's own Maxwell
strain), all three through the first-order low-pass a force sensor applies; :func:`_refined_run` any such model on a
cubic spline of the depth, and :func:`_discretisation` from it and from the model at half the rate the model's error
at the data's rate (identify's floor); :func:`_band_residual` the residual with a foot at rest compared with its band
(issue 23: rest is a band, not a branch), :func:`_rest_samples` the samples read as rest, and
:func:`_bias_reprofiled` the misfit statistic with the force bias re-profiled under its weights (identify's flag and
fit's). The compiled loops are speed plumbing: the same operations in the same order as the numpy they replace, so
the same bits. Private to the calibration package: identify, fit (the rest samples, the band's residual, the sticking
stretches, the flag's statistic) and the paper's model's ``rest_band`` (:func:`_vector_force_and_band`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import reduce
from typing import NamedTuple

import numpy as np
from scipy.interpolate import CubicSpline

from mudforce import _kernel as K
from mudforce._plumbing.jit import njit
from mudforce.estimation.nuisances import REST_SPEED, _lowpass_coefficients, _lowpass_step
from mudforce.model.equations import rest_band_forces
from mudforce.model.foot import Foot
from mudforce.model.law3d import spring_stress
from mudforce.model.parameters import PARAMETER_NAMES, MudParameters
from mudforce.steppers.simulation import run_compact

__all__: list[str] = []

#: The contact state after necking, as the stepper's ``state`` output holds it (:class:`mudforce._kernel.ContactMode`).
_NECKED = int(K.ContactMode.NECKED)


@njit(cache=True, nogil=True)
def _np_min(a: float, b: float) -> float:  # pragma: no cover - compiled
    """``np.minimum(a, b)``: NaN kept, ``b`` on a tie (the sign of a zero as numpy's)."""
    return a if (a < b or a != a) else b


@njit(cache=True, nogil=True)
def _np_max(a: float, b: float) -> float:  # pragma: no cover - compiled
    """``np.maximum(a, b)``: NaN kept, ``b`` on a tie (the sign of a zero as numpy's)."""
    return a if (a > b or a != a) else b


#: Distinct sample steps whose low-pass coefficients :func:`_band_through_lag` keeps [-] (speed plumbing; a step
#: beyond them is computed each time it comes).
_STEP_TABLE = 32


@njit(cache=True, nogil=True)
def _band_through_lag(time: np.ndarray, depth: np.ndarray, force: np.ndarray, state: np.ndarray, mud: np.ndarray,
                      spring: np.ndarray, k_m_i: float, k_m_w: float, area: float, lag: float
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """The rest band ``(low, high)`` [N] about the model's ``force`` [N] at each sample, and all three through a
    force lag ``lag`` [s] (see :func:`_force_and_band`).

    At a sample in contact (``state`` > 0) the band is :func:`~mudforce.model.equations.rest_band_forces` at the
    Maxwell strain ``depth - mud`` [m] and the spring stress ``spring`` [Pa] (its intrusion edge 0 at or above the
    surface; after necking its withdrawal edge the post-necking force, the model's force there, as the engines'
    :func:`~mudforce.engines.dynamics.rest_band.rest_band` has it), widened to hold the force; elsewhere it is the
    force itself. With ``lag`` > 0 the three pass through
    the first-order low-pass ``tau y' + y = x``, exact for ``x`` linear between samples (ours).

    Speed plumbing: one compiled pass for what numpy did in a dozen (one ``exp`` for the three, and one per distinct
    step, not per sample), the same operations in the same order, so the same bits.
    """
    n = force.size
    low = np.empty(n)
    high = np.empty(n)
    for k in range(n):
        f = force[k]
        if state[k] > 0:
            up, down = rest_band_forces(depth[k] - mud[k], spring[k], k_m_i, k_m_w, area)
            if not depth[k] > 0.0:
                down = 0.0
            if state[k] == _NECKED:  # after necking the withdrawal edge is the post-necking force (Eq. (7))
                up = f
            low[k] = _np_min(_np_min(up, down), f)
            high[k] = _np_max(_np_max(up, down), f)
        else:
            low[k] = f
            high[k] = f
    if not lag > 0.0 or n == 0:
        return force, low, high
    f_out, low_out, high_out = np.empty(n), np.empty(n), np.empty(n)
    f_out[0], low_out[0], high_out[0] = force[0], low[0], high[0]
    # a recording's steps take a dozen distinct values (a clock's rounding): each one's (e, c) is computed once and
    # kept in a small table, read back where the step is the same to the bit (the same numbers as computing it anew)
    steps = np.empty(_STEP_TABLE)
    es = np.empty(_STEP_TABLE)
    cs = np.empty(_STEP_TABLE)
    held = 0
    for k in range(n - 1):
        h = time[k + 1] - time[k]
        j = 0
        while j < held and steps[j] != h:
            j += 1
        if j < held:
            e, c = es[j], cs[j]
        else:
            e, c = _lowpass_coefficients(h, lag)
            if held < _STEP_TABLE:
                steps[held], es[held], cs[held] = h, e, c
                held += 1
        f_out[k + 1] = _lowpass_step(e, c, f_out[k], force[k], force[k + 1])
        low_out[k + 1] = _lowpass_step(e, c, low_out[k], low[k], low[k + 1])
        high_out[k + 1] = _lowpass_step(e, c, high_out[k], high[k], high[k + 1])
    return f_out, low_out, high_out


def _force_and_band(time: np.ndarray, depth: np.ndarray, q: MudParameters, foot: Foot,
                    lag: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model's force [N] along ``depth`` [m] (exact rule) and the rest band ``(low, high)`` [N] at each sample.

    The band is that of :func:`mudforce.model.equations.rest_band_forces` at
    the stepper's own Maxwell strain, widened to hold the model's force
    (after necking the withdrawal edge is the post-necking force); out of the
    mud it is the force itself. With ``lag`` > 0 [s] all three pass through
    the first-order low-pass a force sensor applies (:func:`_band_through_lag`).
    """
    return _vector_force_and_band(time, depth, q.as_array(), foot, lag)


_K_M_I, _K_M_W, _ALPHA, _BETA = (PARAMETER_NAMES.index(n) for n in ("k_m_i", "k_m_w", "alpha", "beta"))


def _vector_force_and_band(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot,
                           lag: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_force_and_band` for the paper's parameters as a vector ``values`` [SI] in
    :data:`~mudforce.model.parameters.PARAMETER_NAMES`' order (the fit's vector: no :class:`MudParameters` made,
    so none checked, at each of its evaluations)."""
    row = K.make_params(values, foot.area, foot.width, 1, 0.0)[None, :]
    bad, force, state, mud, _ = run_compact(time, depth, row, 1)
    if bad >= 0:  # numerically impossible parameters: a huge, finite residual
        force[bad:] = 1e6
    # Eq. (4) at every sample, 0 above the surface (one compiled loop over the same function: its power gives the
    # same bits in a loop as in a single call)
    spring = spring_stress(depth, float(values[_ALPHA]), float(values[_BETA]), foot.width)
    # (time contiguous, as run_compact takes it: the half-rate runs' strided times compiled the loop a second time)
    return _band_through_lag(np.ascontiguousarray(time), depth, force, state, mud, spring,  # type: ignore[no-any-return]
                             float(values[_K_M_I]), float(values[_K_M_W]), foot.area, lag)


def _with_neighbours(x: np.ndarray) -> np.ndarray:
    """Each sample the largest of itself and its two neighbours (an event between two samples moves a coarser
    model at a neighbour of the sample it moves the data at)."""
    out: np.ndarray = x.copy()
    out[1:-1] = np.maximum(x[1:-1], np.maximum(x[2:], x[:-2]))
    return out


#: Samples the refined interpolation puts in each step of the recording [-] (ours): the model's error at the data's
#: rate is the difference of the model on the recording and on the refinement (Richardson); more changes it little.
_REFINE = 4


#: ``run(time [s], depth [m]) -> (force, low, high)`` [N]: a model along a depth, its force and its rest band.
Run = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]


def _refined_run(time: np.ndarray, depth: np.ndarray, run: Run) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``run`` [N] at the samples, the model run on a cubic spline of ``depth`` [m] through them.

    The spline (not-a-knot) puts :data:`_REFINE` steps in each step of the recording; it passes through every
    sample, and between them it follows the motion's curvature where the stepper alone takes the depth as linear.
    """
    if time.size < 4:
        return run(time, depth)
    frac = np.arange(_REFINE) / _REFINE
    fine_t = np.concatenate([(time[:-1, None] + frac[None, :] * np.diff(time)[:, None]).ravel(), time[-1:]])
    fine_z = CubicSpline(time, depth)(fine_t)
    fine_z[::_REFINE] = depth
    f, low, high = run(fine_t, fine_z)
    return f[::_REFINE], low[::_REFINE], high[::_REFINE]


def _discretisation(time: np.ndarray, depth: np.ndarray, run: Run, rest: np.ndarray,
                    force: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The model's own discretisation error at the data's rate, sample by sample [N^2], estimated from the data (issue
    23, point 4), and its half-rate part alone [N^2].

    ``run`` is the model along ``depth`` [m] at ``time`` [s], ``force`` [N] the model's force at the samples as
    read, ``rest`` the samples read through the band. The model at half the rate (the even samples, the odd ones)
    against ``force`` at the moving samples: an event between two samples (a touchdown, a reversal, a neck) moves
    the half-rate model at a neighbour of the sample it moves the data at, so each sample takes the largest of
    itself and its two neighbours (:func:`_with_neighbours`); and the model on the recording against the model on a
    refined cubic interpolation of it (:func:`_refined_run`): the stepper takes the depth as linear between the
    samples, the spline follows the motion's curvature (the speed changing within a step, an apex or a stop between
    two samples); their difference is the model's error at the data's rate to leading order. At rest the band's
    edges are compared (the band is what is read). identify's and fit's one statement of it.
    """
    moving = ~rest
    disc2 = np.zeros(time.size)
    for sel in (slice(0, None, 2), slice(1, None, 2)):
        half = run(time[sel], depth[sel])[0]
        disc2[sel] = np.where(moving[sel], half - force[sel], 0.0) ** 2
    ref = _refined_run(time, depth, run)
    own = run(time, depth)
    edges = np.maximum((ref[1] - own[1]) ** 2, (ref[2] - own[2]) ** 2)
    half2 = _with_neighbours(disc2)
    return _with_neighbours(np.maximum(disc2, np.where(rest, edges, (ref[0] - own[0]) ** 2))), half2


#: The sticking test (:func:`_sticking`; ours): a stretch whose depth moves slower than the engines' own deadband
#: (:data:`mudforce.engines.dynamics.result.REST_SPEED`, 0.1 mm/s) plus two standard errors of its slope is read as
#: the foot possibly stuck; the slope is the depth's least-squares one over a centred window of the fewest samples
#: that bring its standard error under :data:`_STICK_SLOPE_ERROR` [m/s] (0.25 mm/s), at most :data:`_STICK_WINDOW`
#: [s] across (and at least three samples).
_STICK_SPEED = 1e-4
_STICK_SLOPE_ERROR = 2.5e-4
_STICK_WINDOW = 0.06
#: The creep up a stuck stretch is also read with [m a sample] (ours): small enough to leave the depth as it was
#: (1 um over a second at 1 kHz), large enough that every step of it is one on the withdrawal branch.
_CREEP_STEP = 1e-9


@njit(cache=True, nogil=True)
def _window_slopes(time: np.ndarray, depth: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
    """The least-squares slope [m/s] of ``depth`` [m] over ``time`` [s] in each centred window of ``2 m + 1``
    samples, and the window's ``sum((t - mean t)^2)`` [s^2], for the samples ``m`` to ``n - m - 1``. Speed plumbing:
    a loop over the windows (no window copies: a ten-minute recording at 1 kHz has 600 000 of 61 samples)."""
    n = time.size - 2 * m
    slope = np.empty(n)
    spread = np.empty(n)
    width = 2 * m + 1
    for k in range(n):
        tm = 0.0
        zm = 0.0
        for i in range(k, k + width):
            tm += time[i]
            zm += depth[i]
        tm /= width
        zm /= width
        stt = 0.0
        stz = 0.0
        for i in range(k, k + width):
            d = time[i] - tm
            stt += d * d
            stz += d * (depth[i] - zm)
        slope[k] = stz / stt
        spread[k] = stt
    return slope, spread


class Sticking(NamedTuple):
    """Where the foot may be stuck along a recording, and the two depths [m] the model also follows there
    (:func:`_sticking`)."""

    stuck: np.ndarray
    held: np.ndarray
    creep: np.ndarray


def _sticking(time: np.ndarray, depth: np.ndarray, noise: float) -> Sticking:
    """Where the foot may be stuck, and the depths the model also follows through those stretches (issue 23, point 4).

    A stuck foot's Maxwell element relaxes with the intrusion parameters (the model's sticking, docs/model.md, as the
    engines step it, with a deadband of 0.1 mm/s); the exact rule along a recorded depth reads the branch from the
    sign of each step, which at a stuck foot is the creep's or the depth noise's, and after a few hundred
    milliseconds the bands' edges differ by about 0.5 N, and the withdrawal that follows by as much. A recording
    cannot tell a creep of 0.05 mm/s from one of 0.2 mm/s, so identify's flag reads the model as the set of the
    relaxations the foot may have had (:func:`_model_set`). ``stuck`` [bool]: the samples, in the mud, whose centred
    window's slope [m/s] is within :data:`_STICK_SPEED` plus two of its standard errors (``noise`` [m], the depth's)
    of none. ``held`` [m]: the depth with each run of two or more of them held at the run's mean (no step: the
    intrusion parameters' relaxation); ``creep`` [m]: the same, creeping up by :data:`_CREEP_STEP` a sample (the
    withdrawal parameters'). Both the depth itself elsewhere.
    """
    n = depth.size
    stuck = np.zeros(n, dtype=bool)
    held = depth.copy()
    creep = depth.copy()
    if n < 3:
        return Sticking(stuck, held, creep)
    h = float(np.median(np.diff(time)))
    largest = max(1, int(_STICK_WINDOW / (2.0 * h)))
    m = 1
    while m < largest and noise / (h * math.sqrt(m * (m + 1) * (2 * m + 1) / 3.0)) > _STICK_SLOPE_ERROR:
        m += 1
    if n < 2 * m + 1:
        return Sticking(stuck, held, creep)
    slope, spread = _window_slopes(time, depth, m)
    stuck[m:n - m] = (np.abs(slope) <= _STICK_SPEED + 2.0 * noise / np.sqrt(spread)) & (depth[m:n - m] > 0.0)
    where = np.flatnonzero(stuck)
    if where.size:
        for run in np.split(where, np.flatnonzero(np.diff(where) > 1) + 1):
            if run.size >= 2:
                held[run] = np.mean(depth[run])
                creep[run] = held[run] - _CREEP_STEP * np.arange(run.size)
    return Sticking(stuck, held, creep)


def _model_set(time: np.ndarray, depth: np.ndarray, offset: float, sticking: Sticking, rest: np.ndarray,
               q: MudParameters, foot: Foot, lag: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model's force [N] along ``depth + offset`` [m] and, at each sample, the set ``[low, high]`` [N] the force
    may lie in, all through the force lag ``lag`` [s].

    Where the foot may be stuck (:func:`_sticking`) the model also runs along the ``sticking`` stretches held and
    creeping up (each plus ``offset``): at the ``rest`` samples and the stuck ones the set is the union of the three
    runs' rest bands, elsewhere the three forces and everything between. With no stuck sample it is the model's force
    itself at a moving sample and its band at rest: :func:`_band_residual` with ``rest`` everywhere then gives the
    same bits as :func:`_band_residual` of :func:`_force_and_band`.
    """
    f, low, high = _force_and_band(time, depth + offset, q, foot, lag)
    if not sticking.stuck.any():
        return f, np.where(rest, low, f), np.where(rest, high, f)
    f2, low2, high2 = _force_and_band(time, sticking.held + offset, q, foot, lag)
    f3, low3, high3 = _force_and_band(time, sticking.creep + offset, q, foot, lag)
    return _union([(f, low, high), (f2, low2, high2), (f3, low3, high3)], rest | sticking.stuck)


def _union(runs: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]],
           banded: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The set several runs of a model span [N]: ``(force, low, high)``, ``force`` the first run's; at the
    ``banded`` samples ``[low, high]`` holds every run's rest band, elsewhere every run's force and everything between.
    ``runs``: each ``(force, low, high)`` [N] along one depth. :func:`_model_set`'s and fit's flag's one statement."""
    forces, lows, highs = zip(*runs, strict=True)
    return (forces[0], np.where(banded, reduce(np.minimum, lows), reduce(np.minimum, forces)),
            np.where(banded, reduce(np.maximum, highs), reduce(np.maximum, forces)))


#: A step in the mud within this many depth noises (beyond the rest speed) of no motion counts as rest [-] (ours):
#: on a robot foot at rest the depth the model follows still moves by a fraction of a depth noise from sample to
#: sample, and a branch the depth cannot tell is read through the rest band.
_REST_NOISE_SIGMAS = 0.5


def _slow_steps(step: np.ndarray, dt: np.ndarray, depth_noise: float) -> np.ndarray:
    """The steps a foot at rest could have made [bool]: ``|step|`` [m] within the rest speed
    (:data:`~mudforce.estimation.nuisances.REST_SPEED`) times the step's ``dt`` [s] plus :data:`_REST_NOISE_SIGMAS`
    depth noises ``depth_noise`` [m]. The first part of :func:`_rest_samples`."""
    out: np.ndarray = np.abs(step) <= REST_SPEED * dt + _REST_NOISE_SIGMAS * depth_noise
    return out


#: A sample where the motion changes (down, rest, up) is read through the rest band when a step beside it moves by
#: more than this many depth noises [-] (ours): there the depth, not the force, fixed the branch, and the change
#: happened anywhere between the neighbours (at 50-100 Hz a robot foot turns between two samples).
_TURN_SIGMAS = 3.0


def _rest_samples(time: np.ndarray, depth: np.ndarray, depth_noise: float, turns: bool = True) -> np.ndarray:
    """The samples read through the rest band [bool] (general path): those whose step moved the foot less than the
    rest speed and the depth noise ``depth_noise`` [m] (:func:`_slow_steps`), and (``turns``) those where the motion
    changes direction or stops (down, rest, up) with a step beside them clearly moving (:data:`_TURN_SIGMAS`).
    ``time`` [s], ``depth`` [m]. The one statement of which samples are rest, for identify and fit."""
    step = np.diff(depth)
    slow = _slow_steps(step, np.diff(time), depth_noise)
    still: np.ndarray = np.concatenate([[False], slow])
    if not turns:
        return still
    # where the motion changes (down, rest, up) at a sample, the change happened anywhere between its two
    # neighbours: at the sample the foot may already be on the other branch, so the band is all it tells
    motion = np.where(slow, 0, np.where(step > 0.0, 1, -1))
    clear = np.abs(step) > _TURN_SIGMAS * depth_noise
    still[1:-1] |= (motion[:-1] != motion[1:]) & (clear[:-1] | clear[1:])
    return still


def _band_residual(model: np.ndarray, low: np.ndarray, high: np.ndarray, measured: np.ndarray,
                   rest: np.ndarray) -> np.ndarray:
    """The model's residual [N] (model minus ``measured``, both [N]); at the ``rest`` samples a foot at rest fits
    anywhere in its rest band ``[low, high]`` [N], so the residual there is the measured force's distance outside
    it (issue 23: rest is a band, not a branch). The one statement of that rule for the fit and the flag's member."""
    out: np.ndarray = np.where(rest, np.clip(measured, low, high), model) - measured
    return out


#: Largest squared standardised residual one sample adds to the misfit statistic [-] (ours, as the tracker's; fit's
#: too): a sample whose branch the labels got wrong counts as five floors, not as an off-family mud.
_MISFIT_CLIP = 25.0
#: A sample is in the statistic's tail when its residual is beyond three floors (``r^2 / floor^2 > 9``) [-] (ours).
_TAIL_Z2 = 9.0
#: Largest share of the samples in the tail before identify's misfit flag fires [-] (ours; 4.5 %, 15 times a normal
#: law's 0.3 %): the statistic clips each sample at five floors, so a law missing a fifth of the samples by a
#: little reads like one missing a few by much; the share tells them apart (docs/estimation.md, "The share of
#: samples beyond three floors").
TAIL_SHARE_WARNING = 0.045
#: Share of its limit [-] past which two of the flag's three readings fire it together (ours, 2026-12-01): the misfit
#: ratio over :data:`~mudforce.estimation.calibration.fit.MISFIT_WARNING_RATIO`, ``Identification.tail_share`` over
#: :data:`TAIL_SHARE_WARNING` and ``Identification.other_mud`` over ``identify.OTHER_MUD_WARNING``. A recording near
#: two limits at once is rarer in family than one past a single limit: on the misfit-flag bench's twelve seeds the
#: three off-family recordings of 1440 that no single reading caught (F = k z and alpha x2 along MuJoCo walks at
#: 50 Hz) read 0.84-0.99 of two limits, and 11 more of the 1080 in-family ones fire with it; chosen there, then read
#: on six fresh seeds: off family 720 of 720 flagged (719 without it), in family 13 of 540 (8) (docs/estimation.md,
#: "Two readings near their limits"). fit's flag holds its robust refit under this share of each limit too.
NEAR_LIMITS_WARNING = 0.8


@njit(cache=True, nogil=True)
def _misfit_terms(model: np.ndarray, low: np.ndarray, high: np.ndarray, measured: np.ndarray, rest: np.ndarray,
                  variance: np.ndarray, free: np.ndarray, d: float, r: np.ndarray, cost_terms: np.ndarray,
                  stat_terms: np.ndarray) -> None:  # pragma: no cover - compiled
    """Each sample's residual ``r`` [N] (:func:`_band_residual` of ``measured + d`` [N]) and its two terms [-] of
    :func:`_bias_reprofiled`: ``r^2 / variance`` capped at :data:`_MISFIT_CLIP` (``stat_terms``), and uncapped at
    the ``free`` samples (``cost_terms``). numpy's operations, one pass (``np.clip`` and ``np.minimum`` as numpy
    has them: NaN kept, the bound on a tie), so the same bits."""
    for k in range(model.size):
        m = measured[k] + d
        if rest[k]:
            c = m if m > low[k] else low[k]
            c = c if c < high[k] else high[k]
        else:
            c = model[k]
        rk = c - m
        r[k] = rk
        z2 = rk * rk / variance[k]
        capped = z2 if (z2 < _MISFIT_CLIP or z2 != z2) else _MISFIT_CLIP
        cost_terms[k] = z2 if free[k] else capped
        stat_terms[k] = capped


@njit(cache=True, nogil=True)
def _newton_terms(r: np.ndarray, variance: np.ndarray, free: np.ndarray, picked: np.ndarray,
                  weights: np.ndarray) -> int:  # pragma: no cover - compiled
    """The samples a Newton step of :func:`_bias_reprofiled` reads (inside their clip, or ``free``; a residual not
    0), in order: ``r / variance`` into ``picked`` [1/N], ``1 / variance`` into ``weights`` [1/N^2]; returns their
    count."""
    count = 0
    for k in range(r.size):
        if ((r[k] * r[k] < _MISFIT_CLIP * variance[k]) or free[k]) and r[k] != 0.0:
            picked[count] = r[k] / variance[k]
            weights[count] = 1.0 / variance[k]
            count += 1
    return count


def _bias_reprofiled(model: np.ndarray, low: np.ndarray, high: np.ndarray, measured: np.ndarray, rest: np.ndarray,
                     variance: np.ndarray, free: np.ndarray) -> tuple[float, float]:
    """The misfit statistic [-], ``mean(min(r_k^2 / variance_k, 25))``, the force bias re-profiled under its weights;
    and the bias moved [N] (the residuals are those of ``measured`` plus it).

    ``model`` [N] is the model's force, ``low``, ``high`` [N] the rest band (``rest`` samples: the residual is the
    measured force's distance outside it), ``measured`` [N] the force with the least-squares bias removed,
    ``variance`` [N^2] each sample's floor. The bias is moved from the least-squares one to the nearest local minimum
    of the statistic (Newton steps on the samples inside their clip, halved until the statistic does not rise; ours):
    least squares weighs every sample alike, so a few samples with a floor of tens of newtons (an event between two
    samples) set the bias that a sample out of the mud, whose floor is the force noise, then reads. The ``free``
    samples (the foot above the surface, the model's force nil) read the bias itself, with no branch to misread: the
    re-profile weighs them uncapped, so that it cannot give them up to fit the samples in the mud.

    Speed plumbing: the per-sample arithmetic in two compiled passes (:func:`_misfit_terms`,
    :func:`_newton_terms`), the sums and means numpy's own, so the same bits as the rule written in numpy alone
    (``tests/estimation/test_identify_speed.py``) and several times faster: it runs thousands of times an identify.
    """
    n = model.size
    r, r_new, cost_terms, stat_terms, picked, weights = (np.empty(n) for _ in range(6))

    def residual(d: float, out: np.ndarray) -> tuple[float, float]:
        _misfit_terms(model, low, high, measured, rest, variance, free, d, out, cost_terms, stat_terms)
        return float(np.mean(cost_terms)), float(np.mean(stat_terms))

    d = 0.0
    cost, stat = residual(d, r)
    for _ in range(30):
        count = _newton_terms(r, variance, free, picked, weights)
        if count == 0:
            break
        step = float(np.sum(picked[:count]) / np.sum(weights[:count]))
        cost_new = stat_new = 0.0
        while abs(step) > 1e-9:
            cost_new, stat_new = residual(d + step, r_new)
            if cost_new <= cost:
                break
            step *= 0.5
        if abs(step) <= 1e-9:
            break
        d, cost, stat = d + step, cost_new, stat_new
        r, r_new = r_new, r
    return stat, d
