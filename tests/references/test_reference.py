"""Batch, streaming and the independent reference solution agree (docs/model.md's "Discretisation").

:func:`mudforce.references.trajectory.reference_simulate` integrates the model's ODEs
with ``solve_ivp`` and locates surface crossings and necking as integrator
events; it shares no code with the compiled stepper. The compiled paths
(:func:`mudforce.simulate` with the exact branch rule, and
:class:`mudforce.MudContact` fed the same samples) must match it to 1e-6 of
the peak force, sample by sample, with the same contact states and the same
necking instants.
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import mudforce as mf
from mudforce.model.foot import Foot
from mudforce.model.parameters import TABLE_I_WATER_CONTENTS, MudParameters
from mudforce.references.trajectory import CONTACT, FREE, NECKED, ReferenceResult, reference_simulate

FORCE_RTOL = 1e-6  # of the peak |force| (seen: ~1e-11; docs/model.md)
NECK_ATOL = 1e-6  # [s]
CODES = {"FREE": FREE, "CONTACT": CONTACT, "NECKED": NECKED}


def _stream(
    time: np.ndarray, depth: np.ndarray, params: MudParameters, foot: Foot | None
) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """Feed the samples one by one to MudContact with dt = np.diff(time)."""
    contact = mf.MudContact(params, foot)
    dts = np.diff(time)
    force = np.empty(time.size)
    state = np.empty(time.size, dtype=np.int8)
    necked_steps: list[int] = []
    for k in range(time.size):
        force[k] = contact.step(depth[k], dts[k - 1] if k else 1.0)  # first call: dt ignored
        last = contact.last
        state[k] = CODES[last.state]
        if last.necked:
            necked_steps.append(k)
    return force, state, necked_steps


def _agree(
    time: np.ndarray, depth: np.ndarray, params: MudParameters, foot: Foot | None = None
) -> tuple[ReferenceResult, mf.SimulationResult, float]:
    """Assert batch, streaming and reference agree; return the reference, batch and max relative error."""
    ref = reference_simulate(time, depth, params, foot)
    batch = mf.simulate(time, depth, params, foot, velocity_filter="exact")
    s_force, s_state, s_necked = _stream(time, depth, params, foot)
    peak = float(np.max(np.abs(ref.force)))
    assert peak > 0.0
    tol = FORCE_RTOL * peak
    assert_allclose(batch.force, ref.force, rtol=0, atol=tol, err_msg="batch vs reference force")
    assert_allclose(s_force, ref.force, rtol=0, atol=tol, err_msg="streaming vs reference force")
    assert_array_equal(batch.state, ref.state, err_msg="batch vs reference state")
    assert_array_equal(s_state, ref.state, err_msg="streaming vs reference state")
    # z_m to 1e-6 of the largest depth excursion, too
    scale = float(np.max(np.abs(depth)))
    assert_allclose(batch.mud_displacement, ref.mud_displacement, rtol=0, atol=1e-6 * scale)
    # necking instants, located inside the step
    assert batch.necking_times.shape == ref.necking_times.shape
    assert_allclose(batch.necking_times, ref.necking_times, rtol=0, atol=NECK_ATOL)
    assert len(s_necked) == ref.necking_times.size
    for k, t_n in zip(s_necked, ref.necking_times, strict=True):
        assert time[k - 1] - NECK_ATOL <= t_n <= time[k] + NECK_ATOL
    err = float(np.max(np.abs(batch.force - ref.force))) / peak
    return ref, batch, err


# ----------------------------------------------------------------------------- (a) the paper's protocol
VELOCITIES = (0.005, 0.01, 0.02, 0.04)  # [m/s]


@pytest.mark.parametrize("velocity", VELOCITIES)
@pytest.mark.parametrize("water", TABLE_I_WATER_CONTENTS)
def test_paper_protocol_agrees_with_reference(water: float, velocity: float) -> None:
    params = MudParameters.table_i(water)
    # 20 mm deep, 6 s hold, out to 20 mm above the surface, 100 Hz (docs/model.md's protocol)
    time, depth = mf.Protocol.paper(depth=0.02, velocity=velocity, hold=6.0).sample()
    ref, _, _ = _agree(time, depth, params)
    # Here the criterion v > sigma_y / b_m_w of docs/model.md decides whether the neck breaks
    # (40 mm of withdrawal is several tau_w at these speeds); W = 15 % at 10 mm/s does not neck.
    expect_neck = velocity > params.critical_withdrawal_velocity
    assert (ref.necking_times.size == 1) == expect_neck
    assert ref.necking_times.size <= 1
    if water == 0.15 and velocity == 0.01:
        assert ref.necking_times.size == 0
        assert ref.state[-1] == CONTACT  # the mud keeps clinging above the surface
    if expect_neck:
        # the force at the necking instant is the yield suction (no drag jump here)
        assert_allclose(ref.necking_forces, -params.sigma_y * Foot.paper().area, rtol=1e-9)


def test_paper_protocol_cases_include_both_outcomes() -> None:
    necks = {
        (w, v): v > MudParameters.table_i(w).critical_withdrawal_velocity
        for w in TABLE_I_WATER_CONTENTS
        for v in VELOCITIES
    }
    assert any(necks.values()) and not all(necks.values())
    assert not necks[(0.15, 0.01)]  # docs/model.md: W = 15 % at 10 mm/s never reaches sigma_y


def test_sanity_numbers_w25() -> None:
    """docs/model.md's sanity check: W = 25 %, 20 mm, 10 mm/s, cuboid foot."""
    params = MudParameters.table_i(0.25)
    protocol = mf.Protocol.paper()
    time, depth = protocol.sample()
    ref, batch, _ = _agree(time, depth, params)
    area = Foot.paper().area
    yield_force = -params.sigma_y * area
    assert round(yield_force, 2) == -11.63  # -6 kPa * 51 mm * 38 mm
    # peak ~59.5 N at the end of intrusion (t = 2 s, sample 200)
    assert int(np.argmax(batch.force)) == 200
    assert abs(batch.force[200] - 59.5) < 0.05
    # ~54.8 N at the end of the 6 s hold (t = 8 s), almost all of it f_e2
    assert abs(batch.force[800] - 54.8) < 0.05
    assert batch.f_e2[800] > 0.95 * batch.force[800]
    # suction minimum -sigma_y S at the necking instant (the reference evaluates it there)
    assert ref.necking_times.size == 1
    assert_allclose(ref.necking_forces[0], yield_force, rtol=1e-9)
    # the sampled minimum is the sample just before necking: not beyond yield, and within 1 %
    assert batch.min_force >= yield_force * (1 + 1e-9)
    assert batch.min_force <= 0.99 * yield_force
    k_n = int(np.searchsorted(time, ref.necking_times[0]))
    assert int(np.argmin(batch.force)) == k_n - 1
    # after necking the force decays towards zero
    assert abs(batch.force[-1]) < 0.05 * abs(yield_force)


# ----------------------------------------------------------------------------- (b) every transition
MM = 1e-3


def _hand_trajectory(rate: float = 100.0, jitter: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A piecewise-linear motion [s], [m] that crosses every transition of docs/model.md's state machine.

    Corners are off the sample grid, so crossings and necking fall inside steps.
    """
    points = [(0.0, -4.73 * MM)]

    def move(z_mm: float, speed_mm_s: float) -> None:
        t0, z0 = points[-1]
        points.append((t0 + abs(z_mm * MM - z0) / (speed_mm_s * MM), z_mm * MM))

    def hold(duration: float) -> None:
        t0, z0 = points[-1]
        points.append((t0 + duration, z0))

    move(15.0, 10.0)  # FREE -> CONTACT: first touchdown from above, inside a step
    move(12.0, 3.0)  # partial withdrawal, too slow to neck
    move(20.0, 10.0)  # re-push (withdrawal -> intrusion branch in CONTACT)
    hold(1.0)
    move(8.0, 40.0)  # fast withdrawal: CONTACT -> NECKED below the surface
    move(14.0, 10.0)  # push down while necked below the surface: NECKED -> CONTACT
    hold(0.5)
    move(-6.0, 40.0)  # withdraw, neck again, lift off above the surface
    hold(0.5)  # NECKED at rest above the surface
    move(10.0, 10.0)  # NECKED -> FREE (above the surface), second touchdown FREE -> CONTACT
    hold(0.3)
    move(-3.17, 2.5)  # slow withdrawal: the mud clings above the surface (CONTACT, z_i < 0)
    hold(0.3)  # CONTACT -> FREE: a step on the intrusion branch ending above the surface
    move(3.0, 10.0)  # third touchdown
    bt = np.array([p[0] for p in points])
    bz = np.array([p[1] for p in points])
    time = np.arange(math.ceil(bt[-1] * rate) + 1) / rate
    if jitter:
        rng = np.random.default_rng(20240302)
        time[1:-1] += rng.uniform(-jitter, jitter, time.size - 2) / rate
    return time, np.interp(time, bt, bz)


def _transitions(state: np.ndarray) -> set[tuple[int, int]]:
    return {(int(a), int(b)) for a, b in itertools.pairwise(state) if a != b}


ALL_TRANSITIONS = {(FREE, CONTACT), (CONTACT, NECKED), (NECKED, CONTACT), (NECKED, FREE), (CONTACT, FREE)}


@pytest.mark.parametrize("water", [0.20, 0.25])
def test_hand_trajectory_agrees_with_reference(water: float) -> None:
    time, depth = _hand_trajectory()
    ref, _, _ = _agree(time, depth, MudParameters.table_i(water))
    assert _transitions(ref.state) == ALL_TRANSITIONS
    assert ref.necking_times.size == 2
    # touchdowns happen inside a step, from above the surface
    down = np.flatnonzero((ref.state[1:] == CONTACT) & (ref.state[:-1] == FREE)) + 1
    assert down.size == 3
    assert np.all(depth[down - 1] < 0.0) and np.all(depth[down] > 0.0)
    # lift-off: suction or decay while the foot is above the surface
    above = depth <= 0.0
    assert np.any(above & (ref.state == NECKED) & (ref.force < 0.0))
    assert np.any(above & (ref.state == CONTACT) & (ref.force < 0.0))


@pytest.mark.parametrize(
    ("lambda_", "foot"),
    [(2000.0, None), (5000.0, Foot.disc(0.05))],
)
def test_hand_trajectory_strong_drag_jittered_time(lambda_: float, foot: Foot | None) -> None:
    """Irregular sampling, a disc foot, and a drag large enough to matter for necking.

    With lambda this large the drag's jump at a velocity change can put the
    stress past the yield at the very start of a step (a neck with a force
    beyond ``-sigma_y S``), and the drag's switch-off at the surface matters.
    """
    params = dataclasses.replace(MudParameters.table_i(0.25), lambda_=lambda_)
    time, depth = _hand_trajectory(jitter=0.3)
    ref, _, _ = _agree(time, depth, params, foot)
    assert _transitions(ref.state) == ALL_TRANSITIONS
    area = (foot or Foot.paper()).area
    assert np.all(ref.necking_forces <= -params.sigma_y * area * (1 - 1e-9))
    assert np.any(ref.necking_forces < -params.sigma_y * area * 1.05)  # a neck at a drag jump


def test_reference_starts_below_the_surface_relaxed() -> None:
    """docs/model.md: a trajectory starting below the surface starts in CONTACT with z_m = z_i.

    Withdrawing at constant speed from relaxed mud also has a closed form
    (written out here, independent of both implementations): the strain
    is ``e(t) = -v tau_w (1 - exp(-t / tau_w))``, the neck breaks when
    ``k_w e - lambda rho v^2 = -sigma_y``, and afterwards the force is
    ``(b_w v_m0 g(t - t_n) + f_s) S`` with the underdamped ``g`` of Eq. (7).
    """
    params = MudParameters.table_i(0.30)  # zeta = 0.36 < 1
    area = Foot.paper().area
    speed = 0.008  # [m/s] upwards
    time = np.arange(301) / 100.0
    depth = 0.01 - speed * time  # 10 mm deep, withdrawing; above the surface after 1.25 s
    ref, batch, _ = _agree(time, depth, params)
    assert ref.state[0] == CONTACT
    assert ref.mud_displacement[0] == depth[0]
    f_e2 = params.alpha * (depth[0] / Foot.paper().width) ** params.beta
    assert_allclose(ref.force[0], f_e2 * area, rtol=1e-14)  # Eq. (4) alone: no strain, no velocity yet

    tau_w = params.b_m_w / params.k_m_w
    drag = params.lambda_ * params.rho_m * speed**2
    t_n = -tau_w * math.log(1.0 - (params.sigma_y - drag) / (params.b_m_w * speed))
    assert ref.necking_times.size == 1
    assert_allclose(ref.necking_times[0], t_n, rtol=0, atol=1e-9)
    e = -speed * tau_w * (1.0 - np.exp(-time / tau_w))
    before = time < t_n
    assert_allclose(ref.force[1:][before[1:]], ((params.k_m_w * e - drag) * area)[1:][before[1:]], rtol=1e-9)
    v_m0 = -speed * (1.0 - math.exp(-t_n / tau_w))  # dz_m/dt = e(t_n) / tau_w, Eq. (3)
    age = time[~before] - t_n
    a = params.zeta * params.omega_0
    wd = params.omega_0 * math.sqrt(1.0 - params.zeta**2)
    g = np.exp(-a * age) * (np.cos(wd * age) - a * np.sin(wd * age) / wd)
    f_s = np.where(depth[~before] > 0.0, -drag, 0.0)
    expected = (params.b_m_w * v_m0 * g + f_s) * area
    assert_allclose(ref.force[~before], expected, rtol=0, atol=1e-9 * np.max(np.abs(expected)))
    assert_allclose(batch.force[~before], expected, rtol=0, atol=1e-9 * np.max(np.abs(expected)))
    assert np.all(ref.state[~before] == NECKED)


def test_reference_closed_form_intrusion() -> None:
    """Constant-speed intrusion from the surface: ``e(t) = v tau_i (1 - exp(-t / tau_i))``, Eqs. (1)-(5)."""
    params = MudParameters.table_i(0.15)
    foot = Foot.disc(0.04)
    speed = 0.02
    time = np.arange(101) / 100.0
    depth = speed * time
    ref, _, _ = _agree(time, depth, params, foot)
    tau_i = params.b_m_i / params.k_m_i
    e = speed * tau_i * (1.0 - np.exp(-time / tau_i))
    stress = params.k_m_i * e + params.alpha * (depth / foot.width) ** params.beta
    stress[1:] += params.lambda_ * params.rho_m * speed**2
    assert_allclose(ref.force, stress * foot.area, rtol=1e-10)
    assert np.all(ref.state[1:] == CONTACT) and ref.state[0] == FREE


def test_reference_refuses_a_mud_or_foot_of_another_type_in_one_line() -> None:
    """Both were read for their fields: AttributeError ('str' object has no attribute 'k_m_i' / 'area')."""
    t, z = np.array([0.0, 0.01]), np.array([0.0, 0.001])
    mud = MudParameters.from_water_content(0.25)
    for params, foot, match in (("w25", None, "params must be a MudParameters, got str"),
                                (mud, "paper", "foot must be a Foot")):
        with pytest.raises(mf.InputError, match=match):
            reference_simulate(t, z, params, foot)  # type: ignore[arg-type]


@pytest.mark.parametrize(("time", "depth", "match"), [
    # each was solved (a depth of 100.5 m: 4.8e6 N), where simulate refuses it: the model's bounds, in its words
    ([0.0, 0.01, 0.02], [0.0, 0.01, 100.5], r"^depth at sample 2 \(100.5 m\) is beyond \+-100 m; expected depths"),
    ([2e9, 2e9 + 0.01], [0.0, 0.01], r"^time at sample 0 \(2000000000.0 s\) is beyond \+-1e\+09 s$"),
    ([0.0, 1e-12], [0.0, 0.001],
     r"^the time step before sample 1 \(t = 1e-12 s\) is 1e-12 s; expected steps within \[1e-09, 1000\]"),
    ([0.0, 2000.0], [0.0, 0.01], r"^the time step before sample 1 \(t = 2000.0 s\) is 2000.0 s; expected steps within"),
    ([0.0, 0.01], [0.0, math.nan], r"^depth is not finite at sample 1 \(nan\); expected numbers \[m\]$"),
    ([0.0, 0.0], [0.0, 0.01], r"^time repeats at sample 1"),
    ([0.0, 0.01], [0.0], r"^time and depth must be non-empty 1-D arrays of the same length, got shapes \(2,\) and "
                         r"\(1,\)$"),
])
def test_reference_refuses_what_simulate_refuses_in_its_words(time: list[float], depth: list[float],
                                                             match: str) -> None:
    with pytest.raises(mf.InputError, match=match):
        reference_simulate(time, depth, MudParameters.from_water_content(0.25))
