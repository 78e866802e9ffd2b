"""Fitting the model to measured intrusion trials, with honest standard errors.

The objective is the force residual ``model - measured`` [N] at every sample
of every trial of a condition (one water content), after each trial is
prepared (:mod:`mudforce.estimation.calibration.preprocess`: motion fitted, force
tared). The model follows the fitted noise-free motion with the exact
branch rule, so the reversal happens at the right sample. On a recording of
any other motion (a walk, a robot's foot) a sample at which the foot is at
rest, or turns between two samples, is read through the model's rest band
(:attr:`ForceModel.rest_band <mudforce.estimation.calibration.models.ForceModel.rest_band>`,
as identify reads it): a stuck foot carries its load anywhere in
``[F_up, F_down]``, and the residual there is the force's distance outside it
(issue 23: rest is a band, not a branch). A band is no likelihood: every
sample inside it costs nothing however wide it is, so a fit of nine free
parameters can widen it over the noise of the samples at its edge (a walk
whose stances lie on the branch read ``zeta`` 5.6 standard errors off,
unwarned). Where the branch reads those samples to their noise, or the
branch with the band at the turns alone, the fit keeps that reading (ours:
:func:`_narrowest_reading`); the band where neither does, as on a robot
whose stuck foot carries its load anywhere in it, and then the band's
pull, measured on data made from the fit, widens the standard errors
(ours: :func:`_band_pull`). Where the foot sticks, the fit is also read
with the stuck stretches' depth held still (the engines' sticking); when
that reads the data as well, each standard error is widened to hold both
readings (ours: :func:`_held_reading`).

The fit is staged, as Section III-A of [1] suggests (:data:`CHEN2024.stages
<mudforce.estimation.calibration.models.CHEN2024>`):

1. intrusion and hold (``k_m_i, b_m_i, alpha, beta``) on the samples up to
   the reversal: bounded least squares from the best Table I rows (a trial
   that starts in the mud: on its first touchdown from above instead,
   :attr:`PreparedTrial.intrusion_window
   <mudforce.estimation.calibration.preprocess.PreparedTrial.intrusion_window>`);
2. withdrawal (``k_m_w, b_m_w, sigma_y, zeta, omega_0``) on the samples after
   it: seeded differential evolution, then least squares. Necking makes this
   objective non-smooth in ``sigma_y`` (the neck breaks at a different
   sample), and a local solver alone stalls on its plateaus;
3. every free parameter jointly, on all samples.

Parameters are fitted as logarithms inside bounds. Standard errors come
from the Jacobian at the optimum (central differences):
``cov = s^2 (J^T J)^-1`` in log space with ``s^2 = SSR / (n - p)``, mapped to
SI by the delta method. Where the cost is flatter than that quadratic on
one side (``b_m_w`` when the data barely sees the withdrawal relaxation,
e.g. at 50 Hz with an early neck), the standard error is widened to the
profile likelihood's (the other parameters refitted): ``value +- k se``
covers the profile interval at ``k = 1, 2, 3``; a side the profile never
closes within its bound gets a warning naming the parameter (ours, not
the paper's). Directions the data does not constrain (a zero
singular value: e.g. ``sigma_y`` when no trial necks) get no standard error
(``null``) and a warning, rather than a meaningless number.

The results (:mod:`mudforce.estimation.calibration.results`) and the standard errors
(:mod:`mudforce.estimation.calibration.uncertainty`) live in their own modules; this
one is the driver.

.. [1] X. Chen, J. Yi, J. Shan, arXiv:2403.02617 (2024).
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import differential_evolution, least_squares
from scipy.stats import t as student_t

from mudforce._plumbing.blas import one_blas_thread
from mudforce._plumbing.progress import Progress
from mudforce.errors import (
    InputError,
    finite_number,
    is_integer,
    number_within,
    positive_int,
    seed_int,
    shown,
    true_or_false,
)
from mudforce.estimation.calibration._recording_model import (
    _TAIL_Z2,
    NEAR_LIMITS_WARNING,
    TAIL_SHARE_WARNING,
    _band_residual,
    _bias_reprofiled,
    _discretisation,
    _rest_samples,
    _sticking,
    _union,
)
from mudforce.estimation.calibration.dataset import Dataset, Trial
from mudforce.estimation.calibration.models import FitStage, ForceModel, get_model, trajectory_force
from mudforce.estimation.calibration.preprocess import (
    PreparedTrial,
    _force_sign_warning,
    noise_floor_parts,
    prepare_trial,
    tare_correction,
)
from mudforce.estimation.calibration.results import (
    MISFIT_WARNING_RATIO,
    POOR_RELATIVE_STDERR,
    ConditionFit,
    FitResult,
    TrialFit,
    load_fit,
    load_fit_parameters,
    misfit_ratio,
    speed_key,
)
from mudforce.estimation.calibration.uncertainty import (
    correlation_inflation,
    covariance,
    jackknife_variance,
    jacobian,
    motion_sensitivity,
    profiled_in_place,
)
from mudforce.estimation.nuisances import DEFAULT_FORCE_GAIN_UNCERTAINTY, check_force_gain_uncertainty
from mudforce.model.foot import Foot
from mudforce.model.parameters import PARAMETER_RANGES

# the results and the uncertainty live in their own modules; their names stay importable from here
__all__ = [
    "DEPTH_NOISE_SHARE_WARNING",
    "MISFIT_WARNING_RATIO",
    "POOR_RELATIVE_STDERR",
    "ConditionFit",
    "FitOptions",
    "FitResult",
    "TrialFit",
    "correlation_inflation",
    "fit_by_velocity",
    "fit_condition",
    "fit_dataset",
    "load_fit",
    "load_fit_parameters",
    "misfit_ratio",
    "speed_key",
]

#: The most each count of :class:`FitOptions` may be [-] (ours): 80 to 2,500 times the defaults; past it a budget is a
#: mistake, which ran for days or failed deep in scipy (``popsize=10**400``: OverflowError).
_MAX_BUDGET = {"starts": 1000, "popsize": 1000, "maxiter": 100_000, "max_nfev": 1_000_000}


@dataclass(frozen=True)
class FitOptions:
    """The optimiser's budget (the defaults fit one condition of 9 trials in a few seconds).

    Attributes
    ----------
    starts : int
        Best starting points (by cost, among the model's ``starts`` and the
        current values) from which each local stage runs least squares, in
        [1, 1000].
    popsize : int
        Differential-evolution population per parameter, in [1, 1000].
    maxiter : int
        Differential-evolution generations at most, in [0, 100000].
    tol : float
        Differential-evolution relative convergence tolerance.
    max_nfev : int
        Residual evaluations per least-squares run, at most, in [1, 1000000].

    The upper bounds are ours, as the package's other counts have theirs:
    80 to 2,500 times the defaults, and 67 and 100 times
    scipy's own defaults of ``popsize`` (15) and ``maxiter`` (1000). Past them
    a budget is a mistake, which ran for days or failed deep in scipy
    (``popsize=10**400`` raised OverflowError, ``10**12`` MemoryError).
    """

    starts: int = 2
    popsize: int = 12
    maxiter: int = 60
    tol: float = 1e-4
    max_nfev: int = 400

    def __post_init__(self) -> None:
        # checked when made (0 or a float reached scipy's ValueError or TypeError mid-fit, True was 1, NaN ran on)
        for name in ("starts", "popsize", "max_nfev"):
            object.__setattr__(self, name, positive_int(getattr(self, name), f"FitOptions.{name}"))
        if not is_integer(self.maxiter) or self.maxiter < 0:  # 0: the initial population alone
            raise InputError(f"FitOptions.maxiter must be an integer >= 0, got {shown(self.maxiter)}")
        object.__setattr__(self, "maxiter", int(self.maxiter))
        for name, most in _MAX_BUDGET.items():  # 10**400 was taken, then ran for ever or failed deep in scipy
            if getattr(self, name) > most:
                raise InputError(f"FitOptions.{name} must be at most {most} (ours: a budget beyond it is a mistake), "
                                 f"got {shown(getattr(self, name))}")
        object.__setattr__(self, "tol", finite_number(self.tol, "FitOptions.tol", "-", nonnegative=True))


def _options(options: FitOptions | None) -> FitOptions:
    """``options``, or the defaults for None; anything else is refused in one line."""
    if options is None:
        return FitOptions()
    if not isinstance(options, FitOptions):
        raise InputError(f"options must be a FitOptions (or None: the defaults), got {type(options).__name__}")
    return options


# ---------------------------------------------------------------------------- the objective
class _Piece:
    """One trial's rows of the objective: its force residual [N] with the tare offset profiled out, and the prior.

    Speed plumbing: what depends only on the trial and the window (the
    trajectory's work arrays, the measured force in the window, where its
    rows go) is found once, so that an evaluation is the model's run and
    three passes over the rows, written where :class:`_Objective` returns
    them.

    With ``rest`` (a recording of any motion, a model with a rest band) ``force`` gives ``(force, low, high)`` [N]
    and the rows are :func:`_rest_band_rows`.
    """

    __slots__ = ("force", "measured", "precontact", "prior", "rest", "rows", "skip")

    def __init__(self, force: Callable[[np.ndarray], Any], skip: int, measured: np.ndarray, rows: slice,
                 prior: int, precontact: int, rest: np.ndarray | None = None) -> None:
        self.force = force  # values -> the model's force [N] (the rows' samples from skip on)
        self.skip = skip
        self.measured = np.ascontiguousarray(measured)
        self.rows = rows
        self.prior = prior
        self.precontact = precontact
        self.rest = rest

    def write(self, values: np.ndarray, out: np.ndarray) -> None:
        """Write the rows for parameters ``values`` [SI] into ``out`` (:func:`profiled`'s numbers, bit for bit)."""
        if self.rest is not None:
            force, low, high = (a[self.skip:] for a in self.force(values))
            out[self.rows], offset = _rest_band_rows(force, low, high, self.measured, self.rest, self.precontact)
            out[self.prior] = offset * math.sqrt(self.precontact)
            return
        force = self.force(values)
        r = out[self.rows]
        np.subtract(force[self.skip:] if self.skip else force, self.measured, out=r)
        out[self.prior] = profiled_in_place(r, self.precontact)


def _rest_band_rows(force: np.ndarray, low: np.ndarray, high: np.ndarray, measured: np.ndarray, rest: np.ndarray,
                    precontact: int) -> tuple[np.ndarray, float]:
    """A recording's residual [N] with a foot at rest read through its band, and the tare offset [N] profiled out.

    The model's ``force`` [N] minus the ``measured`` one [N] less the offset, except at the ``rest`` samples, where a
    stuck foot carries its load anywhere in its band ``[low, high]`` [N] and the residual is the distance outside
    it (:func:`~mudforce.estimation.calibration._recording_model._band_residual`, as identify reads rest). The
    offset is :func:`~mudforce.estimation.calibration.preprocess.tare_correction`'s over the moving samples alone
    (a sample at rest says nothing of it inside its band), as identify's bias is.
    """
    moving = ~rest
    offset = -float(np.sum((force - measured)[moving])) / max(int(np.count_nonzero(moving)) + precontact, 1)
    return _band_residual(force, low, high, measured - offset, rest), offset


class _Objective:
    """Force residuals [N] of groups of trials for a vector of log-parameters.

    ``slots[j]`` lists the (group, parameter index) pairs that ``x[j]`` sets,
    so one entry can be shared by several groups (water contents).
    """

    def __init__(self, model: ForceModel, foot: Foot, groups: Sequence[Sequence[PreparedTrial]],
                 base: Sequence[np.ndarray], slots: Sequence[Sequence[tuple[int, int]]], window: str,
                 prefix_fixed: bool = False, reading: str = "band") -> None:
        self.model = model
        self.reading = reading  # how the samples at rest are read (_rest_of)
        self.foot = foot
        self.groups = groups
        self.base = [b.copy() for b in base]
        self.slots = slots
        self.window = window
        # withdrawal-only parameters: simulate each trial up to its reversal once
        self.tails: list[list[Callable[[np.ndarray], np.ndarray]]] | None = None
        if prefix_fixed and window == "withdrawal" and model.resume is not None:
            resume = model.resume
            self.tails = [[resume(tr.time, tr.depth, b, foot, tr.reversal_index) for tr in group]
                          for b, group in zip(self.base, groups, strict=True)]
        self._pieces = self._make_pieces()

    def _make_pieces(self) -> list[list[_Piece]]:
        """Each trial's :class:`_Piece`: its data rows in trial order, then one prior row per trial."""
        n_data = 0
        windows = []
        for g, group in enumerate(self.groups):
            for i, tr in enumerate(group):
                rest = _rest_of(self.model, tr, self.reading)
                a, b = tr.intrusion_window if self.window == "intrusion" else (0, tr.time.size)
                k = tr.reversal_index if self.window == "withdrawal" else 0
                spec: tuple[Callable[[np.ndarray], Any], int, np.ndarray, np.ndarray | None]
                if rest is not None and rest[max(a, k):b].any():  # a foot at rest: read through its band
                    assert self.model.rest_band is not None  # (_rest_of gives none without)
                    band = self.model.rest_band(tr.time[a:b], tr.depth[a:b], self.foot)
                    spec = (band, k, tr.force[max(a, k):b], rest[max(a, k):b])
                elif self.tails is not None:
                    spec = (self.tails[g][i], 0, tr.force[k:], None)
                elif self.window == "intrusion":  # the force up to the reversal does not depend on what follows
                    # a trial that starts in the mud: its first touchdown, from a free foot
                    spec = (trajectory_force(self.model, self.foot, tr.time[a:b], tr.depth[a:b]), 0, tr.force[a:b],
                            None)
                else:
                    spec = (trajectory_force(self.model, self.foot, tr.time, tr.depth), k, tr.force[k:], None)
                windows.append((g, spec, n_data, tr.precontact))
                n_data += spec[2].size
        self._size = n_data + len(windows)
        pieces: list[list[_Piece]] = [[] for _ in self.groups]
        for j, (g, (force, skip, measured, rest), start, precontact) in enumerate(windows):
            pieces[g].append(_Piece(force, skip, measured, slice(start, start + measured.size), n_data + j,
                                    precontact, rest))
        return pieces

    def values(self, x: np.ndarray) -> list[np.ndarray]:
        out = [b.copy() for b in self.base]
        for xj, targets in zip(np.exp(x), self.slots, strict=True):
            for g, i in targets:
                out[g][i] = xj
        return out

    def __call__(self, x: np.ndarray) -> np.ndarray:
        out = np.empty(self._size)
        for values, pieces in zip(self.values(x), self._pieces, strict=True):
            for piece in pieces:
                piece.write(values, out)
        return out

    def cost(self, x: np.ndarray) -> float:
        r = self(x)
        return float(r @ r)


#: How the fit may read the samples of a recording at which the foot is at rest (:func:`_rest_of`), the narrowest
#: first: every sample on the model's branch; the band at the turns alone (where the motion changes between two
#: samples), the slow samples on the branch; the band at every sample at rest (identify's reading).
_READINGS = ("branch", "turns", "band")


def _rest_of(model: ForceModel, tr: PreparedTrial, reading: str = "band") -> np.ndarray | None:
    """The samples of ``tr`` the fit reads through the model's rest band [bool] (a recording of any motion: identify's
    rest, :func:`~mudforce.estimation.calibration._recording_model._rest_samples`; with ``reading`` ``"turns"`` the
    samples where the motion changes alone, not those merely slow), or None where it reads every sample on the
    branch: ``reading`` ``"branch"``, a lab protocol (its hold is the paper's relaxation, on the branch), or a model
    without a band."""
    if model.rest_band is None or tr.motion is not None or tr.time.size < 2 or reading == "branch":
        return None
    rest = _rest_samples(tr.time, tr.depth, tr.depth_noise)
    if reading == "turns":
        rest &= ~_rest_samples(tr.time, tr.depth, tr.depth_noise, turns=False)
    return rest


def _trial_residual(model: ForceModel, foot: Foot, tr: PreparedTrial, values: np.ndarray, window: str) -> np.ndarray:
    """The residual [N] of one trial's ``window`` (no offset profiled out), at rest the distance outside the band."""
    t, z, f = tr.time, tr.depth, tr.force
    k = tr.reversal_index
    rest = _rest_of(model, tr)
    a, b = tr.intrusion_window if window == "intrusion" else (0, t.size)
    if rest is not None and model.rest_band is not None:
        band = model.rest_band(t[a:b], z[a:b], foot)(values)
        r: np.ndarray = _band_residual(*band, f[a:b], rest[a:b])
        return r if window != "withdrawal" else r[k:]
    if window == "intrusion":  # the force up to the reversal does not depend on what follows
        # a trial that starts in the mud: its first touchdown, from a free foot
        head: np.ndarray = model.force(t[a:b], z[a:b], values, foot) - f[a:b]
        return head
    r = model.force(t, z, values, foot) - f
    return r[k:] if window == "withdrawal" else r


def _fitted(model: ForceModel, foot: Foot, tr: PreparedTrial, values: np.ndarray,
            reading: str = "band") -> tuple[np.ndarray, float]:
    """The model's force along ``tr`` [N] and the tare offset [N] the fit profiles out of it.

    At a sample at rest (:func:`_rest_of`) the model's force is the point of its rest band nearest the measured
    force less the offset (what a stuck foot of this mud could carry there), so that the residual is the objective's.
    ``reading``: :func:`_rest_of`'s.
    """
    rest = _rest_of(model, tr, reading)
    if rest is not None and model.rest_band is not None:
        force, low, high = model.rest_band(tr.time, tr.depth, foot)(values)
        r, offset = _rest_band_rows(force, low, high, tr.force, rest, tr.precontact)
        return r + (tr.force - offset), offset
    fitted = model.force(tr.time, tr.depth, values, foot)
    return fitted, tare_correction(fitted - tr.force, tr.precontact)


#: A narrower reading (:func:`_narrowest_reading`) is kept when its residual's RMS, with the noise its band hides put
#: back, is within this factor of the band reading's [-] (ours). On the sensor-chain bench's clean 100-Hz walks of
#: seed 70 (``mudforce.motions.gait``, the model's force on its branch) the branch reading's factor reads 0.997-1.032;
#: on its MuJoCo robots, both sources, whose feet stick or turn between two samples, 5.1-15.5.
_READING_TIE = 1.1


def _rows_and_hidden(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
                     idx: list[int], reading: str) -> tuple[float, float]:
    """The objective's sum of squares [N^2] of a ``reading`` at ``values`` [SI] (free ``idx``), and the noise its band
    hides [N^2]: at each sample read through the band and inside it, the variance of its noise floor
    (:func:`~mudforce.estimation.calibration.preprocess.noise_floor_parts`)."""
    rows = _Objective(model, foot, [prepared], [values], [[(0, i)] for i in idx], "all",
                      reading=reading)(np.log(values[idx]))
    hidden, start = 0.0, 0
    for tr in prepared:
        stop = start + tr.time.size
        rest = _rest_of(model, tr, reading)
        if rest is not None:
            def force_at(z: np.ndarray, tr: PreparedTrial = tr) -> np.ndarray:
                return model.force(tr.time, z, values, foot)

            var = noise_floor_parts(tr, rows[start:stop], force_at)[0]
            hidden += float(np.sum(var[rest & (rows[start:stop] == 0.0)]))
        start = stop
    return float(rows @ rows), hidden


def _narrowest_reading(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
                       idx: list[int], options: FitOptions, seed: int) -> tuple[str, np.ndarray]:
    """The narrowest reading of the samples at rest (:data:`_READINGS`) that reads the data as well as the band
    does, and its fit: ``(reading, values [SI])`` (ours; issue 23, point 5 for fit).

    The band reading (``values``, the fit with every sample at rest read through the rest band) scores a sample
    inside the band zero however wide the band is, so the fit gains the noise of every sample at the band's edge by
    widening it (each sample's noise a free parameter: a Neyman-Scott bias). On the bench's clean walks of seed 70,
    whose stances lie on the branch (the model's own force), it read ``zeta`` and ``omega_0`` 3-6 standard errors off
    and ``k_m_i``, ``b_m_i`` up to 5, with no warning and an RMSE a quarter below the force noise; at 50 Hz 3. This
    refits locally from ``values``, every free parameter ``idx``, with the samples at rest read on the branch, then
    with the band at the turns alone (at 50 Hz a stance's sway turns between two samples, where the branch at the
    sample is either); the first whose sum of squares, with the noise its band hides put back
    (:func:`_rows_and_hidden`), is within :data:`_READING_TIE` (on the RMS) of the band reading's explains the rest
    as well as any point of the band does, and is the fit (the same walks: every parameter within 1.5 standard
    errors). A foot that carries its load anywhere in the band (MuJoCo's stuck foot) is missed by newtons on both,
    and the band reading stays.
    """
    cost, hidden = _rows_and_hidden(model, foot, prepared, values, idx, "band")
    for reading in _READINGS[:-1]:
        other = _run_stage(model, foot, prepared, values, idx, "all", "local",
                           FitOptions(starts=1, max_nfev=options.max_nfev), seed, reading=reading)
        c, h = _rows_and_hidden(model, foot, prepared, other, idx, reading)
        if c + h <= _READING_TIE**2 * (cost + hidden):
            return reading, other
    return "band", values


def _band_pull(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray, idx: list[int],
               options: FitOptions, seed: int, reading: str) -> np.ndarray:
    """How far the band of a ``reading`` pulls each free parameter ``idx`` [-, on the logarithm], measured on data
    made from the fit itself (ours; issue 23, point 5 for fit).

    A band scores every sample inside it zero, and the noise of the samples at its edge pulls the fit toward wider
    bands (:func:`_narrowest_reading`), by an amount its standard errors do not hold. This makes each recording
    again from ``values`` [SI]: the model's force along its depth, on its branch (a stuck foot's load at the band's
    edge, where the pull is largest), the tare offset and a normal noise of the recording's force noise (seeded by
    ``seed``); and refits it locally twice, on the branch (its truth's own reading: no pull) and through the band of
    ``reading``. Their difference, on the same noise, is the pull: on the bench's 20-Hz walks of seed 70, where the
    band reading stays (the branch misses the turns between the samples), ``zeta`` low and ``omega_0`` high by up to
    3 standard errors.
    """
    rng = np.random.default_rng([seed, 0x8A4D])
    made = []
    for tr in prepared:
        own = model.force(tr.time, tr.depth, values, foot)
        offset = _fitted(model, foot, tr, values, reading)[1]
        sigma = tr.force_noise if math.isfinite(tr.force_noise) else 0.0
        made.append(dataclasses.replace(tr, force=own + offset + rng.normal(0.0, sigma, own.size)))
    local = FitOptions(starts=1, max_nfev=options.max_nfev)
    on_branch = _run_stage(model, foot, made, values, idx, "all", "local", local, seed, reading="branch")
    on_band = _run_stage(model, foot, made, values, idx, "all", "local", local, seed, reading=reading)
    pull: np.ndarray = np.log(on_band[idx] / on_branch[idx])
    return pull


#: The held reading (:func:`_held_reading`) ties with the fit's own when its RMSE is within this factor of the fit's
#: [-] (ours). On the sensor-chain bench's clean robot 0 of seed 67 both sources' readings tie (MuJoCo's force to 1 %,
#: 0.204 and 0.205 N); refitted from scratch, the model's own force along the robot's path (which creeps where it
#: sticks) read held missed fourfold: a reading the data rejects is not held.
_HELD_TIE = 1.1


def _held_reading(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
                  idx: list[int], options: FitOptions, seed: int,
                  rmse: float, reading: str = "band") -> tuple[np.ndarray, np.ndarray] | None:
    """The fit with a stuck foot's depth held still, where that reads the data as well: ``(values [SI], standard
    errors of the free log-parameters [-])``, else None (ours; issue 23, point 5 for fit).

    Where a recording's foot may be stuck (:func:`~mudforce.estimation.calibration._recording_model._sticking`),
    the model's Maxwell element may relax as the engines relax a stuck foot's (no step: the intrusion branch's
    relaxation) or as the recorded depth's creep and noise read it (the fit's own reading, on the depth as recorded);
    the withdrawal that follows starts from either state, and a recording cannot tell them apart. This refits, from
    ``values`` (locally, every free parameter ``idx``), with each stuck stretch held at its mean depth; when its RMSE
    is within :data:`_HELD_TIE` of the fit's ``rmse`` [N], the two readings are equally good and
    :func:`_condition_from` widens each standard error to hold both. On the bench's MuJoCo robot 0 of seed 67 (the
    engine's force, clean; tests/estimation/test_fit_rest_band.py) the fit's own reading alone put ``b_m_w`` at 0.69
    times the truth, 7.8 standard errors off and unwarned; with both readings 2.4, and named in a warning.
    """
    held: list[PreparedTrial] = []
    for tr in prepared:
        sticking = _sticking(tr.time, tr.depth, tr.depth_noise) if _rest_of(model, tr, reading) is not None else None
        held.append(tr if sticking is None else dataclasses.replace(tr, depth=sticking.held))
    if all(np.array_equal(h.depth, tr.depth) for h, tr in zip(held, prepared, strict=True)):  # nothing sticks
        return None
    other = _run_stage(model, foot, held, values, idx, "all", "local",
                       FitOptions(starts=1, max_nfev=options.max_nfev), seed, reading=reading)
    obj = _Objective(model, foot, [held], [other], [[(0, i)] for i in idx], "all", reading=reading)
    x = np.log(other[idx])
    residual = obj(x)
    data = residual[: -len(held)]
    if not _rms(data) <= _HELD_TIE * rmse:
        return None
    cov, _ = covariance(jacobian(obj, x), residual)
    starts = np.cumsum([0] + [tr.time.size for tr in held])
    inflation = correlation_inflation([data[starts[i]:starts[i + 1]] for i in range(len(held))])
    return other, np.sqrt(np.maximum(np.diag(cov), 0.0) * inflation)


def _log_bounds(model: ForceModel, names: Sequence[str], search: bool = False) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = [], []
    for n in names:
        a, b = model.bounds[n]
        if search and n in model.search_bounds:
            a, b = max(a, model.search_bounds[n][0]), min(b, model.search_bounds[n][1])
        lo.append(math.log(a))
        hi.append(math.log(b))
    return np.array(lo), np.array(hi)


def _least_squares(obj: _Objective, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, max_nfev: int) -> np.ndarray:
    x0 = np.clip(x0, lo + 1e-9, hi - 1e-9)
    sol = least_squares(obj, x0, bounds=(lo, hi), method="trf", x_scale=1.0, diff_step=1e-6,
                        max_nfev=max_nfev, xtol=1e-10, ftol=1e-10, gtol=1e-10)
    return np.asarray(sol.x)


#: How many depth noises below the surface a foot out of the mud may have touched between two samples, for fit's
#: flag (:func:`_flag_reading`) [-] (ours: the samples cannot exclude a touch that shallow).
_TOUCH_SIGMAS = 3.0
#: Most evaluations of the robust refit that fit's misfit flag is read at, where least squares fails it (ours; from
#: least squares' optimum it stops in 25-40 on the sensor-chain bench's 1-kHz MuJoCo runs) [-].
_ROBUST_NFEV = 100
#: The limits the refit is held to [-]: identify's tail (``TAIL_SHARE_WARNING``, a share of samples beyond three
#: floors), and the share of each limit, the ratio's and the tail's, it must stay under for the flag to be read there
#: (``NEAR_LIMITS_WARNING``; the 1-kHz MuJoCo runs it unflags read 0.83 and 1.7-2.0 %). One definition each, in
#: ``_recording_model``, identify's and fit's.
_ROBUST_TAIL = TAIL_SHARE_WARNING
_ROBUST_NEAR = NEAR_LIMITS_WARNING


def _robust_refit(obj: _Objective, x: np.ndarray, lo: np.ndarray, hi: np.ndarray, scale: float) -> np.ndarray:
    """The log-parameters [-] of a refit from ``x`` that weighs a residual beyond ``scale`` [N] less (ours).

    scipy's ``arctan`` loss, ``rho(s) = arctan(s)`` of ``s = (r / scale)^2``: bounded, as the misfit flag's statistic
    caps each sample's term (five floors), so that a few samples a neck or a branch switch between two samples puts
    tens of newtons off do not pull the fit off a mud that explains the rest. Read only for the flag
    (:func:`_condition_from`); the fit's parameters and standard errors stay least squares'.
    """
    sol = least_squares(obj, np.clip(x, lo + 1e-9, hi - 1e-9), bounds=(lo, hi), method="trf", x_scale=1.0,
                        diff_step=1e-6, max_nfev=_ROBUST_NFEV, loss="arctan", f_scale=scale)
    return np.asarray(sol.x)


_DE_TAKES_RNG = "rng" in inspect.signature(differential_evolution).parameters


def _global_search(obj: _Objective, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, options: FitOptions,
                   seed: int) -> np.ndarray:
    seeding: dict[str, Any] = {"rng": np.random.default_rng(seed)} if _DE_TAKES_RNG else {"seed": seed}
    sol = differential_evolution(obj.cost, list(zip(lo, hi, strict=True)), popsize=options.popsize,
                                 maxiter=options.maxiter, tol=options.tol, polish=False, workers=1,
                                 updating="immediate", init="latinhypercube", x0=np.clip(x0, lo, hi), **seeding)
    return np.asarray(sol.x)


# ---------------------------------------------------------------------------- profile likelihood
#: ``profile(column, se_log) -> (standard error [SI], open edge [SI] or None)``
_Profile = Callable[[int, float], tuple[float, "float | None"]]
_PROFILE_SCREEN = 0.8  # a cost rise below this share of the quadratic's at +-2 se: profile the parameter
_PROFILE_RELATIVE = 0.05  # a relative standard error above this: profile the parameter
_PROFILE_STEPS = (1.0, 2.0, 3.0, 4.5, 6.0, 9.0, 13.0)  # where the profile is evaluated [se_log]


def _profiler(obj: _Objective, x: np.ndarray, jac: np.ndarray, lo: np.ndarray, hi: np.ndarray,
              max_nfev: int) -> _Profile:
    """The profile-likelihood standard error of each log-parameter (ours; docs/estimation.md).

    The quadratic model of the cost at the optimum predicts a rise of
    ``k^2 u`` at ``k`` standard errors, ``u = se_log^2 / (J^T J)^+_jj``. A
    parameter whose relative standard error exceeds ``_PROFILE_RELATIVE``
    (over 3 of them its logarithm moves far enough for the quadratic to
    fail), or whose cost rises by less than ``_PROFILE_SCREEN`` of that at
    +-2 standard errors along the linearised conditional path, is profiled:
    held at steps of its standard error while the others are refitted, out
    to where the rise reaches ``9 u`` (3 standard errors). The standard error
    returned is the largest ``|edge_k - value| / k`` over ``k = 1, 2, 3`` and
    both sides (in SI units), so ``value +- k se`` covers the profile's
    ``k``-interval; a side the profile does not close before its bound or
    last step is returned as the open edge.
    """
    c0 = obj.cost(x)
    inv = np.linalg.pinv(jac.T @ jac)

    def profile(j: int, se_log: float) -> tuple[float, float | None]:
        unit = se_log**2 / inv[j, j] if inv[j, j] > 0 else 0.0
        if not unit > 0:
            return 0.0, None
        path = inv[:, j] / inv[j, j]
        rises = [(obj.cost(np.clip(x + t * se_log * path, lo, hi)) - c0) / (t * t * unit) for t in (-2.0, 2.0)]
        if min(rises) >= _PROFILE_SCREEN and se_log <= _PROFILE_RELATIVE:
            return 0.0, None
        others = [i for i in range(x.size) if i != j]
        value = math.exp(x[j])
        se, edge = 0.0, None
        for side in (-1.0, 1.0):
            reached = 0  # how many of k = 1, 2, 3 the profile has closed on this side
            last_t, last_rise, far = 0.0, 0.0, math.nan
            start = x.copy()
            for t in _PROFILE_STEPS:
                xj = x[j] + side * t * se_log
                if not lo[j] < xj < hi[j]:
                    far = math.exp(hi[j] if side > 0 else lo[j])
                    break
                if t == _PROFILE_STEPS[0]:  # the first step along the linearised path, then from the last refit
                    start = np.clip(x + side * t * se_log * path, lo, hi)
                sub = _Objective(obj.model, obj.foot, obj.groups, [b.copy() for b in obj.values(x)],
                                 [obj.slots[i] for i in others], obj.window, reading=obj.reading)
                for g, i in obj.slots[j]:
                    sub.base[g][i] = math.exp(xj)
                fitted = _least_squares(sub, start[others], lo[others], hi[others], max_nfev)
                start[others] = fitted
                rise = max(sub.cost(fitted) - c0, 0.0) / unit
                while reached < 3 and rise >= (reached + 1) ** 2:
                    k = reached + 1
                    frac = (k * k - last_rise) / (rise - last_rise) if rise > last_rise else 1.0
                    tk = last_t + frac * (t - last_t)
                    se = max(se, abs(math.exp(x[j] + side * tk * se_log) - value) / k)
                    reached = k
                last_t, last_rise = t, rise
                if reached == 3:
                    break
            if reached < 3:  # open on this side: the standard error reaches its bound or the last point looked at
                far = far if math.isfinite(far) else math.exp(x[j] + side * last_t * se_log)
                se = max(se, abs(far - value) / 3.0)
                edge = far if edge is None or abs(far - value) > abs(edge - value) else edge
        return se, edge

    return profile


# ---------------------------------------------------------------------------- one condition
def _resolve_free(model: ForceModel, free: Iterable[str] | None, fixed: Mapping[str, float] | None) -> tuple[str, ...]:
    names = model.parameter_names
    if isinstance(free, (str, bytes)):  # its letters are no names (as shared's)
        raise InputError(f"free must be a sequence of parameter names, e.g. ('k_m_i', 'beta'), got {shown(free)}")
    chosen = [n for n in names if n not in model.fixed] if free is None else list(free)
    for n in chosen:
        if n not in names:
            raise InputError(f"unknown parameter {n!r} for model {model.name}; expected one of {', '.join(names)}")
    held = set(fixed or {})
    return tuple(n for n in names if n in chosen and n not in held)


def _parameter_values(model: ForceModel, values: Mapping[str, float] | None, what: str) -> dict[str, float]:
    """``fixed`` or ``start`` (``what``) as name -> float [SI], else InputError: a mapping of ``model``'s parameter
    names to finite real numbers (not bool or str) within the parameter's range (``PARAMETER_RANGES``, as
    ``--fix``; >= 0 for another model's names), a start > 0 (the fit starts from its logarithm)."""
    if values is None:
        return {}
    if not isinstance(values, Mapping):
        raise InputError(f"{what} must be a mapping of parameter names to values [SI], e.g. {{'beta': 0.5}}, "
                         f"got {type(values).__name__}")
    out: dict[str, float] = {}
    for name, value in values.items():
        if name not in model.parameter_names:
            raise InputError(f"{what}: unknown parameter {shown(name)} for model {model.name}; expected some of "
                             f"{', '.join(model.parameter_names)}")
        lo, hi = PARAMETER_RANGES.get(name, (0.0, math.inf))
        number = number_within(value, f"{what} {name}", lo, hi, model.units.get(name, "SI"))
        if what == "start" and not number > 0.0:
            raise InputError(f"start {name} must be > 0 (the fit starts from its logarithm), got {shown(value)}")
        out[name] = number
    return out


def _check_dataset(dataset: Any) -> None:
    """Refuse what is no :class:`Dataset` in one line (a list of trials raised AttributeError: no 'conditions')."""
    if not isinstance(dataset, Dataset):
        raise InputError(f"dataset must be a Dataset (load_dataset, synthesize), got {type(dataset).__name__}; fit "
                         "a list of trials of one mud with fit_condition")


def _prepare(trials: Sequence[Trial | PreparedTrial]) -> list[PreparedTrial]:
    if isinstance(trials, (Trial, PreparedTrial)):
        raise InputError("trials must be a list of Trial (or PreparedTrial), got one Trial: pass [trial]")
    if isinstance(trials, (str, bytes)) or not isinstance(trials, Iterable):
        raise InputError(f"trials must be a list of Trial (or PreparedTrial), got {type(trials).__name__}")
    trials = list(trials)
    if not trials:
        raise InputError("no trials to fit")
    for k, t in enumerate(trials):
        if not isinstance(t, (Trial, PreparedTrial)):
            raise InputError(f"trials[{k}] must be a Trial (or PreparedTrial), got {type(t).__name__}")
        # what a file's reader would refuse, as identify refuses it (2 samples gave zeta +- 0, a time of 1e300 s
        # raised ValueError, a force of 1e300 N an RMSE of inf)
        (t.trial if isinstance(t, PreparedTrial) else t).check_bounds()
    return [t if isinstance(t, PreparedTrial) else prepare_trial(t) for t in trials]


def _stage_indices(model: ForceModel, stage: FitStage, free: Sequence[str]) -> list[int]:
    return [model.parameter_names.index(n) for n in stage.parameters if n in free]


def _run_stage(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
               idx: list[int], window: str, search: str, options: FitOptions, seed: int,
               prefix_fixed: bool = False, reading: str = "band") -> np.ndarray:
    names = [model.parameter_names[i] for i in idx]
    obj = _Objective(model, foot, [prepared], [values], [[(0, i)] for i in idx], window, prefix_fixed, reading)
    lo, hi = _log_bounds(model, names)
    current = np.log(values[idx])
    if search == "global":
        slo, shi = _log_bounds(model, names, search=True)
        # the current point is in the initial population, so the search's best is at least as good
        candidates = [_global_search(obj, current, slo, shi, options, seed)]
    else:
        pool = [current] + [np.log(model.vector(s)[idx]) for s in model.starts]
        costs = [obj.cost(np.clip(x, lo, hi)) for x in pool]
        candidates = [pool[i] for i in np.argsort(costs, kind="stable")[: max(options.starts, 1)]]
    best_x, best_cost = current, obj.cost(current)
    for x0 in candidates:
        x = _least_squares(obj, x0, lo, hi, options.max_nfev)
        c = obj.cost(x)
        if c < best_cost:
            best_x, best_cost = x, c
    out: np.ndarray = values.copy()
    out[idx] = np.exp(best_x)
    return out


def _discretisation_of(model: ForceModel, foot: Foot, tr: PreparedTrial, values: np.ndarray,
                       reading: str) -> np.ndarray:
    """The model's own discretisation error at ``tr``'s rate, sample by sample [N^2], at ``values`` [SI]
    (:func:`~mudforce.estimation.calibration._recording_model._discretisation`, identify's reading; issue 23, point 4):
    zeros on a lab protocol (the fitted noise-free motion, the paper's) or a trial of fewer than eight samples."""
    if tr.motion is not None or tr.time.size < 8:
        return np.zeros(tr.time.size)
    band = model.rest_band

    def run(t: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if band is not None:
            out: tuple[np.ndarray, np.ndarray, np.ndarray] = band(t, z, foot)(values)
            return out
        f = model.force(t, z, values, foot)
        return f, f, f

    rest = _rest_of(model, tr, reading)
    rest = np.zeros(tr.time.size, dtype=bool) if rest is None else rest
    return _discretisation(tr.time, tr.depth, run, rest, run(tr.time, tr.depth)[0])[0]


#: The normal law's 97.5 % point [-]: +-this many standard errors is a 95 % interval.
_Z95 = 1.959963984540054

#: Contiguous blocks each trial is cut into for the jackknife when a condition has fewer than three trials (ours).
_JACKKNIFE_BLOCKS = 10

#: Share of the noise floor's variance [-] carried by the depth noise above which fit warns of errors in
#: variables: least squares takes the errors to be in the force, and past half of the floor they are mostly in
#: the depth, the regressor, which biases the fitted parameters by an amount the standard errors do not hold
#: (the project's walks under 1 mm of depth noise read their stiffnesses up to about 3 standard errors low; the
#: floor's depth share there is 0.83-0.96, on every other corruption of the sensor-chain bench's walks at most
#: 0.49; docs/estimation.md, "fit under a noisy depth").
DEPTH_NOISE_SHARE_WARNING = 0.5


def _jackknife_spread(jac: np.ndarray, residual: np.ndarray, groups: Sequence[np.ndarray]) -> np.ndarray | None:
    """:func:`jackknife_variance` over ``groups``, scaled so that +-1.96 of its standard errors is the 95 % interval
    (ours): a variance read from ``g`` groups is itself uncertain, with ``g - 1`` degrees of freedom, so the error
    over that standard error is a Student t of ``g - 1`` degrees, not a normal; the factor is ``(t_{g-1}(0.975) /
    1.96)^2``: 1.33 for one recording's :data:`_JACKKNIFE_BLOCKS` (its standard errors 15 % wider), 4.8 for three
    trials. It applies where the jackknife's variance is the larger. On 80 clean gait walks of the sensor-chain
    bench (30 s, 100 Hz, one recording a fit) the standard errors had been too small in the tail: ``beta``'s errors
    over their standard errors spread 1.12 (1.03 after), and 4 of 67 unwarned fits had a parameter beyond 3 standard
    errors (``beta``, ``zeta`` twice, ``omega_0``), where 1.6 is what nine parameters of exact standard errors give;
    2 after."""
    spread = jackknife_variance(jac, residual, groups)
    if spread is None:
        return None
    factor = (float(student_t.ppf(0.975, len(groups) - 1)) / _Z95) ** 2
    return spread * factor


def _flag_statistic(model: ForceModel, foot: Foot, tr: PreparedTrial, values: np.ndarray, reading: str,
                    offset: float, variance: np.ndarray) -> float:
    """The misfit statistic of one trial [-] (:func:`_flag_reading`'s first)."""
    return _flag_reading(model, foot, tr, values, reading, offset, variance)[0]


def _flag_reading(model: ForceModel, foot: Foot, tr: PreparedTrial, values: np.ndarray, reading: str,
                  offset: float, variance: np.ndarray) -> tuple[float, float]:
    """The misfit statistic of one trial [-], ``mean(min(r^2 / variance, 25))``, read as identify reads its flag's
    (issue 23, point 4): ``variance`` [N^2] each sample's floor, the discretisation error included; at the samples
    read through the rest band (:func:`_rest_of` of ``reading``) and where the foot may be stuck
    (:func:`~mudforce.estimation.calibration._recording_model._sticking`), the model is the set of the relaxations
    a stuck foot may have had (its depth as read, held, creeping up: identify's
    :func:`~mudforce.estimation.calibration._recording_model._model_set`, here of any model with a band), and at
    every sample the set also holds the model along the depth as recorded, before
    :func:`~mudforce.estimation.calibration.branches.denoise_depth` (which moves a sample by up to three depth
    noises, and where the noise is read from a robot's motion, 0.12 mm for 0.03, moved a touch of 0.23 mm out of the
    mud: the model then missed the -5 N neck that followed for 0.2 s); out of the mud, the set also holds the model
    along the depth :data:`_TOUCH_SIGMAS` depth noises deeper (the deeper of the recorded and the denoised one,
    which may stand three noises apart): a foot that comes down to within that of the surface
    may touch it between two samples, and a neck it then pulls out of the mud is the model's (a MuJoCo run of seed
    83 at 100 Hz: the foot hovered 0.02-0.5 mm above the surface for 0.24 s, then lifted with a suction of -20 N
    for 0.15 s that the model along the recorded depth, never in the mud, read as nothing; the truth's own
    parameters read 1.79 times the floor); and the
    force bias, the fit's least-squares ``offset`` [N], is re-profiled under the statistic's weights
    (:func:`~mudforce.estimation.calibration._recording_model._bias_reprofiled`). Least squares weighs every sample
    alike, and a few samples whose branch flips between two samples (a turn, a stance's sway) pulled the tare by half
    a newton, which each sample out of the mud then read as 3-4 force noises (the model's own force along a MuJoCo
    trot, 100 Hz: 2.16 times its floor, 1.03 read so; tests/estimation/test_fit_flag_statistic.py). On the
    sensor-chain bench's ten 10-s MuJoCo runs of seeds 70 and 78 at 50 Hz, 100 Hz and 1 kHz, both sources, clean fits
    flagged 23 -> 11 of 120 with the bias re-profiled and the stuck set, -> 3 with the recorded depth too (seed 80,
    read after the first two: 8 -> 3 of 60). Second, the share of its samples whose residual is beyond three floors
    [-] (identify's tail, ``TAIL_SHARE_WARNING``)."""
    measured = tr.force - offset
    rest = _rest_of(model, tr, reading)
    band = model.rest_band
    if rest is None or band is None:
        force = model.force(tr.time, tr.depth, values, foot)
        every = np.zeros(tr.time.size, dtype=bool)
        stat, d = _bias_reprofiled(force, force, force, measured, every, variance,
                                   (tr.depth <= 0.0) & (force**2 <= 1e-4 * variance))
        return stat, _tail(_band_residual(force, force, force, measured + d, every), variance)
    runs = [band(tr.time, tr.depth, foot)(values)]
    sticking = _sticking(tr.time, tr.depth, tr.depth_noise)
    if sticking.stuck.any():
        runs += [band(tr.time, sticking.held, foot)(values), band(tr.time, sticking.creep, foot)(values)]
    recorded = np.asarray(tr.trial.depth, dtype=np.float64)
    if recorded.shape != tr.depth.shape:
        recorded = tr.depth
    if not np.array_equal(recorded, tr.depth):
        runs.append(band(tr.time, recorded, foot)(values))  # the depth as recorded, before denoise_depth
    force, low, high = _union(runs, rest | sticking.stuck)
    out = tr.depth <= 0.0
    if tr.depth_noise > 0.0:  # a touch between two samples that the samples cannot exclude, out of the mud
        touched = band(tr.time, np.maximum(tr.depth, recorded) + _TOUCH_SIGMAS * tr.depth_noise, foot)(values)[0]
        low, high = np.where(out, np.minimum(low, touched), low), np.where(out, np.maximum(high, touched), high)
    free = out & (force**2 <= 1e-4 * variance)
    every = np.ones(tr.time.size, dtype=bool)
    stat, d = _bias_reprofiled(force, low, high, measured, every, variance, free)
    return stat, _tail(_band_residual(force, low, high, measured + d, every), variance)


def _tail(residual: np.ndarray, variance: np.ndarray) -> float:
    """The share of samples whose ``residual`` [N] is beyond three floors (``variance`` [N^2]) [-]: identify's tail."""
    return float(np.mean(residual**2 > _TAIL_Z2 * variance))


def _statistic_terms(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
                     reading: str, least: float) -> list[tuple[float, float]]:
    """Each trial's sums of the misfit flag's terms and of its samples beyond three floors at ``values`` [SI]
    (:func:`_flag_reading` times its samples): the floor (noise, depth noise carried through, discretisation error;
    at least ``least`` [N^2]) and the tare offset read at those values, as :func:`_condition_from` reads them at the
    fit's."""
    out = []
    for tr in prepared:
        fitted, offset = _fitted(model, foot, tr, values, reading)

        def force_at(z: np.ndarray, tr: PreparedTrial = tr) -> np.ndarray:
            return np.asarray(model.force(tr.time, z, values, foot))

        total, _ = noise_floor_parts(tr, fitted, force_at)
        v = np.maximum(total + _discretisation_of(model, foot, tr, values, reading), least)
        stat, tail = _flag_reading(model, foot, tr, values, reading, offset, v)
        out.append((stat * tr.time.size, tail * tr.time.size))
    return out


def _blocks(starts: np.ndarray, n_data: int) -> list[np.ndarray]:
    """The residual's rows in :data:`_JACKKNIFE_BLOCKS` contiguous blocks per trial (trial ``i``'s data rows
    ``starts[i]:starts[i + 1]``; its tare-prior row ``n_data + i`` goes with its first block).

    With fewer than three trials the delete-one-trial jackknife has too few to spread; a delete-one-block
    jackknife of each recording's stretches (Kunsch 1989, for a dependent series) sees what the noise model
    cannot within one recording: the model's errors that differ from stride to stride (an impact or a neck
    between two samples falls at another phase of the sample grid in each), which the residual's lag-1
    correlation does not hold. A block of a trial shorter than its number of blocks is the trial whole.
    """
    out: list[np.ndarray] = []
    for i in range(starts.size - 1):
        rows = np.arange(starts[i], starts[i + 1])
        parts = np.array_split(rows, _JACKKNIFE_BLOCKS) if rows.size >= _JACKKNIFE_BLOCKS else [rows]
        parts[0] = np.append(parts[0], n_data + i)
        out.extend(parts)
    return out


#: A residual lag [s] below which fit does not warn of one (ours): the fit's residual projected on the fitted force's
#: rate (:func:`_residual_lag`) reads a lag of at most 0.31 ms beyond two standard errors on clean recordings of the
#: sensor-chain bench's walks and MuJoCo runs at 20 Hz to 1 kHz (seeds 70 and 77), and 1.1-1.6 ms under a 10-ms
#: low-pass (the fit absorbs most of a lag in its viscosities; the rest is this).
_LAG_MIN = 5e-4
#: Standard errors of :func:`_residual_lag` beyond which a lag above :data:`_LAG_MIN` is warned of [-] (ours).
_LAG_SIGMAS = 2.0


def _residual_lag(trial_fits: Sequence[TrialFit], floor: float) -> tuple[float, float]:
    """The lag [s] of the measured force behind the fitted one that the fit's residual holds, and its standard
    error [s] (ours; issue 23, point 4): least squares of ``fitted - measured`` on ``tau * d(fitted)/dt``, which is
    what a force low-passed or delayed by ``tau`` leaves to first order; positive when the force lags. The standard
    error is the larger of the noise's (``floor / sqrt(sum(rate^2))``) and a delete-one-block jackknife's over
    :data:`_JACKKNIFE_BLOCKS` stretches per trial (the lag a fit leaves shows at events, which the noise's does not
    hold). ``(nan, nan)`` where the fitted force never changes."""
    num: list[float] = []
    den: list[float] = []
    still = 0.0  # sum(rate^2) [N^2/s^2] below which the fitted force is read as never changing (round-off)
    for t in trial_fits:
        if t.time.size < 3:
            continue
        still += t.time.size * (1e-9 * float(np.max(np.abs(t.fitted))) / float(t.time[-1] - t.time[0])) ** 2
        rate = np.gradient(t.fitted, t.time)
        res = t.fitted - t.force
        for rows in np.array_split(np.arange(t.time.size), _JACKKNIFE_BLOCKS):
            num.append(float(res[rows] @ rate[rows]))
            den.append(float(rate[rows] @ rate[rows]))
    n, d = np.array(num), np.array(den)
    total = float(d.sum())
    if not total > still or not math.isfinite(total):
        return math.nan, math.nan
    tau = float(n.sum()) / total
    se = floor / math.sqrt(total) if math.isfinite(floor) else 0.0
    kept = d < total  # a block that holds every change leaves nothing to divide
    if int(kept.sum()) >= 2:
        loo = (float(n.sum()) - n[kept]) / (total - d[kept])
        g = loo.size
        se = max(se, math.sqrt((g - 1) / g * float(np.sum((loo - loo.mean()) ** 2))))
    return tau, se


def _rms(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(r**2))) if r.size else math.nan


def _condition_from(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
                    free: Sequence[str], cov: np.ndarray, determined: np.ndarray, free_cols: Sequence[int],
                    stage_rmse: dict[str, float], spread: np.ndarray | None = None,
                    profile: _Profile | None = None, force_gain_uncertainty: float = 0.0,
                    held: tuple[np.ndarray, np.ndarray] | None = None, rest_reading: str = "",
                    pull: np.ndarray | None = None,
                    refit: Callable[[float], np.ndarray] | None = None) -> ConditionFit:
    names = model.parameter_names
    params = {n: float(v) for n, v in zip(names, values, strict=True)}
    stderr: dict[str, float | None] = {n: None for n in names}
    # a trial's force sign-flipped (compression negative) first: the misfit it causes is said below in general words
    warnings: list[str] = [w for w in map(_force_sign_warning, prepared) if w]
    fits = [_fitted(model, foot, tr, values, rest_reading or "band") for tr in prepared]
    residuals = [fitted - tr.force for tr, (fitted, _) in zip(prepared, fits, strict=True)]
    inflation = correlation_inflation(residuals)
    sub = cov[np.ix_(list(free_cols), list(free_cols))] * inflation
    if spread is not None:  # trials that disagree more than the noise says: the jackknife's variance wins
        var = np.diag(sub)
        wider = np.sqrt(np.maximum(spread[list(free_cols)], var) / np.where(var > 0, var, 1.0))
        wider = np.where(np.isfinite(wider) & (var > 0), wider, 1.0)
        sub = sub * np.outer(wider, wider)
    # a force gain off by 1 + g reads as every force-scale parameter off by 1 + g, together: g is taken as the
    # bound at 95 % (as identify's interval takes it), a standard error of log(1 + g) / 1.96 on their logarithms
    gain_se = math.log1p(force_gain_uncertainty) / _Z95
    scaled = np.array([n in model.force_scale for n in free], dtype=np.float64)
    sub = sub + gain_se**2 * np.outer(scaled, scaled)
    for k, (n, col) in enumerate(zip(free, free_cols, strict=True)):
        value = params[n]
        if not determined[col]:
            warnings.append(f"{n} is not determined by the data (the force does not depend on it); no standard error")
            continue
        se_log = math.sqrt(max(float(sub[k, k]), 0.0))
        stderr[n] = value * se_log
        if profile is not None and se_log > 0:
            widened, edge = profile(col, math.sqrt(max(se_log**2 - scaled[k] * gain_se**2, 0.0)))
            stderr[n] = max(value * se_log, math.hypot(widened, scaled[k] * gain_se * value))
            if edge is not None:
                warnings.append(f"{n} is not bounded {'above' if edge > value else 'below'} by this data: the "
                                f"likelihood stays within 3 standard errors of its best out to {n} = {edge:.4g} "
                                "(the end of its profile); the standard error is widened to reach it, "
                                "read it as a range, not a measurement")
        if held is not None:  # a stuck foot read both ways (_held_reading): hold the held reading's 3-SE interval
            # (both fitted on their logarithms, so > 0)
            other, other_se = float(held[0][names.index(n)]), float(held[1][k])
            reach = (abs(math.log(other / value)) + 3.0 * (other_se if math.isfinite(other_se) else 0.0)) / 3.0
            if reach * value > (stderr[n] or 0.0):
                if reach * value > 1.5 * (stderr[n] or 0.0):
                    warnings.append(f"{n} depends on how a stuck foot's mud relaxes, which this recording cannot "
                                    f"tell: read with each stuck stretch's depth held (the engines' sticking) it is "
                                    f"{other:.4g}; the standard error is widened to hold both readings")
                stderr[n] = reach * value
        if pull is not None and math.isfinite(float(pull[k])):  # the band's pull (_band_pull): hold it
            # as the held reading's: value +- 3 SE reaches the reading without the pull, 3 of its SE beyond
            reach = (stderr[n] or 0.0) + abs(float(pull[k])) * value / 3.0
            if reach > 1.5 * (stderr[n] or 0.0):
                warnings.append(f"{n} is read with a foot at rest anywhere in its rest band, which pulls it by "
                                f"{math.expm1(float(pull[k])):+.1%} on data made from this fit; the standard error "
                                "is widened to hold that")
            stderr[n] = reach
        relative = max(se_log, (stderr[n] or 0.0) / value if value > 0 else 0.0)
        if relative > POOR_RELATIVE_STDERR:
            warnings.append(f"{n} is poorly determined: relative standard error {relative:.0%}")
        lo, hi = model.bounds[n]
        if value <= lo * 1.001 or value >= hi * 0.999:
            warnings.append(f"{n} = {value:.4g} is at its bound [{lo:g}, {hi:g}]; its standard error is not reliable")
    d = np.sqrt(np.diag(sub))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = sub / np.outer(d, d)
    if model.diagnose is not None:
        warnings.extend(model.diagnose(values, prepared, foot))
    trial_fits = []
    for tr, r, (fitted, offset) in zip(prepared, residuals, fits, strict=True):
        force = tr.force - offset
        scatter = max(tr.force_noise, _rms(r + offset))
        trial_fits.append(TrialFit(
            name=tr.trial.name, water_content=tr.trial.water_content, velocity=tr.velocity,
            nominal_velocity=tr.trial.velocity, repeat=tr.trial.repeat, rmse=_rms(fitted - force),
            bias=tr.bias + offset, force_noise=tr.force_noise, reversal_time=tr.reversal_time, time=tr.time,
            depth=tr.depth, force=force, fitted=fitted,
            bias_method="estimated" if tr.bias_estimated else "tared",
            bias_stderr=scatter * math.sqrt(inflation / (tr.time.size + tr.precontact))))
    all_res = np.concatenate([t.residual for t in trial_fits])
    noise = [t.force_noise for t in trial_fits if math.isfinite(t.force_noise)]
    force_noise = float(np.sqrt(np.mean(np.square(noise)))) if noise else math.nan
    def force_on(tr: PreparedTrial) -> Callable[[np.ndarray], np.ndarray]:
        return lambda z: model.force(tr.time, z, values, foot)

    parts = [noise_floor_parts(tr, t.fitted, force_on(tr)) for tr, t in zip(prepared, trial_fits, strict=True)]
    floor_var = np.concatenate([total for total, _ in parts])
    floor = float(np.sqrt(np.mean(floor_var))) if noise else math.nan
    depth_share = float(np.mean(np.concatenate([depth for _, depth in parts])) / floor**2) if floor > 0.0 else 0.0
    if depth_share > DEPTH_NOISE_SHARE_WARNING:
        depth_noise = math.sqrt(float(np.mean([tr.depth_noise**2 for tr in prepared])))
        warnings.append(f"the depth noise ({depth_noise * 1e3:.2g} mm) carries {depth_share:.0%} of the noise floor: "
                        "the errors are mostly in the depth, where least squares takes them to be in the force, "
                        "so the parameters are biased (errors in variables: stiffnesses tend to read low), by an "
                        "amount the standard errors do not include; a smoother depth (a better kinematic or "
                        "surface estimate, or a filter before the fit) removes it")
    rmse = _rms(all_res)
    scale = max(float(np.max(np.abs(np.concatenate([t.force for t in trial_fits])))), 1.0)
    disc_said = ""
    misfit_values: np.ndarray | None = None  # the mud the flag is read at, where not least squares' (refit)
    ls_ratio = math.nan
    if noise and any(tr.motion is None for tr in prepared):
        # a recording of any motion: the floor holds the model's own discretisation error at the data's rate, each
        # at its own sample, as identify's (the RMS of the residuals each over its own floor): local, it excuses
        # the samples where an event between two samples moves the model, and no others; and the statistic is
        # identify's, the model read as the set of a stuck foot's relaxations and the bias re-profiled (_flag_statistic)
        discs = [_discretisation_of(model, foot, tr, values, rest_reading or "band") for tr in prepared]
        disc = np.concatenate(discs)
        least = max((1e-4 * scale) ** 2, 1e-18)
        vs = [np.maximum(total + d, least) for (total, _), d in zip(parts, discs, strict=True)]
        terms = [_flag_statistic(model, foot, tr, values, rest_reading or "band", offset, vi) * tr.time.size
                 for tr, vi, (_, offset) in zip(prepared, vs, fits, strict=True)]
        standardised = math.sqrt(sum(terms) / all_res.size)
        v = np.concatenate(vs)
        floor = rmse / standardised if standardised > 0.0 else math.sqrt(float(np.mean(v)))
        if refit is not None and misfit_ratio(rmse, floor, scale) > MISFIT_WARNING_RATIO:
            # least squares fails the flag's statistic: read it also at a robust refit from this fit, and keep the
            # better (a few samples may pull least squares off a mud that explains the rest)
            robust = refit(floor)
            sums = _statistic_terms(model, foot, prepared, robust, rest_reading or "band", least)
            again = math.sqrt(math.fsum(a for a, _ in sums) / all_res.size)
            tail = math.fsum(b for _, b in sums) / all_res.size
            # read there only where the refit passes clearly, each reading under 80 % of its limit (identify's
            # NEAR_LIMITS_WARNING; its tail, the share beyond three floors, TAIL_SHARE_WARNING): a second look,
            # taken because least squares failed, excuses a few samples, not a model that misses a whole kind of
            # sample (the paper's model without its rest band, a stuck foot read on the branch: 1.18 and 3.2 %)
            if again <= _ROBUST_NEAR * MISFIT_WARNING_RATIO and tail <= _ROBUST_NEAR * _ROBUST_TAIL:
                misfit_values, ls_ratio, standardised = robust, misfit_ratio(rmse, floor, scale), again
        disc_said = (f" and the model's own discretisation error at this rate, "
                     f"{math.sqrt(float(np.mean(disc))):.3g} N RMS")
        # the floor holds the model's error between two samples, and a force lag's misfit lies at the same samples
        # (fit fits no lag): the lag the residual holds is read apart from the floor
        # (a lag only, the sensor chain's: a lead of up to 2.7 ms reads on clean MuJoCo runs at 50 Hz, where an
        # impact between two samples moves the model ahead of its samples)
        tau, tau_se = _residual_lag(trial_fits, floor)  # least squares' floor (the refit's is set below)
        if math.isfinite(tau) and tau > max(_LAG_MIN, _LAG_SIGMAS * tau_se):
            sigmas = tau / tau_se if tau_se > 0 else math.inf
            warnings.append(f"the force lags the depth by {tau * 1e3:.2g} ms beyond what the fitted mud's "
                            f"viscosities hold ({sigmas:.1f} standard errors; the residual read against the fitted "
                            "force's rate): a sensor's low-pass or delay, which fit does not estimate, so the "
                            "parameters that set the force's phase (the viscosities, beta) are biased by an amount "
                            "the standard errors do not include; identify and track estimate the lag")
    if misfit_values is not None:
        floor = rmse / standardised
        moved = ", ".join(f"{n} x{misfit_values[names.index(n)] / params[n]:.2g}" for n in free
                          if abs(math.log(misfit_values[names.index(n)] / params[n])) > 0.1)
        warnings.append(f"least squares misses the data by {ls_ratio:.2g} times its noise floor, but a refit from it "
                        f"that weighs a sample beyond the floor less reads {misfit_ratio(rmse, floor, scale):.2g}"
                        f"{f' ({moved})' if moved else ''}: a few samples (a neck or a branch switch between two "
                        "samples, an impact) pull least squares off a mud that explains the rest; the misfit flag is "
                        "read at that refit (misfit_parameters), the parameters and standard errors are least "
                        "squares', read them with care")
    ratio = misfit_ratio(rmse, floor, scale)
    if ratio > MISFIT_WARNING_RATIO:
        warnings.append(f"RMSE {rmse:.3g} N is {ratio:.2g} times the noise floor {floor:.3g} N "
                        f"(force noise {force_noise:.3g} N, with the depth noise carried through"
                        f"{disc_said}): "
                        "the model misses systematic features of the data (or the fit did not converge); "
                        "the standard errors are widened for the residuals' correlation, but read them with care")
    ws = {tr.trial.water_content for tr in prepared}
    w = ws.pop() if len(ws) == 1 else math.nan
    return ConditionFit(water_content=w, model=model.name, parameters=params, stderr=stderr, free=tuple(free),
                        rmse=rmse, force_noise=force_noise, trials=tuple(trial_fits), correlation=corr,
                        warnings=tuple(dict.fromkeys(warnings)), stage_rmse=stage_rmse, misfit_ratio=ratio,
                        noise_floor=floor, rest_reading=rest_reading,
                        misfit_parameters={} if misfit_values is None else
                        {n: float(x) for n, x in zip(names, misfit_values, strict=True)})


@one_blas_thread
def fit_condition(
    trials: Sequence[Trial | PreparedTrial],
    foot: Foot | None = None,
    *,
    model: str | ForceModel = "chen2024",
    free: Iterable[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    start: Mapping[str, float] | None = None,
    seed: int = 0,
    options: FitOptions | None = None,
    progress: Progress | None = None,
    force_gain_uncertainty: float = DEFAULT_FORCE_GAIN_UNCERTAINTY,
) -> ConditionFit:
    """Fit a model to the trials of one condition.

    Parameters
    ----------
    trials : sequence of Trial or PreparedTrial
        The condition's trials (any speeds); raw trials are prepared
        (motion fitted, force tared) first.
    foot : Foot, optional
        The intruder; the paper's cuboid by default.
    model : str or ForceModel
        A registered model name (``"chen2024"``) or a model.
    free : iterable of str, optional
        The parameters to fit; by default all but the model's fixed ones
        (``rho_m`` and ``lambda`` for the paper's model).
    fixed : mapping, optional
        Name -> value [SI] for parameters held fixed (overrides ``free``): finite, within the parameter's range
        (:data:`~mudforce.model.parameters.PARAMETER_RANGES`, as ``--fix``; >= 0 for a name not there).
    start : mapping, optional
        Name -> value [SI] to start from (default: the model's defaults): as ``fixed``, and > 0.
    seed : int
        Seeds the global search; the same seed and data give the same fit. An integer >= 0 (for
        :func:`fit_dataset` and :func:`fit_by_velocity` at most ``2**32 - 1``, as ``--seed``).
    options : FitOptions, optional
        Optimiser budget.
    progress : Progress, optional
        Advanced by one per stage.
    force_gain_uncertainty : float
        Relative uncertainty of the force sensor's gain [-], in [0, 0.5) (default 5 %, as identify's): a gain
        error cannot be told from a mud whose force-scale parameters (:attr:`ForceModel.force_scale
        <mudforce.estimation.calibration.models.ForceModel.force_scale>`: the stiffnesses, viscosities, ``alpha``
        and ``sigma_y`` of the paper's model) are all off by as much, so it is taken as their error bound at
        95 %: their standard errors on the logarithm gain ``log(1 + g) / 1.96`` in quadrature, fully correlated.

    Returns
    -------
    ConditionFit
    """
    check_force_gain_uncertainty(force_gain_uncertainty)
    if not is_integer(seed) or seed < 0:  # fit_dataset's conditions' seeds pass MAX_SEED: no upper bound here
        raise InputError(f"seed must be an integer >= 0, got {shown(seed)}")
    m = get_model(model)
    fixed, start = _parameter_values(m, fixed, "fixed"), _parameter_values(m, start, "start")
    foot = Foot.paper() if foot is None else foot
    options = _options(options)
    if progress is not None and not isinstance(progress, Progress):  # 3 raised AttributeError after the first stage
        raise InputError(f"progress must be a mudforce Progress or None, got {type(progress).__name__}")
    prepared = _prepare(trials)
    free_names = _resolve_free(m, free, fixed)
    if not free_names:
        raise InputError("nothing to fit: every parameter is fixed")
    values = m.vector({**(start or {}), **(fixed or {})})
    stage_rmse: dict[str, float] = {}
    for s, stage in enumerate(m.stages):
        idx = _stage_indices(m, stage, free_names)
        if idx:
            values = _run_stage(m, foot, prepared, values, idx, stage.window, stage.search, options,
                                seed + 7919 * s, stage.prefix_fixed)
            stage_rmse[stage.name] = _rms(np.concatenate(
                [_trial_residual(m, foot, tr, values, stage.window) for tr in prepared]))
        if progress is not None:
            progress.update(1, stage.name)
    idx_all = [m.parameter_names.index(n) for n in free_names]
    values = _run_stage(m, foot, prepared, values, idx_all, "all", "local", FitOptions(
        starts=1, max_nfev=options.max_nfev), seed)
    reading = ""
    if any(r is not None and bool(r.any()) for r in (_rest_of(m, tr) for tr in prepared)):
        # a band scores every sample inside it zero: the narrowest reading that reads the data as well
        reading, values = _narrowest_reading(m, foot, prepared, values, idx_all, options, seed)
    obj = _Objective(m, foot, [prepared], [values], [[(0, i)] for i in idx_all], "all", reading=reading or "band")
    x = np.log(values[idx_all])
    residual = obj(x)
    stage_rmse["joint"] = _rms(residual[: -len(prepared)])  # without the tare-prior rows
    jac = jacobian(obj, x)
    cov, determined = covariance(jac, residual, motion_sensitivity(m, foot, [prepared], [values]))
    n_data = residual.size - len(prepared)
    starts = np.cumsum([0] + [tr.time.size for tr in prepared])
    groups = [np.append(np.arange(starts[i], starts[i + 1]), n_data + i) for i in range(len(prepared))]
    if len(groups) < 3:
        groups = _blocks(starts, n_data)
    spread = _jackknife_spread(jac, residual, groups)
    lo, hi = _log_bounds(m, free_names)
    profile = _profiler(obj, x, jac, lo, hi, max(options.max_nfev // 4, 20))
    held = _held_reading(m, foot, prepared, values, idx_all, options, seed, stage_rmse["joint"], reading or "band")
    pull = None
    if reading in ("band", "turns"):  # a band pulls the fit toward wider bands: measured, and held in the errors
        pull = _band_pull(m, foot, prepared, values, idx_all, options, seed, reading)
    if progress is not None:
        progress.update(1, "joint polish")
    def refit(scale: float) -> np.ndarray:  # the robust refit the flag is read at where least squares fails it
        out: np.ndarray = values.copy()
        out[idx_all] = np.exp(_robust_refit(obj, x, lo, hi, scale))
        return out

    return _condition_from(m, foot, prepared, values, free_names, cov, determined, list(range(len(idx_all))),
                           stage_rmse, spread, profile, force_gain_uncertainty, held, reading, pull, refit)


# ---------------------------------------------------------------------------- a dataset
@one_blas_thread
def fit_dataset(
    dataset: Dataset,
    *,
    model: str | ForceModel = "chen2024",
    free: Iterable[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    shared: Sequence[str] = (),
    seed: int = 0,
    options: FitOptions | None = None,
    quiet: bool = False,
    force_gain_uncertainty: float = DEFAULT_FORCE_GAIN_UNCERTAINTY,
) -> FitResult:
    """Fit every water content of a dataset; optionally share some parameters across them.

    Parameters
    ----------
    dataset : Dataset
        The trials and the foot.
    model, free, fixed, seed, options
        As for :func:`fit_condition`.
    shared : sequence of str
        Parameters that take one value for all water contents (e.g.
        ``("k_m_w", "b_m_w")``, which the paper found nearly constant). The
        conditions are first fitted independently, then jointly with these tied.
    quiet : bool
        No progress on the terminal.
    force_gain_uncertainty : float
        As for :func:`fit_condition` [-]; recorded in the result.

    Returns
    -------
    FitResult
    """
    _check_dataset(dataset)
    check_force_gain_uncertainty(force_gain_uncertainty)
    quiet, seed = true_or_false(quiet, "quiet"), seed_int(seed, "seed")
    m = get_model(model)
    fixed, options = _parameter_values(m, fixed, "fixed"), _options(options)
    free_names = _resolve_free(m, free, fixed)
    if isinstance(shared, (str, bytes)):  # its letters are no names
        raise InputError(f"shared must be a sequence of parameter names, e.g. ('k_m_w', 'b_m_w'), got {shared!r}")
    shared = tuple(shared)
    for n in shared:
        if shared.count(n) > 1:  # tied twice, it was two free copies of one parameter: a degenerate joint fit
            raise InputError(f"--shared {n}: given twice; give each parameter once")
        if n not in free_names:
            raise InputError(f"--shared {n}: not a fitted parameter of model {m.name}; "
                             f"expected some of {', '.join(free_names)}")
    groups = dataset.conditions()
    steps = len(groups) * (len(m.stages) + 1) + (1 if shared else 0)
    fits: list[ConditionFit] = []
    prepared_groups: list[list[PreparedTrial]] = []
    with Progress(steps, "fitting", quiet=quiet) as progress:
        for ci, trials in enumerate(groups.values()):
            prepared = _prepare(trials)
            prepared_groups.append(prepared)
            fits.append(fit_condition(prepared, dataset.foot, model=m, free=free_names, fixed=fixed,
                                      seed=seed + 104729 * ci, options=options, progress=progress,
                                      force_gain_uncertainty=force_gain_uncertainty))
        if shared and len(fits) > 1:
            fits = _fit_shared(m, dataset.foot, prepared_groups, fits, free_names, tuple(shared), options,
                               force_gain_uncertainty, seed)
            progress.update(1, "shared")
    return FitResult(conditions=tuple(fits), model=m.name, shared=tuple(shared), seed=seed, foot=dataset.foot,
                     force_gain_uncertainty=force_gain_uncertainty)


@one_blas_thread
def fit_by_velocity(
    dataset: Dataset,
    *,
    model: str | ForceModel = "chen2024",
    free: Iterable[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    seed: int = 0,
    options: FitOptions | None = None,
    quiet: bool = False,
    force_gain_uncertainty: float = DEFAULT_FORCE_GAIN_UNCERTAINTY,
) -> list[tuple[float, ConditionFit]]:
    """Fit each (water content, speed) on its own trials, for parameter-against-speed plots (Fig. 10 of [1]).

    Trials are grouped by :func:`speed_key` (the nominal speed, or the
    measured one to 0.5 mm/s). Returns ``(speed [m/s], fit)`` pairs,
    ordered by water content, then speed.
    """
    _check_dataset(dataset)
    quiet, seed = true_or_false(quiet, "quiet"), seed_int(seed, "seed")
    m = get_model(model)
    fixed, options = _parameter_values(m, fixed, "fixed"), _options(options)
    groups: dict[tuple[float, float], list[PreparedTrial]] = {}
    for w, trials in dataset.conditions().items():
        for tr in _prepare(trials):
            v = speed_key(tr.trial.velocity, tr.velocity)
            groups.setdefault((w, v), []).append(tr)
    out = []
    with Progress(len(groups) * (len(m.stages) + 1), "fitting per speed", quiet=quiet) as progress:
        for i, ((_, v), prepared) in enumerate(sorted(groups.items())):
            out.append((v, fit_condition(prepared, dataset.foot, model=m, free=free, fixed=fixed,
                                         seed=seed + 15485863 * (i + 1), options=options, progress=progress,
                                         force_gain_uncertainty=force_gain_uncertainty)))
    return out


def _fit_shared(model: ForceModel, foot: Foot, groups: list[list[PreparedTrial]], fits: list[ConditionFit],
                free: Sequence[str], shared: tuple[str, ...], options: FitOptions | None,
                force_gain_uncertainty: float = 0.0, seed: int = 0) -> list[ConditionFit]:
    """Refit all conditions jointly, with the ``shared`` parameters tied across them."""
    options = _options(options)
    # the samples at rest read as the widest of the conditions' readings
    reading = max((f.rest_reading for f in fits if f.rest_reading), key=_READINGS.index, default="band")
    names = model.parameter_names
    base = [model.vector(f.parameters) for f in fits]
    slots: list[list[tuple[int, int]]] = []
    x0: list[float] = []
    labels: list[tuple[int | None, str]] = []
    for n in shared:
        i = names.index(n)
        slots.append([(g, i) for g in range(len(groups))])
        x0.append(float(np.mean([math.log(b[i]) for b in base])))  # geometric mean of the separate fits
        labels.append((None, n))
    for g in range(len(groups)):
        for n in free:
            if n not in shared:
                slots.append([(g, names.index(n))])
                x0.append(math.log(base[g][names.index(n)]))
                labels.append((g, n))
    obj = _Objective(model, foot, groups, base, slots, "all", reading=reading)
    lo, hi = _log_bounds(model, [n for _, n in labels])
    x = _least_squares(obj, np.array(x0), lo, hi, options.max_nfev * 2)
    residual = obj(x)
    values = obj.values(x)
    jac = jacobian(obj, x)
    cov, determined = covariance(jac, residual, motion_sensitivity(model, foot, groups, values))
    # as for one condition: the jackknife over every trial of every condition, and the profile likelihood
    # (a shared parameter is profiled once, for the first condition that asks, with every other parameter refitted)
    sizes = [tr.time.size for group in groups for tr in group]
    n_data = residual.size - len(sizes)
    starts = np.cumsum([0, *sizes])
    rows = [np.append(np.arange(starts[i], starts[i + 1]), n_data + i) for i in range(len(sizes))]
    spread = _jackknife_spread(jac, residual, rows)
    one = _profiler(obj, x, jac, lo, hi, max(options.max_nfev // 4, 20))
    seen: dict[int, tuple[float, float | None]] = {}

    def profile(j: int, se_log: float) -> tuple[float, float | None]:
        if j not in seen:
            seen[j] = one(j, se_log)
        return seen[j]

    out = []
    for g, prepared in enumerate(groups):
        cols = [j for j, (owner, _) in enumerate(labels) if owner is None or owner == g]
        order = [labels[j][1] for j in cols]
        # reorder to the model's parameter order
        perm = sorted(range(len(order)), key=lambda k: names.index(order[k]))
        cols = [cols[k] for k in perm]
        fnames = tuple(order[k] for k in perm)
        rest_g = fits[g].rest_reading and reading
        # where a band is read, its pull on this condition's own trials (every one of its free parameters refitted)
        pull = (_band_pull(model, foot, prepared, values[g], [names.index(n) for n in fnames], options,
                           seed + 104729 * g, rest_g) if rest_g in ("band", "turns") else None)
        out.append(_condition_from(model, foot, prepared, values[g], fnames, cov, determined, cols,
                                   {**fits[g].stage_rmse, "shared": _rms(residual)}, spread, profile,
                                   force_gain_uncertainty, rest_reading=rest_g, pull=pull))
    return out

