"""The baselines' quick test of a trajectory (``baselines._within_bounds``) passes exactly what the checks pass.

It stands in front of :func:`check_depths` and :func:`check_times`, which
then run only to word a refusal: a trajectory it passed that they refuse
would reach the force laws unchecked.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.model import baselines as B
from mudforce.model.bounds import MAX_DEPTH, MAX_DT, MAX_TIME, MIN_DT, check_depths, check_times

T = np.arange(6) * 0.01
Z = np.linspace(-0.01, 0.02, 6)


def _set(index: int, what: str, value: float, t: np.ndarray = T, z: np.ndarray = Z) -> tuple[np.ndarray, np.ndarray]:
    t, z = t.copy(), z.copy()
    (t if what == "t" else z)[index] = value
    return t, z


CASES = [
    (T, Z), (T[:1], Z[:1]), (T[:2], Z[:2]),
    (np.array([-MAX_TIME, -MAX_TIME + MAX_DT, MAX_TIME - MAX_DT, MAX_TIME]), np.array([MAX_DEPTH, -MAX_DEPTH, 0, 0])),
    (np.array([0.0, MIN_DT, 2 * MIN_DT]), np.zeros(3)),
    (np.array([0.0, math.nextafter(MIN_DT, 0.0)]), np.zeros(2)),
    (np.array([0.0, math.nextafter(MAX_DT, math.inf)]), np.zeros(2)),
    (np.array([math.nextafter(MAX_TIME, math.inf)]), np.zeros(1)),
    (np.array([0.0]), np.array([math.nextafter(-MAX_DEPTH, -math.inf)])),
    *[_set(k, what, value) for k in (0, 3, 5) for what in "tz" for value in (math.nan, math.inf, -math.inf)],
    _set(0, "t", math.nan, T[:1], Z[:1]), _set(0, "z", math.nan, T[:1], Z[:1]),
    _set(3, "t", T[2]), _set(3, "t", T[1]), _set(5, "z", 100.5), _set(0, "t", -2e9), (T + 2e9, Z),
]


@pytest.mark.parametrize("case", range(len(CASES)))
def test_the_quick_test_passes_what_the_checks_pass(case: int) -> None:
    t, z = CASES[case]
    try:
        check_depths(z)
        check_times(t)
        passes = True
    except InputError:
        passes = False
    assert B._within_bounds(t, z) == passes
