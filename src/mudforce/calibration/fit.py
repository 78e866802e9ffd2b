"""Fitting the model to measured intrusion trials, with honest standard errors.

The objective is the force residual ``model - measured`` [N] at every sample
of every trial of a condition (one water content), after each trial is
prepared (:mod:`mudforce.calibration.preprocess`: motion fitted, force
tared). The model follows the fitted noise-free motion with the exact
branch rule, so the reversal happens at the right sample.

The fit is staged, as Section III-A of [1] suggests (:data:`CHEN2024.stages
<mudforce.calibration.models.CHEN2024>`):

1. intrusion and hold (``k_m_i, b_m_i, alpha, beta``) on the samples up to
   the reversal: bounded least squares from the best Table I rows;
2. withdrawal (``k_m_w, b_m_w, sigma_y, zeta, omega_0``) on the samples after
   it: seeded differential evolution, then least squares. Necking makes this
   objective non-smooth in ``sigma_y`` (the neck breaks at a different
   sample), and a local solver alone stalls on its plateaus;
3. every free parameter jointly, on all samples.

Parameters are fitted as logarithms inside bounds. Standard errors come
from the Jacobian at the optimum (central differences):
``cov = s^2 (J^T J)^-1`` in log space with ``s^2 = SSR / (n - p)``, mapped to
SI by the delta method. Directions the data does not constrain (a zero
singular value: e.g. ``sigma_y`` when no trial necks) get no standard error
(``null``) and a warning, rather than a meaningless number.

.. [1] X. Chen, J. Yi, J. Shan, arXiv:2403.02617 (2024).
"""

from __future__ import annotations

import inspect
import json
import math
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import differential_evolution, least_squares

from mudforce.calibration.dataset import Dataset, Trial
from mudforce.calibration.models import FitStage, ForceModel, get_model
from mudforce.calibration.preprocess import PreparedTrial, noise_floor, prepare_trial, tare_correction
from mudforce.errors import InputError
from mudforce.foot import Foot
from mudforce.io import atomic_write_text
from mudforce.parameters import MudParameters
from mudforce.progress import Progress

__all__ = [
    "MISFIT_WARNING_RATIO",
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

#: Relative standard error above which a parameter is reported as poorly determined [-].
POOR_RELATIVE_STDERR = 0.25
#: RMSE / force noise above which the model is said to miss the data [-].
MISFIT_WARNING_RATIO = 1.25


def misfit_ratio(rmse: float, noise: float, scale: float) -> float:
    """``rmse / noise`` [-], with the noise floored at ``1e-6 scale`` (noiseless data fitted exactly gives ~1, not 1e5).

    Parameters
    ----------
    rmse : float
        RMS residual [N].
    noise : float
        Force noise estimated independently of the fit [N].
    scale : float
        Typical force of the data [N] (its largest magnitude).
    """
    floor = max(noise if math.isfinite(noise) else 0.0, 1e-6 * scale, 1e-9)
    return rmse / floor


def correlation_inflation(residuals: Sequence[np.ndarray]) -> float:
    """``n / n_eff`` >= 1 from the lag-1 autocorrelation of the residuals [-].

    Residuals that the model leaves correlated (it misses a feature of the
    data) carry less information than their count suggests; the
    covariance is multiplied by this factor (``(1 + rho) / (1 - rho)``).
    """
    num = sum(float(r[1:] @ r[:-1]) for r in residuals if r.size > 2)
    den = sum(float(r @ r) for r in residuals if r.size > 2)
    rho = min(max(num / den, 0.0), 0.99) if den > 0 else 0.0
    return (1.0 + rho) / (1.0 - rho)


@dataclass(frozen=True)
class FitOptions:
    """The optimiser's budget (the defaults fit one condition of 9 trials in a few seconds).

    Attributes
    ----------
    starts : int
        Best starting points (by cost, among the model's ``starts`` and the
        current values) from which each local stage runs least squares.
    popsize : int
        Differential-evolution population per parameter.
    maxiter : int
        Differential-evolution generations at most.
    tol : float
        Differential-evolution relative convergence tolerance.
    max_nfev : int
        Residual evaluations per least-squares run, at most.
    """

    starts: int = 2
    popsize: int = 12
    maxiter: int = 60
    tol: float = 1e-4
    max_nfev: int = 400


# ---------------------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class TrialFit:
    """One trial's data and fitted force.

    Attributes
    ----------
    name : str
        The trial's file name or id.
    water_content : float
        [-].
    velocity : float
        Intrusion speed measured from the fitted motion [m/s].
    nominal_velocity : float or None
        The manifest's speed [m/s].
    repeat : int or None
        Repeat number.
    rmse : float
        Root mean square of ``fitted - force`` over all samples [N].
    bias : float
        Force-sensor bias removed [N]: the pre-contact tare, refined by the fit
        within its uncertainty (see :func:`~mudforce.calibration.preprocess.tare_correction`).
    force_noise : float
        Force noise before contact [N].
    reversal_time : float
        Start of the withdrawal [s].
    time, depth, force, fitted : ndarray
        Samples [s], fitted depth [m], tared measured force [N], model force [N].
    bias_method : str
        ``"tared"`` (from the samples before the first contact, refined within
        their uncertainty) or ``"estimated"`` (the trial starts in the mud: the
        bias is a free parameter of the fit).
    bias_stderr : float
        Standard error of ``bias`` [N].
    """

    name: str
    water_content: float
    velocity: float
    nominal_velocity: float | None
    repeat: int | None
    rmse: float
    bias: float
    force_noise: float
    reversal_time: float
    time: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    fitted: np.ndarray
    bias_method: str = "tared"
    bias_stderr: float = math.nan

    @property
    def residual(self) -> np.ndarray:
        """``fitted - force`` [N]."""
        out: np.ndarray = self.fitted - self.force
        return out

    def to_dict(self) -> dict[str, Any]:
        """The JSON entry: ``file, rmse_N, bias_N, force_noise_N, velocity_m_s, reversal_time_s``."""
        return {
            "file": self.name,
            "rmse_N": self.rmse,
            "bias_N": self.bias,
            "force_noise_N": _finite_or_none(self.force_noise),
            "velocity_m_s": _finite_or_none(self.velocity),
            "reversal_time_s": _finite_or_none(self.reversal_time),
            "bias_method": self.bias_method,
            "bias_stderr_N": _finite_or_none(self.bias_stderr),
        }


@dataclass(frozen=True, eq=False)
class ConditionFit:
    """The fit of one condition (one water content).

    Attributes
    ----------
    water_content : float
        [-] (NaN if unknown).
    model : str
        The fitted model's name.
    parameters : dict
        Name -> value [SI], every parameter of the model.
    stderr : dict
        Name -> standard error [SI]; None where fixed or not determined by the data.
    free : tuple of str
        The fitted parameters.
    rmse : float
        Root mean square residual over all samples of all trials [N].
    force_noise : float
        RMS over the trials of their force noise [N], measured without the
        model (pre-contact samples, or the force's high-frequency content).
    trials : tuple of TrialFit
    correlation : ndarray
        Correlation matrix of the log-parameters in ``free`` order (NaN where not determined).
    warnings : tuple of str
        Identifiability and fit-quality warnings.
    stage_rmse : dict
        Stage name -> RMSE [N] over that stage's samples when it ended.
    misfit_ratio : float
        ``rmse / noise_floor`` [-] (see :func:`misfit_ratio`): about 1 when the
        model explains the data to the sensors' noise.
    noise_floor : float
        The RMSE a perfect model would leave [N]: the force noise and the
        depth noise carried through the model's sensitivity to the depth
        (:func:`~mudforce.calibration.preprocess.noise_floor`).
    """

    water_content: float
    model: str
    parameters: dict[str, float]
    stderr: dict[str, float | None]
    free: tuple[str, ...]
    rmse: float
    force_noise: float
    trials: tuple[TrialFit, ...]
    correlation: np.ndarray
    warnings: tuple[str, ...] = ()
    stage_rmse: dict[str, float] = field(default_factory=dict)
    misfit_ratio: float = math.nan
    noise_floor: float = math.nan

    @property
    def model_misses_data(self) -> bool:
        """True when the RMSE is more than :data:`MISFIT_WARNING_RATIO` times the force noise."""
        return self.misfit_ratio > MISFIT_WARNING_RATIO

    def mud_parameters(self) -> MudParameters:
        """The fitted values as :class:`MudParameters` (for the paper's model)."""
        return MudParameters.from_dict(self.parameters, source=f"mudforce fit, W = {self.water_content:g}")

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of one condition in ``fit.json``."""
        corr = [[_finite_or_none(x) for x in row] for row in self.correlation]
        return {
            "water_content": _finite_or_none(self.water_content),
            "model": self.model,
            "parameters": dict(self.parameters),
            "stderr": {k: _finite_or_none(v) for k, v in self.stderr.items()},
            "rmse_N": self.rmse,
            "force_noise_N": _finite_or_none(self.force_noise),
            "noise_floor_N": _finite_or_none(self.noise_floor),
            "misfit_ratio": _finite_or_none(self.misfit_ratio),
            "model_misses_data": self.model_misses_data,
            "trials": [t.to_dict() for t in self.trials],
            "correlation": {"parameters": list(self.free), "matrix": corr},
            "warnings": list(self.warnings),
        }


@dataclass(frozen=True, eq=False)
class FitResult:
    """The fit of a whole dataset.

    Attributes
    ----------
    conditions : tuple of ConditionFit
        One per water content, ascending.
    model : str
        The model's name.
    shared : tuple of str
        Parameters shared across water contents (empty: independent fits).
    seed : int
        The seed used.
    foot : Foot
        The foot of the dataset.
    """

    conditions: tuple[ConditionFit, ...]
    model: str
    shared: tuple[str, ...]
    seed: int
    foot: Foot

    def to_dict(self) -> dict[str, Any]:
        """The ``fit.json`` object."""
        return {
            "model": self.model,
            "seed": self.seed,
            "shared": list(self.shared),
            "foot": {"area_m2": self.foot.area, "width_m": self.foot.width},
            "conditions": [c.to_dict() for c in self.conditions],
        }

    def to_json(self, indent: int | None = 2) -> str:
        """``fit.json`` as text (deterministic for a given dataset and seed)."""
        return json.dumps(self.to_dict(), indent=indent)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write :meth:`to_json` atomically."""
        atomic_write_text(path, self.to_json() + "\n")


def load_fit(path: str | os.PathLike[str]) -> list[dict[str, Any]]:
    """Read the conditions of a ``fit.json`` (plain dicts: ``water_content``, ``parameters``, ``stderr`` ...)."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: malformed JSON at line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    if not isinstance(data, dict) or not isinstance(data.get("conditions"), list):
        raise InputError(f'{path}: expected a fit.json object with "conditions"')
    return list(data["conditions"])


def speed_key(nominal: float | None, measured: float) -> float:
    """The speed [m/s] a trial is grouped under: its nominal one, else the measured one to 0.5 mm/s."""
    if nominal is not None:
        return nominal
    return round(measured * 2000.0) / 2000.0 if math.isfinite(measured) else 0.0


def load_fit_parameters(path: str | os.PathLike[str]) -> dict[float, MudParameters]:
    """The fitted parameter sets of a ``fit.json`` (paper's model), keyed by water content [-]."""
    out = {}
    for i, cond in enumerate(load_fit(path)):
        try:
            w = float(cond["water_content"])
            out[w] = MudParameters.from_dict(cond["parameters"], source=f"{path}, W = {w:g}")
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"{path}: conditions[{i}] is not a fit of the paper's model ({exc})") from None
    return out


def _finite_or_none(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


# ---------------------------------------------------------------------------- the objective
class _Objective:
    """Force residuals [N] of groups of trials for a vector of log-parameters.

    ``slots[j]`` lists the (group, parameter index) pairs that ``x[j]`` sets,
    so one entry can be shared by several groups (water contents).
    """

    def __init__(self, model: ForceModel, foot: Foot, groups: Sequence[Sequence[PreparedTrial]],
                 base: Sequence[np.ndarray], slots: Sequence[Sequence[tuple[int, int]]], window: str,
                 prefix_fixed: bool = False) -> None:
        self.model = model
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

    def values(self, x: np.ndarray) -> list[np.ndarray]:
        out = [b.copy() for b in self.base]
        for xj, targets in zip(np.exp(x), self.slots, strict=True):
            for g, i in targets:
                out[g][i] = xj
        return out

    def __call__(self, x: np.ndarray) -> np.ndarray:
        parts = []
        priors = []
        for g, (values, group) in enumerate(zip(self.values(x), self.groups, strict=True)):
            for i, tr in enumerate(group):
                if self.tails is not None:
                    r = self.tails[g][i](values) - tr.force[tr.reversal_index:]
                else:
                    r = _trial_residual(self.model, self.foot, tr, values, self.window)
                data, prior = _profiled(r, tr.precontact)
                parts.append(data)
                priors.append(prior)
        return np.concatenate([*parts, np.array(priors)])

    def cost(self, x: np.ndarray) -> float:
        r = self(x)
        return float(r @ r)


def _profiled(residual: np.ndarray, precontact: int) -> tuple[np.ndarray, float]:
    """A trial's residual with its tare offset profiled out, and the offset's prior row (see ``tare_correction``)."""
    offset = tare_correction(residual, precontact)
    return residual + offset, offset * math.sqrt(precontact)


def _trial_residual(model: ForceModel, foot: Foot, tr: PreparedTrial, values: np.ndarray, window: str) -> np.ndarray:
    t, z, f = tr.time, tr.depth, tr.force
    k = tr.reversal_index
    if window == "intrusion":  # the force up to the reversal does not depend on what follows
        head: np.ndarray = model.force(t[:k], z[:k], values, foot) - f[:k]
        return head
    r: np.ndarray = model.force(t, z, values, foot) - f
    return r[k:] if window == "withdrawal" else r


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


_DE_TAKES_RNG = "rng" in inspect.signature(differential_evolution).parameters


def _global_search(obj: _Objective, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, options: FitOptions,
                   seed: int) -> np.ndarray:
    seeding: dict[str, Any] = {"rng": np.random.default_rng(seed)} if _DE_TAKES_RNG else {"seed": seed}
    sol = differential_evolution(obj.cost, list(zip(lo, hi, strict=True)), popsize=options.popsize,
                                 maxiter=options.maxiter, tol=options.tol, polish=False, workers=1,
                                 updating="immediate", init="latinhypercube", x0=np.clip(x0, lo, hi), **seeding)
    return np.asarray(sol.x)


def _jacobian(fun: Callable[[np.ndarray], np.ndarray], x: np.ndarray, step: float = 1e-5) -> np.ndarray:
    """Central-difference Jacobian of ``fun`` at ``x`` (log-parameters)."""
    cols = []
    for j in range(x.size):
        e = np.zeros_like(x)
        e[j] = step
        cols.append((fun(x + e) - fun(x - e)) / (2.0 * step))
    return np.column_stack(cols)


@dataclass(frozen=True)
class _MotionBlock:
    """One trial's share of the errors-in-variables term: where its rows are, how they move, and C_m."""

    rows: slice
    prior_row: int
    sensitivity: np.ndarray  # d(data rows)/d(motion), n_i x 7
    prior_sensitivity: np.ndarray  # d(prior row)/d(motion), 7
    covariance: np.ndarray  # 7 x 7


def _motion_sensitivity(model: ForceModel, foot: Foot, groups: Sequence[Sequence[PreparedTrial]],
                        values: Sequence[np.ndarray]) -> list[_MotionBlock]:
    """How the residual vector of :class:`_Objective` (window "all") moves with each trial's fitted motion."""
    trials = [(tr, v) for group, v in zip(groups, values, strict=True) for tr in group]
    n_data = sum(tr.time.size for tr, _ in trials)
    blocks = []
    row = 0
    for i, (tr, v) in enumerate(trials):
        if tr.motion is None or tr.motion_covariance is None:  # general path: the depth is not a fitted motion
            row += tr.time.size
            continue
        m0 = tr.motion.vector()
        dt = float(np.median(np.diff(tr.time)))
        sens = np.empty((tr.time.size, 7))
        prior = np.empty(7)
        for j, h in enumerate([1e-4 * dt] * 4 + [1e-6] * 3):
            e = np.zeros(7)
            e[j] = h
            parts = []
            for sign in (1.0, -1.0):
                depth = tr.motion.from_vector(m0 + sign * e).depth_at(tr.time)
                parts.append(_profiled(model.force(tr.time, depth, v, foot) - tr.force, tr.precontact))
            sens[:, j] = (parts[0][0] - parts[1][0]) / (2 * h)
            prior[j] = (parts[0][1] - parts[1][1]) / (2 * h)
        blocks.append(_MotionBlock(slice(row, row + tr.time.size), n_data + i, sens, prior, tr.motion_covariance))
        row += tr.time.size
    return blocks


def _covariance(jac: np.ndarray, residual: np.ndarray,
                motion: Sequence[_MotionBlock] = ()) -> tuple[np.ndarray, np.ndarray]:
    """Covariance of the log-parameters, and a mask of the ones the data determines.

    ``cov = s^2 (J^T J)^+ + A G C_m G^T A^T`` with ``s^2 = SSR / (n - p)``,
    ``A = J^+``: the first term is the force noise; the second (errors in
    variables) carries the uncertainty ``C_m`` of the motions fitted to the
    measured depth through the residual's sensitivity ``G`` to them
    (``motion``, from :func:`_motion_sensitivity`; block diagonal over trials). A
    parameter with a noticeable share in a (numerically) zero singular
    direction is undetermined.
    """
    n, p = jac.shape
    s2 = float(residual @ residual) / max(n - p, 1)
    u, sv, vt = np.linalg.svd(jac, full_matrices=False)
    tol = sv[0] * 1e-7 if sv.size and sv[0] > 0 else 1.0
    null = sv <= tol
    inv = np.where(null, 0.0, 1.0 / np.where(null, 1.0, sv))
    cov = (vt.T * inv**2) @ vt * s2
    ut = u.T
    for block in motion:
        projected = ut[:, block.rows] @ block.sensitivity + np.outer(ut[:, block.prior_row], block.prior_sensitivity)
        b = (vt.T * inv) @ projected
        cov = cov + b @ block.covariance @ b.T
    determined = np.ones(p, dtype=bool)
    if np.any(null):
        determined = np.sum(vt[null] ** 2, axis=0) < 1e-3
    cov[~determined, :] = np.nan
    cov[:, ~determined] = np.nan
    return cov, determined


# ---------------------------------------------------------------------------- one condition
def _resolve_free(model: ForceModel, free: Iterable[str] | None, fixed: Mapping[str, float] | None) -> tuple[str, ...]:
    names = model.parameter_names
    chosen = [n for n in names if n not in model.fixed] if free is None else list(free)
    for n in chosen:
        if n not in names:
            raise InputError(f"unknown parameter {n!r} for model {model.name}; expected one of {', '.join(names)}")
    held = set(fixed or {})
    return tuple(n for n in names if n in chosen and n not in held)


def _prepare(trials: Sequence[Trial | PreparedTrial]) -> list[PreparedTrial]:
    if not trials:
        raise InputError("no trials to fit")
    return [t if isinstance(t, PreparedTrial) else prepare_trial(t) for t in trials]


def _stage_indices(model: ForceModel, stage: FitStage, free: Sequence[str]) -> list[int]:
    return [model.parameter_names.index(n) for n in stage.parameters if n in free]


def _run_stage(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
               idx: list[int], window: str, search: str, options: FitOptions, seed: int,
               prefix_fixed: bool = False) -> np.ndarray:
    names = [model.parameter_names[i] for i in idx]
    obj = _Objective(model, foot, [prepared], [values], [[(0, i)] for i in idx], window, prefix_fixed)
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


def _rms(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(r**2))) if r.size else math.nan


def _condition_from(model: ForceModel, foot: Foot, prepared: Sequence[PreparedTrial], values: np.ndarray,
                    free: Sequence[str], cov: np.ndarray, determined: np.ndarray, free_cols: Sequence[int],
                    stage_rmse: dict[str, float]) -> ConditionFit:
    names = model.parameter_names
    params = {n: float(v) for n, v in zip(names, values, strict=True)}
    stderr: dict[str, float | None] = {n: None for n in names}
    warnings: list[str] = []
    residuals = [model.force(tr.time, tr.depth, values, foot) - tr.force for tr in prepared]
    inflation = correlation_inflation(residuals)
    sub = cov[np.ix_(list(free_cols), list(free_cols))] * inflation
    for k, (n, col) in enumerate(zip(free, free_cols, strict=True)):
        value = params[n]
        if not determined[col]:
            warnings.append(f"{n} is not determined by the data (the force does not depend on it); no standard error")
            continue
        se_log = math.sqrt(max(float(sub[k, k]), 0.0))
        stderr[n] = value * se_log
        if se_log > POOR_RELATIVE_STDERR:
            warnings.append(f"{n} is poorly determined: relative standard error {se_log:.0%}")
        lo, hi = model.bounds[n]
        if value <= lo * 1.001 or value >= hi * 0.999:
            warnings.append(f"{n} = {value:.4g} is at its bound [{lo:g}, {hi:g}]; its standard error is not reliable")
    d = np.sqrt(np.diag(sub))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = sub / np.outer(d, d)
    if model.diagnose is not None:
        warnings.extend(model.diagnose(values, prepared, foot))
    trial_fits = []
    for tr, r in zip(prepared, residuals, strict=True):
        fitted = r + tr.force
        offset = tare_correction(r, tr.precontact)
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

    floor_var = np.concatenate([noise_floor(tr, t.fitted, force_on(tr))
                                for tr, t in zip(prepared, trial_fits, strict=True)])
    floor = float(np.sqrt(np.mean(floor_var))) if noise else math.nan
    rmse = _rms(all_res)
    scale = max(float(np.max(np.abs(np.concatenate([t.force for t in trial_fits])))), 1.0)
    ratio = misfit_ratio(rmse, floor, scale)
    if ratio > MISFIT_WARNING_RATIO:
        warnings.append(f"RMSE {rmse:.3g} N is {ratio:.2g} times the noise floor {floor:.3g} N "
                        f"(force noise {force_noise:.3g} N, with the depth noise carried through): "
                        "the model misses systematic features of the data (or the fit did not converge); "
                        "the standard errors are widened for the residuals' correlation, but read them with care")
    ws = {tr.trial.water_content for tr in prepared}
    w = ws.pop() if len(ws) == 1 else math.nan
    return ConditionFit(water_content=w, model=model.name, parameters=params, stderr=stderr, free=tuple(free),
                        rmse=rmse, force_noise=force_noise, trials=tuple(trial_fits), correlation=corr,
                        warnings=tuple(dict.fromkeys(warnings)), stage_rmse=stage_rmse, misfit_ratio=ratio,
                        noise_floor=floor)


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
        Name -> value [SI] for parameters held fixed (overrides ``free``).
    start : mapping, optional
        Name -> value [SI] to start from (default: the model's defaults).
    seed : int
        Seeds the global search; the same seed and data give the same fit.
    options : FitOptions, optional
        Optimiser budget.
    progress : Progress, optional
        Advanced by one per stage.

    Returns
    -------
    ConditionFit
    """
    m = get_model(model)
    foot = Foot.paper() if foot is None else foot
    options = FitOptions() if options is None else options
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
    obj = _Objective(m, foot, [prepared], [values], [[(0, i)] for i in idx_all], "all")
    x = np.log(values[idx_all])
    residual = obj(x)
    stage_rmse["joint"] = _rms(residual[: -len(prepared)])  # without the tare-prior rows
    cov, determined = _covariance(_jacobian(obj, x), residual, _motion_sensitivity(m, foot, [prepared], [values]))
    if progress is not None:
        progress.update(1, "joint polish")
    return _condition_from(m, foot, prepared, values, free_names, cov, determined, list(range(len(idx_all))),
                           stage_rmse)


# ---------------------------------------------------------------------------- a dataset
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

    Returns
    -------
    FitResult
    """
    m = get_model(model)
    free_names = _resolve_free(m, free, fixed)
    for n in shared:
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
                                      seed=seed + 104729 * ci, options=options, progress=progress))
        if shared and len(fits) > 1:
            fits = _fit_shared(m, dataset.foot, prepared_groups, fits, free_names, tuple(shared), options)
            progress.update(1, "shared")
    return FitResult(conditions=tuple(fits), model=m.name, shared=tuple(shared), seed=seed, foot=dataset.foot)


def fit_by_velocity(
    dataset: Dataset,
    *,
    model: str | ForceModel = "chen2024",
    free: Iterable[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    seed: int = 0,
    options: FitOptions | None = None,
    quiet: bool = False,
) -> list[tuple[float, ConditionFit]]:
    """Fit each (water content, speed) on its own trials, for parameter-against-speed plots (Fig. 10 of [1]).

    Trials are grouped by :func:`speed_key` (the nominal speed, or the
    measured one to 0.5 mm/s). Returns ``(speed [m/s], fit)`` pairs,
    ordered by water content, then speed.
    """
    m = get_model(model)
    groups: dict[tuple[float, float], list[PreparedTrial]] = {}
    for w, trials in dataset.conditions().items():
        for tr in _prepare(trials):
            v = speed_key(tr.trial.velocity, tr.velocity)
            groups.setdefault((w, v), []).append(tr)
    out = []
    with Progress(len(groups) * (len(m.stages) + 1), "fitting per speed", quiet=quiet) as progress:
        for i, ((_, v), prepared) in enumerate(sorted(groups.items())):
            out.append((v, fit_condition(prepared, dataset.foot, model=m, free=free, fixed=fixed,
                                         seed=seed + 15485863 * (i + 1), options=options, progress=progress)))
    return out


def _fit_shared(model: ForceModel, foot: Foot, groups: list[list[PreparedTrial]], fits: list[ConditionFit],
                free: Sequence[str], shared: tuple[str, ...], options: FitOptions | None) -> list[ConditionFit]:
    """Refit all conditions jointly, with the ``shared`` parameters tied across them."""
    options = FitOptions() if options is None else options
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
    obj = _Objective(model, foot, groups, base, slots, "all")
    lo, hi = _log_bounds(model, [n for _, n in labels])
    x = _least_squares(obj, np.array(x0), lo, hi, options.max_nfev * 2)
    residual = obj(x)
    values = obj.values(x)
    cov, determined = _covariance(_jacobian(obj, x), residual, _motion_sensitivity(model, foot, groups, values))
    out = []
    for g, prepared in enumerate(groups):
        cols = [j for j, (owner, _) in enumerate(labels) if owner is None or owner == g]
        order = [labels[j][1] for j in cols]
        # reorder to the model's parameter order
        perm = sorted(range(len(order)), key=lambda k: names.index(order[k]))
        cols = [cols[k] for k in perm]
        fnames = tuple(order[k] for k in perm)
        out.append(_condition_from(model, foot, prepared, values[g], fnames, cov, determined, cols,
                                   {**fits[g].stage_rmse, "shared": _rms(residual)}))
    return out

