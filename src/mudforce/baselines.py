"""Baseline force models to compare the mud model against: granular RFT, dynamic RFT, a Maxwell-only ablation.

Each baseline is a closed-form (or compiled) force law for a flat foot of
area ``S`` moved vertically along a prescribed depth ``z_i(t)`` (positive
down, SI throughout), and a :class:`~mudforce.calibration.models.ForceModel`
so that the calibration can fit it (``mudforce fit --model NAME``):

``granular_rft``
    Granular resistive force theory for a horizontal plate in vertical
    intrusion (Li, Zhang & Goldman, Science 339, 1408 (2013)): the stress on
    the plate is proportional to depth, ``sigma = k_rft z`` with ``k_rft``
    [Pa/m = N/m^3] the material's vertical RFT coefficient, so
    ``F = k_rft max(z_i, 0) S`` while the foot moves down or rests. Granular
    media are rate independent and cohesionless: no relaxation while held, and
    no suction (``F = 0``) while the foot moves up.
``drft``
    Dynamic RFT (Agarwal et al., PNAS 118 (2021) e2023945118): RFT plus an
    inertial drag ``lambda rho_m v |v|`` [Pa] while the foot is below the
    surface (the same term as Eq. (5) of Chen, Yi & Shan), so
    ``F = (k_rft max(z_i, 0) [v >= 0] + lambda rho_m v |v| [z_i > 0]) S``.
``maxwell_only``
    An ablation of the mud model: Eqs. (2)-(3) and the drag (5) only, with
    the intrusion and withdrawal Maxwell parameters, but no nonlinear spring
    ``f_e2`` (Eq. (4)) and no yield or necking (Eqs. (7), (9)). Held, its
    force relaxes to zero; pulled out, the suction never breaks.

The branch rule is the exact one of ``MODEL.md``: the step from sample
``k-1`` to ``k`` has the velocity ``v_k = (z_k - z_{k-1}) / (t_k - t_{k-1})``
(``v_0 = 0``), and ``v_k >= 0`` (down or at rest) is the intrusion branch.

Importing this module registers the three models with
:func:`mudforce.calibration.models.register_model`; :func:`register_baselines`
does it explicitly (idempotent).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from mudforce.calibration.models import FitStage, ForceModel, register_model
from mudforce.errors import InputError
from mudforce.foot import Foot
from mudforce.parameters import TABLE_I, TABLE_I_WATER_CONTENTS, MudParameters

__all__ = [
    "BASELINE_NAMES",
    "DEFAULT_K_RFT",
    "DRFT",
    "GRANULAR_RFT",
    "MAXWELL_ONLY",
    "baseline_models",
    "branch_velocity",
    "drft_force",
    "granular_rft_force",
    "maxwell_only_force",
    "register_baselines",
]

#: Registry names of the baselines, in the order reports list them.
BASELINE_NAMES: tuple[str, ...] = ("granular_rft", "drft", "maxwell_only")

#: A starting RFT depth coefficient [Pa/m]: about Table I's W = 25 % mud at 20 mm.
DEFAULT_K_RFT = 1.4e6

_RHO_M = TABLE_I[0.25].rho_m  # [kg/m^3], Section III-A of Chen, Yi & Shan
_LAMBDA = TABLE_I[0.25].lambda_  # [-], Fig. 5 of Chen, Yi & Shan

# Maxwell-only as the paper's stepper with the spring and the neck switched off:
# f_e2 = alpha (z/H)^beta with alpha this small is below 1e-20 Pa, and suction never reaches sigma_y.
_NO_SPRING_ALPHA = 1e-24  # [Pa]
_NEVER_YIELD = 1e30  # [Pa]


def _trajectory(time: Any, depth: Any) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(time, dtype=np.float64)
    z = np.asarray(depth, dtype=np.float64)
    if t.ndim != 1 or t.shape != z.shape or t.size == 0:
        raise InputError(f"time and depth must be 1-D arrays of the same non-zero length, got {t.shape}, {z.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(z))):
        raise InputError("time [s] and depth [m] must be finite")
    if t.size > 1 and np.any(np.diff(t) <= 0.0):
        raise InputError("time must be strictly increasing [s]")
    return t, z


def branch_velocity(time: Any, depth: Any) -> np.ndarray:
    """The step velocity that picks the branch: backward difference [m/s], 0 at the first sample.

    Parameters
    ----------
    time : array_like
        Sample times [s], strictly increasing.
    depth : array_like
        Foot depth [m], positive down.
    """
    t, z = _trajectory(time, depth)
    v = np.zeros_like(z)
    if z.size > 1:
        v[1:] = np.diff(z) / np.diff(t)
    return v


def _area(foot: Foot | None) -> float:
    return (Foot.paper() if foot is None else foot).area


def granular_rft_force(time: Any, depth: Any, k_rft: float, foot: Foot | None = None) -> np.ndarray:
    """Granular RFT force on a horizontal plate in vertical intrusion [N], positive up.

    ``F = k_rft max(z_i, 0) S`` when the foot moves down or rests (``v >= 0``),
    ``0`` when it moves up: linear in depth, no relaxation, no suction
    (Li, Zhang & Goldman 2013).

    Parameters
    ----------
    time : array_like
        Sample times [s].
    depth : array_like
        Foot depth ``z_i`` [m], positive down.
    k_rft : float
        Vertical RFT depth coefficient [Pa/m] (N/m^3), > 0.
    foot : Foot, optional
        Gives the area ``S`` [m^2]; the paper's 51 x 38 mm cuboid by default.
    """
    v = branch_velocity(time, depth)
    z = np.asarray(depth, dtype=np.float64)
    force: np.ndarray = np.where(v >= 0.0, float(k_rft) * np.maximum(z, 0.0), 0.0) * _area(foot)
    return force


def drft_force(time: Any, depth: Any, k_rft: float, lambda_: float = _LAMBDA, rho: float = _RHO_M,
               foot: Foot | None = None) -> np.ndarray:
    """Dynamic RFT force [N], positive up: granular RFT plus ``lambda rho v |v| S`` below the surface.

    Parameters
    ----------
    time, depth, k_rft, foot
        As for :func:`granular_rft_force` ([s], [m], [Pa/m]).
    lambda_ : float
        Drag scaling factor [-] (Eq. (5) of Chen, Yi & Shan; the paper's 0.013 by default).
    rho : float
        Density of the medium [kg/m^3] (the paper's mud, 1840, by default).
    """
    v = branch_velocity(time, depth)
    z = np.asarray(depth, dtype=np.float64)
    drag = np.where(z > 0.0, float(lambda_) * float(rho) * v * np.abs(v), 0.0) * _area(foot)
    force: np.ndarray = granular_rft_force(time, depth, k_rft, foot) + drag
    return force


def maxwell_only_force(time: Any, depth: Any, k_m_i: float, b_m_i: float, k_m_w: float, b_m_w: float,
                       rho_m: float = _RHO_M, lambda_: float = _LAMBDA, foot: Foot | None = None) -> np.ndarray:
    """The mud model without its nonlinear spring and without necking [N], positive up.

    Eqs. (2), (3) and (5) of Chen, Yi & Shan with the intrusion parameters
    ``k_m_i`` [Pa/m], ``b_m_i`` [Pa s/m] and the withdrawal ones ``k_m_w``,
    ``b_m_w``; ``f_e2 = 0`` and the neck never breaks. Runs the exact
    compiled stepper of :func:`mudforce.simulate`.
    """
    from mudforce.simulation import simulate

    t, z = _trajectory(time, depth)
    params = MudParameters(k_m_i, b_m_i, k_m_w, b_m_w, _NO_SPRING_ALPHA, 1.0, _NEVER_YIELD, 1.0, 1.0,
                           rho_m, lambda_, source="maxwell_only ablation")
    force: np.ndarray = simulate(t, z, params, foot, velocity_filter="exact").force
    return force


# ---------------------------------------------------------------------------- fitting
def _rft_fit(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
    return granular_rft_force(time, depth, float(values[0]), foot)


def _drft_fit(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
    return drft_force(time, depth, float(values[0]), float(values[1]), float(values[2]), foot)


def _maxwell_fit(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
    k_i, b_i, k_w, b_w, rho, lam = (float(x) for x in values)
    try:
        return maxwell_only_force(time, depth, k_i, b_i, k_w, b_w, rho, lam, foot)
    except InputError:  # numerically impossible values: a huge, finite residual
        return np.full(np.shape(time), 1e6)


_K_STARTS = (1e5, 1e6, 1e7)


def baseline_models() -> dict[str, ForceModel]:
    """The three baselines as :class:`~mudforce.calibration.models.ForceModel` objects, by name."""
    rft = ForceModel(
        name="granular_rft",
        parameter_names=("k_rft",),
        force=_rft_fit,
        bounds={"k_rft": (1e2, 1e10)},
        defaults={"k_rft": DEFAULT_K_RFT},
        starts=tuple({"k_rft": k} for k in _K_STARTS),
        units={"k_rft": "Pa/m"},
    )
    drft = ForceModel(
        name="drft",
        parameter_names=("k_rft", "lambda", "rho_m"),
        force=_drft_fit,
        bounds={"k_rft": (1e2, 1e10), "lambda": (1e-6, 1e4), "rho_m": (1e2, 2e4)},
        defaults={"k_rft": DEFAULT_K_RFT, "lambda": _LAMBDA, "rho_m": _RHO_M},
        fixed=("rho_m",),
        starts=tuple({"k_rft": k, "lambda": lam} for k in _K_STARTS for lam in (_LAMBDA, 10.0)),
        units={"k_rft": "Pa/m", "lambda": "-", "rho_m": "kg/m^3"},
    )
    rows: tuple[Mapping[str, float], ...] = tuple(
        {n: TABLE_I[w].to_dict()[n] for n in ("k_m_i", "b_m_i", "k_m_w", "b_m_w")} for w in TABLE_I_WATER_CONTENTS
    )
    mx = ForceModel(
        name="maxwell_only",
        parameter_names=("k_m_i", "b_m_i", "k_m_w", "b_m_w", "rho_m", "lambda"),
        force=_maxwell_fit,
        bounds={"k_m_i": (1e3, 1e9), "b_m_i": (1e2, 1e9), "k_m_w": (1e3, 1e9), "b_m_w": (1e2, 1e9),
                "rho_m": (1e2, 2e4), "lambda": (1e-6, 1e2)},
        defaults={**rows[2], "rho_m": _RHO_M, "lambda": _LAMBDA},
        fixed=("rho_m", "lambda"),
        starts=rows,
        stages=(
            FitStage("intrusion and hold", ("k_m_i", "b_m_i"), "intrusion", "local"),
            FitStage("withdrawal", ("k_m_w", "b_m_w"), "withdrawal", "local"),
        ),
        units={"k_m_i": "Pa/m", "b_m_i": "Pa s/m", "k_m_w": "Pa/m", "b_m_w": "Pa s/m", "rho_m": "kg/m^3",
               "lambda": "-"},
    )
    return {m.name: m for m in (rft, drft, mx)}


def register_baselines() -> None:
    """Register ``granular_rft``, ``drft`` and ``maxwell_only`` for ``mudforce fit --model NAME`` (idempotent)."""
    for model in _MODELS.values():
        register_model(model)


_MODELS = baseline_models()
#: Granular RFT (Li, Zhang & Goldman 2013) as a fittable model; parameter ``k_rft`` [Pa/m].
GRANULAR_RFT = _MODELS["granular_rft"]
#: Dynamic RFT as a fittable model; parameters ``k_rft`` [Pa/m], ``lambda`` [-], ``rho_m`` [kg/m^3] (fixed).
DRFT = _MODELS["drft"]
#: The Maxwell-only ablation as a fittable model; ``k_m_i, b_m_i, k_m_w, b_m_w`` (+ fixed ``rho_m``, ``lambda``).
MAXWELL_ONLY = _MODELS["maxwell_only"]

register_baselines()
