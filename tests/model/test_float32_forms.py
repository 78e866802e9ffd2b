"""The float32 forms of mudforce.model.equations (used by the JAX step) against the CPU stepper's forms.

Each increment form equals its CPU counterpart in exact arithmetic: in
float64 they agree to a few ulp on a grid of values, and in float32 the
increment forms are the more accurate (why the JAX step uses them).
"""

from __future__ import annotations

import math

import numpy as np

from mudforce.model import equations as eq

EPS = np.finfo(np.float64).eps

# a grid: strains [m], velocities [m/s], relaxation times [s], step lengths [s]
STRAIN = np.array([-2e-2, -3e-3, -1e-5, 0.0, 4e-6, 2e-3, 1.5e-2])
VELOCITY = np.array([-0.5, -0.03, -1e-4, 0.0, 2e-3, 0.1, 0.4])
TAU = np.array([1e-4, 3e-3, 0.02, 0.15, 1.0])
STEP = np.array([1e-5, 1e-4, 1e-3, 4e-3, 0.05])
# Eq. (7)'s filter: damping ratios (under, critical, over), natural frequencies [rad/s]
ZETA = np.array([0.05, 0.4, 0.99, 1.0, 1.01, 1.8, 6.0])
OMEGA = np.array([5.0, 60.0, 400.0, 2000.0])


def _grid(*axes: np.ndarray) -> list[np.ndarray]:
    return [a.ravel() for a in np.meshgrid(*axes, indexing="ij")]


def _response(h: np.ndarray, zeta: np.ndarray, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(g, G) of the compiled neck_filter_response, element by element."""
    out = np.array([eq.neck_filter_response(float(a), float(b), float(c))
                    for a, b, c in zip(h, zeta, omega, strict=True)])
    return out[:, 0], out[:, 1]


def _elementary(h: np.ndarray, zeta: np.ndarray, omega: np.ndarray) -> dict[str, np.ndarray]:
    """The elementary functions of Eq. (7)'s response at age h, as the JAX step forms them (float64, numpy)."""
    a = zeta * omega
    under = zeta < 1.0
    over = zeta > 1.0
    wd = omega * np.sqrt(np.where(under, 1.0 - zeta * zeta, 1.0))
    mu = omega * np.sqrt(np.where(over, zeta * zeta - 1.0, 1.0))
    x = wd * h
    y = mu * h
    s_u = np.where(x > 1e-6, np.sin(x) / wd, h * (1.0 - x * x / 6.0))
    s_o = np.where(y > 1e-6, np.sinh(y) / mu, h * (1.0 + y * y / 6.0))
    return {
        "rate": a,
        "decay": np.exp(-a * h),
        "decay_m1": np.expm1(-a * h),
        "c": np.where(under, np.cos(x), np.where(over, np.cosh(y), 1.0)),
        "c_m1": np.where(under, -2.0 * np.sin(0.5 * x) ** 2, np.where(over, 2.0 * np.sinh(0.5 * y) ** 2, 0.0)),
        "s_over": np.where(under, s_u, np.where(over, s_o, h)),
    }


# ----------------------------------------------------------------------------- Eq. (3)
def test_maxwell_increment_equals_the_step_to_a_few_ulp() -> None:
    e, v, tau, h = _grid(STRAIN, VELOCITY, TAU, STEP)
    step = eq.maxwell_strain_step.py_func(e, v, tau, np.exp(-h / tau))
    inc = eq.maxwell_strain_increment.py_func(e, v, tau, -np.expm1(-h / tau))
    scale = np.abs(e) + np.abs(v * tau)
    assert (np.abs(inc - step) <= 4.0 * EPS * scale).all()
    # exact where the element does not move (e = v tau) or the step is empty
    assert eq.maxwell_strain_increment(2e-3, 0.1, 0.02, 0.7) == 2e-3
    assert eq.maxwell_strain_increment(-3e-3, 0.4, 0.02, 0.0) == -3e-3


def test_maxwell_increment_keeps_float32_digits_over_many_steps() -> None:
    """1000 steps at h/tau = 1e-3..1e-2 in float32: the increment form stays at rounding, the CPU form drifts."""
    tau = np.array([0.1, 0.2, 0.37, 0.5, 0.73, 1.0, 0.13, 0.29])
    h = 1e-3
    v, e0 = 0.02, -1e-3
    n = 1000
    exact = v * tau + (e0 - v * tau) * np.exp(-n * h / tau)  # float64 closed form after n steps
    f = np.float32
    t32 = tau.astype(f)
    decay = np.exp(-f(h) / t32)
    growth = -np.expm1(-f(h) / t32)
    e_step = np.full(tau.shape, e0, dtype=f)
    e_inc = e_step.copy()
    for _ in range(n):
        e_step = eq.maxwell_strain_step.py_func(e_step, f(v), t32, decay)
        e_inc = eq.maxwell_strain_increment.py_func(e_inc, f(v), t32, growth)
    assert e_inc.dtype == f
    scale = np.abs(v * tau) + abs(e0)
    err_inc = np.abs(e_inc - exact) / scale
    err_step = np.abs(e_step - exact) / scale
    assert err_inc.max() <= 3e-6
    assert err_inc.max() < 0.5 * err_step.max()


# ----------------------------------------------------------------------------- Eq. (7)
def test_closed_form_is_the_responses_arithmetic() -> None:
    h, zeta, omega = _grid(np.array([0.0, 1e-4, 3e-3, 0.02]), ZETA, OMEGA)
    parts = _elementary(h, zeta, omega)
    mid = ~((zeta > 1.0) & (omega * np.sqrt(np.maximum(zeta * zeta - 1.0, 0.0)) * h >= 30.0))
    g, gi = eq.neck_filter_closed_form.py_func(parts["decay"], parts["c"], parts["s_over"], parts["rate"])
    g_ref, gi_ref = _response(h, zeta, omega)
    # the same operations on the same elementary functions; numpy's and libm's exp/sin/cos may differ by an ulp
    np.testing.assert_allclose(g[mid], g_ref[mid], rtol=0, atol=8 * EPS)
    np.testing.assert_allclose(gi[mid], gi_ref[mid], rtol=8 * EPS, atol=0)
    # on the elementary functions the compiled response computes, bit for bit
    a, o, t = 0.4 * 400.0, 400.0, 3e-3
    wd = o * math.sqrt(1.0 - 0.16)
    got = eq.neck_filter_closed_form(math.exp(-a * t), math.cos(wd * t), math.sin(wd * t) / wd, a)
    assert got == eq.neck_filter_response.py_func(t, 0.4, o)


def test_response_increment_is_g_minus_one_to_a_few_ulp() -> None:
    """Where g(h) is near 1 (|g - 1| < 1/4, where the JAX step uses it); on longer steps its terms cancel."""
    h, zeta, omega = _grid(STEP, ZETA, OMEGA)
    parts = _elementary(h, zeta, omega)
    gm1 = eq.neck_filter_response_increment.py_func(parts["decay_m1"], parts["c_m1"], parts["s_over"], parts["rate"])
    g_ref, _ = _response(h, zeta, omega)
    short = np.abs(g_ref - 1.0) < 0.25
    assert short.sum() > 60
    np.testing.assert_allclose(gm1[short], g_ref[short] - 1.0, rtol=0, atol=4 * EPS)


def test_response_increment_keeps_float32_digits() -> None:
    """At 1 kHz g(h) - 1 is ~omega_0 h: from a rounded float32 g(h) it loses digits, the increment form keeps them."""
    h, zeta, omega = _grid(np.array([1e-3, 5e-4]), ZETA[ZETA < 1.5], OMEGA[:3])
    g_ref, _ = _response(h, zeta, omega)
    truth = g_ref - 1.0
    p32 = {k: a.astype(np.float32) for k, a in _elementary(h, zeta, omega).items()}
    inc = eq.neck_filter_response_increment.py_func(p32["decay_m1"], p32["c_m1"], p32["s_over"], p32["rate"])
    direct = eq.neck_filter_closed_form.py_func(p32["decay"], p32["c"], p32["s_over"], p32["rate"])[0] - np.float32(1)
    err_inc = np.abs(inc.astype(np.float64) - truth) / np.abs(truth)
    err_direct = np.abs(direct.astype(np.float64) - truth) / np.abs(truth)
    assert err_inc.max() <= 1e-5
    assert err_inc.max() < 0.1 * err_direct.max()


def test_transition_increment_is_the_matrix_minus_identity() -> None:
    h, zeta, omega = _grid(STEP, ZETA, OMEGA)
    g_h, gi_h = _response(h, zeta, omega)
    phi = np.array(eq.neck_filter_transition.py_func(zeta, omega, g_h, gi_h))
    d = np.array(eq.neck_filter_transition_increment.py_func(zeta, omega, g_h - 1.0, gi_h))  # g_h - 1: exact
    scale = 1.0 + np.abs(phi).max(axis=0)
    np.testing.assert_array_less(np.abs(d[0] - (phi[0] - 1.0)), 4 * EPS * scale)
    np.testing.assert_array_equal(d[1], phi[1])
    np.testing.assert_array_equal(d[2], phi[2])
    np.testing.assert_array_equal(d[3], phi[3] - 1.0)


def test_update_increment_follows_the_update_over_many_steps() -> None:
    """x + (Phi - I) x against Phi x, 2000 steps of 1 ms from necking (g = 1, G = 0), float64."""
    zeta, omega = _grid(ZETA, OMEGA[:3])
    h = np.full_like(zeta, 1e-3)
    g_h, gi_h = _response(h, zeta, omega)
    phi = eq.neck_filter_transition.py_func(zeta, omega, g_h, gi_h)
    d = eq.neck_filter_transition_increment.py_func(zeta, omega, g_h - 1.0, gi_h)
    gi_a = gi_b = np.zeros_like(zeta)
    g_a = g_b = np.ones_like(zeta)
    for k in range(2000):
        gi_a, g_a = eq.neck_filter_update.py_func(*phi, gi_a, g_a)
        gi_b, g_b = eq.neck_filter_update_increment.py_func(*d, gi_b, g_b)
        if k == 0:  # one step: a few ulp
            assert (np.abs(g_b - g_a) <= 4 * EPS * (1.0 + np.abs(phi[1]) * omega)).all()
    g_ref, _ = _response(np.full_like(zeta, 2000e-3), zeta, omega)
    # each other to 1e-12 of the initial velocity, and the closed form
    np.testing.assert_allclose(g_b, g_a, rtol=0, atol=1e-12)
    np.testing.assert_allclose(gi_b * omega, gi_a * omega, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g_b, g_ref, rtol=0, atol=1e-11)


def test_float32_forms_are_plain_arithmetic() -> None:
    """The convention of mudforce.model.equations: ``.py_func`` on whole arrays = the compiled function per element."""
    rng = np.random.default_rng(11)
    a, b, c, d, e, f = rng.uniform(0.1, 2.0, (6, 16))
    cases = [
        (eq.maxwell_strain_increment, (a, b, c, d)),
        (eq.neck_filter_closed_form, (a, b, c, d)),
        (eq.neck_filter_response_increment, (a - 1.0, b - 1.0, c, d)),
        (eq.neck_filter_transition_increment, (a, b, c - 1.0, d)),
        (eq.neck_filter_update_increment, (a, b, c, d, e, f)),
    ]
    for fn, args in cases:
        whole = np.asarray(fn.py_func(*args))
        each = np.array([fn(*(float(x[i]) for x in args)) for i in range(16)]).T
        np.testing.assert_array_equal(whole, each, err_msg=fn.__name__)
