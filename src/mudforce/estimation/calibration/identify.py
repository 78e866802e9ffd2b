"""Telling the mud's water content from one intrusion trial.

The paper's Table I gives the parameters at five water contents;
:meth:`MudParameters.from_water_content` interpolates between them. For a
measured trial, :func:`identify_water_content` finds the water content
whose parameters reproduce the measured force best (least squares over
all samples, after the same preparation as a fit: motion fitted, force
tared, tare offset profiled), and an interval from the rise of the
residual sum of squares.

The interval is a likelihood-ratio interval that allows for model error:
``SSR(W) - SSR_min <= chi2_1(level) * s^2 * n / n_eff`` with
``s^2 = SSR_min / (n - 1)`` and ``n_eff`` the effective number of
independent residuals from their lag-1 autocorrelation. A trial that the
family fits to the noise floor gets a narrow interval; a trial it misfits
(correlated residuals, large ``s``) a wide one. The interval is never
narrower than +-:data:`MIN_HALF_WIDTH` (0.25 points): below that the
family's interpolation and the branch labels of a general motion, not the
noise, limit what one trial can tell.

A trial of any motion is accepted (:func:`~mudforce.estimation.calibration.preprocess.prepare_trial`).
The result says how well the family explains it: ``misfit_ratio`` (RMSE
over the force noise measured independently of the family),
``model_misses_data`` and ``off_family`` (the RMS residual in excess of
the noise [N]); ``water_content`` is then the nearest member of the family.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar
from scipy.stats import chi2

from mudforce.errors import InputError
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.fit import MISFIT_WARNING_RATIO, misfit_ratio
from mudforce.estimation.calibration.models import CHEN2024
from mudforce.estimation.calibration.preprocess import PreparedTrial, noise_floor, prepare_trial, tare_correction
from mudforce.model.foot import Foot
from mudforce.model.parameters import WATER_CONTENT_RANGE, MudParameters

__all__ = ["MIN_HALF_WIDTH", "Identification", "identify_water_content"]

#: Smallest half-width of the interval [-] (0.25 percentage points of water content).
MIN_HALF_WIDTH = 0.0025


@dataclass(frozen=True, eq=False)
class Identification:
    """The water content that explains a trial best.

    Attributes
    ----------
    water_content : float
        Best estimate [-] (a fraction: 0.23 is 23%).
    interval : tuple of float
        Confidence interval [-] at ``level``, clipped to the family's range.
    rmse : float
        RMS force residual at the estimate [N].
    level : float
        Confidence level of ``interval`` [-].
    grid, grid_rmse : ndarray
        Water contents scanned [-] and the RMS residual at each [N].
    warnings : tuple of str
    force_noise : float
        The trial's force noise, measured independently of the family [N].
    noise_floor : float
        The RMSE a member of the family that is right would leave [N]: the
        force noise and the depth noise carried through.
    misfit_ratio : float
        ``rmse / noise_floor`` [-]: about 1 when the family explains the trial to the noise.
    off_family : float
        How far the data are off the family [N]: the RMS of the residual in
        excess of the noise, ``sqrt(max(rmse^2 - noise_floor^2, 0))``.
    bias : float
        The sensor bias removed [N].
    bias_method : str
        ``"tared"`` (pre-contact samples, refined) or ``"estimated"`` (a free parameter).
    bias_stderr : float
        Standard error of ``bias`` [N]: the residual scatter over the samples
        (and the pre-contact ones), widened for the residuals' correlation.
    """

    water_content: float
    interval: tuple[float, float]
    rmse: float
    level: float
    grid: np.ndarray
    grid_rmse: np.ndarray
    warnings: tuple[str, ...] = ()
    force_noise: float = math.nan
    noise_floor: float = math.nan
    misfit_ratio: float = math.nan
    off_family: float = math.nan
    bias: float = math.nan
    bias_method: str = "tared"
    bias_stderr: float = math.nan

    @property
    def low(self) -> float:
        """Lower end of :attr:`interval` [-] (as :attr:`mudforce.TrackEstimate.low`)."""
        return self.interval[0]

    @property
    def high(self) -> float:
        """Upper end of :attr:`interval` [-] (as :attr:`mudforce.TrackEstimate.high`)."""
        return self.interval[1]

    @property
    def model_misses_data(self) -> bool:
        """True when the RMSE exceeds the force noise by more than :data:`MISFIT_WARNING_RATIO`."""
        return self.misfit_ratio > MISFIT_WARNING_RATIO

    def to_dict(self) -> dict[str, object]:
        """The JSON object of ``mudforce identify --json``.

        Keys: ``water_content`` (the nearest water content of the family),
        ``nearest_water_content`` (the same, named for what it is when the
        data are off the family), ``interval``, ``rmse_N``, ``level``,
        ``force_noise_N``, ``noise_floor_N``, ``misfit_ratio``, ``model_misses_data``,
        ``off_family_N``, ``bias_N``, ``bias_method``, ``bias_stderr_N``, ``warnings``.
        """

        def finite(x: float) -> float | None:
            return float(x) if math.isfinite(x) else None

        return {
            "water_content": self.water_content,
            "nearest_water_content": self.water_content,
            "interval": [self.interval[0], self.interval[1]],
            "rmse_N": self.rmse,
            "level": self.level,
            "force_noise_N": finite(self.force_noise),
            "noise_floor_N": finite(self.noise_floor),
            "misfit_ratio": finite(self.misfit_ratio),
            "model_misses_data": self.model_misses_data,
            "off_family_N": finite(self.off_family),
            "bias_N": finite(self.bias),
            "bias_method": self.bias_method,
            "bias_stderr_N": finite(self.bias_stderr),
            "warnings": list(self.warnings),
        }


def _edge(ssr: Callable[[float], float], level: float, inside: float, outward: np.ndarray, limit: float) -> float:
    """Where ``ssr`` rises through ``level`` walking from ``inside`` along ``outward`` (else ``limit``)."""
    previous = inside
    for w in outward:
        if ssr(float(w)) > level:
            return float(brentq(lambda x: ssr(x) - level, previous, float(w), xtol=1e-7))
        previous = float(w)
    return float(limit)


def identify_water_content(
    trial: Trial | PreparedTrial,
    foot: Foot | None = None,
    *,
    family: Callable[[float], MudParameters] = MudParameters.from_water_content,
    bounds: tuple[float, float] = WATER_CONTENT_RANGE,
    level: float = 0.95,
    points: int = 81,
) -> Identification:
    """Estimate the water content of one trial from a one-parameter family of parameter sets.

    Parameters
    ----------
    trial : Trial or PreparedTrial
        An intrude/hold/withdraw trial starting above the surface.
    foot : Foot, optional
        The intruder; the paper's cuboid by default.
    family : callable
        Water content [-] -> :class:`MudParameters`; Table I, interpolated, by default.
    bounds : tuple of float
        Range of water contents to search [-].
    level : float
        Confidence level of the interval, in (0, 1).
    points : int
        Grid points for the scan before refinement.

    Returns
    -------
    Identification
    """
    if not 0.0 < level < 1.0:
        raise InputError(f"confidence level must be in (0, 1), got {level!r}")
    foot = Foot.paper() if foot is None else foot
    tr = trial if isinstance(trial, PreparedTrial) else prepare_trial(trial)
    if not np.any(tr.trial.force != tr.trial.force[0]):
        raise InputError(f"{tr.trial.name}: the force is the same in every sample ({float(tr.trial.force[0]):.3g} N): "
                         "the trial carries no force to identify a water content from (is the column right?)")
    lo, hi = bounds

    def residual(w: float) -> np.ndarray:
        values = family(w).as_array()
        r: np.ndarray = CHEN2024.force(tr.time, tr.depth, values, foot) - tr.force
        return r + tare_correction(r, tr.precontact)

    def ssr(w: float) -> float:
        r = residual(w)
        return float(r @ r)

    grid = np.linspace(lo, hi, points)
    costs = np.array([ssr(float(w)) for w in grid])
    k = int(np.argmin(costs))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, points - 1)]
    sol = minimize_scalar(ssr, bounds=(a, b), method="bounded", options={"xatol": 1e-6})
    w_best, c_best = (float(sol.x), float(sol.fun)) if sol.fun < costs[k] else (float(grid[k]), float(costs[k]))
    r = residual(w_best)
    raw = CHEN2024.force(tr.time, tr.depth, family(w_best).as_array(), foot) - tr.force
    n = r.size
    rho = float(np.corrcoef(r[:-1], r[1:])[0, 1]) if n > 2 and np.std(r) > 0 else 0.0
    rho = min(max(rho, 0.0), 0.99)
    n_eff = n * (1.0 - rho) / (1.0 + rho)
    threshold = float(chi2.ppf(level, 1)) * c_best / max(n - 1, 1) * n / max(n_eff, 1.0)
    low = _edge(ssr, c_best + threshold, w_best, grid[grid < w_best][::-1], lo)
    high = _edge(ssr, c_best + threshold, w_best, grid[grid > w_best], hi)
    # resolution floor: the family is interpolated between rows 5 points apart, and the branch
    # labels of a general motion leave small systematic errors that the likelihood does not see
    low, high = min(low, max(w_best - MIN_HALF_WIDTH, lo)), max(high, min(w_best + MIN_HALF_WIDTH, hi))
    warnings = []
    if w_best - lo < 1e-3 or hi - w_best < 1e-3:
        warnings.append(f"the estimate is at the edge of the searched range [{lo:g}, {hi:g}]: "
                        "the mud may be drier or wetter than the family covers")
    rmse = math.sqrt(c_best / n)
    scale = max(float(np.max(np.abs(tr.force))), 1.0)
    best_values = family(w_best).as_array()
    floor = math.sqrt(float(np.mean(noise_floor(
        tr, raw, lambda z: CHEN2024.force(tr.time, z, best_values, foot)))))
    ratio = misfit_ratio(rmse, floor, scale)
    off = math.sqrt(max(rmse**2 - floor**2, 0.0))
    if ratio > MISFIT_WARNING_RATIO:
        warnings.append(f"RMSE {rmse:.3g} N is {ratio:.2g} times the noise floor {floor:.3g} N "
                        f"(force noise {tr.force_noise:.3g} N, with the depth noise carried through): "
                        f"the data are {off:.3g} N (RMS) off the Table I family (another mud, another foot "
                        "than assumed, or a model error); the estimate is the nearest water content and "
                        "the interval is widened for the misfit")
    return Identification(
        water_content=w_best,
        interval=(low, high),
        rmse=rmse,
        level=level,
        grid=grid,
        grid_rmse=np.sqrt(costs / n),
        warnings=tuple(warnings),
        force_noise=tr.force_noise,
        noise_floor=floor,
        misfit_ratio=ratio,
        off_family=off,
        bias=tr.bias + tare_correction(raw, tr.precontact),
        bias_method="estimated" if tr.bias_estimated else "tared",
        bias_stderr=max(rmse, tr.force_noise) * math.sqrt((1.0 + rho) / (1.0 - rho) / (n + tr.precontact)),
    )
