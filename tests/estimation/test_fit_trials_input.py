"""fit_condition's trials: a list of Trial (or PreparedTrial); anything else is refused in one line, before any work.

One Trial passed without its list raised ``TypeError: 'Trial' object is not iterable``, and a list of other
things raised ``AttributeError`` from deep in the preparation. A trial that a file's reader would refuse (too few
samples, a value beyond the readers' bounds) is refused as identify refuses it.
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
    # what a file's reader refuses: 5 samples fitted zeta and omega_0 with a standard error of 0, a time of 1e300 s
    # raised ValueError and a force of 1e300 N gave an RMSE of inf
    ([Trial("b", 0.25, _T[:5], 0.01 * _T[:5], _T[:5])], "trial b: only 5 samples"),
    ([Trial("c", 0.25, _T * 1e300, 0.01 * np.sin(_T), np.sin(_T))], "trial c: the time reaches 1.99e+300 s"),
    ([TRIAL, Trial("d", 0.25, _T, 0.01 * np.sin(_T), 1e300 * np.sin(_T))], "trial d: the force reaches 1e+300 N"),
])
def test_trials_that_are_not_a_list_of_trials_are_refused_in_one_line(trials: Any, words: str) -> None:
    with pytest.raises(InputError) as err:
        fit_condition(trials)
    assert words in str(err.value) and "\n" not in str(err.value)


def test_a_dataset_trial_without_a_water_content_is_refused_by_name() -> None:
    """fit_dataset and fit_by_velocity group trials by water content; a NaN one (load_trial's default) fell in no
    group (NaN equals nothing), and both said "no trials to fit"."""
    import math

    from mudforce import Foot
    from mudforce.estimation.calibration import fit_by_velocity, fit_dataset
    from mudforce.estimation.calibration.dataset import Dataset

    data = Dataset(Foot.paper(), (TRIAL, Trial("unknown", math.nan, _T, 0.01 * np.sin(_T), np.sin(_T))))
    for fit in (fit_dataset, fit_by_velocity):
        with pytest.raises(InputError, match=r"^trial unknown has no water content \(NaN\)"):
            fit(data)


@pytest.mark.parametrize(("options", "words"), [
    # an unknown name was silently ignored; a str's letters were read as fixed names; True was held as 1
    ({"fixed": {"bogus": 1.0}}, "fixed: unknown parameter 'bogus' for model chen2024"),
    ({"fixed": "beta"}, "fixed must be a mapping of parameter names to values [SI]"),
    ({"fixed": {"beta": True}}, "fixed beta must be a number [-], got bool"),
    # NaN raised scipy's ValueError, 10**5000 OverflowError; a start of NaN, -0.5 or inf numpy's LinAlgError, 0 log(0)
    ({"fixed": {"beta": float("nan")}}, "fixed beta must be within [0.001, 1] -, got nan"),
    ({"fixed": {"k_m_i": 10**5000}}, "fixed k_m_i must be a real number within float64's range"),
    ({"start": {"beta": -0.5}}, "start beta must be within [0.001, 1] -, got -0.5"),
    ({"start": {"alpha": 0}}, "start alpha must be > 0"),
    ({"start": {"k_m_i": float("inf")}}, "start k_m_i must be within"),
    ({"start": {"bogus": 1.0}}, "start: unknown parameter 'bogus'"),
    # its letters were read as names: "unknown parameter 'b'", where beta is one
    ({"free": "beta"}, "free must be a sequence of parameter names, e.g. ('k_m_i', 'beta'), got 'beta'"),
])
def test_fixed_and_start_values_are_checked_before_any_fit(options: dict[str, Any], words: str) -> None:
    from mudforce import Foot
    from mudforce.estimation.calibration import fit_by_velocity, fit_dataset
    from mudforce.estimation.calibration.dataset import Dataset

    fits = [lambda: fit_condition([TRIAL], **options)]
    if "free" in options:
        fits.append(lambda: fit_dataset(Dataset(Foot.paper(), (TRIAL,)), free=options["free"], quiet=True))
    if "fixed" in options:
        data = Dataset(Foot.paper(), (TRIAL,))
        fits += [lambda: fit_dataset(data, fixed=options["fixed"], quiet=True),
                 lambda: fit_by_velocity(data, fixed=options["fixed"], quiet=True)]
    for fit in fits:
        with pytest.raises(InputError) as err:
            fit()
        assert str(err.value).startswith(words) and "\n" not in str(err.value)


@pytest.mark.parametrize(("fields", "words"), [
    # 0 max_nfev raised scipy's ValueError mid-fit, a float popsize TypeError; starts=0 and popsize=0 were taken
    # as 1 and 5 and True as 1 without a word; a NaN tol ran on
    ({"max_nfev": 0}, "FitOptions.max_nfev must be an integer >= 1, got 0"),
    ({"popsize": 3.5}, "FitOptions.popsize must be an integer >= 1, got 3.5"),
    ({"starts": 0}, "FitOptions.starts must be an integer >= 1, got 0"),
    ({"maxiter": True}, "FitOptions.maxiter must be an integer >= 0, got True"),
    ({"tol": float("nan")}, "FitOptions.tol must be finite [-], got nan"),
    # 10**400 was taken: a popsize then raised OverflowError in scipy's population (10**12 MemoryError), a maxiter
    # or max_nfev ran for as long as the fit did not converge, and an experiment's config could not be written
    ({"popsize": 10**400}, "FitOptions.popsize must be at most 1000 (ours: a budget beyond it is a mistake), got an "
                           "integer of 1329 bits"),
    ({"popsize": 1001}, "FitOptions.popsize must be at most 1000 (ours: a budget beyond it is a mistake), got 1001"),
    ({"maxiter": 10**400}, "FitOptions.maxiter must be at most 100000 (ours: a budget beyond it is a mistake), got "
                           "an integer of 1329 bits"),
    ({"max_nfev": 10**7}, "FitOptions.max_nfev must be at most 1000000 (ours: a budget beyond it is a mistake), got "
                          "10000000"),
    ({"starts": 10**400}, "FitOptions.starts must be at most 1000 (ours: a budget beyond it is a mistake), got an "
                          "integer of 1329 bits"),
])
def test_fit_options_are_checked_when_made(fields: dict[str, Any], words: str) -> None:
    from mudforce.estimation.calibration import FitOptions

    with pytest.raises(InputError) as err:
        FitOptions(**fields)
    assert str(err.value) == words


def test_fit_options_take_their_bounds() -> None:
    from mudforce.estimation.calibration import FitOptions

    most = FitOptions(starts=1000, popsize=1000, maxiter=100_000, max_nfev=1_000_000)
    assert (most.starts, most.popsize, most.maxiter, most.max_nfev) == (1000, 1000, 100_000, 1_000_000)


def test_options_that_are_not_fit_options_are_refused_in_one_line() -> None:
    """A dict raised AttributeError ('dict' object has no attribute 'starts') after the trials were prepared."""
    with pytest.raises(InputError, match=r"^options must be a FitOptions \(or None: the defaults\), got dict$"):
        fit_condition([TRIAL], options={"starts": 1})  # type: ignore[arg-type]
    # a progress of 3 raised AttributeError ('int' object has no attribute 'update') after the first stage's fit
    with pytest.raises(InputError, match=r"^progress must be a mudforce Progress or None, got int$"):
        fit_condition([TRIAL], progress=3)  # type: ignore[arg-type]


@pytest.mark.parametrize(("seed", "words"), [
    # a str or float raised TypeError at the global search, -8000 numpy's ValueError there; True and -5 were
    # recorded as fit.json's seed (true, -5), 10**5000 made its writer call the result not finite
    ("1", "seed must be an integer"),
    (1.5, "seed must be an integer"),
    (-8000, "seed must be an integer"),
    (True, "seed must be an integer"),
    pytest.param(10**5000, "seed must be an integer in [0, 4294967295], got an integer of 16610 bits", id="10**5000"),
])
def test_seeds_that_are_not_integers_in_range_are_refused_in_one_line(seed: Any, words: str) -> None:
    from mudforce import Foot
    from mudforce.estimation.calibration import fit_by_velocity, fit_dataset
    from mudforce.estimation.calibration.dataset import Dataset

    data = Dataset(Foot.paper(), (TRIAL,))
    fits = [lambda: fit_dataset(data, seed=seed, quiet=True), lambda: fit_by_velocity(data, seed=seed, quiet=True)]
    if seed != 10**5000:
        fits.append(lambda: fit_condition([TRIAL], seed=seed))
    for fit in fits:
        with pytest.raises(InputError) as err:
            fit()
        assert str(err.value).startswith(words) and "\n" not in str(err.value)


def test_a_model_that_is_neither_a_name_nor_a_force_model_is_refused_in_one_line() -> None:
    """get_model(['chen2024']) raised TypeError (unhashable type: 'list'), register_model('chen2024')
    AttributeError ('str' object has no attribute 'name')."""
    from mudforce.estimation.calibration import get_model, register_model

    with pytest.raises(InputError, match=r"^model must be a model name or a ForceModel, got list; known models: "):
        fit_condition([TRIAL], model=["chen2024"])  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"^model must be a model name or a ForceModel, got dict"):
        get_model({})  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"^register_model takes a ForceModel, got str$"):
        register_model("chen2024")  # type: ignore[arg-type]


@pytest.mark.parametrize(("low", "high", "shown"), [
    (1e3, float("inf"), "1000.0, inf"),  # the global search raised scipy's ValueError
    (1e3, 10**5000, "1000.0, an integer of 16610 bits"),  # the force overflowed (not finite), its repr ValueError
    (True, 10.0, "True, 10.0"),  # taken as 1
    (10.0, 1.0, "10.0, 1.0"),
], ids=["inf", "10**5000", "bool", "reversed"])
def test_a_force_model_with_bounds_that_are_not_finite_and_ordered_is_refused_when_made(low: Any, high: Any,
                                                                                      shown: str) -> None:
    from mudforce.estimation.calibration import ForceModel

    with pytest.raises(InputError) as err:
        ForceModel(name="s", parameter_names=("k",), force=lambda t, z, v, foot: z, bounds={"k": (low, high)},
                   defaults={"k": 1e6})
    assert str(err.value) == f"model s: bounds of k must be numbers with 0 < low < high < inf, got {shown}"


@pytest.mark.parametrize(("fields", "words"), [
    # a NaN default was taken: chen2024's lambda = NaN stopped the fit at scipy's ValueError (residuals not finite)
    ({"defaults": {"k": float("nan")}}, "model s: default of k must be a number with 0 < value < inf (the fit works "
                                        "on logarithms), got nan"),
    ({"defaults": {"k": -1.0}}, "model s: default of k must be a number with 0 < value < inf"),
    ({"defaults": {"k": "1e6"}}, "model s: default of k must be a number with 0 < value < inf"),
    # an unknown name was ignored: the parameter the user meant to hold was fitted
    ({"fixed": ("kk",)}, "model s: fixed names kk, not among its parameters k"),
    # two entries in the fit's vector for one parameter
    ({"parameter_names": ("k", "k")}, "model s: parameter_names repeats k; expected each name once"),
    # a list raised TypeError (unhashable type) at register_model; 3 was registered, then refused by get_model
    ({"name": ["s"]}, "a ForceModel's name must be a non-empty str (its --model NAME), got ['s']"),
    ({"name": 3}, "a ForceModel's name must be a non-empty str (its --model NAME), got 3"),
    ({"name": " "}, "a ForceModel's name must be a non-empty str (its --model NAME), got ' '"),
], ids=["nan-default", "negative-default", "str-default", "unknown-fixed", "repeated-name", "list-name", "int-name",
        "blank-name"])
def test_a_force_model_with_bad_defaults_fixed_or_names_is_refused_when_made(fields: dict[str, Any],
                                                                           words: str) -> None:
    from mudforce.estimation.calibration import ForceModel

    made: dict[str, Any] = {"name": "s", "parameter_names": ("k",), "force": lambda t, z, v, foot: z,
                            "bounds": {"k": (1.0, 1e9)}, "defaults": {"k": 1e6}, **fields}
    with pytest.raises(InputError) as err:
        ForceModel(**made)
    assert str(err.value).startswith(words) and "\n" not in str(err.value)


def test_register_model_refuses_a_built_in_name_and_takes_a_users_own_again() -> None:
    """register_model(ForceModel(name='granular_rft', ...)) replaced the built-in model without a word: every later
    fit of that name used the user's."""
    import dataclasses

    from mudforce.estimation.calibration import MODELS, register_model
    from mudforce.estimation.calibration.models import GRANULAR_RFT

    other = dataclasses.replace(GRANULAR_RFT, defaults={"k_rft": 1e6})
    with pytest.raises(InputError) as err:
        register_model(other)
    assert str(err.value) == ("register_model: 'granular_rft' is a built-in model's name; give your model another "
                              "name (not chen2024, drft, granular_rft, maxwell_only)")
    assert MODELS["granular_rft"] is GRANULAR_RFT
    register_model(GRANULAR_RFT)  # the built-in model itself: nothing changes
    assert MODELS["granular_rft"] is GRANULAR_RFT
    mine, revised = (dataclasses.replace(other, name="test_rft_variant", defaults={"k_rft": k}) for k in (1e6, 2e6))
    try:
        register_model(mine)
        register_model(revised)  # a user's own name: the revision replaces it
        assert MODELS["test_rft_variant"] is revised
    finally:
        MODELS.pop("test_rft_variant", None)


@pytest.mark.parametrize(("stage", "words"), [
    # fitted on all samples, without a word
    ({"window": "intrusions"}, "stage a: window must be one of intrusion, withdrawal, all, got 'intrusions'"),
    # ran the local search, without a word
    ({"search": "globl"}, "stage a: search must be local or global, got 'globl'"),
    # its letters were read as parameter names, none of them a parameter: the stage fitted nothing
    ({"parameters": "k"}, "stage a: parameters must be a tuple of parameter names, e.g. ('k_m_i', 'beta'), got 'k'"),
    ({"parameters": None}, "stage a: parameters must be a tuple of parameter names"),
    ({"prefix_fixed": "no"}, "stage a: prefix_fixed must be True or False, got 'no'"),
], ids=["window", "search", "str-parameters", "none-parameters", "prefix-fixed"])
def test_a_fit_stage_with_an_unknown_window_or_search_is_refused_when_made(stage: dict[str, Any], words: str) -> None:
    from mudforce.estimation.calibration import FitStage

    with pytest.raises(InputError) as err:
        FitStage(**{"name": "a", "parameters": ("k",), "window": "intrusion", **stage})
    assert str(err.value).startswith(words) and "\n" not in str(err.value)


def test_a_force_model_whose_stage_names_no_parameter_of_its_own_is_refused_when_made() -> None:
    """A misspelt name in a stage was skipped: the stage left the parameter where it was."""
    from mudforce.estimation.calibration import FitStage, ForceModel

    with pytest.raises(InputError) as err:
        ForceModel(name="s", parameter_names=("k", "b"), force=lambda t, z, v, foot: z,
                   bounds={"k": (1.0, 1e9), "b": (1.0, 1e9)}, defaults={"k": 1e6, "b": 1e3},
                   stages=(FitStage("a", ("k", "bb"), "intrusion"),))
    assert str(err.value) == "model s: stage a names bb, not among its parameters k, b"


@pytest.mark.parametrize(("fields", "words"), [
    # ignored: the search ran over the whole bounds
    ({"search_bounds": {"kk": (1e3, 1e4)}}, "model s: search_bounds names kk, not among its parameters k, b"),
    # searched without a word, from points outside the bounds
    ({"search_bounds": {"k": (1e4, 1e3)}}, "model s: search_bounds of k must be numbers with low < high that "
                                           "overlap its bounds (1, 1e+09), got 10000.0, 1000.0"),
    ({"search_bounds": {"k": (2e9, 3e9)}}, "model s: search_bounds of k must be numbers with low < high that "
                                           "overlap its bounds (1, 1e+09), got 2000000000.0, 3000000000.0"),
    # ignored: the defaults started instead
    ({"starts": ({"kk": 1e5},)}, "model s: starts[0] names 'kk', not among its parameters k, b"),
    # stopped the fit after the trials' preparation (maxwell_only's force: k_m_i must be finite)
    ({"starts": ({"k": 1e5}, {"k": float("nan")})}, "model s: starts[1] k must be a number with 0 < value < inf (the "
                                                    "fit works on logarithms), got nan"),
    # read as its keys: AttributeError ('str' object has no attribute 'get') after the trials' preparation
    ({"starts": {"k": 1e5}}, "model s: starts must be a tuple of mappings of parameter names to values [SI], got "
                             "dict"),
], ids=["search-name", "search-reversed", "search-beside", "start-name", "start-nan", "starts-dict"])
def test_a_force_model_with_bad_search_bounds_or_starts_is_refused_when_made(fields: dict[str, Any],
                                                                           words: str) -> None:
    from mudforce.estimation.calibration import ForceModel

    with pytest.raises(InputError) as err:
        ForceModel(**{"name": "s", "parameter_names": ("k", "b"), "force": lambda t, z, v, foot: z,
                      "bounds": {"k": (1.0, 1e9), "b": (1.0, 1e9)}, "defaults": {"k": 1e6, "b": 1e3}, **fields})
    assert str(err.value) == words
