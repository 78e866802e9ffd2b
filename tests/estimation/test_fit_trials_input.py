"""fit_condition's trials: a list of Trial (or PreparedTrial); anything else is refused in one line, before any work.

One Trial passed without its list raised ``TypeError: 'Trial' object is not iterable``, and a list of other
things raised ``AttributeError`` from deep in the preparation.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration import fit_condition
from mudforce.estimation.calibration.dataset import Trial

_T = np.arange(0.0, 2.0, 0.01)
TRIAL = Trial("a", 0.25, _T, 0.01 * np.sin(_T), np.sin(_T))


@pytest.mark.parametrize(("trials", "words"), [
    (TRIAL, "got one Trial: pass [trial]"),
    ("abc", "got str"),
    (None, "got NoneType"),
    ([TRIAL, 3], "trials[1] must be a Trial (or PreparedTrial), got int"),
    ([], "no trials to fit"),
])
def test_trials_that_are_not_a_list_of_trials_are_refused_in_one_line(trials: Any, words: str) -> None:
    with pytest.raises(InputError) as err:
        fit_condition(trials)
    assert words in str(err.value) and "\n" not in str(err.value)
