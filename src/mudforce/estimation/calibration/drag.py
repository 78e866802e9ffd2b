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

from mudforce._plumbing.blas import one_blas_thread
from mudforce.errors import InputError, number_within, real_array, true_or_false
from mudforce.io.tables import COLUMN_UNITS, read_columns
from mudforce.model.equations import array_form, drag_stress
from mudforce.model.foot import AREA_RANGE
from mudforce.model.parameters import PARAMETER_RANGES, RHO_M

__all__ = ["DragFit", "fit_drag", "read_sliding"]



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
    warnings : tuple of str
        What the caller should know (a negative ``lambda``: the data contradict Eq. (5)).
    """

    lambda_: float
    stderr: float
    rmse: float
    n: int
    rho_m: float
    area: float
    intercept: float | None = None
    intercept_stderr: float | None = None
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The JSON object: ``lambda, stderr, rmse_N, n, rho_m, area_m2, intercept_N, intercept_stderr_N, warnings``."""
        return {
            "lambda": self.lambda_,
            "stderr": self.stderr,
            "rmse_N": self.rmse,
            "n": self.n,
            "rho_m": self.rho_m,
            "area_m2": self.area,
            "intercept_N": self.intercept,
            "intercept_stderr_N": self.intercept_stderr,
            "warnings": list(self.warnings),
        }


def read_sliding(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read a sliding experiment: columns ``velocity_m_s`` (or ``velocity_mm_s``) and ``force_N``.

    Returns velocity [m/s] and force [N].
    """
    cols = read_columns(path, {"velocity": COLUMN_UNITS["velocity"], "force": COLUMN_UNITS["force"]})
    return cols["velocity"], cols["force"]


@one_blas_thread
def fit_drag(velocity: Any, force: Any, area: float, *, rho_m: float = RHO_M,
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
    v = real_array(velocity, "velocity", "m/s")
    f = real_array(force, "force", "N")
    if v.shape != f.shape or v.ndim != 1:
        raise InputError(f"velocity and force must be 1-D arrays of equal length, got {v.shape} and {f.shape}")
    for name, value, (lo, hi), unit in (("area", area, AREA_RANGE, "m^2"),
                                        ("rho_m", rho_m, PARAMETER_RANGES["rho_m"], "kg/m^3")):
        number_within(value, name, lo, hi, unit)  # a repr of 10**5000 raised ValueError
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(f))):
        raise InputError("velocity and force must be finite")
    p = 2 if true_or_false(intercept, "intercept") else 1
    if v.size < p + 1:
        raise InputError(f"fit-drag needs at least {p + 1} samples, got {v.size}")
    x: np.ndarray = array_form(drag_stress)(1.0, rho_m, v) * area  # Eq. (5) with lambda = 1, times S [N]
    if np.count_nonzero(x) == 0 or (intercept and np.ptp(x) == 0.0):
        raise InputError("fit-drag needs samples at more than one non-zero speed")
    # solve in scaled columns (x / max|x|): the normal matrix then cannot overflow or underflow
    scale = float(np.max(np.abs(x)))
    design = np.column_stack([x / scale, np.ones_like(x)]) if intercept else (x / scale)[:, None]
    try:
        coef, _, rank, _ = np.linalg.lstsq(design, f, rcond=None)  # the results are checked below
        if rank < p:
            raise np.linalg.LinAlgError
        residual = f - design @ coef
        s2 = float(residual @ residual) / (v.size - p)
        cov = s2 * np.linalg.inv(design.T @ design)
    except np.linalg.LinAlgError:
        raise InputError("fit-drag: the speeds do not determine lambda (too few distinct non-zero speeds, "
                         "or speeds too far apart in magnitude)") from None
    with np.errstate(all="ignore"):  # an overflow here is caught as a non-finite result
        coef[0] /= scale
        cov[0, :] /= scale
        cov[:, 0] /= scale
    values = [float(coef[0]), float(cov[0, 0]), float(s2), *(float(c) for c in np.ravel(cov))]
    if not all(math.isfinite(value) for value in values):
        raise InputError("fit-drag: lambda or its standard error is not finite; the speeds or forces are too "
                         "extreme to fit")
    warnings = []
    if coef[0] < 0.0:
        warnings.append(f"lambda = {coef[0]:.4g} is negative: the force falls as the speed grows, which Eq. (5) "
                        "cannot describe (check the sign convention: force with the sign of the velocity)")
    return DragFit(
        lambda_=float(coef[0]),
        stderr=math.sqrt(float(cov[0, 0])),
        rmse=math.sqrt(float(np.mean(residual**2))),
        n=int(v.size),
        rho_m=float(rho_m),
        area=float(area),
        intercept=float(coef[1]) if intercept else None,
        intercept_stderr=math.sqrt(float(cov[1, 1])) if intercept else None,
        warnings=tuple(warnings),
    )
