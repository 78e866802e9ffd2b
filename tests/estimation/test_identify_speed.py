"""identify's compiled inner loops against their numpy statements, bit for bit (speed plumbing; docs/speed.md).

The re-profiled misfit statistic (:func:`_bias_reprofiled`) and the rest band through a force lag
(:func:`_band_through_lag`) each replaced a dozen numpy passes that an identify runs thousands of times; these
tests hold them to those passes, as written before, on random inputs and on a model run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mudforce import _kernel as K
from mudforce.estimation.calibration._recording_model import (
    _MISFIT_CLIP,
    _band_residual,
    _band_through_lag,
    _bias_reprofiled,
    _force_and_band,
)
from mudforce.model.equations import array_form, rest_band_forces
from mudforce.model.foot import Foot
from mudforce.model.law3d import spring_stress
from mudforce.model.parameters import MudParameters
from mudforce.steppers.simulation import run_compact


def _bias_reprofiled_numpy(model: np.ndarray, low: np.ndarray, high: np.ndarray, measured: np.ndarray,
                           rest: np.ndarray, variance: np.ndarray, free: np.ndarray) -> float:
    """The rule as numpy statements (identify before the compiled loop)."""
    def residual(d: float) -> tuple[np.ndarray, float, float]:
        m = measured + d
        r = _band_residual(model, low, high, m, rest)
        z2 = r**2 / variance
        return r, float(np.mean(np.where(free, z2, np.minimum(z2, _MISFIT_CLIP)))), float(
            np.mean(np.minimum(z2, _MISFIT_CLIP)))

    d = 0.0
    r, cost, stat = residual(d)
    for _ in range(30):
        active = ((r**2 < _MISFIT_CLIP * variance) | free) & (r != 0.0)
        if not np.any(active):
            break
        step = float(np.sum(r[active] / variance[active]) / np.sum(1.0 / variance[active]))
        while abs(step) > 1e-9:
            r_new, cost_new, stat_new = residual(d + step)
            if cost_new <= cost:
                break
            step *= 0.5
        if abs(step) <= 1e-9:
            break
        d, r, cost, stat = d + step, r_new, cost_new, stat_new
    return stat


def _band_numpy(time: np.ndarray, depth: np.ndarray, force: np.ndarray, state: np.ndarray, mud: np.ndarray,
                spring: np.ndarray, k_m_i: float, k_m_w: float, area: float, lag: float
                ) -> tuple[np.ndarray, ...]:
    """The band and the lag as numpy statements (identify before the compiled loop)."""
    def lowpass(x: np.ndarray) -> np.ndarray:
        y = np.empty_like(x)
        y[0] = x[0]
        for k in range(x.size - 1):
            h = time[k + 1] - time[k]
            e, c = math.exp(-h / lag), -math.expm1(-h / lag) * lag / h
            y[k + 1] = e * y[k] + (1.0 - c) * x[k + 1] - (e - c) * x[k]
        return y

    up, down = array_form(rest_band_forces)(depth - mud, spring, k_m_i, k_m_w, area)
    down = np.where(depth > 0.0, down, 0.0)
    up = np.where(state == int(K.ContactMode.NECKED), force, up)  # after necking: the post-necking force
    contact = state > 0
    low = np.where(contact, np.minimum(np.minimum(up, down), force), force)
    high = np.where(contact, np.maximum(np.maximum(up, down), force), force)
    if lag > 0.0:
        return lowpass(force), lowpass(low), lowpass(high)
    return force, low, high


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.array_equal(np.asarray(a).view(np.int64), np.asarray(b).view(np.int64)))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 700), st.floats(-3.0, 3.0))
def test_the_reprofiled_statistic_is_the_numpy_rules_bits(seed: int, n: int, shift: float) -> None:
    rng = np.random.default_rng(seed)
    model = rng.standard_normal(n) * 20.0 * (rng.random(n) < 0.7)
    low = model - rng.random(n) * 5.0
    high = model + rng.random(n) * 5.0
    measured = model + shift + rng.standard_normal(n) * 10.0 ** rng.uniform(-1.0, 1.5, n)
    rest = rng.random(n) < 0.2
    variance = 10.0 ** rng.uniform(-2.0, 2.0, n)
    free = (model == 0.0) & (rng.random(n) < 0.8)
    got = _bias_reprofiled(model, low, high, measured, rest, variance, free)[0]
    want = _bias_reprofiled_numpy(model, low, high, measured, rest, variance, free)
    assert np.float64(got).view(np.int64) == np.float64(want).view(np.int64)


@pytest.mark.parametrize("lag", [0.0, 0.004, 0.03])
def test_the_band_through_a_lag_is_the_numpy_rules_bits_on_a_model_run(lag: float) -> None:
    t = np.arange(0.0, 3.0, 0.01)
    depth = 0.03 * np.sin(2.0 * np.pi * 0.7 * t) + 0.004 * np.sin(2.0 * np.pi * 3.1 * t)
    foot = Foot.paper()
    q = MudParameters.from_water_content(0.27)
    row = K.make_params(q.as_array(), foot.area, foot.width, 1, 0.0)[None, :]
    bad, force, state, mud, _ = run_compact(t, depth, row, 1)
    assert bad < 0
    spring = spring_stress(depth, q.alpha, q.beta, foot.width)
    want = _band_numpy(t, depth, force, state, mud, spring, q.k_m_i, q.k_m_w, foot.area, lag)
    got = _band_through_lag(t, depth, force, state, mud, spring, q.k_m_i, q.k_m_w, foot.area, lag)
    assert all(_same_bits(g, w) for g, w in zip(got, want, strict=True))
    assert np.any(state > 0) and np.any(got[2] > got[1])  # the band is not the force alone somewhere
    assert all(_same_bits(g, w) for g, w in zip(_force_and_band(t, depth, q, foot, lag), got, strict=True))


def test_after_necking_the_band_s_withdrawal_edge_is_the_post_necking_force() -> None:
    """As the engines' rest_band has it (NECKED: (neck force, intrusion edge)): a foot pulled out until its neck
    broke, then held 40 mm above the surface, carries the post-necking force there (Eq. (7): -11 N, swinging to
    +3.5 N as it decays), and the band is that force and the intrusion edge, 0 above the surface. Its low edge was
    the Maxwell element's withdrawal force at the strain (down to -106 N here), suction the mud cannot give; on a
    robot's swing its refined difference made the misfit floor hundreds of newtons (docs/estimation.md)."""
    t = np.arange(0.0, 2.0, 0.01)
    depth = np.interp(t, [0.0, 0.3, 0.5, 0.8, 2.0], [-0.005, 0.02, 0.02, -0.04, -0.04])
    foot = Foot.paper()
    q = MudParameters.from_water_content(0.25)
    force, low, high = _force_and_band(t, depth, q, foot, 0.0)
    row = K.make_params(q.as_array(), foot.area, foot.width, 1, 0.0)[None, :]
    state = run_compact(t, depth, row, 1)[2]
    necked = (state == int(K.ContactMode.NECKED)) & (depth < 0.0)
    assert np.count_nonzero(necked) > 100 and force[necked].min() < -9.0  # the suction, then its decay's swing
    assert np.array_equal(low[necked], np.minimum(force[necked], 0.0))
    assert np.array_equal(high[necked], np.maximum(force[necked], 0.0))
