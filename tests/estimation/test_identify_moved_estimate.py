"""identify's moved estimate holds the episodes' spread (issue 23, point 5 offline).

The recording (tests/estimation/data/robot_shallow_dry_lowpass_30ms_seed49.csv) is the sensor-chain bench's robot 6
of seed 49 (the MuJoCo quadruped's front-left foot on 16.33 % mud, 4 mm deep, MuJoCo's force) under the row
"low-pass 30 ms": 100 Hz, 0.2 N of force noise, 0.03 mm of depth noise. Least squares reads 23.0 % and fails the
flag's statistic, so the estimate moves to the member that passes, 17.2 %. Around it the interval held the gain's and
the rate check's shifts and the +-0.25-point floor only, [16.42, 26.38] %, and missed the truth with no warning.
It now holds the spread of the evidence over the contact episodes there too, as it does around least squares'.
"""

from __future__ import annotations

from mudforce.estimation.calibration.identify import MIN_HALF_WIDTH
from robot_recording import identify_robot

W_ROBOT = 0.16332000593685272


def test_the_moved_estimate_s_interval_holds_the_episodes_spread() -> None:
    res = identify_robot("robot_shallow_dry_lowpass_30ms_seed49.csv", W_ROBOT)
    assert res.least_squares_water_content > 0.22  # measured 23.04 %
    assert abs(res.water_content - 0.172) < 0.002  # the member: measured 17.20 %
    assert res.episode_half_width > MIN_HALF_WIDTH  # measured 0.88 points
    # below the estimate: at least the episodes' spread (and the gain's and rate check's shifts beyond it)
    assert res.water_content - res.low >= res.episode_half_width + res.rate_shift  # measured 1.40 points
    assert not res.warnings and res.low <= W_ROBOT <= res.high  # measured [15.80, 26.38] %; [16.42, ...] before
