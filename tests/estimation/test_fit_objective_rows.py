"""The fit's objective writes each trial's rows in place (``fit._Piece``): the same numbers as the formula, bit for bit.

Each trial's rows are its force residual ``model - measured`` [N] in the
stage's window with the tare offset profiled out (``uncertainty.profiled``),
in trial order, then one tare-prior row per trial.
"""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.estimation.calibration import synthesize
from mudforce.estimation.calibration.fit import _Objective, _trial_residual
from mudforce.estimation.calibration.models import get_model
from mudforce.estimation.calibration.preprocess import prepare_trial
from mudforce.estimation.calibration.uncertainty import profiled


def _formula(obj: _Objective, x: np.ndarray) -> np.ndarray:
    parts, priors = [], []
    for g, (values, group) in enumerate(zip(obj.values(x), obj.groups, strict=True)):
        for i, tr in enumerate(group):
            if obj.tails is not None:  # withdrawal-only parameters: from the snapshot at the reversal
                r = obj.tails[g][i](values) - tr.force[tr.reversal_index:]
            else:
                r = _trial_residual(obj.model, obj.foot, tr, values, obj.window)
            data, prior = profiled(r, tr.precontact)
            parts.append(data)
            priors.append(prior)
    return np.concatenate([*parts, np.array(priors)])


@pytest.mark.parametrize("model", ["chen2024", "drft"])
@pytest.mark.parametrize("window", ["all", "intrusion", "withdrawal", "withdrawal, prefix fixed"])
def test_the_objective_is_the_formula(model: str, window: str) -> None:
    ds = synthesize(water_contents=[0.2, 0.3], velocities=[0.01, 0.02], repeats=1, seed=2, rate=50.0)
    groups = [[prepare_trial(t) for t in trials] for trials in ds.conditions().values()]
    m = get_model(model)
    base = [m.vector({}) for _ in groups]
    free = [i for i, n in enumerate(m.parameter_names) if n not in m.fixed]
    slots = [[(g, i) for g in range(len(groups))] for i in free]  # shared by both groups, as fit_dataset's
    obj = _Objective(m, ds.foot, groups, base, slots, window.split(",")[0], prefix_fixed="prefix" in window)
    x0 = np.log(base[0][free])
    for step in (0.0, 0.1, -0.2, 0.0):  # again after others: nothing is left behind
        x = x0 + step
        assert obj(x).tobytes() == _formula(obj, x).tobytes()
