"""identify_water_content's options of the wrong type or size: refused in one line, as their bad values are."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration import identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.fit import fit_condition
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import walk


@pytest.fixture(scope="module")
def trial() -> Trial:
    path = walk(0.25, seed=0, duration=6.0)
    return Trial("w.csv", 0.25, path.time, path.depth, path.force)


@pytest.mark.parametrize(("options", "message"), [
    ({"foot": "paper"}, "foot must be a Foot or None, got str"),  # was AttributeError: no attribute 'area'
    ({"force_gain_uncertainty": "0.1"}, "force gain uncertainty must be in [0, 0.5)"),  # was TypeError
    ({"force_gain_uncertainty": None}, "force gain uncertainty must be in [0, 0.5)"),
    ({"force_gain_uncertainty": False}, "force gain uncertainty must be in [0, 0.5)"),  # was read as 0
    ({"level": "0.9"}, "confidence level must be in (0, 1)"),  # was TypeError
    ({"points": 2.5}, "points must be an integer in [2, 100000], got 2.5"),  # was TypeError
    ({"points": 10**9}, "points must be an integer in [2, 100000]"),  # hung allocating the grid
    ({"points": 1}, "points must be an integer in [2, 100000], got 1"),  # searched [0.15, 0.15]: always 15 %
    ({"bounds": "x"}, "bounds must be (low, high)"),  # was ValueError: too many values to unpack
    ({"bounds": ("0.2", "0.3")}, "bounds must be (low, high)"),  # was TypeError
    ({"depth_noise": "1"}, "w.csv: depth noise must be between 0 and 10 mm"),  # was TypeError
    ({"depth_noise": "1mm"}, "w.csv: depth noise must be between 0 and 10 mm (e.g. 0.03 mm, given in metres: 3e-05), "
                             "got str"),  # was "got '1mm' m"
    ({"depth_noise": 0.03}, "w.csv: depth noise must be between 0 and 10 mm (e.g. 0.03 mm, given in metres: 3e-05), "
                            "got 0.03 m"),  # 0.03 m for 0.03 mm: what the example now says
    ({"family": lambda w: None}, "family(0.15) must return MudParameters, got NoneType"),  # was AttributeError
    ({"family": 3}, "family must be a function of the water content [-] returning MudParameters, got int"),
    # past 4,300 digits the message's repr raised ValueError (Exceeds the limit ...), math.isfinite OverflowError
    ({"level": 10**5000}, "confidence level must be in (0, 1), got an integer of 16610 bits"),
    ({"force_gain_uncertainty": 10**5000}, "force gain uncertainty must be in [0, 0.5) (e.g. 0.05 for 5 %), got an "
                                           "integer of 16610 bits"),
    ({"depth_noise": 10**5000}, "w.csv: depth noise must be between 0 and 10 mm (e.g. 0.03 mm, given in metres: "
                                "3e-05), got an integer of 16610 bits"),
    ({"bounds": (0.2, 10**400)}, "bounds must be (low, high) with low < high, both finite [-], got (0.2, an integer "
                                 "of 1329 bits)"),
    ({"bounds": np.zeros((2, 2))}, "bounds must be (low, high) with low < high, both finite [-], got ndarray"),
    # the family's refusal named the first grid point the scan met past its range: "water content 0.35375 is outside
    # Table I's range", after the trial's preparation
    ({"bounds": (0.2, 0.5)}, "bounds (0.2, 0.5) reach 0.5, outside the family's range of water contents [0.15, "
                             "0.35]; pass bounds within it (fractions: 0.25 means 25%)"),
    ({"bounds": (0.1, 0.3)}, "bounds (0.1, 0.3) reach 0.1, outside the family's range of water contents [0.15, "
                             "0.35]"),
    ({"family": lambda w: MudParameters.from_water_content(w + 0.1)},
     "bounds (0.15, 0.35) reach 0.35, outside the family's range of water contents (the family: water content 0.45 "
     "is outside Table I's range [0.15, 0.35] (a fraction: 0.25 means 25%)); pass bounds within it"),
])
def test_identify_refuses_options_of_the_wrong_type(trial: Trial, options: dict[str, Any], message: str) -> None:
    with pytest.raises(InputError) as info:
        identify_water_content(trial, **options)
    assert str(info.value).startswith(message), str(info.value)
    assert "\n" not in str(info.value)


def test_identify_refuses_what_is_not_a_trial(trial: Trial) -> None:
    with pytest.raises(InputError, match=r"^trial must be a Trial or a PreparedTrial, got tuple$"):
        identify_water_content((trial.time, trial.depth, trial.force))  # type: ignore[arg-type]


def test_fit_condition_refuses_a_gain_uncertainty_that_is_not_a_number(trial: Trial) -> None:
    with pytest.raises(InputError, match=r"^force gain uncertainty must be in \[0, 0.5\)"):
        fit_condition([trial], force_gain_uncertainty="0.05")  # type: ignore[arg-type]
    assert np.isfinite(identify_water_content(trial, force_gain_uncertainty=np.float32(0.1)).water_content)
