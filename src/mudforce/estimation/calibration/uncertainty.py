"""Standard errors of a fit: the Jacobian, the covariance with errors in variables, and honest widening.

The fit works on log-parameters; their covariance is ``s^2 (J^T J)^+``
(``s^2 = SSR / (n - p)``) plus the uncertainty of the motions fitted to the
measured depth (protocol trials), carried through the residual's
sensitivity to them, and is widened by :func:`correlation_inflation` when
the model leaves the residuals correlated (``docs/calibration.md``,
``docs/estimation.md``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from mudforce.estimation.calibration.models import ForceModel
from mudforce.estimation.calibration.preprocess import PreparedTrial, tare_correction
from mudforce.model.foot import Foot

__all__ = ["correlation_inflation", "covariance", "jackknife_variance", "jacobian", "motion_sensitivity", "profiled",
           "profiled_in_place"]


def profiled(residual: np.ndarray, precontact: int) -> tuple[np.ndarray, float]:
    """A trial's residual with its tare offset profiled out, and the offset's prior row (see ``tare_correction``)."""
    out = np.array(residual, dtype=np.float64)
    return out, profiled_in_place(out, precontact)


def profiled_in_place(residual: np.ndarray, precontact: int) -> float:
    """:func:`profiled` on ``residual`` [N] itself (float64, written): returns the offset's prior row [N].

    The fit's objective writes each trial's rows where it returns them (speed plumbing: no array per call).
    """
    offset = tare_correction(residual, precontact)
    np.add(residual, offset, out=residual)
    return offset * math.sqrt(precontact)


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


def jacobian(fun: Callable[[np.ndarray], np.ndarray], x: np.ndarray, step: float = 1e-5) -> np.ndarray:
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


def motion_sensitivity(model: ForceModel, foot: Foot, groups: Sequence[Sequence[PreparedTrial]],
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
                parts.append(profiled(model.force(tr.time, depth, v, foot) - tr.force, tr.precontact))
            sens[:, j] = (parts[0][0] - parts[1][0]) / (2 * h)
            prior[j] = (parts[0][1] - parts[1][1]) / (2 * h)
        blocks.append(_MotionBlock(slice(row, row + tr.time.size), n_data + i, sens, prior, tr.motion_covariance))
        row += tr.time.size
    return blocks


def covariance(jac: np.ndarray, residual: np.ndarray,
                motion: Sequence[_MotionBlock] = ()) -> tuple[np.ndarray, np.ndarray]:
    """Covariance of the log-parameters, and a mask of the ones the data determines.

    ``cov = s^2 (J^T J)^+ + A G C_m G^T A^T`` with ``s^2 = SSR / (n - p)``,
    ``A = J^+``: the first term is the force noise; the second (errors in
    variables) carries the uncertainty ``C_m`` of the motions fitted to the
    measured depth through the residual's sensitivity ``G`` to them
    (``motion``, from :func:`motion_sensitivity`; block diagonal over trials). A
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




def jackknife_variance(jac: np.ndarray, residual: np.ndarray, groups: Sequence[np.ndarray]) -> np.ndarray | None:
    """Delete-one-trial jackknife variance of the log-parameters, linearised at the optimum (``p`` values).

    Leaving trial ``i`` out moves the optimum by one Gauss-Newton step,
    ``(J^T J - J_i^T J_i)^+ J_i^T r_i`` (the full gradient vanishes at the
    optimum); the spread of these moves, ``(n - 1)/n sum (d_i - mean)^2``,
    is the jackknife variance. It sees what the noise model cannot: trials
    that disagree systematically (a motion whose branch switches were
    misread pulls the withdrawal parameters its own way). ``groups[i]``
    are trial ``i``'s rows of ``jac`` and ``residual`` (or, for a fit of one or
    two trials, contiguous blocks of them: ``fit._blocks``). None for fewer than
    three groups (too few to spread).
    """
    if len(groups) < 3:
        return None
    h = jac.T @ jac
    moves = []
    for rows in groups:
        ji = jac[rows]
        moves.append(np.linalg.pinv(h - ji.T @ ji, rcond=1e-10) @ (ji.T @ residual[rows]))
    d = np.array(moves)
    out: np.ndarray = (len(groups) - 1) / len(groups) * np.sum((d - d.mean(axis=0)) ** 2, axis=0)
    return out
