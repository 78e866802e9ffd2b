"""fit_3d: the 3-D law's parameters recovered from noisy synthetic force vectors, honest errors, bad input refused."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import mudforce as mf
from mudforce.errors import InputError
from mudforce.estimation.calibration.fit3d import fit_3d
from mudforce.model import shapes
from mudforce.steppers.contact3d import simulate_3d

SHAPE = shapes.sphere(0.04, resolution=0.015)  # 48 elements
MUD = mf.MudParameters.from_water_content(0.25)
NOISE = 0.05  # [N]


def _motion() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """0.4 s at 500 Hz: down into the mud, sliding 20 mm while tilting, out."""
    t = np.arange(200) / 500.0
    s = t / t[-1]
    pos = np.stack([0.02 * np.clip((s - 0.3) / 0.4, 0, 1), 0.005 * np.sin(3 * s),
                    0.03 - 0.045 * np.sin(np.pi * s)], axis=1)
    angle = 0.2 * np.sin(2 * np.pi * s)
    quat = np.stack([np.cos(angle / 2), np.zeros_like(s), np.sin(angle / 2), np.zeros_like(s)], axis=1)
    return t, pos, quat


@pytest.fixture(scope="module")
def data() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    t, pos, quat = _motion()
    truth = simulate_3d(t, pos, quat, MUD.replace(sigma_y=1.3 * MUD.sigma_y), SHAPE, lateral_stiffness=0.5 * MUD.k_m_w)
    noisy = truth.force + np.random.default_rng(0).normal(scale=NOISE, size=truth.force.shape)
    return t, pos, quat, noisy


def test_fit_3d_recovers_the_lateral_stiffness_and_the_shear_yield(
        data: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    t, pos, quat, forces = data
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a fit of the right model to white noise warns of nothing
        fit = fit_3d(t, pos, quat, forces, SHAPE, MUD, free=("lateral_stiffness", "sigma_y"), noise=NOISE)
    truth = {"lateral_stiffness": 0.5 * MUD.k_m_w, "sigma_y": 1.3 * MUD.sigma_y}
    for name, value in truth.items():  # started a factor 2 and 1.3 away
        error = fit.standard_errors[name]
        assert 0.0 < error < 1e-2 * value
        assert abs(fit.values[name] - value) < 4.0 * error
    assert fit.success and fit.residual_rms == pytest.approx(NOISE, rel=0.1)
    assert abs(fit.autocorrelation) < 0.2
    assert fit.params.sigma_y == fit.values["sigma_y"] and fit.lateral_stiffness == fit.values["lateral_stiffness"]


def test_a_model_that_misses_the_data_widens_and_warns(
        data: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    t, pos, quat, forces = data
    wrong = MUD.replace(k_m_i=3.0 * MUD.k_m_i)  # held fixed, wrong: the vertical force misses in shape
    with pytest.warns(RuntimeWarning, match="misses the data"):
        fit = fit_3d(t, pos, quat, forces, SHAPE, wrong, free="lateral_stiffness", noise=NOISE)
    assert fit.residual_rms > 2.0 * NOISE and fit.autocorrelation > 0.5
    good = fit_3d(t, pos, quat, forces, SHAPE, MUD.replace(sigma_y=1.3 * MUD.sigma_y), free="lateral_stiffness")
    assert fit.standard_errors["lateral_stiffness"] > 5.0 * good.standard_errors["lateral_stiffness"]


def test_fit_3d_refuses_bad_input_in_one_line(data: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    t, pos, quat, forces = data
    bad_pos = pos.copy()
    bad_pos[3, 0] = math.nan
    for kwargs, match in (
        ({"positions": bad_pos}, "positions must be finite"),
        ({"forces": forces[:, :2]}, "forces must have shape"),
        ({"quaternions": quat * 1.01}, "norm 1"),
        ({"time": t[::-1]}, "strictly increasing"),
        ({"free": ("beta",)}, "cannot fit"),
        ({"free": ("sigma_y", "sigma_y")}, "twice"),
        ({"params0": "mud"}, "MudParameters"),
        ({"noise": -1.0}, "noise"),
        ({"lateral_stiffness": 0.0}, "lateral_stiffness"),
    ):
        args = {"time": t, "positions": pos, "quaternions": quat, "forces": forces, "shape": SHAPE, "params0": MUD,
                **kwargs}
        with pytest.raises(InputError, match=match) as info:
            fit_3d(**args)
        assert "\n" not in str(info.value)
