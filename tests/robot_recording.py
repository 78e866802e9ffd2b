"""identify on a recording of the MuJoCo quadruped's foot kept as test data (``tests/estimation/data``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mudforce.estimation.calibration import Identification, identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.model.foot import Foot

DATA = Path(__file__).parent / "estimation" / "data"
#: The quadruped's spherical foot: its contact is the 50 mm disc.
ROBOT_FOOT = Foot.disc(0.05)


def identify_robot(filename: str, name: str, water_content: float) -> Identification:
    """identify on ``DATA / filename`` (columns time [s], depth [m], force [N]) with the robot's foot, the trial named
    ``name`` with its true water content [-]."""
    data = np.loadtxt(DATA / filename, delimiter=",", skiprows=1)
    return identify_water_content(Trial(name, water_content, data[:, 0], data[:, 1], data[:, 2]), ROBOT_FOOT)
