"""Granular resistive-force theory per surface element: Li et al.'s planar RFT and Agarwal et al.'s 3D-RFT.

The granular baselines of :mod:`mudforce.model.baselines` treat a flat foot moved
vertically. This module gives the same laws on every surface element of a
foot of any shape, as pure, vectorised numpy functions of element arrays in
the world frame (z up, SI units):

``centroids`` (n, 3) [m], ``normals`` (n, 3) outward unit normals [-],
``areas`` (n,) [m^2], ``velocities`` (n, 3) [m/s], and the height of the
medium's free surface ``surface_height`` [m].

An element below the surface at depth ``|z| = surface_height - z_c`` [m] is
loaded by ``F = scale * alpha * |z| * dA`` [N] (the RFT element force of
Li et al. 2013 and Agarwal et al. 2023; equation numbers are not cited
here, the papers were not at hand), ``alpha`` the dimensionless generic stress
vector of the law and ``scale`` [N/m^3] the medium's magnitude (Li's
``zeta``, Agarwal's ``xi_n``, :func:`medium_scale`).

Laws
----
``li2013`` -- Li, Zhang & Goldman, Science 339, 1408 (2013), generic Fourier fit
    :func:`rft_alpha` gives ``(alpha_x, alpha_z)`` of a plate at angle
    ``beta`` moving in direction ``gamma`` (``gamma = pi/2`` straight down).
    Conventions used here, fixed by the physics of the generic fit and its
    published values (the paper's figure was not at hand; see
    ``docs/granular.md``): ``x`` is the horizontal direction of motion,
    ``alpha_z > 0`` pushes up, ``alpha_x > 0`` pushes against the motion
    (``-x``), and ``beta > 0`` is a plate whose lower face is turned towards
    ``+x`` (lower-face normal ``(sin beta, -cos beta)``). With that reading a
    plate whose lower face leads a horizontal stroke gets more lift and drag
    than the mirror plate whose upper face leads (``alpha_z(pi/4, 0) = 0.363``
    against ``0.049``), as it must. The listed generic coefficients already
    give ``alpha_z(0, pi/2) = A00 + A10 + B01 + B11 + B-11 = 1.000``: no extra
    normalisation is applied, ``scale`` is Li's ``zeta`` (vertical stress per
    depth of a horizontal plate pushed down).

    In 3-D the planar law is applied in the vertical plane that contains the
    element's velocity: ``x = r``, the horizontal direction of the velocity,
    and the plate angle is that of the normal projected on the plane. Li's law
    has no term for the part of the normal out of that plane (3D-RFT's
    ``psi``); a plate edge-on to the plane (normal horizontal and
    perpendicular to the motion) gets no force. For a purely vertical velocity
    the plane is taken through the normal's horizontal part, where a tilted
    plate's sideways push is largest; approached from other azimuths the
    planar law gives other values, a limit of any planar law in 3-D that
    3D-RFT removes.

``rft3d`` -- Agarwal, Goldman & Kamrin, PNAS 120, e2214017120 (2023)
    ``alpha = alpha_r r + alpha_theta theta + alpha_z z`` with
    ``alpha_r = f1 sin(beta) cos(psi) + f2 cos(gamma)``,
    ``alpha_theta = f1 sin(beta) sin(psi)``,
    ``alpha_z = -f1 cos(beta) - f2 sin(gamma) - f3``, and ``f_i`` the cubic
    polynomials of ``x1 = sin(gamma)``, ``x2 = cos(beta)``,
    ``x3 = cos(psi) cos(gamma) sin(beta) + sin(gamma) cos(beta)`` with
    coefficients :data:`RFT3D_C1`, :data:`RFT3D_C2`, :data:`RFT3D_C3`
    (basis :func:`rft3d_basis`). :func:`rft3d_angles` builds the paper's
    local frame (its supplement, S7 as the public ports cite it): ``z`` up, ``r`` the horizontal direction of
    the velocity (the normal's horizontal direction when the velocity is
    vertical, ``+x`` when both are), ``theta = z x r``, ``beta`` the tilt,
    ``gamma`` the velocity angle, ``psi`` the twist.

    Written out, the frame cancels: with ``v`` the unit velocity and ``m`` the
    plate's downward normal (``m = n`` if ``n_z < 0``, else ``m = -n``),
    ``x1 = -v_z``, ``x2 = -m_z = |n_z|``, ``x3 = m . v`` and
    ``alpha = f1 m + f2 v - f3 z``. :func:`rft3d_alpha` evaluates this form:
    it has no degenerate case (vertical velocity, horizontal plate), and the
    test suite checks it against the frame construction. One public MATLAB
    port sets ``psi = 0`` when the normal's horizontal part is perpendicular
    to ``r``; that is the right value only when the normal is vertical, and
    jumps otherwise; the limit used here is ``psi = +-pi/2``. The fit itself
    is not symmetric under ``m -> -m`` for a vertical face (``n_z = 0``),
    where the paper's frame takes ``m = -n``: the stress jumps there by up to
    about 0.04.

Coefficients of 3D-RFT: which copy
----------------------------------
The coefficients were read from public implementations; the paper's
supplement (Table S2) was not reachable from here. Two families of copies
disagree in two places:

* a MATLAB port (``KKKobefeng/3D-RFT``, ``RFT3Dfunc.m``, and its other
  scripts), and the list in the project's RFT3D sheet:
  ``c2[16] = 0.18589``, ``c3[15] = -0.02730`` (0-based);
* an IsaacLab/torch soft-contact fork (two files): ``c2[16] = 0.18519``,
  ``c3[15] = -0.20770``. A third, further edited torch copy differs in six
  more places and was not considered.

``c3[15]`` (basis ``x2 x3^2``) decides a sign. A horizontal plate facing up
and pulled straight up (``x = (-1, 1, -1)``) gets ``alpha_z = -0.0797`` with
``-0.02730`` (the medium resists) and ``+0.1007`` with ``-0.20770`` (the
medium pushes the plate along its motion), impossible for a cohesionless
medium. Over random leading elements the generic stress does positive work
on the body (``alpha . v > 0``) for 0.055 % of them with ``-0.02730`` (at most
0.005) and for 1.2 % with ``-0.20770`` (up to 0.094). A horizontal plate
pushed down gets ``alpha_z = 0.875`` (``1.056`` with the torch value).
This module takes ``-0.02730``.

``c2[16]`` (basis ``x3 x2^2``) changes ``alpha`` by at most 0.0007, below
the fit's precision: no physical check separates ``0.18589`` from
``0.18519`` (the share of positive-work elements is 0.055 % against
0.059 %). This module takes ``0.18589``, the value of the copy whose other
disputed value passes the sign check; it is a transcription call, not a
verified one.

Leading elements, friction, inertial drag
-----------------------------------------
Only leading elements are loaded: ``n . v >= 0`` (the MATLAB port's
criterion, with a tolerance :data:`LEADING_TOLERANCE` on the cosine for
faces tangent to the motion); an element at rest (``v = 0``) has no
direction and is not loaded. The surface friction of 3D-RFT caps the part
of ``alpha`` tangential to the element at ``mu_surf`` times its normal part
(``alpha_t *= min(1, mu_surf |alpha_n| / |alpha_t|)``), as in the paper; the
MATLAB port's extra sign flips of ``alpha_n`` and ``alpha_t`` are not in the
paper and are not applied. The dynamic-RFT inertial drag (Agarwal et al.,
PNAS 118, e2023945118 (2021)) adds ``lambda rho (v . n)^2 dA`` along ``-n``
on leading elements below the surface: it always opposes the motion (a
public fork adds ``rho v_z^2`` upward whatever the sign of ``v_z``, and so
pushes a withdrawing foot out).

Relation to :mod:`mudforce.model.baselines`: a single horizontal sole (``n = -z``)
moved vertically gives ``F_z = scale alpha_z(0, pi/2) max(z, 0) S`` while it
moves down and ``0`` while it moves up, which is
:func:`~mudforce.model.baselines.granular_rft_force` with
``k_rft = scale * alpha_z(0, pi/2)`` (``= zeta`` for ``li2013``); see
``docs/granular.md`` for the rest samples and the drag.
"""

from __future__ import annotations

import math
import sys
from typing import Any, NamedTuple

import numpy as np

from mudforce.errors import InputError, finite_number, is_real, real_array, shown

__all__ = [
    "LAWS",
    "LEADING_TOLERANCE",
    "LI2013_GENERIC",
    "RFT3D_C1",
    "RFT3D_C2",
    "RFT3D_C3",
    "LiCoefficients",
    "medium_scale",
    "rft3d_alpha",
    "rft3d_alpha_unchecked",
    "rft3d_angles",
    "rft3d_basis",
    "rft_alpha",
    "rft_element_alpha",
    "rft_element_forces",
    "rft_wrench",
]

#: The element laws :func:`rft_element_forces` knows.
LAWS: tuple[str, ...] = ("rft3d", "li2013")

#: Tolerance on ``n . v / |v|`` [-]: an element with ``n . v / |v| >= -LEADING_TOLERANCE`` leads.
LEADING_TOLERANCE = 1e-9

_GRAVITY = 9.81  # standard gravity [m/s^2], as mudforce.engines.dynamics.GRAVITY
_TINY = 1e-12  # length below which a unit vector's horizontal part counts as zero [-]
_NORMAL_TOLERANCE = 1e-6  # accepted deviation of |n| from 1 [-]
_MAX_VELOCITY = 1e150  # largest |velocity component| accepted [m/s]: |v|^2 stays finite (the direction's scale)
_MAX_BETA = 0.5 * sys.float_info.max  # largest |beta| accepted [rad]: 2 beta stays finite
_SMALL_VELOCITY = 1e-100  # a velocity whose components are all below it [m/s] is scaled up for its direction


class LiCoefficients(NamedTuple):
    """Fourier coefficients of Li, Zhang & Goldman's RFT fit (Science 2013, generic fit) [-].

    ``alpha_z = A00 + A10 cos 2b + B01 sin g + B11 sin(2b + g) + Bm11 sin(-2b + g)``;
    ``alpha_x = C01 cos g + C11 cos(2b + g) + Cm11 cos(-2b + g) + D10 sin 2b``
    (``Bm11``, ``Cm11`` stand for Li's ``B-11``, ``C-11``). Generic values
    are dimensionless; a material's own fit is in the unit of its stress per
    depth [N/m^3] and is then used with ``scale = 1``.
    """

    A00: float
    A10: float
    B01: float
    B11: float
    Bm11: float
    C01: float
    C11: float
    Cm11: float
    D10: float


#: Li et al.'s generic coefficients (dimensionless; ``alpha_z(0, pi/2) = 1.000``).
LI2013_GENERIC = LiCoefficients(A00=0.206, A10=0.169, B01=0.358, B11=0.212, Bm11=0.055,
                                C01=0.253, C11=-0.124, Cm11=0.007, D10=0.088)


def _frozen(values: list[float]) -> np.ndarray:
    array = np.array(values, dtype=np.float64)
    array.flags.writeable = False
    return array


#: 3D-RFT coefficients of ``f1`` (Agarwal et al. 2023, supplement), basis order of :func:`rft3d_basis` [-].
RFT3D_C1 = _frozen([0.00212, -0.02320, -0.20890, -0.43083, -0.00259, 0.48872, -0.00415, 0.07204, -0.02750,
                    -0.08772, 0.01992, -0.45961, 0.40799, -0.10107, -0.06576, 0.05664, -0.09269, 0.01892,
                    0.01033, 0.15120])
#: 3D-RFT coefficients of ``f2``; ``[16] = 0.18589`` (a torch copy has 0.18519: see the module docstring) [-].
RFT3D_C2 = _frozen([-0.06796, -0.10941, 0.04725, -0.06914, -0.05835, -0.65880, -0.11985, -0.25739, -0.26834,
                    0.02692, -0.00736, 0.63758, 0.08997, 0.21069, 0.04748, 0.20406, 0.18589, 0.04934,
                    0.13527, -0.33207])
#: 3D-RFT coefficients of ``f3``; ``[15] = -0.02730`` (a torch copy's -0.20770 fails the sign check) [-].
RFT3D_C3 = _frozen([-0.02634, -0.03436, 0.45256, 0.00835, 0.02553, -1.31290, -0.05532, 0.06790, -0.16404,
                    0.02287, 0.02927, 0.95406, -0.00131, -0.11028, 0.01487, -0.02730, 0.10911, -0.04097,
                    0.07881, -0.27519])


def rft_alpha(beta: Any, gamma: Any, coefficients: LiCoefficients = LI2013_GENERIC) -> tuple[np.ndarray, np.ndarray]:
    """Li et al.'s stresses per depth ``(alpha_x, alpha_z)`` of a plate at angle ``beta`` moving along ``gamma``.

    Li, Zhang & Goldman, Science 339, 1408 (2013): their Fourier fit, with the generic
    coefficients by default. The fit holds for ``beta, gamma`` in
    ``[-pi/2, pi/2]``; other values are mapped there: ``beta`` by its period
    ``pi`` (a plate has no side; the form is already ``pi``-periodic), and a
    velocity with a backward component (``|gamma| > pi/2`` after wrapping to
    ``[-pi, pi)``) by mirroring ``x -> -x``: ``gamma -> pi - gamma`` (or
    ``-pi - gamma``), ``beta -> -beta``, and ``alpha_x`` changes sign.

    Parameters
    ----------
    beta : array_like
        Plate angle [rad]: ``beta > 0`` turns the plate's lower face towards ``+x``.
    gamma : array_like
        Direction of motion [rad]: the velocity is ``(cos gamma, -sin gamma)`` in ``(x, z)``,
        ``gamma = pi/2`` straight down, ``-pi/2`` straight up.
    coefficients : LiCoefficients
        Fourier coefficients, :data:`LI2013_GENERIC` by default.

    Returns
    -------
    alpha_x, alpha_z : numpy.ndarray
        Stress per depth in the unit of the coefficients (dimensionless for the generic fit, to be
        multiplied by ``zeta`` [N/m^3]); ``alpha_z > 0`` pushes up, ``alpha_x > 0`` pushes towards ``-x``.
        The broadcast shape of ``beta`` and ``gamma``.
    """
    b = _finite_array(beta, "beta [rad]")
    if not np.all(np.abs(b) <= _MAX_BETA):  # 2 beta overflowed: refused as the coefficients' sums overflowing
        raise InputError(f"beta [rad] must be within +-{_MAX_BETA:.4g} (the fit takes cos and sin of 2 beta; "
                         f"it is pi-periodic, wrap beta first), got {float(np.abs(b).max())!r} in size")
    g = _finite_array(gamma, "gamma [rad]")
    coefficients = _li_coefficients(coefficients, "coefficients")
    try:
        b, g = np.broadcast_arrays(b, g)
    except ValueError:
        raise InputError(f"beta and gamma must broadcast together, got shapes {b.shape} and {g.shape}") from None
    g = np.mod(g + math.pi, 2.0 * math.pi) - math.pi  # [-pi, pi)
    back = np.abs(g) > 0.5 * math.pi
    g = np.where(back, np.copysign(math.pi, g) - g, g)
    b = np.where(back, -b, b)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, in one line
        alpha_x, alpha_z = _li(b, g, coefficients, np.where(back, -1.0, 1.0))
    _refuse_overflow(np.stack([alpha_x, alpha_z]), "stresses per depth (alpha_x, alpha_z)", "the coefficients' sums")
    return alpha_x, alpha_z


def _li(b: np.ndarray, g: np.ndarray, c: LiCoefficients, sign: np.ndarray | float = 1.0
        ) -> tuple[np.ndarray, np.ndarray]:
    """Li's Fourier form for ``beta, gamma`` already in range [rad]; ``sign`` multiplies ``alpha_x``."""
    alpha_z = (c.A00 + c.A10 * np.cos(2.0 * b) + c.B01 * np.sin(g) + c.B11 * np.sin(2.0 * b + g)
               + c.Bm11 * np.sin(-2.0 * b + g))
    alpha_x = (c.C01 * np.cos(g) + c.C11 * np.cos(2.0 * b + g) + c.Cm11 * np.cos(-2.0 * b + g)
               + c.D10 * np.sin(2.0 * b)) * sign
    return np.asarray(alpha_x, dtype=np.float64), np.asarray(alpha_z, dtype=np.float64)


def rft3d_basis(x1: Any, x2: Any, x3: Any) -> np.ndarray:
    """The 20 cubic monomials of 3D-RFT, last axis in the paper's order [-].

    ``1, x1, x2, x3, x1^2, x2^2, x3^2, x1 x2, x2 x3, x3 x1, x1^3, x2^3, x3^3,
    x1 x2^2, x2 x1^2, x2 x3^2, x3 x2^2, x3 x1^2, x1 x3^2, x1 x2 x3``
    (Agarwal, Goldman & Kamrin 2023, supplement).

    Parameters
    ----------
    x1, x2, x3 : array_like
        ``sin(gamma)``, ``cos(beta)``, ``cos(psi) cos(gamma) sin(beta) + sin(gamma) cos(beta)`` [-].
    """
    arrays = [_finite_array(x, f"x{k} [-]") for k, x in enumerate((x1, x2, x3), start=1)]
    try:
        a, b, c = np.broadcast_arrays(*arrays)
    except ValueError:
        raise InputError(f"x1, x2 and x3 must broadcast together, got shapes {[x.shape for x in arrays]}") from None
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, in one line
        out: np.ndarray = _basis(a, b, c, np)
    _refuse_overflow(out, "basis monomials", "x1, x2 or x3 cubed")
    return out


def _basis(a: Any, b: Any, c: Any, xp: Any) -> Any:
    """:func:`rft3d_basis` on arrays of one shape, in the array library ``xp`` (numpy or jax.numpy)."""
    return xp.stack([xp.ones_like(a), a, b, c, a * a, b * b, c * c, a * b, b * c, c * a, a ** 3, b ** 3, c ** 3,
                     a * b * b, b * a * a, b * c * c, c * b * b, c * a * a, a * c * c, a * b * c], axis=-1)


def rft3d_angles(normals: Any, velocities: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The angles ``(beta, gamma, psi)`` of 3D-RFT's local frame per element [rad].

    Agarwal, Goldman & Kamrin 2023, supplement S7: ``z`` vertical, ``r`` the
    horizontal direction of the velocity (the normal's horizontal direction
    when the velocity is vertical, ``+x`` when the normal is vertical too),
    ``theta = z x r``. ``beta`` in ``[-pi/2, pi/2]`` with ``cos(beta) = |n_z|``
    (the four sign cases of the paper's frame), ``gamma`` in ``[-pi/2, pi/2]``
    with ``sin(gamma) = -v_z/|v|`` (positive down), and
    ``psi = atan(n_theta / n_r)`` in ``[-pi/2, pi/2]``, 0 for a horizontal
    plate, and its limit ``+-pi/2`` where ``n_r = 0`` (not 0 as in one port).
    For diagnostics and tests: :func:`rft3d_alpha` does not need the frame.

    Parameters
    ----------
    normals : array_like, shape (n, 3)
        Outward unit normals [-].
    velocities : array_like, shape (n, 3)
        Element velocities [m/s], not zero.
    """
    n = _unit_normals(normals)
    v = _direction_scale(_velocities(velocities, len(n)))
    speed = np.linalg.norm(v, axis=1)
    if np.any(speed == 0.0):
        raise InputError("velocities [m/s] must be non-zero for the 3D-RFT angles (their direction is needed)")
    v = v / speed[:, None]
    r = _horizontal_direction(v, n)
    theta = np.stack([-r[:, 1], r[:, 0], np.zeros(len(r))], axis=1)  # z x r
    nr = np.einsum("ij,ij->i", n, r)
    nz = n[:, 2]
    nt = np.einsum("ij,ij->i", n, theta)
    tilt = np.arccos(np.clip(nz, -1.0, 1.0))
    beta = np.where(nr >= 0.0, np.where(nz >= 0.0, -tilt, math.pi - tilt), np.where(nz >= 0.0, tilt, tilt - math.pi))
    vr = np.clip(np.einsum("ij,ij->i", v, r), -1.0, 1.0)
    gamma = np.where(v[:, 2] <= 0.0, np.arccos(vr), -np.arccos(vr))
    horizontal = np.hypot(n[:, 0], n[:, 1]) > _TINY
    psi = np.where(horizontal, np.arctan2(np.where(nr >= 0.0, nt, -nt), np.abs(nr)), 0.0)
    return beta, gamma, psi


def rft3d_alpha(normals: Any, velocities: Any,
                coefficients: tuple[Any, Any, Any] = (RFT3D_C1, RFT3D_C2, RFT3D_C3), *, xp: Any = np) -> Any:
    """3D-RFT's generic stress per depth of each element, world frame, before friction and leading tests [-].

    ``alpha = f1 m + f2 v - f3 z`` with ``v`` the unit velocity, ``m`` the
    plate's downward normal (``n`` if ``n_z < 0``, else ``-n``), and ``f_i``
    the cubic fits in ``x1 = -v_z``, ``x2 = |n_z|``, ``x3 = m . v``: the
    paper's ``alpha_r r + alpha_theta theta + alpha_z z`` with the frame
    written out (module docstring). Multiply by ``xi_n |z| dA`` for the force.

    Parameters
    ----------
    normals : array_like, shape (n, 3)
        Outward unit normals [-].
    velocities : array_like, shape (n, 3)
        Element velocities [m/s]; a zero velocity gives ``alpha = 0`` (no direction).
    coefficients : tuple of three array_like, shape (20,)
        ``(c1, c2, c3)``; :data:`RFT3D_C1`, :data:`RFT3D_C2`, :data:`RFT3D_C3` by default.
    xp : module
        The array library: numpy (the default; every input is checked, and
        bad input refused with :class:`~mudforce.errors.InputError`) or
        ``jax.numpy`` (for :mod:`mudforce.jax.contact3d`, under ``jit`` and ``grad``:
        traced values cannot be checked, the caller guards them; the normals
        are normalised all the same). The same operations either way.

    Returns
    -------
    array, shape (n, 3)
        Generic stress per depth [-] (``xi_n`` [N/m^3] gives it its unit); a
        numpy array, or a jax array with ``xp=jax.numpy``.
    """
    if xp is np:
        n = _unit_normals(normals)
        v = _direction_scale(_velocities(velocities, len(n)))
        c1, c2, c3 = _rft3d_coefficients(coefficients)
    elif getattr(xp, "__name__", None) != "jax.numpy":
        raise InputError(f"xp must be numpy or jax.numpy, got {getattr(xp, '__name__', type(xp).__name__)!r}")
    else:
        n = normals / _norm(normals, xp)[:, None]
        v = velocities
        c1, c2, c3 = (xp.asarray(c) for c in coefficients)
        return rft3d_alpha_unchecked(n, v, c1, c2, c3, xp)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, in one line
        alpha = rft3d_alpha_unchecked(n, v, c1, c2, c3, xp)
    _refuse_overflow(alpha, "stresses per depth alpha", "the coefficients times the basis")
    return alpha


def _norm(x: Any, xp: Any = np) -> Any:
    """The length of each row [-]: ``numpy.linalg.norm(x, axis=1)``'s own operations, in ``xp``."""
    return xp.sqrt(xp.sum(x * x, axis=1))


def rft3d_alpha_unchecked(n: Any, v: Any, c1: Any, c2: Any, c3: Any, xp: Any = np) -> Any:
    """3D-RFT's ``alpha`` on checked unit normals, in the array library ``xp`` (numpy or jax.numpy)."""
    square = xp.sum(v * v, axis=1)
    moving = square > 0.0
    speed = xp.sqrt(xp.where(moving, square, 1.0))  # |v|, 1 at rest: the double where keeps NaN out of gradients
    u = xp.where(moving[:, None], v / speed[:, None], 0.0)
    m = xp.where(n[:, 2:3] < 0.0, n, -n)
    basis = _basis(-u[:, 2], -m[:, 2], xp.einsum("ij,ij->i", m, u), xp)
    # row sums, not a matrix product: the same bits per element whatever the number of elements (BLAS is not)
    f1, f2, f3 = (basis * c1).sum(axis=-1), (basis * c2).sum(axis=-1), (basis * c3).sum(axis=-1)
    alpha = f1[:, None] * m + f2[:, None] * u
    alpha = xp.concatenate([alpha[:, :2], (alpha[:, 2] - f3)[:, None]], axis=1)
    return xp.where(moving[:, None], alpha, 0.0)


def _li_vectors(n: np.ndarray, v: np.ndarray, c: LiCoefficients) -> np.ndarray:
    """Li's law in the vertical plane of each element's motion, as world vectors [-]."""
    speed = np.linalg.norm(v, axis=1)
    moving = speed > 0.0
    u = np.divide(v, speed[:, None], out=np.zeros_like(v), where=moving[:, None])
    m = np.where(n[:, 2:3] > 0.0, -n, n)  # downward normal; a vertical plate keeps n (beta = +-pi/2 alike)
    r = _horizontal_direction(u, m)
    gamma = np.arctan2(-u[:, 2], np.hypot(u[:, 0], u[:, 1]))  # [-pi/2, pi/2]: x = r never points back
    mr = np.einsum("ij,ij->i", m, r)
    beta = np.arctan2(mr, -m[:, 2])
    edge_on = np.hypot(mr, m[:, 2]) <= _TINY
    alpha_x, alpha_z = _li(beta, gamma, c)
    alpha: np.ndarray = -alpha_x[:, None] * r
    alpha[:, 2] += alpha_z
    alpha[~moving | edge_on] = 0.0
    return alpha


def rft_element_alpha(normals: Any, velocities: Any, *, law: str = "rft3d", surface_friction: float = math.inf,
                      li_coefficients: LiCoefficients = LI2013_GENERIC) -> np.ndarray:
    """Generic stress per depth of each element [-]: the law, the leading test and the friction cap.

    Parameters
    ----------
    normals : array_like, shape (n, 3)
        Outward unit normals [-].
    velocities : array_like, shape (n, 3)
        Element velocities [m/s].
    law : {"rft3d", "li2013"}
        3D-RFT (Agarwal et al. 2023) or Li et al.'s planar law in the plane of motion.
    surface_friction : float
        ``mu_surf`` [-], >= 0: the stress's part tangential to the element is capped at ``mu_surf``
        times its normal part; ``inf`` (default) leaves it uncapped.
    li_coefficients : LiCoefficients
        The Fourier coefficients for ``law="li2013"``.

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        ``alpha`` [-], zero on trailing elements (``n . v < 0``) and elements at rest.
    """
    n = _unit_normals(normals)
    v = _direction_scale(_velocities(velocities, len(n)))
    mu = _friction(surface_friction)
    kind, li = _law(law), _li_coefficients(li_coefficients, "li_coefficients")
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, in one line
        alpha = _element_alpha(n, v, kind, mu, li)
    _refuse_overflow(alpha, "stresses per depth alpha", "the coefficients' sums")
    return alpha


def _element_alpha(n: np.ndarray, v: np.ndarray, law: str, mu: float, li: LiCoefficients) -> np.ndarray:
    alpha = rft3d_alpha_unchecked(n, v, RFT3D_C1, RFT3D_C2, RFT3D_C3) if law == "rft3d" else _li_vectors(n, v, li)
    speed = np.linalg.norm(v, axis=1)
    leading = np.einsum("ij,ij->i", n, v) >= -LEADING_TOLERANCE * speed
    alpha[~leading] = 0.0
    if math.isfinite(mu):
        normal = np.einsum("ij,ij->i", alpha, n)[:, None] * n
        tangential = alpha - normal
        size = np.linalg.norm(tangential, axis=1)
        cap = mu * np.linalg.norm(normal, axis=1)
        over = size > cap
        factor = np.divide(cap, size, out=np.ones_like(size), where=over)
        alpha = np.where(over[:, None], normal + factor[:, None] * tangential, alpha)  # others keep their bits
    return alpha


def rft_element_forces(centroids: Any, normals: Any, areas: Any, velocities: Any, surface_height: float = 0.0, *,
                       scale: float, law: str = "rft3d", surface_friction: float = math.inf,
                       inertial_drag: float = 0.0, li_coefficients: LiCoefficients = LI2013_GENERIC) -> np.ndarray:
    """Granular RFT force on each surface element [N], world frame (z up).

    ``F = scale * alpha * |z| * dA`` on leading elements below the surface
    (depth ``|z| = surface_height - z_c > 0``), zero elsewhere, with
    ``alpha`` of :func:`rft_element_alpha` (Li et al. 2013; Agarwal et
    al. 2023); plus, if ``inertial_drag > 0``, dynamic RFT's inertial
    drag ``inertial_drag (v . n)^2 dA`` along ``-n`` on the same elements
    (Agarwal et al. 2021), which always opposes the motion.

    Parameters
    ----------
    centroids : array_like, shape (n, 3)
        Element centroids [m].
    normals : array_like, shape (n, 3)
        Outward unit normals [-].
    areas : array_like, shape (n,)
        Element areas [m^2], >= 0.
    velocities : array_like, shape (n, 3)
        Element velocities [m/s].
    surface_height : float
        Height of the medium's free surface [m].
    scale : float
        The medium's stress per depth [N/m^3], > 0: ``xi_n`` (:func:`medium_scale`) for ``"rft3d"``,
        Li's ``zeta`` for ``"li2013"`` with the generic coefficients (``alpha_z(0, pi/2) = 1``).
    law : {"rft3d", "li2013"}
        The element law.
    surface_friction : float
        ``mu_surf`` [-], >= 0; ``inf`` (default) leaves the tangential stress uncapped.
    inertial_drag : float
        ``lambda rho`` [kg/m^3], >= 0: the drag scaling times the medium's density; 0 (default) turns
        the dynamic term off.
    li_coefficients : LiCoefficients
        Fourier coefficients for ``law="li2013"``.

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        Force on each element [N].
    """
    n = _unit_normals(normals)
    count = len(n)
    c = _vectors(centroids, "centroids [m]", count)
    v = _velocities(velocities, count)
    a = _reals(areas)
    if a is None or a.shape != (count,):
        raise InputError(f"areas [m^2] must be an array of shape ({count},), got "
                         f"{getattr(a, 'shape', type(areas).__name__)}")
    if not np.all(np.isfinite(a)) or np.any(a < 0.0):
        raise InputError("areas [m^2] must be finite and >= 0")
    height = finite_number(surface_height, "surface_height", "m")
    k = finite_number(scale, "scale", "N/m^3", positive=True)
    mu = _friction(surface_friction)
    drag = finite_number(inertial_drag, "inertial_drag (lambda rho)", "kg/m^3", nonnegative=True)
    kind = _law(law)
    li = _li_coefficients(li_coefficients, "li_coefficients")
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, in one line
        depth = np.maximum(height - c[:, 2], 0.0)
        alpha = _element_alpha(n, _direction_scale(v), kind, mu, li)
        forces: np.ndarray = (k * depth * a)[:, None] * alpha
        if drag > 0.0:
            vn = np.einsum("ij,ij->i", n, v)
            speed = np.linalg.norm(v, axis=1)
            loaded = (depth > 0.0) & (vn >= -LEADING_TOLERANCE * speed)
            forces -= (np.where(loaded, drag * vn * vn * a, 0.0))[:, None] * n
    _refuse_overflow(forces, "forces [N]", "scale x depth x area (and inertial_drag x (v.n)^2 x area)")
    return forces


def rft_wrench(centroids: Any, forces: Any, point: Any = (0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """Total force [N] and torque about ``point`` [N m] of element forces applied at their centroids.

    Parameters
    ----------
    centroids : array_like, shape (n, 3)
        Points of application [m].
    forces : array_like, shape (n, 3)
        Element forces [N] (:func:`rft_element_forces`).
    point : array_like, shape (3,)
        Reference point of the torque [m].

    Returns
    -------
    force, torque : numpy.ndarray, shape (3,)
        ``sum F_i`` [N] and ``sum (c_i - point) x F_i`` [N m].
    """
    c = _vectors(centroids, "centroids [m]", None)
    f = _vectors(forces, "forces [N]", len(c))
    p = _reals(point)
    if p is None or p.shape != (3,) or not np.all(np.isfinite(p)):  # words of one line (a repr spans lines)
        got = (f"{type(point).__name__} (not real numbers)" if p is None else f"shape {p.shape}" if p.shape != (3,)
               else repr(p.tolist()))
        raise InputError(f"point [m] must be 3 finite numbers, got {got}")
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, in one line
        force, torque = f.sum(axis=0), np.cross(c - p, f).sum(axis=0)
    _refuse_overflow(np.stack([force, torque]), "force [N] and torque [N m]", "the forces and lever arms")
    return force, torque


def medium_scale(rho_c: float, mu_int: float, gravity: float = _GRAVITY) -> float:
    """3D-RFT's medium scale ``xi_n = rho_c g (894 mu^3 - 386 mu^2 + 89 mu)`` [N/m^3].

    Agarwal, Goldman & Kamrin, PNAS 120, e2214017120 (2023): a cubic
    fitted to their simulated media; far outside their range of internal
    friction it is an extrapolation (it stays positive for all ``mu > 0``).

    Parameters
    ----------
    rho_c : float
        The medium's critical-state (bulk) density [kg/m^3], > 0.
    mu_int : float
        Internal friction coefficient of the medium [-], > 0.
    gravity : float
        Gravitational acceleration [m/s^2], > 0.
    """
    rho = finite_number(rho_c, "rho_c", "kg/m^3", positive=True)
    mu = finite_number(mu_int, "mu_int", "-", positive=True)
    g = finite_number(gravity, "gravity", "m/s^2", positive=True)
    try:
        xi = rho * g * (894.0 * mu ** 3 - 386.0 * mu ** 2 + 89.0 * mu)
    except OverflowError:  # mu ** 3 (the products give inf, refused below)
        xi = math.inf
    if not math.isfinite(xi):
        raise InputError(f"medium_scale overflows for rho_c = {rho_c!r} kg/m^3, mu_int = {mu_int!r}, gravity = "
                         f"{gravity!r} m/s^2; expected a scale below 1.8e308 N/m^3 (a physical medium: rho_c ~ 1e3, "
                         "mu_int ~ 0.1-1)")
    return xi


# --- checks -------------------------------------------------------------------------------------------------------

def _reals(value: Any) -> np.ndarray | None:
    """``value`` as a float64 array if it holds real numbers (:func:`mudforce.errors.real_array`: no booleans, also
    among numbers, no strings, complex numbers or objects), else None."""
    try:
        return real_array(value, "", "")
    except InputError:
        return None


def _finite_array(value: Any, name: str) -> np.ndarray:
    array = _reals(value)
    if array is None:
        raise InputError(f"{name} must be real numbers (not booleans, strings or complex), got "
                         f"{type(value).__name__}")
    if not np.all(np.isfinite(array)):
        raise InputError(f"{name} must be finite")
    return array


def _vectors(value: Any, name: str, count: int | None) -> np.ndarray:
    array = _finite_array(value, name)
    if array.ndim != 2 or array.shape[1] != 3 or (count is not None and array.shape[0] != count):
        expected = f"({count}, 3)" if count is not None else "(n, 3)"
        raise InputError(f"{name} must be an array of shape {expected}, got {array.shape}")
    return array


def _velocities(value: Any, count: int) -> np.ndarray:
    """Element velocities [m/s], (count, 3), finite and within +-:data:`_MAX_VELOCITY` (whose squares are finite:
    beyond, |v| overflowed to inf and the direction to zero, a silently wrong stress)."""
    v = _vectors(value, "velocities [m/s]", count)
    if not np.all(np.abs(v) <= _MAX_VELOCITY):
        raise InputError(f"velocities [m/s] must be within +-{_MAX_VELOCITY:g} (their squares finite), got "
                         f"{float(np.abs(v).max())!r}")
    return v


def _direction_scale(v: np.ndarray) -> np.ndarray:
    """``v`` (n, 3) [m/s] with each row whose components are all below :data:`_SMALL_VELOCITY` (and not all 0)
    multiplied by the power of two that brings it near 1 [-]: exactly the same direction, which is all the laws take
    from it, without the underflow of ``|v|^2`` (below about 1e-154 m/s an element in motion got the stress of one
    at rest, a little above it a direction rounded off). Other rows, and ``v`` if there are none, are as given."""
    largest = np.abs(v).max(axis=1, initial=0.0)
    small = (largest > 0.0) & (largest < _SMALL_VELOCITY)
    if not small.any():
        return v
    scaled: np.ndarray = v.copy()
    scaled[small] = np.ldexp(v[small], -np.frexp(largest[small])[1][:, None])
    return scaled


def _refuse_overflow(values: np.ndarray, what: str, product: str) -> None:
    """InputError if ``values`` are not all finite: finite inputs whose products overflowed."""
    if not np.all(np.isfinite(values)):
        raise InputError(f"the {what} overflow (not finite): {product} beyond float64; expected inputs of "
                         "physical size")


def _unit_normals(value: Any) -> np.ndarray:
    n = _vectors(value, "normals", None)
    with np.errstate(over="ignore"):  # |n|^2 of a normal beyond 1e154: inf, refused below without numpy's warning
        length = _norm(n)
    if np.any(np.abs(length - 1.0) > _NORMAL_TOLERANCE):
        worst = float(length[np.argmax(np.abs(length - 1.0))])
        raise InputError(f"normals must be unit vectors (|n| = 1 within {_NORMAL_TOLERANCE:g}), got |n| = {worst:g}")
    unit: np.ndarray = n / length[:, None]
    return unit


def _horizontal_direction(u: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """Unit horizontal direction of ``u``; of ``fallback`` where ``u`` is vertical; ``+x`` where both are."""
    count = len(u)
    r = np.zeros((count, 3))
    r[:, 0] = 1.0
    for source in (fallback, u):  # u last: it wins where it has a horizontal part
        size = np.hypot(source[:, 0], source[:, 1])
        ok = size > _TINY
        r[ok, 0] = source[ok, 0] / size[ok]
        r[ok, 1] = source[ok, 1] / size[ok]
    return r


def _law(law: Any) -> str:
    """``law`` if it is the name of one of :data:`LAWS` (a str: an array ``["rft3d"]`` compared equal elementwise,
    passed, and was read as ``"['rft3d']"``, Li's law), else InputError."""
    if not isinstance(law, str) or law not in LAWS:
        got = repr(law) if isinstance(law, str) else type(law).__name__
        raise InputError(f"law must be one of {', '.join(LAWS)}, got {got}")
    return str(law)


def _friction(value: Any) -> float:
    if isinstance(value, (float, np.floating)) and value == math.inf:
        return math.inf
    return finite_number(value, "surface_friction (mu_surf)", "-", nonnegative=True)


def _li_coefficients(value: Any, name: str) -> LiCoefficients:
    """``value`` if it is a :class:`LiCoefficients` of finite real numbers, else InputError (a NaN, a string, a bool
    or an array in a field gave NaN, a TypeError, 1, or an array of results)."""
    if not isinstance(value, LiCoefficients):
        raise InputError(f"{name} must be a LiCoefficients, got {type(value).__name__}")
    for field, number in zip(LiCoefficients._fields, value, strict=True):
        # abs(x) <= the largest float, not math.isfinite(x): that raised OverflowError for a Python int beyond it
        if not (is_real(number) and abs(number) <= sys.float_info.max):
            got = shown(number) if is_real(number) or isinstance(number, str) else type(number).__name__
            raise InputError(f"{name} must hold finite real numbers, got {field} = {got}")
    return value


def _rft3d_coefficients(value: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    if not isinstance(value, tuple) or len(value) != 3:
        raise InputError("coefficients must be a tuple (c1, c2, c3) of 20 numbers each")
    arrays = tuple(_finite_array(c, "3D-RFT coefficients") for c in value)
    if any(a.shape != (20,) for a in arrays):
        raise InputError(f"coefficients must be three arrays of shape (20,), got {[a.shape for a in arrays]}")
    return arrays[0], arrays[1], arrays[2]
