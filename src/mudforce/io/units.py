"""Quantities with units at the edges: ``20mm``, ``10mm/s``, ``6s``, ``100Hz``, ``25%``.

Everything is converted to SI here; a bare number is refused with an
example, so that ``--depth 20`` can never silently mean 20 m.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from typing import Any

from mudforce.errors import InputError

__all__ = ["KINDS", "LIMITS", "format_quantity", "parse_list", "parse_quantity"]

# the factors to SI, exact: a value is the float nearest to number x factor ("20um" is 2e-05, where
# 20 * 1e-6 is 1.9999999999999998e-05; "35%" is 0.35, where 35 * 1e-2 is 0.35000000000000003)
_F = Fraction
_LENGTH = {"m": _F(1), "cm": _F(1, 10**2), "mm": _F(1, 10**3), "um": _F(1, 10**6), "µm": _F(1, 10**6)}
_TIME = {"s": _F(1), "ms": _F(1, 10**3), "min": _F(60)}
_UNITS: dict[str, dict[str, Fraction]] = {
    "length": _LENGTH,
    "velocity": {f"{lu}/{tu}": lf / tf for lu, lf in _LENGTH.items() for tu, tf in _TIME.items()},
    "time": _TIME,
    "frequency": {"hz": _F(1), "khz": _F(10**3)},
    "fraction": {"%": _F(1, 10**2)},
    "force": {"N": _F(1), "kN": _F(10**3), "mN": _F(1, 10**3)},
    "mass": {"kg": _F(1), "g": _F(1, 10**3)},
    "pressure": {"Pa": _F(1), "kPa": _F(10**3), "MPa": _F(10**6)},
    "area": {"m2": _F(1), "cm2": _F(1, 10**4), "mm2": _F(1, 10**6)},
}
_EXAMPLES = {
    "length": "20mm or 0.02m",
    "velocity": "10mm/s or 0.01m/s",
    "time": "6s or 500ms",
    "frequency": "100Hz or 1kHz",
    "fraction": "25%",
    "force": "0.2N",
    "mass": "5kg",
    "pressure": "6kPa",
    "area": "19.38cm2",
}
#: The kinds of quantity :func:`parse_quantity` knows.
KINDS = tuple(_UNITS)

#: Magnitudes [SI] accepted per kind: (smallest non-zero, largest). Far beyond any mud
#: experiment at both ends, and well inside float64, so that no product of them overflows
#: or underflows into denormals; the model's own bounds (depth, foot size, ...) are narrower.
LIMITS: dict[str, tuple[float, float]] = {
    "length": (1e-9, 1e3),  # [m]
    "velocity": (1e-9, 1e3),  # [m/s]
    "time": (1e-9, 1e9),  # [s]
    "frequency": (1e-6, 1e9),  # [Hz]
    "fraction": (1e-9, 100.0),  # [-]
    "force": (1e-9, 1e7),  # [N]
    "mass": (1e-6, 1e6),  # [kg]
    "pressure": (1e-6, 1e12),  # [Pa]
    "area": (1e-12, 1e4),  # [m^2]
}

# ASCII digits only: "1_0" and non-ASCII digits are not numbers here
_NUMBER = re.compile(r"^\s*([+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)\s*([^\s0-9.+_-].*?)?\s*$")


def _case_key(kind: str, unit: str) -> str:
    # lengths, times and areas are case-sensitive (mm vs Mm: "20MM2" was read as 20 mm^2, where "20MM" is refused);
    # frequencies, forces and pressures are
    # conventionally capitalised (Hz, N, kPa) and compared case-free, but for the case of a leading m or M, which
    # is milli or mega there ("0.2MN" was read as 0.2 mN, "6mPa" as 6 MPa)
    if kind in ("force", "pressure") and unit[:1] in ("m", "M"):
        return unit[0] + unit[1:].lower()
    return unit.lower() if kind in ("frequency", "force", "pressure", "fraction", "mass") else unit


def _a(kind: str) -> str:
    """``kind`` with its indefinite article: "a length", "an area"."""
    return f"an {kind}" if kind[0] in "aeiou" else f"a {kind}"


def parse_quantity(text: str, kind: str, *, name: str = "value", allow_negative: bool = False,
                   allow_zero: bool = False, example: str | None = None) -> float:
    """Parse ``text`` as a quantity of ``kind`` and return it in SI.

    Parameters
    ----------
    text : str
        A number followed by a unit, e.g. ``"20mm"``, ``"10 mm/s"``, ``"25%"``.
    kind : str
        One of :data:`KINDS`.
    name : str
        What the value is, for the error message (``"--depth"``).
    allow_negative, allow_zero : bool
        Accept values below or equal to zero (default: strictly positive).
    example : str or None
        The example the error message shows (default: the kind's, e.g. ``"25%"`` for a fraction); an option whose
        values are not the kind's usual ones gives its own (``--force-gain-uncertainty``: ``"5%"``).

    Raises
    ------
    InputError
        For a bare number, an unknown unit, a non-finite or out-of-sign value,
        a magnitude outside :data:`LIMITS`, with an example of what is expected.
    """
    if kind not in _UNITS:
        raise ValueError(f"unknown quantity kind {kind!r}")
    example = _EXAMPLES[kind] if example is None else example
    match = _NUMBER.match(str(text))
    if match is None:
        raise _refused(name, f"cannot read {text!r} as {_a(kind)}", f"a number with a unit, e.g. {example}")
    number, unit = match.group(1), (match.group(2) or "").strip()
    if not unit:
        # a bare number is refused for every kind, percentages included:
        # "--water-content 25" (25 % or 2500 %?) must never be guessed
        raise _refused(name, f"{text!r} has no unit", f"{_a(kind)} with a unit, e.g. {example}")
    table = {_case_key(kind, u): f for u, f in _UNITS[kind].items()}
    # spaces around "/" only ("10 mm / s"): "20m m" is no "20mm"; the Greek mu (U+03BC) is the micro sign (U+00B5)
    factor = table.get(_case_key(kind, re.sub(r"\s*/\s*", "/", unit).replace("\u03bc", "\u00b5")))
    if factor is None:
        known = ", ".join(_UNITS[kind])
        raise _refused(name, f"unknown {kind} unit {unit!r} in {text!r}", f"one of {known}, e.g. {example}",
                       lead="use")
    tiny, huge = LIMITS[kind]
    value = float(number) * float(factor)
    if 0.0 < abs(value) <= huge:
        # the exact product, rounded once; only within the limits, where the literal's exponent is no larger than
        # its text ("1e999999999mm" is refused as too large above without 10**999999999 being built)
        value = float(Fraction(number) * factor)
    if not math.isfinite(value) or abs(value) > huge:
        raise _refused(name, f"{text!r} is too large (at most {huge:g} in SI)", f"e.g. {example}")
    # a literal that is not zero is not read as zero when it underflows ("1e-400mm")
    if abs(value) < tiny and any(c in "123456789" for c in number.lower().partition("e")[0]):
        raise _refused(name, f"{text!r} is too small (at least {tiny:g} in SI, or 0 where allowed)", f"e.g. {example}")
    if value < 0.0 and not allow_negative:
        raise _refused(name, f"{text!r} must not be negative", f"e.g. {example}")
    if value == 0.0 and not allow_zero:
        raise _refused(name, f"{text!r} must be greater than zero", f"e.g. {example}")
    return value + 0.0  # "-0N" is 0 N: no negative zero reaches an output ("bias_N": -0.0)


class _QuantityError(InputError):
    """:func:`parse_quantity`'s refusal: its one line, and the reason alone (``why``) for a caller that words its
    own line around it (``--force-lag``'s parts)."""

    def __init__(self, message: str, why: str) -> None:
        super().__init__(message)
        self.why = why


def _refused(name: str, why: str, expected: str, lead: str = "expected") -> _QuantityError:
    """The refusal ``"{name}: {why}; {lead} {expected}"`` (one line) with its reason kept apart."""
    return _QuantityError(f"{name}: {why}; {lead} {expected}", why)


def parse_list(text: str, kind: str, *, name: str = "value", **kwargs: Any) -> list[float]:
    """Parse a comma-separated list of quantities, e.g. ``"10mm/s,20mm/s"``."""
    items = [item for item in str(text).split(",") if item.strip()]
    if not items:
        raise InputError(f"{name}: empty list; expected one value or several separated by commas, e.g. "
                         f"{_EXAMPLES[kind].split()[0]}")
    return [parse_quantity(item, kind, name=name, **kwargs) for item in items]


def format_quantity(value: float, kind: str) -> str:
    """A short human-readable rendering of an SI value (``0.02`` length -> ``"20 mm"``)."""
    if kind == "length":
        return f"{value * 1e3:g} mm"
    if kind == "velocity":
        return f"{value * 1e3:g} mm/s"
    if kind == "fraction":
        return f"{value * 100:g}%"
    if kind == "frequency":
        return f"{value:g} Hz"
    if kind == "time":
        return f"{value:g} s"
    return f"{value:g}"
