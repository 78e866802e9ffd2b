"""fit warns when the depth noise carries most of the noise floor: errors in variables (issue 23, point 5 for fit).

On the sensor-chain bench's fresh seed 5 (full size, 2026-11-29) a gait walk under 1 mm of depth noise was fitted
with ``k_m_w`` 3.09 standard errors low and no warning: least squares takes the errors to be in the force, and
there 87 % of the floor's variance was the depth noise carried through (docs/estimation.md, "fit under a noisy
depth"). The floor's parts and the warning's threshold are checked here on a shorter walk of the same kind.
"""

from __future__ import annotations

import numpy as np
import pytest

from mudforce import Foot, MudParameters, simulate
from mudforce.estimation.calibration import fit_condition
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.fit import DEPTH_NOISE_SHARE_WARNING, ConditionFit
from mudforce.estimation.calibration.preprocess import noise_floor, noise_floor_parts, prepare_trial
from mudforce.motions.gait import gait
from mudforce.motions.sensor_chain import SensorChain, apply

W = 0.3266


def _walk(depth_noise: float) -> Trial:
    path = gait(7, duration=12.0, rate=2000.0)
    force = np.asarray(simulate(path.time, path.depth, MudParameters.from_water_content(W), Foot.paper(),
                                velocity_filter="exact").force)
    chain = SensorChain(force_noise=0.2, depth_noise=depth_noise, force_bias=0.3, rate=100.0)
    t, z, f = apply(path.time, path.depth, force, chain, 11)
    return Trial("walk", W, t, z, f)


@pytest.fixture(scope="module")
def fits() -> dict[float, ConditionFit]:
    return {noise: fit_condition([_walk(noise)], Foot.paper(), seed=0) for noise in (3e-5, 1e-3)}


def _depth_warnings(fit: ConditionFit) -> list[str]:
    return [w for w in fit.warnings if "errors in variables" in w]


def test_a_walk_under_1_mm_of_depth_noise_is_warned_of_errors_in_variables(fits: dict[float, ConditionFit]) -> None:
    (warning,) = _depth_warnings(fits[1e-3])
    assert warning.startswith("the depth noise (")
    share = float(warning.split(" carries ")[1].split("%")[0]) / 100.0
    assert share > DEPTH_NOISE_SHARE_WARNING


def test_a_clean_depth_is_not(fits: dict[float, ConditionFit]) -> None:
    assert _depth_warnings(fits[3e-5]) == []


def test_the_floor_is_its_parts_sum_and_the_same_bits_as_before() -> None:
    """noise_floor is noise_floor_parts' total; the depth part is (dF/dz * depth noise)^2 and at most the total."""
    trial = _walk(1e-3)
    prepared = prepare_trial(trial)
    q = MudParameters.from_water_content(W)

    def force_at(z: np.ndarray) -> np.ndarray:
        return np.asarray(simulate(prepared.time, z, q, Foot.paper()).force)

    model = force_at(prepared.depth)
    total, depth = noise_floor_parts(prepared, model, force_at)
    np.testing.assert_array_equal(noise_floor(prepared, model, force_at), total)
    assert prepared.depth_noise > 0.0 and np.all(depth >= 0.0) and np.all(depth <= total)
    h = 1e-6
    sens = (force_at(prepared.depth + h) - force_at(prepared.depth - h)) / (2.0 * h)
    np.testing.assert_array_equal(depth, (sens * prepared.depth_noise) ** 2)
    assert float(np.mean(depth) / np.mean(total)) > DEPTH_NOISE_SHARE_WARNING
