"""``--shape KIND:SIZE``, as ``mudforce drop`` and ``mudforce simulate`` read it (one parser for both).

A shape is a kind and its full sizes joined by ``x``, each with its unit:
``sphere:40mm`` (diameter), ``capsule:30mmx60mm`` (diameter x length of the
cylindrical part), ``cylinder:30mmx20mm`` (diameter x height),
``disc:50mmx5mm`` (diameter x thickness) and ``box:50mmx40mmx20mm``
(length x width x height, along x, y, z), in the body frames of
:mod:`mudforce.model.shapes` (MuJoCo's, axis along z).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from mudforce.errors import InputError
from mudforce.io.units import parse_quantity

if TYPE_CHECKING:
    from mudforce.model.shapes import Shape

__all__ = ["MAX_SHAPE_SIZE", "MIN_SHAPE_SIZE", "SHAPE_EXAMPLES", "SHAPE_SIZES", "make_shape", "parse_shape"]

#: The kinds ``--shape`` accepts and how many sizes each takes [-].
SHAPE_SIZES: dict[str, int] = {"sphere": 1, "capsule": 2, "cylinder": 2, "disc": 2, "box": 3}
#: The accepted forms, for help and error messages.
SHAPE_EXAMPLES = "sphere:40mm, capsule:30mmx60mm, cylinder:30mmx20mm, disc:50mmx5mm or box:50mmx40mmx20mm"
#: The largest size of a foot ``--shape`` accepts [m].
MAX_SHAPE_SIZE = 1.0
#: The smallest size [m]: the shapes' (:data:`mudforce.model.foot.SIZE_RANGE`); below, ``drop`` gave MuJoCo's
#: error about inertia, ``simulate`` the shape's words without the option's name.
MIN_SHAPE_SIZE = 1e-4


def parse_shape(text: str, *, name: str = "--shape") -> tuple[str, list[float]]:
    """``(kind, sizes [m])`` from ``KIND:SIZE`` (``"sphere:40mm"`` -> ``("sphere", [0.04])``).

    Raises
    ------
    InputError
        One line naming ``name``: an unknown kind or no sizes, the wrong
        number of sizes for the kind, a size without its unit, or one
        larger than :data:`MAX_SHAPE_SIZE` or smaller than :data:`MIN_SHAPE_SIZE`; each with an example.
    """
    kind, _, sizes = str(text).strip().partition(":")
    if kind not in SHAPE_SIZES or not sizes:
        raise InputError(f"{name}: {text!r} is not KIND:SIZE; expected e.g. {SHAPE_EXAMPLES}")
    parts = sizes.replace("×", "x").split("x")
    if len(parts) != SHAPE_SIZES[kind]:
        raise InputError(f"{name}: a {kind} takes {SHAPE_SIZES[kind]} size(s) joined by x, got {sizes!r}; "
                         f"expected e.g. {SHAPE_EXAMPLES}")
    dims = [parse_quantity(p, "length", name=name) for p in parts]
    if any(d > MAX_SHAPE_SIZE for d in dims):
        raise InputError(f"{name}: {sizes!r} is larger than {MAX_SHAPE_SIZE:g} m; expected a foot, e.g. sphere:40mm")
    if any(d < MIN_SHAPE_SIZE for d in dims):  # the shapes' bound (mudforce.model.foot.SIZE_RANGE), in its words
        raise InputError(f"{name}: {sizes!r} is smaller than {MIN_SHAPE_SIZE * 1e3:g} mm; expected a foot, "
                         "e.g. sphere:40mm")
    return kind, dims


def make_shape(kind: str, dims: list[float]) -> Shape:
    """The :class:`~mudforce.model.shapes.Shape` of a parsed ``--shape`` (default resolution).

    Parameters
    ----------
    kind : str
        One of :data:`SHAPE_SIZES`.
    dims : list of float
        Its full sizes [m], as :func:`parse_shape` returns them.
    """
    from mudforce.model import shapes

    if kind == "sphere":
        return shapes.sphere(dims[0])
    if kind == "capsule":
        return shapes.capsule(dims[0], dims[1])
    if kind == "cylinder":
        return shapes.cylinder(dims[0], dims[1])
    if kind == "disc":
        return shapes.disc(dims[0], dims[1])
    if kind == "box":
        return shapes.box(dims[0], dims[1], dims[2])
    raise InputError(f"--shape: unknown kind {kind!r}; expected e.g. {SHAPE_EXAMPLES}")
