"""Each function of :mod:`mudforce.model.equations` against an independent evaluation.

The references here never call the function under test's formula: they
integrate the defining ODE numerically (``scipy.integrate.solve_ivp``), find
roots with ``scipy.optimize.brentq``, or evaluate the inverse Laplace
transform by residues in 50-digit arithmetic (``mpmath``). Equation numbers
are those of Chen, Yi & Shan (2024), arXiv:2403.02617; conventions are
``docs/model.md``'s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from mudforce.model.equations import (
    drag_stress,
    maxwell_strain_step,
    neck_filter_response,
    necking_time,
    nonlinear_spring_stress,
    viscoelastic_stress,
)
from mudforce.model.parameters import MudParameters

W25 = MudParameters.table_i(0.25)  # Table I, W = 25 %, in SI
H = 0.038  # the paper's intruder width [m] (docs/model.md)


# --------------------------------------------------------------------- Eq. (2)
def test_viscoelastic_stress_is_k_times_strain() -> None:
    # Eq. (2): f_e1 = k_m (z_i - z_m); reference is the product itself
    for k, e in [(W25.k_m_i, 1e-3), (W25.k_m_w, -2.5e-3), (1.0, 0.0)]:
        assert_allclose(viscoelastic_stress(k, e), k * e, rtol=1e-15)


# --------------------------------------------------------------------- Eq. (3)
def _strain_ode(e0: float, v: float, tau: float, h: float) -> float:
    """Reference: de/dt = v - e / tau integrated numerically (Eq. (3) with e = z_i - z_m)."""
    sol = solve_ivp(lambda t, y: [v - y[0] / tau], (0.0, h), [e0], method="DOP853", rtol=1e-13, atol=1e-18)
    assert sol.success
    return float(sol.y[0, -1])


@pytest.mark.parametrize("tau", [W25.b_m_i / W25.k_m_i, W25.b_m_w / W25.k_m_w, 0.05])
@pytest.mark.parametrize("e0", [0.0, 1.3e-3, -4.2e-3])
@pytest.mark.parametrize("v", [0.0, 0.01, -0.04])
def test_maxwell_strain_step_matches_ode(tau: float, e0: float, v: float) -> None:
    for h in (1e-5, 0.01, 0.37, 5.0 * tau):
        got = maxwell_strain_step(e0, v, tau, math.exp(-h / tau))
        # solve_ivp of de/dt = v - e/tau from e(0) = e0 over h (first-order-hold input)
        assert_allclose(got, _strain_ode(e0, v, tau, h), rtol=1e-10, atol=1e-16)


def test_maxwell_strain_step_limits() -> None:
    tau = 0.4
    # zero step (decay = 1): unchanged strain
    assert_allclose(maxwell_strain_step(2e-3, -0.01, tau, 1.0), 2e-3, rtol=1e-15)
    # infinite step (decay = 0): the steady strain v * tau, steady stress b * v
    assert_allclose(maxwell_strain_step(2e-3, -0.01, tau, 0.0), -0.01 * tau, rtol=1e-15)


# --------------------------------------------------------------------- Eq. (4)
def test_nonlinear_spring_stress_closed_form() -> None:
    for alpha, beta in [(W25.alpha, W25.beta), (0.17e6, 0.56), (1.0e4, 1.0)]:
        depths = np.array([1e-9, 1e-4, 0.005, 0.02, 0.05])
        got = np.array([nonlinear_spring_stress(alpha, beta, d, H) for d in depths])
        # Eq. (4): alpha * (z_i / H)^beta, via numpy's power
        assert_allclose(got, alpha * np.power(depths / H, beta), rtol=1e-14)
        # docs/model.md: zero at and above the surface
        for d in (0.0, -1e-12, -0.01):
            assert nonlinear_spring_stress(alpha, beta, d, H) == 0.0
    # at z_i = H the stress is alpha whatever beta (Eq. (4))
    assert_allclose(nonlinear_spring_stress(W25.alpha, W25.beta, H, H), W25.alpha, rtol=1e-15)


# --------------------------------------------------------------------- Eq. (5)
def test_drag_stress_sign_and_magnitude() -> None:
    lam, rho = W25.lambda_, W25.rho_m  # 0.013, 1840 kg/m^3 (Table I's common values)
    for v in (1e-4, 0.01, 0.04, 1.0):
        down = drag_stress(lam, rho, v)
        up = drag_stress(lam, rho, -v)
        # Eq. (5): |f_s| = lambda rho v^2; resisting the motion: up (+) when moving down, down (-) moving up
        assert_allclose(down, lam * rho * v * v, rtol=1e-15)
        assert_allclose(up, -lam * rho * v * v, rtol=1e-15)
        assert down > 0.0 > up
    assert drag_stress(lam, rho, 0.0) == 0.0  # sign(0) = +1 times 0
    # hand value: 0.013 * 1840 * 0.01^2 = 2.392e-3 Pa
    assert_allclose(drag_stress(0.013, 1840.0, 0.01), 2.392e-3, rtol=1e-12)


# --------------------------------------------------------------------- Eq. (7)
ZETAS = [0.2, 0.999999, 1.0, 1.000001, 3.0, 50.0]


def _impulse_mp(age: float, zeta: float, omega: float) -> tuple[float, float]:
    """Inverse Laplace transform of s/(s^2 + 2 zeta w s + w^2) (g) and of 1/(...) (G), by residues.

    50-digit arithmetic, so the nearly repeated roots at zeta = 1 +- 1e-6 lose nothing.
    """
    mpmath = pytest.importorskip("mpmath")
    with mpmath.workdps(50):
        t = mpmath.mpf(age)
        w = mpmath.mpf(omega)
        z = mpmath.mpf(zeta)
        if zeta == 1.0:
            # double root -w: s/(s+w)^2 = 1/(s+w) - w/(s+w)^2; 1/(s+w)^2 -> t e^{-wt}
            e = mpmath.exp(-w * t)
            return float(e * (1 - w * t)), float(t * e)
        root = mpmath.sqrt(mpmath.mpc(z * z - 1))
        r1 = w * (-z + root)
        r2 = w * (-z - root)
        e1, e2 = mpmath.exp(r1 * t), mpmath.exp(r2 * t)
        g = (r1 * e1 - r2 * e2) / (r1 - r2)
        big_g = (e1 - e2) / (r1 - r2)
        return float(mpmath.re(g)), float(mpmath.re(big_g))


def _impulse_ode(ages: np.ndarray, zeta: float, omega: float) -> tuple[np.ndarray, np.ndarray]:
    """The mass-spring-damper z'' + 2 zeta w z' + w^2 z = 0, z(0) = 0, z'(0) = 1, integrated numerically.

    Its velocity z' is g (impulse response of G_m(s) = s/(...)), its displacement z is G.
    """
    sol = solve_ivp(
        lambda t, y: [y[1], -2.0 * zeta * omega * y[1] - omega * omega * y[0]],
        (0.0, float(ages[-1])),
        [0.0, 1.0],
        method="DOP853",
        t_eval=ages,
        rtol=1e-13,
        atol=1e-16,
    )
    assert sol.success
    return sol.y[1], sol.y[0]


@pytest.mark.parametrize("zeta", ZETAS)
@pytest.mark.parametrize("omega", [2.23, 4.09])  # omega_0 of Table I, W = 25 % and 15 %
def test_neck_filter_response_matches_ode(zeta: float, omega: float) -> None:
    ages = np.concatenate([[0.0, 1e-9, 1e-6, 1e-3], np.linspace(0.01, 12.0, 60)])
    got = np.array([neck_filter_response(a, zeta, omega) for a in ages])
    g_ref, big_g_ref = _impulse_ode(ages, zeta, omega)
    # references: solve_ivp of the mass-spring-damper (velocity = g, displacement = G)
    assert_allclose(got[:, 0], g_ref, rtol=1e-9, atol=1e-11)
    assert_allclose(got[:, 1], big_g_ref, rtol=1e-9, atol=1e-11 / omega)


@pytest.mark.parametrize("zeta", ZETAS)
def test_neck_filter_response_matches_residues(zeta: float) -> None:
    omega = 2.23
    ages = [0.0, 1e-12, 1e-7, 1e-6 / omega, 3e-6, 0.05, 0.4, 1.0, 3.3, 10.0, 47.0, 200.0, 1e3, 1e4]
    if zeta > 1.0:
        # the overdamped form switches at mu * age = 30 (equations.py): both sides of it
        mu = omega * math.sqrt(zeta * zeta - 1.0)
        ages += [30.0 / mu * (1 - 1e-9), 30.0 / mu * (1 + 1e-9)]
    for a in ages:
        g, big_g = neck_filter_response(a, zeta, omega)
        g_ref, big_g_ref = _impulse_mp(a, zeta, omega)  # residues in 50-digit arithmetic
        assert_allclose(g, g_ref, rtol=1e-8, atol=1e-13, err_msg=f"g at age {a}, zeta {zeta}")
        assert_allclose(big_g, big_g_ref, rtol=1e-8, atol=1e-13 / omega, err_msg=f"G at age {a}, zeta {zeta}")


@pytest.mark.parametrize("zeta", ZETAS)
def test_neck_filter_response_initial_values_and_decay(zeta: float) -> None:
    omega = 2.23
    # docs/model.md: g(0) = 1 (the mud starts at v_m0), G(0) = 0 (displacement since necking)
    g0, big_g0 = neck_filter_response(0.0, zeta, omega)
    assert g0 == 1.0
    assert big_g0 == 0.0
    # large ages: finite (no overflow of cosh/sinh or exp), and decayed to nothing
    for a in (1e4, 1e6, 1e9, 1e15, 1e300):
        g, big_g = neck_filter_response(a, zeta, omega)
        assert math.isfinite(g) and math.isfinite(big_g), (a, g, big_g)
        if a >= 1e6:
            assert abs(g) < 1e-300 and abs(big_g) < 1e-300, (a, g, big_g)
    # G -> 0: the final value of 1/(s^2 + 2 zeta w s + w^2) times s is 0
    assert abs(neck_filter_response(1e4, zeta, omega)[1]) < 1e-12


def test_neck_filter_response_is_continuous_across_critical_damping() -> None:
    omega = 2.23
    for a in (1e-4, 0.1, 0.5, 1.0, 2.0, 5.0, 20.0):
        crit = np.array(neck_filter_response(a, 1.0, omega))
        for zeta in (1.0 - 1e-6, 1.0 + 1e-6, 1.0 - 1e-12, 1.0 + 1e-12):
            near = np.array(neck_filter_response(a, zeta, omega))
            # |dg/dzeta| is O(1) here, so a 1e-6 change in zeta moves g by ~1e-6 at most
            assert_allclose(near, crit, rtol=0, atol=3e-6 * max(1.0, omega * a) * abs(zeta - 1.0) / 1e-6)


# --------------------------------------------------------------------- Eq. (9)
def _necking_root(e0: float, v: float, tau: float, k: float, drag: float, sigma_y: float, length: float) -> float:
    """Reference necking time: brentq root of k e(t) + f_s + sigma_y, e(t) from solve_ivp, or -1."""
    sol = solve_ivp(
        lambda t, y: [v - y[0] / tau],
        (0.0, length),
        [e0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-18,
        dense_output=True,
    )

    def margin(t: float) -> float:
        return k * float(sol.sol(t)[0]) + drag + sigma_y

    if margin(0.0) < 0.0:
        return 0.0
    if margin(length) >= 0.0:
        return -1.0
    return float(brentq(margin, 0.0, length, xtol=1e-15, rtol=1e-15))


NECK_CASES = [
    # strain [m], velocity [m/s], drag [Pa], length [s]      (W = 25 % withdrawal branch)
    (-4.0e-3, -0.01, -0.0024, 0.01),  # root beyond this short step -> -1
    (-4.0e-3, -0.01, -0.0024, 2.0),  # root inside a long interval
    (-4.9e-3, -0.01, -0.0024, 0.01),  # root inside one 100 Hz step
    (2.0e-3, -0.04, -0.038, 1.0),  # starts compressive (after a hold), necks later
    (-4.0e-3, -0.04, -1500.0, 0.2),  # the drag brings it nearer
    (-5.0e-3, -0.01, -0.0024, 0.01),  # already past the yield stress: 0
    (-4.0e-3, -0.002, -0.0001, 5.0),  # slow: relaxes towards v tau, never necks -> -1
    (-6.0e-3, -0.004, -0.0, 0.5),  # past yield at the start (zero drag): 0
]


@pytest.mark.parametrize(("e0", "v", "drag", "length"), NECK_CASES)
def test_necking_time_matches_brentq(e0: float, v: float, drag: float, length: float) -> None:
    k, sigma_y = W25.k_m_w, W25.sigma_y
    tau = W25.b_m_w / W25.k_m_w
    got = necking_time(e0, v, tau, k, drag, sigma_y, length, math.exp(-length / tau))
    ref = _necking_root(e0, v, tau, k, drag, sigma_y, length)
    if ref < 0.0:
        assert got == -1.0
    else:
        assert 0.0 <= got <= length
        assert_allclose(got, ref, rtol=1e-9, atol=1e-13)


def test_necking_time_cases_cover_all_outcomes() -> None:
    tau = W25.b_m_w / W25.k_m_w
    outcomes = {np.sign(_necking_root(e0, v, tau, W25.k_m_w, d, W25.sigma_y, n)) for e0, v, d, n in NECK_CASES}
    assert outcomes == {-1.0, 0.0, 1.0}  # no neck, neck at the start, neck inside


# --------------------------------------------------------------------- the shared pieces (every path calls them)
def test_shared_pieces_run_on_arrays_as_compiled() -> None:
    """array_form(f) on arrays = the compiled f per element, bit for bit, also when f calls others of the module."""
    from mudforce.model import equations as eq

    rng = np.random.default_rng(3)
    a, b, c, d, e, f = rng.uniform(0.1, 2.0, (6, 8))
    cases = [
        (eq.neck_filter_sine_series, (a, b * 1e-6)),
        (eq.neck_filter_sinh_series, (a, b * 1e-6)),
        (eq.neck_filter_slow_mode, (a, b, c + 2.0)),
        (eq.necking_fraction, (-a * 1e-3, -b, c, -d * 2e-3)),
        (eq.rest_band_blend, (a / 2.0, b, c)),
        (eq.rest_band_depth_spread, (a * 1e-3, b * 1e4, c * 1e4, d * 1e5, e * 1e6, f * 1e-3)),
        (eq.piece_midpoint_depth, (a - 1.0, -b, c * 1e-3)),
        (eq.post_necking_force, (a, b, c, d, e, f)),  # calls necked_mud_motion and necked_stress
    ]
    for fn, args in cases:
        whole = np.asarray(eq.array_form(fn)(*args))
        each = np.array([fn(*(float(x[i]) for x in args)) for i in range(8)]).T
        np.testing.assert_array_equal(whole, each, err_msg=fn.__name__)


def test_post_necking_force_is_the_damper_and_continuous_at_necking() -> None:
    """Eq. (7): S b_m_w v_m0 g and z_n + v_m0 G; at necking (g = 1, G = 0) the withdrawal force S k_m_w e."""
    from mudforce.model.equations import necking_velocity, post_necking_force

    area, e, z_n = 0.051 * 0.038, -3e-3, 0.012
    tau_w = W25.b_m_w / W25.k_m_w
    v_m0 = necking_velocity(e, tau_w)
    force, mud = post_necking_force(area, W25.b_m_w, v_m0, z_n, 1.0, 0.0)
    assert force == pytest.approx(area * W25.k_m_w * e, rel=1e-14) and mud == z_n
    g, big_g = neck_filter_response(0.02, W25.zeta, W25.omega_0)
    force, mud = post_necking_force(area, W25.b_m_w, v_m0, z_n, g, big_g)
    assert force == pytest.approx(area * W25.b_m_w * v_m0 * g, rel=1e-15)
    assert mud == pytest.approx(z_n + v_m0 * big_g, rel=1e-15)


def test_rest_band_blend_weights_the_step_ends() -> None:
    from mudforce.model.equations import rest_band_blend

    assert rest_band_blend(0.0, 3.0, 7.0) == 3.0 and rest_band_blend(1.0, 3.0, 7.0) == 7.0
    assert rest_band_blend(0.25, 3.0, 7.0) == 4.0


@pytest.mark.parametrize(("e0", "v", "drag"),
                         [(-4.0e-3, -0.01, -0.0024), (2.0e-3, -0.04, -0.038), (-4.9e-3, -0.01, -0.0024)])
def test_necking_fraction_puts_the_strain_on_the_yield_surface(e0: float, v: float, drag: float) -> None:
    """Eq. (3)'s closed form at t* = -tau_w log1p(fraction) is the yield strain of Eq. (9)."""
    from mudforce.model.equations import necking_fraction, yield_strain

    tau = W25.b_m_w / W25.k_m_w
    target = yield_strain(W25.k_m_w, W25.sigma_y, drag)
    t_star = -tau * math.log1p(necking_fraction(e0, v, tau, target))
    assert t_star > 0.0
    assert maxwell_strain_step(e0, v, tau, math.exp(-t_star / tau)) == pytest.approx(target, rel=1e-12)


def test_neck_filter_thresholds_join_its_forms() -> None:
    """Eq. (7)'s response on both sides of its named thresholds: the series and the slow mode are its limits."""
    from mudforce.model.equations import (
        NECK_FILTER_SERIES_BELOW,
        NECK_FILTER_SLOW_MODE_FROM,
        neck_filter_sine_series,
        neck_filter_sinh_series,
        neck_filter_slow_mode,
    )

    x = NECK_FILTER_SERIES_BELOW
    assert neck_filter_sine_series(2.0, x) == pytest.approx(2.0 * math.sin(x) / x, rel=1e-15)
    assert neck_filter_sinh_series(2.0, x) == pytest.approx(2.0 * math.sinh(x) / x, rel=1e-15)
    zeta, omega = 3.0, 10.0
    mu = omega * math.sqrt(zeta * zeta - 1.0)
    a = zeta * omega
    for y in (0.5 * NECK_FILTER_SLOW_MODE_FROM, 0.9 * NECK_FILTER_SLOW_MODE_FROM):  # both modes, by cosh and sinh
        t = y / mu
        full = (math.exp(-a * t) * (math.cosh(y) - a * math.sinh(y) / mu), math.exp(-a * t) * math.sinh(y) / mu)
        slow = neck_filter_slow_mode(0.5 * math.exp((mu - a) * t), a, mu)
        assert_allclose(slow, full, rtol=1e-9 if y < 20.0 else 1e-12)
    for y in (NECK_FILTER_SLOW_MODE_FROM * (1.0 - 1e-9), NECK_FILTER_SLOW_MODE_FROM * (1.0 + 1e-9)):
        assert_allclose(neck_filter_response(y / mu, zeta, omega),
                        neck_filter_slow_mode(0.5 * math.exp((mu - a) * y / mu), a, mu), rtol=1e-12)
