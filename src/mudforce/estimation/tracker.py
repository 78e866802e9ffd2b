"""Online tracking of the mud's water content from a robot's own foot, one sample at a time.

A robot that walks on mud measures its foot's depth and the vertical force
on it. :class:`MudTracker` turns that stream into an estimate of the mud's
water content ``W`` (with a 95 % interval), the force the model predicts for
the sample, and a flag when the terrain has changed, at a cost of a few
microseconds per sample. :class:`MudTrackers` does the same for many feet at
once. The design (a bank of models on a grid of ``W``, Bayesian updating
with forgetting) is set out in ``docs/tracking.md``; in short:

* **Bank.** One :class:`mudforce.MudContacts` row per grid value of ``W``
  (Table I, interpolated: :meth:`MudParameters.from_water_content`), all
  stepped on the same measured depth with the noise-robust branch rule
  (:class:`mudforce.VelocityFilter`). Each row's force is that model's
  prediction for the sample.
* **Surface offset.** The bank holds the grid once per surface offset
  hypothesis (``depth_offsets``), each stepped on the depth plus its
  offset; the posterior is joint, each offset's evidence tempered (a wrong
  offset is a misfit that lasts a stance), and the water content's is the
  sum over the offsets, so the offset's uncertainty enters the interval.
  The models of an offset other than the most probable one that hold less
  than 1e-12 of the posterior are spared: scored in turn once per two
  correlation times, each score standing for the contact time since its
  last (decay and weight), their posterior 0 in between. With one offset
  nothing is spared.
* **Substeps.** The bank is stepped at no more than ``max_step`` (10 ms)
  per step: a longer sample interval is cut into equal substeps, the
  depth interpolated linearly between the two samples (at 20 Hz a model
  stepped once per sample missed what the foot did between them).
* **Force lag.** A small bank of lags (first-order low-passes of 0-60 ms,
  and two equal low-passes in a row, of 5-15 ms each, the shape of a delay
  with a low-pass) scores the mean model's force through each; every
  model's force goes through the posterior mean of each stage, and the
  lag's posterior spread enters the likelihood's scale, so a lagging sensor
  is read as a lag, not as other mud, and its uncertainty widens the
  interval.
* **Sensor offset (bias) and noise.** While every model is FREE (foot
  above the surface, the mud let go), the model force is exactly zero, so
  the measured force is offset plus noise: the offset is their running
  mean, the noise its running spread (clipped at 4 sigma, so the rare
  sample with force on it does not inflate it; a run of samples beyond the
  clip, a force the bank missed, is left out; after a second of free
  samples it is taken as a real shift of the offset if it scatters about
  its own mean by about the noise). Both are independent of the model fit.
* **Likelihood.** A Student-t (``dof`` degrees of freedom) of the measured
  force minus the offset around each model's force, with a scale of the
  noise, the offset's uncertainty, a ``floor`` and a relative misfit
  ``misfit * |F|`` added in quadrature, and weighted by
  ``min(1, dt / correlation_time)``:
  the model is not exact for measured data (a reversal of the foot is seen a
  few samples late through the noise, so the nonlinear spring can be
  switched on the wrong branch for a few samples, errors of up to the whole
  spring force), and those errors are correlated from sample to sample. The
  heavy tails make such a sample weak evidence; the weight counts
  correlated samples as fewer. A foot at rest is read through its rest
  band (a load anywhere in it fits); beyond the band, under a noisy depth,
  the scale also holds how far that noise moves the band's end
  (:func:`~mudforce.engines.dynamics.rest_band.rest_band_spread`).
* **Forgetting.** The log-posterior decays by ``exp(-dt / tau)`` per sample
  in contact (samples where every model predicts zero force carry no
  information and forget nothing). No model trails the best by more than
  100 nats of log-likelihood (``_MAX_LEAD``): a water content ruled out
  that firmly is as good as excluded, and a change of mud then has that
  little to make up rather than the old mud's whole evidence of ``tau``
  seconds, so the estimate follows a change within about a second of
  contact (3 s with forgetting alone), without being told.
* **Estimate.** Each grid value stands for a cell reaching halfway to its
  neighbours; the posterior is uniform within a cell, and the water content
  is the posterior median, the interval its 2.5 % and 97.5 % quantiles.
  The predicted force is the mean of the models' forces under the posterior
  *before* the sample (a one-step-ahead prediction) plus the offset, i.e. the
  expected sensor reading.
* **Twin bank.** With the default branch rule a second, smaller bank (the
  surface offsets within 3 mm of zero) runs beside the first on the quick
  rule (a secant over 2 steps with a 2.5 mm/s deadband) for every foot at
  every depth, and the reported interval is the union of the two banks'
  (the estimate is the first bank's, the misfit flag is raised where both
  banks' are, the nuisances' spreads hold the twin's readings; the change
  flag reads the union, below): the branch rule is a model choice the data
  seldom settle, and deep wet robots read points low on the 10-step rule
  (the more under a lagged force, which the lag then absorbs) and right on
  the quick one, while noisy gait walks read the other way. A given
  ``velocity_filter`` has no twin.
* **Change flag.** Once the fit's interval is narrower than a settling
  width (4 points, or 6 grid steps) and the offset has been tared (10 free
  samples), its median becomes the anchor, and the reported interval
  there the anchor's interval, which every later settled interval that
  still holds the anchor narrows (their intersection). When a later
  estimate as settled has a reported interval (the one returned, which
  holds the twin bank's) that lies clear of the anchor's interval by more
  than a margin (1 point, or 2 grid steps), the flag is raised for that
  sample. For the next ``tau`` seconds of contact the anchor and its
  interval follow the settling estimate without a second flag. So a flag
  never says more than the intervals do: while the twin bank still holds
  the old mud, or every interval since the anchor has also held the new
  one, no change is flagged.
* **Memory of the interval.** The interval returned is the hull of the
  last second or so of those intervals: each end relaxes toward the
  current one with a time constant of 1 s where that is narrower, a
  change flag included (the flag reads the current interval, not the
  hull; the interval forgets the old mud in the hull's time, so a false
  flag does not leave it clear of the truth). A posterior that jumps
  between two modes for a fraction of a second has not told them apart,
  and the interval keeps both: after the estimate jumps by more than 2
  points in one sample, the hull's ends are held, unrelaxed, for its own
  time of contact before they relax. An end
  that leaves out only a sliver at the grid's end, where the posterior is
  about as dense as within, reaches that end: a foot that says almost
  nothing reports the whole grid, not the grid less a sliver at each end.
  Between a quarter and an eighth of the interval's density it moves part
  of the way, in proportion, so that the reported end never jumps.

Where it lives: the classes and :func:`track` here; the constants and the
arrays' layout in :mod:`mudforce.estimation._tracker_layout`; the speed
plumbing, the whole update (bank step and posterior) as one compiled call
over arrays held by the object, in :mod:`mudforce.estimation._tracker_step`
(:func:`~mudforce.estimation._tracker_step._track_step`).
"""

from __future__ import annotations

import inspect
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import Any, ClassVar

import numpy as np

from mudforce._kernel.bounds import MAX_DEPTH, MAX_TIME, MIN_DT
from mudforce._kernel.layout import S_CACHE_DT
from mudforce._plumbing.deprecation import warn_renamed
from mudforce.errors import InputError, feet_count, positive_number, real_array, real_number, true_or_false
from mudforce.estimation import _tracker_layout as L
from mudforce.estimation._tracker_layout import (
    DEFAULT_DEPTH_OFFSET_PRIOR,
    DEFAULT_DEPTH_OFFSETS,
    DEFAULT_FORCE_LAG_ALLOWANCE,
    DEFAULT_GRID,
    DEFAULT_MAX_STEP,
    MAX_FORCE,
    MISFIT_THRESHOLD,
)
from mudforce.estimation._tracker_step import (
    _blur_matrix,
    _check_bounds,
    _pack,
    _restore_step_cache,
    _track_pair,
    _track_step,
)
from mudforce.estimation.family_check import DEFAULT_FAMILY_EVERY, FamilyCheck, FamilyVerdict, _feed, _flags
from mudforce.estimation.nuisances import DEFAULT_FORCE_GAIN_UNCERTAINTY, REST_SPEED, check_force_varies
from mudforce.model.bounds import check_finite, check_times
from mudforce.model.foot import Foot
from mudforce.model.parameters import WATER_CONTENT_RANGE, MudParameters
from mudforce.model.velocity import VelocityFilter, resolve_velocity_filter

__all__ = [
    "DEFAULT_DEPTH_OFFSETS",
    "DEFAULT_DEPTH_OFFSET_PRIOR",
    "DEFAULT_FORCE_LAG_ALLOWANCE",
    "DEFAULT_GRID",
    "DEFAULT_MAX_STEP",
    "MISFIT_THRESHOLD",
    "MudTracker",
    "MudTrackers",
    "TrackEstimate",
    "TrackEstimates",
    "TrackResult",
    "TrackerState",
    "default_velocity_filter",
    "track",
]



def default_velocity_filter(depth_noise: float = 3e-5, dt: float = 0.01) -> VelocityFilter:
    """The bank's branch rule: :meth:`VelocityFilter.for_noise` for ``depth_noise`` [m] at step ``dt`` [s]."""
    return VelocityFilter.for_noise(depth_noise, dt)



# ---------------------------------------------------------------------------- public API

@dataclass(frozen=True)
class TrackEstimate:
    """One foot's estimate after a sample (from :meth:`MudTracker.update`).

    Attributes
    ----------
    water_content : float
        Posterior median of the water content [-] (0.25 means 25 %).
    low, high : float
        Central 95 % credible interval of the water content [-], widened
        for what the fit does not see (the model's discrepancy, a misfit, a
        shallow sinkage, a low rate, the twin bank's branch rule) and kept
        as the hull of about the last second of such intervals.
    force_predicted : float
        The force the sensor should read for this sample [N]: the models'
        mean force under the posterior before the sample, plus the
        estimated sensor offset. For the sample before where the depth
        noise measured online exceeds 0.8 mm at 80 Hz or faster (at 40 to
        80 Hz, where the motion bends the depth less than the noise): the
        bank then steps on the depth's three-sample mean, one sample behind.
    changed : bool
        True on the sample at which the tracker decided the mud has changed.
    bias : float
        Estimated force-sensor offset [N] (tared while the foot is free, and not while mud may still cling to a
        raised foot).
    noise : float
        Estimated force-sensor noise, standard deviation [N].
    misfit : bool
        True while the model misses the force beyond its noise floor (the
        average squared residual of the last ``tau`` seconds of contact,
        in units of the likelihood's scale, above :data:`MISFIT_THRESHOLD`,
        in the first bank and in the twin bank both where one runs): the mud
        is off the model's family, or the sensors are corrupted beyond the
        allowances; the interval is then not to be trusted. A quiet flag does
        not show the mud in the family: off-family muds go unflagged on most
        robot paths at 50 Hz (docs/estimation.md, "MudTracker's flag").
    depth_offset, depth_offset_stderr : float
        Posterior mean of the surface offset [m] over the tracker's
        ``depth_offsets``, and its standard deviation with each hypothesis's
        cell (half-way to its neighbours; +-0.87 mm for the default 3-mm
        grid) added, and with the twin bank the difference of its reading
        from the twin's, in quadrature: the model follows the measured depth
        plus it (as ``identify``'s ``depth_offset``), so a depth that reads
        5 mm too deep gives about -0.005.
    force_lag, force_lag_stderr : float
        The force sensor's lag [s], the mean delay of a low-pass of the
        model's force (one first-order stage or two) or of a pure delay of
        it (5-40 ms), read from the lag hypotheses' evidence without their
        prior, and its standard deviation with each hypothesis's cell
        (0.7-4.3 ms) and, with the twin bank, the difference from the twin's
        reading added; beyond the lag allowance ``A`` also ``0.3 (lag - A)``,
        and where the sample interval ``dt`` exceeds 10 ms ``(dt - 10 ms) /
        sqrt(12)``, each in quadrature (docs/tracking.md, "The lag's spread
        holds a lag beyond the allowance"); before any contact, the
        hypotheses' mean (21 ms) and their whole spread (16.5 ms with the
        widening). The models' forces are low-passed by the
        bank's own lag, the same evidence (nine of the eleven hypotheses:
        not the two at 5 ms) under an exponential prior of mean 5 ms, whose
        spread over the hypotheses enters the likelihood's scale (and so the
        interval).
    """

    water_content: float
    low: float
    high: float
    force_predicted: float
    changed: bool
    bias: float
    noise: float
    misfit: bool = False
    depth_offset: float = 0.0
    depth_offset_stderr: float = 0.0
    force_lag: float = 0.0
    force_lag_stderr: float = 0.0

    @property
    def interval(self) -> tuple[float, float]:
        """Deprecated: ``(low, high)`` [-]; use :attr:`low` and :attr:`high`."""
        warn_renamed("TrackEstimate.interval", "TrackEstimate.low and TrackEstimate.high")
        return self.low, self.high


@dataclass(frozen=True)
class TrackEstimates:
    """Every foot's estimate after a sample (from :meth:`MudTrackers.update`); arrays of shape (n,), copies.

    Attributes
    ----------
    water_content, low, high : numpy.ndarray
        Posterior median and central 95 % interval of the water content [-].
    force_predicted : numpy.ndarray
        Predicted sensor reading [N] (see :class:`TrackEstimate`).
    changed : numpy.ndarray of bool
        Where the tracker decided the mud has changed at this sample.
    bias, noise : numpy.ndarray
        Estimated sensor offset [N] and noise standard deviation [N].
    misfit : numpy.ndarray of bool
        Where the model misses the force beyond its noise floor (see :class:`TrackEstimate`).
    depth_offset, depth_offset_stderr : numpy.ndarray
        Posterior mean and standard deviation (with its cell) of the surface offset [m] (see :class:`TrackEstimate`).
    force_lag, force_lag_stderr : numpy.ndarray
        Posterior mean and standard deviation (with its cell) of the force lag [s] (see :class:`TrackEstimate`).
    """

    water_content: np.ndarray
    low: np.ndarray
    high: np.ndarray
    force_predicted: np.ndarray
    changed: np.ndarray
    bias: np.ndarray
    noise: np.ndarray
    misfit: np.ndarray | None = None
    depth_offset: np.ndarray | None = None
    depth_offset_stderr: np.ndarray | None = None
    force_lag: np.ndarray | None = None
    force_lag_stderr: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class TrackerState:
    """A snapshot of a tracker's state, for save and restore (rollouts, replays).

    Read it from :attr:`MudTrackers.state` (or :attr:`MudTracker.state`) and
    assign it back to restore; it is a copy (read-only arrays), and it restores
    only into a tracker of the same feet, grid and options.
    """

    #: the bank's contact states, as :attr:`mudforce.MudContacts.state`
    bank: np.ndarray
    #: each foot's log-likelihood over the gains, surface offsets and grid, shape (n, gains * offsets * G)
    log_posterior: np.ndarray
    #: each foot's joint posterior over the surface offsets and grid, shape (n, offsets * G)
    posterior: np.ndarray
    #: each foot's offset, noise, contact time, change-flag and force-lag state, then per model the contact time at
    #: which it was last scored (the spared models', see the module docstring), its lagged force and its last force
    aux: np.ndarray
    #: False before the first sample
    started: bool
    #: the tracker configuration the snapshot belongs to
    key: bytes
    #: the twin bank's state (the default branch rule's second bank, see :data:`_TWIN_WINDOW`), else None
    twin: TrackerState | None = None

    def __post_init__(self) -> None:
        for name in ("bank", "log_posterior", "posterior", "aux"):
            arr = np.array(getattr(self, name), dtype=np.float64)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)


def _impossible_state(posterior: np.ndarray, aux: np.ndarray) -> str:
    """What in a restored state's (finite) posterior or per-foot state no update makes, worded; ``""`` if nothing.

    Restored states are checked as strictly as fresh ones: a posterior that is not a distribution, or a negative
    variance, time or count, was taken as it was (quantiles of negative probabilities: a silently wrong estimate).
    """
    sums = posterior.sum(axis=1)
    if not (np.all(posterior >= 0.0) and np.all(np.abs(sums - 1.0) <= 1e-9)):
        return "posterior is not probabilities summing to 1 for each foot"
    for column, name in ((L._A_NFREE, "free-sample count"), (L._A_VAR, "force noise variance"),
                         (L._A_RUN, "tare run time"), (L._A_RUN_QUIET, "tare run's quiet time"),
                         (L._A_RUN_SQ, "tare run's mean square"), (L._A_CONTACT, "contact time"),
                         (L._A_HOLD, "change-flag hold"), (L._A_JUMP, "hull's hold after a jump"),
                         (L._A_MISFIT, "misfit average"),
                         (L._A_MISFIT_T, "misfit time"), (L._A_DVAR, "depth noise variance"),
                         (L._A_D2VAR, "depth's second differences' mean square"),
                         (L._A_TARE_VAR0, "tare stretch's noise variance"),
                         (L._A_LAG_SD, "force lag spread"), (L._A_LAG_A, "force lag's first stage")):
        if np.any(aux[:, column] < 0.0):
            return f"{name} is negative"
    for column, name in ((L._A_STARTED, "started"), (L._A_QUICK, "branch rule"), (L._A_TARE_PREV, "tare")):
        if not np.all(np.isin(aux[:, column], (0.0, 1.0))):
            return f"{name} flag is not 0 or 1"
    if not np.all((aux[:, L._A_ZN] >= 0.0) & (aux[:, L._A_ZN] <= 3.0)):
        return "depth count is not within [0, 3]"
    longest = float(L._LAGS.max())
    if not np.all((aux[:, L._A_LAG] >= 0.0) & (aux[:, L._A_LAG] <= longest * (1.0 + 1e-9))):  # a mean of the lags
        return f"force lag is not within [0, {longest:g}] s"
    anchor = aux[:, L._A_ANCHOR]
    set_ = ~np.isnan(anchor)
    if not np.all((aux[set_, L._A_ANCHOR_LOW] <= anchor[set_]) & (anchor[set_] <= aux[set_, L._A_ANCHOR_HIGH])):
        return "change-flag anchor lies outside its interval"
    hull_low, hull_high = aux[:, L._A_HULL_LOW], aux[:, L._A_HULL_HIGH]
    if not np.array_equal(np.isnan(hull_low), np.isnan(hull_high)) or np.any(hull_low > hull_high):
        return "reported interval's hull has its ends crossed or one of them missing"
    return ""


def _non_negative(value: Any, name: str, unit: str) -> float:
    """``value`` as a finite float >= 0, else a one-line InputError."""
    x = real_number(value, f"{name} [{unit}]")
    if not (x >= 0.0 and math.isfinite(x)):
        raise InputError(f"{name} must be finite and >= 0 [{unit}], got {value!r}")
    return x


def _at_most(value: float, name: str, bound: float, unit: str) -> float:
    """``value`` if it is at most ``bound`` [``unit``], else a one-line InputError: the likelihood's scales
    (their squares) overflowed beyond ~1e154, and every later estimate was NaN."""
    if not value <= bound:
        raise InputError(f"{name} must be at most {bound:g} [{unit}], got {value!r}")
    return value


def _offsets(depth_offsets: Sequence[float] | None) -> np.ndarray:
    """The surface offset hypotheses [m], as an array; refused in one line unless finite, increasing, within 20 mm."""
    if depth_offsets is None:
        return np.array(DEFAULT_DEPTH_OFFSETS, dtype=np.float64)
    d = np.array(real_array(depth_offsets, "depth_offsets", "m"), dtype=np.float64)
    if d.ndim != 1 or d.size < 1 or not np.all(np.isfinite(d)) or np.any(np.diff(d) <= 0.0) \
            or np.any(np.abs(d) > 0.02):
        # one line, of a few values: the repr of a 2-D or long array spans lines
        got = f"shape {d.shape}" if d.ndim != 1 or d.size < 1 else \
            np.array2string(d, separator=", ", threshold=8, edgeitems=3, max_line_width=1 << 30)
        raise InputError(f"depth_offsets must list at least one surface offset [m], finite, strictly increasing and "
                         f"within 20 mm (e.g. (-0.003, 0.0, 0.003)), got {got}")
    return np.ascontiguousarray(d)


def _grid(water_contents: Sequence[float] | None) -> np.ndarray:
    if water_contents is None:
        return np.array(DEFAULT_GRID, dtype=np.float64)
    grid = np.array(real_array(water_contents, "water_contents", "-"))
    lo, hi = WATER_CONTENT_RANGE
    if grid.ndim != 1 or grid.size < 2:
        raise InputError(f"water_contents must list at least 2 water contents [-], got shape {grid.shape}")
    if not np.all(np.isfinite(grid)) or np.any(np.diff(grid) <= 0.0):
        raise InputError("water_contents must be finite and strictly increasing [-]")
    if grid[0] < lo - 1e-12 or grid[-1] > hi + 1e-12:
        raise InputError(f"water_contents must lie within Table I's [{lo:g}, {hi:g}], got "
                         f"{grid[0]:g} .. {grid[-1]:g}")
    return grid


class MudTrackers:
    """Track the mud's water content under ``n`` feet at once, one sample at a time (see the module docstring).

    Parameters
    ----------
    n : int
        Number of feet, >= 1; each has its own posterior, offset and noise.
    foot : Foot, optional
        The foot geometry (shared); the paper's 51 x 38 mm cuboid by default.
    water_contents : sequence of float, optional
        The grid of water contents [-], increasing, within Table I's
        range; :data:`DEFAULT_GRID` (15-35 % by 0.5 points) by default. The
        estimate cannot resolve finer than about one grid step.
    tau : float
        Forgetting time constant [s of contact], > 0 (default 3 s: the
        estimate follows new mud within a few steps).
    misfit : float
        Relative model misfit [-] added to the likelihood's scale, in (0, 1000] (default 0.05).
    floor : float
        Floor on the likelihood's scale [N], in (0, 1e7] (default 0.2 N).
    dof : float
        Degrees of freedom of the Student-t likelihood [-] (default 2).
    correlation_time : float
        Time over which the model's misfit stays correlated [s] (default
        0.05 s): each sample's log-likelihood is weighted by
        ``min(1, dt / correlation_time)`` (1/5 at 100 Hz), so the evidence
        per second does not grow with the sampling rate.
    noise : float
        Prior force-noise standard deviation [N], in (0, 1e7], until the foot has been
        free (default 0.5 N).
    bias : float
        Prior spread of the force offset [N], in (0, 1e7], until the foot has been free
        (default 2 N).
    velocity_filter : VelocityFilter or "exact", optional
        The bank's branch rule; by default the noise-robust rule of
        :func:`default_velocity_filter` (30 um depth noise at 100 Hz) with a
        quick rule where a clean foot 10-40 mm deep moves, and a twin bank
        (``twin``). A rule given is kept as given, with no twin.
    twin : bool
        With the default branch rule, also run a twin bank on the quick rule
        (a 2-step secant, 2.5 mm/s deadband; the surface offsets within 3 mm of zero) and report the union of the
        two banks' intervals (default True; docs/tracking.md, "A twin bank").
        It costs about 60 % more an update (one foot about 26 us, against
        16 us without); without it, on the sensor-chain bench's seeds 17-20,
        the interval missed the truth unflagged on 2411 samples, against 259.
        False only for a control loop that cannot afford it. The estimate and
        the misfit flag are the same either way; the change flag reads the
        reported interval, so without the twin it may come sooner, on the
        first bank's word alone (and falsely more often).
    level : float
        Probability of the credible interval [-], in (0, 1) (default 0.95).
    discrepancy : float
        Standard deviation [-] of the model's systematic error in water
        content (default 0.0075, three quarters of a point): the fit's posterior is
        blurred by it before the estimate and interval are read (0: none); at most 1.
    force_gain_uncertainty : float
        Relative uncertainty of the force sensor's gain [-], >= 0 (default
        :data:`~mudforce.estimation.nuisances.DEFAULT_FORCE_GAIN_UNCERTAINTY`,
        5 %, as ``identify``'s): every model is also weighed with its force
        times ``1 - g`` and ``1 + g``, and the posterior of the water content
        is summed over the three. A gain error cannot be told from stiffer
        mud, so the interval widens by the shift it causes (0: one gain).
    force_lag : float
        Force lag allowance [s], within [0, 1000] (default :data:`DEFAULT_FORCE_LAG_ALLOWANCE`,
        10 ms): the predicted force's change over this time is added to the
        likelihood's scale, so a low-passed or delayed force sensor is not
        read as other mud (0: none).
    depth_offsets : sequence of float, optional
        Surface offset hypotheses [m], increasing, within 20 mm
        (:data:`DEFAULT_DEPTH_OFFSETS`: -6, -3, 0, +3, +6 mm by default): the
        bank holds every grid model once per offset, stepped on the measured
        depth plus it, and the water content's posterior sums over them
        (each offset's evidence tempered), so an unknown surface height widens
        the interval instead of biasing it; the estimate reports the offset's
        posterior mean and spread. ``[0.0]``: the depth is taken as exact.
    depth_offset_prior : float
        Prior standard deviation of the surface offset [m], > 0 (default
        :data:`DEFAULT_DEPTH_OFFSET_PRIOR`, 4 mm), and at least a 38th of the
        offset nearest 0 (beyond, every offset's prior is 0 in float64).
    max_step : float
        The bank's longest step [s], >= 0 (default :data:`DEFAULT_MAX_STEP`,
        10 ms): a sample interval ``dt`` is cut into ``round(dt / max_step)``
        equal substeps (at least one, at most 64), the depth interpolated linearly between
        the two samples, so that at a low rate the models are not stepped
        coarser than the branch rule and the data allow (0: one step per
        sample). The branch rule (``velocity_filter``) is applied at the
        substeps.

    Notes
    -----
    One update steps ``n * len(depth_offsets) * len(water_contents)`` models in compiled code and
    scores those of the most probable offset and the others that hold at least 1e-12 of the
    posterior; the rest are spared, scored in turn once per two ``correlation_time`` (see the
    module docstring).
    """

    def __init__(
        self,
        n: int,
        foot: Foot | None = None,
        *,
        water_contents: Sequence[float] | None = None,
        tau: float = 3.0,
        misfit: float = 0.05,
        floor: float = 0.2,
        dof: float = 2.0,
        correlation_time: float = 0.05,
        noise: float = 0.5,
        bias: float = 2.0,
        velocity_filter: VelocityFilter | str | None = None,
        twin: bool = True,
        level: float = 0.95,
        discrepancy: float = 0.0075,
        force_gain_uncertainty: float = DEFAULT_FORCE_GAIN_UNCERTAINTY,
        force_lag: float = DEFAULT_FORCE_LAG_ALLOWANCE,
        depth_offsets: Sequence[float] | None = None,
        depth_offset_prior: float = DEFAULT_DEPTH_OFFSET_PRIOR,
        max_step: float = DEFAULT_MAX_STEP,
    ) -> None:
        self.n = feet_count(n)
        if foot is not None and not isinstance(foot, Foot):
            raise InputError(f"foot must be a Foot or None, got {type(foot).__name__}")
        self.foot = Foot.paper() if foot is None else foot
        self.grid = _grid(water_contents)
        level = positive_number(level, "level", "-")
        if not level < 1.0:
            raise InputError(f"level must be within (0, 1), got {level!r}")
        self.level = level
        twin = true_or_false(twin, "twin")
        self.velocity_filter = (default_velocity_filter() if velocity_filter is None
                                else resolve_velocity_filter(velocity_filter))
        cfg = np.empty(L._N_CFG, dtype=np.float64)
        # the default rule follows each foot's depth noise measured online (quick while it is low, see
        # _QUICK_WINDOW); a rule given is kept as given
        cfg[L._C_QUICK] = 1.0 if velocity_filter is None else 0.0
        cfg[L._C_ROBUST_WINDOW] = float(self.velocity_filter.window)
        cfg[L._C_ROBUST_DEADBAND] = float(self.velocity_filter.deadband)
        cfg[L._C_QUICK_ON] = L._QUICK_ON
        cfg[L._C_QUICK_OFF] = L._QUICK_OFF
        cfg[L._C_QUICK_SINK] = L._QUICK_SINK
        cfg[L._C_QUICK_SINK_MAX] = L._QUICK_SINK_MAX
        cfg[L._C_TAU] = positive_number(tau, "tau", "s")
        cfg[L._C_MISFIT] = _at_most(positive_number(misfit, "misfit", "-"), "misfit", L._MAX_MISFIT, "-")
        cfg[L._C_FLOOR] = _at_most(positive_number(floor, "floor", "N"), "floor", MAX_FORCE, "N")
        cfg[L._C_DOF] = positive_number(dof, "dof", "-")
        cfg[L._C_TEMP] = positive_number(correlation_time, "correlation_time", "s")
        cfg[L._C_NOISE0] = _at_most(positive_number(noise, "noise", "N"), "noise", MAX_FORCE, "N")
        cfg[L._C_BIAS0] = _at_most(positive_number(bias, "bias", "N"), "bias", MAX_FORCE, "N")
        cfg[L._C_FREE_MEMORY] = 500.0  # samples: the offset and noise follow slow drift over ~5 s of swing at 100 Hz
        step = float(np.max(np.diff(self.grid)))
        cfg[L._C_SETTLE] = max(0.04, 6.0 * step)  # [-] interval width under which an estimate counts as settled
        cfg[L._C_MARGIN] = max(0.01, 2.0 * step)  # [-] how far a settled interval must leave the anchor
        cfg[L._C_LEVEL] = level
        cfg[L._C_GAIN] = _non_negative(force_gain_uncertainty, "force_gain_uncertainty", "-")
        if not cfg[L._C_GAIN] < 0.5:
            raise InputError(f"force_gain_uncertainty must be within [0, 0.5) [-] (0.05 is 5 %), "
                             f"got {force_gain_uncertainty!r}")
        cfg[L._C_LAG] = _at_most(_non_negative(force_lag, "force_lag", "s"), "force_lag", L._MAX_FORCE_LAG, "s")
        cfg[L._C_REST] = REST_SPEED
        cfg[L._C_MISFIT_RATIO] = MISFIT_THRESHOLD
        cfg[L._C_DISC] = L._MISFIT_DISCRETISATION
        cfg[L._C_BLUR_REF] = L._MISFIT_BLUR_REF
        cfg[L._C_TEMPER] = L._MISFIT_TEMPER_REF
        cfg[L._C_OFFSET_TEMPER] = L._OFFSET_TEMPER
        cfg[L._C_SUBSTEP] = _non_negative(max_step, "max_step", "s")
        cfg[L._C_HULL] = L._HULL_MEMORY
        cfg[L._C_LEAD] = L._MAX_LEAD
        cfg[L._C_SMOOTH] = L._SMOOTH_NOISE
        cfg[L._C_REST_SPREAD] = L._REST_SPREAD
        self._cfg = cfg
        self.depth_offsets = _offsets(depth_offsets)
        # the largest |depth| taken [m]: the bank's models follow the depth plus each offset, within MAX_DEPTH
        self._max_depth = MAX_DEPTH - float(np.max(np.abs(self.depth_offsets)))
        cfg[L._C_MAX_DEPTH] = self._max_depth
        cfg[L._C_SHALLOW] = L._SHALLOW_WIDENING
        cfg[L._C_SHALLOW_GAIN] = L._SHALLOW_GAIN
        cfg[L._C_RATE_GAIN] = L._RATE_WIDENING
        cfg[L._C_OFFSET_RES] = 0.5 * float(np.max(np.diff(self.depth_offsets))) if self.depth_offsets.size > 1 else 0.0
        prior = positive_number(depth_offset_prior, "depth_offset_prior", "m")
        with np.errstate(over="ignore"):  # an offset beyond 1e154 priors out: -inf, a prior probability of 0
            self._log_prior = np.ascontiguousarray(-0.5 * (self.depth_offsets / prior) ** 2)
        if not np.exp(self._log_prior).max() > 0.0:  # reset()'s prior would be 0/0: a NaN posterior for good
            near = float(np.min(np.abs(self.depth_offsets)))
            raise InputError(f"depth_offset_prior {prior:g} m leaves every one of depth_offsets a prior probability "
                             f"of 0 (the nearest to 0, {near:g} m, lies {near / prior:.3g} standard deviations out); "
                             f"expected depth_offset_prior >= {near / 38.0:.3g} m or an offset nearer 0")
        self.depth_offset_prior = prior
        G = self.grid.size
        M = self.depth_offsets.size * G  # models per foot
        mids = 0.5 * (self.grid[1:] + self.grid[:-1])
        self._edges = np.concatenate(([self.grid[0] - (mids[0] - self.grid[0])], mids,
                                      [self.grid[-1] + (self.grid[-1] - mids[-1])]))
        if isinstance(discrepancy, (int, float)) and not isinstance(discrepancy, bool) and discrepancy == 0.0:
            self.discrepancy = 0.0
        else:
            # at most 1 (100 points of water content): far wider, the blurs' cells lost their mass to rounding (0/0)
            self.discrepancy = _at_most(positive_number(discrepancy, "discrepancy", "-"), "discrepancy", 1.0, "-")
        # transposed: _blurred_quantiles reads them column by column
        # (one per factor of _BLUR_FACTORS, then the widened ones' piled twins: _blur_matrix's pile)
        self._blur = np.ascontiguousarray(np.stack(
            [_blur_matrix(self.grid, self._edges, self.discrepancy * float(k)).T for k in L._BLUR_FACTORS]
            + [_blur_matrix(self.grid, self._edges, self.discrepancy * float(k), pile=True).T
               for k in L._BLUR_FACTORS[1:]]))
        self._Q = np.zeros(G, dtype=np.float64)
        # scratch of the compiled step: the water content's and the offsets' posteriors, the lag filters' coefficients
        self._work = np.zeros(G + self.depth_offsets.size + 1 + 4 * L._N_LAGS, dtype=np.float64)
        self._scored = np.zeros(M, dtype=np.float64)  # the models scored on this sample, scratch of the compiled step
        mud = [MudParameters.from_water_content(float(w)) for w in self.grid]
        from mudforce.steppers.many import MudContacts

        rows = self.n * self.depth_offsets.size
        self._bank = MudContacts(mud * rows, rows * G, self.foot, velocity_filter=self.velocity_filter, threads=1)
        self._zbuf = np.zeros(rows * G, dtype=np.float64)
        self._L = np.zeros((self.n, (3 if cfg[L._C_GAIN] > 0.0 else 1) * M), dtype=np.float64)
        self._P = np.zeros((self.n, M), dtype=np.float64)
        self._aux = np.zeros((self.n, L._N_AUX + 4 * M), dtype=np.float64)
        self._out = np.zeros((self.n, L._N_OUT), dtype=np.float64)
        self._depths = np.zeros(self.n, dtype=np.float64)
        self._forces = np.zeros(self.n, dtype=np.float64)
        # the twin bank's readings this bank's step takes (its columns L._G_LOW ... L._G_OFFSET; NaN: no twin), an input
        # of the compiled step, written before each step
        self._guard = np.full((self.n, L._N_GUARD), math.nan, dtype=np.float64)
        bank = self._bank
        buf, layout = _pack(self)  # the arrays above become views of one buffer
        # the compiled step's arrays after dt, in its order (all updated in place, never rebound)
        self._args = (bank._states, bank.ring, bank.params_array, bank.forces, bank._scratch[0], bank._index[0], buf,
                      layout)
        # the default rule's twin: the same models on the quick rule, whose interval the reported one also holds
        self._twin: MudTrackers | None = None
        if velocity_filter is None and twin:
            near = self.depth_offsets[np.abs(self.depth_offsets) <= L._TWIN_OFFSET_SPAN + 1e-12]
            self._twin = MudTrackers(
                n, self.foot, water_contents=self.grid.tolist(), tau=tau, misfit=misfit, floor=floor, dof=dof,
                correlation_time=correlation_time, noise=noise, bias=bias,
                velocity_filter=VelocityFilter(L._TWIN_WINDOW, L._TWIN_DEADBAND), level=level, discrepancy=discrepancy,
                force_gain_uncertainty=force_gain_uncertainty, force_lag=force_lag,
                depth_offsets=(near if near.size else self.depth_offsets).tolist(),
                depth_offset_prior=depth_offset_prior, max_step=max_step)
            # the twin's interval is a guard of this bank's, not reported: it keeps no hull (_HULL_MEMORY); and it takes
            # the depths this bank takes, no more (its offsets span less: a depth it took, refused here, moved it)
            self._twin._cfg[L._C_HULL] = 0.0
            self._twin._max_depth = self._twin._cfg[L._C_MAX_DEPTH] = self._max_depth
            self._twin._state_key = self._twin._own_key()
        # what a snapshot must have been taken from (fixed once made, so built once here: about 0.4 MB with the twin,
        # 37 us a snapshot when built at each)
        key = self._own_key()
        self._state_key: bytes = key if self._twin is None else key + b"twin" + self._twin._state_key
        self.reset()

    def _own_key(self) -> bytes:
        """This bank's part of a snapshot's key: the grid, the options, the blurs, the offsets and their prior, the
        bank's rows as made (the branch rule's columns change later, as it follows the noise), and the force lag's
        hypotheses (what the state's lag columns mean: a state of a mudforce with other hypotheses is refused)."""
        return b"".join((self.grid.tobytes(), self._cfg.tobytes(), self._blur.tobytes(), self.depth_offsets.tobytes(),
                         self._log_prior.tobytes(), self._bank.params_array.tobytes(), L._LAGS_A.tobytes(),
                         L._LAGS_B.tobytes()))

    def reset(self) -> None:
        """Forget everything: the next update is a first sample, the posterior uniform."""
        self._bank.reset()
        self._L[:] = 0.0
        prior = np.exp(self._log_prior)
        self._P[:] = np.repeat(prior / (prior.sum() * self.grid.size), self.grid.size)
        self._aux[:] = 0.0
        self._aux[:, L._A_VAR] = self._cfg[L._C_NOISE0] ** 2
        self._aux[:, L._A_DVAR] = L._DEPTH_NOISE0**2
        self._aux[:, L._A_D2VAR] = L._DEPTH_NOISE0**2
        self._aux[:, L._A_ANCHOR] = np.nan
        self._aux[:, L._A_HULL_LOW] = np.nan
        self._aux[:, L._A_HULL_HIGH] = np.nan
        self._started = False
        if self._twin is not None:
            self._twin.reset()

    def _step(self, dt: float) -> None:
        if not self._started:
            dt = 1.0  # the first sample's dt is ignored
        elif not (MIN_DT <= dt <= MAX_TIME):  # (a long gap, a clock jump, is taken: at most 64 substeps)
            raise InputError(f"dt must be within [{MIN_DT:g}, {MAX_TIME:g}] s after the first sample, got {dt!r}")
        twin = self._twin
        if twin is not None:  # the twin first: the reported interval, and so the change flag, holds its interval
            bad = _track_pair(dt, *twin._args, *self._args)
            if bad < 0:
                twin._started = True
        else:
            bad = _track_step(dt, *self._args)
        if bad >= 0:  # the first foot refused (the feet before it passed): beyond the bounds, or not finite
            _check_bounds(self._depths, self._forces, self._max_depth)
            raise InputError(f"depth and force of foot {bad} must be finite [m, N], got "
                             f"{float(self._depths[bad])!r} and {float(self._forces[bad])!r}")
        self._started = True

    def update(self, depths: Any, forces: Any, dt: float) -> TrackEstimates:
        """Take one sample of every foot; return every foot's estimate.

        Parameters
        ----------
        depths : array_like, shape (n,)
            Foot depths below the undisturbed surface [m], positive down, within +-100 m (less the
            largest surface offset).
        forces : array_like, shape (n,)
            Measured vertical forces [N], positive up (with any sensor offset), within +-1e7 N.
        dt : float
            Time since the previous sample [s], within [1e-9, 1e9]; ignored on the first call.

        Returns
        -------
        TrackEstimates
        """
        z = real_array(depths, "depths", "m")
        f = real_array(forces, "forces", "N")
        if z.shape != (self.n,) or f.shape != (self.n,):
            raise InputError(f"depths and forces must have shape ({self.n},), got {z.shape} and {f.shape}")
        self._depths[:] = z
        self._forces[:] = f
        self._step(real_number(dt, "dt [s]"))
        o = self._out
        return TrackEstimates(o[:, L._O_W].copy(), o[:, L._O_LOW].copy(), o[:, L._O_HIGH].copy(),
                              o[:, L._O_PRED].copy(),
                              o[:, L._O_CHANGED] != 0.0, o[:, L._O_BIAS].copy(), o[:, L._O_NOISE].copy(),
                              o[:, L._O_MISFIT] != 0.0, o[:, L._O_OFFSET].copy(), o[:, L._O_OFFSET_SD].copy(),
                              o[:, L._O_LAG].copy(), o[:, L._O_LAG_SD].copy())


    @property
    def state(self) -> TrackerState:
        """A snapshot of every foot's state (a copy); assign one back to restore it.

        A refused restore (not a :class:`TrackerState`, one of another
        tracker's configuration, or a state the tracker never makes) leaves
        the tracker exactly as it was.
        """
        return TrackerState(self._bank.state, self._L, self._P, self._aux, self._started, self._state_key,
                            None if self._twin is None else self._twin.state)

    @state.setter
    def state(self, value: TrackerState) -> None:
        if not isinstance(value, TrackerState):
            raise InputError(f"state must be a TrackerState (from a tracker's .state), got {type(value).__name__}")
        if value.key != self._state_key or value.log_posterior.shape != self._L.shape or \
                value.aux.shape != self._aux.shape or value.posterior.shape != self._P.shape:
            raise InputError("this TrackerState was taken from a tracker of other feet, grid or options (or of "
                             "another mudforce version); expected one from a tracker made with the same arguments")
        if not (np.isfinite(value.posterior).all() and np.isfinite(value.log_posterior).all()
                and np.isfinite(np.delete(value.aux, [L._A_ANCHOR, L._A_HULL_LOW, L._A_HULL_HIGH], axis=1)).all()
                and not np.isinf(value.aux[:, [L._A_ANCHOR, L._A_HULL_LOW, L._A_HULL_HIGH]]).any()):
            raise InputError("a TrackerState holds non-finite values; expected one taken from a tracker")
        problem = _impossible_state(value.posterior, value.aux)
        if problem:
            raise InputError(f"a TrackerState's {problem}; expected one taken from a tracker")
        twin, saved = self._twin, value.twin
        if (twin is None) != (saved is None):
            raise InputError("this TrackerState was taken from a tracker of other feet, grid or options (or of "
                             "another mudforce version); expected one from a tracker made with the same arguments")
        if twin is not None and saved is not None:
            before = twin.state
            twin.state = saved  # validated there before anything changes (else it raises here)
            try:
                self._bank.state = value.bank
            except InputError:
                twin.state = before  # a refused restore leaves the tracker as it was
                raise
        else:
            self._bank.state = value.bank  # validated there before anything changes (else it raises here)
        bank = self._bank
        _restore_step_cache(bank._states, bank.params_array, np.ascontiguousarray(value.bank[:, S_CACHE_DT]))
        self._L[:] = value.log_posterior
        self._P[:] = value.posterior
        self._aux[:] = value.aux
        self._started = bool(value.started)

    @property
    def posterior(self) -> np.ndarray:
        """Each foot's posterior probability of each grid water content, shape (n, G) (a copy).

        The surface offsets summed over: :attr:`TrackerState.posterior` holds the joint one.
        """
        p: np.ndarray = self._P.reshape(self.n, self.depth_offsets.size, self.grid.size).sum(axis=1)
        return p

    def __len__(self) -> int:
        return self.n

    def __repr__(self) -> str:
        return f"MudTrackers(n={self.n}, grid={self.grid[0]:g}..{self.grid[-1]:g} ({self.grid.size}))"


_MISSING: Any = object()  # an argument not given (MudTracker.update's defaults)
_ESTIMATE_FIELDS = tuple(f.name for f in fields(TrackEstimate))  # the columns of MudTrackers._out, in order
_new_object = object.__new__


def _old_update_keywords(depth: Any, force: Any, dt: Any, given: dict[str, Any]) -> tuple[Any, Any, Any]:
    """``MudTracker.update``'s arguments from its deprecated keywords ``depth_m``, ``force_N``, ``dt_s`` (warns)."""
    names = {"depth_m": "depth", "force_N": "force", "dt_s": "dt"}
    unknown = sorted(set(given) - set(names))
    if unknown:
        raise InputError(f"MudTracker.update got an unexpected keyword {unknown[0]!r}; expected depth, force, dt")
    values = {"depth": depth, "force": force, "dt": dt}
    for old, value in given.items():
        if values[names[old]] is not _MISSING:
            raise InputError(f"MudTracker.update: give {names[old]}= only ({old}= is its deprecated name)")
        values[names[old]] = value
    warn_renamed("MudTracker.update(" + "=, ".join(given) + "=)", "update(depth=, force=, dt=)", stacklevel=4)
    return values["depth"], values["force"], values["dt"]


def _one_foot(foot: Foot | None, options: dict[str, Any]) -> MudTrackers:
    """``MudTrackers(1, foot, **options)``, an unknown option refused in one line (not ``__init__``'s TypeError)."""
    names = list(inspect.signature(MudTrackers.__init__).parameters)[3:]  # after self, n and foot: the options
    unknown = sorted(set(options) - set(names))
    if unknown:
        raise InputError(f"unknown tracker option(s) {', '.join(unknown)}; expected some of {', '.join(names)}")
    return MudTrackers(1, foot, **options)


class MudTracker:
    """Track the mud's water content under one foot, one sample at a time.

    ``MudTracker(foot, **options)`` is :class:`MudTrackers` for one foot with
    a scalar interface; the options are the same.

    Examples
    --------
    >>> from mudforce import MudTracker
    >>> from mudforce.motions.gait import walk
    >>> w = walk(0.25, seed=3, duration=15.0, force_noise=0.2, bias=0.5)
    >>> tracker = MudTracker()
    >>> previous = w.time[0]
    >>> for t, z, f in zip(w.time, w.depth, w.force):
    ...     estimate = tracker.update(z, f, t - previous)
    ...     previous = t
    >>> bool(estimate.low <= 0.25 <= estimate.high)
    True
    """

    def __init__(self, foot: Foot | None = None, **options: Any) -> None:
        self._bank = _one_foot(foot, options)
        self.grid = self._bank.grid

    def update(self, depth: float = _MISSING, force: float = _MISSING, dt: float = _MISSING,
               **deprecated: float) -> TrackEstimate:
        """Take one sample; return the estimate.

        Parameters
        ----------
        depth : float
            Foot depth below the undisturbed surface [m], positive down, within +-100 m (less the
            largest surface offset).
        force : float
            Measured vertical force [N], positive up (with any sensor offset), within +-1e7 N.
        dt : float
            Time since the previous sample [s], within [1e-9, 1e9]; ignored on the first call.
            (``depth_m``, ``force_N``, ``dt_s``: deprecated names of the three.)

        Returns
        -------
        TrackEstimate
        """
        b = self._bank
        if deprecated:  # the old keywords, kept for one release (a decorator would cost every update a call)
            depth, force, dt = _old_update_keywords(depth, force, dt, deprecated)
        # real numbers only: numpy would parse a string, drop an imaginary part, take a bool as 0 or 1
        if type(depth) is not float or type(force) is not float or type(dt) is not float:
            for name, value in (("depth", depth), ("force", force), ("dt", dt)):
                if value is _MISSING:
                    raise InputError(f"MudTracker.update: {name} is missing; expected update(depth [m], force [N], "
                                     "dt [s])")
            depth, force = real_number(depth, "depth [m]"), real_number(force, "force [N]")
            dt = real_number(dt, "dt [s]")
        b._depths[0] = depth
        b._forces[0] = force
        b._step(dt)
        # the columns _O_W .. _O_LAG_SD are TrackEstimate's fields in order (a test pins it); built without the
        # frozen dataclass's __init__ (ten object.__setattr__ calls, about a microsecond of the update)
        o = b._out[0].tolist()
        o[L._O_CHANGED] = o[L._O_CHANGED] != 0.0
        o[L._O_MISFIT] = o[L._O_MISFIT] != 0.0
        e = _new_object(TrackEstimate)
        e.__dict__.update(zip(_ESTIMATE_FIELDS, o, strict=True))
        return e

    def reset(self) -> None:
        """Forget everything: the next update is a first sample."""
        self._bank.reset()

    @property
    def state(self) -> TrackerState:
        """A snapshot of the tracker's state (a copy); assign one back to restore it (see :attr:`MudTrackers.state`)."""
        return self._bank.state

    @state.setter
    def state(self, value: TrackerState) -> None:
        self._bank.state = value

    @property
    def posterior(self) -> np.ndarray:
        """The posterior probability of each grid water content, shape (G,) (a copy)."""
        p: np.ndarray = self._bank.posterior[0]
        return p

    def __repr__(self) -> str:
        g = self.grid
        return f"MudTracker(grid={g[0]:g}..{g[-1]:g} ({g.size}))"


@dataclass(frozen=True)
class TrackResult:
    """A whole recording tracked by :func:`track`; arrays of shape (samples,).

    Attributes
    ----------
    time, depth, force : numpy.ndarray
        The input [s], [m], [N] (copies).
    water_content, low, high : numpy.ndarray
        Estimate and 95 % interval [-] after each sample.
    force_predicted : numpy.ndarray
        Predicted sensor reading [N].
    changed : numpy.ndarray of bool
        Samples where a change of mud was flagged.
    bias, noise : numpy.ndarray
        Estimated offset and noise [N].
    misfit : numpy.ndarray of bool
        Samples where the model missed the force beyond its noise floor (see :class:`TrackEstimate`).
    depth_offset, depth_offset_stderr : numpy.ndarray
        Posterior mean and standard deviation (with its cell) of the surface offset [m] (see :class:`TrackEstimate`).
    force_lag, force_lag_stderr : numpy.ndarray
        Posterior mean and standard deviation (with its cell) of the force lag [s] (see :class:`TrackEstimate`).
    water_content_range : tuple of float
        The tracker's grid's first and last water content [-] (:data:`DEFAULT_GRID`'s, 0.15 and 0.35, unless
        ``water_contents`` was given): the family's ends that :attr:`family_edge` reads.
    family_misfit : numpy.ndarray of bool or None
        With ``track(..., family_window=...)``: True from each sample where the family check
        (:class:`~mudforce.estimation.family_check.FamilyCheck`: identify's misfit flag on the last
        ``family_window`` seconds) found the mud off the family, until a later check that found it in; a check
        that told nothing (the foot out of the mud) leaves it as it was. None where the check did not run.
    family_checks : tuple of (int, FamilyVerdict)
        Each check's sample index and verdict, in order (empty where the check did not run).
    model_misses_data : bool
        (Property.) True when the misfit flag or the family check's was raised on any sample of the recording
        (``misfit.any()``, ``family_misfit.any()``; the name of
        :attr:`~mudforce.estimation.calibration.Identification.model_misses_data`): the mud may not be in the
        Table I family, or the sensor chain is off (a force of noise alone, a depth in mm read as m). A final
        estimate with its flag down can follow a recording flagged nearly throughout. The tracker's own flag is
        quiet on in-family mud but is not a test of the family (docs/estimation.md); the family check is.
    family_edge : str
        (Property.) ``"wet"`` when the final interval reaches the family's wet end (``high[-1] >=
        water_content_range[1]``: the mud may be wetter than the family holds), ``"dry"`` when it reaches its dry
        end (``low[-1] <= water_content_range[0]``: it may be drier), ``"both"`` when it spans the whole family (the
        recording told little), ``""`` otherwise.
    """

    time: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    water_content: np.ndarray
    low: np.ndarray
    high: np.ndarray
    force_predicted: np.ndarray
    changed: np.ndarray
    bias: np.ndarray
    noise: np.ndarray
    misfit: np.ndarray | None = None
    depth_offset: np.ndarray | None = None
    depth_offset_stderr: np.ndarray | None = None
    force_lag: np.ndarray | None = None
    force_lag_stderr: np.ndarray | None = None
    water_content_range: tuple[float, float] = (DEFAULT_GRID[0], DEFAULT_GRID[-1])
    family_misfit: np.ndarray | None = None
    family_checks: tuple[tuple[int, FamilyVerdict], ...] = ()

    #: The columns of :meth:`to_csv` (and of ``mudforce track --out``), in order; ``family_misfit`` follows them
    #: where the family check ran.
    COLUMNS: ClassVar[tuple[str, ...]] = ("time_s", "water_content", "water_content_low", "water_content_high",
                                          "force_predicted_N", "force_N", "changed", "misfit", "depth_offset_m",
                                          "depth_offset_stderr_m", "force_lag_s", "force_lag_stderr_s",
                                          "force_bias_N")

    def _misfit(self) -> np.ndarray:
        return np.zeros(self.time.shape, dtype=bool) if self.misfit is None else self.misfit

    @property
    def model_misses_data(self) -> bool:
        """True when the misfit flag or the family check's was raised on any sample (see the class's attributes)."""
        return bool(np.any(self._misfit())) or bool(self.family_misfit is not None and np.any(self.family_misfit))

    @property
    def family_edge(self) -> str:
        """``"wet"``, ``"dry"`` or ``"both"`` when the final interval reaches that end of the family (or both), else
        ``""`` (see the class's attributes)."""
        wet = bool(self.high.size and self.high[-1] >= self.water_content_range[1])
        dry = bool(self.low.size and self.low[-1] <= self.water_content_range[0])
        return "both" if wet and dry else "wet" if wet else "dry" if dry else ""

    def _nuisances(self) -> tuple[np.ndarray, ...]:
        """The surface offset, its spread, the force lag, its spread and the force bias per sample (NaN where not
        given)."""
        none = np.full(self.time.shape, np.nan)
        return tuple(none if x is None else np.asarray(x, dtype=np.float64) for x in (
            self.depth_offset, self.depth_offset_stderr, self.force_lag, self.force_lag_stderr, self.bias))

    def columns(self) -> dict[str, np.ndarray]:
        """The per-sample data under the names of :attr:`COLUMNS` (``changed``, ``misfit`` as bool), and
        ``family_misfit`` (bool) where the family check ran."""
        arrays = (self.time, self.water_content, self.low, self.high, self.force_predicted, self.force, self.changed,
                  self._misfit(), *self._nuisances())
        out = dict(zip(self.COLUMNS, arrays, strict=True))
        if self.family_misfit is not None:
            out["family_misfit"] = self.family_misfit
        return out

    def to_pandas(self) -> Any:
        """A :class:`pandas.DataFrame` with the columns of :meth:`to_csv` (needs pandas)."""
        from mudforce.io.results import to_pandas

        return to_pandas(self.columns())

    def _csv_text(self) -> str:
        family = self.family_misfit
        lines = [",".join(self.COLUMNS + (("family_misfit",) if family is not None else ()))]
        nuisances = [x.tolist() for x in self._nuisances()]
        for row in zip(self.time.tolist(), self.water_content.tolist(), self.low.tolist(), self.high.tolist(),
                       self.force_predicted.tolist(), self.force.tolist(), self.changed.tolist(),
                       self._misfit().tolist(), *nuisances, strict=True):
            values, (changed, misfit), after = row[:6], row[6:8], row[8:]
            lines.append(",".join(repr(float(v)) for v in values) + f",{int(changed)},{int(misfit)},"
                         + ",".join(repr(float(v)) for v in after))
        if family is not None:
            lines[1:] = [f"{line},{int(x)}" for line, x in zip(lines[1:], family.tolist(), strict=True)]
        return "\n".join(lines) + "\n"

    def to_csv(self, path: str | os.PathLike[str]) -> None:
        """Write the estimates as CSV, atomically: the columns :attr:`COLUMNS` (``changed`` as 0 or 1).

        The file ``mudforce track --out`` writes; units in the names ([s], [-], [N]).
        """
        from mudforce.io.results import write_text

        write_text(path, self._csv_text())

    def plot(self, path: str | os.PathLike[str] | None = None, *, truth: Any = None, title: str | None = None) -> Any:
        """Force measured and predicted, and the water content with its band (needs matplotlib).

        Saved as PNG at ``path`` if given; ``truth`` the true water content per sample [-], if known.
        See :func:`mudforce.estimation.tracking_plots.plot_track`.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from mudforce.estimation.tracking_plots import plot_track

        if path is not None and not isinstance(path, (str, os.PathLike)):
            raise InputError(f"path must be a file path (str or os.PathLike), got {type(path).__name__}")
        return plot_track(self, path, truth=truth, title=title)


def track(time: Any, depth: Any, force: Any, foot: Foot | None = None, *, family_window: float | None = None,
          family_every: float = DEFAULT_FAMILY_EVERY, quiet: bool = True, **options: Any) -> TrackResult:
    """Run a :class:`MudTracker` over a whole recording (offline convenience; same results as online).

    Parameters
    ----------
    time : array_like
        Sample times [s], strictly increasing.
    depth : array_like
        Foot depth [m], positive down.
    force : array_like
        Measured force [N].
    foot : Foot, optional
        The foot (the paper's by default).
    family_window : float, optional
        Also run the family check beside the tracker (:class:`~mudforce.estimation.family_check.FamilyCheck`:
        identify's misfit flag on the samples of the last ``family_window`` seconds [s], online, the same verdicts
        as a :class:`FamilyCheck` fed sample by sample): the result's ``family_misfit`` and ``family_checks``.
        None (default): not run (it costs identify's time per check, about 0.3 s per 10 s of samples at 50 Hz).
    family_every : float
        How often the family check runs [s] of the recording (default 2.5).
    quiet : bool
        No progress line for the family check (default); False: one on stderr when it is a terminal.
    **options
        As for :class:`MudTrackers` (``force_gain_uncertainty`` also goes to the family check).

    Raises
    ------
    InputError
        On bad input, and on a force the same in every sample while the depth reaches the mud (as
        :func:`~mudforce.estimation.calibration.identify_water_content` refuses it).
    """
    t = real_array(time, "time", "s")
    z = real_array(depth, "depth", "m")
    f = real_array(force, "force", "N")
    if t.ndim != 1 or t.shape != z.shape or t.shape != f.shape or t.size < 1:
        raise InputError(f"time, depth and force must be 1-D of one length >= 1, got {t.shape}, {z.shape}, {f.shape}")
    # each refusal names the sample, in simulate()'s words, though a gap of up to MAX_TIME is taken here, as
    # MudTracker.update takes it
    check_times(t, max_dt=MAX_TIME)
    check_finite(z, "depth", "m")
    check_finite(f, "force", "N")
    tracker = _one_foot(foot, options)
    _check_bounds(z, f, tracker._max_depth, t)
    if family_window is not None:  # its options checked before any work
        checker = FamilyCheck(foot, window=family_window, every=family_every,
                              force_gain_uncertainty=options.get("force_gain_uncertainty",
                                                                 DEFAULT_FORCE_GAIN_UNCERTAINTY))
    # a force of one value while the foot is in the mud (a sensor unplugged, the wrong column) is identify's refusal:
    # the tracker read it as the wettest mud, 34 % (27.6-35.2 %) for a 25 % protocol, its misfit flag quiet at the end
    if f.size > 1 and np.any(z > 0.0):
        check_force_varies(f, "", "recording",
                           f" while the foot is in the mud (deepest {float(np.max(z)) * 1e3:.3g} mm)")
    m = t.size
    cols = np.empty((m, L._N_OUT), dtype=np.float64)
    previous = t[0]
    for k in range(m):
        tracker._depths[0] = z[k]
        tracker._forces[0] = f[k]
        tracker._step(float(t[k] - previous) if k else 1.0)
        cols[k] = tracker._out[0]
        previous = t[k]
    family: np.ndarray | None = None
    checks: tuple[tuple[int, FamilyVerdict], ...] = ()
    if family_window is not None:
        checks = tuple(_feed(checker, t, z, f, quiet))
        family = _flags(checks, m)
    # copies: a float64 input came back as the result's own array, which changed with the caller's buffer
    return TrackResult(t.copy(), z.copy(), f.copy(), cols[:, L._O_W], cols[:, L._O_LOW], cols[:, L._O_HIGH],
                       cols[:, L._O_PRED], cols[:, L._O_CHANGED] != 0.0, cols[:, L._O_BIAS], cols[:, L._O_NOISE],
                       cols[:, L._O_MISFIT] != 0.0,
                       cols[:, L._O_OFFSET], cols[:, L._O_OFFSET_SD], cols[:, L._O_LAG], cols[:, L._O_LAG_SD],
                       (float(tracker.grid[0]), float(tracker.grid[-1])), family, checks)

