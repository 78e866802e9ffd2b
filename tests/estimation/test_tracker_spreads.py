"""MudTracker's reported nuisances: pure delays beside the low-passes in the force lag, and the twin bank's readings
in the lag's and the surface offset's spreads (issue 23, point 3 online).

A sensor's delay is not a low-pass: a delayed force's sharp edges fit a low-pass of about half the delay better than
one of the delay, and the low-pass hypotheses alone read a 20-ms delay at about half, beyond three spreads on 9-15 %
of the sensor-chain bench's samples. The reported lag now also weighs pure delays of the bank's mean model force
(``_DELAYS``), and its spread holds what the twin bank (the quick branch rule) reads: the lag takes up what a branch
rule misses (a deep wet robot's 30-ms low-pass read as 45 ms on the first bank's rule, 30 on the twin's), and so
does the surface offset (the deep wet robots at 20 Hz under a lag read a -5 mm offset as +2 to +3 mm, 2.4 mm wide).
A lag beyond the allowance widens its own spread by 0.3 of the excess (``_LAG_SPREAD_WIDENING``): the hypotheses are
scored on the bank's mean model, whose water content and offset trade with a large lag.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mudforce.estimation import _tracker_layout as L
from mudforce.estimation._tracker_step import _delayed_forces
from mudforce.estimation.tracker import track
from mudforce.model.foot import Foot
from mudforce.model.velocity import VelocityFilter
from mudforce.motions.gait import walk
from mudforce.motions.sensor_chain import SensorChain, apply

DATA = Path(__file__).parent / "data" / "robot_walk_fast_seed1.csv"


def test_a_delay_reads_the_ring_linearly_between_its_steps() -> None:
    aux = np.zeros((1, L._N_AUX))
    times = np.arange(5) * 0.01  # five (sub)steps of 10 ms, forces 0, 10, 20, 30, 40 N, the newest at 40 ms
    for k, t in enumerate(times):
        aux[0, L._A_DRING + k] = 10.0 * k
        aux[0, L._A_DRING_T + k] = t
    aux[0, L._A_DHEAD] = 4
    aux[0, L._A_DN] = 5
    aux[0, L._A_CLOCK] = 0.04

    def delayed(*delays: float) -> np.ndarray:
        _delayed_forces(aux, 0, np.array(delays), L._A_DEL_Y)  # (one walk for all: ascending)
        return aux[0, L._A_DEL_Y:L._A_DEL_Y + len(delays)].copy()

    # beyond the ring's oldest: the oldest
    np.testing.assert_allclose(delayed(0.0, 0.005, 0.02, 0.035, 0.1), [40.0, 35.0, 20.0, 5.0, 0.0], rtol=1e-12)
    np.testing.assert_allclose(delayed(0.02), [20.0], rtol=1e-12)  # one alone reads the same
    # a ring that wrapped: the head at 1, the oldest entry at 2
    ring = np.roll(np.arange(L._N_DRING, dtype=float), 2)  # entry i holds step (i - 2) % 64
    aux[0, L._A_DRING:L._A_DRING + L._N_DRING] = ring
    aux[0, L._A_DRING_T:L._A_DRING_T + L._N_DRING] = ring * 1e-3
    aux[0, L._A_DHEAD] = 1
    aux[0, L._A_DN] = L._N_DRING
    aux[0, L._A_CLOCK] = 63e-3
    np.testing.assert_allclose(delayed(0.0105, 1.0), [52.5, 0.0], rtol=1e-12)


def test_a_pure_delay_on_a_gait_walk_stays_within_the_lag_s_spread() -> None:
    # a 20-ms delay on a 25 % walk at 100 Hz: read 13.8 +- 8.4 ms at the end (median 8.6 ms after 3 s), no sample
    # beyond three spreads; on the low-passes alone 6.9 +- 4.4 ms, 1310 of 1701 samples beyond
    w = walk(0.25, seed=4, duration=20.0)
    t, z, f = apply(w.time, w.depth, w.force, SensorChain(force_delay=0.02, force_noise=0.2, depth_noise=3e-5), 4)
    r = track(t, z, f)
    late = t - t[0] >= 3.0
    assert not np.any(np.abs(r.force_lag[late] - 0.02) > 3.0 * r.force_lag_stderr[late])
    assert abs(r.water_content[-1] - 0.25) < 0.005


def test_a_pure_delay_on_the_robot_is_read_as_itself() -> None:
    # the MuJoCo robot's foot (test_tracker_lag.py's recording), its force delayed 20 ms: read 20.00 +- 2.17 ms at
    # the end and on the median sample after 3 s; on the low-passes alone 19.4 +- 3.7 ms at the end, median 16.0
    t, z, f = np.loadtxt(DATA, delimiter=",", skiprows=1, unpack=True)
    t, z, f = apply(t, z, f, SensorChain(force_delay=0.02), 0)
    r = track(t, z, f, Foot.disc(0.05))
    late = t - t[0] >= 3.0
    assert abs(r.force_lag[-1] - 0.02) < 1e-3 and abs(float(np.median(r.force_lag[late])) - 0.02) < 1e-3
    assert not np.any(np.abs(r.force_lag[late] - 0.02) > 3.0 * r.force_lag_stderr[late])


def test_the_lag_s_and_the_offset_s_spreads_hold_the_twin_bank_s_readings() -> None:
    t, z, f = np.loadtxt(DATA, delimiter=",", skiprows=1, unpack=True)
    t, z, f = apply(t, z, f, SensorChain(force_lowpass=0.03, force_noise=0.2), 1)
    foot = Foot.disc(0.05)
    r = track(t, z, f, foot)
    first = track(t, z, f, foot, twin=False)  # the first bank alone
    twin = track(t, z, f, foot, velocity_filter=VelocityFilter(2, 0.0025), depth_offsets=[-0.003, 0.0, 0.003])
    assert np.array_equal(r.force_lag, first.force_lag)  # the lag reported is the first bank's
    expected = np.sqrt(first.force_lag_stderr**2 + (first.force_lag - twin.force_lag) ** 2)
    np.testing.assert_allclose(r.force_lag_stderr, expected, rtol=1e-12, atol=0.0)
    assert np.any(r.force_lag_stderr > first.force_lag_stderr)
    assert np.array_equal(r.depth_offset, first.depth_offset)  # and the offset
    expected = np.sqrt(first.depth_offset_stderr**2 + (first.depth_offset - twin.depth_offset) ** 2)
    np.testing.assert_allclose(r.depth_offset_stderr, expected, rtol=1e-12, atol=0.0)
    assert np.any(r.depth_offset_stderr > first.depth_offset_stderr)
    assert np.array_equal(r.water_content, first.water_content)


def test_a_lag_beyond_the_allowance_widens_its_spread() -> None:
    # the robot's force low-passed by 30 ms: read 30.0 +- 7.0 ms at the end (+- 3.6 ms without the widening's 6.0); at
    # every sample the spread holds 0.3 of the lag beyond the 10-ms allowance. On seed 22's sensor-chain bench a 30-ms
    # low-pass read about 20 ms on shallow dry robots, with 3.5-ms spreads: 8.0 % of the samples beyond three, 0.2 % now
    recording = np.loadtxt(DATA, delimiter=",", skiprows=1, unpack=True)
    r = track(*apply(*recording, SensorChain(force_lowpass=0.03), 0), Foot.disc(0.05))
    beyond = np.maximum(r.force_lag - 0.01, 0.0)
    assert np.all(r.force_lag_stderr >= L._LAG_SPREAD_WIDENING * beyond)
    assert L._LAG_SPREAD_WIDENING == 0.3
    assert abs(r.force_lag[-1] - 0.03) < 1e-4
    assert r.force_lag_stderr[-1] == pytest.approx(0.0070, abs=2e-4)
    # a lag within the allowance is not widened: the clean recording's spread is its hypotheses' cell
    clean = track(*recording, Foot.disc(0.05))
    assert clean.force_lag[-1] < 0.001 and clean.force_lag_stderr[-1] == pytest.approx(0.0025 / 12**0.5, rel=0.01)


def test_at_20_hz_the_lag_s_spread_holds_the_interpolated_part_of_a_sample() -> None:
    # every fifth sample of the robot's recording (20 Hz): each sample interval is 50 ms, and the spread holds the
    # 40 ms beyond one 10-ms step, which the substeps interpolate, as a uniform, 40 ms / sqrt(12) = 11.5 ms, in
    # quadrature; at 100 Hz nothing
    t, z, f = np.loadtxt(DATA, delimiter=",", skiprows=1, unpack=True)
    t, z, f = apply(t, z, f, SensorChain(force_delay=0.01, force_lowpass=0.01, force_noise=0.2), 2)
    r = track(t[::5], z[::5], f[::5], Foot.disc(0.05))
    assert np.all(r.force_lag_stderr[1:] >= 0.04 / 12**0.5)
    assert np.all(np.abs(r.force_lag[r.time >= 3.0] - 0.02) <= 3.0 * r.force_lag_stderr[r.time >= 3.0])
