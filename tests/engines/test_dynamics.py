"""Coupled dynamics: sticking, the built-in engine against the exact drop, no chatter."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mudforce import Foot, MudParameters
from mudforce import _kernel as K
from mudforce._kernel import params_row
from mudforce.engines.dynamics import (
    GRAVITY,
    ExactDrop,
    Phase,
    branch_forces,
    exact_drop,
    naive_drop,
    rest_band,
    simulate_foot,
)
from mudforce.errors import InputError
from mudforce.model.velocity import VelocityFilter

CASES = [(w, m) for w in (0.15, 0.20, 0.25) for m in (5.0, 10.0, 15.0, 20.0)]


@pytest.fixture(scope="module")
def exact() -> dict[tuple[float, float], ExactDrop]:
    return {(w, m): exact_drop(m, MudParameters.from_water_content(w)) for w, m in CASES}


@pytest.mark.parametrize(("water", "mass"), CASES)
def test_builtin_drop_rests_at_the_exact_depth(water: float, mass: float,
                                               exact: dict[tuple[float, float], ExactDrop]) -> None:
    params = MudParameters.from_water_content(water)
    res = simulate_foot(mass, params)
    ref = exact[(water, mass)]
    # the requirement is 2%; the event-driven RK4 engine is far closer
    assert abs(res.end_depth / ref.end_depth - 1.0) < 1e-4  # (W = 25%, 15-20 kg: still creeping at 8 s)
    # no chatter: the force over the last second is the weight
    assert res.force_std(1.0) <= 0.02 * mass * GRAVITY
    assert abs(np.mean(res.force[res.time >= 7.0]) - mass * GRAVITY) < 1e-3 * mass * GRAVITY
    # the whole trajectory follows the exact solution, not only its end
    np.testing.assert_allclose(res.depth, ref.depth, atol=2e-6 + 1e-4 * abs(ref.end_depth))


@pytest.mark.parametrize(("water", "mass"), [(0.15, 5.0), (0.25, 15.0), (0.25, 20.0)])
def test_no_chatter_and_no_ratchet(water: float, mass: float) -> None:
    res = simulate_foot(mass, MudParameters.from_water_content(water))
    late = res.time >= res.time[-1] - 3.0
    # after settling the foot never moves up: no branch chatter...
    assert np.all(res.velocity[late] >= 0.0)
    names = set(np.array(res.phase_names)[late])
    assert names <= {"STUCK", "INTRUSION"}
    # ...and while stuck it does not move at all
    stuck = res.phase == Phase.STUCK
    assert np.all(res.velocity[stuck] == 0.0)
    runs = np.split(res.depth[stuck], np.flatnonzero(np.diff(np.flatnonzero(stuck)) > 1) + 1)
    assert all(np.ptp(r) == 0.0 for r in runs if r.size)


def test_naive_coupling_chatters_and_ratchets() -> None:
    """docs/model.md: the explicit coupling chatters every step and sinks far deeper."""
    params = MudParameters.from_water_content(0.25)
    t, z, f = naive_drop(5.0, params)
    ref = exact_drop(5.0, params)
    last = t > t[-1] - 1.0
    flips = np.count_nonzero(np.diff(np.sign(np.diff(z[last]))))
    assert flips > 500
    assert z[-1] > 1.5 * ref.rest_depth
    assert np.std(f[last]) > 0.5 * 5.0 * GRAVITY


def test_exact_drop_phases() -> None:
    """W = 15%: sinks, stops with F_up <= m g <= F_down, and stays; W = 25%, 20 kg: rebounds and necks."""
    params = MudParameters.from_water_content(0.15)
    ref = exact_drop(10.0, params)
    assert [e[1] for e in ref.events] == ["FREE", "INTRUSION", "STUCK"]
    _, _, z, _, e = ref.events[-1]
    foot = Foot.paper()
    f_down = foot.area * (params.k_m_i * e + params.alpha * (z / foot.width) ** params.beta)
    f_up = foot.area * params.k_m_w * e
    assert f_up <= 10.0 * GRAVITY <= f_down
    # the spring alone then carries the load: stuck for good (e* <= 0)
    assert foot.area * params.alpha * (z / foot.width) ** params.beta >= 10.0 * GRAVITY
    assert ref.final_depth == z
    heavy = exact_drop(20.0, MudParameters.from_water_content(0.25))
    names = [e[1] for e in heavy.events]
    assert names[:4] == ["FREE", "INTRUSION", "WITHDRAWAL", "NECKED"]
    assert "STUCK" in names


def test_sticking_ends_when_the_intrusion_force_falls_to_the_load() -> None:
    """While stuck, e relaxes with tau_i; the foot sinks again at e* = (m g / S - alpha (z/H)^beta) / k_i."""
    params = MudParameters.from_water_content(0.25)
    ref = exact_drop(15.0, params)
    foot = Foot.paper()
    stuck = [i for i, e in enumerate(ref.events) if e[1] == "STUCK"]
    assert len(stuck) >= 3  # creep: stick, slip, stick, ...
    i = stuck[0]
    t_s, _, z, _, e_s = ref.events[i]
    t_r, name, z_r, _, e_r = ref.events[i + 1]
    assert name == "INTRUSION" and z_r == z
    tau_i = params.b_m_i / params.k_m_i
    e_star = (15.0 * GRAVITY / foot.area - params.alpha * (z / foot.width) ** params.beta) / params.k_m_i
    assert math.isclose(e_r, e_star, rel_tol=1e-12)
    assert math.isclose(t_r - t_s, tau_i * math.log(e_s / e_star), rel_tol=1e-9)
    res = simulate_foot(15.0, params)
    k = np.searchsorted(res.time, 0.5 * (t_s + t_r))
    assert res.phase_names[k] == "STUCK" and res.force[k] == 15.0 * GRAVITY


def test_band_is_a_trial_step_on_a_copy() -> None:
    """branch_forces(weight=1) at rest equals trial kernel steps holding the depth (up to a 1 nm nudge for F_up)."""
    params = MudParameters.from_water_content(0.20)
    prow = params_row(params, Foot.paper(), VelocityFilter.exact())[None, :]
    states = K.new_states(1)
    ring = K.new_ring(1, 1)
    out = K.new_out(1)
    dt = 1e-3
    for z in np.r_[np.linspace(0.0, 0.02, 41), np.full(5, 0.02)]:
        K.step(states, ring, 0, prow, float(z), dt, out, 0)
    f_up, f_down, drag = np.zeros(1), np.zeros(1), np.zeros(1)
    branch_forces(states, prow, dt, 1.0, f_up, f_down, drag)
    trial = states.copy()
    hold = K.step(trial, ring, 0, prow, 0.02, dt, out, 0)
    assert math.isclose(f_down[0], hold, rel_tol=1e-12)
    trial = states.copy()
    up = K.step(trial, ring, 0, prow, 0.02 - 1e-9, dt, out, 0)
    assert abs(f_up[0] - up) < 1e-3 * abs(up)
    assert drag[0] == 0.0
    lo, hi = rest_band(prow[0], K.ContactMode.CONTACT, 0.02, 1e-4, 0.0)
    assert lo == pytest.approx(Foot.paper().area * params.k_m_w * 1e-4)
    assert hi > lo
    assert rest_band(prow[0], K.ContactMode.FREE, 0.02, 1e-4, 0.0) == (0.0, 0.0)


def test_applied_force_pulls_the_foot_out() -> None:
    params = MudParameters.from_water_content(0.25)
    profile = (np.array([0.0, 2.0, 2.01]), np.array([0.0, 0.0, -150.0]))  # [s], [N] (negative: upward)
    res = simulate_foot(5.0, params, duration=4.0, applied_force=profile)
    names = res.phase_names
    k = names.index("WITHDRAWAL", int(1.0 / 1e-3))
    assert 2.0 < res.time[k] < 2.01
    assert "NECKED" in names[k:]
    assert res.depth[-1] < 0.0  # out of the mud
    # an upward pull inside the band keeps it stuck
    held = simulate_foot(5.0, params, duration=4.0, applied_force=(np.array([2.0, 2.01]), np.array([0.0, -20.0])))
    assert held.phase_names[-1] == "STUCK"
    assert held.rest_depth == pytest.approx(exact_drop(5.0, params).rest_depth, rel=1e-6)


def test_substeps_converge() -> None:
    params = MudParameters.from_water_content(0.20)
    a = simulate_foot(10.0, params, duration=1.0, substeps=5, height=0.02)
    b = simulate_foot(10.0, params, duration=1.0, substeps=40, height=0.02)
    np.testing.assert_allclose(a.depth, b.depth, atol=1e-6)  # 5e-5 of the depth (touchdown: z^beta)
    ref = exact_drop(10.0, params, duration=1.0, height=0.02)
    np.testing.assert_allclose(b.depth, ref.depth, atol=1e-7)


def test_bad_input() -> None:
    params = MudParameters.from_water_content(0.20)
    with pytest.raises(InputError, match="mass"):
        simulate_foot(0.0, params)
    with pytest.raises(InputError, match="duration"):
        simulate_foot(1.0, params, duration=-1.0)
    with pytest.raises(InputError, match="applied_force"):
        simulate_foot(1.0, params, applied_force=(np.array([1.0, 0.0]), np.array([0.0, 0.0])))
    with pytest.raises(InputError, match="MudParameters"):
        simulate_foot(1.0, "mud")  # type: ignore[arg-type]


def test_stiffer_withdrawal_branch_can_pump_energy() -> None:
    """docs/model.md keeps k_m_w >> k_m_i: at each reversal the stored strain meets an 11.5x stiffer
    spring (W = 30%), so a light foot bounces higher each time; both solvers agree on it."""
    params = MudParameters.from_water_content(0.30)
    res = simulate_foot(2.0, params, duration=1.0)
    ref = exact_drop(2.0, params, duration=1.0)
    np.testing.assert_allclose(res.depth, ref.depth, atol=1e-6)
    flights = np.split(-res.depth, np.flatnonzero(np.diff((res.depth < 0).astype(int))) + 1)
    heights = [f.max() for f in flights if f.max() > 0.0]
    assert len(heights) >= 2 and heights[1] > 3.0 * heights[0] > 0.1


def test_necked_force_is_summed_as_the_stepper() -> None:
    """The engine's NECKED force below the surface is the stepper's sample force, bit for bit (one sum order)."""
    from mudforce._kernel import transitions as T
    from mudforce.engines.dynamics.engine import A_TN, A_VM0, A_ZN, N_AUX, _mud_force
    from mudforce.model.equations import neck_filter_response

    mud = MudParameters.from_water_content(0.20)
    row = params_row(mud, Foot.paper(), VelocityFilter.exact())
    q = K.params_of(row)
    aux = np.zeros(N_AUX)
    aux[A_TN], aux[A_VM0], aux[A_ZN] = 0.1, -0.0213, 0.0047
    age = 0.0137
    g, gi = neck_filter_response(age, q.zeta, q.omega_0)
    old_order_differs = False
    for z, v in ((0.011, -0.31), (0.023, -0.77), (0.0031, -1.9), (0.017, -0.05)):
        got = _mud_force(int(Phase.NECKED), 0.1 + age, z, v, 0.0, row, aux, 0.0)
        s = K.State(1.0, int(K.ContactMode.NECKED), 0.0, z, 0.0, age, aux[A_VM0], aux[A_ZN], -1.0, v, g, gi, 0.0)
        ref, fe1, _, fs, _ = T.sample_outputs.py_func(q, s, v)
        assert got == ref
        old_order_differs |= q.area * fe1 + q.area * fs != ref  # the engine's own sum before it shared the stepper's
    assert old_order_differs  # so the test tells the two orders apart


def test_the_engines_interpolation_is_numpys_to_the_bit() -> None:
    from mudforce.engines.dynamics.engine import _interp

    rng = np.random.default_rng(3)
    for n in (2, 3, 7, 40):
        xp = np.cumsum(rng.uniform(1e-3, 2.0, n)) - 1.0
        fp = rng.normal(0.0, 50.0, n)
        fp[n // 2] = fp[n // 2 - 1]  # a flat piece
        xs = [*xp, xp[0] - 1.0, xp[-1] + 1.0, math.nan, *rng.uniform(xp[0] - 0.5, xp[-1] + 0.5, 200),
              *(np.nextafter(xp, np.inf)), *(np.nextafter(xp, -np.inf))]
        for x in xs:
            want, got = float(np.interp(x, xp, fp)), _interp(float(x), xp, fp)
            assert got == want or (math.isnan(got) and math.isnan(want)), (n, x, got, want)
