"""Calibration: fit the model to measured intrusion experiments, and identify the mud's water content.

Modules, in the order data flows through them:

* :mod:`~mudforce.estimation.calibration.dataset` -- the dataset format (``dataset.json``
  plus one CSV per trial, or one tidy CSV), :func:`load_dataset`, :func:`save_dataset`;
* :mod:`~mudforce.estimation.calibration.synth` -- :func:`synthesize`, :func:`synthesize_gait`:
  datasets from the model (the lab protocol, or robot-like walks) with noise
  and sensor bias (``mudforce synth [--motion gait]``);
* :mod:`~mudforce.estimation.calibration.branches` -- trials of any motion: each step's
  branch from the depth and the force's jumps, the denoised depth, the noise;
* :mod:`~mudforce.estimation.calibration.preprocess` -- each trial readied: the protocol
  refinement (motion fitted, reversal located precisely) or the general path;
  force tared or its bias left to the fit;
* :mod:`~mudforce.estimation.calibration.models` -- every model a fit can use, listed in
  one place (:data:`CHEN2024` and the baselines; add others with :func:`register_model`);
* :mod:`~mudforce.estimation.calibration.fit` -- :func:`fit_condition`, :func:`fit_dataset`
  (``mudforce fit``); its results in :mod:`~mudforce.estimation.calibration.results`
  (:class:`FitResult`, :func:`load_fit`) and its standard errors in
  :mod:`~mudforce.estimation.calibration.uncertainty`;
* :mod:`~mudforce.estimation.calibration.drag` -- :func:`fit_drag`, lambda from sliding
  experiments (``mudforce fit-drag``);
* :mod:`~mudforce.estimation.calibration.identify` -- :func:`identify_water_content`
  (``mudforce identify``);
* :mod:`~mudforce.estimation.calibration.report` -- :func:`write_report` (``--report``).

Everything is SI: s, m, N, Pa; water content is a fraction.
"""

from __future__ import annotations

from mudforce.estimation.calibration.dataset import Dataset, Trial, load_dataset, load_trial, parse_foot, save_dataset
from mudforce.estimation.calibration.drag import DragFit, fit_drag, read_sliding
from mudforce.estimation.calibration.fit import (
    ConditionFit,
    FitOptions,
    FitResult,
    TrialFit,
    fit_by_velocity,
    fit_condition,
    fit_dataset,
    load_fit,
    load_fit_parameters,
)
from mudforce.estimation.calibration.fit3d import Fit3D, fit_3d
from mudforce.estimation.calibration.identify import Identification, identify_water_content
from mudforce.estimation.calibration.models import CHEN2024, MODELS, FitStage, ForceModel, get_model, register_model
from mudforce.estimation.calibration.preprocess import Motion, PreparedTrial, fit_motion, prepare_trial, tare
from mudforce.estimation.calibration.synth import synthesize, synthesize_gait

__all__ = [
    "CHEN2024",
    "MODELS",
    "ConditionFit",
    "Dataset",
    "DragFit",
    "Fit3D",
    "FitOptions",
    "FitResult",
    "FitStage",
    "ForceModel",
    "Identification",
    "Motion",
    "PreparedTrial",
    "Trial",
    "TrialFit",
    "fit_3d",
    "fit_by_velocity",
    "fit_condition",
    "fit_dataset",
    "fit_drag",
    "fit_motion",
    "get_model",
    "identify_water_content",
    "load_dataset",
    "load_fit",
    "load_fit_parameters",
    "load_trial",
    "parse_foot",
    "prepare_trial",
    "read_sliding",
    "register_model",
    "save_dataset",
    "synthesize",
    "synthesize_gait",
    "tare",
]
