"""The numbers of :mod:`mudforce.reproduce`: what ``summary.json`` holds, and which fitted values are determined.

Everything in ``summary.json`` is SI (m, s, N, Pa, kg/m^3; water content
as a fraction) and rounded to 6 significant digits, so that the file is
the same, byte for byte, for the same seed. The paper's units
(:data:`PAPER_UNITS`) are for display only (``report.html``, figures).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from mudforce.estimation.calibration.dataset import Dataset
from mudforce.estimation.calibration.fit import POOR_RELATIVE_STDERR, ConditionFit
from mudforce.model.foot import Foot
from mudforce.model.parameters import (
    CITATION,
    PAPER_UNITS,  # the one table of the paper's units (re-exported here)
    TABLE_I,
    TABLE_I_RMSE_N,
    MudParameters,
)
from mudforce.reproduce.experiments import ReproduceConfig
from mudforce.steppers.simulation import simulate

__all__ = [
    "MODEL_LABELS",
    "NINE",
    "PAPER_UNITS",
    "POORLY_DETERMINED",
    "determined",
    "in_paper_units",
    "make_summary",
    "summary_json",
]

#: The nine parameters of Table I, in its order.
NINE: tuple[str, ...] = tuple(PAPER_UNITS)
#: Display names of the models in the summary (the paper's model, then the baselines).
MODEL_LABELS: dict[str, str] = {"mud_model": "mud model (Chen et al.)", "granular_rft": "granular RFT",
                                "drft": "dynamic RFT", "maxwell_only": "Maxwell only"}


def in_paper_units(name: str, value: Any) -> Any:
    """``value`` of parameter ``name`` (SI; float or array) in the paper's unit (:data:`PAPER_UNITS`)."""
    return value / PAPER_UNITS[name][0]


def _round(x: Any) -> Any:
    """Floats to 6 significant digits (NaN/inf to None), recursively."""
    if isinstance(x, bool) or x is None or isinstance(x, (int, str)):
        return x
    if isinstance(x, (float, np.floating)):
        v = float(x)
        return float(f"{v:.6g}") if math.isfinite(v) else None
    if isinstance(x, Mapping):
        return {str(k): _round(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_round(v) for v in x]
    if isinstance(x, np.ndarray):
        return [_round(v) for v in x.tolist()]
    raise TypeError(f"cannot put {type(x).__name__} in summary.json")


#: Relative standard error above which a fitted value is drawn and listed as not determined [-]: the
#: calibration's own threshold (:data:`mudforce.estimation.calibration.fit.POOR_RELATIVE_STDERR`), written once there.
POORLY_DETERMINED: float = POOR_RELATIVE_STDERR


def determined(fit: ConditionFit, name: str) -> bool:
    """Whether the data determines parameter ``name`` of ``fit``.

    True when it was fitted, has a standard error below
    :data:`POORLY_DETERMINED` of its value, and is not at a bound of the model.
    """
    from mudforce.estimation.calibration.models import get_model

    se = fit.stderr.get(name)
    value = fit.parameters[name]
    if name not in fit.free or se is None or not math.isfinite(se) or se > POORLY_DETERMINED * abs(value):
        return False
    lo, hi = get_model(fit.model).bounds[name]
    return lo * 1.001 < value < hi * 0.999


def _pooled_rmse(fits: Sequence[ConditionFit]) -> float:
    res = np.concatenate([t.residual for f in fits for t in f.trials])
    return float(np.sqrt(np.mean(res**2)))


def _rmse_with(params: MudParameters, fit: ConditionFit, foot: Foot) -> float:
    """RMSE [N] of fixed parameters on a condition's (tared) trials."""
    res = [simulate(t.time, t.depth, params, foot, velocity_filter="exact").force - t.force for t in fit.trials]
    r = np.concatenate(res)
    return float(np.sqrt(np.mean(r**2)))


def _necks(params: MudParameters, velocity: float, foot: Foot) -> bool:
    from mudforce.motions.protocol import Protocol

    t, z = Protocol.paper(velocity=velocity, approach=0.005).sample()
    return bool(simulate(t, z, params, foot, velocity_filter="exact").necking_times.size)


def make_summary(config: ReproduceConfig, dataset: Dataset, table: dict[float, ConditionFit],
             by_speed: dict[tuple[float, float], ConditionFit], baselines: dict[str, dict[float, ConditionFit]],
             figures: list[tuple[str, str, str]]) -> dict[str, Any]:
    from mudforce import __version__

    foot = dataset.foot
    rows = []
    critical = []
    for w, fit in table.items():
        paper = MudParameters.from_water_content(w)
        fitted = fit.mud_parameters()
        in_table = any(abs(w - tw) < 1e-9 for tw in TABLE_I)
        rows.append({
            "water_content": w,
            "fitted": {n: fit.parameters[n] for n in (*NINE, "rho_m", "lambda")},
            "stderr": {n: fit.stderr.get(n) for n in NINE},
            "determined": {n: determined(fit, n) for n in NINE},
            "paper": paper.to_dict(),
            "rmse_N": fit.rmse,
            "force_noise_N": fit.force_noise,
            "paper_parameters_rmse_N": _rmse_with(paper, fit, foot),
            "paper_reported_rmse_N": TABLE_I_RMSE_N.get(round(w, 2)) if in_table else None,
            "trials": len(fit.trials),
            "warnings": list(fit.warnings),
        })
        critical.append({
            "water_content": w,
            "fitted_m_s": fitted.critical_withdrawal_velocity,
            "fitted_determined": determined(fit, "sigma_y") and determined(fit, "b_m_w"),
            "paper_m_s": paper.critical_withdrawal_velocity,
            "necks_at_m_s": {f"{v:g}": _necks(paper, v, foot) for v in config.velocities},
        })
    base: dict[str, Any] = {"mud_model": {
        "model": "chen2024",
        "rmse_N": _pooled_rmse(list(table.values())),
        "rmse_N_by_water_content": {f"{w:g}": f.rmse for w, f in table.items()},
        "parameters_by_water_content": {f"{w:g}": f.parameters for w, f in table.items()},
    }}
    for name, fits in baselines.items():
        base[name] = {
            "model": name,
            "rmse_N": _pooled_rmse(list(fits.values())),
            "rmse_N_by_water_content": {f"{w:g}": f.rmse for w, f in fits.items()},
            "parameters_by_water_content": {f"{w:g}": f.parameters for w, f in fits.items()},
        }
    per_speed = [{"water_content": w, "velocity_m_s": v, "rmse_N": f.rmse,
                  **{n: f.parameters[n] for n in ("alpha", "beta", "sigma_y")},
                  "stderr": {n: f.stderr.get(n) for n in ("alpha", "beta", "sigma_y")},
                  "determined": {n: determined(f, n) for n in ("alpha", "beta", "sigma_y")}}
                 for (w, v), f in by_speed.items()]
    summary = {
        "mudforce_version": __version__,
        "paper": CITATION,
        "units": "SI (m, s, N, Pa, kg/m^3); water content as a fraction",
        "config": config.to_dict(),
        "table_i": rows,
        "critical_withdrawal_velocity": critical,
        "velocity_fits": per_speed,
        "baselines": base,
        "figures": [{"file": f, "paper_figure": p, "caption": c} for f, p, c in figures],
    }
    out: dict[str, Any] = _round(summary)
    return out



def summary_json(summary: Mapping[str, Any]) -> str:
    """The text of ``summary.json``."""
    return json.dumps(summary, indent=2, sort_keys=False) + "\n"
