"""Fitting the 3-D law's parameters from 3-D force data: force VECTORS along known poses (:func:`fit_3d`).

The 3-D law (:mod:`mudforce.model.law3d`, docs/model.md "Mud in 3-D") adds
to the paper one parameter of its own, the lateral stiffness ``k`` [Pa/m]
of the elements' horizontal slip (default: the paper's withdrawal
stiffness ``k_m_w``), and uses paper parameters in roles the paper does not
measure: ``sigma_y`` as the yield stress in shear, ``lambda_`` for the
horizontal drag. :func:`fit_3d` fits any of these (and the paper's
stiffnesses and spring coefficient) to measured forces [N], world frame,
along the measured poses of the foot, by nonlinear least squares on the
logarithms of the values (so every value stays positive), with the
simulation of :class:`mudforce.steppers.contact3d.MudContacts3D` (one foot per
trial value: the central-difference Jacobian is one simulation of ``2p + 1``
feet).

Honest uncertainty: the standard errors are those of the linearised least
squares with the noise variance estimated from the residuals, so a model
that misses the data gets wider intervals; residuals that are correlated
from sample to sample (a misfit has a shape in time; white sensor noise
does not) make the independent samples fewer than the samples, and the
errors are widened by ``sqrt((1 + rho) / (1 - rho))`` (``rho`` the residuals'
lag-1 autocorrelation, the AR(1) effective sample size) with a warning when
``rho > 0.5``. Given the sensor's ``noise`` [N], a residual RMS above twice
it is warned about too.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mudforce._kernel.bounds import check_times
from mudforce._plumbing.blas import one_blas_thread
from mudforce.errors import InputError, finite_number, is_real, positive_int, real_array, shown
from mudforce.io.tables import COLUMN_LIMITS
from mudforce.model import law3d
from mudforce.model.law3d import (
    MAX_BEARING_SCALE,
    MAX_LATERAL_STIFFNESS,
    check_bearing_scale,
    check_lateral_stiffness,
)
from mudforce.model.parameters import PARAMETER_RANGES, MudParameters
from mudforce.model.shapes import Shape
from mudforce.steppers.contact3d import MudContacts3D, simulate_3d

__all__ = ["FIT3D_PARAMETERS", "Fit3D", "fit_3d"]

#: The names :func:`fit_3d` can fit: the 3-D law's own ``lateral_stiffness`` [Pa/m] and ``bearing_scale`` [-], and
#: mud parameters (:class:`~mudforce.model.parameters.MudParameters` fields) that the 3-D law uses beyond the paper's
#: case.
FIT3D_PARAMETERS = ("lateral_stiffness", "bearing_scale", "sigma_y", "lambda_", "k_m_w", "b_m_w", "k_m_i", "b_m_i",
                    "alpha")
_LAW = ("lateral_stiffness", "bearing_scale")  # the 3-D law's own (not MudParameters fields)

_UNITS = {"lateral_stiffness": "Pa/m", "bearing_scale": "-", "sigma_y": "Pa", "lambda_": "-", "k_m_w": "Pa/m",
          "b_m_w": "Pa s/m", "k_m_i": "Pa/m", "b_m_i": "Pa s/m", "alpha": "Pa"}
_RANGE = math.log(1e3)  # each value is searched within a factor 1000 of its start
_STEP = 1e-4  # the central differences' step in log(value)


@dataclass(frozen=True)
class Fit3D:
    """The result of :func:`fit_3d`.

    Attributes
    ----------
    values : dict of str to float
        The fitted values, SI (``lateral_stiffness`` [Pa/m], ``sigma_y`` [Pa], ...).
    standard_errors : dict of str to float
        Their standard errors, SI (linearised, widened as the module says).
    params : MudParameters
        ``params0`` with the fitted mud parameters.
    lateral_stiffness : float
        The lateral stiffness to use with them [Pa/m] (fitted, or as given).
    bearing_scale : float
        The bearing scale to use with them [-] (fitted, or as given).
    residual_rms : float
        RMS of the force residuals over all samples and axes [N].
    autocorrelation : float
        Lag-1 autocorrelation of the residuals [-] (about 0 for white noise).
    n_samples : int
        Force samples used (each with 3 components).
    success : bool
        Whether the optimiser converged.
    message : str
        The optimiser's message.
    covariance : ndarray, shape (p, p)
        Covariance of ``log(value)`` in ``values``' order [-].
    """

    values: dict[str, float]
    standard_errors: dict[str, float]
    params: MudParameters
    lateral_stiffness: float
    bearing_scale: float
    residual_rms: float
    autocorrelation: float
    n_samples: int
    success: bool
    message: str
    covariance: np.ndarray = field(repr=False)


def _array(value: Any, name: str, shape: tuple[int, ...], unit: str) -> np.ndarray:
    """``value`` as a float64 array of ``shape``, finite, else InputError (real numbers only: errors.real_array
    refuses strings, complex numbers and booleans, which np.asarray parsed, cut or read as 0 and 1)."""
    a = real_array(value, name, unit)
    if a.shape != shape:
        raise InputError(f"{name} must have shape {shape} [{unit}], got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite [{unit}]")
    return a


def _free(free: Any) -> tuple[str, ...]:
    if isinstance(free, (bytes, bytearray, memoryview)):  # a sequence of ints: "got 115 among them"
        raise InputError(f"free must name one or more of {', '.join(FIT3D_PARAMETERS)} as a str or a sequence of "
                         f"str, got {type(free).__name__}")
    names = (free,) if isinstance(free, str) else tuple(free) if isinstance(free, Sequence) else None
    if not names or not all(isinstance(n, str) for n in names):
        # words of one line, not free's repr (over lines for a 2-D array, ValueError for an int of 10**5000)
        others = [n for n in names or () if not isinstance(n, str)]
        bad = others[0] if others else free
        got = repr(free) if names is not None and not others else (
            f"{shown(bad) if is_real(bad) else type(bad).__name__}{' among them' if others else ''}")
        raise InputError(f"free must name one or more of {', '.join(FIT3D_PARAMETERS)}, got {got}")
    unknown = [n for n in names if n not in FIT3D_PARAMETERS]
    if unknown:
        raise InputError(f"free names {unknown[0]!r}, which fit_3d cannot fit; expected one of "
                         f"{', '.join(FIT3D_PARAMETERS)}")
    if len(set(names)) != len(names):
        raise InputError(f"free names a parameter twice: {list(names)}")
    return names


@one_blas_thread
def fit_3d(time: Any, positions: Any, quaternions: Any, forces: Any, shape: Shape, params0: MudParameters, *,
           free: Sequence[str] | str = ("lateral_stiffness",), lateral_stiffness: float | None = None,
           bearing_scale: float | None = None, surface_height: float = 0.0, width: float | None = None,
           noise: float | None = None, max_iterations: int = 50) -> Fit3D:
    """Fit the 3-D law's parameters to measured force vectors along measured poses.

    Parameters
    ----------
    time : array_like, shape (m,)
        Sample times [s], strictly increasing.
    positions : array_like, shape (m, 3)
        The foot's body origin at each sample [m], world frame, z up.
    quaternions : array_like, shape (m, 4)
        Its orientation ``(w, x, y, z)`` [-], unit (within 1e-6).
    forces : array_like, shape (m, 3)
        The measured force of the mud on the foot [N], world frame.
    shape : Shape
        The foot's surface (:mod:`mudforce.model.shapes`).
    params0 : MudParameters
        The mud: the values held fixed, and the start of the free ones.
    free : str or sequence of str
        What to fit (:data:`FIT3D_PARAMETERS`); by default the 3-D law's own
        ``lateral_stiffness``.
    lateral_stiffness : float, optional
        Its start, or its value if not free [Pa/m]; by default ``params0.k_m_w``.
    bearing_scale : float, optional
        Its start, or its value if not free [-]; by default 1 (3D-RFT's granular bearing). Fitted, it must start
        above 0 (a log scale).
    surface_height, width : float
        As for :class:`~mudforce.steppers.contact3d.MudContact3D` [m].
    noise : float, optional
        The force sensor's noise [N]: a residual RMS above twice it is warned about.
    max_iterations : int
        Gauss-Newton iterations at most (each one simulation of ``2p + 1`` feet).

    Returns
    -------
    Fit3D
    """
    from scipy.optimize import least_squares

    if not isinstance(params0, MudParameters):
        raise InputError(f"params0 must be a MudParameters, got {type(params0).__name__}")
    if not isinstance(shape, Shape):
        raise InputError(f"shape must be a mudforce.model.shapes.Shape, got {type(shape).__name__}")
    names = _free(free)
    t = real_array(time, "time", "s")
    if t.ndim != 1:
        raise InputError(f"time must have shape (m,) [s], got {t.shape}")
    t = _array(t, "time", t.shape, "s")
    m = t.shape[0]
    if m < 2 * len(names) + 2:
        raise InputError(f"fit_3d needs at least {2 * len(names) + 2} samples to fit {len(names)} parameter(s), "
                         f"got {m}")
    check_times(t)  # simulate_3d's bounds and words: within +-1e9 s, steps within [1e-9, 1e3] s
    x = _array(positions, "positions", (m, 3), "m")
    q = _array(quaternions, "quaternions", (m, 4), "-")
    f = _array(forces, "forces", (m, 3), "N")
    most = COLUMN_LIMITS["force"]
    if not np.all(np.abs(f) <= most):  # a recording's bound: beyond, the residuals' squares overflow
        k = int(np.argmax(np.abs(f).max(axis=1)))
        raise InputError(f"forces must be within +-{most:g} N (as a recording's force column), got "
                         f"{f[k].tolist()!r} at sample {k}")
    norms = np.linalg.norm(q, axis=1)
    if np.any(np.abs(norms - 1.0) > law3d.QUATERNION_TOLERANCE):
        k = int(np.argmax(np.abs(norms - 1.0)))
        raise InputError(f"quaternions must have norm 1 (within {law3d.QUATERNION_TOLERANCE:g}); sample {k} has "
                         f"norm {norms[k]:.9g}")
    if noise is not None:  # not a bool (True was 1 N)
        noise = finite_number(noise, "noise", "N", positive=True)
    iterations = positive_int(max_iterations, "max_iterations")
    # one number each (MudContacts3D, which simulates the 2p + 1 points of a step as feet, would take a sequence as
    # one value per foot: each point of the Jacobian's differences in another mud surface or foot width)
    surface_height = finite_number(surface_height, "surface_height", "m")
    if width is not None:
        width = finite_number(width, "width", "m", positive=True)
    # MudContact3D's check
    k0 = check_lateral_stiffness(params0.k_m_w if lateral_stiffness is None else lateral_stiffness)
    b0 = check_bearing_scale(1.0 if bearing_scale is None else bearing_scale)
    law0 = {"lateral_stiffness": k0, "bearing_scale": b0}
    # the poses through simulate_3d once: a pose the model refuses (beyond its depths or horizontal bounds, at any
    # value of the parameters) in its words, with the sample, not from inside the search as a point of the
    # Jacobian ("foot 0: ...")
    simulate_3d(t, x, q, params0, shape, surface_height=surface_height, width=width, lateral_stiffness=k0,
                bearing_scale=b0)
    start = {n: float(law0[n]) if n in _LAW else float(getattr(params0, n)) for n in names}
    if any(v <= 0.0 for v in start.values()):
        bad = next(n for n, v in start.items() if v <= 0.0)
        raise InputError(f"the start of {bad} must be > 0 [{_UNITS[bad]}] (it is fitted on a log scale), got "
                         f"{start[bad]!r}")
    x0 = np.log(np.array([start[n] for n in names]))
    p = len(names)
    # searched within a factor 1000 of the start, and within the values the model takes (with room for the
    # central differences' step): beyond, a step of the search was refused by MudContacts3D or MudParameters
    ranges = {"lateral_stiffness": (0.0, MAX_LATERAL_STIFFNESS), "bearing_scale": (0.0, MAX_BEARING_SCALE),
              "lambda_": PARAMETER_RANGES["lambda"], **PARAMETER_RANGES}
    floor = np.array([math.log(ranges[n][0]) + 2 * _STEP if ranges[n][0] > 0.0 else -math.inf for n in names])
    ceiling = np.array([math.log(ranges[n][1]) - 2 * _STEP for n in names])
    lower, upper = np.maximum(x0 - _RANGE, floor), np.minimum(x0 + _RANGE, ceiling)
    x0 = np.clip(x0, lower, upper)
    dts = np.diff(t)

    def feet(points: np.ndarray) -> tuple[list[MudParameters], list[float], list[float]]:
        muds, stiffness, bearing = [], [], []
        for row in points:
            values = dict(zip(names, np.exp(row).tolist(), strict=True))
            stiffness.append(values.pop("lateral_stiffness", float(k0)))
            bearing.append(values.pop("bearing_scale", float(b0)))
            muds.append(params0.replace(**values) if values else params0)
        return muds, stiffness, bearing

    def simulate(points: np.ndarray) -> np.ndarray:
        """The forces [N] of one foot per row of ``points`` (log values): (rows, m, 3)."""
        n = points.shape[0]
        muds, stiffness, bearing = feet(points)
        contacts = MudContacts3D(muds, shape, n, surface_heights=surface_height, widths=width,
                                 lateral_stiffness=stiffness, bearing_scale=bearing)
        out = np.empty((m, n, 3))
        torques = np.empty((n, 3))
        pos = np.broadcast_to(x[:, None, :], (m, n, 3))
        quat = np.broadcast_to(q[:, None, :], (m, n, 4))
        for k in range(m):
            contacts.step(np.ascontiguousarray(pos[k]), np.ascontiguousarray(quat[k]), float(dts[k - 1]) if k else 0.0,
                          out=(out[k], torques))
        return np.moveaxis(out, 1, 0)

    cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def evaluate(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = z.tobytes()
        if key not in cache:
            points = np.vstack([z, z + _STEP * np.eye(p), z - _STEP * np.eye(p)])
            sims = simulate(points)
            residual = (sims[0] - f).ravel()
            jacobian = ((sims[1:p + 1] - sims[p + 1:]) / (2.0 * _STEP)).reshape(p, -1).T
            cache.clear()
            cache[key] = (residual, jacobian)
        return cache[key]

    solution = least_squares(lambda z: evaluate(z)[0], x0, jac=lambda z: evaluate(z)[1],
                             bounds=(lower, upper), method="trf", x_scale=1.0, max_nfev=iterations)
    residual, jacobian = evaluate(solution.x)
    dof = max(residual.size - p, 1)
    variance = float(residual @ residual) / dof
    r = residual.reshape(m, 3)
    centred = r - r.mean(axis=0)
    denominator = float(np.sum(centred * centred))
    rho = float(np.sum(centred[1:] * centred[:-1]) / denominator) if denominator > 0.0 else 0.0
    widen = math.sqrt((1.0 + rho) / (1.0 - rho)) if 0.0 < rho < 1.0 else 1.0
    jtj = jacobian.T @ jacobian
    try:
        covariance = np.linalg.inv(jtj) * variance * widen * widen
    except np.linalg.LinAlgError:
        covariance = np.full((p, p), math.inf)
    if not np.all(np.isfinite(covariance)) or np.linalg.cond(jtj) > 1e14:
        warnings.warn(f"fit_3d: the data do not determine {', '.join(names)} (the motion does not exercise them): "
                      "their standard errors are infinite", RuntimeWarning, stacklevel=3)
        covariance = np.full((p, p), math.inf)
    if rho > 0.5:
        warnings.warn(f"fit_3d: the residuals are correlated in time (lag-1 {rho:.2f}): the model misses the data "
                      f"in shape, not only by noise; the standard errors are widened {widen:.1f}x", RuntimeWarning,
                      stacklevel=3)
    rms = math.sqrt(float(residual @ residual) / residual.size)
    if noise is not None and rms > 2.0 * noise:
        warnings.warn(f"fit_3d: the residual RMS {rms:.3g} N is more than twice the sensor noise {noise:.3g} N: the "
                      "model misses the data", RuntimeWarning, stacklevel=3)
    fitted = np.exp(solution.x)
    values = dict(zip(names, fitted.tolist(), strict=True))
    errors = {n: float(values[n] * math.sqrt(covariance[i, i])) for i, n in enumerate(names)}
    mud = {n: v for n, v in values.items() if n not in _LAW}
    return Fit3D(values=values, standard_errors=errors, params=params0.replace(**mud) if mud else params0,
                 lateral_stiffness=float(values.get("lateral_stiffness", k0)),
                 bearing_scale=float(values.get("bearing_scale", b0)), residual_rms=rms, autocorrelation=rho,
                 n_samples=m, success=bool(solution.success), message=str(solution.message), covariance=covariance)
