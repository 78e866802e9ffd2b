"""Baseline force models to compare the mud model against: granular RFT, dynamic RFT, a Maxwell-only ablation.

Each baseline is a closed-form (or compiled) force law for a flat foot of
area ``S`` moved vertically along a prescribed depth ``z_i(t)`` (positive
down, SI throughout), and a :class:`~mudforce.estimation.calibration.models.ForceModel`
which the calibration fits (``mudforce fit --model NAME``, see
:mod:`mudforce.estimation.calibration.models`):

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

The branch rule is the exact one of ``docs/model.md``: the step from sample
``k-1`` to ``k`` has the velocity ``v_k = (z_k - z_{k-1}) / (t_k - t_{k-1})``
(``v_0 = 0``), and ``v_k >= 0`` (down or at rest) is the intrusion branch.

This module holds the force laws only and imports nothing from the
calibration; the fittable models built on them (``GRANULAR_RFT``, ``DRFT``,
``MAXWELL_ONLY``) are listed with the paper's model in
:mod:`mudforce.estimation.calibration.models`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mudforce._plumbing.jit import njit
from mudforce.errors import InputError, finite_number, real_array, shown
from mudforce.model.bounds import MAX_DEPTH, MAX_DT, MAX_TIME, MIN_DT, check_depths, check_times
from mudforce.model.equations import (
    array_form,
    drag_acts,
    drag_stress,
    intrusion_stress,
    maxwell_strain_step,
    relaxation_time,
    submerged_drag_stress,
    total_stress,
    withdrawal_stress,
)
from mudforce.model.foot import Foot
from mudforce.model.parameters import TABLE_I

__all__ = [
    "BASELINE_NAMES",
    "DEFAULT_K_RFT",
    "branch_velocity",
    "drft_force",
    "granular_rft_force",
    "maxwell_only_force",
]

#: Registry names of the baselines, in the order reports list them.
BASELINE_NAMES: tuple[str, ...] = ("granular_rft", "drft", "maxwell_only")

#: A starting RFT depth coefficient [Pa/m]: about Table I's W = 25 % mud at 20 mm.
DEFAULT_K_RFT = 1.4e6

_RHO_M = TABLE_I[0.25].rho_m  # [kg/m^3], Section III-A of Chen, Yi & Shan
_LAMBDA = TABLE_I[0.25].lambda_  # [-], Fig. 5 of Chen, Yi & Shan


def _within_bounds(t: np.ndarray, z: np.ndarray) -> bool:
    """Whether times [s] and depths [m] (1-D, one non-zero length) pass :func:`check_times` and :func:`check_depths`.

    Speed plumbing: a fit evaluates a baseline thousands of times on one
    trajectory; four reductions and a difference (NaN fails every
    comparison) instead of the checks' dozen passes, which then run only
    to word a refusal. Steps within [``MIN_DT``, ``MAX_DT``] make the times
    increase, so the first and last are their extremes.
    """
    if t.size > 1:
        steps = t[1:] - t[:-1]
        if not (steps.min() >= MIN_DT and steps.max() <= MAX_DT):
            return False
    return bool(-MAX_TIME <= t[0] and t[-1] <= MAX_TIME and z.min() >= -MAX_DEPTH and z.max() <= MAX_DEPTH)


def _trajectory(time: Any, depth: Any) -> tuple[np.ndarray, np.ndarray]:
    t = real_array(time, "time", "s")
    z = real_array(depth, "depth", "m")
    if t.ndim != 1 or t.shape != z.shape or t.size == 0:
        raise InputError(f"time and depth must be 1-D arrays of the same non-zero length, got {t.shape}, {z.shape}")
    # simulate's bounds and words (beyond them, k z, dz/dt and the drag's v|v| overflowed to inf)
    if not _within_bounds(t, z):
        check_depths(z)
        check_times(t)
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
    if foot is not None and not isinstance(foot, Foot):
        raise InputError(f"foot must be a Foot (or None for the paper's cuboid), got {type(foot).__name__}")
    return (Foot.paper() if foot is None else foot).area


def _finite_force(force: np.ndarray, model: str) -> np.ndarray:
    """``force`` [N], refused in one line where finite inputs overflowed it (a parameter beyond float64's reach).

    The check is on the output, not the parameters' ranges: the fits step these parameters to their bounds and
    a little past them (finite differences), which a range would refuse.
    """
    if not np.isfinite(force).all():
        k = int(np.flatnonzero(~np.isfinite(force))[0])
        raise InputError(f"{model}: the force overflows (not finite) at sample {k}: a parameter beyond float64's "
                         "reach; expected parameters of physical size")
    return force


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
    k = finite_number(k_rft, "k_rft", "Pa/m", positive=True)  # "1e5" was parsed, True was 1, NaN gave NaN
    area = _area(foot)
    v = branch_velocity(time, depth)
    z = np.asarray(depth, dtype=np.float64)
    with np.errstate(over="ignore", invalid="ignore"):  # refused below, without numpy's warnings
        force: np.ndarray = np.where(v >= 0.0, k * np.maximum(z, 0.0), 0.0) * area
    return _finite_force(force, "granular_rft")


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
    lam = finite_number(lambda_, "lambda_", "-", nonnegative=True)
    density = finite_number(rho, "rho", "kg/m^3", nonnegative=True)
    v = branch_velocity(time, depth)
    z = np.asarray(depth, dtype=np.float64)
    with np.errstate(over="ignore", invalid="ignore"):  # refused below, without numpy's warnings
        drag = np.where(array_form(drag_acts)(z), array_form(drag_stress)(lam, density, v), 0.0) * _area(foot)
        force: np.ndarray = granular_rft_force(time, depth, k_rft, foot) + drag
    return _finite_force(force, "drft")


@njit(cache=True, nogil=True)
def _maxwell_only_loop(t: np.ndarray, z: np.ndarray, k_i: float, tau_i: float, k_w: float, tau_w: float,
                       lam: float, rho_m: float, area: float) -> np.ndarray:
    """The Maxwell-only force [N] per sample: the contact state machine of ``docs/model.md`` without necking.

    FREE until the foot crosses the surface (CONTACT from the crossing
    instant, ``z_m = 0`` there); in CONTACT the extension ``e = z_i - z_m``
    follows Eq. (3) in closed form on the branch of the step's velocity
    (intrusion for ``v >= 0``); a step that ends on the intrusion branch at
    or above the surface returns to FREE; on the withdrawal branch the mud
    clings (no yield). Force ``(k e + lambda rho v |v| [z_i > 0]) S``. The
    equations are the physics layer's (:mod:`mudforce.model.equations`);
    the loop is this model's own control flow.
    """
    n = t.size
    out = np.zeros(n)
    contact = z[0] > 0.0  # a start below the surface: CONTACT with relaxed mud (e = 0)
    strain = 0.0
    for k in range(1, n):
        dt = t[k] - t[k - 1]
        z0 = z[k - 1]
        z1 = z[k]
        v = (z1 - z0) / dt
        start = 0.0
        if not contact and z1 > 0.0:
            start = -z0 / v if z0 < 0.0 else 0.0  # touchdown inside the step
            contact = True
            strain = 0.0
        if not contact:
            continue
        if v >= 0.0:
            strain = maxwell_strain_step(strain, v, tau_i, math.exp(-(dt - start) / tau_i))
            if z1 <= 0.0:
                contact = False  # on the intrusion branch at or above the surface
                continue
            fe1, _ = intrusion_stress(k_i, tau_i, strain)
        else:
            strain = maxwell_strain_step(strain, v, tau_w, math.exp(-(dt - start) / tau_w))
            fe1, _ = withdrawal_stress(k_w, tau_w, strain)
        # no spring (f_e2 = 0): the ablation; the stepper's sum and drag gate
        out[k] = total_stress(fe1, 0.0, submerged_drag_stress(lam, rho_m, v, z1)) * area
    return out


def maxwell_only_force(time: Any, depth: Any, k_m_i: float, b_m_i: float, k_m_w: float, b_m_w: float,
                       rho_m: float = _RHO_M, lambda_: float = _LAMBDA, foot: Foot | None = None) -> np.ndarray:
    """The mud model without its nonlinear spring and without necking [N], positive up.

    Eqs. (2), (3) and (5) of Chen, Yi & Shan with the intrusion parameters
    ``k_m_i`` [Pa/m], ``b_m_i`` [Pa s/m] and the withdrawal ones ``k_m_w``,
    ``b_m_w``; ``f_e2 = 0`` and the neck never breaks. The contact states,
    the surface-crossing instant and the closed-form Maxwell step are those
    of :func:`mudforce.simulate` (``docs/model.md``), written out here for
    this model alone (a compiled loop of its own).

    Parameters
    ----------
    time, depth : array_like
        Sample times [s] and foot depth [m], positive down.
    k_m_i, b_m_i, k_m_w, b_m_w : float
        Maxwell stiffness [Pa/m] and damping [Pa s/m] per branch, > 0.
    rho_m : float
        Mud density [kg/m^3], >= 0.
    lambda_ : float
        Drag scaling factor [-], >= 0.
    foot : Foot, optional
        Gives the area ``S`` [m^2]; the paper's cuboid by default.
    """
    t, z = _trajectory(time, depth)
    values = {"k_m_i": k_m_i, "b_m_i": b_m_i, "k_m_w": k_m_w, "b_m_w": b_m_w, "rho_m": rho_m, "lambda": lambda_}
    for name, value in values.items():
        positive = name not in ("rho_m", "lambda")
        # a real number first: float() parsed "1e5", read True as 1 and raised TypeError for a list
        number = finite_number(value, f"maxwell_only: {name}", "SI")
        if number < 0.0 or (positive and number == 0.0):  # (finite_number refused NaN and infinities)
            raise InputError(f"maxwell_only: {name} must be finite and {'> 0' if positive else '>= 0'}, "
                             f"got {shown(value)}")
    tau = array_form(relaxation_time)  # Eq. (3)
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        taus = {"intrusion": float(tau(float(k_m_i), float(b_m_i))),
                "withdrawal": float(tau(float(k_m_w), float(b_m_w)))}
    for branch, value in taus.items():  # b / k beyond float64 (1e-320 / 1e5 is 0: a division by zero in the loop)
        if not 0.0 < value < math.inf:
            raise InputError(f"maxwell_only: the {branch} branch's relaxation time b / k is {value!r} s; expected a "
                             "positive finite time (k and b of physical size)")
    force: np.ndarray = _maxwell_only_loop(t, z, float(k_m_i), taus["intrusion"], float(k_m_w), taus["withdrawal"],
                                           float(lambda_), float(rho_m), _area(foot))
    return _finite_force(force, "maxwell_only")
