"""identify's misfit flag means off-family (issue 23, point 4): quiet on clean in-family walks,
raised on a granular law F = k z and on a mud with alpha x2 and sigma_y x0.3 along the same path."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mudforce.estimation.calibration import identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import Walk, walk
from mudforce.steppers.simulation import simulate

CASES = ((1, 0.18), (2, 0.24), (3, 0.30))


@pytest.fixture(scope="module")
def walks() -> list[Walk]:
    """Three clean 10-s walks at 50 Hz (0.2 N force noise, 30 um depth noise)."""
    return [walk(w, seed=seed, duration=10.0, rate=50.0) for seed, w in CASES]


def _identify(wk: Walk, force: np.ndarray) -> tuple[bool, float]:
    res = identify_water_content(Trial("walk.csv", float(wk.water_content[0]), wk.time, wk.depth, force))
    return res.model_misses_data, res.misfit_ratio


def test_quiet_on_clean_in_family_walks(walks: list[Walk]) -> None:
    """In family the RMSE is the noise: the ratio is near 1 (measured 0.80-0.93; 0.68-0.78 since it is read at the
    best member, the depth offset and force lag refitted there; 0.54-0.69 since the flag reads the model where the
    foot may be stuck as the set of the relaxations it may have had, the walks' pauses among them) and nothing is
    flagged."""
    for wk in walks:
        flagged, ratio = _identify(wk, wk.force)
        assert not flagged and 0.45 < ratio < 1.1


def test_fires_on_a_granular_law(walks: list[Walk]) -> None:
    """F = k z with k matching the peak, the same noise: flagged on every walk (measured ratio >= 28 before each
    sample's square was capped at 25, so that the ratio is at most 5; then >= 3.6; read at the best member, the
    depth offset and force lag refitted there, >= 3.49)."""
    rng = np.random.default_rng(7)
    for wk in walks:
        z = np.maximum(wk.depth_true, 0.0)
        force = np.max(wk.force_true) / np.max(z) * z + 0.2 * rng.standard_normal(z.size)
        flagged, ratio = _identify(wk, force)
        assert flagged and ratio > 3.0


def test_fires_on_a_mud_outside_table_one(walks: list[Walk]) -> None:
    """alpha x2 and sigma_y x0.3 along the same path: flagged on every walk (measured ratio >= 8 uncapped, >= 3.8
    with each sample's square capped at 25; 2.61, 3.49 and 3.68 read at the best member, the depth offset and force
    lag refitted there)."""
    rng = np.random.default_rng(8)
    for wk in walks:
        q = wk.params[0]
        odd = dataclasses.replace(q, alpha=2.0 * q.alpha, sigma_y=0.3 * q.sigma_y)
        force = np.asarray(simulate(wk.time, wk.depth_true, odd, Foot.paper(), velocity_filter="exact").force)
        flagged, ratio = _identify(wk, force + 0.2 * rng.standard_normal(force.size))
        assert flagged and ratio > 2.5


def test_a_local_discretisation_error_does_not_mask_an_off_family_mud() -> None:
    """At 100 Hz (seed 2) the half-rate model leaves the data's for a few strides (disc. error ~5 N RMS).

    Added to one global floor it hid this off-family mud (ratio 0.69, silent); each sample weighed by
    its own floor, the mud is flagged.
    """
    wk = walk(0.24, seed=2, duration=10.0, rate=100.0)
    q = MudParameters.from_water_content(0.24)
    odd = dataclasses.replace(q, alpha=2.0 * q.alpha, sigma_y=0.3 * q.sigma_y)
    force = np.asarray(simulate(wk.time, wk.depth_true, odd, Foot.paper(), velocity_filter="exact").force)
    res = identify_water_content(Trial("walk.csv", 0.24, wk.time, wk.depth,
                                       force + 0.2 * np.random.default_rng(2).standard_normal(force.size)))
    assert res.discretisation > 1.0
    # measured 3.95 (each sample capped at 5 floors); 2.71 read at the best member, offset and lag refitted there
    assert res.model_misses_data and res.misfit_ratio > 2.5


def test_a_law_missing_many_samples_by_a_little_is_flagged_by_the_tail_too(monkeypatch: pytest.MonkeyPatch) -> None:
    """A linear law F = k z along a MuJoCo trot's foot path at 50 Hz (the sensor-chain bench's flag table, seed 8,
    robot 8; ``tests/estimation/data``): least squares absorbs it with a -7.5 mm depth offset. The clipped statistic
    read 1.24, under the ratio's 1.25, until the rest band after necking became the post-necking force (its low
    edge had been the Maxwell element's, hundreds of newtons of suction, and the misfit floor with it: 1.31 since, so
    the ratio fires too); 5.4 % of the samples lie beyond three floors at the least statistic found, over the tail's
    4.5 %, so with the ratio's limit raised past it the tail alone still flags it, with its own warning
    (docs/estimation.md, "What is not met"). An in-family recording at 4.1 % passes the tail's limit (its ratio
    1.15 and that 4.1 % then fire the combined reading: tests/estimation/test_identify_member.py)."""
    from pathlib import Path

    from mudforce.estimation.calibration import identify as identify_module
    from mudforce.estimation.calibration.fit import MISFIT_WARNING_RATIO
    from mudforce.estimation.calibration.identify import TAIL_SHARE_WARNING
    from mudforce.motions.quadruped import ROBOT_FOOT

    data = Path(__file__).parent / "data" / "robot_trot_fast_linear_law_50hz_seed8.csv"
    t, z, f = np.loadtxt(data, delimiter=",", skiprows=1, unpack=True)
    trial = Trial("linear.csv", 0.306, t, z, f)
    res = identify_water_content(trial, ROBOT_FOOT)
    assert res.misfit_ratio == pytest.approx(1.311, abs=0.002) and res.misfit_ratio > MISFIT_WARNING_RATIO
    assert res.tail_share == pytest.approx(0.0539, abs=0.0005) and res.tail_share > TAIL_SHARE_WARNING
    assert res.model_misses_data and res.to_dict()["model_misses_data"] is True
    assert res.to_dict()["tail_share"] == res.tail_share
    # as if the ratio read under its limit (the members that pass, and so the figures, move with it)
    monkeypatch.setattr(identify_module, "MISFIT_WARNING_RATIO", 1.35)
    quiet_ratio = identify_water_content(trial, ROBOT_FOOT)
    assert quiet_ratio.misfit_ratio <= 1.35 and quiet_ratio.tail_share > TAIL_SHARE_WARNING
    assert quiet_ratio.model_misses_data
    assert sum("beyond three noise floors" in w for w in quiet_ratio.warnings) == 1


def test_a_mud_read_at_the_family_s_edge_is_flagged() -> None:
    """The one off-family recording of the flag bench's six seeds that neither the ratio nor the tail caught: a mud
    with alpha x2 and sigma_y x0.3 (W 21.5 %) along a MuJoCo trot's foot path at 50 Hz (seed 8, robot 0;
    ``tests/estimation/data``), read at the dry edge, 15 %, with the ratio at 1.20 and 4.2 % of the samples beyond
    three floors; the model's own parameters, varied off the family, explained 1.035 of the standardised residual's
    mean square there, over the third reading's 0.9 (docs/estimation.md, "What another mud explains"). Since the flag
    reads the model where the foot may be stuck as the set of the relaxations it may have had ("A stuck foot read as
    a set"), the ratio reads 1.09, the tail 4.4 % and the other mud 0.45: flagged by two readings near their limits
    (0.87 and 0.98 of them)."""
    from pathlib import Path

    from mudforce.estimation.calibration.fit import MISFIT_WARNING_RATIO
    from mudforce.estimation.calibration.identify import NEAR_LIMITS_WARNING, OTHER_MUD_WARNING, TAIL_SHARE_WARNING
    from mudforce.motions.quadruped import ROBOT_FOOT

    data = Path(__file__).parent / "data" / "robot_trot_alpha_x2_sigma_y_x03_50hz_seed8.csv"
    t, z, f = np.loadtxt(data, delimiter=",", skiprows=1, unpack=True)
    res = identify_water_content(Trial("alpha_x2.csv", 0.2154, t, z, f), ROBOT_FOOT)
    assert res.water_content == pytest.approx(0.15, abs=1e-3)
    assert res.misfit_ratio == pytest.approx(1.093, abs=0.002) and res.misfit_ratio <= MISFIT_WARNING_RATIO
    assert res.tail_share == pytest.approx(0.0439, abs=0.0005) and res.tail_share <= TAIL_SHARE_WARNING
    assert res.other_mud == pytest.approx(0.453, abs=0.005) and res.other_mud <= OTHER_MUD_WARNING
    assert res.misfit_ratio / MISFIT_WARNING_RATIO > NEAR_LIMITS_WARNING
    assert res.tail_share / TAIL_SHARE_WARNING > NEAR_LIMITS_WARNING
    assert res.model_misses_data and res.to_dict()["other_mud"] == res.other_mud
    assert sum(w.startswith("two of the misfit flag's three readings") for w in res.warnings) == 1


def test_a_law_near_two_limits_at_once_is_flagged() -> None:
    """A linear law F = k z along a MuJoCo walk's foot path at 50 Hz (the misfit-flag bench's seed 21, robot 0;
    ``tests/estimation/data``), the truth 30.6 %: read at 24.1 % [22.5, 25.5] with a -7.4 mm depth offset, the ratio
    at 1.242 (limit 1.25), 4.0 % of the samples beyond three floors (4.5 %) and another mud explaining 0.72 (0.9).
    No reading alone fired, and the interval missed the truth: confidently wrong. Two readings past 80 % of their
    limits fire the flag, with a warning of its own (docs/estimation.md, "Two readings near their limits")."""
    from pathlib import Path

    from mudforce.estimation.calibration.fit import MISFIT_WARNING_RATIO
    from mudforce.estimation.calibration.identify import (
        NEAR_LIMITS_WARNING,
        OTHER_MUD_WARNING,
        TAIL_SHARE_WARNING,
    )
    from mudforce.motions.quadruped import ROBOT_FOOT

    data = Path(__file__).parent / "data" / "robot_walk_linear_law_50hz_seed21.csv"
    t, z, f = np.loadtxt(data, delimiter=",", skiprows=1, unpack=True)
    res = identify_water_content(Trial("linear.csv", 0.3062, t, z, f), ROBOT_FOOT)
    assert res.water_content == pytest.approx(0.2408, abs=5e-4) and res.interval[1] < 0.3062
    assert res.misfit_ratio == pytest.approx(1.242, abs=0.002) and res.misfit_ratio <= MISFIT_WARNING_RATIO
    assert res.tail_share == pytest.approx(0.0399, abs=0.0005) and res.tail_share <= TAIL_SHARE_WARNING
    assert res.other_mud == pytest.approx(0.724, abs=0.005) and res.other_mud <= OTHER_MUD_WARNING
    shares = (res.misfit_ratio / MISFIT_WARNING_RATIO, res.tail_share / TAIL_SHARE_WARNING,
              res.other_mud / OTHER_MUD_WARNING)
    assert sum(x > NEAR_LIMITS_WARNING for x in shares) == 3
    assert res.model_misses_data and res.to_dict()["model_misses_data"] is True
    assert sum(w.startswith("two of the misfit flag's three readings are past 80% of their limits")
               for w in res.warnings) == 1


def test_what_another_mud_explains_is_little_in_family_and_much_off_it(walks: list[Walk]) -> None:
    """On the clean walks the parameters off the family explain a few hundredths of a floor squared a sample
    (measured 0.02-0.05); along the same paths, a mud with alpha x2 and sigma_y x0.3 far more (measured >= 1.9)."""
    rng = np.random.default_rng(8)
    for wk in walks:
        assert identify_water_content(Trial("walk.csv", 0.2, wk.time, wk.depth, wk.force)).other_mud < 0.1
        q = wk.params[0]
        odd = dataclasses.replace(q, alpha=2.0 * q.alpha, sigma_y=0.3 * q.sigma_y)
        force = np.asarray(simulate(wk.time, wk.depth_true, odd, Foot.paper(), velocity_filter="exact").force)
        res = identify_water_content(Trial("walk.csv", 0.2, wk.time, wk.depth,
                                           force + 0.2 * rng.standard_normal(force.size)))
        assert res.other_mud > 1.5


def test_what_another_mud_explains_has_its_own_warning(walks: list[Walk], monkeypatch: pytest.MonkeyPatch) -> None:
    """Where the ratio and the tail read under their limits (here: the limits raised past them), the third reading
    fires the flag alone and says so in its own warning."""
    import mudforce.estimation.calibration.identify as identify_module

    wk = walks[0]
    q = wk.params[0]
    odd = dataclasses.replace(q, alpha=2.0 * q.alpha, sigma_y=0.3 * q.sigma_y)
    force = np.asarray(simulate(wk.time, wk.depth_true, odd, Foot.paper(), velocity_filter="exact").force)
    noisy = force + 0.2 * np.random.default_rng(8).standard_normal(force.size)
    trial = Trial("walk.csv", 0.2, wk.time, wk.depth, noisy)
    monkeypatch.setattr(identify_module, "MISFIT_WARNING_RATIO", 1e3)
    monkeypatch.setattr(identify_module, "TAIL_SHARE_WARNING", 1.0)
    monkeypatch.setattr(identify_module, "NEAR_LIMITS_WARNING", 1e3)
    res = identify_water_content(trial)
    assert res.other_mud > identify_module.OTHER_MUD_WARNING and res.model_misses_data
    assert sum(w.startswith("another mud explains") for w in res.warnings) == 1


def test_a_force_of_the_wrong_sign_is_named_as_such() -> None:
    """A sensor with compression negative was said only in the general misfit message (a 10-s walk at 24 %, negated:
    15.98 % [15, 35], "RMSE 38 N is 4.3 times the noise floor ... another mud, another foot than assumed, or a model
    error"). Now one line first that names the sign and the convention; none on the walk as recorded, nor on a force
    of noise alone, whose intrusion samples lie about half below the tare (none on the suite's and synthesize's
    in-family trials: at most 6 % of those samples below the tare, where 90 % warns)."""
    from mudforce.estimation.calibration.preprocess import _force_sign_warning, prepare_trial

    wk = walk(0.24, seed=2, duration=1.0, rate=50.0)
    noise = 0.2 * np.random.default_rng(3).standard_normal(wk.time.size)
    for force in (wk.force, noise):
        assert _force_sign_warning(prepare_trial(Trial("walk.csv", 0.24, wk.time, wk.depth, force))) == ""
    res = identify_water_content(Trial("walk.csv", 0.24, wk.time, wk.depth, -wk.force))
    assert res.warnings[0] == (
        "walk.csv: the force lies below its tare on 100% of the 14 samples where the foot goes down well below the "
        "surface: it looks sign-flipped; mudforce expects the force + up (the mud pushing back on a foot going in "
        "reads positive): negate the force column if compression reads negative")
