"""identify's surface offset holds what the force gain's uncertainty does to it (issue 23, point 3: nuisances with
standard errors that enter the interval).

The recording (``tests/estimation/data``): the sensor-chain bench's fresh seed 102, MuJoCo's robot 6 with the model's
force, 34.10 % mud, under "gain -5 %" (no offset), 100 Hz, 30 s. identify reads the gain (0.952) and the water content
(34.14 %), and the surface 0.19 mm off. Before, its standard error was 0.017 mm: 11 of them, unwarned. The offset
trades with the gain as the water content does (at a gain of 1 the same fit reads -0.51 mm, at 0.95 -0.09 mm), and
its standard error now holds its move under the same +-5 % change of the gain that widens the water content's
interval.
"""

from __future__ import annotations

import pytest

from robot_recording import identify_robot

TRUTH = 0.3410333065198872  # [-]


def test_the_offset_s_standard_error_holds_its_move_under_the_gain_s_uncertainty() -> None:
    res = identify_robot("robot_model_wet_gain_minus5_seed102.csv", TRUTH)
    assert res.force_gain == pytest.approx(0.952, abs=0.002)  # read: the recording determines it
    assert res.water_content == pytest.approx(TRUTH, abs=0.002)
    assert res.interval[0] <= TRUTH <= res.interval[1]
    assert abs(res.depth_offset) == pytest.approx(0.19e-3, abs=0.03e-3)  # the offset read, 0.19 mm off the truth (0)
    assert abs(res.depth_offset) < 3.0 * res.depth_offset_stderr  # measured: 0.38 standard errors (11.6 before)
    assert res.depth_offset_stderr < 1e-3  # and still read to better than a millimetre (0.51 mm)
