"""The default branch rule tells the depth's noise from its motion (mudforce.model.velocity.analyse_depth_noise).

Clean input of any shape and rate gets the paper's exact rule, so the ``auto`` force equals the exact one;
noisy input gets the filter; the choice and the noise assumed are reported.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudforce as mf
from mudforce import InputError, VelocityFilter, simulate
from mudforce.model.velocity import (
    MAX_NOISE_ORDER,
    NOISE_FLOOR_M,
    SLOWEST_MOTION,
    analyse_depth_noise,
    choose_velocity_filter,
    describe_velocity_rule,
    estimate_depth_noise,
)
from mudforce.motions.gait import gait

W20 = mf.MudParameters.from_water_content(0.20)


def _sine_record() -> tuple[np.ndarray, np.ndarray]:
    """The issue's case: a 3.14 s sine of 10 mm about 20 mm, 100 Hz, depths printed to 12 digits."""
    i = np.arange(600)
    time = np.array([float(f"{k / 100:.2f}") for k in i])
    depth = np.array([float(f"{0.02 + 0.01 * math.sin(2 * math.pi * k / 314):.12g}") for k in i])
    return time, depth


def test_a_clean_sine_gets_the_exact_rule() -> None:
    """Before: the line through three samples read the sine's curvature as 1.8 um of noise, and the filter
    gave 209 N at 0.80 s where the model gives 5.14 N."""
    t, z = _sine_record()
    auto = simulate(t, z, W20)
    exact = simulate(t, z, W20, velocity_filter="exact")
    assert auto.velocity_filter.is_exact
    assert auto.depth_noise is not None and auto.depth_noise.clean
    assert auto.depth_noise.std <= NOISE_FLOOR_M
    np.testing.assert_array_equal(auto.force, exact.force)
    assert auto.force[80] == pytest.approx(5.143, abs=1e-3)
    assert exact.depth_noise is None  # given, not chosen


@st.composite
def _smooth_motions(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """Smooth motions resolved by their sampling: up to three sines below a tenth of the rate, a
    minimum-jerk or a polynomial stroke, 20 Hz to 1 kHz, optionally jittered time stamps."""
    rate = draw(st.sampled_from([20.0, 50.0, 100.0, 333.0, 1000.0]))
    duration = draw(st.floats(2.0, 8.0))
    n = int(duration * rate)
    t = np.arange(n) / rate
    jitter = draw(st.sampled_from([0.0, 0.2]))
    if jitter:
        t = t + np.random.default_rng(draw(st.integers(0, 99))).uniform(-jitter, jitter, n) / rate
    kind = draw(st.sampled_from(["sines", "min-jerk", "polynomial"]))
    s = (t - t[0]) / (t[-1] - t[0])
    if kind == "sines":
        z = np.full(n, draw(st.floats(-0.01, 0.03)))
        for _ in range(draw(st.integers(1, 3))):
            f = draw(st.floats(0.05, min(5.0, rate / 10)))
            z = z + draw(st.floats(1e-3, 1e-2)) * np.sin(2 * np.pi * f * t + draw(st.floats(0.0, 6.0)))
    elif kind == "min-jerk":
        z = draw(st.floats(-0.02, 0.0)) + draw(st.floats(0.01, 0.05)) * (10 * s**3 - 15 * s**4 + 6 * s**5)
    else:
        c = draw(st.lists(st.floats(-0.03, 0.03), min_size=2, max_size=6))
        z = np.polyval(np.array(c), s)
    return t, z


@settings(max_examples=int(os.environ.get("MUDFORCE_EXAMPLES", "40")), deadline=None)
@given(_smooth_motions())
def test_clean_smooth_input_of_any_shape_and_rate_gets_the_exact_force(motion: tuple[np.ndarray, np.ndarray]) -> None:
    t, z = motion
    auto = simulate(t, z, W20)
    exact = simulate(t, z, W20, velocity_filter="exact")
    assert auto.depth_noise is not None and auto.depth_noise.clean, auto.depth_noise
    peak = max(1.0, float(np.max(np.abs(exact.force))))
    assert np.max(np.abs(auto.force - exact.force)) <= 1e-9 * peak


@pytest.mark.parametrize("rate", [20.0, 50.0, 100.0, 1000.0])
@pytest.mark.parametrize("seed", [0, 1])
def test_clean_gaits_with_kinks_and_sway_are_clean(rate: float, seed: int) -> None:
    """A gait: touchdowns and lift-offs (kinks every few samples at 20 Hz), stances with sway, jitter."""
    g = gait(seed, duration=10.0, rate=rate, jitter=0.2)
    noise = analyse_depth_noise(g.time, g.depth)
    assert noise.clean, noise
    noisy = analyse_depth_noise(g.time, g.depth + np.random.default_rng(seed).normal(0.0, 3e-5, g.depth.size))
    assert noisy.white and 0.8 < noisy.std / 3e-5 < 2.0, noisy


@pytest.mark.parametrize("sigma", [1e-6, 3e-5, 1e-3])
def test_noise_on_a_curved_motion_is_found_and_measured(sigma: float) -> None:
    """Noise under a 1 Hz sine of 10 mm at 100 Hz: the curvature swamps the order-2 residual at small sigma,
    so the estimate comes from higher orders, where the motion has fallen below the noise."""
    t = np.arange(1000) / 100.0
    z = 0.01 + 0.01 * np.sin(2 * np.pi * t) + np.random.default_rng(3).normal(0.0, sigma, t.size)
    noise = analyse_depth_noise(t, z)
    assert noise.white
    assert noise.std == pytest.approx(sigma, rel=0.2)
    assert (noise.order > 2) == (sigma < 1e-5)
    vf, _ = choose_velocity_filter(t, z)
    assert vf == VelocityFilter.for_noise(noise.std, 0.01)
    assert not vf.is_exact


def test_white_noise_alone_is_measured_at_order_two() -> None:
    """On a piecewise-linear motion (the paper's protocol) the estimate is the line through three samples,
    as before, value for value."""
    t, z = mf.Protocol.paper().sample()
    noisy = z + np.random.default_rng(5).normal(0.0, 5e-5, z.size)
    noise = analyse_depth_noise(t, noisy)
    assert noise.white and noise.order == 2
    h0, h1 = t[1:-1] - t[:-2], t[2:] - t[1:-1]
    r = noisy[2:] - (noisy[1:-1] + (noisy[1:-1] - noisy[:-2]) * (h1 / h0))
    assert noise.std == 1.4826 * float(np.median(np.abs(r - np.median(r)))) / math.sqrt(6.0)
    assert estimate_depth_noise(t, noisy) == noise.std


def test_short_and_long_records() -> None:
    t = np.arange(10) * 0.01
    assert analyse_depth_noise(t, np.random.default_rng(0).normal(0, 1e-3, 10)).clean  # too few to tell
    t = np.arange(1_000_000) * 1e-3
    z = 0.01 * np.sin(t) + np.random.default_rng(1).normal(0.0, 3e-5, t.size)
    noise = analyse_depth_noise(t, z)  # a subset of runs of consecutive samples
    assert noise.white and noise.std == pytest.approx(3e-5, rel=0.05)
    assert analyse_depth_noise(t, 0.01 * np.sin(t)).clean
    assert MAX_NOISE_ORDER >= 6


def test_the_choice_is_reported() -> None:
    t, z = mf.Protocol.paper().sample()
    res = simulate(t, z + np.random.default_rng(0).normal(0.0, 5e-5, z.size), W20)
    assert res.depth_noise is not None and res.depth_noise.white
    text = describe_velocity_rule(res.velocity_filter, res.depth_noise)
    assert text.startswith("filtered (secant over 10 steps") and "depth noise 0.0498 mm (white, from order-2" in text
    clean = simulate(t, z, W20)
    assert describe_velocity_rule(clean.velocity_filter, clean.depth_noise).startswith("exact")


def test_small_noise_gets_a_short_window() -> None:
    """The window is the shortest whose deadband is at most 1 mm/s: small noise is not delayed by 0.1 s."""
    assert VelocityFilter.for_noise(5e-5, 0.01).window == 10  # motion capture: the whole 0.1 s
    small = VelocityFilter.for_noise(1e-6, 0.01)
    assert small.window == 1
    assert small.deadband == pytest.approx(5 * math.sqrt(2) * 1e-6 / 0.01)
    mid = VelocityFilter.for_noise(5e-6, 0.01)
    assert mid.window == math.ceil(5 * math.sqrt(2) * 5e-6 / (0.01 * SLOWEST_MOTION))
    assert mid.deadband <= SLOWEST_MOTION


@pytest.mark.parametrize(("time", "depth", "match"), [
    (np.arange(20.0), np.zeros(19), "one length"),
    (np.arange(20.0), np.where(np.arange(20) == 7, np.nan, 0.0), "finite.*sample 7"),
    (np.r_[np.arange(10.0), np.arange(10.0)], np.zeros(20), "strictly increasing"),
    (np.zeros((4, 5)), np.zeros((4, 5)), "1-D"),
])
def test_bad_records_are_refused(time: np.ndarray, depth: np.ndarray, match: str) -> None:
    with pytest.raises(InputError, match=match):
        estimate_depth_noise(time, depth)




@pytest.mark.parametrize(("scale", "words"), [
    # overflowed
    (1e-200, "the time step before sample 1 (t = 1e-203 s) is 1e-203 s; expected steps within [1e-09, 1000] s"),
    (-1.0, "time goes backwards at sample 1"),
    (1e7, "the time step before sample 1 (t = 10000.0 s) is 10000.0 s; expected steps within"),
])
def test_times_are_refused_as_simulate_refuses_them(scale: float, words: str) -> None:
    """The noise analysis refuses sample times with simulate's words (model.bounds.check_times): a step of 1e-200 s
    overflowed its differences into NaN, with numpy's warnings and an answer (2026-11-29)."""
    t = np.arange(200) * 1e-3 * scale
    z = 0.01 * np.sin(np.arange(200) / 20.0)
    with pytest.raises(InputError) as info:
        analyse_depth_noise(t, z)
    assert words in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(InputError, match="depth is not finite at sample 3"):
        analyse_depth_noise(np.arange(200) * 1e-3, np.where(np.arange(200) == 3, np.nan, z))


@pytest.mark.parametrize(("args", "words"), [
    # the deadband overflowed: OverflowError from math.ceil(inf)
    ((1e-3, 1e-320), "time step must be at least 1e-09 s (the steppers' shortest step), got 1e-320"),
    ((1.7e308, 1e-3), "noise level must be within [0, 100] m (the depths' bound), got 1.7e+308"),
    ((150.0, 1e-3), "noise level must be within [0, 100] m (the depths' bound), got 150.0"),
])
def test_for_noise_refuses_what_overflows_its_window_in_one_line(args: tuple[float, float], words: str) -> None:
    """for_noise's window and deadband overflowed (math.ceil(inf): OverflowError) for a denormal step or a noise of
    1e308 m; it takes noise within the depths' +-100 m and steps of at least the steppers' 1 ns (2026-11-29)."""
    with pytest.raises(InputError) as info:
        VelocityFilter.for_noise(*args)
    assert words in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(InputError) as info:
        mf.MudContact(W20, noise_std=args[0], dt=args[1])
    assert words in str(info.value)


def test_for_noise_takes_any_window_length() -> None:
    """A window of 1e300 s at a 1 ns step (round(inf): OverflowError) is the longest window, 64 steps."""
    assert VelocityFilter.for_noise(1e-3, 1e-9, 1e300) == VelocityFilter.for_noise(1e-3, 1e-9, 1.0)
    assert VelocityFilter.for_noise(1e-3, 1e-9, 1e300).window == 64
    assert VelocityFilter.for_noise(100.0, 1e-9).deadband < 1e12


def test_for_noise_of_float32_numbers_is_that_of_their_values() -> None:
    """The arithmetic ran in float32 for a float32 noise or step (NumPy's promotion): deadband 0.007071067579 for
    np.float32(1e-4) against 0.007071067633 for its value as a float."""
    noise, dt, span = np.float32(1e-4), np.float32(0.01), np.float32(0.05)
    assert VelocityFilter.for_noise(noise, dt, span) == VelocityFilter.for_noise(float(noise), float(dt), float(span))
    assert VelocityFilter.for_noise(noise, 0.01).deadband == 0.007071067633235277


def test_depths_at_random_within_100_m_are_simulated() -> None:
    """Depths of +-100 m at random (valid input) read as white noise of 121 m, which simulate's "auto" handed to
    VelocityFilter.for_noise, which refused it ('noise level must be within [0, 100] m'): the filter is now the one
    for 100 m, and the noise found is reported as found."""
    z = np.array([100.0 if c == "+" else -100.0 for c in "+----+---++++-+-+--+"])
    res = simulate(np.arange(20) * 0.01, z, mf.MudParameters.from_water_content(0.25))
    assert res.depth_noise is not None and res.depth_noise.std > 100.0
    assert res.velocity_filter == VelocityFilter.for_noise(100.0, 0.01)
    assert np.isfinite(res.force).all()


def test_a_quantised_depth_is_noise_and_gets_a_filter_long_enough_for_its_quantum() -> None:
    """A depth read in 0.1 mm steps (an encoder) holds still between steps while the foot withdraws at 1 mm/s: its
    residuals were exactly zero, so auto read it as clean, and the exact rule took each still run for a stop (the
    intrusion branch's 52 N on 1,796 of 2,301 samples, where the motion gives -0.3 N). Now it reads the quantum,
    takes its noise (q / sqrt(12)) and the shortest window whose secant reads 1 mm/s above it (21 steps): 34
    samples more than 5 N off. A clean protocol with holds is still clean."""
    from mudforce.motions.protocol import Hold, Intrude, Protocol, Withdraw

    steps = (Intrude(depth=0.02, velocity=0.01), Hold(duration=1.0), Withdraw(velocity=0.001, rise=0.0))
    t, z = Protocol(steps, rate=100.0).sample()
    q = 1e-4
    zq = np.round(z / q) * q
    rule, noise = choose_velocity_filter(t, zq)
    assert noise.quantum == pytest.approx(q, rel=1e-6) and noise.std == pytest.approx(q / math.sqrt(12), rel=1e-6)
    assert noise.white and noise.describe().startswith("quantised depth: steps of 0.1 mm between still samples")
    assert rule.window == 21 and rule.deadband < 1e-3
    params = mf.MudParameters.from_water_content(0.25)
    truth = simulate(t, z, params, velocity_filter="exact").force
    off = np.abs(simulate(t, zq, params).force - truth) > 5.0
    assert off.sum() == 34
    clean = analyse_depth_noise(t, z)
    assert clean.clean and clean.quantum == 0.0
    # a depth held within an ulp (steps of 3.5e-18 m about 15.6 mm, found by the property test below): rounding, not
    # an encoder's quantum: clean, as noise below the 1 nm floor is
    held = 0.015625 + 5e-17 * np.sin(2.0 * np.pi * t / 3.0)
    assert analyse_depth_noise(t, held).clean
