"""identify on a recording of the MuJoCo quadruped's foot kept as test data (``tests/estimation/data``)."""

from __future__ import annotations

from pathlib import Path

from mudforce.estimation.calibration import Identification, identify_water_content, load_trial
from mudforce.model.foot import Foot

DATA = Path(__file__).parent / "estimation" / "data"
#: The quadruped's spherical foot: its contact is the 50 mm disc.
ROBOT_FOOT = Foot.disc(0.05)


def identify_robot(filename: str, water_content: float) -> Identification:
    """identify on ``DATA / filename`` (read by the package's own ``load_trial``: ``time_s, depth_m, force_N``) with
    the robot's foot, the trial carrying its true water content [-]."""
    return identify_water_content(load_trial(DATA / filename, water_content), ROBOT_FOOT)
