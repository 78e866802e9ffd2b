"""Speed plumbing only: numpy's sum and mean of a float64 vector, bit for bit, in compiled code.

numpy sums a contiguous float64 vector by pairwise summation (``pairwise_sum`` in numpy's
``loops_utils.h.src``): below 8 values one after the other; up to 128 in eight running sums combined as
``((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))`` and the rest added one by one; above that the two halves
(the first half's length a multiple of 8) summed alike and added. numba's ``np.sum`` adds one after the other,
which rounds differently. :func:`pairwise_sum` is numpy's order, so that a statistic moved from numpy into a
compiled loop gives the same bits (``tests/kernel/test_pairwise.py`` holds it to ``np.sum`` and ``np.mean``
over lengths 0 to 70,000). Nothing here is physics.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["pairwise_mean", "pairwise_sum"]

_BLOCK = 128  # numpy's PW_BLOCKSIZE


@njit(cache=True, nogil=True)
def _leaf(a: np.ndarray, lo: int, n: int) -> float:  # pragma: no cover - compiled
    """numpy's ``pairwise_sum`` of ``a[lo:lo + n]`` for ``n`` <= 128: one block, no split."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0, r1, r2, r3 = float(a[lo]), float(a[lo + 1]), float(a[lo + 2]), float(a[lo + 3])
    r4, r5, r6, r7 = float(a[lo + 4]), float(a[lo + 5]), float(a[lo + 6]), float(a[lo + 7])
    i = 8
    whole = n - n % 8
    while i < whole:
        k = lo + i
        r0 += a[k]
        r1 += a[k + 1]
        r2 += a[k + 2]
        r3 += a[k + 3]
        r4 += a[k + 4]
        r5 += a[k + 5]
        r6 += a[k + 6]
        r7 += a[k + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@njit(cache=True, nogil=True)
def _pairwise(a: np.ndarray, lo: int, n: int) -> float:  # pragma: no cover - compiled
    """numpy's ``pairwise_sum`` of ``a[lo:lo + n]``: above 128 values, the sum of the two halves' sums (the first
    half's length a multiple of 8), each summed alike. Its recursion walked with a stack of its own (numba's cache
    cannot load a recursive function)."""
    if n <= _BLOCK:
        return _leaf(a, lo, n)
    los = np.empty(64, dtype=np.int64)  # a split halves the length: 64 levels hold any array
    ns = np.empty(64, dtype=np.int64)
    stage = np.empty(64, dtype=np.int64)  # 0: split next; 1: its first half summed; 2: both summed
    values = np.empty(64)
    top, count = 0, 0
    los[0], ns[0], stage[0] = lo, n, 0
    while top >= 0:
        m = ns[top]
        if m <= _BLOCK:
            values[count] = _leaf(a, los[top], m)
            count += 1
            top -= 1
            continue
        half = m // 2
        half -= half % 8
        if stage[top] == 2:  # first half's sum + second half's sum
            values[count - 2] = values[count - 2] + values[count - 1]
            count -= 1
            top -= 1
            continue
        first = stage[top] == 0
        stage[top] += 1
        top += 1
        los[top] = los[top - 1] if first else los[top - 1] + half
        ns[top] = half if first else m - half
        stage[top] = 0
    return float(values[0])


@njit(cache=True, nogil=True)
def pairwise_sum(a: np.ndarray, n: int) -> float:  # pragma: no cover - compiled
    """``np.sum(a[:n])`` of a float64 vector ``a``, the same bits (numpy's pairwise order)."""
    return 0.0 + _pairwise(a, 0, n)


@njit(cache=True, nogil=True)
def pairwise_mean(a: np.ndarray, n: int) -> float:  # pragma: no cover - compiled
    """``np.mean(a[:n])`` of a float64 vector ``a``, the same bits; NaN for ``n`` = 0, as numpy (without its
    warning)."""
    return pairwise_sum(a, n) / n if n > 0 else np.nan
