"""identify's surface offset: the rate check's move read on a profile (issue 23, point 3 offline).

The recording (tests/estimation/data/robot_model_wet_deep_offset_minus_5mm_seed49.csv) is the sensor-chain bench's
robot 4 of seed 49 under the row "offset -5 mm" with the model's force along the MuJoCo quadruped's foot path (34.42 %
mud, 26 mm deep at most): 100 Hz, 0.2 N of force noise, 0.03 mm of depth noise, the depth 5 mm short, so the surface
offset the model follows is +5 mm. identify read 4.925 +- 0.011 mm, 7 standard errors off, with no warning: the rate
check's half-rate refits, started at the full fit's answer, stopped there (a move of 0.26 um), and the offset's
standard error held the scatter alone. Each half's offset is now also read on a profile about its fit's, and the
larger move counts.
"""

from __future__ import annotations

from robot_recording import identify_robot

W_ROBOT = 0.34417422788562346


def test_the_offset_s_standard_error_holds_the_half_rate_move_read_on_a_profile() -> None:
    res = identify_robot("robot_model_wet_deep_offset_minus_5mm_seed49.csv", W_ROBOT)
    assert abs(res.depth_offset - 0.005) < 1e-4  # measured 4.9252 mm
    assert res.depth_offset_stderr > 0.03e-3  # measured 0.0413 mm (0.0107 before: the scatter alone)
    assert abs(res.depth_offset - 0.005) < 3.0 * res.depth_offset_stderr  # measured 1.8 standard errors (7.0 before)
    # the water content and its interval are not the offset's standard error's: as before, to the bit's neighbourhood
    assert abs(res.water_content - 0.344843) < 1e-5 and res.interval[0] <= W_ROBOT <= res.interval[1]
    assert not res.warnings
