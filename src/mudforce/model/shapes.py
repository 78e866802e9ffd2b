"""Foot surfaces as elements: the surface of a sole, box, disc, sphere, capsule, cylinder, ellipsoid or mesh.

The 3-D mud model puts the paper's stress law on every surface element of a
foot. This module provides the elements; it computes no force.

What a shape is
---------------
A :class:`Shape` is a surface cut into ``n`` small patches (elements). Each
element ``i`` has

* ``centroids[i]`` [m]: the area centroid ``(1/A) ∫ x dA`` of the patch, in
  the body frame. On a curved patch it lies slightly inside the surface
  (a sphere's at a radius a little under ``r``); its ``z`` is the patch's
  mean height, so a stress linear in depth integrates exactly.
* ``normals[i]`` [-]: the outward unit vector along ``∫ n dA``, the
  direction of the net force of a uniform pressure on the patch (on a
  sphere, the radius through the centroid).
* ``areas[i]`` [m^2]: the patch's true area on the curved surface, so the
  total area is exact at any resolution (a sphere's is ``4 pi r^2``).

For a closed shape ``Σ areas·normals = 0`` up to rounding (the grids are
mirror-symmetric, so the axial component cancels exactly) and
``Σ areas (centroid·normal) / 3`` (the divergence theorem,
:attr:`Shape.volume`) converges to the enclosed volume as the resolution
is refined: exact for flat faces (box, mesh), second order in the element
size on curved ones (figures in docs/shapes.md).

The body frame
--------------
The frame MuJoCo gives a geom of the same kind, so that a shape from
:func:`from_mujoco_geom` is placed by ``data.geom_xpos`` and
``data.geom_xmat``:

* :func:`sphere`, :func:`ellipsoid`, :func:`box`: origin at the centre; a
  box's and an ellipsoid's ``length``, ``width``, ``height`` along x, y, z.
* :func:`capsule`, :func:`cylinder`, :func:`disc`: origin at the centre,
  axis along z. ``length`` is the length of the cylindrical part: for a
  capsule the distance between the two hemispheres' centres (MuJoCo's
  ``2 size[1]``; the capsule is ``length + diameter`` long overall), for a
  cylinder its full height (MuJoCo's ``2 size[1]``). A disc is a cylinder
  ``thickness`` high.
* :func:`sole`: the flat bottom face of a :class:`mudforce.model.foot.Foot`, the
  paper's foot (only the bottom face is loaded; a cuboid's sides are not).
  Origin at the face's centre, the face in the plane ``z = 0``, every normal
  ``(0, 0, -1)``; a rectangle's length along x and width along y. It is an
  open surface (:attr:`Shape.closed` is False).
* :func:`mesh`: the vertices' own frame. MuJoCo re-centres a mesh geom on the
  mesh's inertial frame (its centre of mass and principal axes) and stores
  ``model.mesh_vert`` in that frame, which is the geom's frame
  (``data.geom_xpos``, ``data.geom_xmat``): :func:`from_mujoco_geom` uses
  ``mesh_vert`` as it is.

Resolution
----------
Every constructor takes ``resolution`` [m]: the largest element edge
allowed, measured along the surface (an arc on a curved patch; for an
ellipsoid, a bound on it). Halving it roughly quadruples ``n``. The default
(``None``) is ``sqrt(total area / DEFAULT_ELEMENTS)`` (twice that for a
mesh, whose triangles are smaller than squares of the same edge): about
:data:`DEFAULT_ELEMENTS` elements of about equal size whatever the shape's
scale (somewhat more, 130 to 210, since each grid rounds its counts up). A resolution
is within :data:`mudforce.model.foot.SIZE_RANGE`, and a shape has at most
:data:`MAX_ELEMENTS` elements; beyond, a one-line :class:`InputError` names
a resolution that fits.

The grids: a sphere, each end of a capsule and an ellipsoid (through its
parametrisation ``(a sin t cos p, b sin t sin p, c cos t)`` about its
longest axis) are cut into latitude bands of equal meridian arc (equal
angles on a sphere), an even number of them so that the equator is an
edge, and each band into an even number (at least 4) of equal longitude
sectors, as many as keep the band's longer parallel within the
resolution; the southern half mirrors the northern. Cylinder sides are
``z x longitude`` grids, flat discs polar grids (rings of equal width,
sectors as above), box faces and rectangular soles grids of equal
rectangles. Elements are reasonably uniform: the largest has about 2 to 3
times the area of the smallest (1.2 on a box, 4.3 on a 5:1 ellipsoid).
Sphere, capsule, cylinder, disc, box and sole elements come from
closed-form integrals; an ellipsoid's areas and centroids from a composite
6 x 6 Gauss-Legendre rule per element (its normals in closed form): total
areas within 1e-13 for ordinary proportions, 1e-10 for a needle of aspect
ratio 100 (its quadrature capped at 5 million points).

Everything is deterministic: the same arguments give the same arrays, bit
for bit.

Meshes
------
:func:`mesh` takes a closed, outward-facing triangle mesh; each triangle
(subdivided into ``k^2`` equal triangles when an edge is longer than
``resolution``) is an element, its normal from the winding by the
right-hand rule. It refuses, each with a one-line :class:`InputError`
naming the face or edge: faces that are not an ``(m, 3)`` integer array,
indices out of range, non-finite vertices, zero-area faces, an open mesh
(an edge of one face only), a non-manifold edge (three faces or more),
inconsistent winding, a mesh that encloses no volume, an inward-facing
mesh (negative signed volume: "faces point inward; reverse their
winding"), and a separate shell facing inward outside the other shells
(one inside them, facing inward, is a cavity: taken).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mudforce._plumbing.optional import require
from mudforce.errors import InputError, holds_boolean, is_real, number_within, real_array, shown
from mudforce.model.foot import AREA_RANGE, SIZE_RANGE, Foot

__all__ = ["DEFAULT_ELEMENTS", "MAX_ELEMENTS", "Shape", "box", "capsule", "cylinder", "disc", "ellipsoid",
           "from_mujoco_geom", "mesh", "sole", "sphere"]

#: The default resolution is ``sqrt(total area / DEFAULT_ELEMENTS)`` [m]: about this many elements [-].
DEFAULT_ELEMENTS = 128
#: The most elements a shape may have [-]: memory and time per step stay bounded.
MAX_ELEMENTS = 100_000

_UNIT_TOL = 1e-9  # |normal| - 1 accepted in a Shape [-]
_CLOSED_TOL = 1e-9  # |Σ a n| / Σ a accepted for a closed Shape [-]
_DEGENERATE = 1e-12  # a mesh face with area < this x extent^2 is degenerate [-]
_FLAT = 1e-9  # a closed mesh with |volume| < this x extent^3 encloses nothing [-]
_GAUSS = 6  # Gauss-Legendre points per direction and panel in an ellipsoid element [-]
_PANEL = math.pi / 16  # the widest panel of that rule, on a sphere [rad]
_POINTS = 5_000_000  # the most quadrature points for one ellipsoid [-] (about 1 s)
_MERIDIAN = 16_384  # trapezoids along an ellipsoid's quarter meridian, for its band edges [-]
_CHUNK = 500_000  # quadrature points evaluated at once [-] (memory)

Float = NDArray[np.float64]
Elements = tuple[Float, Float, Float]  # centroids (n, 3) [m], normals (n, 3) [-], areas (n,) [m^2]
Counter = Callable[[float], int]  # a shape's number of elements at a resolution [m]


def _numbers(value: Any, what: str) -> Float:
    """``value`` as a new float64 array if it holds real numbers (real_array: not complex, booleans, strings or
    objects, which numpy would cut, read as 0 and 1, or parse), else InputError "``what`` ..., got <what it holds>"."""
    array: Float = np.array(real_array(value, what, "-", must=what), dtype=np.float64, copy=True)
    return array


def _readonly(value: Any, name: str, shape: tuple[int, ...]) -> Float:
    array = _numbers(value, f"shape {name} must be an array of numbers")
    if array.shape != shape:
        expected = "(n, 3)" if len(shape) == 2 else "(n,)"
        raise InputError(f"shape {name} must have shape {expected} with n = {shape[0]}, got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputError(f"shape {name} must be finite, got a non-finite value at row "
                         f"{int(np.argwhere(~np.isfinite(array))[0][0])}")
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False, repr=False)
class Shape:
    """A foot's surface as ``n`` elements, in the body frame (module docstring: frames and conventions).

    Parameters
    ----------
    centroids : array_like, (n, 3)
        Each element's area centroid ``(1/A) ∫ x dA`` [m], body frame.
    normals : array_like, (n, 3)
        Each element's outward unit normal, along ``∫ n dA`` [-]; unit within 1e-9.
    areas : array_like, (n,)
        Each element's true (curved-surface) area [m^2], > 0.
    name : str
        What the shape is, for display (``"sphere 40 mm, 180 elements"``).
    closed : bool
        Whether the elements tile a closed surface (then ``|Σ areas·normals|``
        must be below 1e-9 of the total area); the sole is open.
    width : float or None
        The intruder width ``H`` of Eq. (4) [m] that the 3-D law uses for
        this foot, within :data:`mudforce.model.foot.SIZE_RANGE`: the constructors
        set the shorter horizontal side of the body frame (a sole's ``H``, a
        box's shorter of length and width, a sphere's, capsule's,
        cylinder's or disc's diameter, a mesh's shorter x or y extent);
        None for a shape built from arrays (give it, or give the contact one).

    The arrays are stored as read-only float64 copies; ``1 <= n <=``
    :data:`MAX_ELEMENTS`. Two shapes compare equal only if they are the
    same object (compare the arrays to compare geometry).
    """

    centroids: Float
    normals: Float
    areas: Float
    name: str = "custom"
    closed: bool = field(default=False)
    width: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise InputError(f"shape name must be a str, got {type(self.name).__name__}")
        if not isinstance(self.closed, (bool, np.bool_)):
            raise InputError(f"shape closed must be True or False, got {shown(self.closed)}")
        try:
            n = len(self.areas) if np.ndim(self.areas) == 1 else -1
        except (TypeError, ValueError):
            n = -1
        if n < 0:
            raise InputError(f"shape areas must be a 1-d array (n,) [m^2], got {type(self.areas).__name__}")
        if not 1 <= n <= MAX_ELEMENTS:
            raise InputError(f"a shape must have 1 to {MAX_ELEMENTS} elements, got {n}")
        areas = _readonly(self.areas, "areas", (n,))
        centroids = _readonly(self.centroids, "centroids", (n, 3))
        normals = _readonly(self.normals, "normals", (n, 3))
        if not np.all(areas > 0.0):
            raise InputError(f"shape areas must be > 0 [m^2], got {float(areas[np.argmin(areas)])!r} "
                             f"at element {int(np.argmin(areas))}")
        if not np.all(areas <= AREA_RANGE[1]):  # a foot's largest area (Foot), so each element's force stays finite
            raise InputError(f"shape areas must be at most {AREA_RANGE[1]:g} m^2 each, got "
                             f"{float(areas[np.argmax(areas)])!r} at element {int(np.argmax(areas))}")
        reach = np.sqrt(np.einsum("ij,ij->i", centroids, centroids))
        if not np.all(reach <= SIZE_RANGE[1]):  # a foot's largest size (Foot): its moments stay finite
            i = int(np.argmax(reach))
            raise InputError(f"shape centroids must be within {SIZE_RANGE[1]:g} m of the body origin [m], got "
                             f"{reach[i]:.6g} m at element {i}")
        length = np.sqrt(np.einsum("ij,ij->i", normals, normals))
        bad = np.abs(length - 1.0) > _UNIT_TOL
        if np.any(bad):
            i = int(np.argmax(bad))
            raise InputError(f"shape normals must be unit vectors, got length {length[i]:.12g} at element {i}")
        closed = bool(self.closed)
        if closed:
            net = float(np.linalg.norm(areas @ normals))
            total = math.fsum(areas)
            if net > _CLOSED_TOL * total:
                raise InputError(f"a closed shape has Σ areas·normals = 0; got |Σ a n| = {net:.3g} m^2 "
                                 f"for a total area {total:.3g} m^2 (pass closed=False for an open surface)")
        object.__setattr__(self, "areas", areas)
        object.__setattr__(self, "centroids", centroids)
        object.__setattr__(self, "normals", normals)
        object.__setattr__(self, "closed", closed)
        if self.width is not None:
            object.__setattr__(self, "width", number_within(self.width, "shape width", *SIZE_RANGE, "m"))

    def __repr__(self) -> str:
        return f"Shape({self.name!r}, n={self.n}, {'closed' if self.closed else 'open'})"

    @property
    def n(self) -> int:
        """The number of elements [-]."""
        return int(self.areas.shape[0])

    @property
    def total_area(self) -> float:
        """The surface's area Σ areas [m^2] (an exactly rounded sum)."""
        return math.fsum(self.areas.tolist())

    @property
    def vector_area(self) -> Float:
        """Σ areas·normals [m^2], shape (3,): zero for a closed shape; ``(0, 0, -S)`` for a sole of area ``S``."""
        out: Float = self.areas @ self.normals
        return out

    @property
    def volume(self) -> float:
        """The enclosed volume by the divergence theorem, Σ areas (centroid·normal) / 3 [m^3]; NaN if open.

        Exact for flat elements (box, mesh); on curved surfaces it converges
        to the true volume, second order in the element size.
        """
        if not self.closed:
            return math.nan
        return math.fsum((self.areas * np.einsum("ij,ij->i", self.centroids, self.normals)).tolist()) / 3.0

    @property
    def bounds(self) -> Float:
        """The box around the element centroids [m], shape (2, 3): row 0 the minima, row 1 the maxima of x, y, z.

        ``bounds[0, 2]`` is the lowest centroid in the body frame; it lies
        within an element's size of the true surface's lowest point.
        """
        out = np.stack([self.centroids.min(axis=0), self.centroids.max(axis=0)])
        out.setflags(write=False)
        return out


# ----------------------------------------------------------------------------------------------- checks and counts

def _size(value: Any, name: str) -> float:
    return number_within(value, name, *SIZE_RANGE, "m")


def _resolution(resolution: Any, total_area: float, extent: float, label: str, elements: Counter) -> float:
    """The resolution [m]: the caller's, checked, or the default for ``total_area`` [m^2].

    ``extent`` [m] is the shape's largest dimension: a grid with more than
    MAX_ELEMENTS rows along it is refused before any array is made;
    ``elements`` counts the shape's elements at a resolution (for the one the message suggests).
    """
    if resolution is None:
        return math.sqrt(total_area / DEFAULT_ELEMENTS)
    res = number_within(resolution, f"{label} resolution", *SIZE_RANGE, "m")
    if extent / res > MAX_ELEMENTS:
        _too_many(label, res, None, total_area, elements)
    return res


def _too_many(label: str, res: float, count: int | None, total_area: float, elements: Counter) -> None:
    # n grows as 1/resolution^2: aim at 80% of the cap (or, count unknown, at the area's share of it)
    guess = res * math.sqrt(count / (0.8 * MAX_ELEMENTS)) if count else math.sqrt(total_area / MAX_ELEMENTS) * 1.5
    got = f"{count} elements" if count is not None else "too many elements"
    raise InputError(f"{label} at resolution {res * 1e3:g} mm would have {got}, more than the {MAX_ELEMENTS} "
                     f"allowed; use a coarser resolution, e.g. {_fitting(guess, elements) * 1e3:.3g} mm")


def _fitting(guess: float, elements: Counter) -> float:
    """The first resolution [m] from ``guess`` up (in steps of 10 %, as the message shows it: three digits in mm)
    within SIZE_RANGE at which the shape has at most MAX_ELEMENTS ``elements``: the guess assumes a count that grows
    as 1/resolution^2, and a long thin shape's grows as 1/resolution only."""
    res = max(guess, SIZE_RANGE[0])
    while res <= SIZE_RANGE[1]:
        shown_res = float(f"{res * 1e3:.3g}") * 1e-3
        if SIZE_RANGE[0] <= shown_res <= SIZE_RANGE[1] and elements(shown_res) <= MAX_ELEMENTS:
            return shown_res
        res *= 1.1
    return SIZE_RANGE[1]


def _check_count(count: int, label: str, res: float, total_area: float, elements: Counter) -> None:
    if count > MAX_ELEMENTS:
        _too_many(label, res, count, total_area, elements)


def _count(n: float) -> int:
    """ceil(n) as an int, at least 1."""
    return max(1, math.ceil(n))


def _mm(value: float) -> str:
    return f"{value * 1e3:g}"


def _shape(elements: Elements, name: str, closed: bool, width: float) -> Shape:
    centroids, normals, areas = elements
    return Shape(centroids, normals, areas, name=f"{name}, {areas.shape[0]} elements", closed=closed, width=width)


def _join(*parts: Elements) -> Elements:
    return (np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
            np.concatenate([p[2] for p in parts]))


def _mirror_z(elements: Elements, shift: float = 0.0) -> tuple[Elements, Elements]:
    """``elements`` moved up by ``shift`` [m], and their mirror image in ``z = 0`` moved down by it."""
    centroids, normals, areas = elements
    flip = np.array([1.0, 1.0, -1.0])
    up = centroids + np.array([0.0, 0.0, shift])
    return (up, normals, areas), (up * flip, normals * flip, areas.copy())


# ----------------------------------------------------------------------------------------------------- the grids

def _x_minus_sin(x: Float) -> Float:
    """``x - sin(x)`` without cancellation for small ``x`` (Taylor series below 0.1)."""
    small = x < 0.1
    x2 = x * x
    series = x * x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0)))
    out: Float = np.where(small, series, x - np.sin(x))
    return out


def _bands(polar: float, equatorial: float, res: float) -> tuple[Float, NDArray[np.int64]]:
    """The northern hemisphere's bands: polar-angle edges (h+1,) [rad] and sectors per band (h,) [-].

    The meridian ``(equatorial sin t, polar cos t)`` [m] is cut into ``h``
    arcs of equal length, each within ``res`` [m] (equal angles on a sphere,
    ``polar == equatorial``); ``equatorial`` [m] times ``sin(t)`` bounds the
    parallels' radius, and each band has as many sectors as keep its longer
    parallel's arcs within ``res``.
    """
    if polar == equatorial:
        h = _count(0.5 * math.pi * polar / res)
        theta = np.linspace(0.0, 0.5 * math.pi, h + 1)
    else:
        t = np.linspace(0.0, 0.5 * math.pi, _MERIDIAN + 1)
        speed = np.hypot(equatorial * np.cos(t), polar * np.sin(t))
        arc = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
        h = _count(arc[-1] * (1.0 + 1e-4) / res)  # the margin covers the trapezoid rule's error
        theta = np.interp(np.linspace(0.0, arc[-1], h + 1), arc, t)
        theta[0], theta[-1] = 0.0, 0.5 * math.pi
    return theta, _sectors(equatorial * np.sin(theta[1:]), res)


def _sectors(radius: Float | float, res: float) -> NDArray[np.int64]:
    """Sectors in a ring of ``radius`` [m]: the fewest that keep its arcs within ``res`` [m], even and >= 4.

    An even count makes every grid symmetric under ``x -> -x`` as well as
    ``y -> -y``, so a symmetric shape's elements are symmetric too.
    """
    return np.maximum(2, np.ceil(np.pi * np.asarray(radius, dtype=np.float64) / res)).astype(np.int64) * 2


def _cells(edges: Float, sectors: NDArray[np.int64]) -> tuple[Float, Float, Float, Float]:
    """Each cell of a (band x sector) grid: lower and upper band edge, start angle and width of its sector.

    ``edges`` (h+1,) are the band edges; band ``j`` has ``sectors[j]`` equal
    sectors in [0, 2 pi). Returns four (Σ sectors,) arrays.
    """
    band = np.repeat(np.arange(sectors.shape[0]), sectors)
    first = np.repeat(np.cumsum(sectors) - sectors, sectors)
    k = np.arange(band.shape[0]) - first
    width = 2.0 * math.pi / sectors[band]
    return edges[band], edges[band + 1], k * width, width


def _sphere_north(r: float, theta: Float, sectors: NDArray[np.int64]) -> Elements:
    """The northern hemisphere of a sphere of radius ``r`` [m], in closed form."""
    t1, t2, p1, dp = _cells(theta, sectors)
    tm, dt = 0.5 * (t1 + t2), t2 - t1
    pm, half = p1 + 0.5 * dp, np.sin(0.5 * dp)
    areas = r * r * 2.0 * np.sin(tm) * np.sin(0.5 * dt) * dp
    # ∫ sin^2 t dt = (dt - cos(2 tm) sin dt) / 2 = ((dt - sin dt) + 2 sin^2(tm) sin dt) / 2
    i_ss = 0.5 * (_x_minus_sin(dt) + 2.0 * np.sin(tm) ** 2 * np.sin(dt))
    i_sc = 0.5 * np.sin(2.0 * tm) * np.sin(dt)  # ∫ sin t cos t dt
    moment = r**3 * np.stack([i_ss * 2.0 * np.cos(pm) * half, i_ss * 2.0 * np.sin(pm) * half, i_sc * dp], axis=1)
    centroids = moment / areas[:, None]
    normals = centroids / np.linalg.norm(centroids, axis=1)[:, None]
    return centroids, normals, areas


def _ellipsoid_north(a: float, b: float, c: float, theta: Float, sectors: NDArray[np.int64]) -> Elements:
    """The northern half of the ellipsoid with semi-axes ``a, b, c`` [m] along x, y, z.

    Areas and centroids by a composite Gauss-Legendre rule per element on
    the parametrisation ``(a sin t cos p, b sin t sin p, c cos t)``
    (:func:`_rule`); normals from the closed form of
    ``∫ n dA = ∫∫ x_t × x_p dt dp``.
    """
    t1, t2, p1, dp = _cells(theta, sectors)
    tm, dt = 0.5 * (t1 + t2), t2 - t1
    pm, half = p1 + 0.5 * dp, np.sin(0.5 * dp)
    panel = _PANEL * min(1.0, 4.0 * min(a, b, c) / max(a, b, c))
    (ut, wt), (up, wp) = _rule(float(dt.max()), float(dp.max()), panel, t1.shape[0])
    areas = np.empty_like(t1)
    moment = np.empty((t1.shape[0], 3))
    chunk = max(1, _CHUNK // (ut.shape[0] * up.shape[0]))
    for lo in range(0, t1.shape[0], chunk):
        s = slice(lo, lo + chunk)
        t = t1[s, None, None] + dt[s, None, None] * ut[None, :, None]
        p = p1[s, None, None] + dp[s, None, None] * up[None, None, :]
        w = (dt[s] * dp[s])[:, None, None] * wt[None, :, None] * wp[None, None, :]
        st, ct, sp, cp = np.sin(t), np.cos(t), np.sin(p), np.cos(p)
        da = w * st * np.sqrt((b * c * st * cp) ** 2 + (a * c * st * sp) ** 2 + (a * b * ct) ** 2)
        areas[s] = da.sum(axis=(1, 2))
        moment[s, 0] = (da * (a * st * cp)).sum(axis=(1, 2))
        moment[s, 1] = (da * (b * st * sp)).sum(axis=(1, 2))
        moment[s, 2] = (da * (c * ct)).sum(axis=(1, 2))
    centroids = moment / areas[:, None]
    i_ss = 0.5 * (_x_minus_sin(dt) + 2.0 * np.sin(tm) ** 2 * np.sin(dt))
    i_sc = 0.5 * np.sin(2.0 * tm) * np.sin(dt)
    vector = np.stack([b * c * i_ss * 2.0 * np.cos(pm) * half, a * c * i_ss * 2.0 * np.sin(pm) * half,
                       a * b * i_sc * dp], axis=1)
    normals = vector / np.linalg.norm(vector, axis=1)[:, None]
    return centroids, normals, areas


def _rule(dt: float, dp: float, panel: float, cells: int) -> tuple[tuple[Float, Float], tuple[Float, Float]]:
    """Nodes and weights on [0, 1] in t and in p for elements up to ``dt`` x ``dp`` [rad].

    ``_GAUSS`` points on each of ``ceil(span / panel)`` equal panels per
    direction (``panel`` [rad] narrower on elongated ellipsoids, whose
    area element varies faster), so that coarse grids' wide elements are
    integrated as accurately as fine grids' narrow ones; the panels are
    reduced, evenly, where ``cells`` [-] elements would need more than
    ``_POINTS`` points in all.
    """
    nt, np_ = max(1, math.ceil(dt / panel)), max(1, math.ceil(dp / panel))
    excess = cells * nt * np_ * _GAUSS**2 / _POINTS
    if excess > 1.0:
        nt, np_ = max(1, int(nt / math.sqrt(excess))), max(1, int(np_ / math.sqrt(excess)))
    nodes, weights = np.polynomial.legendre.leggauss(_GAUSS)

    def composite(panels: int) -> tuple[Float, Float]:
        starts = np.arange(panels)[:, None] / panels
        return (starts + 0.5 * (nodes[None, :] + 1.0) / panels).ravel(), np.tile(0.5 * weights / panels, panels)

    return composite(nt), composite(np_)


def _side(r: float, length: float, res: float) -> Elements:
    """The side of a cylinder of radius ``r`` [m] from ``z = -length/2`` to ``length/2`` [m], axis z."""
    rows = _count(length / res)
    m = int(_sectors(r, res))
    z = np.linspace(-0.5 * length, 0.5 * length, rows + 1)
    zm = np.repeat(0.5 * (z[:-1] + z[1:]), m)
    dz = np.repeat(np.diff(z), m)
    dp = 2.0 * math.pi / m
    pm = np.tile((np.arange(m) + 0.5) * dp, rows)
    shrink = math.sin(0.5 * dp) / (0.5 * dp)  # the arc's centroid: r sin(dp/2) / (dp/2)
    centroids = np.stack([r * shrink * np.cos(pm), r * shrink * np.sin(pm), zm], axis=1)
    normals = np.stack([np.cos(pm), np.sin(pm), np.zeros_like(pm)], axis=1)
    return centroids, normals, r * dp * dz


def _polar(r: float, z: float, up: bool, res: float) -> Elements:
    """A flat disc of radius ``r`` [m] in the plane at height ``z`` [m]; normals +z if ``up`` else -z."""
    rings = _count(r / res)
    rho = np.linspace(0.0, r, rings + 1)
    sectors = _sectors(rho[1:], res)
    r1, r2, p1, dp = _cells(rho, sectors)
    areas = 0.5 * (r2 - r1) * (r2 + r1) * dp
    pm, half = p1 + 0.5 * dp, np.sin(0.5 * dp)
    radial = (r2**3 - r1**3) / 3.0 * 2.0 * half / areas  # ∫ rho^2 drho (sin p2 - sin p1) / A, rotated
    centroids = np.stack([radial * np.cos(pm), radial * np.sin(pm), np.full_like(pm, z)], axis=1)
    normals = np.zeros_like(centroids)
    normals[:, 2] = 1.0 if up else -1.0
    return centroids, normals, areas


def _polar_count(r: float, res: float) -> int:
    rings = _count(r / res)
    rho = np.linspace(0.0, r, rings + 1)
    return int(_sectors(rho[1:], res).sum())


def _rectangle(u: float, v: float, res: float, axes: tuple[int, int, int], offset: float, sign: float) -> Elements:
    """A ``u x v`` [m] rectangle centred on an axis, gridded within ``res`` [m].

    ``axes`` = (axis along u, axis along v, normal axis); the face lies at
    ``offset`` [m] along the normal axis, its normal ``sign`` (±1) along it.
    """
    nu, nv = _count(u / res), _count(v / res)
    cu = (np.arange(nu) + 0.5) * (u / nu) - 0.5 * u
    cv = (np.arange(nv) + 0.5) * (v / nv) - 0.5 * v
    gu, gv = np.meshgrid(cu, cv, indexing="ij")
    centroids = np.zeros((nu * nv, 3))
    centroids[:, axes[0]] = gu.ravel()
    centroids[:, axes[1]] = gv.ravel()
    centroids[:, axes[2]] = offset
    normals = np.zeros_like(centroids)
    normals[:, axes[2]] = sign
    return centroids, normals, np.full(nu * nv, (u / nu) * (v / nv))


# --------------------------------------------------------------------------------------------------- constructors

def sole(foot: Foot, *, resolution: float | None = None) -> Shape:
    """The flat bottom face of ``foot``: the surface the paper loads (an open shape).

    Parameters
    ----------
    foot : Foot
        A cuboid foot gives a rectangle ``S/H`` long (x) and ``H`` wide (y);
        a disc foot (``Foot.disc``: ``shape`` starts with ``"disc"`` and
        ``S = pi H^2 / 4``) a disc of diameter ``H``; any other foot the
        rectangle ``S/H x H`` with its area ``S`` and width ``H`` [m].
    resolution : float or None
        The largest element edge [m], within :data:`mudforce.model.foot.SIZE_RANGE`;
        None: ``sqrt(S / DEFAULT_ELEMENTS)``.

    Returns
    -------
    Shape
        Elements in the plane ``z = 0`` of a frame centred on the face, every
        normal ``(0, 0, -1)``; the areas are scaled so that their total is
        ``foot.area`` [m^2] to rounding.
    """
    if not isinstance(foot, Foot):
        raise InputError(f"sole needs a mudforce.model.foot.Foot, got {type(foot).__name__}")
    area, width = foot.area, foot.width
    is_disc = foot.shape.lower().startswith("disc") and math.isclose(area, math.pi * width**2 / 4.0, rel_tol=1e-9)
    length = area / width
    label = f"the sole of {foot.shape}"

    def elements(step: float) -> int:
        return _polar_count(0.5 * width, step) if is_disc else _count(length / step) * _count(width / step)

    # the corner elements' centroids lie at least L/2 (1 - 1/ceil(L/10 m)) from the centre (at a resolution of 10 m)
    nearest = 0.5 * length * (1.0 - 1.0 / _count(length / SIZE_RANGE[1]))
    if nearest > SIZE_RANGE[1] * (1.0 + 1e-9):  # (the margin: Shape's own check decides at the bound)
        raise InputError(f"{label} is {length:.4g} m long (its area {area:g} m^2 over its width {width:g} m): its "
                         f"elements would lie {nearest:.4g} m or more from its centre at any resolution, more than the "
                         f"{SIZE_RANGE[1]:g} m a shape allows; expected a foot's area in m^2 and width in m")
    res = _resolution(resolution, area, max(length, width), label, elements)
    _check_count(elements(res), label, res, area, elements)
    if is_disc:
        centroids, normals, areas = _polar(0.5 * width, 0.0, False, res)
    else:
        centroids, normals, areas = _rectangle(length, width, res, (0, 1, 2), 0.0, -1.0)
    areas = areas * (area / math.fsum(areas.tolist()))
    return _shape((centroids, normals, areas), f"sole of {foot.shape}", closed=False, width=width)


def box(length: float, width: float, height: float, *, resolution: float | None = None) -> Shape:
    """The closed surface of a box: six faces, each a grid of equal rectangles.

    Parameters
    ----------
    length, width, height : float
        The box's sides along x, y, z [m] (MuJoCo's ``2 size``), each within
        :data:`mudforce.model.foot.SIZE_RANGE`; centred on the origin.
    resolution : float or None
        The largest element edge [m]; None: ``sqrt(area / DEFAULT_ELEMENTS)``.
    """
    x, y, z = _size(length, "box length"), _size(width, "box width"), _size(height, "box height")
    label = f"box {_mm(x)}x{_mm(y)}x{_mm(z)} mm"
    total = 2.0 * (x * y + x * z + y * z)

    def elements(step: float) -> int:
        nx, ny, nz = _count(x / step), _count(y / step), _count(z / step)
        return 2 * (nx * ny + nx * nz + ny * nz)

    res = _resolution(resolution, total, max(x, y, z), label, elements)
    _check_count(elements(res), label, res, total, elements)
    faces: list[Elements] = []
    for u, v, axes, offset in ((y, z, (1, 2, 0), 0.5 * x), (x, z, (0, 2, 1), 0.5 * y), (x, y, (0, 1, 2), 0.5 * z)):
        faces.append(_rectangle(u, v, res, axes, offset, 1.0))
        faces.append(_rectangle(u, v, res, axes, -offset, -1.0))
    return _shape(_join(*faces), label, closed=True, width=min(x, y))


def sphere(diameter: float, *, resolution: float | None = None) -> Shape:
    """The surface of a sphere centred on the origin, in equal-angle latitude bands.

    Parameters
    ----------
    diameter : float
        The sphere's diameter [m] (MuJoCo's ``2 size[0]``), within
        :data:`mudforce.model.foot.SIZE_RANGE`.
    resolution : float or None
        The largest element edge (arc) [m]; None: ``sqrt(pi d^2 / DEFAULT_ELEMENTS)``.

    Total area ``pi d^2`` exactly (to rounding) at any resolution.
    """
    d = _size(diameter, "sphere diameter")
    label = f"sphere {_mm(d)} mm"
    r = 0.5 * d
    total = math.pi * d * d

    def elements(step: float) -> int:
        return 2 * int(_bands(r, r, step)[1].sum())

    res = _resolution(resolution, total, d, label, elements)
    theta, sectors = _bands(r, r, res)
    _check_count(2 * int(sectors.sum()), label, res, total, elements)
    north, south = _mirror_z(_sphere_north(r, theta, sectors))
    return _shape(_join(north, south), label, closed=True, width=d)


def ellipsoid(length: float, width: float, height: float, *, resolution: float | None = None) -> Shape:
    """The surface of an ellipsoid centred on the origin, with its axes ``length, width, height`` along x, y, z.

    Parameters
    ----------
    length, width, height : float
        The ellipsoid's full axes (diameters) along x, y, z [m] (MuJoCo's
        ``2 size``), each within :data:`mudforce.model.foot.SIZE_RANGE`.
    resolution : float or None
        A bound on the largest element edge [m]: the grid of latitude bands
        about the longest axis, fine enough for the largest semi-axis along
        the meridians and the second largest along the parallels; None:
        ``sqrt(area / DEFAULT_ELEMENTS)``.

    The elements' areas and centroids come from a 6 x 6 Gauss-Legendre rule
    each, so the total area converges to the ellipsoid's exact area
    ``4 pi abc R_G(a^-2, b^-2, c^-2)`` far faster than the volume does.
    """
    x = _size(length, "ellipsoid length")
    y = _size(width, "ellipsoid width")
    z = _size(height, "ellipsoid height")
    label = f"ellipsoid {_mm(x)}x{_mm(y)}x{_mm(z)} mm"
    a, b, c = 0.5 * x, 0.5 * y, 0.5 * z
    total = _ellipsoid_area(a, b, c)
    # the grid's polar axis is the longest axis (z on a tie): the fewest elements for the resolution
    polar = 2 if c >= max(a, b) else (0 if a >= b else 1)
    order = [(polar + 1) % 3, (polar + 2) % 3, polar]  # a cyclic permutation: local (u, v, w) = axes[order]
    semi = [(a, b, c)[i] for i in order]

    def elements(step: float) -> int:
        return 2 * int(_bands(semi[2], max(semi[0], semi[1]), step)[1].sum())

    res = _resolution(resolution, total, max(x, y, z), label, elements)
    theta, sectors = _bands(semi[2], max(semi[0], semi[1]), res)  # the meridian through the longer other axis
    _check_count(2 * int(sectors.sum()), label, res, total, elements)
    north, south = _mirror_z(_ellipsoid_north(semi[0], semi[1], semi[2], theta, sectors))
    centroids, normals, areas = _join(north, south)
    back = np.argsort(order)  # column j of the body frame is local column back[j]
    return _shape((centroids[:, back], normals[:, back], areas), label, closed=True, width=min(x, y))


def _ellipsoid_area(a: float, b: float, c: float) -> float:
    """The area of the ellipsoid with semi-axes ``a, b, c`` [m]: ``4 pi abc R_G(a^-2, b^-2, c^-2)`` [m^2]."""
    from scipy.special import elliprg

    return float(4.0 * math.pi * a * b * c * elliprg(a**-2, b**-2, c**-2))


def capsule(diameter: float, length: float, *, resolution: float | None = None) -> Shape:
    """The surface of a capsule along z: a cylinder ``length`` long capped by two hemispheres.

    Parameters
    ----------
    diameter : float
        The capsule's diameter [m] (MuJoCo's ``2 size[0]``), within
        :data:`mudforce.model.foot.SIZE_RANGE`.
    length : float
        The cylindrical part's length: the distance between the hemispheres'
        centres [m] (MuJoCo's ``2 size[1]``), within [0, 10]; the capsule is
        ``length + diameter`` long overall. 0 gives a sphere.
    resolution : float or None
        The largest element edge [m]; None: ``sqrt(area / DEFAULT_ELEMENTS)``.

    Total area ``pi d^2 + pi d length`` to rounding.
    """
    d = _size(diameter, "capsule diameter")
    span = number_within(length, "capsule length", 0.0, SIZE_RANGE[1], "m") + 0.0  # -0.0 is a length of 0
    label = f"capsule {_mm(d)} mm, length {_mm(span)} mm"
    r = 0.5 * d
    total = math.pi * d * (d + span)

    def elements(step: float) -> int:
        side = _count(span / step) * int(_sectors(r, step)) if span > 0.0 else 0
        return 2 * int(_bands(r, r, step)[1].sum()) + side

    res = _resolution(resolution, total, d + span, label, elements)
    theta, sectors = _bands(r, r, res)
    _check_count(elements(res), label, res, total, elements)
    north, south = _mirror_z(_sphere_north(r, theta, sectors), 0.5 * span)
    parts = (north, _side(r, span, res), south) if span > 0.0 else (north, south)
    return _shape(_join(*parts), label, closed=True, width=d)


def _cylinder(d: float, height: float, res: float | None, label: str) -> Shape:
    r = 0.5 * d
    total = 0.5 * math.pi * d * d + math.pi * d * height

    def elements(size: float) -> int:
        return 2 * _polar_count(r, size) + _count(height / size) * int(_sectors(r, size))

    step = _resolution(res, total, max(d, height), label, elements)
    _check_count(elements(step), label, step, total, elements)
    top = _polar(r, 0.5 * height, True, step)
    bottom = _polar(r, -0.5 * height, False, step)
    return _shape(_join(top, _side(r, height, step), bottom), label, closed=True, width=d)


def cylinder(diameter: float, length: float, *, resolution: float | None = None) -> Shape:
    """The closed surface of a cylinder along z: side and two flat ends.

    Parameters
    ----------
    diameter : float
        The cylinder's diameter [m] (MuJoCo's ``2 size[0]``), within
        :data:`mudforce.model.foot.SIZE_RANGE`.
    length : float
        Its full height along z [m] (MuJoCo's ``2 size[1]``), within
        :data:`mudforce.model.foot.SIZE_RANGE`; the ends lie at ``z = ±length/2``.
    resolution : float or None
        The largest element edge [m]; None: ``sqrt(area / DEFAULT_ELEMENTS)``.

    Total area ``pi d^2 / 2 + pi d length`` to rounding.
    """
    d = _size(diameter, "cylinder diameter")
    height = _size(length, "cylinder length")
    return _cylinder(d, height, resolution, f"cylinder {_mm(d)} mm, length {_mm(height)} mm")


def disc(diameter: float, thickness: float, *, resolution: float | None = None) -> Shape:
    """The closed surface of a disc: a cylinder ``thickness`` high along z (bottom, rim and top).

    Parameters
    ----------
    diameter : float
        The disc's diameter [m], within :data:`mudforce.model.foot.SIZE_RANGE`.
    thickness : float
        Its height along z [m], within :data:`mudforce.model.foot.SIZE_RANGE`; the
        faces lie at ``z = ±thickness/2``.
    resolution : float or None
        The largest element edge [m]; None: ``sqrt(area / DEFAULT_ELEMENTS)``.
    """
    d = _size(diameter, "disc diameter")
    t = _size(thickness, "disc thickness")
    return _cylinder(d, t, resolution, f"disc {_mm(d)} mm, thickness {_mm(t)} mm")


# ---------------------------------------------------------------------------------------------------------- mesh

def _mesh_arrays(vertices: Any, faces: Any) -> tuple[Float, NDArray[np.int64]]:
    """The checked vertices (k, 3) [m] and faces (m, 3) of a mesh, or InputError."""
    verts = _numbers(vertices, "mesh vertices must be an array (k, 3) of numbers [m]")
    if verts.ndim != 2 or verts.shape[1] != 3 or verts.shape[0] < 4:
        raise InputError(f"mesh vertices must be an array (k, 3) [m] with k >= 4, got shape {verts.shape}")
    try:
        tris = np.asarray(faces)
    except (TypeError, ValueError):  # ragged rows
        raise InputError(f"mesh faces must be an integer array (m, 3) of vertex indices with m >= 4, got "
                         f"{type(faces).__name__} that is not an array (rows of different lengths?)") from None
    if tris.dtype.kind not in "iu" or tris.ndim != 2 or tris.shape[1] != 3 or tris.shape[0] < 4:
        raise InputError(f"mesh faces must be an integer array (m, 3) of vertex indices with m >= 4, "
                         f"got {tris.dtype} array of shape {tris.shape}")
    if not isinstance(faces, np.ndarray) and holds_boolean(faces):  # numpy reads [0, True, 2] as [0, 1, 2]
        raise InputError("mesh faces must be an integer array (m, 3) of vertex indices, got a sequence holding "
                         "booleans (True/False among the indices)")
    if tris.shape[0] > MAX_ELEMENTS:
        raise InputError(f"a mesh may have at most {MAX_ELEMENTS} faces, got {tris.shape[0]}")
    out_of_range = (tris < 0) | (tris >= verts.shape[0])
    if np.any(out_of_range):
        f, j = (int(i) for i in np.argwhere(out_of_range)[0])
        raise InputError(f"mesh face {f} has vertex index {int(tris[f, j])}, expected 0 to {verts.shape[0] - 1}")
    tris = tris.astype(np.int64)
    used = np.unique(tris)
    bad = ~np.all(np.isfinite(verts[used]), axis=1)
    if np.any(bad):
        i = int(used[np.argmax(bad)])
        raise InputError(f"mesh vertex {i} is not finite: {verts[i].tolist()}")
    limit = SIZE_RANGE[1]
    far = np.max(np.abs(verts[used]), axis=1) > limit
    if np.any(far):
        raise InputError(f"mesh vertex {int(used[np.argmax(far)])} is {verts[used[np.argmax(far)]].tolist()} m, "
                         f"expected coordinates within ±{limit:g} m of the body frame's origin")
    extent = float(np.max(np.ptp(verts[used], axis=0)))
    if not SIZE_RANGE[0] <= extent:
        raise InputError(f"a mesh must be at least {SIZE_RANGE[0]:g} m across, got {extent:.3g} m")
    repeat = (tris[:, 0] == tris[:, 1]) | (tris[:, 1] == tris[:, 2]) | (tris[:, 0] == tris[:, 2])
    if np.any(repeat):
        f = int(np.argmax(repeat))
        raise InputError(f"mesh face {f} {tris[f].tolist()} repeats a vertex: it has zero area; "
                         f"expected three distinct vertices")
    return verts, tris


def _coincident(verts: NDArray[np.float64], used: NDArray[np.int64]) -> tuple[int, int] | None:
    """The first two of the ``used`` vertices at exactly the same point (the lowest indices), or None."""
    _, first, inverse = np.unique(verts[used], axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    repeated = np.flatnonzero(first[inverse] != np.arange(used.size))
    if not repeated.size:
        return None
    k = int(repeated[0])  # used is sorted, so the first repeat found names the lowest pair
    return int(used[first[inverse[k]]]), int(used[k])


def _check_closed(tris: NDArray[np.int64]) -> None:
    """InputError unless every edge of ``tris`` is shared by exactly two faces with opposite directions."""
    m = tris.shape[0]
    start = tris.ravel()
    end = tris[:, [1, 2, 0]].ravel()
    face = np.repeat(np.arange(m), 3)
    lo, hi = np.minimum(start, end), np.maximum(start, end)
    order = np.lexsort((face, hi, lo))
    lo, hi, start, face = lo[order], hi[order], start[order], face[order]
    new = np.ones(lo.shape[0], dtype=bool)
    new[1:] = (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1])
    first = np.flatnonzero(new)
    uses = np.diff(np.append(first, lo.shape[0]))
    if np.any(uses == 1):
        e = first[np.argmax(uses == 1)]
        raise InputError(f"mesh edge ({lo[e]}, {hi[e]}) belongs to face {face[e]} only: the mesh is open; "
                         f"expected a closed surface (every edge shared by two faces)")
    if np.any(uses > 2):
        i = int(np.argmax(uses > 2))
        e = first[i]
        faces = ", ".join(str(f) for f in face[e:e + uses[i]])
        raise InputError(f"mesh edge ({lo[e]}, {hi[e]}) is shared by {uses[i]} faces ({faces}): the mesh is "
                         f"not manifold; expected every edge shared by exactly two faces")
    same = start[first] == start[first + 1]
    if np.any(same):
        e = first[np.argmax(same)]
        a, b = (lo[e], hi[e]) if start[e] == lo[e] else (hi[e], lo[e])
        raise InputError(f"mesh faces {face[e]} and {face[e + 1]} both run edge {a} -> {b}: inconsistent "
                         f"winding; expected each edge run once each way (reverse one of them)")


def _check_shells(verts: Float, tris: NDArray[np.int64], signed: Float, extent: float) -> None:
    """InputError if a separate shell of the mesh faces inward (negative signed volume) outside the rest of it.

    ``signed`` (m,) is each face's ``v0 . (v1 - v0) x (v2 - v0)`` [m^3] (six times its share of the volume). A
    shell (faces joined through their vertices) with a negative volume is a cavity when it lies inside the other
    shells (their winding number at one of its vertices is 1); outside them (winding number 0) it is a solid
    whose faces point inward.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    k = verts.shape[0]
    graph = coo_matrix((np.ones(2 * tris.shape[0]), (tris[:, :2].ravel(), tris[:, 1:].ravel())), shape=(k, k))
    label = connected_components(graph, directed=False)[1]
    shell = label[tris[:, 0]]
    names, shell = np.unique(shell, return_inverse=True)
    if names.size == 1:  # one shell: its volume is the mesh's, checked already
        return
    volume = np.bincount(shell, weights=signed) / 6.0
    for s in np.flatnonzero(volume < -_FLAT * extent**3):
        mine = shell == s
        rest = tris[~mine]
        point = verts[tris[np.argmax(mine), 0]]
        a, b, c = (verts[rest[:, i]] - point for i in range(3))  # each triangle's solid angle (Van Oosterom)
        la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
        numerator = np.einsum("ij,ij->i", a, np.cross(b, c))
        denominator = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb
                       + np.einsum("ij,ij->i", b, c) * la)
        winding = 2.0 * math.fsum(np.arctan2(numerator, denominator).tolist()) / (4.0 * math.pi)
        if winding < 0.5:
            first = int(np.argmax(mine))
            raise InputError(f"the mesh's shell of {int(mine.sum())} faces from face {first} points inward (its "
                             f"signed volume is {volume[s]:.3g} m^3 < 0) and lies outside the solid the other shells "
                             "enclose, so it is no cavity; reverse the winding of its faces")


def mesh(vertices: Any, faces: Any, *, resolution: float | None = None) -> Shape:
    """A closed, outward-facing triangle mesh: each triangle an element (subdivided to meet ``resolution``).

    Parameters
    ----------
    vertices : array_like, (k, 3)
        Vertex positions in the body frame [m]: finite, within ±10 m of the
        origin, the mesh 1e-4 m to 10 m across. Vertices no face uses are
        ignored.
    faces : array_like of int, (m, 3)
        Triangles as vertex indices, wound counter-clockwise seen from
        outside (right-hand rule: the normal points out); 4 to
        :data:`MAX_ELEMENTS` of them.
    resolution : float or None
        The largest element edge [m]: a triangle whose longest edge is
        ``e`` is cut into ``k^2`` equal triangles, ``k = ceil(e / resolution)``;
        None: ``2 sqrt(area / DEFAULT_ELEMENTS)`` (triangles are smaller than
        squares of the same edge: about as many elements as the other shapes').

    Raises
    ------
    InputError
        One line naming the face or edge, for: faces not an (m, 3) integer
        array, an index out of range, a non-finite vertex, a zero-area face,
        an open mesh (an edge of one face only), a non-manifold edge
        (three faces or more), inconsistent winding (two faces running an
        edge the same way), two vertices at the same point (a mesh not
        welded, or shells that overlay or touch), a mesh enclosing no volume,
        a mesh whose faces point inward (negative signed volume), a separate
        shell whose faces point inward outside the other shells (inside them it
        is a cavity, and taken), or too many elements.
    """
    verts, tris = _mesh_arrays(vertices, faces)
    used = np.unique(tris)
    extent = float(np.max(np.ptp(verts[used], axis=0)))
    v0, v1, v2 = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    cross = np.cross(v1 - v0, v2 - v0)
    doubled = np.linalg.norm(cross, axis=1)
    flat = doubled < 2.0 * _DEGENERATE * extent**2
    if np.any(flat):
        f = int(np.argmax(flat))
        raise InputError(f"mesh face {f} {tris[f].tolist()} has zero area ({0.5 * doubled[f]:.3g} m^2): "
                         f"its vertices are collinear; expected a proper triangle")
    twins = _coincident(verts, used)
    try:
        _check_closed(tris)
    except InputError as error:
        if twins is None:
            raise
        i, j = twins  # an open edge between faces that share a point but not its vertex: the mesh is not welded
        raise InputError(f"{error}; its vertices {i} and {j} are the same point: merge repeated vertices "
                         "(weld the mesh) first") from None
    if twins is not None:
        i, j = twins
        raise InputError(f"mesh vertices {i} and {j} are the same point {verts[i].tolist()} m though no edge joins "
                         "them: the surface overlays or touches itself (two shells, or one pinched); expected each "
                         "point of a closed surface once (give separate solids as separate shapes)")
    signed = np.einsum("ij,ij->i", v0, cross)
    volume = math.fsum(signed.tolist()) / 6.0
    if abs(volume) < _FLAT * extent**3:
        raise InputError(f"the mesh encloses no volume ({volume:.3g} m^3); expected a closed solid's surface")
    if volume < 0.0:
        raise InputError(f"the mesh's faces point inward; reverse their winding (its signed volume is "
                         f"{volume:.3g} m^3 < 0)")
    _check_shells(verts, tris, signed, extent)
    label = f"mesh of {tris.shape[0]} triangles"
    total = 0.5 * math.fsum(doubled.tolist())
    # a triangle with edges up to r has at most 0.43 r^2: the default doubles the grids' r for about as many
    longest = np.max(np.stack([np.linalg.norm(v1 - v0, axis=1), np.linalg.norm(v2 - v1, axis=1),
                               np.linalg.norm(v0 - v2, axis=1)]), axis=0)

    def elements(step: float) -> int:
        cuts = np.maximum(1, np.ceil(longest / step))
        return int((cuts * cuts).sum())

    res = 2.0 * _resolution(None, total, extent, label, elements) if resolution is None else \
        _resolution(resolution, total, extent, label, elements)
    k = np.maximum(1, np.ceil(longest / res)).astype(np.int64)
    _check_count(int((k * k).sum()), label, res, total, elements)
    normals = cross / doubled[:, None]
    parts: list[Elements] = []
    order: list[NDArray[np.int64]] = []
    for level in np.unique(k):
        which = np.flatnonzero(k == level)
        bary = _subdivision(int(level))
        corners = np.stack([v0[which], v1[which], v2[which]], axis=1)  # (f, 3 corners, 3)
        cents = np.einsum("sc,fcx->fsx", bary, corners).reshape(-1, 3)
        count = bary.shape[0]
        parts.append((cents, np.repeat(normals[which], count, axis=0),
                      np.repeat(0.5 * doubled[which] / count, count)))
        order.append(np.repeat(which, count))
    centroids, normal_rows, areas = _join(*parts)
    face_of = np.concatenate(order)
    keep = np.argsort(face_of, kind="stable")  # elements in face order whatever the levels
    horizontal = np.ptp(verts[used], axis=0)[:2]
    width = float(np.clip(np.min(horizontal), *SIZE_RANGE))
    return _shape((centroids[keep], normal_rows[keep], areas[keep]), label, closed=True, width=width)


def _subdivision(k: int) -> Float:
    """The barycentric centroids (k^2, 3) of the ``k^2`` equal triangles a triangle is cut into."""
    rows = []
    for i in range(k):
        for j in range(k - i):
            rows.append((i + 1.0 / 3.0, j + 1.0 / 3.0))  # upward triangle at (i, j)
            if j < k - i - 1:
                rows.append((i + 2.0 / 3.0, j + 2.0 / 3.0))  # downward triangle between it and its neighbours
    ij = np.array(rows) / k
    return np.column_stack([1.0 - ij[:, 0] - ij[:, 1], ij[:, 0], ij[:, 1]])


# ------------------------------------------------------------------------------------------------------- MuJoCo

def from_mujoco_geom(model: Any, geom: int | str, *, resolution: float | None = None) -> Shape:
    """The shape of a MuJoCo geom, in the geom's frame (``data.geom_xpos``, ``data.geom_xmat``).

    Parameters
    ----------
    model : mujoco.MjModel
        A compiled model.
    geom : int or str
        The geom's id (0 to ``model.ngeom - 1``) or name.
    resolution : float or None
        The largest element edge [m], as in the constructors; None: their default.

    Sphere, capsule, cylinder, box and ellipsoid convert MuJoCo's
    ``geom_size`` (radius, half-length, half-sizes, semi-axes) to
    :func:`sphere`, :func:`capsule`, :func:`cylinder`, :func:`box` and
    :func:`ellipsoid`'s full sizes. A mesh geom gives :func:`mesh` of the
    model's ``mesh_vert`` and ``mesh_face``: MuJoCo stores those vertices in
    the mesh's inertial frame (centre of mass, principal axes), which is the
    geom's frame. Plane, height field, SDF and any other type: InputError.
    Errors from the constructors (an open mesh, say) name the geom.
    """
    mujoco = require("mujoco", "mujoco", "from_mujoco_geom")
    if not all(hasattr(model, a) for a in ("ngeom", "geom_type", "geom_size", "geom_dataid")):
        raise InputError(f"from_mujoco_geom needs a compiled mujoco.MjModel, got {type(model).__name__}")
    ngeom = int(model.ngeom)
    if isinstance(geom, str):
        gid = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom))
        if gid < 0:
            raise InputError(f"the model has no geom named {geom!r}; expected a geom's name or an id "
                             f"0 to {ngeom - 1}")
    elif isinstance(geom, (int, np.integer)) and not isinstance(geom, bool):
        gid = int(geom)
        if not 0 <= gid < ngeom:
            # shown: an int of over 4300 digits has no str (ValueError)
            raise InputError(f"geom id {shown(geom)} is out of range; expected 0 to {ngeom - 1} (the model has "
                             f"{ngeom})")
    else:
        raise InputError(f"geom must be a geom's id (int) or name (str), got {type(geom).__name__}")
    if resolution is not None and not is_real(resolution):
        raise InputError(f"resolution must be a number [m] or None, got {type(resolution).__name__}")
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, gid)
    label = f"MuJoCo geom {name!r}" if name else f"MuJoCo geom {gid}"
    try:
        kind = mujoco.mjtGeom(int(model.geom_type[gid]))
    except ValueError:  # a geom_type written by hand after compiling: was mjtGeom's ValueError (Invalid int value)
        raise InputError(f"{label} has geom_type {int(model.geom_type[gid])}, which is no MuJoCo geom type; expected "
                         "sphere, capsule, cylinder, box, ellipsoid or mesh (mujoco.mjtGeom)") from None
    size = [float(s) for s in model.geom_size[gid]]
    try:
        if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            shape = sphere(2.0 * size[0], resolution=resolution)
        elif kind == mujoco.mjtGeom.mjGEOM_CAPSULE:
            shape = capsule(2.0 * size[0], 2.0 * size[1], resolution=resolution)
        elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
            shape = cylinder(2.0 * size[0], 2.0 * size[1], resolution=resolution)
        elif kind == mujoco.mjtGeom.mjGEOM_BOX:
            shape = box(2.0 * size[0], 2.0 * size[1], 2.0 * size[2], resolution=resolution)
        elif kind == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
            shape = ellipsoid(2.0 * size[0], 2.0 * size[1], 2.0 * size[2], resolution=resolution)
        elif kind == mujoco.mjtGeom.mjGEOM_MESH:
            mid, nmesh = int(model.geom_dataid[gid]), int(model.nmesh)
            if not 0 <= mid < nmesh:  # a geom_dataid written by hand: -1 was the model's last mesh, 5 an IndexError
                expected = f"a mesh id 0 to {nmesh - 1}" if nmesh else "a mesh, and the model has none"
                raise InputError(f"{label} is a mesh geom of mesh id {mid} (geom_dataid); expected {expected}")
            v0, nv = int(model.mesh_vertadr[mid]), int(model.mesh_vertnum[mid])
            f0, nf = int(model.mesh_faceadr[mid]), int(model.mesh_facenum[mid])
            shape = mesh(np.asarray(model.mesh_vert[v0:v0 + nv], dtype=np.float64),
                         np.asarray(model.mesh_face[f0:f0 + nf], dtype=np.int64), resolution=resolution)
        else:
            kind_name = kind.name.removeprefix("mjGEOM_").lower()
            raise InputError(f"{label} is a {kind_name}; from_mujoco_geom supports sphere, capsule, cylinder, "
                             f"box, ellipsoid and mesh")
    except InputError as error:
        if str(error).startswith(label):
            raise
        raise InputError(f"{label}: {error}") from None
    return replace(shape, name=f"{label}: {shape.name}")
