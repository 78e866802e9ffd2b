"""Mud model parameters: the validated parameter set and the paper's Table I.

All values are SI inside the package. Table I is stored in the paper's own
units (MPa/m, MPa s/m, MPa, kPa) and converted once, here, on load.

References
----------
.. [1] X. Chen, J. Yi, J. Shan, "A Reduced-Order Resistive Force Model for
   Robotic Foot-Mud Interactions", arXiv:2403.02617 (2024), Table I.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mudforce._plumbing.deprecation import module_getattr as _deprecated_getattr
from mudforce.errors import InputError, is_real, real_number, shown

__all__ = [
    "CITATION",
    "PAPER_UNITS",
    "PARAMETER_NAMES",
    "PARAMETER_RANGES",
    "RHO_M",
    "TABLE_I",
    "TABLE_I_RMSE_N",
    "TABLE_I_WATER_CONTENTS",
    "WATER_CONTENT_RANGE",
    "MudParameters",
]

#: The paper this package implements, as a citation string; every built-in parameter set cites it.
#: (Its model, as a force law to fit, is :data:`mudforce.estimation.calibration.CHEN2024`.)
CITATION = (
    'X. Chen, J. Yi, J. Shan, "A Reduced-Order Resistive Force Model for '
    'Robotic Foot-Mud Interactions", arXiv:2403.02617 (2024)'
)

#: The 11 parameters, in SI, under their JSON keys (``lambda`` is ``lambda_`` in Python).
PARAMETER_NAMES: tuple[str, ...] = (
    "k_m_i",
    "b_m_i",
    "k_m_w",
    "b_m_w",
    "alpha",
    "beta",
    "sigma_y",
    "zeta",
    "omega_0",
    "rho_m",
    "lambda",
)

_PY_NAME = {name: ("lambda_" if name == "lambda" else name) for name in PARAMETER_NAMES}

_UNITS = {
    "k_m_i": "Pa/m",
    "b_m_i": "Pa s/m",
    "k_m_w": "Pa/m",
    "b_m_w": "Pa s/m",
    "alpha": "Pa",
    "beta": "-",
    "sigma_y": "Pa",
    "zeta": "-",
    "omega_0": "rad/s",
    "rho_m": "kg/m^3",
    "lambda": "-",
}

#: Water contents (volume fraction) of Table I's rows.
TABLE_I_WATER_CONTENTS: tuple[float, ...] = (0.15, 0.20, 0.25, 0.30, 0.35)

#: The range of water contents that :meth:`MudParameters.from_water_content` accepts.
WATER_CONTENT_RANGE: tuple[float, float] = (0.15, 0.35)

# Table I of [1] in the paper's units:
# k_i [MPa/m], b_i [MPa s/m], k_w [MPa/m], b_w [MPa s/m], alpha [MPa], beta,
# sigma_y [kPa], zeta, omega_0 [rad/s]
_TABLE_I_PAPER_UNITS = (
    (1.21, 0.24, 1.48, 1.35, 0.17, 0.56, 17.0, 0.47, 4.09),
    (0.70, 0.16, 1.71, 1.56, 0.12, 0.49, 14.0, 0.31, 3.45),
    (0.26, 0.29, 1.21, 1.35, 0.04, 0.54, 6.0, 0.49, 2.23),
    (0.11, 0.06, 1.27, 1.40, 0.01, 0.46, 2.0, 0.36, 1.44),
    (0.28, 0.07, 1.16, 1.36, 0.01, 0.38, 2.0, 0.81, 2.21),
)
#: The paper's units of Table I: name -> (SI value of one paper unit, unit); the one table of them
#: (Table I below, the reproduce report and the calibration report all convert with it).
PAPER_UNITS: dict[str, tuple[float, str]] = {
    "k_m_i": (1e6, "MPa/m"), "b_m_i": (1e6, "MPa s/m"), "k_m_w": (1e6, "MPa/m"), "b_m_w": (1e6, "MPa s/m"),
    "alpha": (1e6, "MPa"), "beta": (1.0, "-"), "sigma_y": (1e3, "kPa"), "zeta": (1.0, "-"),
    "omega_0": (1.0, "rad/s"),
}
_TABLE_I_SCALE = tuple(scale for scale, _ in PAPER_UNITS.values())

#: The RMSE [N] the paper reports for each row of Table I (its own data; cited, not reproducible).
TABLE_I_RMSE_N: dict[float, float] = {0.15: 2.57, 0.20: 1.52, 0.25: 0.84, 0.30: 0.36, 0.35: 0.32}

#: Accepted range of each parameter [SI]. Each spans orders of magnitude beyond Table I and
#: beyond every value ``mudforce fit`` explores (``calibration.models``: stiffnesses 1e3-1e9,
#: dampers 1e2-1e9, zeta 1e-3-1e2, omega_0 1e-2-1e3, ...), yet keeps the stepper's arithmetic
#: finite for every depth, step and foot within their own bounds: no denormal stiffness or damper
#: (time constants b/k within [1e-15, 1e15] s), no filter so stiff or so damped that Eq. (7)'s
#: response overflows. ``beta`` keeps the model's (0, 1] (Eq. (4) is concave), from 1e-3.
PARAMETER_RANGES: dict[str, tuple[float, float]] = {
    "k_m_i": (1e-3, 1e12),
    "b_m_i": (1e-3, 1e12),
    "k_m_w": (1e-3, 1e12),
    "b_m_w": (1e-3, 1e12),
    "alpha": (0.0, 1e12),  # 0: no spring (the Maxwell-only ablation uses 1e-24); alpha only scales (z/H)^beta
    "beta": (1e-3, 1.0),
    "sigma_y": (1e-3, 1e30),  # only compared with the suction (Eq. (9)): a huge value means "never necks"
    "zeta": (1e-4, 1e3),
    "omega_0": (1e-3, 1e4),
    "rho_m": (1.0, 1e5),
    "lambda": (0.0, 1e4),
}

#: Mud density [kg/m^3], Section III-A of [1], common to all rows of Table I.
RHO_M = 1.84e3
_LAMBDA = 0.013  # [-], Fig. 5 of [1], common to all rows


def _water_content(value: Any) -> float:
    """A water content [-] as a float if it is a real number (not bool), else one line; its range is not checked."""
    if not is_real(value):
        raise InputError(f"water content must be a number (a fraction: 0.25 means 25%), got {type(value).__name__}")
    return real_number(value, "water content")


@dataclass(frozen=True)
class MudParameters:
    """The 11 parameters of the mud resistive-force model, in SI.

    Parameters
    ----------
    k_m_i : float
        Maxwell stiffness on intrusion and hold [Pa/m], Eqs. (2)-(3).
    b_m_i : float
        Maxwell damping on intrusion and hold [Pa s/m], Eqs. (2)-(3).
    k_m_w : float
        Maxwell stiffness on withdrawal [Pa/m], Section II-B of [1].
    b_m_w : float
        Maxwell damping on withdrawal [Pa s/m], Section II-B of [1].
    alpha : float
        Nonlinear spring stiffness [Pa], Eq. (4).
    beta : float
        Nonlinear spring exponent, in (0, 1] [-], Eq. (4).
    sigma_y : float
        Yield stress at which the neck breaks [Pa], Eq. (9).
    zeta : float
        Damping ratio of the post-necking filter [-], Eq. (7); within [1e-4, 1e3].
    omega_0 : float
        Natural frequency of the post-necking filter [rad/s], Eq. (7).
    rho_m : float
        Mud density [kg/m^3], Eq. (5).
    lambda_ : float
        Drag scaling factor [-], Eq. (5) (JSON key ``lambda``).
    source : str
        Where the values come from (a citation, a file, a fit).

    Notes
    -----
    Every value must be finite and within :data:`PARAMETER_RANGES`
    (stiffnesses and dampers within [1e-3, 1e12], ``alpha`` within [0, 1e12] Pa,
    ``beta`` within [1e-3, 1], ``sigma_y`` within [1e-3, 1e30] Pa (it is only
    compared with the suction; 1e30 means the neck never breaks), ``zeta`` within
    [1e-4, 1e3], ``omega_0`` within [1e-3, 1e4] rad/s, ``rho_m`` within
    [1, 1e5] kg/m^3, ``lambda`` within [0, 1e4]).
    The instance is immutable and validated on construction; use
    :func:`dataclasses.replace` or :meth:`replace` to derive a changed copy.
    """

    k_m_i: float
    b_m_i: float
    k_m_w: float
    b_m_w: float
    alpha: float
    beta: float
    sigma_y: float
    zeta: float
    omega_0: float
    rho_m: float = RHO_M
    lambda_: float = _LAMBDA
    source: str = field(default="user", compare=False)

    def __post_init__(self) -> None:
        for name in PARAMETER_NAMES:
            attr = _PY_NAME[name]
            value = getattr(self, attr)
            if not is_real(value):
                raise InputError(f"parameter {name} must be a number, got {shown(value)}")
            value = real_number(value, f"parameter {name}")
            object.__setattr__(self, attr, value)
            if not math.isfinite(value):
                raise InputError(f"parameter {name} must be finite, got {value!r}")
        for name in PARAMETER_NAMES:
            value = getattr(self, _PY_NAME[name])
            lo, hi = PARAMETER_RANGES[name]
            if not lo <= value <= hi:
                raise InputError(f"parameter {name} must be within [{lo:g}, {hi:g}] [{_UNITS[name]}], got {value:g}")
        if not isinstance(self.source, str):
            raise InputError(f"source must be a str, got {type(self.source).__name__}")

    # ------------------------------------------------------------------ constructors
    @classmethod
    def table_i(cls, water_content: float) -> MudParameters:
        """The row of Table I of [1] for one of its five water contents.

        Parameters
        ----------
        water_content : float
            Volume fraction of water [-], one of 0.15, 0.20, 0.25, 0.30, 0.35.
        """
        given = _water_content(water_content)  # abs(x - w) took a complex, an array, True (as 1); a str: TypeError
        for w, row in zip(TABLE_I_WATER_CONTENTS, _TABLE_I_PAPER_UNITS, strict=True):
            if abs(given - w) < 1e-9:
                values = [v * s for v, s in zip(row, _TABLE_I_SCALE, strict=True)]
                return cls._from_nine(values, f"{CITATION}, Table I, W = {w:.0%}")
        raise InputError(
            f"Table I has no row for water content {given:.12g}; rows are "  # not :g: 0.2000001 showed as 0.2
            + ", ".join(f"{w:g}" for w in TABLE_I_WATER_CONTENTS)
        )

    @classmethod
    def from_water_content(cls, water_content: float) -> MudParameters:
        """Parameters for a water content, from Table I of [1].

        Exact at the table's five water contents. Between them every
        parameter is interpolated linearly in its logarithm (geometric
        interpolation between neighbouring rows).

        Parameters
        ----------
        water_content : float
            Volume fraction of water ``V_w / (V_c + V_s + V_w)`` [-], e.g. 0.25
            for 25 %, within [0.15, 0.35].

        Notes
        -----
        Why log-linear: every parameter is positive and several (alpha,
        sigma_y, k_m_i) fall by an order of magnitude across the table, so a
        straight line in the logarithm follows their steep, roughly
        exponential decay with W better than a straight line in the value,
        never leaves the interval spanned by the two neighbouring rows (so
        ``beta`` stays in (0, 1] and nothing turns negative), and adds no
        overshoot between rows as a cubic spline through five noisy points
        would. The paper gives no law between its rows; this is a
        project choice.
        """
        w = _water_content(water_content)
        lo, hi = WATER_CONTENT_RANGE
        if not math.isfinite(w) or w < lo - 1e-12 or w > hi + 1e-12:
            raise InputError(
                f"water content {w:.12g} is outside Table I's range [{lo:g}, {hi:g}] "  # not :g: 0.3500001 was 0.35
                f"(a fraction: 0.25 means 25%)"
            )
        for tw in TABLE_I_WATER_CONTENTS:
            if abs(w - tw) < 1e-9:
                return cls.table_i(tw)
        table = np.array(_TABLE_I_PAPER_UNITS) * np.array(_TABLE_I_SCALE)
        logs = np.log(table)
        values = [float(np.exp(np.interp(w, TABLE_I_WATER_CONTENTS, logs[:, j]))) for j in range(table.shape[1])]
        return cls._from_nine(values, f"{CITATION}, Table I, log-linear interpolation at W = {w:.2%}")

    @classmethod
    def _from_nine(cls, values: list[float], source: str) -> MudParameters:
        """The nine calibrated values of a Table I row [SI], with the paper's rho_m and lambda."""
        k_i, b_i, k_w, b_w, alpha, beta, sigma_y, zeta, omega_0 = values
        return cls(k_i, b_i, k_w, b_w, alpha, beta, sigma_y, zeta, omega_0, RHO_M, _LAMBDA, source)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], source: str = "user") -> MudParameters:
        """Build from a flat mapping with the 11 JSON keys, in SI.

        Unknown keys and missing keys are refused with a message naming them.
        """
        if not isinstance(data, Mapping):
            raise InputError(f"parameters must be a JSON object with keys {', '.join(PARAMETER_NAMES)}")
        keys = set(data)
        allowed = set(PARAMETER_NAMES) | {"source"}
        unknown = sorted(shown(k) if not isinstance(k, str) else k for k in keys - allowed)  # (keys of any type)
        if unknown:
            raise InputError(
                f"unknown parameter key(s) {', '.join(unknown)}; expected {', '.join(PARAMETER_NAMES)}"
            )
        missing = [k for k in PARAMETER_NAMES if k not in keys]
        if missing:
            raise InputError(f"missing parameter key(s) {', '.join(missing)} (SI units)")
        kwargs = {_PY_NAME[k]: data[k] for k in PARAMETER_NAMES}
        # a source that is not a str is refused (the constructor's words): str() read None as "None" and raised
        # ValueError for 10**5000
        return cls(**kwargs, source=data.get("source", source))

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> MudParameters:
        """Load a parameter set from a JSON file written by :meth:`save`.

        Parameters
        ----------
        path : path-like
            A JSON file holding a flat object with the 11 keys in SI.
        """
        from mudforce.io import load_json

        if not isinstance(path, (str, os.PathLike)):
            raise InputError(f"path must be a file name, got {type(path).__name__}")
        p = Path(path)
        data = load_json(p, "parameter file", 'an object like {"k_m_i": 260000.0, ...}')
        try:
            return cls.from_dict(data, source=str(p))
        except InputError as exc:
            raise InputError(f"{p}: {exc}") from None

    # ------------------------------------------------------------------ export
    def to_dict(self) -> dict[str, float]:
        """The 11 parameters as a flat dict under their JSON keys, in SI."""
        return {name: float(getattr(self, _PY_NAME[name])) for name in PARAMETER_NAMES}

    def to_json(self, indent: int | None = 2) -> str:
        """The flat JSON object of :meth:`to_dict`."""
        from mudforce.io import dumps_json

        return dumps_json(self.to_dict(), indent=indent)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write :meth:`to_json` to ``path`` atomically (temporary file, then rename)."""
        from mudforce.io import atomic_write_text

        atomic_write_text(path, self.to_json() + "\n")

    def replace(self, **changes: Any) -> MudParameters:
        """A validated copy with some values changed (``lambda`` as ``lambda_``)."""
        if "lambda" in changes:
            if "lambda_" in changes:
                raise InputError("give lambda or lambda_, not both")
            changes["lambda_"] = changes.pop("lambda")
        unknown = sorted(set(changes) - set(_PY_NAME.values()) - {"source"})
        if unknown:  # not dataclasses.replace's TypeError
            raise InputError(f"unknown parameter(s) {', '.join(unknown)}; expected some of "
                             f"{', '.join(PARAMETER_NAMES)} or source")
        return dataclasses.replace(self, **changes)

    def as_array(self) -> np.ndarray:
        """The 11 values in :data:`PARAMETER_NAMES` order, as float64 [SI]."""
        return np.array([getattr(self, _PY_NAME[n]) for n in PARAMETER_NAMES], dtype=np.float64)

    @property
    def critical_withdrawal_velocity(self) -> float:
        """Withdrawal speed above which the neck can break, ``sigma_y / b_m_w`` [m/s].

        The steady withdrawal stress of the Maxwell element is ``b_m_w * v``;
        below this speed (ignoring drag) suction never reaches ``sigma_y``.
        """
        return self.sigma_y / self.b_m_w

    def describe(self) -> str:
        """A human-readable multi-line table of the values with units."""
        lines = [f"# {self.source}"]
        for name in PARAMETER_NAMES:
            lines.append(f"{name:>8} = {getattr(self, _PY_NAME[name]):.6g} [{_UNITS[name]}]")
        return "\n".join(lines)


def _table() -> dict[float, MudParameters]:
    return {w: MudParameters.table_i(w) for w in TABLE_I_WATER_CONTENTS}


#: Table I of [1] in SI, keyed by water content (fraction).
TABLE_I: dict[float, MudParameters] = _table()

PARAMETER_UNITS = _UNITS


# renamed in 0.2 (docs/api.md): the citation was CHEN2024, the name of the model in mudforce.estimation.calibration
__getattr__ = _deprecated_getattr(__name__, {"CHEN2024": ("mudforce.model.parameters.CITATION",
                                                          "mudforce.model.parameters:CITATION")})
