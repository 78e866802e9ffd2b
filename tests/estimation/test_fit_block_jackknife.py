"""fit's jackknife with fewer than three trials: each recording cut into contiguous blocks (issue 23, point 5 for fit).

On the sensor-chain bench at full size (30-s recordings, one per fit) the standard errors of one-recording fits had
shrunk onto errors of the model that the noise model does not hold, and 6 of 72 fits were confidently wrong on
seed 0 (docs/estimation-history.md, "fit's jackknife over blocks of one recording"). A delete-one-block jackknife
sees the ones that differ from stride to stride.
"""

from __future__ import annotations

import numpy as np

import mudforce.estimation.calibration.fit as fit_module
from mudforce.estimation.calibration.uncertainty import jackknife_variance


def test_the_blocks_cover_every_row_once_with_each_prior_in_its_trials_first_block() -> None:
    starts = np.array([0, 95, 100])  # a 95-sample trial and a 5-sample one (fewer samples than blocks: whole)
    n_data = 100
    blocks = fit_module._blocks(starts, n_data)
    assert len(blocks) == fit_module._JACKKNIFE_BLOCKS + 1
    rows = np.sort(np.concatenate(blocks))
    np.testing.assert_array_equal(rows, np.arange(n_data + 2))
    assert [b.size for b in blocks[:10]] == [11, 10, 10, 10, 10, 9, 9, 9, 9, 9]  # 95 split, the prior with the first
    assert blocks[0][-1] == n_data and blocks[10].tolist() == [95, 96, 97, 98, 99, 101]


def test_blocks_that_disagree_widen_what_one_trial_gives() -> None:
    """A line fitted to data whose slope's error differs from block to block: the jackknife of the blocks sees it,
    one trial alone gives none."""
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 200)
    jac = np.vstack([np.column_stack([np.ones_like(t), t]), [0.0, 0.0]])  # and the tare prior's row
    residual = 0.05 * rng.standard_normal(t.size) + np.repeat(rng.standard_normal(10), 20) * (t - t.mean())
    residual = np.append(residual, 0.0)
    one = jackknife_variance(jac, residual, [np.arange(201)])
    blocks = fit_module._blocks(np.array([0, 200]), 200)
    spread = jackknife_variance(jac, residual, blocks)
    assert one is None and spread is not None
    s2 = float(residual @ residual) / (residual.size - 2)
    noise_var = np.diag(np.linalg.inv(jac.T @ jac) * s2)
    assert spread[1] > 2.0 * noise_var[1]  # the slope: what the blocks disagree on


def test_the_jackknife_variance_is_read_on_a_student_t_of_its_groups() -> None:
    """``_jackknife_spread``: the jackknife's variance times ``(t_{g-1}(0.975) / 1.96)^2``, so that +-1.96 standard
    errors is its 95 % interval: 1.33 for one recording's 10 blocks, 4.8 for three trials; none under three groups."""
    from scipy.stats import norm, t

    rng = np.random.default_rng(4)
    jac = rng.standard_normal((60, 2))
    residual = rng.standard_normal(60)
    for g, factor in ((10, 1.33214), (3, 4.81922)):
        groups = np.array_split(np.arange(60), g)
        plain = jackknife_variance(jac, residual, groups)
        scaled = fit_module._jackknife_spread(jac, residual, groups)
        assert plain is not None and scaled is not None
        expected = (t.ppf(0.975, g - 1) / norm.ppf(0.975)) ** 2
        np.testing.assert_allclose(scaled, plain * expected, rtol=1e-15)
        assert abs(expected - factor) < 1e-5
    assert fit_module._jackknife_spread(jac, residual, np.array_split(np.arange(60), 2)) is None
