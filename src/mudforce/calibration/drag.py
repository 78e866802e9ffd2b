"""The drag scaling factor ``lambda`` from sliding experiments, Eq. (5) and Fig. 5 of [1].

In the paper's sliding experiment the foot touches the mud surface at a
small depth and moves along it at constant speed; the measured resistance
is the inertial drag of Eq. (5) times the contact area::

    F = sign(v) * lambda * rho_m * v^2 * S

``lambda`` is linear in this law, so it is fitted by linear least squares
(through the origin, or with a constant offset ``F_0`` for a sensor bias
or a speed-independent friction), with the usual standard error
``s / sqrt(sum x^2)``, ``s^2 = SSR / (n - p)``.

.. [1] X. Chen, J. Yi, J. Shan, arXiv:2403.02617 (2024), Section III-A.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from mudforce.errors import InputError
from mudforce.tables import COLUMN_UNITS, read_columns

__all__ = ["DragFit", "fit_drag", "read_sliding"]

_RHO_M = 1.84e3  # [kg/m^3], Section III-A of [1]


@dataclass(frozen=True)
class DragFit:
    """The fitted drag factor.

    Attributes
    ----------
    lambda_ : float
        Drag scaling factor [-] (JSON key ``lambda``).
    stderr : float
        Its standard error [-].
    rmse : float
        RMS force residual [N].
    n : int
        Number of samples [-].
    rho_m : float
        Mud density used [kg/m^3].
    area : float
        Contact area used [m^2].
    intercept : float or None
        Fitted constant force ``F_0`` [N], if asked for.
    intercept_stderr : float or None
        Its standard error [N].
    """

    lambda_: float
    stderr: float
    rmse: float
    n: int
    rho_m: float
    area: float
    intercept: float | None = None
    intercept_stderr: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """``{"lambda", "stderr", "rmse_N", "n", "rho_m", "area_m2", "intercept_N", "intercept_stderr_N"}``."""
        return {
            "lambda": self.lambda_,
            "stderr": self.stderr,
            "rmse_N": self.rmse,
            "n": self.n,
            "rho_m": self.rho_m,
            "area_m2": self.area,
            "intercept_N": self.intercept,
            "intercept_stderr_N": self.intercept_stderr,
        }


def read_sliding(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read a sliding experiment: columns ``velocity_m_s`` (or ``velocity_mm_s``) and ``force_N``.

    Returns velocity [m/s] and force [N].
    """
    cols = read_columns(path, {"velocity": COLUMN_UNITS["velocity"], "force": COLUMN_UNITS["force"]})
    return cols["velocity"], cols["force"]


def fit_drag(velocity: Any, force: Any, area: float, *, rho_m: float = _RHO_M,
             intercept: bool = False) -> DragFit:
    """Fit ``lambda`` of Eq. (5) to sliding data.

    Parameters
    ----------
    velocity : array_like
        Sliding speed of each sample [m/s] (its sign gives the direction).
    force : array_like
        Measured resistance [N], with the sign of the velocity.
    area : float
        Contact area ``S`` [m^2].
    rho_m : float
        Mud density [kg/m^3]; the paper's 1840 by default.
    intercept : bool
        Also fit a constant force offset [N].

    Returns
    -------
    DragFit
    """
    v = np.asarray(velocity, dtype=np.float64)
    f = np.asarray(force, dtype=np.float64)
    if v.shape != f.shape or v.ndim != 1:
        raise InputError(f"velocity and force must be 1-D arrays of equal length, got {v.shape} and {f.shape}")
    for name, value in (("area", area), ("rho_m", rho_m)):
        if not math.isfinite(value) or value <= 0.0:
            raise InputError(f"{name} must be finite and > 0, got {value!r}")
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(f))):
        raise InputError("velocity and force must be finite")
    p = 2 if intercept else 1
    if v.size < p + 1:
        raise InputError(f"fit-drag needs at least {p + 1} samples, got {v.size}")
    x = rho_m * area * np.sign(v) * v**2  # [kg/m] ... force per unit lambda [N]
    if np.count_nonzero(x) == 0 or (intercept and np.ptp(x) == 0.0):
        raise InputError("fit-drag needs samples at more than one non-zero speed")
    design = np.column_stack([x, np.ones_like(x)]) if intercept else x[:, None]
    coef, *_ = np.linalg.lstsq(design, f, rcond=None)
    residual = f - design @ coef
    s2 = float(residual @ residual) / (v.size - p)
    cov = s2 * np.linalg.inv(design.T @ design)
    return DragFit(
        lambda_=float(coef[0]),
        stderr=math.sqrt(float(cov[0, 0])),
        rmse=math.sqrt(float(np.mean(residual**2))),
        n=int(v.size),
        rho_m=float(rho_m),
        area=float(area),
        intercept=float(coef[1]) if intercept else None,
        intercept_stderr=math.sqrt(float(cov[1, 1])) if intercept else None,
    )
