"""identify warns where the depth noise it read carries most of the noise floor (issue 23, point 5).

The recording (``tests/estimation/data/robot_trot_hard_all_seed74.csv``): the sensor-chain bench's fresh seed 74, the
MuJoCo quadruped's front-left foot, gait ``trot``, in mud of W = 26.88 %, MuJoCo's force, through "hard, all" (the
depth read 5 mm deep, a 10-ms delay and a 10-ms low-pass on the force, 20 Hz, a force noise of 0.2 N and a depth
noise of 0.03 mm). At 20 Hz the trotting foot never rests, and the depth noise read from the recording is its motion
between the samples, 2.5 mm; the floor is then mostly that reading, the misfit flag blind, and identify read 34.5 %
[28.25, 35] with no warning: confidently wrong. Given the depth noise, it covers the truth and warns of the rate.

The second (``robot_trot_hard_all_seed86.csv``): the same bench row on the fresh seed 86, the trot in mud of
W = 26.93 %. Its depth noise read the same 2.5 mm but carried 48 % of the floor, under the 50 % the warning asked, and
identify read 33.5 % [30.7, 35] with the misfit ratio at 1.13 and no warning: confidently wrong again. Without the depth
noise's part of the floor the ratio reads 1.54, past the flag's 1.25: the flag was quiet on that reading alone, and
the warning now says so (docs/estimation.md, "What is not met").
"""

from __future__ import annotations

from mudforce.estimation.calibration import identify_water_content, load_trial
from robot_recording import DATA, ROBOT_FOOT

TRUTH = 0.26877565346143967
TRUTH_86 = 0.2692894050093562


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


def test_a_flag_quiet_on_the_depth_noise_read_alone_is_named() -> None:
    trial = load_trial(DATA / "robot_trot_hard_all_seed86.csv", TRUTH_86)
    read = identify_water_content(trial, ROBOT_FOOT)
    assert read.depth_noise > 1e-3  # 2.5 mm again
    assert not read.interval[0] <= TRUTH_86 <= read.interval[1]  # the interval misses the truth ...
    assert not read.model_misses_data and read.misfit_ratio < 1.25  # ... with the misfit flag down (1.13)
    said = [w for w in read.warnings if w.startswith("the depth noise read from the recording")]
    assert len(said) == 1  # said, though the reading carries under half the floor (48 %)
    assert "carries 48% of the noise floor (without it the misfit ratio would read 1.54, against 1.25)" in said[0]
    given = identify_water_content(trial, ROBOT_FOOT, depth_noise=3e-5)
    assert given.interval[0] <= TRUTH_86 <= given.interval[1]  # 29.1 % [26.2, 34.0]
    assert not any(w.startswith("the depth noise read from the recording") for w in given.warnings)
