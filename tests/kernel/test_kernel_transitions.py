"""The named transitions of the state machine, each against a closed form, and advance() as their composition.

The transitions run as plain Python (numba's ``.py_func``), which also checks
that the physics layer's functions are callable outside compiled code.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import mudforce as mf
from mudforce import _kernel as K
from mudforce._kernel import layout, params_row
from mudforce._kernel import transitions as T
from mudforce.model import equations as eq

P = K.params_of(params_row(mf.MudParameters.from_water_content(0.25), mf.Foot.paper(), mf.VelocityFilter.exact()))
DT = 1e-3
NO_CACHE = K.Cache(-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
C = T.step_cache.py_func(NO_CACHE, P, DT)


def state(mode: int, depth: float, mud: float = 0.0, strain: float = 0.0, **kw: float) -> K.State:
    fields = dict(started=1.0, mode=mode, time=0.5, depth=depth, mud=mud, neck_age=0.0, neck_v=0.0, neck_z=0.0,
                  direction=0.0, velocity=0.0, neck_g=0.0, neck_gi=0.0, strain=strain)
    fields.update(kw)
    return K.State(**fields)  # type: ignore[arg-type]


def maxwell(e0: float, v: float, tau: float, h: float) -> float:
    """Eq. (3)'s closed form under a constant foot velocity."""
    return v * tau + (e0 - v * tau) * math.exp(-h / tau)


def test_touchdown_enters_contact_at_the_crossing() -> None:
    s, start = T.touchdown.py_func(state(layout.FREE, -0.002), 4.0)
    assert start == pytest.approx(0.0005) and (s.mode, s.mud, s.strain) == (layout.CONTACT, 0.0, 0.0)


def test_intrusion_step_is_the_maxwell_closed_form() -> None:
    s0 = state(layout.CONTACT, 0.01, mud=0.009, strain=0.001)
    s = T.intrusion_step.py_func(s0, C, P, 0.0101, 0.1, DT, 0.0)
    assert s.mode == layout.CONTACT and s.strain == pytest.approx(maxwell(0.001, 0.1, P.tau_i, DT), rel=1e-13)
    assert s.mud == 0.0101 - s.strain
    later = T.intrusion_step.py_func(s0, C, P, 0.0101, 0.1, DT, 0.4 * DT)  # CONTACT from 40 % into the step
    assert later.strain == pytest.approx(maxwell(0.001, 0.1, P.tau_i, 0.6 * DT), rel=1e-13)
    up = T.intrusion_step.py_func(state(layout.CONTACT, 0.0, strain=0.0), C, P, -1e-4, 0.0, DT, 0.0)
    assert (up.mode, up.mud) == (layout.FREE, -1e-4)  # ends above the surface on the intrusion branch


def test_withdrawal_step_necks_where_the_suction_reaches_the_yield_stress() -> None:
    v, z0 = -0.05, 0.02
    z1 = z0 + v * DT
    fs = eq.drag_stress(P.lam, P.rho_m, v)
    e_yield = (-P.sigma_y - fs) / P.k_w
    e0 = e_yield + 0.4 * DT * abs(v - e_yield / P.tau_w)  # reaches the yield surface 40 % into the step

    def suction(t: float) -> float:
        return P.k_w * maxwell(e0, v, P.tau_w, t) + fs + P.sigma_y

    assert suction(0.0) > 0.0 > suction(DT), "the case must neck inside the step"
    tn = brentq(suction, 0.0, DT, xtol=1e-16, rtol=1e-15)
    s, offset = T.withdrawal_step.py_func(state(layout.CONTACT, z0, strain=e0), C, P, z0, z1, v, DT, 0.0)
    assert s.mode == layout.NECKED and offset == pytest.approx(tn, rel=1e-9)
    assert P.k_w * s.strain + fs == pytest.approx(-P.sigma_y, rel=1e-14)
    assert s.neck_v == s.strain / P.tau_w and s.neck_age == pytest.approx(DT - tn, rel=1e-9)
    g, gi = eq.neck_filter_response(s.neck_age, P.zeta, P.omega_0)
    assert (s.neck_g, s.neck_gi) == (g, gi) and s.mud == s.neck_z + s.neck_v * gi
    held, none = T.withdrawal_step.py_func(state(layout.CONTACT, z0, strain=-1e-5), C, P, z0, z1, v, DT, 0.0)
    assert held.mode == layout.CONTACT and math.isnan(none)
    assert held.strain == pytest.approx(maxwell(-1e-5, v, P.tau_w, DT), rel=1e-13)


def test_necked_step_follows_the_impulse_response() -> None:
    g0, gi0 = eq.neck_filter_response(2e-4, P.zeta, P.omega_0)
    s = state(layout.NECKED, 0.01, neck_age=2e-4, neck_v=-0.03, neck_z=0.012, neck_g=g0, neck_gi=gi0)
    for _ in range(200):
        s = T.necked_step.py_func(s, C, P, DT)
    g, gi = eq.neck_filter_response(s.neck_age, P.zeta, P.omega_0)
    assert s.neck_g == pytest.approx(g, rel=1e-9, abs=1e-15) and s.neck_gi == pytest.approx(gi, rel=1e-9, abs=1e-18)
    assert s.mud == pytest.approx(0.012 - 0.03 * gi, rel=1e-12)


def test_leave_necked_follows_the_table() -> None:
    below = T.leave_necked.py_func(state(layout.NECKED, 0.01, mud=0.013, strain=-0.002))
    assert (below.mode, below.mud, below.strain) == (layout.CONTACT, 0.013, 0.01 - 0.013)  # keeps z_m
    above = T.leave_necked.py_func(state(layout.NECKED, -0.001, mud=0.013, strain=-0.002))
    assert (above.mode, above.mud) == (layout.FREE, -0.001)


def composed(s: K.State, c: K.Cache, p: K.Params, z1: float, dt: float) -> tuple[K.State, float, float]:
    """The model's table step by step (exact velocity rule), from the named transitions alone."""
    v = (z1 - s.depth) / dt
    d = float(np.sign(v))
    c = T.step_cache.py_func(c, p, dt)
    if s.mode == layout.NECKED and d > 0.0:
        s = T.leave_necked.py_func(s)
    start, z_start, offset = 0.0, s.depth, math.nan
    if s.mode == layout.FREE and z1 > 0.0:
        s, start = T.touchdown.py_func(s, v)
        z_start = 0.0
    elif s.mode == layout.FREE:
        s = T.free_step.py_func(s, z1)
    if s.mode == layout.CONTACT and d >= 0.0:
        s = T.intrusion_step.py_func(s, c, p, z1, v, dt, start)
    elif s.mode == layout.CONTACT:
        s, offset = T.withdrawal_step.py_func(s, c, p, z_start, z1, v, dt, start)
    elif s.mode == layout.NECKED:
        s = T.necked_step.py_func(s, c, p, dt)
    return s._replace(time=s.time + dt, depth=z1, direction=d, velocity=v), offset, v


def test_advance_is_the_composition_of_the_transitions() -> None:
    """Through every row of the table (touchdown, both branches, necking, NECKED, leaving it), bit for bit."""
    t = np.arange(0.0, 1.2, 0.004)
    z = 0.012 * np.sin(2 * np.pi * 1.3 * t) + 0.002  # starts below the surface, crosses it both ways
    prow = params_row(mf.MudParameters.from_water_content(0.25), mf.Foot.paper(), mf.VelocityFilter.exact())[None]
    states, out = K.new_states(1), K.new_out(1)
    K.step(states, K.new_ring(1, 1), 0, prow, z[0], 0.0, out, 0)
    s, c, seen = K.state_of(states[0]), NO_CACHE, set()
    for k in range(1, t.size):
        dt = t[k] - t[k - 1]
        K.step(states, K.new_ring(1, 1), 0, prow, z[k], dt, out, 0)
        s, offset, v = composed(s, c, P, z[k], dt)
        c = T.step_cache.py_func(c, P, dt)
        assert s == K.state_of(states[0]), k
        o = K.outputs(out[:, 0])
        assert (offset == o.neck_offset) or (math.isnan(offset) and math.isnan(o.neck_offset))
        force, fe1, fe2, fs, mud_velocity = T.sample_outputs(P, s, v)
        assert (force, fe1, fe2, fs, mud_velocity) == (o.force, o.f_e1, o.f_e2, o.f_s, o.mud_velocity)
        seen.add(s.mode)
    assert seen == {layout.FREE, layout.CONTACT, layout.NECKED}


def test_plain_arithmetic_runs_on_arrays_with_the_compiled_bits() -> None:
    """The convention of mudforce.model.equations: ``.py_func`` on whole arrays = the compiled function per element."""
    rng = np.random.default_rng(7)
    a, b, c, d, e, f = rng.uniform(0.1, 2.0, (6, 16))
    cases = [
        (eq.maxwell_strain_step, (a, b, c, d)),
        (eq.intrusion_stress, (a, b, c)),
        (eq.withdrawal_stress, (a, b, c)),
        (eq.necked_stress, (a, b)),
        (eq.total_stress, (a, b, c)),
        (eq.necked_mud_motion, (a, b, c, d)),
        (eq.neck_filter_transition, (a, b, c, d)),
        (eq.neck_filter_update, (a, b, c, d, e, f)),
        (eq.yield_strain, (a, b, c)),
        (eq.necking_velocity, (a, b)),
        (eq.drag_stress, (a, b, c - 1.0)),
    ]
    for fn, args in cases:
        whole = np.asarray(fn.py_func(*args))
        each = np.array([fn(*(float(x[i]) for x in args)) for i in range(16)]).T
        np.testing.assert_array_equal(whole, each, err_msg=fn.__name__)
