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
  (the estimate and the misfit flag are the first bank's; the change flag
  reads the union, below): the branch rule is a model choice the data
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
  current one with a time constant of 1 s where that is narrower, and
  starts afresh at a change flag (which reads the current interval, not
  the hull). A posterior that jumps between two modes for a fraction of a
  second has not told them apart, and the interval keeps both. An end
  that leaves out only a sliver at the grid's end, where the posterior is
  about as dense as within, reaches that end: a foot that says almost
  nothing reports the whole grid, not the grid less a sliver at each end.

Speed plumbing: the whole update (bank step and posterior) is one compiled
call, :func:`_track_step`, over arrays held by the object.
"""

from __future__ import annotations

import functools
import inspect
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import Any, ClassVar

import numpy as np

from mudforce import _kernel as K
from mudforce._kernel.bounds import MAX_DEPTH, MAX_TIME, MIN_DT
from mudforce._kernel.layout import N_RING, P_DEADBAND, P_WINDOW, R_HEAD, R_T, R_Z, RING, S_CACHE_DT, store_cache
from mudforce._kernel.transitions import step_cache
from mudforce._plumbing.deprecation import warn_renamed
from mudforce._plumbing.jit import njit
from mudforce.engines.dynamics.rest_band import rest_band, rest_band_spread
from mudforce.errors import (
    InputError,
    feet_count,
    positive_number,
    real_array,
    real_number,
    true_or_false,
)
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

#: Largest |force| a tracker takes [N] (~1000 t, as a recording's force column: mudforce.io.tables.COLUMN_LIMITS):
#: beyond it a finite force could overflow the likelihood's squares and leave the posterior NaN for good.
MAX_FORCE = 1e7
# Largest relative model misfit ``misfit`` [-] and force lag allowance ``force_lag`` [s] a tracker takes: far beyond
# any use, and far below where the likelihood's scale overflows (~1e154).
_MAX_MISFIT = 1e3
_MAX_FORCE_LAG = 1e3

#: The default grid of water contents [-]: 15 % to 35 % in steps of 0.5 points (41 models).
DEFAULT_GRID: tuple[float, ...] = tuple(round(0.15 + 0.005 * k, 4) for k in range(41))

# per-foot auxiliary state, columns of MudTrackers._aux
_A_STARTED = 0  # 1 after the first sample
_A_BIAS = 1  # force offset estimate [N]
_A_NFREE = 2  # free samples seen (capped at the offset's memory)
_A_VAR = 3  # force noise variance estimate [N^2]
_A_CONTACT = 4  # seconds of contact seen (informative samples)
_A_ANCHOR = 5  # water content of the last settled estimate [-], NaN before
_A_HOLD = 6  # seconds of contact left in which the anchor follows the estimate after a flag [s]
_A_PPREV = 7  # the previous sample's predicted model force, offset excluded [N] (the lag allowance)
_A_ZPREV = 8  # the previous sample's depth [m] (the rest test)
_A_MISFIT = 9  # contact-time average of the clipped squared standardised residual [-] (the misfit flag)
_A_MISFIT_T = 10  # seconds of contact in that average [s]
_A_Z2 = 11  # the depth two samples back [m] (the depth noise estimate)
_A_Z3 = 12  # the depth three samples back [m]
_A_DVAR = 13  # depth noise variance estimate [m^2] (the rest test)
_A_ZN = 14  # depths seen, capped at 3
_A_TURN = 15  # samples of contact seen, modulo: whose turn it is to be scored among the spared models
_A_LAG = 16  # posterior mean of the force lag [s]: of the two stages' sum (_LAGS)
_A_LAG_SD = 17  # its posterior standard deviation [s]
_A_LAG_Y = 18  # then one column per lag hypothesis (_LAGS): the mean model's force through its first stage [N]
_N_LAGS = 9  # force lag hypotheses (_LAGS)
_A_LAG_L = _A_LAG_Y + _N_LAGS  # then one per lag hypothesis: its log-likelihood (forgotten as the water content's)
_A_LAG_Y2 = _A_LAG_L + _N_LAGS  # then one per lag hypothesis: the mean model's force through both its stages [N]
_A_PSUB = _A_LAG_Y2 + _N_LAGS  # the mean model's force at the last substep [N] (the lag hypotheses' filters run on it)
_A_SINK = _A_PSUB + 1  # the foot's sinkage [m]: the deepest depth plus the surface offset, forgotten over tau
_A_QUICK = _A_SINK + 1  # 1 while the bank's rows take the quick branch rule (its hysteresis), else 0
# then, per model: the contact time [s] at which it was last scored (_SPARE_MASS); its force low-passed by the force
# lag's two stages [N]; its force at the previous substep [N]; its force through the first stage [N] (four blocks of
# one column per model)
_A_ANCHOR_LOW = _A_QUICK + 1  # the reported interval's low end where the anchor was set [-] (the change flag)
_A_ANCHOR_HIGH = _A_QUICK + 2  # and its high end [-]
_A_HULL_LOW = _A_QUICK + 3  # the reported interval's low end at the last sample [-] (the hull, _HULL_MEMORY); NaN: none
_A_HULL_HIGH = _A_QUICK + 4  # and its high end [-]
_A_RUN = _A_QUICK + 5  # seconds of tare samples in the current run of them beyond the clip, 0 if none [s] (_TARE_RUN)
_A_RUN_QUIET = _A_QUICK + 6  # seconds of tare samples within 3 sigma in a row at the run's end [s] (_TARE_RUN_QUIET)
_A_RUN_MEAN = _A_QUICK + 7  # the run's tare samples' mean since it began or was last judged [N] (_TARE_RUN_SPREAD)
_A_RUN_SQ = _A_QUICK + 8  # and their mean square [N^2]
_A_LAG_A = _A_QUICK + 9  # posterior mean of the force lag's first stage [s] (the second's: _A_LAG less it, _lag_stages)
_A_FPREV = _A_QUICK + 10  # the previous sample's measured force [N] (scored where the depth is smoothed)
_A_D2VAR = _A_QUICK + 11  # the depth's second differences' mean square over 6 [m^2]: its noise plus the motion's bend
_A_TARE_EW = _A_QUICK + 12  # the tare residuals' short mean over the current stretch of tare samples [N] (_TARE_SHORT)
_A_TARE_VAR0 = _A_QUICK + 13  # the force noise variance where that stretch began [N^2] (its clip's)
_A_TARE_PREV = _A_QUICK + 14  # 1 where the sample before was a tare sample, else 0
_N_AUX = _A_QUICK + 15

# outputs, columns of MudTrackers._out
_O_W = 0
_O_LOW = 1
_O_HIGH = 2
_O_PRED = 3
_O_CHANGED = 4
_O_BIAS = 5
_O_NOISE = 6
_O_MISFIT = 7  # 1 where the model misses the force beyond its noise floor
_O_OFFSET = 8  # posterior mean of the surface offset [m] (the model follows the depth plus it)
_O_OFFSET_SD = 9  # its posterior standard deviation [m]
_O_LAG = 10  # posterior mean of the force lag [s]
_O_LAG_SD = 11  # its posterior standard deviation [s]
_N_OUT = 12

# configuration vector, entries of MudTrackers._cfg
_C_TAU = 0
_C_MISFIT = 1
_C_FLOOR = 2
_C_DOF = 3
_C_TEMP = 4  # correlation time [s]
_C_NOISE0 = 5
_C_BIAS0 = 6
_C_FREE_MEMORY = 7
_C_SETTLE = 8
_C_MARGIN = 9
_C_LEVEL = 10
_C_GAIN = 11  # force gain uncertainty g [-]: the models' forces are also weighed at (1 - g) and (1 + g)
_C_LAG = 12  # force lag allowance [s]: the model's force change over it is added to the likelihood's scale
_C_REST = 13  # rest speed [m/s]: a slower sample constrains the mud only through the rest band
_C_MISFIT_RATIO = 14  # misfit flag threshold on the average squared standardised residual [-]
_C_DISC = 15  # discretisation allowance [samples]: the model at the rate may be off by this many steps' force change
_C_BLUR_REF = 16  # misfit average [-] above which the reported posterior's blur widens (_MISFIT_BLUR_REF)
_C_TEMPER = 17  # misfit average [-] above which the fit's posterior is tempered by the excess
_C_OFFSET_TEMPER = 18  # the surface offsets' evidence is divided by this [-] (_OFFSET_TEMPER)
_C_SUBSTEP = 19  # the bank's longest step [s] (0: one step per sample)
_C_SHALLOW = 20  # the shallow-sinkage widening [-] (_SHALLOW_WIDENING)
_C_OFFSET_RES = 21  # half the widest step between two surface offset hypotheses [m] (0 with one)
_C_SHALLOW_GAIN = 22  # the shallow-sinkage widening's gain [-] (_SHALLOW_GAIN)
_C_RATE_GAIN = 23  # the low-rate widening's gain [-] (_RATE_WIDENING)
_C_QUICK = 24  # 1 where the bank's branch rule follows the measured depth noise (the default rule), else 0
_C_ROBUST_WINDOW = 25  # the noise-robust rule's window [steps] (:func:`default_velocity_filter`'s)
_C_ROBUST_DEADBAND = 26  # its deadband [m/s]
_C_QUICK_ON = 27  # the quick rule is taken above this many times the quick secant's noise [-] (_QUICK_ON)
_C_QUICK_OFF = 28  # ... and kept down to this many [-] (_QUICK_OFF)
_C_QUICK_SINK = 29  # ... only while the foot's sinkage is at least this [m] (_QUICK_SINK)
_C_QUICK_SINK_MAX = 30  # ... and at most this [m] (_QUICK_SINK_MAX)
_C_MAX_DEPTH = 31  # the largest |depth| taken [m] (MAX_DEPTH less the largest surface offset)
_C_HULL = 32  # the reported interval's hull memory [s] (_HULL_MEMORY; 0 in the twin bank, whose interval is a guard)
_C_LEAD = 33  # the most log-evidence any scored model may trail the best by [-] (_MAX_LEAD)
_C_SMOOTH = 34  # the depth noise [m] above which the bank steps on the depth's three-sample mean (_SMOOTH_NOISE)
_C_REST_SPREAD = 35  # the rest band's ends' spread under the depth noise is this many times its own [-] (_REST_SPREAD)
_N_CFG = 36

#: The misfit flag's threshold [-] (ours): the contact-time average of the squared standardised residual
#: (each clipped at 25) above which the model is taken to miss the data. In-family gait() walks average
#: about 1; the MuJoCo robot's feet at 100 Hz, in-family, 5 to 8 (vibration and impacts between the
#: samples), hence 10: the residual's rms above about 3 scales.
MISFIT_THRESHOLD = 10.0
_MISFIT_CLIP = 25.0  # [-] one sample counts at most 5 scales (a reversal seen late is one bad sample, not a miss)
_MISFIT_MIN_CONTACT = 1.0  # [s] of contact before the flag may fire
#: The misfit flag's discretisation floor [samples] (ours): at the sample rate the model is not the model of the
#: true path (a touchdown between two samples, a reversal seen late), an error of about a few samples' change of
#: the predicted force; the flag's scale holds this many.
_MISFIT_DISCRETISATION = 3.0

#: The misfit average [-] above which the fit's posterior is tempered (ours): its log is divided by the average over
#: this, a scale mixture (residuals larger than the scale says make each sample that much weaker evidence). In-family
#: gait() walks average 1 to 2.
_MISFIT_TEMPER_REF = 2.0
#: The misfit average [-] above which the reported posterior's blur widens (ours), by the square root of the excess.
_MISFIT_BLUR_REF = 3.0
#: An end of the reported interval moves to the grid's end where the posterior's tail beyond it is at least this
#: many times as dense as the interval is on average [-] (ours): the posterior is then not falling toward the end,
#: and an equal-tailed interval leaves out a sliver at the grid's end (the prior's bound) that nothing excludes. A
#: foot that says almost nothing (a flat posterior over the grid) was reported as [15.3, 35.2] % and a truth of 15.1 %
#: as missed, unflagged (the sensor-chain bench's seed 34, a MuJoCo foot 2 mm deep under "standard, all (-)", 23
#: samples), and a 4-mm-deep dry foot's [15.9, 33.2] % missed 15.7 % (seed 33, 8 samples). A posterior peaked inside
#: (its tail density a few percent of its mean) keeps its interval. Read on the interval before the hull (which the
#: change flag reads) and on the hull reported (an end the hull relaxed to a sliver from the grid's: seed 34's foot
#: at [15.16, 34.89] %, 8 samples), not on the hull kept (a reached end would be held at the grid's for good).
_END_REACH = 0.25
#: The spreads of the reported posterior's blurs, in units of ``discrepancy`` (ours): the blur is widened by the
#: square root of the misfit's excess over its reference, rounded up to one of these (precomputed, so the update's
#: cost does not depend on it). 9 and 13.5 added (was at most 6): the widening (with the shallow sinkage's and the low
#: rate's, in quadrature) asks for 8-11 on the sensor-chain bench's seed-13 robot that sinks 2-4 mm in 19.1 % mud,
#: which read anywhere from 18 to 34 % with the 6-fold blur's 15-19-point interval and missed the truth unflagged on
#: up to 17 % of its samples.
_BLUR_FACTORS = np.array([1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 9.0, 13.5])
#: The shallow-sinkage widening [-] (ours): with ``s`` this times the depth's uncertainty over the foot's sinkage,
#: ``s = 4 sqrt(sd^2 + (step / 2)^2 + noise^2) / sinkage`` (``sd`` the surface offset's posterior spread, ``step`` the
#: widest step between two offset hypotheses, which an offset between them is off by, ``noise`` the depth noise
#: measured online: since 2026-11-30, when a robot foot sinking 4 mm under 1 mm of depth noise at 50 Hz, its offset
#: read on the +3 mm hypothesis, was read 7 points wet with an interval 0.3 points short for 1.5 s; the sinkage the
#: deepest depth plus the offset in contact, forgotten over ``tau``), the reported interval's blur is widened by
#: ``_SHALLOW_GAIN sqrt(s^2 - 1)`` where ``s > 1``, in quadrature with the misfit's: only where the offset's
#: uncertainty is more than a quarter of the sinkage. A foot that sinks 3 mm, read through a surface known to 1.5 mm,
#: is read at a depth uncertain by half itself: on the sensor-chain bench such robots (dry mud, trots, walks on
#: 16.7-20 %; ``s`` 2-4) read 4-7 points off, the more under a lagged force, with their misfit that of right robots;
#: robots that sink 6 mm or more, and gait walks (1-3 cm deep), have ``s`` at or below 1. Nothing with one offset.
_SHALLOW_WIDENING = 4.0
#: The shallow-sinkage widening's gain [-] (ours, see :data:`_SHALLOW_WIDENING`): the blur's widening per unit of
#: ``sqrt(s^2 - 1)``. Was 1 with ``s`` at 5 times the ratio: seed 3's robot on 16.7 % mud (sinkage 3.1 mm, ``s``
#: 2.5, read 23-24 % under a 30 ms low-pass, lag known or not) then kept an interval of 12 points that missed the
#: truth on half its samples; a larger ``s`` instead widened the robots that sink 5 mm, which are right.
_SHALLOW_GAIN = 2.5
#: The low-rate widening [-] (ours): with ``k = round(dt / _RATE_STEP)`` the number of 10-ms steps a sample interval
#: ``dt`` spans (1 at 100 Hz, 2 at 50 Hz, 5 at 20 Hz), the reported interval's blur is widened by
#: ``_RATE_WIDENING sqrt(k - 1)``, in quadrature with the misfit's and the shallow sinkage's. Between two samples at a
#: low rate the foot's path is interpolated, and the model's force at a lift-off (the neck's start and decay) or a
#: strike depends on what the foot did there; those few samples carry the strongest evidence, each counted as an
#: independent one, and the misfit statistic's floor (three samples' force change) excuses their error. On the
#: sensor-chain bench's seed 4 a wet robot (33.9 %) at 20 Hz under an offset and a lag read 30.4 % with a 3.6-point
#: interval, unflagged, its offset and lag known or not. 1.5 (was 1: at 20 Hz a 4-discrepancy blur, was 3; at 50 Hz
#: 2, was 1.5): on the full-size bench's seed 0 a wet robot (34.8 %, 43 mm deep) under "hard, all" (+5 mm, 10 ms
#: delay and low-pass, 20 Hz) read 4.4 points low, its offset read -3 mm (truth -5 mm), with a 4.3-point half-width.
_RATE_WIDENING = 1.5
#: The force lag's widening [-] (ours): with ``L`` the posterior mean force lag and ``A`` the lag allowance
#: (``force_lag``, 10 ms by default, which the likelihood's scale already holds), the reported interval's blur is
#: widened by ``_LAG_WIDENING (L - A) / _LAG_WIDENING_STEP`` where ``L > A``, in quadrature with the others (from any
#: lag at all, it widened clean walks by half: the blurs come in steps, 1 then 1.5). The bank reads a lag's size
#: well but its shape from a few hypotheses (one low-pass, or two in a row: :data:`_LAGS_A`), and a sensor's chain is
#: seldom exactly one of them; the larger the lag, the more the model's force depends on its shape. On the
#: sensor-chain bench a 30-ms low-pass on two shallow robots of seed 21 (12 and 21 mm deep) was read as a 20-ms lag,
#: partly two-stage, and their intervals missed the truth by 0.001-0.11 points on 153 and 160 samples (a 20-ms
#: one-stage lag, before the two-stage hypotheses, had missed by as little). 0.5 covers them (a 20-ms lag takes the
#: blur's next step, 1.5-fold); a clean sensor is not widened.
_LAG_WIDENING = 0.5
#: The lag the widening counts in [s] (ours, :data:`_LAG_WIDENING`): the issue's standard low-pass.
_LAG_WIDENING_STEP = 0.01
#: The step [s] the low-rate widening counts a sample interval in (ours): the rate the bank's branch rule and its
#: substeps are built for (:data:`DEFAULT_MAX_STEP`); a fixed reference, so ``max_step`` does not move it.
_RATE_STEP = 0.01

#: Default force lag allowance [s] (10 ms, the issue's standard low-pass): a sensor that lags the
#: model by this much is not read as other mud.
DEFAULT_FORCE_LAG_ALLOWANCE = 0.01

#: Default longest step of the bank [s] (ours, the step its default branch rule is built for): a longer sample
#: interval is cut into equal substeps, the depth interpolated linearly between the two samples, so that at a low data
#: rate the models are not stepped coarser than at 100 Hz (at 20 Hz, a model stepped once per sample missed what the
#: foot did between two samples by points of water content, with a narrow interval).
DEFAULT_MAX_STEP = 0.01
#: At most this many substeps per sample (ours): a gap in the time stamps (a dropped stretch, a clock jump) is
#: stepped in as many, not in thousands.
_MAX_SUBSTEPS = 64

#: Default surface offset hypotheses [m] (ours): the bank holds each grid model at each, stepped on the measured
#: depth plus the offset, and the water content's posterior sums over them (so the offset's uncertainty widens
#: the interval). A robot's surface estimate is off by a few millimetres (issue 23).
DEFAULT_DEPTH_OFFSETS: tuple[float, ...] = (-0.006, -0.003, 0.0, 0.003, 0.006)
#: Default prior standard deviation of the surface offset [m] (ours).
DEFAULT_DEPTH_OFFSET_PRIOR = 0.004
#: The surface offsets' evidence is divided by this [-] (ours): a wrong offset is a misfit that persists over a
#: whole stance, far longer than ``correlation_time``, so its evidence is worth that much less; untempered, the
#: posterior jumped between neighbouring offsets, moving the estimate by points with a narrow interval each time.
_OFFSET_TEMPER = 4.0

#: The force offset is tared on a sample where the models of every surface offset holding at least this share of
#: the posterior say zero force [-] (ours): with the models of an unlikely offset of +6 mm in contact whenever the
#: foot is within 6 mm of the surface, a swing would otherwise leave few samples to tare on.
_TARE_MASS = 0.01
#: A run of tare samples beyond the clip is judged once it holds this many seconds of them [s] (ours). The
#: offset and the noise are the running mean and spread of the tare samples (over the last cfg[_C_FREE_MEMORY], 500),
#: each residual clipped at 4 standard deviations (4 floors at least). A run begins at a tare sample beyond the clip
#: and ends once :data:`_TARE_RUN_QUIET` of tare samples in a row lie within 3 standard deviations, whatever lies
#: between (contact included); its first sample is taken clipped, as any, and its later samples beyond 2 standard
#: deviations (:data:`_TARE_RUN_OUT`) change neither the offset, the noise nor the count. Once it holds this much
#: tare time it is judged by its own spread (:data:`_TARE_RUN_SPREAD`): a step of the offset scatters about its own
#: mean by about the noise, and is then taken as a real shift (clipped, and followed as before, the spread and so
#: the clip growing with it); a force that varies more is left out, and judged again after as long again.
#: A force the bank cannot explain on a foot that every probable model says is free (the mud's pull and push after
#: a lift-off, the necking decay of Eq. (7) that the models ended early; a touchdown seen late) comes as such a run:
#: taken clipped, each of its samples fed the spread the clip, the clip grew with the run, and the offset ran away
#: (`mudforce synth --motion gait --seed 1 --water-content 22%`'s walk r1, offset 0.5 N and noise 0.2 N: a run of
#: -4.5 to +8 N at 17.8-18.4 s, 0.6 s, moved them from 0.50 / 0.23 N to 1.05 / 1.44 N, 0.95 / 1.37 N at the end;
#: now 0.52 / 0.25 N, 0.50 / 0.23 N at the end; the sensor-chain bench's robots 3, 4 and 9 of seed 0, clean, ended
#: 0.4-0.8 N off with a noise of 1.1-1.5 N for 0.2 N, now within 0.06 N and 0.25-0.32 N). Longer than such a run,
#: shorter than one of a sensor whose offset has jumped (it holds every later tare sample): a jump of 15 sigma is
#: followed from its first second of tare samples on (before: from its first sample), a long swing or as many
#: strides as that takes (docs/tracking.md, "Limits").
_TARE_RUN = 1.0
#: ... a later sample of a run beyond this share of the clip in squared residual (2 of its 4 standard deviations) is
#: left out [-]: samples between 2 and 4 of a slowly rising push, taken, grew the clip until the push was followed
#: (1 mm of depth noise, W 25 %, 100 Hz: the foot 13 mm up from 4.5 to 5.5 s under a pull then a push of -3.6 to
#: +2.9 N, the offset 0.43 -> 1.42 N, 1.8 N at the end, for 0.4 N).
_TARE_RUN_OUT = 0.25
#: ... and a run begins only once this many free samples have been taken [-] (before, the spread is still mostly
#: the prior ``noise``: a sensor ten times noisier than it would have had its first samples rejected).
_TARE_RUN_AFTER = 5.0
#: ... a run ends once this many seconds of tare samples in a row lie within :data:`_TARE_RUN_QUIET_BAND` of the clip
#: [s] (ours): a pull and a push cross zero on their way, and one quiet sample there ended the run (0.12 s into it), the
#: push then crept in within the clip.
_TARE_RUN_QUIET = 0.2
#: ... that band, in squared residual over the clip [-] (3 of its 4 standard deviations).
_TARE_RUN_QUIET_BAND = 9.0 / 16.0
#: A judged run is a shift of the offset when its samples' standard deviation is at most this many times the noise
#: [-] (ours; a step reads 1 plus its sampling error, the pull and push of a lift-off 5-15).
_TARE_RUN_SPREAD = 3.0
#: Within a stretch of tare samples (ours, 2026-11-30): the clip is read against the smaller of the noise variance
#: and that where the stretch began, and a run also begins where the tare residuals' mean over about this many seconds
#: [s] (an exponential one, from zero at the stretch's start) leaves the offset by :data:`_TARE_SHORT_SIGMAS` of the
#: noise where the stretch began. Each tare sample taken within the clip fed the spread, so a force that rises slowly
#: (a neck the bank's models ended early: under 1 mm of depth noise their necks break before the data's) kept inside
#: a clip that grew faster than it and never started a run: on the sensor-chain bench's seed 36, "depth noise 1 mm",
#: a gait walk's offset went -0.42 -> +0.21 N and its noise 0.21 -> 0.81 N in half a second (5 of the 10 walks ended
#: 0.2-0.9 N off, the noise read 0.4-1.0 N for 0.2); now at most 0.21 N off, the noise at most 0.38 N.
_TARE_SHORT = 0.1
#: ... that many noise standard deviations [-] (ours): the short mean of white noise has a standard deviation of a
#: quarter of the noise at 100 Hz (at 20 Hz 0.6 of it; a low-passed noise's more), so 2 is no false run on a clean
#: sensor and a third of a second of a force the size of the noise.
_TARE_SHORT_SIGMAS = 2.0
#: A sample is tare only where the models' forces through the force lag are within this many noise standard deviations
#: of zero too [-] (ours, 2026-11-30): the models' own forces end at a lift-off, a low-passed sensor's force runs on as
#: the low-pass's tail, and the tare took that tail for the offset (the sensor-chain bench's "low-pass 30 ms", seed
#: 36: 10 of 20 robot recordings ended 0.3-2.8 N off; with this bound 4, 0.5-1.3 N off).
_TARE_TAIL = 1.0

#: A model of a surface offset other than the most probable one that holds less than this share of the posterior
#: [-] (ours) is spared: scored on one sample in ``_SPARE_TURN * correlation_time / dt`` only, in turn, its score
#: then standing for the contact time since its last (the decay over it, and a weight of that time over
#: ``correlation_time``: the likelihood counts a correlation time's samples as one); its posterior is 0 until then.
#: Its share is below any figure the estimate shows, and the score keeps it ready for when the data turn to it
#: (it is scored on every sample again once it holds this share). With one offset nothing is spared (the tracker
#: is the single-offset one number for number).
_SPARE_MASS = 1e-12
#: A spared model is scored once per this many correlation times [-] (ours).
_SPARE_TURN = 2.0

#: The depth noise assumed before any is measured [m] (that of :func:`default_velocity_filter`'s default).
_DEPTH_NOISE0 = 3e-5

#: The force lag hypotheses' first and second stages [s] (ours): the model's force through a first-order low-pass of
#: each time constant, then another (0: none). One stage is a sensor's low-pass; two equal ones have the shape of a
#: delay and a low-pass together (mean delay ``a + b``, and a response that starts later and rises faster than one
#: stage of the same mean: a 10-ms delay with a 10-ms low-pass, read as one 20-ms stage, drew the bank's estimate 3.7
#: points low on a deep wet robot of the sensor-chain bench, its interval missing the truth). Scored on the mean
#: model's force; the models' forces go through the posterior mean of each stage, and the posterior spread of the
#: sum enters the likelihood's scale (issue 23: the force lag as a nuisance).
_LAGS_A = np.array([0.0, 0.01, 0.02, 0.03, 0.045, 0.06, 0.005, 0.01, 0.015])
_LAGS_B = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.005, 0.01, 0.015])
#: Each hypothesis's mean delay [s]: the sum of its stages (the lag reported, its prior and its spread).
_LAGS = _LAGS_A + _LAGS_B
assert _LAGS.size == _N_LAGS and _LAGS_A.size == _N_LAGS
#: The force lag's log prior over :data:`_LAGS` [-] (ours): exponential of mean 5 ms (a sensor is taken to lag little
#: until its force says otherwise: the prior puts 86 % on no lag, and its mean over the hypotheses is 1.6 ms; with a
#: broader prior the lag the tracker starts with moved the early tare and the estimates of clean walks).
_LAG_LOG_PRIOR = -_LAGS / 0.005
#: Memory of the online depth noise estimate [s of contact] (ours).
_DEPTH_NOISE_MEMORY = 2.0
#: A step within this many standard deviations of the depth noise (on the difference of two samples, the noise in
#: excess of the branch rule's) of the rest speed counts as rest (ours): its branch the depth cannot tell, so it is
#: read through the rest band.
_REST_NOISE_SIGMAS = 2.0
#: At rest, beyond the band, the residual's scale holds the band's end's spread under the depth noise (ours; this many
#: times it): a depth ``sd`` off moves the Maxwell strain by as much, ``F_up`` by ``S k_m_w sd`` and ``F_down`` by about
#: ``S (k_m_i + df_e2/dz) sd`` (:func:`~mudforce.engines.dynamics.rest_band.rest_band_spread`), ``sd`` the noise in
#: excess of the branch rule's (as the rest test's), over sqrt(3) on the three-sample mean. Under 1 mm of depth noise
#: that is 1.4 N on ``F_up`` for a force noise of 0.2 N: a standing foot's load that rides the band's end (a foot
#: sinking or rising too slowly for the noisy depth to show) fell outside the right mud's band on half its samples, and
#: wetter muds, whose bands reach further, took the stance (the sensor-chain bench's seed 36, a gait walk on 31.4 % mud:
#: 31.9 -> 34.0 % through a 4-s stance, its interval missing the truth unflagged). The normalisation keeps the force's
#: scale alone, so the likelihood stays continuous at the band's end. Clean depths (no excess) are read as before, to
#: the bit. Seed 36's walk: highest estimate 33.4 %, none missed; on ten seeds' tracker tables 113 samples confidently
#: wrong -> 0 (with _END_REACH).
_REST_SPREAD = 1.0
#: Only the depth noise beyond this many times :data:`_DEPTH_NOISE0` widens the rest test (ours): the bank's branch
#: rule is built for that noise, and on clean recordings a wider test reads real slow motion as rest. Was 3: a MuJoCo
#: foot at rest whose depth reads 40-60 um of noise and vibration was then read as moving on a third of its samples,
#: the models' branch forces against a load anywhere in the rest band (in-family robot misfit averages of 4-9, and a
#: trot on dry mud confidently wrong under a 30 ms low-pass); at 1 the change flag fired more often on the bench.
_REST_NOISE_EXCESS = 2.0
#: The quick branch rule [steps], [m/s] (ours): a secant over two steps, with a deadband of 2.5 mm/s. The bank's
#: noise-robust default (:func:`default_velocity_filter`: a secant over 10 steps, for 30 um of depth noise at 100 Hz)
#: sees a reversal of the foot half its window late, about 50 ms. What the model gives as the foot turns (the spring's
#: release on the withdrawal branch) is then missed by every model of the bank, and drier, stiffer models fit better:
#: the sensor-chain bench's seed-4 robot, walking 24 mm deep into 33.9 % mud, ended at 32.3-32.9 % at 100 Hz under
#: the clean and standard single corruptions (within 1.5 points on 51 % of its samples under a -2 mm offset); on the
#: quick rule where it moves, 33.4-33.9 % (within on 96-100 %). Two steps rather than the exact rule's one, so that
#: the filter's history is kept for the switch back to the noise-robust rule. The deadband keeps a foot that slows to
#: the depth noise's speed (3 mm/s after a stroke at 46 mm/s, while the robust secant still reads motion) from
#: flipping branch for a sample: without it the one-step-ahead force dropped from 145 to 20 N and back on single
#: samples of `mudforce reproduce`'s tracking walk (32 jumps over 20 N at rest, against 26 on the robust rule); 1.5-3
#: mm/s all gave 26, while 4 mm/s made seed 4's delay-20-ms row confidently wrong.
_QUICK_WINDOW = 2.0
_QUICK_DEADBAND = 0.0025
#: A foot's bank takes the quick rule while the depth noise measured online is within this many times
#: :data:`_DEPTH_NOISE0` (150 um) [-] (ours), else the noise-robust rule: the quick one flips branch on 0.3-1 mm of
#: noise (gait walks then read 1-3 points high). The online estimate (third differences) reads about 30 um on clean
#: gait walks, 40-110 um on most of the bench's MuJoCo robots (vibration, impacts), 150-370 um with 0.3 mm of noise
#: added, and 300-600 um on a robot bounding 20 cm at 3 Hz (its own motion: those keep the robust rule).
_QUICK_NOISE = 5.0
#: ... and only after this much contact [s] (ours): the noise estimate starts at :data:`_DEPTH_NOISE0` and takes
#: about a second of contact to reach 0.3 mm; quick before that, a noisy foot's first stances were read on a rule that
#: flips branch on its noise (seed 3's "standard, all (-)" within 1.5 points 80 -> 70 %, seed 6's offset -5 mm
#: confidently wrong on 0.3 % of its samples). And only while the foot may be in the mud (its depth plus the largest
#: surface offset > 0): above it, a foot hovering after a lift-off read as moving down on its noise ends the models'
#: necking decay (Eq. (7)) at once, so the bank says zero force while the sensor still reads the mud's pull, and the
#: force offset was tared on it (gait walks: offset 0.5 N for -1 N, noise 3 N for 0.3 N).
_QUICK_AFTER = 1.0
#: ... and only while the foot moves (ours): the robust rule's secant above this many times the quick secant's noise
#: ``sqrt(2) sigma / (2 dt)`` (sigma the depth noise measured online: 10.6 mm/s for 30 um at 100 Hz), kept down to
#: :data:`_QUICK_OFF` times it [-]. The quick rule on every clean foot in the mud made the one-step-ahead force
#: chatter between about 10 and 200 N through every stance at rest (`mudforce reproduce`'s tracking walk: 203 jumps
#: over 20 N at rest, against 26 on the robust rule). Higher (8-20 on, 4-10 off) left feet on the robust rule at the
#: turns that the quick one is for: seed 4's delay rows confidently wrong.
_QUICK_ON = 5.0
_QUICK_OFF = 3.0
#: ... and only while the foot's sinkage (:data:`_A_SINK`) is within this band [m] (ours). Shallow feet (3-10 mm,
#: dry) read up to 2.5 points further from the truth on the quick rule (the sensor-chain bench's seed 3 robot 0 under
#: a -2 mm offset within 1.5 points 99 -> 65 %, seed 4's "gain +5 %" 80 -> 79 %: FAIL; a floor of 5 mm made seed 4's
#: offset +5 mm confidently wrong). Deep fast feet (robots driven 65-80 mm deep at 1-2.5 m/s) read 1-1.5 points high
#: on it under the standard corruptions (seed 3's robot 1 on 29.5 %: within 1.5 points 100 -> 25-46 %, its two rows
#: FAIL) though it cleared seed 5's low-pass 30 ms (8.0 % confidently wrong -> 0): the band leaves them on the robust
#: rule once they have sunk 40 mm. Floors of 8-12 mm and ceilings of 30-55 mm gave the same verdicts on seeds 3-5.
_QUICK_SINK = 0.010
_QUICK_SINK_MAX = 0.040
#: The twin bank's branch rule [steps], [m/s] (ours): with the default rule, a second, smaller bank of the same models
#: runs beside the first on the quick rule (:data:`_QUICK_WINDOW`, :data:`_QUICK_DEADBAND`) for every foot, at every
#: depth and speed, and the reported interval is the union of the two banks' intervals (the estimate and the misfit
#: flag are the first bank's). The branch rule is a model choice the data seldom settle: on the sensor-chain bench wet
#: robots (seeds 10, 13, 16: 32-34 %, 31-70 mm deep) read 2-4 points low on the 10-step rule with a 3-6-point interval
#: (confidently wrong on up to 74 % of a recording's samples) and right on shorter secants, while wet gait walks under
#: 1 mm of depth noise and seed 3's 74-mm robot read 1-3 points high on them: no one rule is right for every foot, and
#: the interval holds both. The twin ran a 5-step secant (no deadband) until 2026-11-29; on the quick rule it also
#: holds the deep wet robots that the first bank reads 4 points low under a 30 ms low-pass (seed 21's `robot-model` 1,
#: 74 mm deep in 32.3 %: a bank on the 10-step or the 5-step rule alone reads a median 28.1-28.3 % with the lag at
#: 45 ms, and the 5-step twin's union missed the truth unflagged on 717 of 2701 samples; a bank on the quick rule alone
#: reads 31.8 % [29.8, 33.7] with the lag at 30 ms, the chain's), which the sink band keeps off the first bank's
#: quick rule (docs/tracking.md, "The twin bank on the quick rule").
_TWIN_WINDOW = 2
_TWIN_DEADBAND = _QUICK_DEADBAND
#: The reported interval's memory [s of contact] (ours): each end of the reported interval relaxes toward the current
#: one with this time constant where the current one is narrower on that side (a hull of the last second or so of
#: intervals; counted in contact time, as the evidence is, so that a swing in which every model is free does not use it
#: up: at 20 Hz seed 21's `robot-model` 7 jumped to the wet end in a swing and stayed there 0.65 s into the next stance,
#: and its hull, relaxed through the swing too, let the truth out by 0.3-0.6 points on 2 samples),
#: and starts afresh at a change flag, which reads the current interval, not the hull (so flags come as before). A
#: posterior that jumps between two modes faster than the change flag settles has not told them apart: the foot the
#: sensor-chain bench's hard rows were still confidently wrong on, on all three full-size seeds (`robot-model` 7, a
#: trot 4-7 mm deep in 17.6-21.4 % mud whose posterior jumps to the wet end for 0.2-2.5 s at a time, the interval
#: [20-25, 35.2] %), is covered throughout with 1 s (0.5 s left one sample of seed 0's "hard, all"); the clean rows'
#: median width grows 3.4 -> 3.8 (seed 0) and 6.1 -> 6.6 points (seed 22). docs/tracking.md, "The reported interval's
#: memory".
_HULL_MEMORY = 1.0
#: The most log-likelihood [nats, untempered] by which any scored model may trail the best (ours, 2026-11-30):
#: a model further behind is raised to this distance. Forgetting alone (``tau``) lets the old mud lead a new one by
#: the whole evidence of ``tau`` seconds (about 400 nats on a walk at 18 % against 28 %), which a change must first
#: forget: the estimate reached 1.5 points of a change 18 -> 28 % a median 3.1 s after it. Kept at most 100 nats
#: behind (a chance of e^-100, far below any quantile reported or the spared models' _SPARE_MASS), a new mud is
#: within 1.5 points a median 1.2 s after the change (40 walks, 40 of 40 by 3 s; 17 of 40 without), a change
#: 20 -> 30 % is flagged a median 1.9 s after it (4.4 s without), intervals the same width; at 60 nats a standard
#: row lost 7 points of accuracy (seed 21's offset -5 mm), at 30 the intervals widened by a point.
_MAX_LEAD = 100.0
#: Depth noise [m] (as measured online, :data:`_DEPTH_NOISE_MEMORY`) above which the bank steps on the depth's
#: three-sample mean and scores the force of the sample before, one sample behind (ours; errors in variables): the
#: mean is centred on that sample, so neither the depth nor the force lags the other. A depth noise of 1 mm at 100 Hz
#: is 0.14 m/s of noise on the step velocity the drag squares and the Maxwell element follows; the models stepped on
#: the raw depth read the mud 1-3 points dry (the bench's row "depth noise 1 mm": 79 % of seed 31's samples within
#: 1.5 points; on the mean 90 %, seeds 0, 8, 21, 22 the same or better, and no other row's share moved). The online
#: estimate reads 1.0-1.2 mm under 1 mm of noise, 0.3-0.4 mm under 0.3 mm, and 0.5-0.9 mm on clean MuJoCo robots that
#: strike hard (their impacts), whose motion the mean bends (a third of dt^2 times the acceleration: 1 mm at 35 m/s^2
#: and 100 Hz): 0.8 mm keeps most of those on the raw depth (docs/tracking.md, "A noisy depth is stepped ...").
_SMOOTH_NOISE = 8e-4
#: ... at sample intervals up to this [s] (ours): at 20 Hz a motion sampled this coarsely reads as noise to every
#: order of differences, and the mean cost the bench's 20 Hz rows 5-14 points of "within".
_SMOOTH_MAX_STEP = 0.025
#: Beyond this sample interval [s] (ours; at 50 Hz), only where the mean's bend costs less than the noise it removes:
#: the mean of three samples sits a third of their second difference ``d2`` off the middle one and removes two thirds
#: of the noise variance ``s^2``, so it is the better depth (in mean square) where ``E[d2^2]`` (``6 s^2`` of noise plus
#: the motion's) is below ``12 s^2``: the second differences' reading over 6 (``_A_D2VAR``) below
#: :data:`_SMOOTH_BEND` times the third differences' (``_A_DVAR``). The bench's clean robots at 50 Hz read 2.7-5.4
#: (their impacts, taken as 0.3-3.8 mm of noise), gait walks under 1 mm of noise 1.0, robots 1.3-1.9. At 100 Hz the
#: test is not made: there the deep robots that strike hard read 3.6 under 1 mm of noise, and the mean still took
#: them from 19-21 to 56 % of their samples within 1.5 points (the noise on the step velocity matters more than the
#: bend of the depth); with the test at 100 Hz "depth noise 1 mm" lost 1-3 points on three seeds.
_SMOOTH_BEND_STEP = 0.0125
_SMOOTH_BEND = 2.0
#: The twin bank holds the surface offsets of the first within this of zero [m] (ours; all of them where none is):
#: -3, 0, +3 mm of the default five, three fifths of the first bank's cost. With the default offsets' middle three
#: the bench's tuning seeds' confidently wrong shares were those with a twin of all five to 0.2 % of a row's samples;
#: with one offset (0 mm) two rows were left at 1.4 and 2.2 %.
_TWIN_OFFSET_SPAN = 0.003


def default_velocity_filter(depth_noise: float = 3e-5, dt: float = 0.01) -> VelocityFilter:
    """The bank's branch rule: :meth:`VelocityFilter.for_noise` for ``depth_noise`` [m] at step ``dt`` [s]."""
    return VelocityFilter.for_noise(depth_noise, dt)


# ---------------------------------------------------------------------------- compiled update (speed plumbing)

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
def _reach_ends(low: float, high: float, first: float, last: float, half: float) -> tuple[float, float]:
    """The interval ``[low, high]`` [-] with an end moved to the grid's (``first``, ``last``) where the tail it leaves
    out there is at least :data:`_END_REACH` times as dense as the interval (ours): each tail holds ``half`` of the
    posterior, the interval ``1 - 2 half``."""
    inside = (1.0 - 2.0 * half) / max(high - low, 1e-12)
    reach_low = half >= _END_REACH * inside * (low - first)
    reach_high = half >= _END_REACH * inside * (last - high)
    return (first if reach_low else low), (last if reach_high else high)


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


@njit(cache=True, nogil=True, error_model="numpy")
def _lowpass_coefficients(dt: float, lag: float) -> tuple[float, float]:
    """``(e, c)`` of :func:`_lowpass_step` for a step of ``dt`` [s] and a lag ``lag`` > 0 [s]:
    ``e = exp(-dt / lag)``, ``c = (1 - e) lag / dt`` (the latter through ``expm1``)."""
    return math.exp(-dt / lag), -math.expm1(-dt / lag) * lag / dt


@njit(cache=True, nogil=True, error_model="numpy")
def _lowpass_step(e: float, c: float, y0: float, f0: float, f1: float) -> float:
    """One step of the first-order low-pass ``lag y' + y = F`` (the force lag, ours), exact for a force linear over
    the step from ``f0`` to ``f1`` [N]: ``y1 = e y0 + (1 - c) f1 - (e - c) f0`` [N], with ``(e, c)`` of
    :func:`_lowpass_coefficients`."""
    return e * y0 + (1.0 - c) * f1 - (e - c) * f0


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
    nsub = 1
    if cfg[_C_SUBSTEP] > 0.0 and aux[0, _A_STARTED] != 0.0:
        nsub = max(1, min(_MAX_SUBSTEPS, int(min(dt / cfg[_C_SUBSTEP], float(_MAX_SUBSTEPS)) + 0.5)))
    for s in range(1, nsub + 1):
        u = s / nsub
        for j in range(n):
            z_now = depths[j]
            z_before = aux[j, _A_ZPREV]
            if _smoothed(aux, j, dt, cfg):  # a noisy depth: its three-sample mean, one sample behind
                z_now = (depths[j] + aux[j, _A_ZPREV] + aux[j, _A_Z2]) / 3.0
                z_before = (aux[j, _A_ZPREV] + aux[j, _A_Z2] + aux[j, _A_Z3]) / 3.0
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
            if po > p_map:
                p_map = po
                o_map = o
        out[j, _O_PRED] = predl + aux[j, _A_BIAS]
        if first:
            aux[j, _A_PPREV] = pred
            aux[j, _A_PSUB] = pred
        # the mean model's force low-passed by each lag hypothesis (every sample: a lag runs on into the swing)
        _lag_hypotheses(aux, j, h_sub, pred, first, lag_cache)
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
                yk = aux[j, _A_LAG_Y2 + k]
                rk = f - bias - yk
                sk = var + bias_var + floor2 + misfit2 * yk * yk
                v = keep * aux[j, _A_LAG_L + k] + weight * (
                    -0.5 * (dof + 1.0) * math.log1p(rk * rk / (dof * sk)) - 0.5 * math.log(sk))
                aux[j, _A_LAG_L + k] = v
                top_k = max(top_k, v / cfg[_C_OFFSET_TEMPER] + _LAG_LOG_PRIOR[k])
            zk = l1 = l2 = la = 0.0
            for k in range(_LAGS.shape[0]):
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
            rest = abs(depths[j] - aux[j, _A_ZPREV]) <= cfg[_C_REST] * dt + _REST_NOISE_SIGMAS * math.sqrt(2.0 * excess)
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
        for g in range(G):
            marginal[g] = 0.0
        for o in range(NO):
            po = 0.0
            for g in range(G):
                po += P[j, o * G + g]
                marginal[g] += P[j, o * G + g]
            om += po * offsets[o]
            o2 += po * offsets[o] * offsets[o]
        out[j, _O_OFFSET] = om
        osd = math.sqrt(max(o2 - om * om, 0.0))
        if not free and not first:
            # the sinkage: the deepest depth plus the offset in contact, forgotten as the evidence is
            aux[j, _A_SINK] = max(aux[j, _A_SINK] * math.exp(-dt / tau), depths[j] + om)
        out[j, _O_LAG] = aux[j, _A_LAG]
        out[j, _O_LAG_SD] = aux[j, _A_LAG_SD]
        out[j, _O_OFFSET_SD] = osd
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
        if not math.isnan(guard[j, 0]):
            w_low = min(w_low, guard[j, 0])
            w_high = max(w_high, guard[j, 1])
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
        # toward the current one where that is narrower, afresh at a change flag (which read the current interval)
        if cfg[_C_HULL] > 0.0:
            h_low = aux[j, _A_HULL_LOW]
            h_high = aux[j, _A_HULL_HIGH]
            if changed == 0.0 and not first and h_low == h_low:  # (NaN: no interval yet)
                keep_hull = 1.0 if free else math.exp(-dt / cfg[_C_HULL])  # (contact time, as the evidence's)
                if h_low < w_low:
                    w_low = w_low + (h_low - w_low) * keep_hull
                if h_high > w_high:
                    w_high = w_high + (h_high - w_high) * keep_hull
            aux[j, _A_HULL_LOW] = w_low
            aux[j, _A_HULL_HIGH] = w_high
            # an end the hull relaxed to a sliver from the grid's reaches it too (_END_REACH on what is reported; the
            # hull keeps its own ends, else a reached end would be held there by the hull for good)
            w_low, w_high = _reach_ends(w_low, w_high, edges[0], edges[edges.shape[0] - 1], half)
        out[j, _O_W] = w_mid
        out[j, _O_LOW] = w_low
        out[j, _O_HIGH] = w_high
        out[j, _O_BIAS] = aux[j, _A_BIAS]
        out[j, _O_NOISE] = math.sqrt(aux[j, _A_VAR])
        out[j, _O_CHANGED] = changed
        out[j, _O_MISFIT] = 1.0 if (aux[j, _A_CONTACT] >= _MISFIT_MIN_CONTACT
                                    and aux[j, _A_MISFIT] > cfg[_C_MISFIT_RATIO]) else 0.0
        aux[j, _A_PPREV] = pred
        aux[j, _A_PSUB] = pred
        aux[j, _A_Z3] = aux[j, _A_Z2]
        aux[j, _A_Z2] = aux[j, _A_ZPREV]
        aux[j, _A_ZPREV] = depths[j]
        aux[j, _A_FPREV] = measured[j]
        aux[j, _A_ZN] = min(aux[j, _A_ZN] + 1.0, 3.0)
    return -1


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
        Estimated force-sensor offset [N] (tared while the foot is free).
    noise : float
        Estimated force-sensor noise, standard deviation [N].
    misfit : bool
        True while the model misses the force beyond its noise floor (the
        average squared residual of the last ``tau`` seconds of contact,
        in units of the likelihood's scale, above :data:`MISFIT_THRESHOLD`):
        the mud is off the model's family, or the sensors are corrupted
        beyond the allowances; the interval is then not to be trusted.
    depth_offset, depth_offset_stderr : float
        Posterior mean and standard deviation of the surface offset [m]
        over the tracker's ``depth_offsets``: the model follows the measured
        depth plus it (as ``identify``'s ``depth_offset``), so a depth that
        reads 5 mm too deep gives about -0.005.
    force_lag, force_lag_stderr : float
        Posterior mean and standard deviation of the force sensor's lag [s]:
        the time constant of a first-order low-pass of the model's force (a
        pure delay reads as about half of it), as ``identify``'s ``force_lag``; the
        models' forces are low-passed by it, and its spread enters the
        likelihood's scale (and so the interval).
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
        Posterior mean and standard deviation of the surface offset [m] (see :class:`TrackEstimate`).
    force_lag, force_lag_stderr : numpy.ndarray
        Posterior mean and standard deviation of the force lag [s] (see :class:`TrackEstimate`).
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
    for column, name in ((_A_NFREE, "free-sample count"), (_A_VAR, "force noise variance"), (_A_RUN, "tare run time"),
                         (_A_RUN_QUIET, "tare run's quiet time"), (_A_RUN_SQ, "tare run's mean square"),
                         (_A_CONTACT, "contact time"), (_A_HOLD, "change-flag hold"), (_A_MISFIT, "misfit average"),
                         (_A_MISFIT_T, "misfit time"), (_A_DVAR, "depth noise variance"),
                         (_A_D2VAR, "depth's second differences' mean square"),
                         (_A_TARE_VAR0, "tare stretch's noise variance"),
                         (_A_LAG_SD, "force lag spread"), (_A_LAG_A, "force lag's first stage")):
        if np.any(aux[:, column] < 0.0):
            return f"{name} is negative"
    for column, name in ((_A_STARTED, "started"), (_A_QUICK, "branch rule"), (_A_TARE_PREV, "tare")):
        if not np.all(np.isin(aux[:, column], (0.0, 1.0))):
            return f"{name} flag is not 0 or 1"
    if not np.all((aux[:, _A_ZN] >= 0.0) & (aux[:, _A_ZN] <= 3.0)):
        return "depth count is not within [0, 3]"
    longest = float(_LAGS.max())
    if not np.all((aux[:, _A_LAG] >= 0.0) & (aux[:, _A_LAG] <= longest * (1.0 + 1e-9))):  # a mean of the lags
        return f"force lag is not within [0, {longest:g}] s"
    anchor = aux[:, _A_ANCHOR]
    set_ = ~np.isnan(anchor)
    if not np.all((aux[set_, _A_ANCHOR_LOW] <= anchor[set_]) & (anchor[set_] <= aux[set_, _A_ANCHOR_HIGH])):
        return "change-flag anchor lies outside its interval"
    hull_low, hull_high = aux[:, _A_HULL_LOW], aux[:, _A_HULL_HIGH]
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
        cfg = np.empty(_N_CFG, dtype=np.float64)
        # the default rule follows each foot's depth noise measured online (quick while it is low, see
        # _QUICK_WINDOW); a rule given is kept as given
        cfg[_C_QUICK] = 1.0 if velocity_filter is None else 0.0
        cfg[_C_ROBUST_WINDOW] = float(self.velocity_filter.window)
        cfg[_C_ROBUST_DEADBAND] = float(self.velocity_filter.deadband)
        cfg[_C_QUICK_ON] = _QUICK_ON
        cfg[_C_QUICK_OFF] = _QUICK_OFF
        cfg[_C_QUICK_SINK] = _QUICK_SINK
        cfg[_C_QUICK_SINK_MAX] = _QUICK_SINK_MAX
        cfg[_C_TAU] = positive_number(tau, "tau", "s")
        cfg[_C_MISFIT] = _at_most(positive_number(misfit, "misfit", "-"), "misfit", _MAX_MISFIT, "-")
        cfg[_C_FLOOR] = _at_most(positive_number(floor, "floor", "N"), "floor", MAX_FORCE, "N")
        cfg[_C_DOF] = positive_number(dof, "dof", "-")
        cfg[_C_TEMP] = positive_number(correlation_time, "correlation_time", "s")
        cfg[_C_NOISE0] = _at_most(positive_number(noise, "noise", "N"), "noise", MAX_FORCE, "N")
        cfg[_C_BIAS0] = _at_most(positive_number(bias, "bias", "N"), "bias", MAX_FORCE, "N")
        cfg[_C_FREE_MEMORY] = 500.0  # samples: the offset and noise follow slow drift over ~5 s of swing at 100 Hz
        step = float(np.max(np.diff(self.grid)))
        cfg[_C_SETTLE] = max(0.04, 6.0 * step)  # [-] interval width under which an estimate counts as settled
        cfg[_C_MARGIN] = max(0.01, 2.0 * step)  # [-] how far a settled interval must leave the anchor
        cfg[_C_LEVEL] = level
        cfg[_C_GAIN] = _non_negative(force_gain_uncertainty, "force_gain_uncertainty", "-")
        if not cfg[_C_GAIN] < 0.5:
            raise InputError(f"force_gain_uncertainty must be within [0, 0.5) [-] (0.05 is 5 %), "
                             f"got {force_gain_uncertainty!r}")
        cfg[_C_LAG] = _at_most(_non_negative(force_lag, "force_lag", "s"), "force_lag", _MAX_FORCE_LAG, "s")
        cfg[_C_REST] = REST_SPEED
        cfg[_C_MISFIT_RATIO] = MISFIT_THRESHOLD
        cfg[_C_DISC] = _MISFIT_DISCRETISATION
        cfg[_C_BLUR_REF] = _MISFIT_BLUR_REF
        cfg[_C_TEMPER] = _MISFIT_TEMPER_REF
        cfg[_C_OFFSET_TEMPER] = _OFFSET_TEMPER
        cfg[_C_SUBSTEP] = _non_negative(max_step, "max_step", "s")
        cfg[_C_HULL] = _HULL_MEMORY
        cfg[_C_LEAD] = _MAX_LEAD
        cfg[_C_SMOOTH] = _SMOOTH_NOISE
        cfg[_C_REST_SPREAD] = _REST_SPREAD
        self._cfg = cfg
        self.depth_offsets = _offsets(depth_offsets)
        # the largest |depth| taken [m]: the bank's models follow the depth plus each offset, within MAX_DEPTH
        self._max_depth = MAX_DEPTH - float(np.max(np.abs(self.depth_offsets)))
        cfg[_C_MAX_DEPTH] = self._max_depth
        cfg[_C_SHALLOW] = _SHALLOW_WIDENING
        cfg[_C_SHALLOW_GAIN] = _SHALLOW_GAIN
        cfg[_C_RATE_GAIN] = _RATE_WIDENING
        cfg[_C_OFFSET_RES] = 0.5 * float(np.max(np.diff(self.depth_offsets))) if self.depth_offsets.size > 1 else 0.0
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
            [_blur_matrix(self.grid, self._edges, self.discrepancy * float(k)).T for k in _BLUR_FACTORS]
            + [_blur_matrix(self.grid, self._edges, self.discrepancy * float(k), pile=True).T
               for k in _BLUR_FACTORS[1:]]))
        self._Q = np.zeros(G, dtype=np.float64)
        # scratch of the compiled step: the water content's and the offsets' posteriors, the lag filters' coefficients
        self._work = np.zeros(G + self.depth_offsets.size + 1 + 4 * _N_LAGS, dtype=np.float64)
        self._scored = np.zeros(M, dtype=np.float64)  # the models scored on this sample, scratch of the compiled step
        mud = [MudParameters.from_water_content(float(w)) for w in self.grid]
        from mudforce.steppers.many import MudContacts

        rows = self.n * self.depth_offsets.size
        self._bank = MudContacts(mud * rows, rows * G, self.foot, velocity_filter=self.velocity_filter, threads=1)
        self._zbuf = np.zeros(rows * G, dtype=np.float64)
        self._L = np.zeros((self.n, (3 if cfg[_C_GAIN] > 0.0 else 1) * M), dtype=np.float64)
        self._P = np.zeros((self.n, M), dtype=np.float64)
        self._aux = np.zeros((self.n, _N_AUX + 4 * M), dtype=np.float64)
        self._out = np.zeros((self.n, _N_OUT), dtype=np.float64)
        self._depths = np.zeros(self.n, dtype=np.float64)
        self._forces = np.zeros(self.n, dtype=np.float64)
        # the twin bank's reported interval [-], shape (n, 2), which this bank's also holds (NaN: no twin); an input
        # of the compiled step, written before each step
        self._guard = np.full((self.n, 2), math.nan, dtype=np.float64)
        bank = self._bank
        buf, layout = _pack(self)  # the arrays above become views of one buffer
        # the compiled step's arrays after dt, in its order (all updated in place, never rebound)
        self._args = (bank._states, bank.ring, bank.params_array, bank.forces, bank._scratch[0], bank._index[0], buf,
                      layout)
        # the default rule's twin: the same models on the quick rule, whose interval the reported one also holds
        self._twin: MudTrackers | None = None
        if velocity_filter is None and twin:
            near = self.depth_offsets[np.abs(self.depth_offsets) <= _TWIN_OFFSET_SPAN + 1e-12]
            self._twin = MudTrackers(
                n, self.foot, water_contents=self.grid.tolist(), tau=tau, misfit=misfit, floor=floor, dof=dof,
                correlation_time=correlation_time, noise=noise, bias=bias,
                velocity_filter=VelocityFilter(_TWIN_WINDOW, _TWIN_DEADBAND), level=level, discrepancy=discrepancy,
                force_gain_uncertainty=force_gain_uncertainty, force_lag=force_lag,
                depth_offsets=(near if near.size else self.depth_offsets).tolist(),
                depth_offset_prior=depth_offset_prior, max_step=max_step)
            # the twin's interval is a guard of this bank's, not reported: it keeps no hull (_HULL_MEMORY); and it takes
            # the depths this bank takes, no more (its offsets span less: a depth it took, refused here, moved it)
            self._twin._cfg[_C_HULL] = 0.0
            self._twin._max_depth = self._twin._cfg[_C_MAX_DEPTH] = self._max_depth
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
                         self._log_prior.tobytes(), self._bank.params_array.tobytes(), _LAGS_A.tobytes(),
                         _LAGS_B.tobytes()))

    def reset(self) -> None:
        """Forget everything: the next update is a first sample, the posterior uniform."""
        self._bank.reset()
        self._L[:] = 0.0
        prior = np.exp(self._log_prior)
        self._P[:] = np.repeat(prior / (prior.sum() * self.grid.size), self.grid.size)
        self._aux[:] = 0.0
        self._aux[:, _A_VAR] = self._cfg[_C_NOISE0] ** 2
        self._aux[:, _A_DVAR] = _DEPTH_NOISE0**2
        self._aux[:, _A_D2VAR] = _DEPTH_NOISE0**2
        self._aux[:, _A_ANCHOR] = np.nan
        self._aux[:, _A_HULL_LOW] = np.nan
        self._aux[:, _A_HULL_HIGH] = np.nan
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
            twin._depths[:] = self._depths  # (inputs of its step only: a refused sample changes no state)
            twin._forces[:] = self._forces
            bad = _track_step(dt, *twin._args)  # the same check of the sample as the first bank's, before any change
            if bad < 0:
                twin._started = True
                self._guard[:, 0] = twin._out[:, _O_LOW]
                self._guard[:, 1] = twin._out[:, _O_HIGH]
                bad = _track_step(dt, *self._args)
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
        return TrackEstimates(o[:, _O_W].copy(), o[:, _O_LOW].copy(), o[:, _O_HIGH].copy(), o[:, _O_PRED].copy(),
                              o[:, _O_CHANGED] != 0.0, o[:, _O_BIAS].copy(), o[:, _O_NOISE].copy(),
                              o[:, _O_MISFIT] != 0.0, o[:, _O_OFFSET].copy(), o[:, _O_OFFSET_SD].copy(),
                              o[:, _O_LAG].copy(), o[:, _O_LAG_SD].copy())


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
                and np.isfinite(np.delete(value.aux, [_A_ANCHOR, _A_HULL_LOW, _A_HULL_HIGH], axis=1)).all()
                and not np.isinf(value.aux[:, [_A_ANCHOR, _A_HULL_LOW, _A_HULL_HIGH]]).any()):
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
        o[_O_CHANGED] = o[_O_CHANGED] != 0.0
        o[_O_MISFIT] = o[_O_MISFIT] != 0.0
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
        Posterior mean and standard deviation of the surface offset [m] (see :class:`TrackEstimate`).
    force_lag, force_lag_stderr : numpy.ndarray
        Posterior mean and standard deviation of the force lag [s] (see :class:`TrackEstimate`).
    water_content_range : tuple of float
        The tracker's grid's first and last water content [-] (:data:`DEFAULT_GRID`'s, 0.15 and 0.35, unless
        ``water_contents`` was given): the family's ends that :attr:`family_edge` reads.
    model_misses_data : bool
        (Property.) True when the misfit flag was raised on any sample of the recording (``misfit.any()``; the name
        of :attr:`~mudforce.estimation.calibration.Identification.model_misses_data`): the mud may not be in the
        Table I family, or the sensor chain is off (a force of noise alone, a depth in mm read as m). A final
        estimate with its flag down can follow a recording flagged nearly throughout.
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

    #: The columns of :meth:`to_csv` (and of ``mudforce track --out``), in order.
    COLUMNS: ClassVar[tuple[str, ...]] = ("time_s", "water_content", "water_content_low", "water_content_high",
                                          "force_predicted_N", "force_N", "changed", "misfit")

    def _misfit(self) -> np.ndarray:
        return np.zeros(self.time.shape, dtype=bool) if self.misfit is None else self.misfit

    @property
    def model_misses_data(self) -> bool:
        """True when the misfit flag was raised on any sample (see the class's attributes)."""
        return bool(np.any(self._misfit()))

    @property
    def family_edge(self) -> str:
        """``"wet"``, ``"dry"`` or ``"both"`` when the final interval reaches that end of the family (or both), else
        ``""`` (see the class's attributes)."""
        wet = bool(self.high.size and self.high[-1] >= self.water_content_range[1])
        dry = bool(self.low.size and self.low[-1] <= self.water_content_range[0])
        return "both" if wet and dry else "wet" if wet else "dry" if dry else ""

    def columns(self) -> dict[str, np.ndarray]:
        """The per-sample data under the names of :attr:`COLUMNS` (``changed``, ``misfit`` as bool)."""
        arrays = (self.time, self.water_content, self.low, self.high, self.force_predicted, self.force, self.changed,
                  self._misfit())
        return dict(zip(self.COLUMNS, arrays, strict=True))

    def to_pandas(self) -> Any:
        """A :class:`pandas.DataFrame` with the columns of :meth:`to_csv` (needs pandas)."""
        from mudforce.io.results import to_pandas

        return to_pandas(self.columns())

    def _csv_text(self) -> str:
        lines = [",".join(self.COLUMNS)]
        for row in zip(self.time.tolist(), self.water_content.tolist(), self.low.tolist(), self.high.tolist(),
                       self.force_predicted.tolist(), self.force.tolist(), self.changed.tolist(),
                       self._misfit().tolist(), strict=True):
            *values, changed, misfit = row
            lines.append(",".join(repr(float(v)) for v in values) + f",{int(changed)},{int(misfit)}")
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


def track(time: Any, depth: Any, force: Any, foot: Foot | None = None, **options: Any) -> TrackResult:
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
    **options
        As for :class:`MudTrackers`.

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
    # a force of one value while the foot is in the mud (a sensor unplugged, the wrong column) is identify's refusal:
    # the tracker read it as the wettest mud, 34 % (27.6-35.2 %) for a 25 % protocol, its misfit flag quiet at the end
    if f.size > 1 and np.any(z > 0.0):
        check_force_varies(f, "", "recording",
                           f" while the foot is in the mud (deepest {float(np.max(z)) * 1e3:.3g} mm)")
    m = t.size
    cols = np.empty((m, _N_OUT), dtype=np.float64)
    previous = t[0]
    for k in range(m):
        tracker._depths[0] = z[k]
        tracker._forces[0] = f[k]
        tracker._step(float(t[k] - previous) if k else 1.0)
        cols[k] = tracker._out[0]
        previous = t[k]
    # copies: a float64 input came back as the result's own array, which changed with the caller's buffer
    return TrackResult(t.copy(), z.copy(), f.copy(), cols[:, _O_W], cols[:, _O_LOW], cols[:, _O_HIGH], cols[:, _O_PRED],
                       cols[:, _O_CHANGED] != 0.0, cols[:, _O_BIAS], cols[:, _O_NOISE], cols[:, _O_MISFIT] != 0.0,
                       cols[:, _O_OFFSET], cols[:, _O_OFFSET_SD], cols[:, _O_LAG], cols[:, _O_LAG_SD],
                       (float(tracker.grid[0]), float(tracker.grid[-1])))
