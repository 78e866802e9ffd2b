"""Fit results: what a fit returns, what ``fit.json`` holds, and reading it back.

:class:`FitResult` (a dataset), :class:`ConditionFit` (one water content)
and :class:`TrialFit` (one trial) are what :func:`~mudforce.estimation.calibration.fit.fit_dataset`
and :func:`~mudforce.estimation.calibration.fit.fit_condition` return; :func:`load_fit`
reads a ``fit.json`` back into a :class:`FitResult` (without the trials'
samples, which the file does not hold).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mudforce.errors import InputError
from mudforce.io import atomic_write_text, load_json
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

__all__ = [
    "MISFIT_WARNING_RATIO",
    "POOR_RELATIVE_STDERR",
    "ConditionFit",
    "FitResult",
    "TrialFit",
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
    """``rmse / noise`` [-], with the noise floored at ``1e-4 scale`` (noiseless data fitted exactly is no misfit).

    Parameters
    ----------
    rmse : float
        RMS residual [N].
    noise : float
        Force noise estimated independently of the fit [N].
    scale : float
        Typical force of the data [N] (its largest magnitude).
    """
    floor = max(noise if math.isfinite(noise) else 0.0, 1e-4 * scale, 1e-9)
    return rmse / floor


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
        within its uncertainty (see :func:`~mudforce.estimation.calibration.preprocess.tare_correction`).
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

    @classmethod
    def from_dict(cls, data: dict[str, Any], water_content: float) -> TrialFit:
        """The summary :meth:`to_dict` wrote (no samples: empty arrays)."""
        empty = np.empty(0)
        return cls(name=str(data["file"]), water_content=water_content, velocity=_nan_if_none(data["velocity_m_s"]),
                   nominal_velocity=None, repeat=None, rmse=float(data["rmse_N"]), bias=float(data["bias_N"]),
                   force_noise=_nan_if_none(data["force_noise_N"]),
                   reversal_time=_nan_if_none(data["reversal_time_s"]), time=empty, depth=empty, force=empty,
                   fitted=empty, bias_method=str(data.get("bias_method", "tared")),
                   bias_stderr=_nan_if_none(data.get("bias_stderr_N")))

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
        model explains the data to the sensors' noise. On a recording of any
        motion, the misfit flag's statistic (each residual over its own floor),
        read at ``misfit_parameters`` where those are given.
    noise_floor : float
        The RMSE a perfect model would leave [N]: the force noise and the
        depth noise carried through the model's sensitivity to the depth
        (:func:`~mudforce.estimation.calibration.preprocess.noise_floor`);
        on a recording of any motion (not a lab protocol) also the model's
        own discretisation error at the data's rate, estimated from the data
        as identify's, each sample over its own floor (issue 23, point 4).
        A force lag's misfit lies where that error does, and fit estimates
        no lag: the lag the residual holds is read apart, and warned of
        (docs/estimation.md, "fit").
    rest_reading : str
        How the samples at which a foot is at rest (or turns between two samples) were read: ``"band"``, anywhere
        in the model's rest band (a stuck foot carries its load there); ``"branch"``, on the model's branch, which
        reads them to their noise; ``"turns"``, the band at the turns alone and the slow samples on the branch. The
        fit keeps the narrowest that reads the data as well as the band (a band scores every sample inside it zero,
        and would let the fit widen it over the noise). ``""`` where no sample is read so (a lab protocol, a model
        without a band, a foot never at rest).
    misfit_parameters : dict
        Name -> value [SI] of the mud the misfit flag was read at, where that is not ``parameters`` (ours): on a
        recording of any motion whose least-squares fit fails the flag's statistic, a refit from it with a loss
        that weighs a sample beyond the floor less (a few samples, a neck or a branch switch between two samples,
        can pull least squares off a mud that explains the rest); the flag reads the better of the two, and a
        warning says so. Empty where the flag is read at ``parameters``.
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
    rest_reading: str = ""
    misfit_parameters: dict[str, float] = field(default_factory=dict)

    @property
    def model_misses_data(self) -> bool:
        """True when the RMSE is more than :data:`MISFIT_WARNING_RATIO` times the force noise."""
        return self.misfit_ratio > MISFIT_WARNING_RATIO

    def mud_parameters(self) -> MudParameters:
        """The fitted values as :class:`MudParameters` (for the paper's model)."""
        return MudParameters.from_dict(self.parameters, source=f"mudforce fit, W = {self.water_content:g}")

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> ConditionFit:
        """A condition as :meth:`to_dict` wrote it."""
        w = _nan_if_none(data["water_content"])
        corr = data["correlation"]
        matrix = np.array([[_nan_if_none(x) for x in row] for row in corr["matrix"]], dtype=np.float64)
        return cls(water_content=w, model=str(data["model"]),
                   parameters={k: float(v) for k, v in data["parameters"].items()},
                   stderr={k: None if v is None else float(v) for k, v in data["stderr"].items()},
                   free=tuple(corr["parameters"]), rmse=float(data["rmse_N"]),
                   force_noise=_nan_if_none(data["force_noise_N"]),
                   trials=tuple(TrialFit.from_dict(t, w) for t in data["trials"]),
                   correlation=matrix.reshape(len(corr["parameters"]), len(corr["parameters"])),
                   warnings=tuple(data["warnings"]), misfit_ratio=_nan_if_none(data.get("misfit_ratio")),
                   noise_floor=_nan_if_none(data.get("noise_floor_N")),
                   rest_reading=str(data.get("rest_reading", "")),
                   misfit_parameters={k: float(v) for k, v in (data.get("misfit_parameters") or {}).items()})

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
            "rest_reading": self.rest_reading,
            "misfit_parameters": dict(self.misfit_parameters),
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
    force_gain_uncertainty : float
        The force sensor's gain uncertainty assumed [-] (0.05: 5 %), in the standard errors of the parameters the
        force is proportional to (:attr:`~mudforce.estimation.calibration.models.ForceModel.force_scale`).
    """

    conditions: tuple[ConditionFit, ...]
    model: str
    shared: tuple[str, ...]
    seed: int
    foot: Foot
    force_gain_uncertainty: float = 0.0

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> FitResult:
        """A result as :meth:`to_dict` wrote it (the trials without their samples)."""
        foot = data["foot"]
        return cls(conditions=tuple(ConditionFit.from_dict(c) for c in data["conditions"]), model=str(data["model"]),
                   shared=tuple(data["shared"]), seed=int(data["seed"]),
                   foot=Foot(float(foot["area_m2"]), float(foot["width_m"])),
                   force_gain_uncertainty=float(data.get("force_gain_uncertainty", 0.0)))

    def to_dict(self) -> dict[str, Any]:
        """The ``fit.json`` object."""
        return {
            "model": self.model,
            "seed": self.seed,
            "shared": list(self.shared),
            "force_gain_uncertainty": self.force_gain_uncertainty,
            "foot": {"area_m2": self.foot.area, "width_m": self.foot.width},
            "conditions": [c.to_dict() for c in self.conditions],
        }

    def to_json(self, indent: int | None = 2) -> str:
        """``fit.json`` as text (deterministic for a given dataset and seed); refuses NaN and infinities."""
        from mudforce.io import dumps_json

        return dumps_json(self.to_dict(), indent=indent)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write :meth:`to_json` atomically."""
        atomic_write_text(path, self.to_json() + "\n")


def load_fit(path: str | os.PathLike[str]) -> FitResult:
    """Read a ``fit.json`` back into a :class:`FitResult`.

    Everything the file holds comes back (parameters, standard errors,
    correlations, RMSEs, noise, warnings, per-trial summaries); the trials'
    samples are not in the file, so each :class:`TrialFit` has empty arrays.
    The file is read strictly (:func:`mudforce.io.load_json`: no NaN, no key twice).
    ``load_fit(p).to_dict()`` equals the file's object.
    """
    data = load_json(path, "fit result", 'a fit.json object with "conditions"')
    if not isinstance(data, dict) or not isinstance(data.get("conditions"), list):
        raise InputError(f'{path}: expected a fit.json object with "conditions"')
    try:
        return FitResult.from_dict(data)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{path}: not a fit.json written by mudforce fit ({type(exc).__name__}: {exc})") from None


def speed_key(nominal: float | None, measured: float) -> float:
    """The speed [m/s] a trial is grouped under: its nominal one, else the measured one to 0.5 mm/s."""
    if nominal is not None:
        return nominal
    return round(measured * 2000.0) / 2000.0 if math.isfinite(measured) else 0.0


def load_fit_parameters(path: str | os.PathLike[str]) -> dict[float, MudParameters]:
    """The fitted parameter sets of a ``fit.json`` (paper's model), keyed by water content [-]."""
    out = {}
    for i, cond in enumerate(load_fit(path).conditions):
        try:
            w = float(cond.water_content)
            out[w] = MudParameters.from_dict(cond.parameters, source=f"{path}, W = {w:g}")
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"{path}: conditions[{i}] is not a fit of the paper's model ({exc})") from None
    return out


def _finite_or_none(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def _nan_if_none(x: Any) -> float:
    return math.nan if x is None else float(x)


