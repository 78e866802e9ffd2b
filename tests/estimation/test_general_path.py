"""Estimation from trials of any motion: branch labels, denoised depth, noise, bias, fit and identify on gaits."""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.estimation.calibration import fit_condition, identify_water_content, prepare_trial
from mudforce.estimation.calibration.branches import creep_withdrawals, estimate_force_noise, label_branches
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.models import CHEN2024
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import walk
from mudforce.steppers.simulation import simulate


def _trial(w: float, seed: int, **kw: object) -> tuple[Trial, object]:
    path = walk(w, seed=seed, **kw)  # type: ignore[arg-type]
    return Trial(f"walk{seed}.csv", w, path.time, path.depth, path.force), path


@pytest.mark.parametrize("jitter", [0.0, 0.3])
def test_force_noise_is_measured_without_the_model(jitter: float) -> None:
    path = walk(0.2, seed=4, duration=15.0, force_noise=0.3, jitter=jitter)
    assert abs(estimate_force_noise(path.time, path.force) / 0.3 - 1.0) < 0.1
    # a constant offset and the model's jumps do not move it
    assert abs(estimate_force_noise(path.time, path.force + 50.0) / 0.3 - 1.0) < 0.1


@pytest.mark.parametrize(("w", "seed", "start_below", "jitter"),
                         [(0.18, 1, False, 0.0), (0.25, 2, True, 0.3), (0.33, 3, False, 0.3)])
def test_denoised_depth_drives_the_model_to_the_true_force(w: float, seed: int, start_below: bool,
                                                           jitter: float) -> None:
    """Reversals and necking at the right samples: the force on the denoised depth is the true force within noise."""
    trial, path = _trial(w, seed, duration=15.0, force_noise=0.2, bias=0.5, start_below=start_below, jitter=jitter)
    prepared = prepare_trial(trial)
    assert prepared.motion is None  # a gait is not a protocol
    force = CHEN2024.force(trial.time, prepared.depth, MudParameters.from_water_content(w).as_array(), Foot.paper())
    error = force - path.force_true  # type: ignore[attr-defined]
    assert np.sqrt(np.mean(error**2)) < 0.25
    assert prepared.bias_estimated == start_below
    if not start_below:
        assert abs(prepared.bias - 0.5) < 0.2


def _stance(rise: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A foot at 1 kHz: touchdown, a bounce, 0.2 s of stance rising by ``rise`` [m], withdrawal; the true model force,
    and the force a stuck foot measures (constant in the rest band through the stance, as MuJoCo's carries it)."""
    t = np.arange(500) * 1e-3
    z = np.interp(t, [0.0, 0.062, 0.074, 0.110, 0.286, 0.33, 0.5],
                  [-0.005, 0.0031, 0.00297, 0.00299, 0.00299 - rise, -0.010, -0.010])
    true = np.asarray(simulate(t, z, MudParameters.from_water_content(0.16), Foot.paper(),
                               velocity_filter="exact").force)
    measured = true.copy()
    measured[(t > 0.074) & (t < 0.286)] = true[75]
    return t, z, true, measured


def test_a_stance_that_creeps_up_is_read_as_a_withdrawal() -> None:
    """A standing foot that rises by 80 um over 0.2 s (0.4 um a step under 30 um of depth noise): the step-by-step
    labels read rest until the foot lifts clearly, and the model then withdrew from the wrong depth (its force 2.8-2.9 N
    off during the withdrawal, seeds 0-7); the hinge through the stance finds the creep (docs/estimation.md)."""
    t, z, true, measured = _stance(8e-5)
    params = MudParameters.from_water_content(0.16).as_array()
    lifting = (t > 0.29) & (t < 0.33)
    for seed in range(3):
        rng = np.random.default_rng(seed)
        zn, fn = z + 3e-5 * rng.standard_normal(t.size), measured + 0.2 * rng.standard_normal(t.size)
        labels = label_branches(t, zn, fn, depth_noise=3e-5, force_noise=0.2)
        assert np.all(labels[120:280] == 1)  # read step by step: rest, on the intrusion branch
        creep = creep_withdrawals(t, zn, labels, 3e-5)
        first = int(np.argmax(creep[80:286] == -1)) + 80
        assert 0.105 <= t[first] <= 0.16 and np.all(creep[first:286] == -1)
        prepared = prepare_trial(Trial("creep", 0.16, t, zn, fn), depth_noise=3e-5, protocol=False)
        force = CHEN2024.force(t, prepared.depth, params, Foot.paper())
        assert np.max(np.abs(force - true)[lifting]) < 0.8


def test_a_still_stance_stays_at_rest() -> None:
    """The same stance without the rise: no creep read, in 30 noise draws (the hinge's best slope through noise
    stays under CREEP_SIGMAS standard errors)."""
    t, z, _, measured = _stance(0.0)
    for seed in range(30):
        rng = np.random.default_rng(seed)
        zn, fn = z + 3e-5 * rng.standard_normal(t.size), measured + 0.2 * rng.standard_normal(t.size)
        labels = label_branches(t, zn, fn, depth_noise=3e-5, force_noise=0.2)
        assert np.array_equal(creep_withdrawals(t, zn, labels, 3e-5), labels)


def test_noiseless_gait_is_followed_exactly() -> None:
    trial, path = _trial(0.25, 5, duration=10.0, force_noise=0.0, depth_noise=0.0, start_below=True)
    prepared = prepare_trial(trial)
    assert np.array_equal(prepared.depth, trial.depth)
    force = CHEN2024.force(trial.time, prepared.depth, MudParameters.from_water_content(0.25).as_array(), Foot.paper())
    assert np.max(np.abs(force - path.force_true)) < 1e-9  # type: ignore[attr-defined]
    result = identify_water_content(trial)
    assert abs(result.water_content - 0.25) < 1e-4
    assert not result.model_misses_data and not result.warnings


def test_identify_on_a_stepping_trajectory() -> None:
    """The issue's example: 13 s of stepping at W = 22%, force noise 0.2 N, bias 0.5 N."""
    trial, _ = _trial(0.22, 1, duration=13.0, force_noise=0.2, bias=0.5)
    result = identify_water_content(trial)
    assert abs(result.water_content - 0.22) < 0.005
    assert result.interval[0] <= 0.22 <= result.interval[1]
    assert (result.low, result.high) == result.interval
    d = result.to_dict()
    assert {"nearest_water_content", "misfit_ratio", "model_misses_data", "off_family_N", "noise_floor_N",
            "force_noise_N", "bias_N", "bias_method"} <= set(d)
    assert abs(d["force_noise_N"] - 0.2) < 0.03  # type: ignore[operator]


def test_identify_says_when_the_data_are_off_the_family() -> None:
    """A foot twice as large as assumed: the force is off the family, and identify says so."""
    big = Foot.cuboid(0.072, 0.054)
    path = walk(0.25, seed=2, duration=10.0, force_noise=0.2, foot=big)
    result = identify_water_content(Trial("big.csv", 0.25, path.time, path.depth, path.force), Foot.paper())
    assert result.model_misses_data and result.off_family > 1.0
    assert any("off the Table I family" in w for w in result.warnings)


def test_fit_two_gaits_reaches_the_noise_and_the_parameters() -> None:
    trials = [_trial(0.25, s, duration=12.0, force_noise=0.2, bias=0.5, start_below=s == 12)[0] for s in (11, 12)]
    fit = fit_condition(trials, seed=0)
    truth = MudParameters.from_water_content(0.25).to_dict()
    for name in ("alpha", "beta", "k_m_w", "sigma_y", "k_m_i"):
        assert abs(fit.parameters[name] / truth[name] - 1.0) < 0.1, name
    assert abs(fit.force_noise - 0.2) < 0.03
    assert fit.misfit_ratio < 1.5 and not fit.model_misses_data
    assert not any("no trial necked" in w for w in fit.warnings)
    assert [t.bias_method for t in fit.trials] == ["tared", "estimated"]
    for t in fit.trials:
        assert abs(t.bias - 0.5) < 0.1 and 0 < t.bias_stderr < 0.1


def test_identify_refuses_a_constant_force() -> None:
    path = walk(0.25, seed=1, duration=6.0)
    from mudforce.errors import InputError

    with pytest.raises(InputError, match="force is the same in every sample"):
        identify_water_content(Trial("zero.csv", 0.25, path.time, path.depth, np.zeros_like(path.time)))
