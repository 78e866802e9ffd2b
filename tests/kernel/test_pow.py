"""The spring's power function (:func:`mudforce._plumbing.pow.power`) against mpmath, and vectorised == scalar."""

from __future__ import annotations

import math

import mpmath
import numpy as np
from numba import njit

from mudforce._plumbing.pow import power


def _ulp_errors(x: np.ndarray, y: np.ndarray, got: np.ndarray) -> np.ndarray:
    """Error of ``got`` against ``x ** y`` in 40-digit arithmetic, in units of the last place of the exact value."""
    mpmath.mp.dps = 40
    errors = np.empty(x.size)
    for i, (a, b, g) in enumerate(zip(x.tolist(), y.tolist(), got.tolist(), strict=True)):
        exact = mpmath.power(mpmath.mpf(a), mpmath.mpf(b))
        errors[i] = float(abs(mpmath.mpf(g) - exact)) / math.ulp(float(exact))
    return errors


@njit(cache=True)
def _vector_loop(x: np.ndarray, y: np.ndarray, out: np.ndarray) -> None:
    for i in range(x.shape[0]):  # a branch-free loop: the compiler vectorises it
        out[i] = power(x[i], y[i])


def _vectorised(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    out = np.empty_like(x)
    _vector_loop(x, y, out)
    return out


def test_within_one_ulp_where_the_spring_uses_it() -> None:
    """Depth ratios from 1e-9 to 20 and exponents in (0, 1] (Table I: 0.38-0.56)."""
    rng = np.random.default_rng(0)
    x = np.exp(rng.uniform(math.log(1e-9), math.log(20.0), 20_000))
    y = rng.uniform(0.0, 1.0, x.size) + 1e-12
    errors = _ulp_errors(x, y, _vectorised(x, y))
    assert errors.max() < 1.0
    assert np.mean(errors > 0.5) < 0.05  # nearly always correctly rounded


def test_within_one_ulp_over_the_whole_range() -> None:
    rng = np.random.default_rng(1)
    x = np.exp(rng.uniform(math.log(1e-300), math.log(1e300), 5_000))
    y = rng.uniform(0.0, 4.0, x.size) + 1e-12
    ok = np.abs(y * np.log(x)) < 700.0  # results that are normal numbers
    errors = _ulp_errors(x[ok], y[ok], _vectorised(x[ok], y[ok]))
    assert errors.max() < 1.0


def test_exact_cases() -> None:
    rng = np.random.default_rng(2)
    x = np.exp(rng.uniform(-30.0, 30.0, 1000))
    np.testing.assert_array_equal(_vectorised(x, np.ones_like(x)), x)  # a linear spring: x ** 1 == x
    y = rng.uniform(0.0, 4.0, 1000)
    np.testing.assert_array_equal(_vectorised(np.ones_like(y), y), 1.0)
    assert power(0.0, 0.5) == 0.0
    assert math.isnan(power(-1.0, 0.5))
    assert power(4.0, 0.5) == 2.0
    assert power(2.0**-20, 0.25) == 2.0**-5


def test_vectorised_equals_scalar_bit_for_bit() -> None:
    """The spring gives the same bits in a vectorised loop (batch, many feet) as alone (streaming)."""
    rng = np.random.default_rng(3)
    x = np.exp(rng.uniform(math.log(1e-9), math.log(20.0), 3000))
    y = rng.uniform(0.0, 1.0, x.size)
    scalar = np.array([power(a, b) for a, b in zip(x.tolist(), y.tolist(), strict=True)])
    np.testing.assert_array_equal(_vectorised(x, y), scalar)
