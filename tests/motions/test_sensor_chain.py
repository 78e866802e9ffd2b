"""The sensor chain (mudforce.motions.sensor_chain) does what each corruption says, reproducibly, and refuses bad
values;
the MuJoCo quadruped (mudforce.motions.quadruped) makes a foot path with touchdowns in the mud."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import gait
from mudforce.motions.sensor_chain import SensorChain, apply, drift_path
from mudforce.steppers.simulation import simulate


def _signal(n: int = 2001, rate: float = 1000.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(5)
    t = np.arange(n) / rate
    return t, 0.01 * np.sin(2.0 * t) + 1e-4 * rng.standard_normal(n), 20.0 + 5.0 * rng.standard_normal(n)


def test_a_clean_chain_returns_copies_of_its_input() -> None:
    t, z, f = _signal()
    out = apply(t, z, f, SensorChain(), seed=0)
    assert SensorChain().is_clean
    for a, b in zip(out, (t, z, f), strict=True):
        assert np.array_equal(a, b) and a is not b


def test_gain_scales_bias_offsets_and_offset_shifts_depth_exactly() -> None:
    t, z, f = _signal()
    _, zo, fo = apply(t, z, f, SensorChain(force_gain=1.05, force_bias=0.5, depth_offset=-0.002), seed=3)
    assert np.array_equal(fo, 1.05 * f + 0.5)
    assert np.array_equal(zo, z + -0.002)


def test_a_delay_shifts_the_force_by_its_samples_holding_the_first() -> None:
    t, z, f = _signal()
    _, _, fo = apply(t, z, f, SensorChain(force_delay=0.005), seed=0)
    np.testing.assert_allclose(fo[5:], f[:-5], rtol=1e-9, atol=1e-9)
    assert np.all(fo[:5] == f[0])


def test_the_lowpass_has_dc_gain_one_the_exact_step_response_and_a_ramp_lag_of_tau() -> None:
    tau, h = 0.01, 0.001
    t = np.arange(201) * h
    one = np.ones_like(t)
    _, _, fo = apply(t, 0 * t, 3.0 * one, SensorChain(force_lowpass=tau), seed=0)
    assert np.array_equal(fo, 3.0 * one)  # DC gain 1, started in steady state
    step = np.minimum(t / h, 1.0)  # 0 at t=0, 1 from the next sample on (linear between)
    _, _, fo = apply(t, 0 * t, step, SensorChain(force_lowpass=tau), seed=0)
    after = t[1:]
    exact = 1.0 - tau / h * (math.exp(h / tau) - 1.0) * np.exp(-after / tau)  # the continuous filter's answer
    np.testing.assert_allclose(fo[1:], exact, rtol=0, atol=1e-12)
    assert abs(fo[11] - (1.0 - math.exp(-1.0))) < 0.06  # about 63 % one tau after the step
    _, _, fo = apply(t, 0 * t, t, SensorChain(force_lowpass=tau), seed=0)
    np.testing.assert_allclose(fo[-1], t[-1] - tau * (1.0 - math.exp(-t[-1] / tau)), rtol=1e-12)


def test_drift_starts_at_zero_and_stays_within_a_quarter_of_its_size_from_the_ramp() -> None:
    t = np.linspace(0.0, 60.0, 6001)
    chain = SensorChain(drift=0.002, drift_time=30.0)
    ramp = 0.002 * t / 30.0
    for seed in range(20):
        d = drift_path(t, chain, seed)
        assert d[0] == 0.0
        assert np.max(np.abs(d - ramp)) <= 0.002 / 4.0 + 1e-15
    down = drift_path(t, SensorChain(drift=-0.002, drift_time=30.0), 0)
    assert down[-1] < -0.002 * 1.5
    _, zo, _ = apply(t, 0 * t, 0 * t, chain, seed=4)
    assert np.array_equal(zo, drift_path(t, chain, 4))
    # IndexError, ValueError, AttributeError and TypeError; a NaN time gave a NaN drift
    for args, words in ((([], chain, 0), "time must be 1-D"), ((["0", "1"], chain, 0), "array of real numbers"),
                        (([0.0, 1.0], "chain", 0), "chain must be a SensorChain"), (([[0.0, 1.0]], chain, 0), "1-D"),
                        (([0.0, math.nan], chain, 0), "time is not finite")):
        with pytest.raises(InputError, match=words):
            drift_path(*args)  # type: ignore[arg-type]


def test_resampling_samples_the_fine_model_not_the_model_of_the_samples() -> None:
    params, foot = MudParameters.from_water_content(0.25), Foot.paper()
    path = gait(3, duration=6.0, rate=2000.0)
    fine = simulate(path.time, path.depth, params, foot, velocity_filter="exact").force
    t, z, f = apply(path.time, path.depth, fine, SensorChain(rate=50.0), seed=0)
    assert t.size == 301 and np.allclose(t, np.arange(301) / 50.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(f, fine[::40], rtol=0, atol=1e-6)
    np.testing.assert_allclose(z, path.depth[::40], rtol=0, atol=1e-12)
    coarse = simulate(t, z, params, foot, velocity_filter="exact").force
    assert np.max(np.abs(coarse - f)) > 1.0  # at 50 Hz the model of the samples is not the model of the true path


def test_the_same_seed_gives_the_same_bytes_and_each_corruption_draws_its_own_stream() -> None:
    t, z, f = _signal()
    chain = SensorChain(depth_noise=3e-4, force_noise=0.2, drift=0.002, rate=200.0)
    a, b = apply(t, z, f, chain, seed=11), apply(t, z, f, chain, seed=11)
    assert all(x.tobytes() == y.tobytes() for x, y in zip(a, b, strict=True))
    c = apply(t, z, f, chain, seed=12)
    assert not np.array_equal(a[1], c[1]) and not np.array_equal(a[2], c[2])
    no_force_noise = apply(t, z, f, SensorChain(depth_noise=3e-4, drift=0.002, rate=200.0), seed=11)
    assert np.array_equal(no_force_noise[1], a[1])  # the depth's draws do not depend on the force's


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"force_gain": 3.0}, "force_gain must be within [0.5, 2]"),
    ({"force_gain": True}, "force_gain must be a number"),
    ({"depth_offset": 0.5}, "depth_offset must be within [-0.1, 0.1] m"),
    ({"depth_noise": -1e-4}, "depth_noise must be within [0, 0.01] m"),
    ({"force_delay": math.nan}, "force_delay must be within"),
    ({"force_lowpass": 2.0}, "force_lowpass must be within [0, 1] s"),
    ({"drift_time": 0.0}, "drift_time must be within [1, 3600] s"),
    ({"rate": 0.5}, "rate must be within [1, 100000] Hz"),
    ({"force_noise": "0.2N"}, "force_noise must be a number [N]"),
])
def test_bad_chain_values_are_refused_in_one_line(kwargs: dict[str, object], words: str) -> None:
    with pytest.raises(InputError) as info:
        SensorChain(**kwargs)  # type: ignore[arg-type]
    assert words in str(info.value) and "\n" not in str(info.value)


def test_bad_recordings_are_refused_in_one_line_and_the_input_is_left_as_it_was() -> None:
    t, z, f = _signal()
    kept = f.copy()
    for args, words in (
        ((t, z, f, SensorChain(rate=5000.0), 0), "finer than the clean recording's 1000 Hz"),
        ((t[::-1], z, f, SensorChain(), 0), "expected strictly increasing time"),  # simulate's words
        ((t * 1e-200, z, f, SensorChain(), 0), "the time step before sample 1 (t = 1e-203 s) is 1e-203 s; expected"),
        ((t, z[:-1], f, SensorChain(), 0), "of one length"),
        ((t, z, np.where(t > 1, np.nan, f), SensorChain(), 0), "force must be finite [N]; sample 1001"),
        ((t, z, f, {"rate": 50.0}, 0), "chain must be a SensorChain"),
        ((t, z, f, SensorChain(), -1), "seed"),
        ((t[:3], z[:3], f[:3], SensorChain(rate=100.0), 0), "fewer than 2 samples"),
    ):
        with pytest.raises(InputError) as info:
            apply(*args)  # type: ignore[arg-type]
        assert words in str(info.value) and "\n" not in str(info.value)
    assert np.array_equal(f, kept)


def test_a_recording_of_text_booleans_or_huge_values_is_refused_not_read_or_overflowed() -> None:
    # numpy parsed strings and read booleans as 0 and 1; 1e308 N times a gain of 2 came back as inf
    for args, words in (
        ((["0", "1"], [0.0, 0.0], [1.0, 2.0]), "time must be an array of real numbers"),
        (([0.0, 1.0], [True, False], [1.0, 2.0]), "depth must be an array of real numbers"),
        (([0.0, 1.0], [0.0, 0.0], [1e308, 1e308]), "force must be within +-1e+07 N; sample 0"),
        (([0.0, 1.0], [0.0, 1e300], [1.0, 2.0]), "depth must be within +-100 m; sample 1"),
        (([0.0, 1e300], [0.0, 0.0], [1.0, 2.0]), "time at sample 1 (1e+300 s) is beyond +-1e+09 s"),
    ):
        with pytest.raises(InputError) as info:
            apply(*args, SensorChain(force_gain=2.0), 0)
        assert words in str(info.value) and "\n" not in str(info.value)


def test_the_quadruped_foot_strikes_the_mud_and_repeats_bit_for_bit() -> None:
    pytest.importorskip("mujoco", reason="the quadruped needs MuJoCo: pip install 'mudforce[mujoco]'")
    from mudforce.motions.quadruped import robot_walk

    run = robot_walk("trot", 0.25, seed=2, duration=0.8)
    assert run.time.size == 1601 and run.time[1] == 0.0005
    assert -0.03 < run.depth[0] <= -0.0099  # starts above the surface (the lowest foot 10 mm above it)
    assert run.depth.max() > 0.005  # struck and sank
    down = np.flatnonzero(run.depth > 0.0)[0]
    speed = (run.depth[down] - run.depth[down - 1]) / 0.0005
    assert speed > 0.05  # an impact: it enters the mud fast
    assert np.all(run.force[run.depth < 0.0] <= 0.0) and run.force.max() > 10.0
    assert np.all(run.force_contact[:down] == 0.0)
    again = robot_walk("trot", 0.25, seed=2, duration=0.8)
    assert again.depth.tobytes() == run.depth.tobytes() and again.force_contact.tobytes() == run.force_contact.tobytes()
    with pytest.raises(InputError, match="gait must be one of walk, walk-fast, trot, trot-fast, bound"):
        robot_walk("gallop")
    with pytest.raises(InputError, match=r"gait must be one of .*, got \['trot'\]"):  # was TypeError: unhashable
        robot_walk(["trot"])  # type: ignore[arg-type]


def test_the_synthesizers_take_a_chain_without_its_noise_and_refuse_one_with_it() -> None:
    from mudforce.estimation.calibration.synth import synthesize_gait

    with pytest.raises(InputError, match="depth_noise, force_noise, force_bias and rate as 0 and None"):
        synthesize_gait(chain=SensorChain(force_noise=0.1), repeats=1, duration=2.0)
    with pytest.raises(InputError, match="jitter cannot go with a sensor chain"):
        synthesize_gait(chain=SensorChain(force_gain=1.05), repeats=1, duration=2.0, jitter=0.2)
    data = synthesize_gait(chain=SensorChain(force_gain=1.05), repeats=1, duration=2.0, rate=50.0, seed=1)
    assert data.trials[0].time.size == 101 and data.extra["synthetic"]["sensor_chain"]["force_gain"] == 1.05
