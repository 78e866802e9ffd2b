"""The 3-D law of :mod:`mudforce.model.law3d` for ONE element, as compiled scalar functions: physics, not plumbing.

Each function here is its namesake in :mod:`mudforce.model.law3d` (or
:func:`mudforce.model.granular.rft3d_alpha`) written for one surface element, in
the world frame (z up), SI units, so that the compiled 3-D step
(:mod:`mudforce._kernel.step3d`) runs the law without numpy's per-call cost.
What the law is, and which of it is the paper's and which is ours, is
:mod:`mudforce.model.law3d`'s docstring; change the law there and here together.
``tests/steppers/test_many3d.py`` holds each function to its numpy
namesake: bit for bit where both evaluate the same expression in the same
order (:func:`rotation`, :func:`vertical_weight`, :func:`lateral_capacity`,
:func:`lateral_return_map`, :func:`horizontal_drag`), and within a few ulp
where numpy picks its own order of summation (``einsum``, pairwise sums,
``x ** 3`` through ``pow``): :func:`shear_fraction`, :func:`rft3d_alpha`
(to 1e-15 of :func:`mudforce.model.granular.rft3d_alpha`) and
:func:`bearing_factor`.

Eq. (4)'s spring is not here: the compiled step takes it from
:func:`mudforce.model.equations.nonlinear_spring_stress`, as every compiled path
does (its power is :func:`mudforce._plumbing.pow.power`, within 1 ulp of the
``**`` of :func:`mudforce.model.law3d.spring_stress`).
"""

from __future__ import annotations

import math

from mudforce._kernel.layout import _compiled
from mudforce.model.granular import RFT3D_C1, RFT3D_C2, RFT3D_C3
from mudforce.model.law3d import FLAT_PLATE_ALPHA

__all__ = [
    "bearing_factor",
    "horizontal_drag",
    "lateral_capacity",
    "lateral_return_map",
    "rft3d_alpha",
    "rotation",
    "shear_fraction",
    "vertical_weight",
]

# the 3D-RFT cubic fits' coefficients (mudforce.model.granular), frozen into the compiled code as constants
_C1 = tuple(float(c) for c in RFT3D_C1)
_C2 = tuple(float(c) for c in RFT3D_C2)
_C3 = tuple(float(c) for c in RFT3D_C3)
_PER_FLAT = 1.0 / float(FLAT_PLATE_ALPHA)


@_compiled(inline="always")
def rotation(w: float, x: float, y: float, z: float) -> tuple[float, float, float, float, float, float, float, float,
                                                              float]:
    """:func:`mudforce.model.law3d.rotation_matrix` of a unit quaternion ``(w, x, y, z)``, row by row [-].

    Normalised if its norm is not exactly 1 (the caller has checked it is
    within :data:`mudforce.model.law3d.QUATERNION_TOLERANCE`).
    """
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    if norm != 1.0:
        w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return (1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),
            2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x),
            2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y))


@_compiled(inline="always")
def vertical_weight(nz: float) -> float:
    """:func:`mudforce.model.law3d.vertical_weight`: ``max(-n_z, 0)``, the share of the area under the paper's
    stress [-]."""
    v = -nz
    return v if v >= 0.0 else 0.0


@_compiled(inline="always")
def shear_fraction(nx: float, ny: float, nz: float, dx: float, dy: float) -> float:
    """:func:`mudforce.model.law3d.shear_fraction`: ``|s - (s.n) n|`` for the unit horizontal slip direction
    ``s`` [-]."""
    dn = dx * nx + dy * ny
    ax = dx - dn * nx
    ay = dy - dn * ny
    az = -(dn * nz)
    return math.sqrt(ax * ax + ay * ay + az * az)


@_compiled(inline="always")
def _cubic(c: tuple[float, ...], a: float, b: float, d: float) -> float:
    """``c . basis(a, b, d)``: 3D-RFT's cubic fit in :func:`mudforce.model.granular.rft3d_basis`'s order [-]."""
    return (c[0] + c[1] * a + c[2] * b + c[3] * d + c[4] * (a * a) + c[5] * (b * b) + c[6] * (d * d)
            + c[7] * (a * b) + c[8] * (b * d) + c[9] * (d * a) + c[10] * (a * a * a) + c[11] * (b * b * b)
            + c[12] * (d * d * d) + c[13] * (a * b * b) + c[14] * (b * a * a) + c[15] * (b * d * d)
            + c[16] * (d * b * b) + c[17] * (d * a * a) + c[18] * (a * d * d) + c[19] * (a * b * d))


@_compiled(inline="always")
def rft3d_alpha(nx: float, ny: float, nz: float, vx: float, vy: float, vz: float) -> tuple[float, float, float]:
    """:func:`mudforce.model.granular.rft3d_alpha` of one element: 3D-RFT's generic stress per depth ``(x, y, z)`` [-].

    ``alpha = f1 m + f2 u - f3 z`` with ``u`` the unit velocity, ``m`` the
    downward normal, ``f_i`` the cubic fits in ``(-u_z, -m_z, m . u)``
    (Agarwal, Goldman & Kamrin 2023). ``n`` must be a unit normal; a zero
    velocity gives 0.
    """
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    if speed == 0.0:
        return 0.0, 0.0, 0.0
    ux, uy, uz = vx / speed, vy / speed, vz / speed
    if nz < 0.0:
        mx, my, mz = nx, ny, nz
    else:
        mx, my, mz = -nx, -ny, -nz
    x1 = -uz
    x2 = -mz
    x3 = mx * ux + my * uy + mz * uz
    f1 = _cubic(_C1, x1, x2, x3)
    f2 = _cubic(_C2, x1, x2, x3)
    f3 = _cubic(_C3, x1, x2, x3)
    return f1 * mx + f2 * ux, f1 * my + f2 * uy, (f1 * mz + f2 * uz) - f3


@_compiled(inline="always")
def _cubic_level(c: tuple[float, ...], b: float, d: float) -> float:
    """:func:`_cubic` at ``x1 = -u_z = 0`` (a horizontal motion): its ten terms free of ``x1`` [-].

    The other ten are products with ``x1 = -0.0``, signed zeros that change
    no sum (at most the sign of an exact zero), so this is the full cubic's
    value at a third of its cost.
    """
    return (c[0] + c[2] * b + c[3] * d + c[5] * (b * b) + c[6] * (d * d) + c[8] * (b * d) + c[11] * (b * b * b)
            + c[12] * (d * d * d) + c[15] * (b * d * d) + c[16] * (d * b * b))


@_compiled(inline="always")
def bearing_factor(nx: float, ny: float, nz: float, dx: float, dy: float) -> float:
    """:func:`mudforce.model.law3d.bearing_factor`: 3D-RFT's resistance along ``s = (dx, dy, 0)``, per a flat
    plate's [-].

    ``max(0, -alpha . s) / FLAT_PLATE_ALPHA`` on a leading element
    (``n . s > 0``), else 0: :func:`rft3d_alpha` for a horizontal motion,
    whose vertical part ``f3`` does not enter ``alpha . s``.
    """
    if not nx * dx + ny * dy > 0.0:
        return 0.0
    ux, uy = dx, dy  # a unit vector already (numpy's rft3d_alpha divides it by its norm again: within an ulp of 1)
    if nz < 0.0:
        mx, my, mz = nx, ny, nz
    else:
        mx, my, mz = -nx, -ny, -nz
    x2 = -mz
    x3 = mx * ux + my * uy
    f1 = _cubic_level(_C1, x2, x3)
    f2 = _cubic_level(_C2, x2, x3)
    against = -((f1 * mx + f2 * ux) * dx + (f1 * my + f2 * uy) * dy)
    return (against if against >= 0.0 else 0.0) * _PER_FLAT


@_compiled(inline="always")
def lateral_capacity(sigma_y: float, shear: float, spring: float, bearing: float) -> float:
    """:func:`mudforce.model.law3d.lateral_capacity`: ``sigma_y shear + spring bearing`` [Pa].

    ``sigma_y`` the yield stress [Pa] (Eq. (9)), ``shear`` and ``bearing`` [-],
    ``spring`` Eq. (4)'s stress at the element's depth [Pa].
    """
    return sigma_y * shear + spring * bearing


@_compiled(inline="always")
def lateral_return_map(sx: float, sy: float, stiffness: float, capacity: float) -> tuple[float, float, float, float]:
    """:func:`mudforce.model.law3d.lateral_return_map` of one element: ``(slip x, slip y, traction x, traction y)``.

    The trial slip ``(sx, sy)`` [m] kept where ``k |s| <= capacity``, else
    scaled back to ``capacity / k``; the traction ``-k s`` [Pa].
    """
    size = math.sqrt(sx * sx + sy * sy)
    limit = capacity / stiffness
    scale = 1.0
    if size > limit:
        scale = limit / (size if size > 0.0 else 1.0)
    kx = sx * scale
    ky = sy * scale
    return kx, ky, -stiffness * kx, -stiffness * ky


@_compiled(inline="always")
def horizontal_drag(lambda_: float, rho_m: float, nx: float, ny: float, ux: float, uy: float) -> tuple[float, float]:
    """:func:`mudforce.model.law3d.horizontal_drag`: Eq. (5), ``-lambda rho (n.u)_+ u`` [Pa], on the leading projection.

    ``lambda_`` [-], ``rho_m`` [kg/m^3], ``(nx, ny)`` the normal's horizontal
    part [-], ``(ux, uy)`` the element's horizontal velocity [m/s].
    """
    facing = nx * ux + ny * uy
    if not facing >= 0.0:
        facing = 0.0
    scale = -(lambda_ * rho_m) * facing
    return scale * ux, scale * uy
