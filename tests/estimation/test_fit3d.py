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


def test_fit_3d_recovers_the_bearing_scale() -> None:
    """The sideways bearing's scale (3D-RFT's granular bearing times it, law3d.bearing_stress), 0.4 in the data,
    fitted from 1 with sigma_y: within 4 standard errors of under 2 %, and Fit3D carries it."""
    t, pos, quat = _motion()
    truth = simulate_3d(t, pos, quat, MUD, SHAPE, bearing_scale=0.4)
    forces = truth.force + np.random.default_rng(1).normal(scale=NOISE, size=truth.force.shape)
    fit = fit_3d(t, pos, quat, forces, SHAPE, MUD, free=("bearing_scale", "sigma_y"), noise=NOISE)
    for name, value in (("bearing_scale", 0.4), ("sigma_y", MUD.sigma_y)):
        error = fit.standard_errors[name]
        assert 0.0 < error < 2e-2 * value
        assert abs(fit.values[name] - value) < 4.0 * error
    assert fit.bearing_scale == fit.values["bearing_scale"] and fit.lateral_stiffness == MUD.k_m_w


def test_a_model_that_misses_the_data_widens_and_warns(
        data: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    t, pos, quat, forces = data
    wrong = MUD.replace(k_m_i=3.0 * MUD.k_m_i)  # held fixed, wrong: the vertical force misses in shape
    with pytest.warns(RuntimeWarning, match="misses the data") as record:
        fit = fit_3d(t, pos, quat, forces, SHAPE, wrong, free="lateral_stiffness", noise=NOISE)
    assert fit.residual_rms > 2.0 * NOISE and fit.autocorrelation > 0.5
    # at the caller's line (was _plumbing/blas.py's, the BLAS-thread wrapper's, one frame short)
    assert {w.filename for w in record} == {__file__}
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
        # free's repr in the message: ValueError (4300 digits) for 10**5000, over lines for a 2-D array
        ({"free": ("sigma_y", 10**5000)}, "got an integer of 16610 bits among them$"),
        ({"free": np.full((2, 2), "sigma_y")}, "got ndarray$"),
        # its bytes iterated as ints: "got 115 among them"
        ({"free": b"sigma_y"}, "free must name one or more of .* as a str or a sequence of str, got bytes$"),
        ({"free": bytearray(b"sigma_y")}, "got bytearray$"),
        ({"params0": "mud"}, "MudParameters"),
        ({"noise": -1.0}, "noise"),
        ({"lateral_stiffness": 0.0}, "lateral_stiffness"),
        # read by np.asarray: strings parsed, complex cut, booleans as 0/1, ragged lists a ValueError
        ({"time": [str(v) for v in t]}, "time must be an array of real numbers"),
        ({"forces": forces + 0j}, "complex"),
        ({"forces": forces > 0.0}, "boolean"),
        ({"time": [[0.0], [0.1, 0.2]]}, "time must be an array of real numbers"),
        ({"noise": True}, "noise must be a number"),  # was 1 N
        ({"lateral_stiffness": True}, "lateral_stiffness"),  # was 1 Pa/m
        ({"lateral_stiffness": 1e13}, r"within \(0, 1e\+12\]"),
        ({"time": t + 1e12}, "beyond"),  # simulate_3d's time bounds
        ({"time": t * 1e-9}, "steps within"),  # refused from inside the fit as "no foot was stepped"
        ({"forces": forces * 1e300}, r"forces must be within \+-1e\+07 N"),  # fitted to an infinite residual
        # taken as one value per simulated point (2p + 1 = 3 here): a Jacobian across surfaces or widths
        ({"surface_height": [0.0, 0.0, 0.01]}, "surface_height must be a number"),
        ({"width": [0.04, 0.04, 0.05]}, "width must be a number"),
        ({"width": True}, "width must be a number"),  # was in MudContacts3D's words, "widths ..."
        ({"time": 0.0}, r"time must have shape \(m,\) \[s\], got \(\)$"),  # was "must have shape (-1,)"
        ({"time": t[None]}, r"time must have shape \(m,\) \[s\], got \(1, 200\)$"),
    ):
        args = {"time": t, "positions": pos, "quaternions": quat, "forces": forces, "shape": SHAPE, "params0": MUD,
                **kwargs}
        with pytest.raises(InputError, match=match) as info:
            fit_3d(**args)
        assert "\n" not in str(info.value)


def test_fit_3d_searches_only_values_the_model_takes() -> None:
    """A start near a bound of the model (a lateral stiffness or k_m_w of 1e12, MudContacts3D's and MudParameters'
    largest) was searched up to 1000 times above it, and the fit was refused mid-way by a step beyond it."""
    t, pos, quat = _motion()
    t, pos, quat = t[:24], pos[:24], quat[:24]
    forces = simulate_3d(t, pos, quat, MUD, SHAPE).force
    for kwargs in ({"lateral_stiffness": 1e12}, {"free": "k_m_w", "params0": MUD.replace(k_m_w=1e12)}):
        args = {"free": "lateral_stiffness", "params0": MUD, "max_iterations": 3, **kwargs}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # the data hardly determine it: not the point here
            fit = fit_3d(t, pos, quat, forces, SHAPE, **args)  # type: ignore[arg-type]
        assert all(0.0 < v <= 1e12 for v in fit.values.values())


def test_fit_3d_names_the_sample_of_a_pose_the_model_refuses() -> None:
    """A pose beyond the model's bounds was refused from inside the fit in MudContacts3D's words, "foot 0: ...; no
    foot was stepped" (foot 0: a point of the Jacobian's differences), without the sample; now in simulate_3d's."""
    t, pos, quat = _motion()
    t, pos, quat = t[:12], pos[:12].copy(), quat[:12]
    forces = simulate_3d(t, pos, quat, MUD, SHAPE).force
    far, deep = pos.copy(), pos.copy()
    far[5, 0] = 2e4
    deep[7, 2] = -500.0
    for moved, match in ((far, r"^sample 5 \(t = 0\.01 s\): position x and y must be within \+-10000 m"),
                         (deep, r"^sample 7 \(t = 0\.014 s\): element \d+ would be at depth")):
        with pytest.raises(InputError, match=match) as info:
            fit_3d(t, moved, quat, forces, SHAPE, MUD)
        assert "foot 0" not in str(info.value) and "\n" not in str(info.value)
