"""numpy's sum and mean in compiled code (:mod:`mudforce._plumbing.pairwise`): the same bits as numpy's."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from mudforce._plumbing.pairwise import pairwise_mean, pairwise_sum


def test_every_length_to_a_few_blocks_and_long_ones_sum_as_numpy_does() -> None:
    rng = np.random.default_rng(7)
    lengths = [*range(0, 530), 1000, 1023, 1024, 1025, 4097, 8191, 8192, 8193, 30001, 70000]
    for n in lengths:
        # magnitudes over six decades, so that the order of the additions shows in the last bits
        x = rng.standard_normal(n) * 10.0 ** rng.uniform(-3.0, 3.0, n)
        assert pairwise_sum(x, n) == np.sum(x), n
        if n:
            assert pairwise_mean(x, n) == np.mean(x), n
    x = rng.standard_normal(100)
    assert pairwise_sum(x, 37) == np.sum(x[:37])  # a prefix: the first n values


def test_the_empty_mean_is_nan_and_a_nan_is_kept() -> None:
    assert np.isnan(pairwise_mean(np.zeros(0), 0))
    x = np.ones(300)
    x[200] = np.nan
    assert np.isnan(pairwise_sum(x, 300))


@settings(max_examples=200, deadline=None)
@given(arrays(np.float64, st.integers(0, 2000), elements=st.floats(-1e6, 1e6, allow_nan=False)))
def test_any_finite_vector_sums_to_numpys_bits(x: np.ndarray) -> None:
    assert pairwise_sum(x, x.size) == np.sum(x)
