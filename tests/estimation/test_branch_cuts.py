"""The general path on what a robot's foot does between two samples (issue 23, point 4).

A suction cut off out of the mud by a downward flick between two samples (the foot rising over the
step): the force shows it, the depth cannot. And the force noise measured where the force is simple.
"""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.estimation.calibration import identify_water_content, prepare_trial
from mudforce.estimation.calibration.branches import CUT, estimate_force_noise, label_branches
from mudforce.estimation.calibration.dataset import Trial
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.sensor_chain import SensorChain, apply
from mudforce.steppers.simulation import simulate

W = 0.25


def _steps_with_flicks() -> tuple[np.ndarray, np.ndarray]:
    """Four steps at 2 kHz: down at 60 mm/s to 20 mm, hold 0.15 s, up at 120 mm/s to -12 mm (the neck breaks),
    rise at 4 mm/s, a 1.1-ms flick down at 6 mm/s (0.007 mm: a quarter of the depth noise), then lift off."""
    corners = [(0.0, -0.01)]
    t, z = 0.0, -0.01
    for k in range(4):
        for duration, speed in (((0.02 - z) / 0.06, 0.06), (0.15, 0.0), ((0.032) / 0.12, -0.12),
                                (0.0453 + 0.01 * k, -0.004), (0.0011, 0.006), (0.08, -0.05), (0.1, 0.0)):
            t, z = t + duration, z + duration * speed
            corners.append((t, z))
    tc, zc = np.array(corners).T
    fine = np.arange(0.0, tc[-1], 5e-4)
    return fine, np.interp(fine, tc, zc)


@pytest.fixture(scope="module")
def recording() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model's force along the fine path, sampled at 100 Hz with 0.2 N and 30 um of noise."""
    t, z = _steps_with_flicks()
    force = np.asarray(simulate(t, z, MudParameters.from_water_content(W), Foot.paper(),
                                velocity_filter="exact").force)
    assert force[z < 0.0].min() < -5.0  # a suction of several newtons out of the mud, which the flick cuts
    tt, zz, ff = apply(t, z, force, SensorChain(force_noise=0.2, depth_noise=3e-5, rate=100.0), 3)
    return tt, zz, ff


def test_a_suction_cut_between_samples_is_an_upward_switch(recording: tuple[np.ndarray, ...]) -> None:
    """Each flick is labelled CUT from the force alone, and the model is free after it (the step starts out of
    the mud). Before (no force evidence out of the mud) the suction ran on: misfit ratio 7.2, flagged."""
    tt, zz, ff = recording
    prepared = prepare_trial(Trial("flicks.csv", W, tt, zz, ff))
    labels = label_branches(tt, zz, ff, depth_noise=prepared.depth_noise, force_noise=prepared.force_noise)
    cuts = np.flatnonzero(labels == CUT)
    assert cuts.size == 4
    assert np.all(prepared.depth[cuts] < 0.0) and np.all(prepared.depth[cuts + 1] < 0.0)
    res = identify_water_content(Trial("flicks.csv", W, tt, zz, ff))
    assert not res.warnings and res.misfit_ratio < 1.1  # measured 0.81
    assert res.low <= W <= res.high and abs(res.water_content - W) < 0.003


def test_force_noise_from_where_the_force_is_simple() -> None:
    """A force that flicks between two levels at every other sample (a robot foot at rest, the rest band's
    edges between the samples) fools the third differences; the samples clear of the mud do not."""
    rng = np.random.default_rng(5)
    t = np.arange(2000) * 0.01
    clear = t < 5.0
    f = np.where(clear, 0.0, 20.0 + 15.0 * (rng.random(t.size) < 0.5)) + 0.2 * rng.standard_normal(t.size)
    assert estimate_force_noise(t, f) > 1.0  # measured 4.8 for 0.2
    assert abs(estimate_force_noise(t, f, where=clear) / 0.2 - 1.0) < 0.15
    # clear of the mud a suction may still decay (here one every 0.25 s, 50 ms): only the free level's samples
    # count (measured 0.215; 0.251 from all the clear samples)
    decays = np.where(clear, -10.0 * np.exp(-(t % 0.25) / 0.05), 0.0)
    assert abs(estimate_force_noise(t, f + decays, where=clear) / 0.2 - 1.0) < 0.1
    # a smooth force elsewhere: the estimate over all samples stands (more of them)
    smooth = np.where(clear, 0.0, 20.0 * np.sin(t)) + 0.2 * rng.standard_normal(t.size)
    assert estimate_force_noise(t, smooth, where=clear) == estimate_force_noise(t, smooth)


def test_a_cut_is_found_when_a_settled_sample_reads_three_noises_off() -> None:
    """The sensor-chain bench's MuJoCo run 2 of seed 70 (100 Hz): a suction of 3.8 N cut between two samples, the
    third sample after it 3.1 force noises off the free level by chance. Within three noises each, the cut was missed
    and the model clung to the raised foot through its swing; within four it is found, and not with that sample 4.5
    noises off (then no cut: below the six noises a force must be off before a cut)."""
    from mudforce.estimation.calibration.branches import _cut_steps, _jump_statistic

    noise = 0.19
    z = np.concatenate([[-0.3, -0.36, -0.74, -3.1, -6.8], -11.0 - np.arange(25.0)]) * 1e-3
    t = np.arange(z.size) * 0.01
    f = np.concatenate([[-3.10, -3.80, 0.03, -0.21, 3.1 * noise], 0.1 * noise * np.sin(np.arange(25.0))])
    cut = _cut_steps(z, f, _jump_statistic(t, f, noise), 3e-5, noise)
    assert np.flatnonzero(cut).tolist() == [1]
    g = f.copy()
    g[4] = 4.5 * noise  # not settled
    assert not _cut_steps(z, g, _jump_statistic(t, g, noise), 3e-5, noise).any()
