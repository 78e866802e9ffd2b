"""fit and a force sensor whose gain is off (issue 23, point 5): the parameters within 3 standard errors, or warned.

A gain of 1 + g on the measured force reads as a mud whose force-scale parameters (``ForceModel.force_scale``)
are all 1 + g larger: the paper's force is exactly homogeneous in them. The data cannot tell the two apart, so
the gain's uncertainty enters those parameters' standard errors, fully correlated.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration import (
    ConditionFit,
    FitOptions,
    Trial,
    fit_condition,
    fit_dataset,
    load_fit,
    synthesize,
)
from mudforce.estimation.calibration.models import CHEN2024
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import walk

FAST = FitOptions(popsize=8, maxiter=25)
GAIN = 1.05


def test_the_force_is_homogeneous_in_its_force_scale_parameters() -> None:
    """F(c p) = c F(p) for the paper's model, necking and the suction after it included."""
    w = walk(0.3, seed=1, duration=8.0, force_noise=0.0)
    q = MudParameters.from_water_content(0.3).to_dict()
    base = CHEN2024.vector(q)
    scaled = CHEN2024.vector({**q, **{n: 1.05 * q[n] for n in CHEN2024.force_scale}})
    f = CHEN2024.force(w.time, w.depth, base, Foot.paper())
    g = CHEN2024.force(w.time, w.depth, scaled, Foot.paper())
    assert np.min(f) < 0.0  # a suction was reached
    np.testing.assert_allclose(g, 1.05 * f, rtol=0.0, atol=1e-9 * float(np.max(np.abs(f))))


@pytest.fixture(scope="module")
def fits() -> tuple[dict[str, float], ConditionFit, ConditionFit]:
    ds = synthesize(water_contents=[0.25], velocities=[0.04], repeats=1, seed=3, force_noise=0.2)
    trials = [Trial(t.name, t.water_content, t.time, t.depth, GAIN * t.force) for t in ds.trials]
    with_gain = fit_condition(trials, ds.foot, seed=1, options=FAST)
    without = fit_condition(trials, ds.foot, seed=1, options=FAST, force_gain_uncertainty=0.0)
    return MudParameters.table_i(0.25).to_dict(), with_gain, without


def _z(fit: ConditionFit, truth: dict[str, float], name: str) -> float:
    value, se = fit.parameters[name], fit.stderr[name]
    assert se is not None
    return math.log(value / truth[name]) / (se / value)


def test_a_gain_error_is_within_the_standard_errors(fits: tuple[dict[str, float], ConditionFit, ConditionFit]) -> None:
    truth, with_gain, without = fits
    scale = [n for n in CHEN2024.force_scale if n in with_gain.free]
    # without the gain's uncertainty the stiffest-determined parameters are confidently 5 % off ...
    assert max(abs(_z(without, truth, n)) for n in scale) > 3.0
    # ... with it (5 %, the default) every parameter the data determine is within 3 standard errors
    for n in scale:
        se = with_gain.stderr[n]
        if se is not None:
            assert abs(_z(with_gain, truth, n)) < 3.0, n
            # the gain's part: log(1.05) / 1.96 on the logarithm, at least
            assert se / with_gain.parameters[n] >= math.log(GAIN) / 1.96 - 1e-12
    # the same values: the gain changes the standard errors, not the fit
    assert with_gain.parameters == without.parameters


def test_fit_json_records_the_gain_uncertainty(tmp_path: Path) -> None:
    ds = synthesize(water_contents=[0.25], velocities=[0.04], repeats=1, seed=3, force_noise=0.2)
    result = fit_dataset(ds, seed=1, options=FitOptions(popsize=4, maxiter=3, max_nfev=30), quiet=True,
                         force_gain_uncertainty=0.1)
    result.save(tmp_path / "fit.json")
    assert load_fit(tmp_path / "fit.json").force_gain_uncertainty == 0.1
    assert json.loads((tmp_path / "fit.json").read_text())["force_gain_uncertainty"] == 0.1


def test_the_gain_uncertainty_is_checked() -> None:
    with pytest.raises(InputError, match="force gain uncertainty must be in"):
        fit_condition([], force_gain_uncertainty=0.7)
