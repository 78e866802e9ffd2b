"""The rest band as physics (equations.rest_band_forces), its state machine (rest_band) and branch_forces."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mudforce import Foot, MudParameters
from mudforce import _kernel as K
from mudforce._kernel import ContactMode, params_row
from mudforce.engines.dynamics import branch_forces, rest_band
from mudforce.model.equations import maxwell_strain_step, nonlinear_spring_stress, rest_band_forces
from mudforce.model.velocity import VelocityFilter

W20 = MudParameters.from_water_content(0.20)
FOOT = Foot.paper()
ROW = params_row(W20, FOOT, VelocityFilter.exact())


def test_rest_band_forces_are_the_two_branch_limits() -> None:
    """Eqs. (2), (4) at v = 0: F_up = S k_m_w e, F_down = S (k_m_i e + f_e2); checked against the paper's formulas."""
    e, z = 2e-4, 0.015
    spring = W20.alpha * (z / FOOT.width) ** W20.beta
    f_up, f_down = rest_band_forces(e, spring, W20.k_m_i, W20.k_m_w, FOOT.area)
    assert f_up == pytest.approx(FOOT.area * W20.k_m_w * e, rel=1e-15)
    assert f_down == pytest.approx(FOOT.area * (W20.k_m_i * e + spring), rel=1e-15)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.tuples(st.floats(-1e-2, 1e-2), st.floats(0.0, 1e5)), min_size=1, max_size=20))
def test_rest_band_forces_py_func_works_on_arrays(rows: list[tuple[float, float]]) -> None:
    """Plain arithmetic: the Python function on arrays equals the compiled one on each element, bit for bit."""
    e = np.array([r[0] for r in rows])
    spring = np.array([r[1] for r in rows])
    up, down = rest_band_forces.py_func(e, spring, W20.k_m_i, W20.k_m_w, FOOT.area)
    for i in range(e.size):
        assert (up[i], down[i]) == rest_band_forces(e[i], spring[i], W20.k_m_i, W20.k_m_w, FOOT.area)


def test_rest_band_applies_the_state_machine() -> None:
    e = 1e-4
    z = 0.02
    spring = nonlinear_spring_stress(W20.alpha, W20.beta, z, FOOT.width)
    both = rest_band_forces(e, spring, W20.k_m_i, W20.k_m_w, FOOT.area)
    assert rest_band(ROW, ContactMode.CONTACT, z, e, 0.0) == both
    assert rest_band(ROW, ContactMode.FREE, z, e, 0.0) == (0.0, 0.0)
    # above the surface the intrusion branch is FREE: no downward limit
    lo, hi = rest_band(ROW, ContactMode.CONTACT, -1e-3, e, 0.0)
    assert hi == 0.0 and lo == FOOT.area * W20.k_m_w * e
    # after necking the upward limit is the post-necking force (Eq. (7)), given
    lo, hi = rest_band(ROW, ContactMode.NECKED, z, e, -3.5)
    assert lo == -3.5 and hi == both[1]


def test_rest_band_spread_is_the_band_moved_by_the_depth_error() -> None:
    """A depth ``sd`` off moves the strain by ``sd`` (the mud's z_m holds) and the spring with the depth: each end
    of the band moves by the difference of rest_band at the two depths (F_up exactly, F_down as a central secant)."""
    from mudforce.engines.dynamics.rest_band import rest_band_spread

    e, z, sd = 1e-4, 0.02, 1e-3
    d_up, d_down = rest_band_spread(ROW, ContactMode.CONTACT, z, sd)
    lo_a, hi_a = rest_band(ROW, ContactMode.CONTACT, z + sd, e + sd, 0.0)
    lo_b, hi_b = rest_band(ROW, ContactMode.CONTACT, z - sd, e - sd, 0.0)
    assert d_up == pytest.approx(0.5 * (lo_a - lo_b), rel=1e-12) and d_up == pytest.approx(
        FOOT.area * W20.k_m_w * sd, rel=1e-15)
    assert d_down == pytest.approx(0.5 * (hi_a - hi_b), rel=1e-12)
    # the spring's part is a secant: finite at the surface, where Eq. (4)'s slope is not (beta < 1)
    _, at_surface = rest_band_spread(ROW, ContactMode.CONTACT, 0.0, sd)
    spring = nonlinear_spring_stress(W20.alpha, W20.beta, sd, FOOT.width)
    assert at_surface == pytest.approx(FOOT.area * (W20.k_m_i * sd + 0.5 * spring), rel=1e-14)
    # the state machine: nothing when FREE or for no error; F_down's none above the surface, F_up's none after necking
    assert rest_band_spread(ROW, ContactMode.FREE, z, sd) == (0.0, 0.0)
    assert rest_band_spread(ROW, ContactMode.CONTACT, z, 0.0) == (0.0, 0.0)
    assert rest_band_spread(ROW, ContactMode.CONTACT, -2e-3, sd) == (d_up, 0.0)
    assert rest_band_spread(ROW, ContactMode.NECKED, z, sd) == (0.0, d_down)


def _moving_state(velocity: float) -> tuple[np.ndarray, np.ndarray]:
    """A foot stepped down to 20 mm and then at ``velocity`` [m/s] for a few 1 ms steps (CONTACT)."""
    prow = ROW[None, :]
    states = K.new_states(1)
    ring = K.new_ring(1, 1)
    out = K.new_out(1)
    z = 0.0
    for z in np.linspace(0.0, 0.02, 21):
        K.step(states, ring, 0, prow, float(z), 1e-3, out, 0)
    for _ in range(3):
        z += velocity * 1e-3
        K.step(states, ring, 0, prow, float(z), 1e-3, out, 0)
    return states, prow


@pytest.mark.parametrize("velocity", [0.05, -0.02, 0.0])
def test_branch_forces_advance_eq3_with_maxwell_strain_step(velocity: float) -> None:
    """The predicted-end band is rest_band after Eq. (3)'s closed-form step, on each bound's own branch."""
    states, prow = _moving_state(velocity)
    s = K.state_of(states[0])
    assert s.mode == ContactMode.CONTACT
    dt = 1e-3
    f_up, f_down, drag = np.zeros(1), np.zeros(1), np.zeros(1)
    branch_forces(states, prow, dt, 1.0, f_up, f_down, drag)
    v = s.velocity
    z = s.depth
    e0 = z - s.mud
    v_dn, v_up = max(v, 0.0), min(v, 0.0)
    e_dn = maxwell_strain_step(e0, v_dn, W20.b_m_i / W20.k_m_i, math.exp(-dt * W20.k_m_i / W20.b_m_i))
    e_up = maxwell_strain_step(e0, v_up, W20.b_m_w / W20.k_m_w, math.exp(-dt * W20.k_m_w / W20.b_m_w))
    assert f_down[0] == pytest.approx(rest_band(ROW, ContactMode.CONTACT, z + v_dn * dt, e_dn, 0.0)[1], rel=1e-12)
    assert f_up[0] == pytest.approx(rest_band(ROW, ContactMode.CONTACT, z + v_up * dt, e_up, 0.0)[0], rel=1e-12)


def test_branch_forces_cached_decays_equal_computed_ones() -> None:
    """The decays the stepper cached for a step of dt are the ones branch_forces would compute: same bits."""
    states, prow = _moving_state(0.05)
    assert K.load_cache(states, 0).dt == 1e-3
    cached = [np.zeros(1) for _ in range(3)]
    branch_forces(states, prow, 1e-3, 1.0, *cached)
    fresh = states.copy()
    K.forget_cache(fresh)  # no cache: exp(-dt / tau) computed in place
    computed = [np.zeros(1) for _ in range(3)]
    branch_forces(fresh, prow, 1e-3, 1.0, *computed)
    for a, b in zip(cached, computed, strict=True):
        assert a[0] == b[0]


def test_branch_forces_refuses_outputs_or_rows_shorter_than_the_states() -> None:
    """The compiled loop reads and writes without bounds checks: outputs of 2 rows for 4 states were written past
    their end (memory corruption, silently). Each short array is now one InputError, nothing written."""
    from mudforce.errors import InputError

    states = K.new_states(4)
    row = K.make_params(MudParameters.from_water_content(0.25).as_array(), 0.002, 0.05, 1, 0.0)
    params = np.tile(row, (4, 1))
    good = [np.full(4, 7.0) for _ in range(3)]
    branch_forces(states, params, 1e-3, 1.0, *good)
    assert all(np.array_equal(g, np.zeros(4)) for g in good)  # no foot started: no band
    narrow_states, narrow_params = np.ascontiguousarray(states[:, :5]), np.ascontiguousarray(params[:, :3])
    for bad in ((states, params[:2], *good), (states, params, np.zeros(2), good[1], good[2]),
                (states, params, good[0], good[1], np.zeros(3)), (narrow_states, params, *good),
                (states, narrow_params, *good)):  # (contiguous: the compiled code the other tests use, no new compile)
        with pytest.raises(InputError, match="at least as many rows"):
            branch_forces(bad[0], bad[1], 1e-3, 1.0, *bad[2:])
