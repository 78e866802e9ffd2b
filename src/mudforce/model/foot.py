"""Foot geometry: the contact area that turns stress into force, and the width in Eq. (4)."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from mudforce.errors import InputError, number_within

__all__ = ["AREA_RANGE", "FOOT_EXAMPLES", "SIZE_RANGE", "Foot", "parse_foot"]

#: The foot specifications every ``--foot`` option accepts, for help and error messages.
FOOT_EXAMPLES = "paper, cuboid:51mmx38mm, disc:50mm or area:19.38cm2,width:38mm"

_SIDES = re.compile(r"\s*[x×*,]\s*", flags=re.IGNORECASE)

#: Accepted foot sizes (length, width, diameter, ``H``) [m]: 0.1 mm to 10 m, a robot's toe to a
#: vehicle's track; the bounds keep ``S``, ``(z/H)^beta`` and every force finite.
SIZE_RANGE: tuple[float, float] = (1e-4, 10.0)
#: Accepted contact areas ``S`` [m^2] (a 0.1 mm disc has 7.9e-9 m^2).
AREA_RANGE: tuple[float, float] = (1e-9, 100.0)

_PAPER_LENGTH = 0.051  # [m], the paper's 51 x 38 x 25 mm cuboid intruder
_PAPER_WIDTH = 0.038  # [m]


@dataclass(frozen=True)
class Foot:
    """A flat foot pressed vertically into mud.

    Parameters
    ----------
    area : float
        Contact area ``S`` of the bottom face [m^2], within [1e-9, 100]; force = stress x area, Eq. (1).
    width : float
        Intruder width ``H`` in the nonlinear spring, Eq. (4) [m], within [1e-4, 10].
    shape : str
        ``"cuboid"``, ``"disc"`` or ``"custom"``; for display only.

    Notes
    -----
    The paper only says "intruder width" for ``H``; for a cuboid the
    project uses the shorter side of the bottom face (38 mm for the paper's
    51 x 38 mm foot), and for a disc its diameter.
    """

    area: float
    width: float
    shape: str = "custom"

    def __post_init__(self) -> None:
        for name, (lo, hi), unit in (("area", AREA_RANGE, "m^2"), ("width", SIZE_RANGE, "m")):
            value = number_within(getattr(self, name), f"foot {name}", lo, hi, unit)
            object.__setattr__(self, name, value)
        if not isinstance(self.shape, str):
            raise InputError(f"foot shape must be a str, got {type(self.shape).__name__}")

    @classmethod
    def cuboid(cls, length: float = _PAPER_LENGTH, width: float = _PAPER_WIDTH) -> Foot:
        """A rectangular bottom face ``length x width`` [m]; ``H`` is the shorter side.

        The defaults are the paper's 51 x 38 mm intruder (``S = 1.938e-3 m^2``,
        ``H = 0.038 m``).
        """
        length = number_within(length, "cuboid length", *SIZE_RANGE, "m")
        width = number_within(width, "cuboid width", *SIZE_RANGE, "m")
        return cls(area=length * width, width=min(length, width), shape=f"cuboid {length * 1e3:g}x{width * 1e3:g} mm")

    @classmethod
    def disc(cls, diameter: float) -> Foot:
        """A circular bottom face of ``diameter`` [m]; ``H`` is the diameter."""
        diameter = number_within(diameter, "disc diameter", *SIZE_RANGE, "m")
        return cls(area=math.pi * diameter**2 / 4.0, width=diameter, shape=f"disc {diameter * 1e3:g} mm")

    @classmethod
    def paper(cls) -> Foot:
        """The paper's 51 x 38 mm cuboid intruder."""
        return cls.cuboid()


def parse_foot(text: str, *, name: str = "--foot") -> Foot:
    """Parse a command-line foot specification into a :class:`Foot` (every size needs a unit).

    Accepted forms (keywords are case-insensitive):

    ``cuboid:LxW``
        A rectangular bottom face ``L`` by ``W``, e.g. ``cuboid:51mmx38mm``
        (``cuboid:51mm,38mm`` too); area ``L W`` [m^2], ``H`` of Eq. (4) the shorter side.
    ``disc:D``
        A circular bottom face of diameter ``D``, e.g. ``disc:50mm`` (``H = D``).
    ``area:S,width:H``
        Any flat foot: contact area ``S`` (``m2``, ``cm2`` or ``mm2``) and width
        ``H``, in either order, e.g. ``area:19.38cm2,width:38mm``; also
        ``custom:S,H`` (area then width).
    ``paper``
        The paper's 51 x 38 mm cuboid.

    Raises
    ------
    InputError
        For anything else, naming the problem and showing the forms above.
    """
    from mudforce.io.units import parse_quantity

    if not isinstance(text, str):  # str() of 10**5000 raised ValueError, of a 2-D array spanned lines; None read "None"
        raise InputError(f"{name}: expected a foot specification (a str: {FOOT_EXAMPLES}), got {type(text).__name__}")
    spec = text.strip()
    kind, sep, body = spec.partition(":")
    kind = kind.strip().lower()
    if kind == "paper" and not sep:
        return Foot.paper()
    if not sep or not body.strip():
        raise InputError(f"{name}: cannot read {text!r}; expected {FOOT_EXAMPLES}")
    if kind in ("cuboid", "box", "rect", "rectangle"):
        sides = _SIDES.split(body.strip())
        if len(sides) != 2:
            raise InputError(f"{name}: {text!r} needs two sides LENGTHxWIDTH, each with a unit, e.g. cuboid:51mmx38mm")
        length = parse_quantity(sides[0], "length", name=f"{name} cuboid length")
        width = parse_quantity(sides[1], "length", name=f"{name} cuboid width")
        return Foot.cuboid(length, width)
    if kind in ("disc", "disk", "circle"):
        return Foot.disc(parse_quantity(body, "length", name=f"{name} disc diameter"))
    if kind == "custom":
        parts = body.split(",")
        if len(parts) != 2:
            raise InputError(f"{name}: {text!r} needs AREA,WIDTH, e.g. custom:19.38cm2,38mm")
        values = {"area": parts[0], "width": parts[1]}
    elif kind in ("area", "width"):
        values = {}
        for item in spec.split(","):
            key, sep_item, value = item.partition(":")
            key = key.strip().lower()
            if not sep_item or key not in ("area", "width") or key in values:
                raise InputError(f"{name}: cannot read {item.strip()!r} in {text!r}; "
                                 f"expected area:AREA,width:LENGTH, e.g. area:19.38cm2,width:38mm")
            values[key] = value
        if set(values) != {"area", "width"}:
            raise InputError(f"{name}: {text!r} needs both area and width, e.g. area:19.38cm2,width:38mm")
    else:
        raise InputError(f"{name}: unknown foot shape {kind!r} in {text!r}; expected {FOOT_EXAMPLES}")
    area = parse_quantity(values["area"], "area", name=f"{name} area")
    width = parse_quantity(values["width"], "length", name=f"{name} width")
    return Foot(area=area, width=width, shape="custom")
