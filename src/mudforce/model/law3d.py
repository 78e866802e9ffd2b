"""The 3-D law per surface element: what is the paper's and what is ours (docs/model.md, "Mud in 3-D").

The paper (Chen, Yi & Shan 2024) gives the vertical force on a flat sole
moved straight up and down. A robot's foot is a sphere, capsule or box that
also slides, tilts and twists. :class:`mudforce.steppers.contact3d.MudContact3D`
puts a law on every surface element of a :class:`mudforce.model.shapes.Shape`;
this module holds that law's pieces as small pure functions of one element
(world frame, z up, SI), which run on floats, numpy arrays and JAX arrays
alike. The 1-D stepper supplies each element's paper stress.

One law, written once, for every path
-------------------------------------
Each function here is the law for ONE element, written as scalar
arithmetic on its components (``nx, ny, nz`` rather than an (n, 3) array):

* called from Python on numpy arrays (columns of elements), it is the law on
  every element at once (:class:`mudforce.steppers.contact3d.MudContact3D`
  places its elements so; the tests hold this form to the compiled one, bit
  for bit);
* called on JAX arrays, the same (:mod:`mudforce.jax.contact3d`, under
  ``jit``, ``vmap``, ``lax.scan`` and ``grad``);
* called from numba-compiled code on floats, it is compiled into the
  caller (:mod:`mudforce._kernel.step3d`: the many-feet step, and the loop
  MudContact3D runs the law in): each function
  is registered with numba (``numba.extending.overload``), so the compiled
  step runs this very source, not a copy.

So the placement of the elements (:func:`rotation`, :func:`rotate`,
:func:`element_depth`), the velocities from consecutive poses and the
horizontal law (:func:`element_force`), the vertical/lateral split and
the wrench's moments (:func:`moment`) exist once. A choice is a
:func:`select` (``where`` on arrays, ``a if c else b`` compiled) and a
square root :func:`root`; where a square root or a quotient meets 0 (a slip
of zero length, a slip straight into a face) its argument is guarded first
(the "double where"), so that the branch not taken puts no NaN into a JAX
gradient. Eq. (4)'s spring is :func:`spring_stress`: the compiled paths and
numpy take it from :func:`mudforce.model.equations.nonlinear_spring_stress`
(its power, :func:`mudforce._plumbing.pow.power`, is the one every path
shares); JAX, which cannot run that power, computes ``x ** beta`` itself
(within an ulp). Only :func:`rotation_matrix` checks its input.

The law, element by element
---------------------------
* **Vertical: the paper, on the downward-facing projection, in 3D-RFT's
  direction.** Each element carries the paper's whole state (Maxwell
  strain, suction, necking, the post-necking decay), stepped by the 1-D
  stepper on the element's own depth below the surface, so a tilted foot
  pulled out peels element by element. Its stress ``sigma_i`` (Eq. (8),
  positive up) acts on its horizontal projection facing down: vertical
  force ``f_z = sigma_i A_i max(-n_z, 0)`` (:func:`vertical_weight`), with
  the sideways part ``f_z L(n_z) (n_x, n_y)`` that 3D-RFT gives a plate of
  that tilt moved straight down (:func:`vertical_lean`,
  :func:`vertical_element_force`). A flat sole moved vertically is exactly
  the paper. *Ours:* the projection (an element facing up, or a vertical
  wall, carries no vertical paper stress), the per-element state (the
  paper has one state for the whole foot), and 3D-RFT's direction on the
  paper's size (suction included, which granular media do not have).
* **Horizontal: elastic, then yielding.** Each submerged element carries a
  horizontal elastic slip ``s_i`` [m]; its traction is ``-k s_i``, with
  ``k`` the paper's withdrawal stiffness ``k_m_w`` by default
  (:func:`lateral_return_map`). When ``k |s_i|`` reaches the element's
  capacity in that direction (:func:`lateral_capacity`), the slip stops
  growing: the element flows at its capacity, dissipating. A foot at rest
  under a small sideways load therefore holds (it deflects by
  ``load / (k S)``, without creep), and a sliding foot meets its capacity.
  The slip follows from the poses by the exact rule: each element's
  horizontal displacement since the last step (:func:`element_force`).
  The capacity is the sum of
  - **shear** along the face, capped by the paper's yield stress:
    ``sigma_y |s_t|``, with ``s_t`` the part of the slip direction in the
    element's plane (:func:`shear_fraction`). *Ours:* the paper's
    ``sigma_y`` is the yield stress of the neck in tension; we take the
    same stress as mud's yield in shear;
  - **bearing** of the faces that lead the slip, from 3D-RFT
    (Agarwal, Goldman & Kamrin 2023, :mod:`mudforce.model.granular`): the
    granular law's stress against the slip direction, per unit of what it
    gives a flat plate pushed down, times the paper's rate-independent
    depth stress, the nonlinear spring ``alpha (z/H)^beta`` of Eq. (4)
    (:func:`bearing_factor`). *Ours:* the spring as the medium's depth
    stress (3D-RFT's ``xi |z|``), and 3D-RFT's orientation dependence,
    measured for granular media, carried over to mud.
* **Horizontal drag**, Eq. (5)'s ``lambda rho_m v^2`` on the leading
  elements' projection against the horizontal velocity
  (:func:`horizontal_drag`): it always opposes the motion. The vertical
  drag is the paper's, inside ``sigma_i``.
* Only elements below the surface are loaded (the paper's FREE above it;
  an element that leaves the mud forgets its slip).

No 3-D mud measurements exist: the horizontal law and every *ours* above
are assumptions, stated so that they can be tested and fitted when data
come. The parameters beyond the paper are the lateral stiffness (default
``k_m_w``, from Table I), the bearing scale (default 1, 3D-RFT's granular
bearing as it is: :func:`bearing_stress`) and the 3D-RFT coefficients
(published); nothing else is new.
"""

from __future__ import annotations

import inspect
import math
import sys
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from mudforce._plumbing.jit import njit, overload
from mudforce.errors import InputError, is_real, real_array, shown
from mudforce.model.equations import nonlinear_spring_stress
from mudforce.model.granular import RFT3D_C1, RFT3D_C2, RFT3D_C3, rft3d_alpha, rft3d_basis

__all__ = [
    "FLAT_PLATE_ALPHA",
    "MAX_BEARING_SCALE",
    "MAX_LATERAL_STIFFNESS",
    "QUATERNION_TOLERANCE",
    "ROUNDING_DEPTH",
    "bearing_factor",
    "bearing_stress",
    "check_bearing_scale",
    "check_lateral_stiffness",
    "element_depth",
    "element_force",
    "horizontal_drag",
    "lateral_capacity",
    "lateral_return_map",
    "moment",
    "root",
    "rotate",
    "rotation",
    "rotation_matrix",
    "select",
    "settle_depth",
    "shear_fraction",
    "spring_stress",
    "vertical_element_force",
    "vertical_force",
    "vertical_lean",
    "vertical_weight",
]

#: The stiffest horizontal slip accepted [Pa/m]: the bound on the paper's stiffnesses (``MudParameters``).
MAX_LATERAL_STIFFNESS = 1e12


def check_lateral_stiffness(k: object) -> float:
    """``lateral_stiffness`` [Pa/m] as a float within (0, :data:`MAX_LATERAL_STIFFNESS`], else a one-line InputError
    (the one check of it, for the CPU step, the JAX step and the 3-D fit)."""
    if not is_real(k) or not 0.0 < k <= MAX_LATERAL_STIFFNESS:  # type: ignore[operator]
        # shown, not repr: a Python int of over 4300 digits has no repr (ValueError)
        raise InputError(f"lateral_stiffness must be within (0, {MAX_LATERAL_STIFFNESS:g}] [Pa/m], got {shown(k)}")
    return float(k)  # type: ignore[arg-type]

#: The largest ``bearing_scale`` accepted [-]: a thousand times 3D-RFT's granular bearing.
MAX_BEARING_SCALE = 1e3


def check_bearing_scale(b: object) -> float:
    """``bearing_scale`` [-] as a float within [0, :data:`MAX_BEARING_SCALE`], else a one-line InputError (the one
    check of it, for the CPU step, the JAX step, the reference and the 3-D fit)."""
    if not is_real(b) or not 0.0 <= b <= MAX_BEARING_SCALE:  # type: ignore[operator]
        raise InputError(f"bearing_scale must be within [0, {MAX_BEARING_SCALE:g}] [-] (1: 3D-RFT's granular "
                         f"bearing), got {shown(b)}")
    return float(b)  # type: ignore[arg-type]


#: 3D-RFT's generic vertical stress on a flat plate facing down and pushed down [-] (the bearing's unit).
FLAT_PLATE_ALPHA: float = float(rft3d_alpha(np.array([[0.0, 0.0, -1.0]]), np.array([[0.0, 0.0, -1.0]]))[0, 2])

#: A quaternion whose norm is within this of 1 is normalised; farther, refused [-].
QUATERNION_TOLERANCE = 1e-6

#: A change of an element's depth up to this [m] between steps is the rounding of a pose, not motion.
ROUNDING_DEPTH = 1e-13

# the 3D-RFT cubic fits' coefficients (mudforce.model.granular) as constants of the compiled code
_C1 = tuple(float(c) for c in RFT3D_C1)
_C2 = tuple(float(c) for c in RFT3D_C2)
_PER_FLAT = 1.0 / FLAT_PLATE_ALPHA


def _pushed_down(c: Any) -> tuple[float, float, float, float]:
    """A 3D-RFT cubic fit (``rft3d_basis``'s order) for a downward motion, as a cubic in ``x2 = x3 = c`` [-].

    A plate moved straight down has ``x1 = sin(gamma) = 1`` and ``x2 = x3 = cos(beta) = c``; each of the 20
    terms is then ``c`` to its degree in ``x2`` and ``x3``, read from :func:`rft3d_basis` itself (its monomials
    at ``x1 = 1``, ``x2 = x3 = 2`` are 2 to those degrees, exactly). Returns the coefficients of ``1, c, c^2, c^3``.
    """
    degrees = [int(d) for d in np.log2(rft3d_basis(1.0, 2.0, 2.0))]
    out = [0.0, 0.0, 0.0, 0.0]
    for k, term in zip(degrees, c, strict=True):
        out[k] += float(term)
    return out[0], out[1], out[2], out[3]


_D1, _D2, _D3 = _pushed_down(RFT3D_C1), _pushed_down(RFT3D_C2), _pushed_down(RFT3D_C3)
# vertical_lean = -f1(c) / q(c) with q = c f1 + f2 + f3 = -alpha_z (from -0.93 to -0.24 on [0, 1]), a quartic
_MINUS_ALPHA_Z = (_D2[0] + _D3[0], _D1[0] + _D2[1] + _D3[1], _D1[1] + _D2[2] + _D3[2], _D1[2] + _D2[3] + _D3[3], _D1[3])

Array = Any  # a float, a numpy array, or a jax array
_F = TypeVar("_F", bound=Callable[..., Any])


# ---------------------------------------------------------------- one source for floats, numpy, JAX and numba
def _namespace(*values: Any) -> Any:
    """``jax.numpy`` if one of ``values`` is a JAX array (or tracer), else numpy."""
    jax = sys.modules.get("jax")
    if jax is not None:
        for v in values:
            if isinstance(v, jax.Array):
                return sys.modules["jax.numpy"]
    return np


def select(condition: Array, a: Array, b: Array) -> Array:
    """``a`` where ``condition``, else ``b``: ``where`` on arrays, ``a if condition else b`` compiled and on scalars."""
    if isinstance(condition, (bool, np.bool_)):  # a Python or numpy scalar: as compiled (np.where costs ~3 us)
        return a if condition else b
    return _namespace(condition, a, b).where(condition, a, b)


def root(x: Array) -> Array:
    """The square root of ``x`` (``x >= 0``): ``sqrt`` of numpy or JAX, ``math.sqrt`` compiled and on floats."""
    if isinstance(x, float):  # also numpy's float64; IEEE's square root, correctly rounded either way
        return math.sqrt(x)
    return _namespace(x).sqrt(x)


@overload(select)
def _select_compiled(condition: Any, a: Any, b: Any) -> Any:
    def impl(condition: Any, a: Any, b: Any) -> Any:  # pragma: no cover - compiled
        return a if condition else b
    return impl


@overload(root)
def _root_compiled(x: Any) -> Any:
    def impl(x: Any) -> Any:  # pragma: no cover - compiled
        return math.sqrt(x)
    return impl


def _law(function: _F) -> _F:
    """Register a law function with numba, so that compiled code calls (and inlines) this very source.

    The function itself is returned unchanged: from Python it runs on
    floats, numpy arrays and JAX arrays (the module docstring).
    """
    def typer(*args: Any) -> Any:
        return function

    typer.__signature__ = inspect.signature(function)  # type: ignore[attr-defined]
    overload(function, inline="always")(typer)
    return function


def _positive(x: Array) -> Array:
    """``max(x, 0)`` (0 for NaN's sake never arises: the callers' arguments are finite)."""
    return select(x >= 0.0, x, 0.0)


_law(_positive)


# ---------------------------------------------------------------- placing the elements
def rotation_matrix(quaternion: Any) -> np.ndarray:
    """The rotation matrix of a unit quaternion ``(w, x, y, z)`` (MuJoCo's order) [-], shape (3, 3); checked.

    A quaternion whose norm is within :data:`QUATERNION_TOLERANCE` of 1 is
    normalised (:func:`rotation`); farther, or not 4 finite numbers, it is
    refused with an :class:`~mudforce.errors.InputError`.
    """
    q = real_array(quaternion, "quaternion", "-")  # real numbers only (a complex or boolean array refused)
    if q.shape != (4,) or not np.all(np.isfinite(q)):  # (not its repr: over lines for a 2-D array)
        got = f"shape {q.shape}" if q.shape != (4,) else repr(q.tolist())
        raise InputError(f"a quaternion must be 4 finite numbers (w, x, y, z), got {got}")
    with np.errstate(over="ignore"):  # a component beyond 1e154: norm inf, refused below without numpy's warning
        norm = math.sqrt(float(q @ q))
    if abs(norm - 1.0) > QUATERNION_TOLERANCE:
        raise InputError(f"a quaternion must have norm 1 (within {QUATERNION_TOLERANCE:g}), got norm {norm:.9g}")
    return np.reshape(np.array(_rotation_compiled(*q.tolist())), (3, 3))


@_law
def rotation(w: Array, x: Array, y: Array, z: Array) -> tuple[Array, ...]:
    """The rotation matrix of the quaternion ``(w, x, y, z)`` divided by its norm, row by row [-]: 9 entries.

    Unchecked (:func:`rotation_matrix` checks); ``(1, 0, 0, 0)`` gives the
    identity exactly, and a quaternion of norm exactly 1 is used as it is
    (a division by 1 is exact).
    """
    norm = root(w * w + x * x + y * y + z * z)
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return (1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),
            2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x),
            2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y))


@njit(cache=True, nogil=True, error_model="numpy")
def _rotation_compiled(w: float, x: float, y: float, z: float) -> tuple[float, ...]:
    """:func:`rotation` of Python floats, compiled (the same source; a fraction of numpy's per-call cost)."""
    return rotation(w, x, y, z)  # type: ignore[no-any-return]


@_law
def rotate(r: tuple[Array, ...], x: Array, y: Array, z: Array) -> tuple[Array, Array, Array]:
    """``R (x, y, z)`` for a rotation ``r`` given row by row (:func:`rotation`) [the unit of x, y, z].

    A body-frame centroid gives the element's offset from the body origin
    in the world frame (its world centroid is the body position plus
    that); a body-frame normal, its world normal.
    """
    return (r[0] * x + r[1] * y + r[2] * z,
            r[3] * x + r[4] * y + r[5] * z,
            r[6] * x + r[7] * y + r[8] * z)


@_law
def element_depth(surface_height: Array, pz: Array, oz: Array) -> Array:
    """An element's depth below the undisturbed surface [m]: ``h - (p_z + o_z)``.

    ``surface_height`` [m], ``pz`` the body origin's height [m], ``oz`` the
    element's world offset's height (:func:`rotate`) [m].
    """
    return surface_height - (pz + oz)


@_law
def settle_depth(depth: Array, previous: Array) -> Array:
    """Each element's depth [m], or its previous depth where the two differ by rounding only.

    An element that stays at its depth while the foot turns about it gets
    a depth that moves by a few 1e-18 m from the rounding of the rotation;
    the paper's branch follows the sign of that motion (Eq. (8)), and a
    false withdrawal drops the nonlinear spring (tens of newtons). A change
    of at most :data:`ROUNDING_DEPTH` (0.1 pm a step, 1e-10 m/s at 1 kHz)
    is therefore no change: the element is at rest. *Ours* (the paper's
    foot does not turn).

    Parameters
    ----------
    depth, previous : float or array
        The elements' depths now and at the last step [m].
    """
    return select(abs(depth - previous) <= ROUNDING_DEPTH, previous, depth)


# ---------------------------------------------------------------- the vertical law
@_law
def vertical_weight(nz: Array) -> Array:
    """The share of an element's area that carries the paper's vertical stress, ``max(-n_z, 0)`` [-].

    Its horizontal projection facing down: 1 for a sole, 0 for a wall or an
    upward-facing element. ``nz`` the world normal's vertical component [-].
    """
    return _positive(-nz)


@_law
def vertical_lean(nz: Array) -> Array:
    """3D-RFT's sideways stress per vertical stress on an element pushed down, per unit of its normal's tilt [-].

    A downward-facing plate tilted by ``beta`` (outward normal ``n``, ``n_z = -cos(beta)``) and moved straight
    down meets, in 3D-RFT (Agarwal, Goldman & Kamrin 2023), ``alpha = f1 n + f2 u - f3 z`` with ``u = -z``:
    vertically ``alpha_z = -(c f1 + f2 + f3)`` and sideways ``f1 (n_x, n_y)``, with the cubic fits ``f_i`` at
    ``x1 = 1``, ``x2 = x3 = c = cos(beta)``. This is ``f1 / alpha_z``: the element's sideways force is its
    vertical force times ``lean (n_x, n_y)`` (:func:`vertical_element_force`). About -0.31 for a nearly flat
    plate (a 30 deg plate: 15 % of its vertical force, away from the side its normal leans to), -0.37 at
    60 deg; 0 for a flat plate's normal. Evaluated at ``c = max(-n_z, 0)``: an element facing up or sideways
    carries no vertical stress (:func:`vertical_weight`), and ``alpha_z`` stays within [0.24, 0.93] on [0, 1].
    """
    c = vertical_weight(nz)
    f1 = ((_D1[3] * c + _D1[2]) * c + _D1[1]) * c + _D1[0]
    a = _MINUS_ALPHA_Z
    q = (((a[4] * c + a[3]) * c + a[2]) * c + a[1]) * c + a[0]
    return -f1 / q


@_law
def vertical_element_force(stress: Array, area: Array, nx: Array, ny: Array,
                           nz: Array) -> tuple[Array, Array, Array]:
    """The paper's vertical stress on an element, in 3D-RFT's direction: ``(f_z lean n_x, f_z lean n_y, f_z)`` [N].

    ``f_z`` is :func:`vertical_force` (the paper's stress on the downward projection, its size), and
    :func:`vertical_lean` turns it as 3D-RFT turns a tilted plate's resistance to a vertical motion (its
    direction). The sideways part follows ``f_z``'s sign: suction pulls a tilted element into the mud along
    the same line. A flat sole (``n_x = n_y = 0``) gets no sideways force: the paper's own case.

    Parameters
    ----------
    stress : float or array
        The element's paper stress ``sigma_i`` [Pa], Eq. (8), positive up.
    area : float or array
        [m^2].
    nx, ny, nz : float or array
        Its outward unit normal, world frame [-].
    """
    fz = vertical_force(stress, area, nz)
    side = fz * vertical_lean(nz)
    return side * nx, side * ny, fz


@_law
def vertical_force(stress: Array, area: Array, nz: Array) -> Array:
    """The paper's vertical force on an element [N]: ``sigma_i A_i max(-n_z, 0)``, Eq. (8) on its projection.

    ``stress`` the element's paper stress ``sigma_i`` [Pa] (positive up),
    ``area`` [m^2], ``nz`` its world normal's vertical component [-].
    """
    return stress * area * vertical_weight(nz)


def spring_stress(depth: Array, alpha: Any, beta: Any, width: Any) -> Array:
    """The nonlinear spring ``alpha (z/H)^beta`` of Eq. (4) at each element's depth [Pa], 0 above the surface.

    :func:`mudforce.model.equations.nonlinear_spring_stress` on floats and
    numpy arrays (its power, :func:`mudforce._plumbing.pow.power`, is the one
    every path shares) and in compiled code; on JAX arrays ``x ** beta``
    (within an ulp), guarded so that no NaN reaches a gradient above the
    surface.

    Parameters
    ----------
    depth : float or array
        Element depths below the surface [m].
    alpha : float
        Spring coefficient [Pa], Eq. (4).
    beta : float
        Spring exponent [-], Eq. (4).
    width : float
        Intruder width ``H`` [m], Eq. (4).
    """
    xp = _namespace(depth, alpha, beta, width)
    if xp is np:
        z = np.asarray(depth, dtype=np.float64)
        out = np.empty(z.shape)
        _springs(z.reshape(-1), float(alpha), float(beta), float(width), out.reshape(-1))
        return out if out.ndim else float(out)
    below = depth > 0.0
    base = xp.where(below, depth, width) / width  # 1 at and above the surface: no NaN in a gradient there
    return xp.where(below, alpha * base ** beta, 0.0)


@overload(spring_stress)
def _spring_stress_compiled(depth: Any, alpha: Any, beta: Any, width: Any) -> Any:
    def impl(depth: Any, alpha: Any, beta: Any, width: Any) -> Any:  # pragma: no cover - compiled
        return nonlinear_spring_stress(alpha, beta, depth, width)
    return impl


@njit(cache=True, nogil=True, error_model="numpy")
def _springs(depth: np.ndarray, alpha: float, beta: float, width: float, out: np.ndarray) -> None:
    """:func:`spring_stress` of every depth, into ``out`` (a loop the compiler vectorises)."""
    for i in range(depth.shape[0]):
        out[i] = nonlinear_spring_stress(alpha, beta, depth[i], width)


# ---------------------------------------------------------------- the horizontal law
@_law
def shear_fraction(nx: Array, ny: Array, nz: Array, dx: Array, dy: Array) -> Array:
    """``|s - (s.n) n|`` for the unit horizontal slip direction ``s = (dx, dy, 0)`` [-]: 1 along a face, 0 into it.

    ``(nx, ny, nz)`` the element's outward unit normal [-]. The square root
    is guarded at 0 (a slip straight into the face).
    """
    dn = dx * nx + dy * ny
    ax = dx - dn * nx
    ay = dy - dn * ny
    az = -(dn * nz)
    square = ax * ax + ay * ay + az * az
    some = square > 0.0
    return select(some, root(select(some, square, 1.0)), 0.0)


def _cubic_level(c: tuple[float, ...], b: Array, d: Array) -> Array:
    """3D-RFT's cubic fit (:func:`mudforce.model.granular.rft3d_basis`'s order) at ``x1 = -u_z = 0`` [-].

    A horizontal motion: the ten terms with ``x1`` are products with a
    zero, which change no sum, and are left out.
    """
    return (c[0] + c[2] * b + c[3] * d + c[5] * (b * b) + c[6] * (d * d) + c[8] * (b * d) + c[11] * (b * b * b)
            + c[12] * (d * d * d) + c[15] * (b * d * d) + c[16] * (d * b * b))


_law(_cubic_level)


@_law
def bearing_factor(nx: Array, ny: Array, nz: Array, dx: Array, dy: Array) -> Array:
    """3D-RFT's resistance of an element to motion along ``s = (dx, dy, 0)``, per a flat plate's pushed down [-].

    ``max(0, -alpha(n, s) . s) / FLAT_PLATE_ALPHA`` on an element that
    leads the motion (``n . s > 0``), 0 on the others; ``alpha`` is
    :func:`mudforce.model.granular.rft3d_alpha` (Agarwal, Goldman & Kamrin
    2023) for a horizontal unit velocity ``s``, whose vertical part ``f3``
    does not enter ``alpha . s``. A wall facing the motion gets about 0.26.
    ``(nx, ny, nz)`` the outward unit normal [-].
    """
    sign = select(nz < 0.0, 1.0, -1.0)  # the downward normal m (an exact change of sign)
    mx, my, mz = sign * nx, sign * ny, sign * nz
    x2 = -mz
    x3 = mx * dx + my * dy
    f1 = _cubic_level(_C1, x2, x3)
    f2 = _cubic_level(_C2, x2, x3)
    against = -((f1 * mx + f2 * dx) * dx + (f1 * my + f2 * dy) * dy)
    return select(nx * dx + ny * dy > 0.0, _positive(against) * _PER_FLAT, 0.0)


@_law
def bearing_stress(spring: Array, bearing_scale: Array) -> Array:
    """The depth stress the bearing multiplies [Pa]: Eq. (4)'s spring times ``bearing_scale`` [-].

    ``bearing_scale`` 1 (the default everywhere) is 3D-RFT's granular ratio of a face's sideways bearing to a
    flat plate's vertical stress, carried over to mud as it is (*ours*); it is the bearing's one parameter a
    user can fit from 3-D force data (:func:`mudforce.estimation.calibration.fit3d.fit_3d`), 0 leaves the shear
    alone. ``spring`` [Pa], :func:`spring_stress` at the element's depth.
    """
    return spring * bearing_scale


@_law
def lateral_capacity(sigma_y: Array, shear: Array, spring: Array, bearing: Array) -> Array:
    """The horizontal stress an element can carry before it flows [Pa]: ``sigma_y shear + spring bearing``.

    Parameters
    ----------
    sigma_y : float
        Yield stress [Pa], Eq. (9) (taken as the yield in shear).
    shear : float or array
        :func:`shear_fraction` [-].
    spring : float or array
        :func:`spring_stress` [Pa].
    bearing : float or array
        :func:`bearing_factor` [-].
    """
    return sigma_y * shear + spring * bearing


@_law
def lateral_return_map(sx: Array, sy: Array, size: Array, stiffness: Array,
                       capacity: Array) -> tuple[Array, Array, Array, Array]:
    """Elastic-perfectly-plastic update of an element's horizontal slip: ``(slip x, slip y, traction x, y)``.

    Parameters
    ----------
    sx, sy : float or array
        The trial slip [m]: the last slip plus this step's horizontal displacement.
    size : float or array
        Its length ``|(sx, sy)|`` [m] (:func:`element_force` has it already).
    stiffness : float
        Lateral stiffness ``k`` [Pa/m].
    capacity : float or array
        :func:`lateral_capacity` in the trial slip's direction [Pa].

    Returns
    -------
    The slip kept [m] (the trial where ``k |slip| <= capacity``, else
    scaled back to ``capacity / k``: the rest flowed), and the traction
    ``-k slip`` [Pa].
    """
    limit = capacity / stiffness
    scale = select(size > limit, limit / select(size > 0.0, size, 1.0), 1.0)
    kx = sx * scale
    ky = sy * scale
    return kx, ky, -stiffness * kx, -stiffness * ky


@_law
def horizontal_drag(lambda_: Array, rho_m: Array, nx: Array, ny: Array, ux: Array, uy: Array) -> tuple[Array, Array]:
    """Eq. (5) against the horizontal motion on the leading projection: ``-lambda rho (n.u)_+ u`` [Pa].

    Its size is ``lambda rho |u|^2 (n.u/|u|)_+``: the paper's drag on the part
    of the element that faces the motion; it always opposes the motion.
    ``lambda_`` [-], ``rho_m`` [kg/m^3], ``(nx, ny)`` the normal's
    horizontal part [-], ``(ux, uy)`` the element's horizontal velocity [m/s].
    """
    scale = -(lambda_ * rho_m) * _positive(nx * ux + ny * uy)
    return scale * ux, scale * uy


@_law
def element_force(stress: Array, spring: Array, area: Array, nx: Array, ny: Array, nz: Array, depth: Array,
                  sx: Array, sy: Array, mx: Array, my: Array, per_dt: Array, started: Array, stiffness: Array,
                  sigma_y: Array, lambda_: Array, rho_m: Array) -> tuple[Array, Array, Array, Array, Array]:
    """An element's force [N] and its new slip [m]: the 3-D law, vertical and horizontal, in one place.

    Vertically the paper's stress on the downward projection
    (:func:`vertical_force`). Horizontally, on an element below the surface
    after the foot's first step (``started``): the trial slip ``s + m`` (the last slip
    plus the displacement since the last pose, the exact rule), yielding at
    :func:`lateral_capacity` in its direction (:func:`lateral_return_map`),
    plus Eq. (5)'s drag at the velocity ``m / dt`` (:func:`horizontal_drag`);
    elsewhere no horizontal force and no slip (an element that leaves the
    mud forgets its slip). An element whose trial slip is 0 (a foot moved
    straight up and down, the paper's own case) gets 0 and no slip.

    Parameters
    ----------
    stress : float or array
        The element's paper stress ``sigma_i`` [Pa], Eq. (8).
    spring : float or array
        The depth stress the bearing multiplies [Pa]: :func:`bearing_stress`, Eq. (4) at its depth times the
        bearing scale (not read where it carries no horizontal force).
    area : float or array
        [m^2].
    nx, ny, nz : float or array
        Its outward unit normal, world frame [-].
    depth : float or array
        [m], positive below the surface.
    sx, sy : float or array
        Its slip at the last step [m].
    mx, my : float or array
        Its horizontal displacement since the last step [m].
    per_dt : float
        ``1 / dt`` [1/s].
    started : bool
        Whether the foot has a last pose (after its first step).
    stiffness, sigma_y, lambda_, rho_m : float
        ``k`` [Pa/m], the yield stress [Pa], the drag factor [-], the mud's density [kg/m^3].

    Returns
    -------
    slip_x, slip_y, fx, fy, fz
        The slip kept [m] and the force [N], world frame.
    """
    vx, vy, fz = vertical_element_force(stress, area, nx, ny, nz)
    tx = sx + mx
    ty = sy + my
    square = tx * tx + ty * ty
    some = square > 0.0
    size = select(some, root(select(some, square, 1.0)), 0.0)
    per = 1.0 / select(some, size, 1.0)
    dx = tx * per
    dy = ty * per
    capacity = lateral_capacity(sigma_y, shear_fraction(nx, ny, nz, dx, dy), spring,
                                bearing_factor(nx, ny, nz, dx, dy))
    kx, ky, ax, ay = lateral_return_map(tx, ty, size, stiffness, capacity)
    gx, gy = horizontal_drag(lambda_, rho_m, nx, ny, mx * per_dt, my * per_dt)
    loaded = started & (depth > 0.0)
    return (select(loaded, kx, 0.0), select(loaded, ky, 0.0), select(loaded, (ax + gx) * area, 0.0) + vx,
            select(loaded, (ay + gy) * area, 0.0) + vy, fz)


@_law
def moment(ox: Array, oy: Array, oz: Array, fx: Array, fy: Array, fz: Array) -> tuple[Array, Array, Array]:
    """The moment ``o x f`` of an element's force about the body origin [N m]: the wrench is the sums.

    ``(ox, oy, oz)`` the element's world offset from the body origin [m]
    (:func:`rotate`), ``(fx, fy, fz)`` its force [N].
    """
    return oy * fz - oz * fy, oz * fx - ox * fz, ox * fy - oy * fx
