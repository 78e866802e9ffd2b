"""Telling the mud's water content from one intrusion trial.

The paper's Table I gives the parameters at five water contents;
:meth:`MudParameters.from_water_content` interpolates between them. For a
measured trial, :func:`identify_water_content` finds the water content
whose parameters reproduce the measured force best (least squares over
all samples, after the same preparation as a fit: motion fitted, force
tared, tare offset profiled), and an interval from the rise of the
residual sum of squares.

The interval is a likelihood-ratio interval that allows for model error:
``SSR(W) - SSR_min <= chi2_1(level) * s^2 * n / n_eff`` with
``s^2 = SSR_min / (n - 1)`` and ``n_eff`` the effective number of
independent residuals from their lag-1 autocorrelation. A trial that the
family fits to the noise floor gets a narrow interval; a trial it misfits
(correlated residuals, large ``s``) a wide one. The interval is never
narrower than +-:data:`MIN_HALF_WIDTH` (0.25 points): below that the
family's interpolation and the branch labels of a general motion, not the
noise, limit what one trial can tell.

**A robot's sensor chain** (docs/estimation.md, "What a robot should log"):
on the general path the model is compared with the data through three
nuisances, fitted jointly with the water content (Gauss-Newton, bias
profiled): a surface offset of the depth (the model follows ``depth +
offset``), a force lag (the model's force through a first-order low-pass
of time constant ``force_lag``, which also stands for a pure delay of about
that size) and the force bias (tared or free, as before). Their
correlation with the water content widens the interval (the likelihood
interval scaled by ``sqrt(C_ww / C_ww|nuisances fixed)``). A force-gain
error cannot be told from a mud whose force-scale parameters are all off by
as much, but along Table I they do not move together: the force's gain is
read where the recording determines it (``force_gain``: a sharp least of the
cost over a grid of gains within two uncertainties of 1, ours), else it is 1.
Its uncertainty is an input (``force_gain_uncertainty``, default
:data:`DEFAULT_FORCE_GAIN_UNCERTAINTY`) and the interval is widened on each
side by the water-content shift that a further gain change of that size
causes (the same fit on the force divided by ``gain * (1 +- g)``). A sample where
the foot is at rest in the mud (it moved less than :data:`REST_SPEED` times
the step, plus half a depth noise) constrains the mud only through the rest band it must lie in
(:func:`mudforce.model.equations.rest_band_forces`): its residual is the
distance of the force outside the band, zero inside. So does a sample where
the motion changes direction or stops beside a step clear of the depth noise
(the change happened anywhere between its neighbours, so at the sample the
foot may be on either branch). The depth noise, when not given, is
the noise of the depth's quietest stretches, and the rest of its high-frequency content (a foot ringing between
the samples) is motion the rate does not resolve: the branch labels follow it, and the noise floor holds it
(``unresolved_depth``). The noise floor of the
misfit flag includes the model's own discretisation error at the data's
rate, estimated from the data (the model on the even samples and on the odd
ones against the model on every sample, each sample taking the largest of
itself and its neighbours), sample by sample: the misfit statistic is the RMS
of the residuals each divided by its own floor (each sample counting at most
five floors), so that a local
discretisation error (a branch switch a sample late) excuses only the
samples where it is large, not an off-family mud everywhere.

The interval then reaches the member of the family that explains the data
best by that statistic (the bias re-profiled under its weights; searched over
the family's whole range): least squares weighs every sample alike, so a
few samples whose floor is tens of newtons (an event between two samples) can
pull the estimate points away, and the interval around it with it. The
interval is extended to hold that member +-:data:`MIN_HALF_WIDTH` (general
path), and to hold every water content of a 0.25-point grid whose statistic
passes once the depth offset and the force lag are refitted there; the flag
reads the least statistic found (at the estimate or at such a member), so a
quiet flag says that a member the interval holds explains the data to the
floor. The estimate is that of least squares, unless its own statistic fails
(above :data:`~mudforce.estimation.calibration.fit.MISFIT_WARNING_RATIO`) and such
a refitted member reads less: the estimate is then that member
(``misfit_water_content``; ``least_squares_water_content`` keeps least squares').

A trial of any motion is accepted (:func:`~mudforce.estimation.calibration.preprocess.prepare_trial`).
The result says how well the family explains it: ``misfit_ratio`` (RMSE
over the force noise measured independently of the family),
``model_misses_data`` and ``off_family`` (the RMS residual in excess of
the noise [N]); ``water_content`` is then the nearest member of the family.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import partial

import numpy as np
from scipy.optimize import OptimizeResult, brentq, least_squares, minimize_scalar
from scipy.stats import chi2
from scipy.stats import t as student_t

from mudforce._plumbing.blas import one_blas_thread
from mudforce.errors import InputError, is_integer, is_real, shown
from mudforce.estimation.calibration._recording_model import (
    _MISFIT_CLIP,
    _REST_NOISE_SIGMAS,
    _TAIL_Z2,
    NEAR_LIMITS_WARNING,
    TAIL_SHARE_WARNING,
    _band_residual,
    _bias_reprofiled,
    _discretisation,
    _force_and_band,
    _model_set,
    _rest_samples,
    _sticking,
)
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.fit import DEPTH_NOISE_SHARE_WARNING, MISFIT_WARNING_RATIO, misfit_ratio
from mudforce.estimation.calibration.models import CHEN2024
from mudforce.estimation.calibration.preprocess import (
    MIN_PRECONTACT_SAMPLES,
    PreparedTrial,
    _force_sign_warning,
    noise_floor_parts,
    prepare_trial,
    tare_correction,
)
from mudforce.estimation.nuisances import (
    DEFAULT_FORCE_GAIN_UNCERTAINTY,
    REST_SPEED,
    check_force_gain_uncertainty,
    check_force_varies,
)
from mudforce.model.foot import Foot
from mudforce.model.parameters import WATER_CONTENT_RANGE, MudParameters

__all__ = [
    "DEFAULT_FORCE_GAIN_UNCERTAINTY",
    "MAX_DEPTH_OFFSET",
    "MAX_FORCE_LAG",
    "MIN_HALF_WIDTH",
    "NEAR_LIMITS_WARNING",
    "OTHER_MUD_WARNING",
    "REST_SPEED",
    "TAIL_SHARE_WARNING",
    "Identification",
    "identify_water_content",
]

#: Smallest half-width of the interval [-] (0.25 percentage points of water content).
MIN_HALF_WIDTH = 0.0025

#: Most grid points of identify's scan [-] (10**9 hung allocating the grid).
_MAX_POINTS = 100_000
_FLOAT_MAX = float(np.finfo(np.float64).max)  # the largest finite float64: a bound beyond it is no number to search
#: Largest surface offset of the depth that identify fits [m] (+-10 mm).
MAX_DEPTH_OFFSET = 0.01
#: Largest force lag (first-order time constant) that identify fits [s] (50 ms).
MAX_FORCE_LAG = 0.05
#: The lag's shape (:func:`identify_water_content`'s fit with a pure delay in place of the low-pass, whose reading
#: counts in the lag's standard error): its start's least delay [s] and its evaluations [-] (ours).
_SHAPE_START = 0.005
_SHAPE_EVALUATIONS = 20
#: The offset that fit reads counts in the offset's standard error where its sum of squares is within this many
#: residual variances of the low-pass fit's (chi-squared's 95 % quantile, one degree of freedom; ours).
_SHAPE_OFFSET_CHI2 = 3.841
#: Half-widths of the secants that read the surface offset's [m] and the force lag's [s] part in their standard
#: errors (:func:`_nuisance_stderr`; ours): 0.5 mm and 2 ms, a few times what the bench's recordings read them to,
#: and wide enough to step over a branch switch that a move of a few micrometres makes at one sample.
_NUISANCE_SECANTS = (0.0005, 0.002)
#: Half-width of the secant that reads the water content's column of the same Jacobian [-] (ours): the interval's
#: smallest half-width, :data:`MIN_HALF_WIDTH`. The fit's own derivative (a step of 1e-4) read the evidence's spread
#: over the contact episodes on one robot recording 1.69 points on one machine and 1.90 on another, its last bits
#: (numpy's vector kernels) moving a neck across a sample; over the secants 1.77 on both (to 1e-8).
_WATER_SECANT = MIN_HALF_WIDTH
#: The offsets [m] about each half-rate fit's at which the rate check reads the offset's move on a profile (ours).
_OFFSET_PROFILE = np.linspace(-2e-4, 2e-4, 21)
#: The rate check's shift [-] above which identify warns that the model at the data's rate does not follow the
#: motion closely (0.5 points; ours). On the sensor-chain bench the gait walks reach it only at 20 Hz, but most MuJoCo
#: robot recordings reach it at every rate, 100 Hz included (docs/estimation.md, "identify's rate check on the MuJoCo
#: robots": the check reads turns on their branches, so it also holds an error of the robots' that is not the rate's).
_RATE_SHIFT_WARNING = 0.005
#: The force gain is read on a grid of this many uncertainties about 1 (ours) ...
_GAIN_STEPS = np.linspace(-2.0, 2.0, 9)
#: ... where the least squares' cost at both neighbours of the grid's least (inside the grid, off 1) is at least this
#: many times its own (ours; a looser reading, the parabola's rise, read gains where a kinked cost misled it)
_GAIN_SHARPNESS = 1.25
#: A gain read further off 1 than this many force gain uncertainties is warned of (ours): on the bench's 5 % gain rows
#: it reads 0.944-0.960 and 1.039-1.057, so a gain read just beyond the uncertainty is the uncertainty itself
_GAIN_WARNING = 1.5
#: The joint fit also starts from the scan's second valley where one is this far [-] from the best (0.5 points) and
#: reads at most this many times its sum of squares [-] (ours, 2026-11-30): below the family's row at 30 % the force
#: falls steeply with the water content and above it barely (its RMS on a gait 10.9 -> 10.5 N from 30 to 35 %), so
#: the cost over the water content has a narrow valley below the row and a broad one above it, and the surface
#: offset decides which is deeper. A deep robot at 29.5 % sampled at 50 Hz read 31.3 % from the broad valley at the
#: scan's offset where the narrow one, its offset refitted, fits better (RMSE 0.60 against 0.76 N)
_SECOND_VALLEY_GAP = 0.005
_SECOND_VALLEY_RATIO = 4.0
#: Largest mean square of the standardised residual [-] that another mud (the model's own parameters varied off the
#: family) may explain before the misfit flag fires (:attr:`Identification.other_mud`; ours, chosen on the misfit-flag
#: bench: docs/estimation.md, "What another mud explains").
OTHER_MUD_WARNING = 0.9
#: The parameters the off-family test varies, each by a relative step of :data:`_OTHER_MUD_STEP` (every parameter of
#: Table I but the density, which only scales the drag with lambda).
_OTHER_MUD_PARAMETERS = ("k_m_i", "b_m_i", "k_m_w", "b_m_w", "alpha", "beta", "sigma_y", "zeta", "omega_0", "lambda_")
_OTHER_MUD_STEP = 1e-3
#: Step of the member's scan of the family's range [-] (0.5 points; ours): on the robot recordings of the sensor-chain
#: bench the statistic's minimum over the water content is about a point wide, and it has local minima (a branch
#: read differently at a sample makes it jump), so the scan covers the whole range, not only the interval.
_MEMBER_STEP = 0.005
#: Half-width held about the member [-] when the interval is extended to it (ours; chosen on the sensor-chain
#: bench's seed 1, docs/estimation-history.md, "identify's interval reaches the member that fits").
_MEMBER_MARGIN = MIN_HALF_WIDTH
#: Spacing of the grid of water contents whose statistic the interval and the flag read [-] (0.25 points; ours).
_PASS_STEP = 0.0025
#: A grid point whose statistic (its square root, the depth offset and force lag held at the estimate's) reads above
#: this [-] is refitted only when among the :data:`_PASS_LOWEST` lowest (ours; a screen for time: without it, on the
#: bench's seeds 1 and 3, 8 of 743 intervals came out wider, by 5.5 points in all, at about 4 times the refits' cost).
_PASS_SCREEN = 2.0
#: How many of the grid's lowest points are refitted whatever their statistic [-] (ours).
_PASS_LOWEST = 6
#: The refit's first search: force lags [s] at the estimate's depth offset, then depth offsets about the estimate's
#: [m] at the best lag (ours; a bounded search on each follows).
_REFIT_LAGS = np.array([0.0, 0.005, 0.01, 0.02, 0.03, 0.04, 0.05])
_REFIT_OFFSETS = np.array([-4, -2, -1, 0, 1, 2, 4]) * 1e-3
#: Half-widths of the refit's bounded searches about the best of the first: force lag [s] and depth offset [m] (ours).
_REFIT_LAG_SPAN = 0.01
_REFIT_OFFSET_SPAN = 0.002


@dataclass(frozen=True, eq=False)
class Identification:
    """The water content that explains a trial best.

    Attributes
    ----------
    water_content : float
        Best estimate [-] (a fraction: 0.23 is 23%): least squares' (``least_squares_water_content``), or, on the
        general path, ``misfit_water_content`` where least squares' own misfit statistic fails
        (:data:`~mudforce.estimation.calibration.fit.MISFIT_WARNING_RATIO`) and a member explains the data better
        with the depth offset and the force lag refitted there (ours; docs/estimation-history.md, "identify's
        estimate at the misfit member"). The interval holds it +-:data:`MIN_HALF_WIDTH`.
    interval : tuple of float
        Confidence interval [-] at ``level``, clipped to the family's range.
    rmse : float
        RMS force residual at the least-squares fit [N] (``least_squares_water_content``; as ``grid_rmse``, ``bias``,
        ``depth_offset``, ``force_lag`` and their standard errors, which are that fit's).
    level : float
        Confidence level of ``interval`` [-].
    grid, grid_rmse : ndarray
        Water contents scanned [-] and the RMS residual at each [N].
    warnings : tuple of str
    force_noise : float
        The trial's force noise, measured independently of the family [N].
    noise_floor : float
        The RMSE a member of the family that is right would leave [N]: the
        force noise, the depth noise carried through and the model's
        discretisation error, each at its own sample (``rmse / misfit_ratio``).
    misfit_ratio : float
        The RMS of the residuals each divided by its own floor [-] (so ``rmse / noise_floor``), each sample
        counting at most five floors (a sample whose branch the labels got wrong is not an off-family mud):
        about 1 when the family explains the trial to the noise. On the general path it is read where it is
        least: at the estimate, or at ``misfit_water_content`` with the depth offset and the force lag refitted
        there, when a water content the interval holds explains the data better; there, where the foot may be
        stuck, the model is read as the set of the relaxations a stuck foot may have had (as ``tail_share`` and
        ``other_mud``; docs/estimation.md, "A stuck foot read as a set").
    off_family : float
        How far the data are off the family [N]: the RMS of the residual in
        excess of the noise, ``sqrt(max(rmse^2 - noise_floor^2, 0))``.
    bias : float
        The sensor bias removed [N].
    bias_method : str
        ``"tared"`` (pre-contact samples, refined) or ``"estimated"`` (a free parameter).
    bias_stderr : float
        Standard error of ``bias`` [N]: the residual scatter over the samples
        (and the pre-contact ones), widened for the residuals' correlation; on a tared trial of a general
        motion, in quadrature with the refinement's move off the tare (the model's own mean error, which
        the refinement cannot tell from the bias's).
    depth_offset, depth_offset_stderr : float
        The surface offset fitted [m]: the model follows ``depth + depth_offset``
        (a depth that reads 2 mm too deep gives -0.002); NaN on the protocol path.
    force_lag, force_lag_stderr : float
        The force lag fitted [s]: the time constant of a first-order low-pass on the model's force (a pure delay
        of ``d`` reads up to about ``d`` on a robot's trot, and under 1 ms for 5-10 ms on a smooth gait walk);
        NaN on the protocol path. The two standard errors add in quadrature the scatter (least squares' or, where
        larger, the spread over the contact episodes, each read on secants 0.5 mm and 2 ms wide), the rate check's
        move of each, the move of each under a further gain change of ``force_gain_uncertainty`` (the refits of
        ``gain_shift``), and the misfit's worst case (:func:`_nuisance_stderr`); the lag's also the lag's shape: the
        mean delay the same fit reads with a pure delay in place of the low-pass, less the lag; the offset's the
        offset that fit reads, less the offset, where it explains the data as well. On the
        sensor-chain bench each holds its truth within three of them (docs/estimation.md, "The nuisances' standard
        errors").
    force_gain_uncertainty : float
        The force gain's relative uncertainty assumed [-] (an input).
    gain_shift : float
        The largest water-content shift [-] a gain change of ``force_gain_uncertainty`` (up or down)
        causes; the interval is widened on each side by the shift towards it.
    force_gain : float
        The force sensor's gain read from the recording [-] (the measured force over the mud's): the estimate, the
        interval and the floors are read with the force divided by it. 1 where the recording does not determine it
        (the least-squares cost over a grid of gains within two ``force_gain_uncertainty`` of 1 has no sharp least
        inside it: a shallow recording, or a misfit the gain does not explain) and with ``force_gain_uncertainty``
        0 (ours; docs/estimation.md, "The force gain, read where the recording determines it"). Where it was
        read, ``gain_shift`` is the shift of a further change of ``force_gain_uncertainty`` about it.
    discretisation : float
        The model's own discretisation error at the data's rate [N] (RMS over the samples); it
        enters the misfit statistic sample by sample, excusing only the samples where it is large.
    rest_fraction : float
        Share of the samples read through the rest band [-]: the foot at rest in the mud, or its motion
        changing direction or stopping at the sample.
    rate_shift : float
        The rate check [-]: how far the estimate moves when the model runs on every other sample (the even
        and the odd ones, nuisances refitted), plus how far it moves when the turns are read on their branches
        rather than through the rest band: the model's own error at the data's rate and at its turns, which the
        interval is widened by on each side (general path; 0 on a protocol).
    episode_half_width : float
        The interval's half-width [-] from the spread of the evidence over the contact episodes (a sandwich
        estimate); the interval holds at least this on each side (general path; 0 on a protocol).
    depth_noise : float
        The depth noise the trial was read with [m]: given, or estimated from the depth's quietest stretches
        (:func:`~mudforce.estimation.calibration.branches.estimate_quiet_noise`: a foot's ringing between the
        samples is motion, not noise) (general path; 0 on a protocol, whose fitted motion carries its own
        uncertainty).
    unresolved_depth : float
        The depth's high-frequency content above its noise [m] (ours): the whole record's third differences over the
        quiet estimate, in quadrature; motion the rate does not resolve (a foot ringing after its impacts). The
        branch labels follow it as motion, and the noise floor holds it, carried through the model's sensitivity to
        the depth, as the model's error at this rate. 0 when the depth noise is given, and on a protocol.
    misfit_shift : float
        The most the residual the noise does not explain could move the estimate [-] (its RMS, the larger of
        ``off_family`` and the moving samples' excess over the force and depth noise, the discretisation error
        included, over ``rms(dF/dW)``: Cauchy-Schwarz on a Gauss-Newton step); the interval holds at least this
        on each side (general path; 0 when the family explains the data to the noise, and on a protocol).
    member_water_content : float
        The water content [-] whose model explains the data best by the misfit statistic (each residual over its
        own floor, capped at five floors; the bias re-profiled under those weights), searched over the family's
        range; the interval holds it +-:data:`MIN_HALF_WIDTH`. It can differ from ``water_content``
        (least squares, every sample weighed alike) where a few samples with a large floor pull the estimate.
        NaN on a protocol and on a trial of fewer than 8 samples (not searched).
    misfit_water_content : float
        The water content [-] where ``misfit_ratio`` was read: ``water_content`` itself, or the member of a 0.25-point
        grid of the range (the member and the estimate added, then a search about the best) whose statistic is least
        with the depth offset and the force lag refitted there. The interval holds every grid point whose statistic
        so refitted passes (:data:`~mudforce.estimation.calibration.fit.MISFIT_WARNING_RATIO`), so a quiet flag says
        that a member the interval holds explains the data to the floor. NaN where ``member_water_content`` is.
    least_squares_water_content : float
        The least-squares estimate [-] (every sample weighed alike, the depth offset and the force lag fitted jointly):
        the fit ``rmse``, ``bias``, ``depth_offset`` and ``force_lag`` belong to. Equal to ``water_content`` unless
        that was moved to ``misfit_water_content``. NaN where the result was built without it.
    tail_share : float
        The share of the samples [-] whose residual lies beyond three noise floors at the least misfit statistic
        found (its water content, depth offset and force lag; the model read as a set where the foot may be stuck,
        and the bias re-profiled against it): the misfit flag's second reading (:data:`TAIL_SHARE_WARNING`). NaN on
        a protocol trial and on fewer than 8 samples (not read).
    other_mud : float
        The mean square [-] of the standardised residual (each sample's over its floor, clipped as the statistic
        clips it) at the least misfit statistic found that another mud would explain: the model's own parameters
        varied off the family (:data:`_OTHER_MUD_PARAMETERS`), beyond what the water content, the depth offset, the
        force lag and the bias explain there (one Gauss-Newton step: a score test). The misfit flag's third reading
        (:data:`OTHER_MUD_WARNING`): a mud that the family approaches but does not hold (alpha x2 read at the dry
        edge) leaves a misfit that the statistic reads as little more than noise but that other parameters explain.
        NaN where ``tail_share`` is.
    """

    water_content: float
    interval: tuple[float, float]
    rmse: float
    level: float
    grid: np.ndarray
    grid_rmse: np.ndarray
    warnings: tuple[str, ...] = ()
    force_noise: float = math.nan
    noise_floor: float = math.nan
    misfit_ratio: float = math.nan
    off_family: float = math.nan
    bias: float = math.nan
    bias_method: str = "tared"
    bias_stderr: float = math.nan
    depth_offset: float = math.nan
    depth_offset_stderr: float = math.nan
    force_lag: float = math.nan
    force_lag_stderr: float = math.nan
    force_gain_uncertainty: float = 0.0
    gain_shift: float = 0.0
    force_gain: float = 1.0
    discretisation: float = 0.0
    rest_fraction: float = 0.0
    rate_shift: float = 0.0
    episode_half_width: float = 0.0
    misfit_shift: float = 0.0
    depth_noise: float = math.nan
    unresolved_depth: float = 0.0
    member_water_content: float = math.nan
    misfit_water_content: float = math.nan
    least_squares_water_content: float = math.nan
    tail_share: float = math.nan
    other_mud: float = math.nan

    @property
    def low(self) -> float:
        """Lower end of :attr:`interval` [-] (as :attr:`mudforce.TrackEstimate.low`)."""
        return self.interval[0]

    @property
    def high(self) -> float:
        """Upper end of :attr:`interval` [-] (as :attr:`mudforce.TrackEstimate.high`)."""
        return self.interval[1]

    @property
    def model_misses_data(self) -> bool:
        """True when the RMSE exceeds the noise floor by more than :data:`MISFIT_WARNING_RATIO`, when more than
        :data:`TAIL_SHARE_WARNING` of the samples lie beyond three floors (:attr:`tail_share`), when another mud
        explains more than :data:`OTHER_MUD_WARNING` of the standardised residual's mean square (:attr:`other_mud`),
        or when two of these three readings are past :data:`NEAR_LIMITS_WARNING` of their limits."""
        return (self.misfit_ratio > MISFIT_WARNING_RATIO or self.tail_share > TAIL_SHARE_WARNING
                or self.other_mud > OTHER_MUD_WARNING
                or _near_limits(self.misfit_ratio, self.tail_share, self.other_mud))

    def to_dict(self) -> dict[str, object]:
        """The JSON object of ``mudforce identify --json``.

        Keys: ``water_content`` (the nearest water content of the family),
        ``nearest_water_content`` (the same, named for what it is when the
        data are off the family), ``interval``, ``rmse_N``, ``level``,
        ``force_noise_N``, ``noise_floor_N``, ``misfit_ratio``, ``model_misses_data``,
        ``off_family_N``, ``bias_N``, ``bias_method``, ``bias_stderr_N``,
        ``depth_offset_m``, ``depth_offset_stderr_m``, ``force_lag_s``,
        ``force_lag_stderr_s``, ``force_gain_uncertainty``, ``gain_shift``, ``force_gain``,
        ``discretisation_N``, ``rest_fraction``, ``rate_shift``, ``episode_half_width``, ``misfit_shift``,
        ``depth_noise_m``, ``unresolved_depth_m``, ``member_water_content``, ``misfit_water_content``,
        ``least_squares_water_content``, ``tail_share``, ``other_mud``, ``warnings``.
        """

        def finite(x: float) -> float | None:
            return float(x) if math.isfinite(x) else None

        return {
            "water_content": self.water_content,
            "nearest_water_content": self.water_content,
            "interval": [self.interval[0], self.interval[1]],
            "rmse_N": self.rmse,
            "level": self.level,
            "force_noise_N": finite(self.force_noise),
            "noise_floor_N": finite(self.noise_floor),
            "misfit_ratio": finite(self.misfit_ratio),
            "model_misses_data": self.model_misses_data,
            "off_family_N": finite(self.off_family),
            "bias_N": finite(self.bias),
            "bias_method": self.bias_method,
            "bias_stderr_N": finite(self.bias_stderr),
            "depth_offset_m": finite(self.depth_offset),
            "depth_offset_stderr_m": finite(self.depth_offset_stderr),
            "force_lag_s": finite(self.force_lag),
            "force_lag_stderr_s": finite(self.force_lag_stderr),
            "force_gain_uncertainty": self.force_gain_uncertainty,
            "gain_shift": self.gain_shift,
            "force_gain": self.force_gain,
            "discretisation_N": self.discretisation,
            "rest_fraction": self.rest_fraction,
            "rate_shift": self.rate_shift,
            "episode_half_width": self.episode_half_width,
            "misfit_shift": self.misfit_shift,
            "depth_noise_m": finite(self.depth_noise),
            "unresolved_depth_m": self.unresolved_depth,
            "member_water_content": finite(self.member_water_content),
            "misfit_water_content": finite(self.misfit_water_content),
            "least_squares_water_content": finite(self.least_squares_water_content),
            "tail_share": finite(self.tail_share),
            "other_mud": finite(self.other_mud),
            "warnings": list(self.warnings),
        }


def _edge(ssr: Callable[[float], float], level: float, inside: float, outward: np.ndarray, limit: float) -> float:
    """Where ``ssr`` rises through ``level`` walking from ``inside`` along ``outward`` (else ``limit``)."""
    previous = inside
    for w in outward:
        if ssr(float(w)) > level:
            return float(brentq(lambda x: ssr(x) - level, previous, float(w), xtol=1e-7))
        previous = float(w)
    return float(limit)


def _sandwich_covariance(jac: np.ndarray, r: np.ndarray, contact: np.ndarray) -> tuple[np.ndarray, int]:
    """The fit's covariance from the spread of the evidence over the contact episodes, and their count (ours).

    A sandwich (cluster-robust) estimate: the fit's score ``J_k r_k`` summed
    over each contact episode (the samples from one touchdown to the next;
    eight equal blocks when there are fewer than four), ``cov = A^-1 (sum_b
    g_b g_b^T) A^-1 B / (B - 1)`` with ``A = J^T J``. Unlike ``s^2 (J^T J)^-1``
    it does not assume the residuals are independent of where a parameter is
    read: a misfit concentrated in the strides that carry the evidence
    (reversals or touchdowns between two samples, a delay read as a lag and
    an offset) widens it.
    """
    n = r.size
    starts = contact & ~np.concatenate([[False], contact[:-1]])
    block = np.maximum(np.cumsum(starts) - 1, 0)
    count = int(block[-1]) + 1 if n else 0
    if count < 4:
        count = 8
        block = (np.arange(n) * count) // max(n, 1)
    scores = np.zeros((count, jac.shape[1]))
    np.add.at(scores, block, jac * r[:, None])
    inv = np.linalg.pinv(jac.T @ jac)
    return inv @ (scores.T @ scores) @ inv * count / (count - 1), count


def _secant_jacobian(residual: Callable[[np.ndarray], np.ndarray], x: np.ndarray,
                     water_bounds: tuple[float, float]) -> np.ndarray:
    """The joint fit's Jacobian at ``x`` (water content [-], surface offset [m], force lag [s]) read as central
    secants [N per unit] (ours): :data:`_WATER_SECANT` and :data:`_NUISANCE_SECANTS` to either side, within the bounds
    (the water content's ``water_bounds``). ``residual`` maps ``x`` to the residuals [N].

    A model run at the samples is stepped in each of the three (a branch switch, the rest band's edge, a neck a
    sample early or late); least squares' finite differences (a step of 1e-4) cross such steps or not by the last
    bits of the arithmetic, and read slopes a thousand times too steep where they do. The evidence's spread over the
    contact episodes, the nuisances' correlation with the water content, the misfit's worst case and the nuisances'
    standard errors all read this one.
    """
    columns = []
    for j, (step, low, high) in enumerate(((_WATER_SECANT, *water_bounds),
                                           (_NUISANCE_SECANTS[0], -MAX_DEPTH_OFFSET, MAX_DEPTH_OFFSET),
                                           (_NUISANCE_SECANTS[1], 0.0, MAX_FORCE_LAG))):
        below, above = x.copy(), x.copy()
        below[j], above[j] = max(x[j] - step, low), min(x[j] + step, high)
        columns.append((residual(above) - residual(below)) / (above[j] - below[j]))
    return np.column_stack(columns).astype(np.float64)


def _nuisance_stderr(wide: np.ndarray, r: np.ndarray, contact: np.ndarray, s2: float, moves: np.ndarray,
                     unexplained: float) -> np.ndarray:
    """Standard errors of the joint fit's (water content, surface offset [m], force lag [s]) (ours; the last two
    are the ones reported).

    Three parts in quadrature, each measured on the sensor-chain bench to be needed (docs/estimation.md, "The
    nuisances' standard errors"):

    - the scatter: least squares' ``s^2 (J^T J)^-1`` or, where larger, the spread over the contact episodes
      (:func:`_sandwich_covariance`), with the offset's and the lag's columns of ``J`` read as secants over
      :data:`_NUISANCE_SECANTS` on either side of the fit. The fit's own derivatives (a step of 1e-4 m or s) cross
      the steps of a model run at the samples (a branch switch, the rest band's edge, a neck a sample early or
      late): they read slopes a thousand times too steep, and errors of nanometres;
    - ``moves``, each nuisance's systematic moves: the rate check's (the same refits on the even and the odd samples
      and with the turns on their branches: the model's own error at the data's rate, which the scatter does not
      see) and, for the lag, its shape's (the mean delay a pure delay in its place reads, less the lag), and for the
      offset the offset that fit reads, less the offset, where its sum of squares is within
      :data:`_SHAPE_OFFSET_CHI2` residual variances of the low-pass fit's; and each one's move under the force gain's
      uncertainty (the joint fit on the force divided by the gain times ``1 +- force_gain_uncertainty``);
    - the misfit's worst case, ``unexplained / rms(J_j)`` (as the interval's ``misfit_shift``): a residual the
      family cannot explain (a delay read as a lag, the depth's unresolved motion) moves a nuisance by at most that.

    ``wide`` is the joint fit's Jacobian read as secants (:func:`_secant_jacobian`) [N per unit], ``r`` the
    residuals [N], ``contact`` where the model's force is not nil, ``s2`` the residual variance [N^2] (widened for
    the residuals' correlation), ``unexplained`` the RMS residual beyond the noise [N].
    """
    scatter = np.diag(np.linalg.pinv(wide.T @ wide)) * s2
    spread, _ = _sandwich_covariance(wide, r, contact)
    variance = np.maximum(np.maximum(scatter, np.diag(spread)), 0.0) + moves**2
    sensitivity = np.sqrt(np.mean(wide**2, axis=0))
    worst = np.divide(unexplained, sensitivity, out=np.zeros(3), where=sensitivity > 0.0)
    return np.asarray(np.sqrt(variance + worst**2), dtype=np.float64)


def _scan_minimum(cost: Callable[[float], float], points: np.ndarray, *, ties_to_search: bool) -> float:
    """The water content [-] minimising ``cost`` (ours): the best of the increasing ``points`` [-], then a bounded
    search between its neighbours, taken where it reads less than that point (or as little, ``ties_to_search``)."""
    values = [cost(float(w)) for w in points]
    j = int(np.argmin(values))
    bracket = (float(points[max(j - 1, 0)]), float(points[min(j + 1, points.size - 1)]))
    found = minimize_scalar(cost, bounds=bracket, method="bounded", options={"xatol": 1e-5})
    better = float(found.fun) <= values[j] if ties_to_search else float(found.fun) < values[j]
    return float(found.x) if better else float(points[j])


def _local_minima(costs: np.ndarray) -> np.ndarray:
    """Where ``costs`` is below both neighbours (an end: below its one), as a mask."""
    inner = np.zeros(costs.size, dtype=bool)
    if costs.size > 1:
        inner[1:-1] = (costs[1:-1] < costs[:-2]) & (costs[1:-1] < costs[2:])
        inner[0], inner[-1] = costs[0] < costs[1], costs[-1] < costs[-2]
    return inner


def _second_valley(grid: np.ndarray, costs: np.ndarray, best: int) -> float | None:
    """The water content [-] of the scan's second valley (ours): the lowest local minimum of ``costs`` over ``grid``
    [-] at least :data:`_SECOND_VALLEY_GAP` from the best point ``best`` (an index) and within
    :data:`_SECOND_VALLEY_RATIO` times its cost; None where there is none."""
    inner = _local_minima(costs)
    inner &= np.abs(grid - grid[best]) >= _SECOND_VALLEY_GAP - 1e-12
    inner &= costs <= _SECOND_VALLEY_RATIO * costs[best]
    if not inner.any():
        return None
    candidates = np.flatnonzero(inner)
    return float(grid[candidates[int(np.argmin(costs[candidates]))]])


def _near_limits(ratio: float, tail_share: float, other_mud: float) -> bool:
    """True when two of the misfit flag's three readings (the misfit ratio [-], the tail's share [-], what another mud
    explains [-]) are past :data:`NEAR_LIMITS_WARNING` of their limits (ours; a NaN reading is past none)."""
    shares = (ratio / MISFIT_WARNING_RATIO, tail_share / TAIL_SHARE_WARNING, other_mud / OTHER_MUD_WARNING)
    return sum(x > NEAR_LIMITS_WARNING for x in shares) >= 2


def _standardised(model_set: Callable[[MudParameters, float, float], tuple[np.ndarray, np.ndarray, np.ndarray]],
                  measured: np.ndarray, floor: np.ndarray, q: MudParameters, offset: float, lag: float,
                  bias: float = 0.0) -> np.ndarray:
    """Each sample's residual over its ``floor`` [N] (:func:`_band_residual` of ``measured + bias`` [N] against the
    set ``model_set(q, offset, lag)``: :func:`_model_set` of the parameters ``q``, the depth offset ``offset`` [m]
    and the force lag ``lag`` [s])."""
    model, low, high = model_set(q, offset, lag)
    out: np.ndarray = _band_residual(model, low, high, measured + bias, np.ones(model.size, dtype=bool)) / floor
    return out


def _other_mud(residual: Callable[..., np.ndarray], family: Callable[[float], MudParameters],
               at: tuple[float, float, float], bounds: tuple[float, float]) -> float:
    """The mean square [-] of the standardised ``residual`` that the mud's own parameters explain beyond the water
    content, the depth offset, the force lag and the bias, at ``at`` = (water content [-], offset [m], lag [s]).

    ``residual(q, offset, lag, bias=0)`` is :func:`_standardised` for parameters ``q``. Each column is the residual's
    change over a small step of one quantity (the water content by 0.2 points inward of ``bounds``, the offset by
    0.2 mm, the lag by 1 ms, the bias by 0.05 N, each of :data:`_OTHER_MUD_PARAMETERS` by :data:`_OTHER_MUD_STEP` of
    itself); the residual, clipped at +-5 as the misfit statistic clips it (:data:`_MISFIT_CLIP`), is fitted on the
    first four columns and on all of them, and the result is the drop of its sum of squares over the samples: the
    score test of the family against the model's whole parameter space, for the clipped statistic (ours).
    """
    w, offset, lag = at
    q = family(w)
    raw = residual(q, offset, lag)
    bound = math.sqrt(_MISFIT_CLIP)
    e = np.clip(raw, -bound, bound)
    dw = 0.002 if w + 0.002 <= bounds[1] else -0.002
    doff = 2e-4 if offset + 2e-4 <= MAX_DEPTH_OFFSET else -2e-4
    dlag = 1e-3 if lag + 1e-3 <= MAX_FORCE_LAG else -1e-3
    nuisance = [residual(family(w + dw), offset, lag) - raw, residual(q, offset + doff, lag) - raw,
                residual(q, offset, lag + dlag) - raw, residual(q, offset, lag, 0.05) - raw]
    other = []
    for name in _OTHER_MUD_PARAMETERS:
        value = getattr(q, name)
        try:
            moved = replace(q, **{name: value * (1.0 + _OTHER_MUD_STEP)})
        except InputError:  # at the edge of the parameter's range: the step the other way
            moved = replace(q, **{name: value * (1.0 - _OTHER_MUD_STEP)})
        other.append(residual(moved, offset, lag) - raw)

    def unexplained(columns: list[np.ndarray]) -> float:
        a = np.stack(columns, axis=1)
        step = np.linalg.lstsq(a, e, rcond=None)[0]
        left = e - a @ step
        return float(left @ left)

    return max(unexplained(nuisance) - unexplained(nuisance + other), 0.0) / float(e.size)


def _least_member(statistic: Callable[[float], float], estimate: float, lo: float, hi: float) -> float:
    """The water content [-] minimising ``statistic`` over ``[lo, hi]`` [-] (ours): a scan at :data:`_MEMBER_STEP` with
    ``estimate`` [-] added, then a bounded search between the best point's neighbours."""
    points = np.union1d(np.linspace(lo, hi, max(math.ceil((hi - lo) / _MEMBER_STEP), 1) + 1), [estimate])
    return _scan_minimum(statistic, points, ties_to_search=False)


def _refit_nuisances(root: Callable[[float, float, float], float], w: float, offset: float, lag: float,
                     warm: tuple[float, float] | None = None,
                     stop_at: float | None = None) -> tuple[float, float, float]:
    """The misfit statistic's square root [-] at water content ``w`` [-], the depth offset and the force lag refitted.

    ``root(w, offset, lag)`` is the statistic's square root with the model at ``depth + offset`` [m] through a force
    lag ``lag`` [s]. The search (ours) starts at the estimate's ``offset`` [m] and ``lag`` [s] and at ``warm`` (the
    offset [m] and lag [s] refitted at a neighbouring water content, when given), tries the lags of
    :data:`_REFIT_LAGS`, then the offsets ``offset + _REFIT_OFFSETS`` (within +-:data:`MAX_DEPTH_OFFSET`), then a
    bounded search over the lag and one over the offset about the best. It stops as soon as the statistic reads
    ``stop_at`` [-] or less. Returns ``(root, offset [m], lag [s])`` at the best point found: a local search, so an
    upper bound on the statistic's least over the two nuisances.
    """
    best = (root(w, offset, lag), offset, lag)
    if warm is not None:
        best = min(best, (root(w, warm[0], warm[1]), warm[0], warm[1]))

    def done() -> bool:
        return stop_at is not None and best[0] <= stop_at

    if done():
        return best
    for lg in _REFIT_LAGS:
        best = min(best, (root(w, offset, float(lg)), offset, float(lg)))
        if done():
            return best
    for step in _REFIT_OFFSETS:
        o = float(np.clip(offset + step, -MAX_DEPTH_OFFSET, MAX_DEPTH_OFFSET))
        best = min(best, (root(w, o, best[2]), o, best[2]))
        if done():
            return best
    o, lg = best[1], best[2]
    found = minimize_scalar(lambda x: root(w, o, float(x)),
                            bounds=(max(lg - _REFIT_LAG_SPAN, 0.0), min(lg + _REFIT_LAG_SPAN, MAX_FORCE_LAG)),
                            method="bounded", options={"xatol": 5e-4, "maxiter": 8})
    if float(found.fun) < best[0]:
        best = (float(found.fun), o, float(found.x))
    if done():
        return best
    lg = best[2]
    found = minimize_scalar(lambda x: root(w, float(x), lg),
                            bounds=(max(o - _REFIT_OFFSET_SPAN, -MAX_DEPTH_OFFSET),
                                    min(o + _REFIT_OFFSET_SPAN, MAX_DEPTH_OFFSET)),
                            method="bounded", options={"xatol": 1e-4, "maxiter": 8})
    if float(found.fun) < best[0]:
        best = (float(found.fun), float(found.x), lg)
    return best


def _passing_members(root: Callable[[float, float, float], float], points: np.ndarray, held: np.ndarray,
                     member: float, interval: tuple[float, float], offset: float, lag: float,
                     bounds: tuple[float, float]) -> tuple[float, float, float, float]:
    """The interval holding every water content that passes, and the least statistic found (ours; issue 23).

    ``points`` [-] are the water contents to read (a grid, the member and the estimate), ``held`` [-] the statistic's
    square root at each with the estimate's depth offset ``offset`` [m] and force lag ``lag`` [s], ``member`` [-] the
    member (its held statistic among ``held``), ``interval`` [-] the interval so far, ``bounds`` [-] the family's
    range. A point passes when its statistic reads :data:`MISFIT_WARNING_RATIO` or less, held or with the offset and
    the lag refitted there (:func:`_refit_nuisances`, warm-started from the previous point refitted when it is the
    grid's neighbour). Screen (for time): only points held at most :data:`_PASS_SCREEN`, or among the
    :data:`_PASS_LOWEST` lowest, are refitted; and where the member passes held (the flag is then quiet whatever
    the refits say) only those outside the interval built so far, each refit stopping once it passes. Where it does
    not, every screened point is refitted in full and then the water content searched within +-0.5 points of the best
    refitted one (the point found held by the interval if it passes). Returns ``(low, high, least, at)``: the
    interval [-] (the one given and every point that passes), the least square-rooted statistic found [-] and the
    water content [-] it was read at.
    """
    lo, hi = bounds
    passing = [float(w) for w, h in zip(points, held, strict=True) if h <= MISFIT_WARNING_RATIO]
    held_member = float(held[int(np.flatnonzero(points == member)[0])])
    full = held_member > MISFIT_WARNING_RATIO
    lowest = set(np.argsort(held, kind="stable")[:_PASS_LOWEST].tolist())
    refits: dict[float, tuple[float, float, float]] = {}
    previous: tuple[float, float, float] | None = None
    for j, w in enumerate(points.tolist()):
        if held[j] <= MISFIT_WARNING_RATIO or not (held[j] <= _PASS_SCREEN or j in lowest):
            continue
        if not full and min([interval[0], *passing]) <= w <= max([interval[1], *passing]):
            continue
        near = previous is not None and abs(previous[0] - w) <= 1.01 * _PASS_STEP
        warm = (previous[1], previous[2]) if near and previous is not None else None
        refits[w] = found = _refit_nuisances(root, w, offset, lag, warm, None if full else MISFIT_WARNING_RATIO)
        previous = (w, found[1], found[2])
        if found[0] <= MISFIT_WARNING_RATIO:
            passing.append(w)
    least, at = held_member, member
    for w, found in refits.items():
        if found[0] < least:
            least, at = found[0], w
    if full:  # the best refitted point's neighbourhood, the water content searched too
        centre = min(refits, key=lambda x: refits[x][0]) if refits else member
        warm = refits[centre][1:] if refits else None
        search = minimize_scalar(lambda x: _refit_nuisances(root, float(x), offset, lag, warm)[0],
                                 bounds=(max(centre - 2 * _PASS_STEP, lo), min(centre + 2 * _PASS_STEP, hi)),
                                 method="bounded", options={"xatol": 5e-4, "maxiter": 6})
        if float(search.fun) < least:
            least, at = float(search.fun), float(search.x)
        if float(search.fun) <= MISFIT_WARNING_RATIO:
            passing.append(float(search.x))
    low, high = max(min([interval[0], *passing]), lo), min(max([interval[1], *passing]), hi)
    return low, high, least, at


def _once_each(family: Callable[[float], MudParameters], lo: float, hi: float) -> Callable[[float], MudParameters]:
    """``family`` [-] -> :class:`MudParameters`, called once per water content (speed plumbing: an identify reads
    the family thousands of times, at a few hundred water contents; a family is a function of the water content).

    The family is called at ``lo`` and ``hi`` [-] here, the scan's first and last grid points: an end it refuses is
    refused as the bounds', naming the family's range (Table I's, for its own family), not as the first grid point
    past that range the scan met (``water content 0.35375 is outside Table I's range`` for bounds (0.2, 0.5))."""
    made: dict[float, MudParameters] = {}
    if not callable(family):
        raise InputError(f"family must be a function of the water content [-] returning MudParameters, got "
                         f"{type(family).__name__}")

    def once(w: float) -> MudParameters:
        q = made.get(w)
        if q is None:
            q = made[w] = family(w)
            if not isinstance(q, MudParameters):
                raise InputError(f"family({w:.6g}) must return MudParameters, got {type(q).__name__}")
        return q

    for end in (lo, hi):
        try:
            q = family(end)
        except InputError as err:
            low, high = WATER_CONTENT_RANGE
            where = f"[{low:g}, {high:g}]" if family == MudParameters.from_water_content else f"(the family: {err})"
            raise InputError(f"bounds ({lo:g}, {hi:g}) reach {end:g}, outside the family's range of water contents "
                             f"{where}; pass bounds within it (fractions: 0.25 means 25%)") from None
        if not isinstance(q, MudParameters):
            raise InputError(f"family({end:.6g}) must return MudParameters, got {type(q).__name__}")
        made[end] = q
    return once


@one_blas_thread
def identify_water_content(
    trial: Trial | PreparedTrial,
    foot: Foot | None = None,
    *,
    family: Callable[[float], MudParameters] = MudParameters.from_water_content,
    bounds: tuple[float, float] = WATER_CONTENT_RANGE,
    level: float = 0.95,
    points: int = 81,
    force_gain_uncertainty: float = DEFAULT_FORCE_GAIN_UNCERTAINTY,
    depth_noise: float | None = None,
) -> Identification:
    """Estimate the water content of one trial from a one-parameter family of parameter sets.

    Parameters
    ----------
    trial : Trial or PreparedTrial
        An intrude/hold/withdraw trial starting above the surface, or a trial of any motion.
    foot : Foot, optional
        The intruder; the paper's cuboid by default.
    family : callable
        Water content [-] -> :class:`MudParameters`; Table I, interpolated, by default.
    bounds : tuple of float
        Range of water contents to search [-], within the family's (Table I's, [0.15, 0.35], by default).
    level : float
        Confidence level of the interval, in (0, 1).
    points : int
        Grid points for the scan before refinement [-], at least 2 (the ends of ``bounds``).
    force_gain_uncertainty : float
        Relative uncertainty of the force sensor's gain [-], in [0, 0.5) (default 5 %): a gain
        error reads as stiffer or softer mud, so the interval is widened by the water-content
        shift a gain change of this size causes.

    depth_noise : float, optional
        The depth's noise [m] when the recording system knows it (:func:`prepare_trial
        <mudforce.estimation.calibration.preprocess.prepare_trial>`); None (default): estimated from the depth,
        and a warning says where that reading decides which samples are rest and the misfit flag leans on it (most
        of the floor, or the flag would fire without it: at a low rate a foot that never rests reads its motion
        between the samples as noise). Only for a raw :class:`Trial` (a prepared one already holds its noise).

    Returns
    -------
    Identification
    """
    if not isinstance(trial, (Trial, PreparedTrial)):
        raise InputError(f"trial must be a Trial or a PreparedTrial, got {type(trial).__name__}")
    if not is_real(level) or not 0.0 < level < 1.0:
        raise InputError(f"confidence level must be in (0, 1), got {shown(level)}")
    check_force_gain_uncertainty(force_gain_uncertainty)
    if not is_integer(points) or not 2 <= points <= _MAX_POINTS:  # one point searched [low, low]: always low
        raise InputError(f"points must be an integer in [2, {_MAX_POINTS}], got {shown(points)}")
    if foot is not None and not isinstance(foot, Foot):
        raise InputError(f"foot must be a Foot or None, got {type(foot).__name__}")
    foot = Foot.paper() if foot is None else foot
    lo, hi = bounds if isinstance(bounds, (tuple, list)) and len(bounds) == 2 else (math.nan, math.nan)
    # each end finite within float64 (math.isfinite raised OverflowError on 10**400); the message in one line
    if not (is_real(lo) and is_real(hi) and abs(lo) <= _FLOAT_MAX and abs(hi) <= _FLOAT_MAX and lo < hi):
        got = type(bounds).__name__ if not isinstance(bounds, (tuple, list)) else \
            "(" + ", ".join(shown(x) if is_real(x) else type(x).__name__ for x in bounds[:3]) \
            + (", ...)" if len(bounds) > 3 else ")")
        raise InputError(f"bounds must be (low, high) with low < high, both finite [-], got {got}")
    family = _once_each(family, float(lo), float(hi))
    if isinstance(trial, PreparedTrial) and depth_noise is not None:
        raise InputError(f"{trial.trial.name}: a prepared trial already holds its depth noise "
                         f"({trial.depth_noise * 1e3:.3g} mm); pass the raw Trial with depth_noise=, or prepare it "
                         "with prepare_trial(trial, depth_noise=...)")
    # what a file's reader would refuse (a force of 1e300 N overflowed the least squares, one sample indexed past)
    (trial.trial if isinstance(trial, PreparedTrial) else trial).check_bounds()
    tr = trial if isinstance(trial, PreparedTrial) else prepare_trial(trial, depth_noise=depth_noise,
                                                                       depth_noise_from="quiet")
    read_noise = depth_noise is None and not isinstance(trial, PreparedTrial)  # the depth noise read, not given
    check_force_varies(tr.trial.force, f"{tr.trial.name}: ", "trial")
    t = tr.time
    general = tr.motion is None
    raw = tr.trial.force

    def at_rest(time: np.ndarray, depth: np.ndarray, turns: bool = True) -> np.ndarray:
        """Samples read through the rest band (:func:`_rest_samples` on the general path; none on a protocol)."""
        if not general:
            return np.zeros(time.size, dtype=bool)
        return _rest_samples(time, depth, tr.depth_noise, turns)

    rest = at_rest(t, tr.depth)
    moving = ~rest

    def evaluate(w: float, offset: float, lag: float, gain: float = 1.0,
                 sel: slice = slice(None), turns: bool = True,
                 delay: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, int]:
        """Residual (model - measured / gain) [N], model force [N], measured force [N], bias [N], tare count.

        ``sel`` picks the samples the model is run on (every other one for the rate check); ``turns`` False reads
        the turns on their branches, not through the rest band (the rate check's turns part); ``delay`` [s] runs
        the model on the depth that much earlier (the lag's shape, in its standard error).
        """
        if not general:
            f = CHEN2024.force(t, tr.depth, family(w).as_array(), foot)
            r0 = f - tr.force / gain
            return r0 + tare_correction(r0, tr.precontact), f, tr.force, tr.bias, tr.precontact
        ts, zs, fs = t[sel], tr.depth[sel] + offset, raw[sel]
        if delay > 0.0:  # the depth between its samples is smooth (the force, with its neck breaking, is not)
            zs = np.interp(ts - delay, t, tr.depth) + offset
        still = rest if (sel == slice(None) and turns and delay == 0.0) else at_rest(ts, zs, turns=turns)
        f, low, high = _force_and_band(ts, zs, family(w), foot, lag)
        pre, bias = 0, 0.0
        if tr.precontact:  # re-tare from the samples before the first contact of the offset depth
            first_in = int(np.argmax(zs > 0.0))
            if first_in >= MIN_PRECONTACT_SAMPLES:
                pre, bias = first_in, float(np.mean(fs[:first_in]))
        meas = (fs - bias) / gain
        c = -float(np.sum((f - meas)[~still])) / (int(np.count_nonzero(~still)) + pre)
        meas = meas - c
        r = _band_residual(f, low, high, meas, still)
        return r, f, meas, bias + c * gain, pre

    def ssr_at(w: float, offset: float, lag: float, gain: float = 1.0, sel: slice = slice(None),
               turns: bool = True) -> float:
        r = evaluate(w, offset, lag, gain, sel, turns)[0]
        return float(r @ r)

    def joint_fit(residual: Callable[[np.ndarray], np.ndarray], start: np.ndarray, evaluations: int) -> OptimizeResult:
        """Least squares over (water content, surface offset, force lag) from ``start``, within their bounds."""
        return least_squares(residual, start,
                             bounds=([lo, -MAX_DEPTH_OFFSET, 0.0], [hi, MAX_DEPTH_OFFSET, MAX_FORCE_LAG]),
                             x_scale=np.array([0.01, 0.001, 0.005]), diff_step=1e-4, max_nfev=evaluations)

    def refit_from(w0: float, gain: float, sel: slice = slice(None), turns: bool = True) -> OptimizeResult:
        """The joint fit (20 evaluations) from water content ``w0`` [-] at the current offset and lag, with the force
        divided by ``gain`` [-], on the samples ``sel``, the turns read through the band unless ``turns`` is False:
        the gain's profile, the gain read, and the rate check's two parts each refit this way."""

        def residual(th: np.ndarray) -> np.ndarray:
            return evaluate(float(th[0]), float(th[1]), float(th[2]), gain, sel, turns)[0]

        return joint_fit(residual, np.array([w0, offset, lag]), 20)

    def best_w(cost: Callable[[float], float]) -> float:
        """The water content [-] minimising ``cost``: a coarse scan and the fine scan's valleys, then a bounded search
        about its best (the coarse scan alone, in 1-point steps, steps over the narrow valley below the family's 30 %
        row: a gain's shift on a robot at 29.5 % read 0.63 points where undoing the gain moves the estimate by 1.8)."""
        return _scan_minimum(cost, np.union1d(np.linspace(lo, hi, 21), valleys), ties_to_search=True)

    offset, lag = 0.0, 0.0
    if general:  # a coarse scan of the surface offset first: a few millimetres move the water content by points
        coarse = np.linspace(lo, hi, 21)
        scan = [(ssr_at(float(w), s0, 0.0), s0) for s0 in np.linspace(-0.8, 0.8, 5) * MAX_DEPTH_OFFSET
                for w in coarse]
        offset = float(min(scan)[1])
    grid = np.linspace(lo, hi, points)
    costs = np.array([ssr_at(float(w), offset, 0.0) for w in grid])
    k = int(np.argmin(costs))
    valleys = grid[_local_minima(costs)]
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, points - 1)]
    sol = minimize_scalar(lambda x: ssr_at(float(x), offset, 0.0), bounds=(a, b), method="bounded",
                          options={"xatol": 1e-6})
    w_best, c_best = (float(sol.x), float(sol.fun)) if sol.fun < costs[k] else (float(grid[k]), float(costs[k]))
    cov = None
    jac = None
    if general:  # the nuisances, jointly with the water content, from the best of the scan and its second valley
        starts = [w_best]
        second = _second_valley(grid, costs, k)
        if second is not None:
            starts.append(second)
        scan_offset = offset
        for n_start, w0 in enumerate(starts):
            joint = joint_fit(lambda th: evaluate(float(th[0]), float(th[1]), float(th[2]))[0],
                              np.array([w0, scan_offset, 0.0]), 60)
            if 2.0 * float(joint.cost) < c_best:
                w_best, offset, lag = (float(x) for x in joint.x)
                c_best = 2.0 * float(joint.cost)
                jac = np.asarray(joint.jac, dtype=np.float64)
            elif n_start == 0:  # the first start's Jacobian, unless the second valley fits better
                jac = np.asarray(joint.jac, dtype=np.float64)
    # the force gain, where the recording determines it (ours; docs/estimation.md, "The force gain, read where the
    # recording determines it"): the water content's own fit with the force divided by each gain of a grid over
    # +-2 uncertainties. A gain error scales every force alike, a change of water content does not (the relaxation,
    # the neck, the suction change their share), so on a deep or long recording the cost over the gain has a sharp
    # least; on a shallow one, or where the model misses the data by more than the gain explains, it is flat or
    # runs to an end, and the gain is left at 1 (the interval's gain shift still holds it)
    gain = 1.0
    profile: dict[float, float] = {}
    profile_fits: dict[float, np.ndarray] = {}  # (the joint refit at each gain of the profile: its offset and lag)
    if force_gain_uncertainty:
        gains = 1.0 + force_gain_uncertainty * _GAIN_STEPS
        fits = np.full(gains.size, c_best)
        for i, g in enumerate(gains.tolist()):
            if g == 1.0:
                continue
            profile[g] = best_w(partial(ssr_at, offset=offset, lag=lag, gain=g))
            # on a motion the offset and the lag refitted at each gain (held at 1's, they had taken part of it; the
            # refit starts where the held fit ends and never costs more)
            if general:
                refit = refit_from(profile[g], g)
                profile_fits[g] = np.asarray(refit.x, dtype=np.float64)
                fits[i] = 2.0 * float(refit.cost)
            else:
                fits[i] = ssr_at(profile[g], offset, lag, g)
        j = int(np.argmin(fits))
        if 0 < j < gains.size - 1 and gains[j] != 1.0 and min(fits[j - 1], fits[j + 1]) >= _GAIN_SHARPNESS * fits[j]:
            # the parabola's least through the grid's least and its two neighbours (both above it: a least between
            # them)
            step = float(gains[1] - gains[0])
            curve = float(fits[j - 1] - 2.0 * fits[j] + fits[j + 1])
            gain = float(gains[j]) + 0.5 * step * float(fits[j - 1] - fits[j + 1]) / curve
        if gain != 1.0 and general:  # the joint fit redone at the gain read
            joint = refit_from(best_w(partial(ssr_at, offset=offset, lag=lag, gain=gain)), gain)
            w_best, offset, lag = (float(x) for x in joint.x)
            c_best = 2.0 * float(joint.cost)
            jac = np.asarray(joint.jac, dtype=np.float64)
        elif gain != 1.0:  # a protocol trial: the water content alone
            w_best = best_w(partial(ssr_at, offset=offset, lag=lag, gain=gain))
            c_best = ssr_at(w_best, offset, lag, gain)
    r, f_best, meas, bias, pre = evaluate(w_best, offset, lag, gain)
    n = r.size
    rho = float(np.corrcoef(r[:-1], r[1:])[0, 1]) if n > 2 and np.std(r) > 0 else 0.0
    rho = min(max(rho, 0.0), 0.99)
    n_eff = n * (1.0 - rho) / (1.0 + rho)
    s2 = c_best / max(n - 1, 1) * n / max(n_eff, 1.0)
    if jac is None:  # the water content alone: its derivative by central differences
        wa, wb = max(w_best - 1e-4, lo), min(w_best + 1e-4, hi)
        jac = ((evaluate(wb, 0.0, 0.0, gain)[0] - evaluate(wa, 0.0, 0.0, gain)[0]) / (wb - wa))[:, None]
    else:  # the joint fit's: read again as secants (least squares' own crosses the model's steps by chance)
        jac = _secant_jacobian(lambda x: evaluate(float(x[0]), float(x[1]), float(x[2]), gain)[0],
                               np.array([w_best, offset, lag]), (lo, hi))
    jtj = jac.T @ jac
    cov = np.linalg.pinv(jtj)
    inflate = math.sqrt(max(float(cov[0, 0] * jtj[0, 0]), 1.0)) if jtj[0, 0] > 0 else 1.0
    stderr = np.full(3, math.nan)  # the surface offset's and the force lag's, read on the general path below
    # a gain off by +-g: the water content the same fit finds on the force divided by gain * (1 +- g)
    shifts = [0.0]
    # ... and the surface offset and force lag that fit reads, refitted with it: they trade with the gain as the water
    # content does (a force 5 % low reads as the foot 0.2-0.5 mm shallower on a wet robot), and their standard errors
    # hold their moves (below; ours, 2026-12-03: the sensor-chain bench's seed 102, a wet robot's gain -5 % read the
    # gain to 0.2 % and the offset 0.19 mm off at 0.017 mm, 11 standard errors, unwarned)
    gain_moves = np.zeros(3)
    for g in ((1.0 + force_gain_uncertainty, 1.0 - force_gain_uncertainty) if force_gain_uncertainty else ()):
        g_off = gain * g  # about the gain read, where it was (1 otherwise: the profile's own points)
        w_off = profile[g_off] if gain == 1.0 and g_off in profile else \
            best_w(partial(ssr_at, offset=offset, lag=lag, gain=g_off))
        shifts.append(w_off - w_best)
        if general:
            x_off = profile_fits[g_off] if gain == 1.0 and g_off in profile_fits else \
                np.asarray(refit_from(w_off, g_off).x, dtype=np.float64)
            gain_moves = np.maximum(gain_moves, np.abs(x_off - np.array([w_best, offset, lag])))
    shift_down, shift_up = max(-min(shifts), 0.0), max(max(shifts), 0.0)
    gain_shift = max(shift_down, shift_up)

    def ssr(w: float) -> float:
        return ssr_at(w, offset, lag, gain)

    threshold = float(chi2.ppf(level, 1)) * c_best / max(n - 1, 1) * n / max(n_eff, 1.0)
    low = _edge(ssr, c_best + threshold, w_best, grid[grid < w_best][::-1], lo)
    high = _edge(ssr, c_best + threshold, w_best, grid[grid > w_best], hi)
    # the nuisances' correlation with the water content
    low, high = w_best - inflate * (w_best - low), w_best + inflate * (high - w_best)
    rate_shift = sandwich = 0.0
    rate_moves = np.zeros(3)
    if general:
        # the evidence's spread over the contact episodes, in case the misfit sits where the water content is read
        spread, episodes = _sandwich_covariance(jac, r, f_best != 0.0)
        sandwich = float(student_t.ppf(0.5 + 0.5 * level, episodes - 1) * math.sqrt(max(float(spread[0, 0]), 0.0)))
        low, high = min(low, w_best - sandwich), max(high, w_best + sandwich)
        # the rate check: the same fit with the model run on every other sample (the even ones, the odd ones).
        # At the data's rate the model is not the model of the true path (a touchdown or a reversal between two
        # samples); the estimate's move at half the rate measures that error (Richardson, first order: the same
        # estimator at two rates, its turns read through the rest band as at the data's rate). Then its turns' own
        # part: the estimate's move with the turns read on their branches, at the data's rate (what the model does at
        # a turn between two samples is an error of the model's there; on the MuJoCo robots it is most of the
        # check: docs/estimation.md, "identify's rate check on the MuJoCo robots"). The two add; the offset's and the
        # lag's moves in the same refits count in their standard errors (below)
        if n >= 16:
            halves = []
            for sel in (slice(0, None, 2), slice(1, None, 2)):
                w_half = best_w(partial(ssr_at, offset=offset, lag=lag, gain=gain, sel=sel))
                halves.append(np.asarray(refit_from(w_half, gain, sel).x, dtype=np.float64))
            best_x = np.array([w_best, offset, lag])
            rate_moves = np.abs(0.5 * (halves[0] + halves[1]) - best_x) + 0.5 * np.abs(halves[0] - halves[1])
            w_turn = best_w(partial(ssr_at, offset=offset, lag=lag, gain=gain, turns=False))
            rate_moves = rate_moves + np.abs(np.asarray(refit_from(w_turn, gain, turns=False).x) - best_x)
            # the offset's move read again on a profile: each half's sum of squares over offsets about its fit's (its
            # water content and lag held), the least taken. A refit from the full fit's answer can stop where it
            # started (the sum of squares, a model run at the samples, is stepped below the finite differences'
            # 0.1 mm): on a robot's model force it read a move of 0.26 um where the offset was 0.075 mm off, 7
            # standard errors (docs/estimation-history.md, "identify's offset: the rate check's move on a profile")
            profiled = []
            for sel, half in zip((slice(0, None, 2), slice(1, None, 2)), halves, strict=True):
                trial_offsets = np.clip(half[1] + _OFFSET_PROFILE, -MAX_DEPTH_OFFSET, MAX_DEPTH_OFFSET)
                sums = [ssr_at(float(half[0]), float(d), float(half[2]), gain, sel) for d in trial_offsets]
                profiled.append(float(trial_offsets[int(np.argmin(sums))]))
            profile_move = abs(0.5 * (profiled[0] + profiled[1]) - offset) + 0.5 * abs(profiled[0] - profiled[1])
            rate_moves[1] = max(rate_moves[1], profile_move)
            rate_shift = float(rate_moves[0])
    # resolution floor: the family is interpolated between rows 5 points apart, and the branch
    # labels of a general motion leave small systematic errors that the likelihood does not see;
    # then the gain's shift, which no amount of data reduces
    low = max(min(low, w_best - MIN_HALF_WIDTH) - shift_down - rate_shift, lo)
    high = min(max(high, w_best + MIN_HALF_WIDTH) + shift_up + rate_shift, hi)
    # a force sign-flipped (compression negative) first: the misfit it causes is said below in general words
    warnings: list[str] = [w for w in (_force_sign_warning(tr),) if w]
    rmse = math.sqrt(c_best / n)
    scale = max(float(np.max(np.abs(meas))), 1.0)
    best_values = family(w_best).as_array()
    # the floor a perfect member of the family would leave, sample by sample: force noise, depth noise
    # carried through, and the model's own discretisation error at the data's rate
    var, depth_var = noise_floor_parts(tr, f_best - meas, lambda z: CHEN2024.force(t, z + offset, best_values, foot))
    disc2 = np.zeros(n)
    half2 = disc2  # the half-rate part alone (the interval's measure of the misfit, below)
    if general and n >= 8:
        # the model at half the rate against the model at the data's rate, and on the recording against a refined
        # cubic interpolation of it (_discretisation)
        best_mud = family(w_best)

        def run(tt: np.ndarray, zz: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            return _force_and_band(tt, zz, best_mud, foot, lag)

        disc2, half2 = _discretisation(t, tr.depth + offset, run, rest, f_best)
    discretisation = math.sqrt(float(np.mean(disc2)))
    # the statistic: the RMS of the residuals each divided by its own floor. The discretisation error
    # is local (a branch switch or a necking a sample early or late can move the half-rate model by
    # tens of newtons over a few strides), so it excuses the samples where it is large and no others;
    # added in quadrature to one global floor it would excuse an off-family mud everywhere.
    noise_var = var
    least = max((1e-4 * scale) ** 2, 1e-18)

    def floor_of(extra: np.ndarray) -> float:
        """The RMSE over the RMS of the residuals each divided by its floor (noise plus ``extra``) [N]."""
        v = np.maximum(noise_var + extra, least)
        standardised = math.sqrt(float(np.mean(np.minimum(r**2 / v, _MISFIT_CLIP))))
        return rmse / standardised if standardised > 0.0 else math.sqrt(float(np.mean(v)))

    floor = floor_of(disc2)
    ratio = misfit_ratio(rmse, floor, scale)
    # the same statistic with the depth noise's part of the floor taken out: where a depth noise read from the
    # recording decides the rest, the flag may be quiet only because of that reading (the warning below)
    ratio_without_depth = misfit_ratio(rmse, floor_of(disc2 - depth_var), scale)
    # the misfit's worst case: a residual of RMS `unexplained` that the family cannot explain moves the estimate by
    # at most unexplained / rms(dF/dW) (Cauchy-Schwarz on the Gauss-Newton step); the interval holds that much on
    # each side. What the noise does not explain counts, the discretisation error included: the flag excuses it as
    # no sign of another mud, but at this rate it is a model error all the same and can move the estimate. So the
    # interval reads the misfit against the half-rate floor alone, not the refined model's: that one serves the flag
    model_shift = 0.0
    off_interval = math.sqrt(max(rmse**2 - floor_of(half2) ** 2, 0.0))
    unexplained = math.sqrt(max(off_interval**2, float(np.sum(r[moving] ** 2) - np.sum(noise_var[moving])) / n))
    if general and unexplained > 0.0:
        sensitivity = math.sqrt(float(np.mean(jac[:, 0] ** 2)))
        model_shift = unexplained / sensitivity if sensitivity > 0.0 else hi - lo
        low, high = max(min(low, w_best - model_shift), lo), min(max(high, w_best + model_shift), hi)
    if general:
        # the lag's shape: the same fit with a pure delay in place of the low-pass. A delay is no first-order
        # low-pass, and on a smooth walk a 5-ms one read as a lag of 0.05-0.7 ms; the mean delay the other shape
        # reads is what the recording leaves open of the lag, and counts in its standard error
        # (the joint fit's bounds and scales, the delay in the lag's place)
        shape = joint_fit(lambda th: evaluate(float(th[0]), float(th[1]), 0.0, gain, delay=float(th[2]))[0],
                          np.array([w_best, offset, max(lag, _SHAPE_START)]), _SHAPE_EVALUATIONS)
        # ... and the surface offset it reads counts in the offset's, where that fit explains the data as well
        # (its sum of squares within chi-squared's 95 % quantile, one degree, times the residual variance of the
        # low-pass's; _SHAPE_OFFSET_CHI2): a delay read as no lag moves the surface by the delay times the
        # touchdown's speed (0.05-0.11 mm on wet walks whose offset read to 0.02 mm), while a delay fit that ends
        # hundreds of times worse (20 evaluations from the low-pass's answer) says nothing of the offset
        same = 2.0 * float(shape.cost) <= float(np.sum(r**2)) + _SHAPE_OFFSET_CHI2 * s2
        moves = np.hypot(rate_moves, np.array([0.0, float(shape.x[1]) - offset if same else 0.0,
                                               float(shape.x[2]) - lag]))
        moves = np.hypot(moves, np.array([0.0, gain_moves[1], gain_moves[2]]))
        stderr = _nuisance_stderr(jac, r, f_best != 0.0, s2, moves, unexplained)
    # the member that explains the data best by the flag's statistic (each sample over its own floor, the bias
    # re-profiled under those weights; offset, lag and the floors held at the estimate's). Least squares weighs
    # every sample alike, and a few samples whose floor is tens of newtons (an event between two samples, a stuck
    # foot read on a branch) pull the estimate by points on drier mud; the member is then nearer the truth, at or
    # beyond the interval's edge. The interval reaches it, with a margin (docs/estimation-history.md, "identify's
    # interval reaches the member that fits"); the flag, and where least squares fails it the estimate, below
    member = misfit_w = math.nan
    tail_share = tail_at = other_mud = math.nan
    estimate = w_best
    if general and n >= 8:
        v = np.maximum(noise_var + disc2, least)
        seen: dict[tuple[float, float, float], tuple[float, float]] = {}

        def reprofiled(depth_offset: float, model: np.ndarray, band_low: np.ndarray, band_high: np.ndarray,
                       banded: np.ndarray) -> tuple[float, float]:
            """:func:`_bias_reprofiled` of the model at ``depth + depth_offset`` [m], its force ``model`` [N] and its
            band ``[band_low, band_high]`` [N] read at the ``banded`` samples."""
            z = tr.depth + depth_offset
            free = (z <= 0.0) & (model**2 <= 1e-4 * v)  # out of the mud, the model's force nil (1 % of the floor)
            return _bias_reprofiled(model, band_low, band_high, meas, banded, v, free)

        def statistic_at(w: float, depth_offset: float, force_lag: float) -> float:
            """The statistic [-] at water content ``w`` [-], the model at ``depth + depth_offset`` [m] through a
            force lag ``force_lag`` [s] (each point computed once, with its re-profiled bias)."""
            key = (w, depth_offset, force_lag)
            if key not in seen:
                seen[key] = reprofiled(depth_offset, *_force_and_band(t, tr.depth + depth_offset, family(w), foot,
                                                                      force_lag), rest)
            return seen[key][0]

        def statistic(w: float) -> float:
            return statistic_at(w, offset, lag)

        def root(w: float, depth_offset: float, force_lag: float) -> float:
            return math.sqrt(statistic_at(w, depth_offset, force_lag))

        member = _least_member(statistic, w_best, lo, hi)
        low, high = max(min(low, member - _MEMBER_MARGIN), lo), min(max(high, member + _MEMBER_MARGIN), hi)
        # the interval holds every water content whose statistic passes with the depth offset and force lag refitted
        # there, and the flag reads the least statistic found: a quiet flag then says that a member the interval holds
        # explains the data to the floor. Held at the estimate's lag, the truth did not pass under a force lag the
        # least-squares fit misread, and a flag read at the member left such intervals missing it (docs/estimation-
        # history.md, "identify's misfit flag at the member ... NOT kept" and the entries after it)
        readings = np.append(np.linspace(lo, hi, max(math.ceil((hi - lo) / _PASS_STEP - 1e-9), 1) + 1),
                             [member, w_best])
        held = np.array([root(float(w), offset, lag) for w in readings])
        low, high, least_root, at = _passing_members(root, readings, held, member, (low, high), offset, lag, (lo, hi))
        # the flag's three readings at the least statistic found (its offset and lag), the model read there as the set
        # of the relaxations a stuck foot may have had (_model_set; the statistic again, its bias re-profiled):
        # the statistic, the tail's share (which the statistic's clip hides) and what another mud would explain
        (tail_at, flag_offset, flag_lag) = min(seen.items(), key=lambda item: item[1][0])[0]
        # where the foot may be stuck (the fit, the floors, the interval's members and the estimate read the exact
        # rule there too)
        sticking = _sticking(t, tr.depth, tr.depth_noise)
        everywhere = np.ones(t.size, dtype=bool)
        flag_point = (family(tail_at), flag_offset, flag_lag)
        flag_set = _model_set(t, tr.depth, flag_offset, sticking, rest, family(tail_at), foot, flag_lag)

        def model_set(q: MudParameters, depth_offset: float,
                      force_lag: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            """:func:`_model_set` of ``q`` at ``depth + depth_offset`` [m] through ``force_lag`` [s] (the flag's own
            point computed once: the other mud's reading reads it twice more)."""
            if (q, depth_offset, force_lag) == flag_point:
                return flag_set
            return _model_set(t, tr.depth, depth_offset, sticking, rest, q, foot, force_lag)

        flag_statistic, moved = reprofiled(flag_offset, *flag_set, everywhere)
        r_flag = _band_residual(*flag_set, meas + moved, everywhere)
        tail_share = float(np.mean(r_flag * r_flag / v > _TAIL_Z2))
        other_mud = _other_mud(partial(_standardised, model_set, meas + moved, np.sqrt(v)), family,
                               (tail_at, flag_offset, flag_lag), (lo, hi))
        misfit_w, estimate_fails = w_best, ratio > MISFIT_WARNING_RATIO
        if least_root < ratio:
            misfit_w = at
        least_flag = min(least_root, math.sqrt(flag_statistic)) if math.isfinite(least_root) else least_root
        if least_flag < ratio:
            floor = rmse / least_flag if least_flag > 0.0 else math.sqrt(float(np.mean(v)))
            ratio = misfit_ratio(rmse, floor, scale)
        # the estimate moves to that member only where least squares' own member fails the statistic: where it
        # passes, the data do not tell the two apart by the floor, and least squares (every sample alike) is kept.
        # Where it fails, the member read with the nuisances refitted is nearer the truth under a misread force lag
        # or depth offset (docs/estimation-history.md, "identify's estimate at the misfit member")
        if estimate_fails:
            estimate = misfit_w
            # with the allowances least squares' estimate has: the evidence's spread over the contact episodes (the
            # member is read from the same episodes; without it a shallow dry robot under a 30-ms low-pass, read at
            # 17.17 % for 16.33, held [16.37, 26.43], unflagged: docs/estimation-history.md, "identify's moved
            # estimate holds the episodes' spread"), the gain's shift and the rate check's
            reach = max(MIN_HALF_WIDTH, sandwich)
            low = max(min(low, estimate - reach - shift_down - rate_shift), lo)
            high = min(max(high, estimate + reach + shift_up + rate_shift), hi)
    # at the range's edge: the reported estimate, or least squares' where the estimate moved off it
    edge = [name for name, x in (("the estimate", estimate), ("least squares' estimate", w_best))
            if x - lo < 1e-3 or hi - x < 1e-3]
    if edge:
        warnings.append(f"{edge[0]} is at the edge of the searched range [{lo:g}, {hi:g}]: "
                        "the mud may be drier or wetter than the family covers")
    off = math.sqrt(max(rmse**2 - floor**2, 0.0))
    if ratio > MISFIT_WARNING_RATIO:
        warnings.append(f"RMSE {rmse:.3g} N is {ratio:.2g} times the noise floor {floor:.3g} N "
                        f"(force noise {tr.force_noise:.3g} N, with the depth noise carried through and the "
                        f"model's discretisation error {discretisation:.3g} N at this rate): "
                        f"the data are {off:.3g} N (RMS) off the Table I family (another mud, another foot "
                        "than assumed, or a model error), and no water content explains them better (read at "
                        f"{misfit_w * 100 if math.isfinite(misfit_w) else w_best * 100:.4g} %, the depth offset and "
                        "force lag refitted there); the estimate is the nearest water content and the interval is "
                        "widened for the misfit")
    elif tail_share > TAIL_SHARE_WARNING:
        warnings.append(f"{tail_share:.1%} of the samples lie beyond three noise floors at the best water content "
                        f"found ({tail_at * 100:.4g} %, the depth offset and force lag refitted there), where at "
                        f"most {TAIL_SHARE_WARNING:.1%} would: the "
                        "data are off the Table I family (another mud, another foot than assumed, or a model "
                        "error) in more samples than the misfit ratio shows; the estimate is the nearest water "
                        "content")
    elif other_mud > OTHER_MUD_WARNING:
        warnings.append(f"another mud explains {other_mud:.2g} of the residual's mean square (in noise floors squared) "
                        f"at the best water content found ({tail_at * 100:.4g} %, the depth offset and force lag "
                        f"refitted there), where at most {OTHER_MUD_WARNING:g} would: the model's parameters fit the "
                        "data better off the Table I family than on it (another mud, or a model error) though the "
                        "misfit ratio and the tail read little; the estimate is the nearest water content")
    elif _near_limits(ratio, tail_share, other_mud):
        warnings.append(f"two of the misfit flag's three readings are past {NEAR_LIMITS_WARNING:.0%} of their limits "
                        f"(misfit ratio {ratio:.3g} of {MISFIT_WARNING_RATIO:g}, {tail_share:.1%} of the samples "
                        f"beyond three noise floors of {TAIL_SHARE_WARNING:.1%}, another mud explaining "
                        f"{other_mud:.2g} of {OTHER_MUD_WARNING:g}), at the best water content found "
                        f"({tail_at * 100:.4g} %, the depth offset and force lag refitted there): together they read "
                        "more than an in-family recording does (another mud, or a model error); the estimate is the "
                        "nearest water content")
    if rate_shift > _RATE_SHIFT_WARNING:
        warnings.append(f"the estimate moves by {rate_shift * 100:.2g} points when the model runs on every other "
                        "sample or reads the turns on their branches (the two moves added): at this rate the model "
                        "does not follow this motion closely (touchdowns, reversals and stops between the samples, "
                        "or the model's own error at them); the interval is widened by that, and a faster rate "
                        "narrows it only where the rate is the cause")
    if abs(gain - 1.0) > _GAIN_WARNING * force_gain_uncertainty:
        warnings.append(f"the force reads {gain:.4g} times the mud's at the estimate (the gain read from the "
                        f"recording), well beyond the force gain uncertainty given ({force_gain_uncertainty:.3g}): a "
                        "sensor gain that far off, or a mud uniformly stiffer or softer than Table I's at this water "
                        "content; the estimate is read with the force divided by it")
    depth_share = float(np.mean(depth_var) / np.mean(var)) if float(np.mean(var)) > 0.0 else 0.0
    moves_rest = _REST_NOISE_SIGMAS * tr.depth_noise > REST_SPEED * float(np.median(np.diff(t))) if n > 1 else False
    leans_on_depth = depth_share > DEPTH_NOISE_SHARE_WARNING or ratio_without_depth > MISFIT_WARNING_RATIO
    if general and read_noise and leans_on_depth and moves_rest:
        # the floor is mostly the depth noise read from the recording, or the flag would fire without that part of
        # it, and that reading decides which samples are rest: the flag is as blind as the reading is large (at
        # 20 Hz a robot's foot that never rests reads its motion between the samples as noise, 2.5 mm for 0.03,
        # carrying 48-57 % of the floor; a stiff mud's floor may be mostly a true 0.04 mm)
        warnings.append(f"the depth noise read from the recording ({tr.depth_noise * 1e3:.2g} mm) carries "
                        f"{depth_share:.0%} of the noise floor (without it the misfit ratio would read "
                        f"{ratio_without_depth:.3g}, against {MISFIT_WARNING_RATIO:g}) and decides which samples are "
                        "read as rest: the misfit flag, the rest and the interval rest on that reading, and where the "
                        "foot does not rest the motion between the samples reads as noise; give the depth noise the "
                        "robot knows (--depth-noise) if it is smaller")
    if general and (abs(offset) > 0.95 * MAX_DEPTH_OFFSET or lag > 0.95 * MAX_FORCE_LAG):
        warnings.append(f"the fitted sensor nuisances reach their limits (surface offset {offset * 1e3:.3g} mm, "
                        f"force lag {lag * 1e3:.3g} ms; at most {MAX_DEPTH_OFFSET * 1e3:g} mm and "
                        f"{MAX_FORCE_LAG * 1e3:g} ms): the depth or the force is not what the model can explain")
    bias_stderr = max(rmse, tr.force_noise) * math.sqrt((1.0 + rho) / (1.0 - rho) / (n + pre))
    if general and pre:
        # the refinement moves the tare (the mean of the pre-contact samples: the bias and the force noise alone) by
        # the moving samples' mean residual, which holds the model's own mean error there too (the depth noise carried
        # through a force convex in the depth, the force lag held at its bound): the move is not told from an error
        # of the bias, and counts in its standard error (a 1 mm depth noise refined a 0.4 N bias to 0.0 N +- 0.03)
        bias_stderr = math.hypot(bias_stderr, bias - float(np.mean(raw[:pre])))
    return Identification(
        water_content=estimate,
        interval=(low, high),
        rmse=rmse,
        level=level,
        grid=grid,
        grid_rmse=np.sqrt(costs / n),
        warnings=tuple(warnings),
        force_noise=tr.force_noise,
        noise_floor=floor,
        misfit_ratio=ratio,
        off_family=off,
        bias=bias,
        bias_method="estimated" if tr.bias_estimated else "tared",
        bias_stderr=bias_stderr,
        depth_offset=offset if general else math.nan,
        depth_offset_stderr=float(stderr[1]) if general else math.nan,
        force_lag=lag if general else math.nan,
        force_lag_stderr=float(stderr[2]) if general else math.nan,
        force_gain_uncertainty=force_gain_uncertainty,
        gain_shift=gain_shift,
        force_gain=gain,
        discretisation=discretisation,
        rest_fraction=float(np.mean(rest)),
        rate_shift=rate_shift,
        episode_half_width=sandwich,
        misfit_shift=model_shift,
        depth_noise=tr.depth_noise,
        unresolved_depth=tr.unresolved_depth,
        member_water_content=member,
        misfit_water_content=misfit_w,
        least_squares_water_content=w_best,
        tail_share=tail_share,
        other_mud=other_mud,
    )

