"""Calibration round trips: synthetic data from known parameters -> fit -> the parameters back.

Kept small (one or two conditions, a reduced optimiser budget) so the file
runs in well under a minute on two shared cores; ``benchmarks/bench_fit.py``
runs the full acceptance check (3 speeds x 3 repeats, several seeds).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration import (
    FitOptions,
    ForceModel,
    Trial,
    fit_condition,
    fit_dataset,
    load_dataset,
    synthesize,
)
from mudforce.estimation.calibration.report import write_report
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

FAST = FitOptions(popsize=10, maxiter=40)


def _check_recovery(fit_params: dict[str, float], stderr: dict[str, float | None], truth: dict[str, float],
                    names: tuple[str, ...], rel: float = 0.05) -> None:
    for n in names:
        err = fit_params[n] - truth[n]
        se = stderr[n]
        ok = abs(err) <= rel * truth[n] or (se is not None and abs(err) <= 3 * se)
        assert ok, f"{n}: fitted {fit_params[n]:.5g}, true {truth[n]:.5g}, stderr {se}"


def test_round_trip_one_condition() -> None:
    """W = 25%, 10 and 40 mm/s, 2 repeats, noise 0.3 N, depth noise 0.03 mm, bias 0.5 N."""
    ds = synthesize(water_contents=[0.25], velocities=[0.01, 0.04], repeats=2, seed=4, force_noise=0.3)
    fit = fit_condition(ds.trials, ds.foot, seed=4, options=FAST)
    truth = MudParameters.table_i(0.25).to_dict()
    assert fit.free == ("k_m_i", "b_m_i", "k_m_w", "b_m_w", "alpha", "beta", "sigma_y", "zeta", "omega_0")
    _check_recovery(fit.parameters, fit.stderr, truth, fit.free)
    # every fitted parameter within 3 standard errors when the errors are honest
    for n in fit.free:
        se = fit.stderr[n]
        assert se is not None and abs(fit.parameters[n] - truth[n]) < 4 * se, n
    assert fit.stderr["rho_m"] is None and fit.stderr["lambda"] is None
    # the noise floor: RMSE close to the force noise
    assert fit.rmse < 1.1 * 0.3
    assert all(t.rmse < 1.15 * 0.3 for t in fit.trials)
    assert all(abs(t.bias - 0.5) < 0.15 for t in fit.trials)
    corr = fit.correlation
    assert corr.shape == (9, 9)
    np.testing.assert_allclose(np.diag(corr), 1.0)


def test_no_necking_is_reported_not_invented() -> None:
    """W = 15% at 10 mm/s: the suction never reaches sigma_y, so sigma_y, zeta, omega_0 are undetermined."""
    ds = synthesize(water_contents=[0.15], velocities=[0.01], repeats=1, seed=8, force_noise=0.2)
    fit = fit_condition(ds.trials, ds.foot, seed=1, options=FAST)
    for n in ("sigma_y", "zeta", "omega_0"):
        assert fit.stderr[n] is None
        assert any(w.startswith(f"{n} is not determined") for w in fit.warnings)
    assert any("no trial necked" in w for w in fit.warnings)
    assert fit.rmse < 1.1 * 0.2
    _check_recovery(fit.parameters, fit.stderr, MudParameters.table_i(0.15).to_dict(),
                    ("k_m_i", "b_m_i", "alpha", "beta", "k_m_w"))
    out = json.loads(json.dumps(fit.to_dict()))
    assert out["stderr"]["sigma_y"] is None


def test_shared_parameters_across_water_contents() -> None:
    """Two water contents whose k_m_w, b_m_w agree (as the paper found): the joint fit ties them."""
    truth = {w: MudParameters.table_i(w).replace(k_m_w=1.3e6, b_m_w=1.4e6) for w in (0.2, 0.3)}
    ds = synthesize(water_contents=[0.2, 0.3], velocities=[0.02, 0.04], repeats=1, seed=6, force_noise=0.2,
                    parameters=truth)
    result = fit_dataset(ds, shared=("k_m_w", "b_m_w"), seed=2, options=FAST, quiet=True)
    a, b = result.conditions
    assert a.parameters["k_m_w"] == b.parameters["k_m_w"]
    assert a.parameters["b_m_w"] == b.parameters["b_m_w"]
    for cond, w in ((a, 0.2), (b, 0.3)):
        _check_recovery(cond.parameters, cond.stderr, truth[w].to_dict(), cond.free, rel=0.05)
        assert cond.rmse < 1.1 * 0.2
    assert json.loads(result.to_json())["shared"] == ["k_m_w", "b_m_w"]


@pytest.mark.parametrize(("shared", "words"), [
    (("k_m_w", "k_m_w"), "--shared k_m_w: given twice"),  # two free copies of one parameter: a degenerate fit
    ("k_m_w", "shared must be a sequence of parameter names"),  # its letters were read as names
])
def test_shared_names_given_twice_or_as_a_string_are_refused_before_any_fit(shared: object, words: str) -> None:
    ds = synthesize(water_contents=[0.2, 0.3], velocities=[0.02], repeats=1, seed=6)
    with pytest.raises(InputError, match=f"^{words}"):
        fit_dataset(ds, shared=shared, quiet=True)  # type: ignore[arg-type]


def test_report_is_written_and_deterministic(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    ds = synthesize(water_contents=[0.25], velocities=[0.04], repeats=2, seed=1)
    result = fit_dataset(ds, seed=0, options=FitOptions(popsize=6, maxiter=10), quiet=True)
    first = write_report(result, tmp_path / "a")
    second = write_report(result, tmp_path / "b")
    names = sorted(p.name for p in first.parent.iterdir())
    assert "report.md" in names and "W25_error_profile.png" in names and "parameters_vs_water_content.png" in names
    for name in names:
        assert (first.parent / name).read_bytes() == (second.parent / name).read_bytes(), name
    text = first.read_text()
    assert "| alpha |" in text and "## W = 25.0%" in text


def test_load_dataset_after_synth(tmp_path: Path) -> None:
    ds = synthesize(tmp_path, water_contents=[0.25], velocities=[0.04], repeats=1, seed=0)
    back = load_dataset(tmp_path)
    np.testing.assert_allclose(back.trials[0].force, ds.trials[0].force, rtol=1e-8, atol=1e-8)
    assert back.extra is not None
    assert back.extra["synthetic"]["parameters"]["0.25"]["alpha"] == 4e4


def test_another_model_plugs_in() -> None:
    """A model is a force function plus bounds: here a linear spring F = k max(z, 0) S."""

    def spring(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
        out: np.ndarray = values[0] * np.clip(depth, 0.0, None) * foot.area
        return out

    model = ForceModel(name="test-spring", parameter_names=("k",), force=spring, bounds={"k": (1e3, 1e10)},
                       defaults={"k": 1e6}, units={"k": "Pa/m"})
    ds = synthesize(water_contents=[0.25], velocities=[0.02], repeats=2, seed=1, depth_noise=0.0)
    rng = np.random.default_rng(0)
    trials = [Trial(t.name, t.water_content, t.time, t.depth,
                    spring(t.time, t.depth, np.array([2e6]), ds.foot) + 0.3 + 0.2 * rng.standard_normal(t.time.size))
              for t in ds.trials]
    fit = fit_condition(trials, ds.foot, model=model)
    se = fit.stderr["k"]
    assert se is not None and abs(fit.parameters["k"] - 2e6) < 4 * se
    assert fit.rmse < 0.22 and fit.model == "test-spring"
    assert not any("sign-flipped" in w for w in fit.warnings)
    # the force of the wrong sign (compression negative) is named per trial, before the general misfit message
    flipped = [dataclasses.replace(t, force=-t.force) for t in trials]
    warned = fit_condition(flipped, ds.foot, model=model, options=FitOptions(starts=1, popsize=4, maxiter=3,
                                                                            max_nfev=40)).warnings
    assert [w.split(":")[0] for w in warned[:2]] == [t.name for t in trials]
    assert all("looks sign-flipped; mudforce expects the force + up" in w for w in warned[:2])
