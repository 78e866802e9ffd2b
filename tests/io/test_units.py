"""A quantity with a unit is read as the float nearest to its exact value."""

from __future__ import annotations

import time
from decimal import Decimal
from fractions import Fraction

import pytest

from mudforce.errors import InputError
from mudforce.io.units import parse_quantity


@pytest.mark.parametrize(("text", "kind", "exact"), [
    # each was the number times a float factor, a last bit off: 20 * 1e-6 = 1.9999999999999998e-05,
    # 35 * 1e-2 = 0.35000000000000003, 1.001 * 1e3 = 1000.9999999999999, 0.12 * 60 = 7.199999999999999, ...
    ("20um", "length", "2e-5"), ("5µm", "length", "5e-6"), ("9mm", "length", "9e-3"), ("35cm", "length", "0.35"),
    ("3cm2", "area", "3e-4"), ("5mm2", "area", "5e-6"), ("9mm/s", "velocity", "9e-3"),
    ("35cm/s", "velocity", "0.35"), ("0.14cm/ms", "velocity", "1.4"), ("27um/min", "velocity", "4.5e-7"),
    ("35%", "fraction", "0.35"), ("1.001kHz", "frequency", "1001"), ("1.001kPa", "pressure", "1001"),
    ("4.1MPa", "pressure", "4.1e6"), ("9mN", "force", "9e-3"), ("1.001kN", "force", "1001"), ("9g", "mass", "9e-3"),
    ("9ms", "time", "9e-3"), ("0.12min", "time", "7.2"),
    # already the nearest float before, unchanged
    ("20mm", "length", "0.02"), ("1m", "length", "1"), ("0.3mm", "length", "3e-4"), ("10mm/s", "velocity", "0.01"),
    ("7cm2", "area", "7e-4"), ("25%", "fraction", "0.25"), ("50Hz", "frequency", "50"),
    ("2.5kPa", "pressure", "2500"), ("6s", "time", "6"),
])
def test_a_decimal_value_is_the_float_nearest_to_it(text: str, kind: str, exact: str) -> None:
    assert parse_quantity(text, kind) == float(Decimal(exact))


def test_per_minute_is_the_exact_ratio_rounded_once() -> None:
    """5mm/min is 5/60000 m/s rounded once: 5 * (1e-3 / 60) was 8.333333333333334e-05, rounded three times."""
    assert parse_quantity("5mm/min", "velocity") == float(Fraction(5, 60000)) == 8.333333333333333e-05


def test_a_huge_exponent_is_refused_without_being_expanded() -> None:
    start = time.perf_counter()
    for text in ("1e999999999mm", "1e-999999999mm"):
        with pytest.raises(InputError, match=r"too large|too small"):
            parse_quantity(text, "length")
    assert time.perf_counter() - start < 0.05


@pytest.mark.parametrize("text", ["abc", "5", "5parsec", "1e999ms", "1e-400ms", "-5ms", "0ms"])
def test_a_refusal_keeps_its_reason_apart_for_a_caller_that_words_its_own_line(text: str) -> None:
    # (synth's --force-lag words "is no delay time (<reason>)" from it; it cut the message apart before)
    with pytest.raises(InputError) as caught:
        parse_quantity(text, "time", name="--x")
    why = getattr(caught.value, "why", None)
    assert why and str(caught.value).startswith(f"--x: {why}; ") and "\n" not in str(caught.value)
