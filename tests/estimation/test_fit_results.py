"""fit.json round trip: load_fit returns a FitResult equal, field for field, to what was saved."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration import Dataset, fit_dataset, load_fit, load_fit_parameters
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.results import ConditionFit, FitResult
from mudforce.model.foot import Foot
from mudforce.motions.gait import walk


def test_load_fit_returns_the_saved_result(tmp_path: Path) -> None:
    trials = []
    for seed, below in ((21, False), (22, True)):
        path = walk(0.28, seed=seed, duration=8.0, force_noise=0.2, bias=0.3, start_below=below)
        trials.append(Trial(f"walk{seed}.csv", 0.28, path.time, path.depth, path.force))
    result = fit_dataset(Dataset(foot=Foot.paper(), trials=tuple(trials)), seed=0, quiet=True)
    result.save(tmp_path / "fit.json")
    loaded = load_fit(tmp_path / "fit.json")
    assert isinstance(loaded, FitResult) and isinstance(loaded.conditions[0], ConditionFit)
    assert loaded.to_dict() == json.loads((tmp_path / "fit.json").read_text())
    cond = loaded.conditions[0]
    assert cond.parameters == result.conditions[0].parameters
    assert [t.bias_method for t in cond.trials] == ["tared", "estimated"]
    assert load_fit_parameters(tmp_path / "fit.json")[0.28].alpha == cond.parameters["alpha"]


def test_load_fit_refuses_other_json(tmp_path: Path) -> None:
    bad = tmp_path / "x.json"
    bad.write_text('{"conditions": [{"water_content": 0.25}]}')
    with pytest.raises(InputError, match=r"not a fit\.json written by mudforce fit"):
        load_fit(bad)
