"""Foot geometry: the contact area that turns stress into force, and the width in Eq. (4)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from mudforce.errors import InputError

__all__ = ["Foot"]

_PAPER_LENGTH = 0.051  # [m], the paper's 51 x 38 x 25 mm cuboid intruder
_PAPER_WIDTH = 0.038  # [m]


@dataclass(frozen=True)
class Foot:
    """A flat foot pressed vertically into mud.

    Parameters
    ----------
    area : float
        Contact area ``S`` of the bottom face [m^2]; force = stress x area, Eq. (1).
    width : float
        Intruder width ``H`` in the nonlinear spring, Eq. (4) [m].
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
        for name in ("area", "width"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise InputError(f"foot {name} must be a number, got {value!r}")
            if not math.isfinite(value) or value <= 0.0:
                raise InputError(f"foot {name} must be finite and > 0 [m^2 or m], got {value!r}")
            object.__setattr__(self, name, float(value))

    @classmethod
    def cuboid(cls, length: float = _PAPER_LENGTH, width: float = _PAPER_WIDTH) -> Foot:
        """A rectangular bottom face ``length x width`` [m]; ``H`` is the shorter side.

        The defaults are the paper's 51 x 38 mm intruder (``S = 1.938e-3 m^2``,
        ``H = 0.038 m``).
        """
        for name, value in (("length", length), ("width", width)):
            if not math.isfinite(value) or value <= 0.0:
                raise InputError(f"cuboid {name} must be finite and > 0 [m], got {value!r}")
        return cls(area=length * width, width=min(length, width), shape=f"cuboid {length * 1e3:g}x{width * 1e3:g} mm")

    @classmethod
    def disc(cls, diameter: float) -> Foot:
        """A circular bottom face of ``diameter`` [m]; ``H`` is the diameter."""
        if not math.isfinite(diameter) or diameter <= 0.0:
            raise InputError(f"disc diameter must be finite and > 0 [m], got {diameter!r}")
        return cls(area=math.pi * diameter**2 / 4.0, width=diameter, shape=f"disc {diameter * 1e3:g} mm")

    @classmethod
    def paper(cls) -> Foot:
        """The paper's 51 x 38 mm cuboid intruder."""
        return cls.cuboid()
