"""identify on a robot's sensor chain: the surface offset and the force lag fitted, the gain's
uncertainty in the interval, a foot at rest compared with the rest band (issue 23, points 2-3)."""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.estimation.calibration import identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import gait
from mudforce.motions.sensor_chain import SensorChain, apply
from mudforce.steppers.simulation import simulate

W = 0.24


@pytest.fixture(scope="module")
def fine() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A 10-s gait simulated at 2 kHz along its true path (time [s], depth [m], force [N])."""
    path = gait(3, duration=10.0, rate=2000.0)
    force = simulate(path.time, path.depth, MudParameters.from_water_content(W), Foot.paper(),
                     velocity_filter="exact").force
    return path.time, path.depth, np.asarray(force)


def _trial(fine: tuple[np.ndarray, np.ndarray, np.ndarray], **chain: float) -> Trial:
    fields = {"force_noise": 0.2, "depth_noise": 3e-5, "force_bias": 0.4, "rate": 100.0, **chain}
    t, z, f = apply(*fine, SensorChain(**fields), 5)
    return Trial("chain.csv", W, t, z, f)


def test_a_surface_offset_is_fitted_not_read_as_mud(fine: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
    """The depth reads 4 mm too deep: identify finds -4 mm and the water content it finds without the offset."""
    clean = identify_water_content(_trial(fine))
    res = identify_water_content(_trial(fine, depth_offset=0.004))
    assert abs(res.depth_offset + 0.004) < 3e-4
    assert np.isfinite(res.depth_offset_stderr) and res.depth_offset_stderr > 0.0
    assert abs(res.water_content - clean.water_content) < 0.002
    assert res.low <= W <= res.high and not res.model_misses_data


def test_a_force_lag_is_fitted_and_the_gain_widens_the_interval(
        fine: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
    """A 20-ms low-pass on the force is found to within 6 ms; the 5 % gain uncertainty widens the interval."""
    trial = _trial(fine, force_lowpass=0.02)
    res = identify_water_content(trial)
    assert abs(res.force_lag - 0.02) < 0.006
    assert res.low <= W <= res.high
    bare = identify_water_content(trial, force_gain_uncertainty=0.0)
    assert res.gain_shift > 5e-4 and bare.gain_shift == 0.0
    assert res.high - res.low > bare.high - bare.low + 1e-3
    d = res.to_dict()
    assert d["force_lag_s"] == res.force_lag and d["force_gain_uncertainty"] == 0.05


def test_a_gain_the_walk_determines_is_read_and_one_well_beyond_the_uncertainty_warned(
        fine: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
    """The gait walk's force 7 % low: the gain reads 0.922 and the water content 23.96 % for 24 % (24.33 % with the gain
    left at 1, ``force_gain_uncertainty`` 0); 7.8 % is over 1.5 times the 5 % given, and warned of. 4 % high is not
    read: between the grid's 1.025 and 1.05 the two cost nearly alike, so the least is not sharp; the gain stays 1, the
    estimate 23.82 % and the interval, widened by the gain's shift, holds 24 %. Without a gain error the gain is 1."""
    assert identify_water_content(_trial(fine)).force_gain == 1.0
    low = identify_water_content(_trial(fine, force_gain=0.93))
    assert low.force_gain == pytest.approx(0.93, abs=0.012)
    assert abs(low.water_content - W) < 0.001 and low.low <= W <= low.high and not low.model_misses_data
    assert [w for w in low.warnings if w.startswith("the force reads 0.92")] == list(low.warnings) != []
    bare = identify_water_content(_trial(fine, force_gain=0.93), force_gain_uncertainty=0.0)
    assert bare.force_gain == 1.0 and bare.water_content > W + 0.003
    high = identify_water_content(_trial(fine, force_gain=1.04))
    assert high.force_gain == 1.0 and abs(high.water_content - W) < 0.003 and high.low <= W <= high.high


def test_a_foot_at_rest_is_a_band_not_a_branch() -> None:
    """One foot of the MuJoCo quadruped, its force the load MuJoCo applied: identify finds its own mud."""
    pytest.importorskip("mujoco")
    from mudforce.motions.quadruped import ROBOT_FOOT, robot_walk

    run = robot_walk("walk", 0.25, seed=1, duration=3.0)
    t, z, f = apply(run.time, run.depth, run.force_contact, SensorChain(force_noise=0.2, depth_noise=3e-5), 2)
    res = identify_water_content(Trial("robot.csv", 0.25, t, z, f), ROBOT_FOOT)
    assert res.rest_fraction > 0.2
    assert abs(res.water_content - 0.25) < 0.01
    assert res.low <= 0.25 <= res.high or res.warnings


@pytest.fixture(scope="module")
def trot() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """10 s of a MuJoCo trot in 29.47 % mud, 40-90 mm deep (seed 22's robot 2 of the sensor-chain bench): time [s],
    depth [m], the model's force [N] along the robot's path."""
    pytest.importorskip("mujoco")
    from mudforce.motions.quadruped import robot_walk

    run = robot_walk("trot", 0.2947, seed=1022036340, duration=10.0)
    return run.time, run.depth, run.force


def test_the_joint_fit_starts_from_the_scans_second_valley_too(trot: tuple[np.ndarray, np.ndarray, np.ndarray],
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """A MuJoCo trot 40-90 mm deep in 29.47 % mud sampled at 50 Hz (seed 22's robot 2 of the sensor-chain bench, 10 s
    of it): the cost over the water content has a narrow valley below the family's 30 % row and a broad one above it.
    At the scan's offset the broad one is deeper and least squares settled there, at 31.2 % (RMSE 0.88 N); from the
    second valley too, the surface offset refitted, the narrow one fits better (0.79 N) and reads the truth."""
    from mudforce.estimation.calibration import identify as module
    from mudforce.motions.quadruped import ROBOT_FOOT

    t, z, f = apply(*trot, SensorChain(force_noise=0.2, depth_noise=3e-5, rate=50.0), 3)
    trial = Trial("trot.csv", 0.2947, t, z, f)
    res = identify_water_content(trial, ROBOT_FOOT)
    assert abs(res.water_content - 0.2947) < 0.002 and res.low <= 0.2947 <= res.high
    monkeypatch.setattr(module, "_SECOND_VALLEY_RATIO", 0.0)  # one start, as before
    one = identify_water_content(trial, ROBOT_FOOT)
    assert one.water_content > 0.31 and one.rmse > res.rmse + 0.05


def test_the_gain_this_trot_determines_is_read_and_its_shift_still_reaches_the_other_valley(
        trot: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
    """The same trot at 100 Hz, its force 5 % low. Until the gain was read it was read at 31.23 %, and at 29.48 % with
    the gain undone (the gain's shift 1.75 points; scanning the coarse points alone, 1-point steps, 0.62). Now the
    least-squares cost over the gain has a sharp least: the gain reads 0.9515 and the estimate 29.473 %, the undone
    recording's 29.469 % (its own gain left at 1). A further 5 % about the gain read still moves the estimate to the
    broad valley above Table I's 30 % row (`gain_shift` 1.73 points), so the interval reaches 31.4 %."""
    from mudforce.motions.quadruped import ROBOT_FOOT

    t, z, f = apply(*trot, SensorChain(force_noise=0.2, depth_noise=3e-5), 3)
    low = identify_water_content(Trial("trot.csv", 0.2947, t, z, 0.95 * f), ROBOT_FOOT)
    undone = identify_water_content(Trial("trot.csv", 0.2947, t, z, f), ROBOT_FOOT)
    assert low.force_gain == pytest.approx(0.95, abs=0.005) and undone.force_gain == 1.0
    assert low.water_content == pytest.approx(undone.water_content, abs=0.001)
    assert low.gain_shift > 0.015 and low.high > 0.31 and low.low <= 0.2947
    assert low.to_dict()["force_gain"] == low.force_gain


def test_the_second_valley_is_a_separate_local_minimum_near_the_best() -> None:
    """The scan at 50 Hz of that robot's 30 s (RMSE per point of the fine grid, 29-32 %): the valley at 29.5 % is the
    second, 31.25 % the best; a slope down to the best has none, a dip 0.5 points off is one, a valley at over 4 times
    the best's cost is none."""
    from mudforce.estimation.calibration.identify import _second_valley

    grid = np.array([0.29, 0.2925, 0.295, 0.2975, 0.30, 0.3025, 0.305, 0.3075, 0.31, 0.3125, 0.315, 0.3175, 0.32])
    rmse = np.array([1.791, 1.225, 0.98, 1.101, 1.402, 1.216, 1.039, 0.891, 0.8, 0.795, 0.884, 1.052, 1.283])
    costs = rmse**2
    assert _second_valley(grid, costs, int(np.argmin(costs))) == 0.295
    falling = np.where(grid < 0.3075, 1.0 + (0.3075 - grid) * 100.0, costs)  # down to the best: no other minimum
    assert _second_valley(grid, falling, 9) is None
    dip = falling.copy()
    dip[7] = 0.635  # a dip at 30.75 %, 0.5 points from the best: a valley of its own
    assert _second_valley(grid, dip, 9) == 0.3075
    assert _second_valley(grid, costs * np.where(grid < 0.30, 5.0, 1.0), 9) is None  # beyond 4 times the best's cost


def test_the_bias_stderr_holds_the_refinements_move(fine: tuple[np.ndarray, np.ndarray, np.ndarray]) -> None:
    """Under 1 mm of depth noise the refinement moves the 0.4 N tare by the model's mean error: the standard error
    holds the move (-0.082 +- 0.041 N before, the truth 12 standard errors off; now +- 0.50 N)."""
    res = identify_water_content(_trial(fine, depth_noise=0.001))
    assert res.bias_method == "tared" and abs(res.bias - 0.4) > 0.2
    assert abs(res.bias - 0.4) < 1.5 * res.bias_stderr and res.bias_stderr < 0.6


@pytest.mark.parametrize(("chain", "offset", "lag"), [
    ({}, 0.0, 0.0),
    ({"depth_offset": 0.004}, -0.004, 0.0),
    ({"force_lowpass": 0.02}, 0.0, 0.02),
    ({"depth_noise": 0.001}, 0.0, 0.0),
    ({"force_delay": 0.01}, 0.0, 0.01),
])
def test_the_nuisances_standard_errors_hold_their_errors(fine: tuple[np.ndarray, np.ndarray, np.ndarray],
                                                          chain: dict[str, float], offset: float, lag: float) -> None:
    """The surface offset and the force lag each within three of their standard errors of the truth (least squares'
    own read them to micrometres and microseconds: a 10-ms delay's offset 11 of them off, the clean walk's lag 1.5 of
    a 0.04-ms error). A pure delay is no first-order low-pass: this walk reads 10 ms of it as a lag of 0.19 ms, and
    the same fit with a delay in its place reads 10.6 ms; the lag's standard error holds the difference (+-10.4 ms:
    what the recording leaves open of the lag's shape). The water content is the same with or without these."""
    res = identify_water_content(_trial(fine, **chain))
    assert 0.0 < res.depth_offset_stderr < 1e-3 and abs(res.depth_offset - offset) < 3.0 * res.depth_offset_stderr
    assert 0.0 < res.force_lag_stderr < 0.015 and abs(res.force_lag - lag) < 3.0 * res.force_lag_stderr
    assert res.low <= W <= res.high


def test_the_issues_gain_case_on_the_lab_protocol_reads_the_gain() -> None:
    """Issue 23's case: ``mudforce synth --water-content 31% --repeats 1 --seed 2``, the force times 1.05. It read
    29.81 % [29.56, 30.06] when the issue was filed; the gain reads 1.05 and the water content 31.0 % at each speed.
    Without the gain error nothing is read and the estimate is the same as at ``force_gain_uncertainty`` 0."""
    from mudforce.estimation.calibration.synth import synthesize

    ds = synthesize(water_contents=[0.31], repeats=1, seed=2)
    for t in ds.trials:
        res = identify_water_content(Trial(t.name, t.water_content, t.time, t.depth, 1.05 * t.force), ds.foot)
        assert res.force_gain == pytest.approx(1.05, abs=0.003) and abs(res.water_content - 0.31) < 0.001
        assert res.low <= 0.31 <= res.high
        clean = identify_water_content(t, ds.foot)
        bare = identify_water_content(t, ds.foot, force_gain_uncertainty=0.0)
        assert clean.force_gain == 1.0 and clean.water_content == bare.water_content


def test_the_offset_s_standard_error_holds_what_a_delay_in_the_lag_s_place_reads() -> None:
    """A 5-ms delay on a wet walk (the sensor-chain bench's seed-48 gait walk 0, row "delay 5 ms": W 31.5 %, 30 s at
    100 Hz) is read as a low-pass of about nothing, and the surface moves by the delay times the touchdown's speed:
    -0.083 mm for none. With a delay in the lag's place the fit explains the data as well and reads another offset;
    that move counts in the offset's standard error (+-0.096 mm; +-0.025 before, 3.3 of them off)."""
    rng = np.random.default_rng([48, 1, 0])
    w = float(rng.uniform(0.15, 0.35))
    path = gait(int(rng.integers(0, 2**31)), duration=30.0, rate=2000.0)
    force = simulate(path.time, path.depth, MudParameters.from_water_content(w), Foot.paper(),
                     velocity_filter="exact").force
    chain = SensorChain(force_noise=0.2, depth_noise=3e-5, force_bias=-0.4426441032329733, rate=100.0,
                        force_delay=0.005)
    t, z, f = apply(path.time, path.depth, np.asarray(force), chain, 552491422)
    res = identify_water_content(Trial("walk.csv", w, t, z, f))
    assert abs(res.depth_offset + 0.0825e-3) < 0.002e-3  # measured -0.0825 mm
    assert abs(res.depth_offset) < 3.0 * res.depth_offset_stderr  # measured 0.86 of them
    assert res.low <= w <= res.high
