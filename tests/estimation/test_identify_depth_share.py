"""identify warns where the depth noise it read carries most of the noise floor (issue 23, point 5).

The recording (``tests/estimation/data/robot_trot_hard_all_seed74.csv``): the sensor-chain bench's fresh seed 74, the
MuJoCo quadruped's front-left foot, gait ``trot``, in mud of W = 26.88 %, MuJoCo's force, through "hard, all" (the
depth read 5 mm deep, a 10-ms delay and a 10-ms low-pass on the force, 20 Hz, a force noise of 0.2 N and a depth
noise of 0.03 mm). At 20 Hz the trotting foot never rests, and the depth noise read from the recording is its motion
between the samples, 2.5 mm; the floor is then mostly that reading, the misfit flag blind, and identify read 34.5 %
[28.25, 35] with no warning: confidently wrong. Given the depth noise, it covers the truth and warns of the rate.
"""

from __future__ import annotations

from mudforce.estimation.calibration import identify_water_content, load_trial
from robot_recording import DATA, ROBOT_FOOT

TRUTH = 0.26877565346143967


def test_a_depth_noise_read_as_the_foot_s_motion_is_named() -> None:
    trial = load_trial(DATA / "robot_trot_hard_all_seed74.csv", TRUTH)
    read = identify_water_content(trial, ROBOT_FOOT)
    assert read.depth_noise > 1e-3  # 2.5 mm: the motion between the samples
    assert not read.interval[0] <= TRUTH <= read.interval[1]  # the interval misses the truth ...
    assert not read.model_misses_data  # ... with the misfit flag down
    assert any(w.startswith("the depth noise read from the recording") for w in read.warnings)  # but said
    given = identify_water_content(trial, ROBOT_FOOT, depth_noise=3e-5)
    assert given.interval[0] <= TRUTH <= given.interval[1]
    assert not any(w.startswith("the depth noise read from the recording") for w in given.warnings)
