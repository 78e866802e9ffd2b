"""Batch simulation, protocols, streaming API, noisy inputs, and the result object."""

from __future__ import annotations

import math
import pathlib
from typing import Any

import numpy as np
import pytest

import mudforce as mf
from mudforce import TABLE_I, Hold, InputError, Intrude, MudContact, Protocol, VelocityFilter, Withdraw, simulate

W25 = TABLE_I[0.25]


def test_paper_protocol_sampling() -> None:
    prot = Protocol.paper()
    time, depth = prot.sample()
    # 2 s down to 20 mm, 6 s hold, 4 s up to 20 mm above: 12 s at 100 Hz
    assert time.size == 1201
    np.testing.assert_array_equal(time, np.arange(1201) / 100.0)  # exactly k / rate
    assert depth[200] == pytest.approx(0.02) and depth[800] == pytest.approx(0.02)
    assert depth[-1] == pytest.approx(-0.02)
    assert prot.duration == pytest.approx(12.0)


def test_protocol_with_approach_and_custom_steps() -> None:
    prot = Protocol((Intrude(0.02, 0.01), Hold(1.0), Withdraw(0.01, 0.0)), rate=50.0, start_depth=-0.005)
    t, z = prot.sample()
    assert z[0] == -0.005 and t[1] == 1.0 / 50.0
    assert prot.duration == pytest.approx(0.015 / 0.02 + 1.0 + 0.01 / 0.01)
    with pytest.raises(InputError, match="must go deeper"):
        Protocol((Intrude(0.01, 0.01), Intrude(0.01, 0.005)))
    with pytest.raises(InputError, match="velocity must be finite and > 0"):
        Intrude(0.0, 0.02)
    with pytest.raises(InputError, match="sampling rate"):
        Protocol.paper(rate=0.0)


def test_model_md_sanity_values_at_25_percent() -> None:
    """docs/model.md: peak ~59.5 N, ~54.8 N at the end of the hold, suction minimum -sigma_y*S = -11.63 N."""
    res = Protocol.paper().simulate(W25)
    assert res.peak_force == pytest.approx(59.5, abs=0.05)
    assert int(np.argmax(res.force)) == 200  # end of intrusion, t = 2 s
    assert res.force[800] == pytest.approx(54.8, abs=0.05)
    assert res.f_e2[800] * res.foot.area == pytest.approx(54.8, abs=0.05)  # almost all of it f_e2
    assert res.necking_times.size == 1
    assert res.min_force >= -W25.sigma_y * res.foot.area - 1e-9
    assert res.min_force == pytest.approx(-11.63, abs=0.05)
    # after necking the suction decays to zero
    assert abs(res.force[-1]) < 0.05 * abs(res.min_force)
    assert res.state_names[0] == "FREE" and res.state_names[100] == "CONTACT" and res.state_names[-1] == "NECKED"


def test_no_necking_at_15_percent_and_10_mm_s() -> None:
    """docs/model.md: at W = 15 % the steady suction b_m_w v = 13.5 kPa stays below sigma_y = 17 kPa."""
    res = Protocol.paper().simulate(TABLE_I[0.15])
    assert res.necking_times.size == 0
    assert not np.any(res.state == 2)
    assert res.min_force > -TABLE_I[0.15].sigma_y * res.foot.area


def test_components_add_up_to_the_force() -> None:
    res = Protocol.paper(velocity=0.02).simulate(W25, mf.Foot.disc(0.04))
    np.testing.assert_allclose(res.force, (res.f_e1 + res.f_e2 + res.f_s) * res.foot.area, rtol=1e-12, atol=1e-12)
    # drag: lambda rho v^2 = 0.013 * 1840 * 0.02^2 = 9.568e-3 Pa while intruding (Eq. (5))
    assert res.f_s[50] == pytest.approx(0.013 * 1840 * 0.02**2, rel=1e-9)


def test_result_unpacks_and_exports(tmp_path: pathlib.Path) -> None:
    res = Protocol.paper().simulate(W25)
    t, f = res
    assert t is res.time and f is res.force
    path = tmp_path / "out.csv"
    res.to_csv(path)
    lines = path.read_text().splitlines()
    assert lines[0].split(",")[:2] == ["time_s", "depth_m"]
    assert {"force_N", "mud_displacement_m", "state"} <= set(lines[0].split(","))
    assert len(lines) == 1202
    df = res.to_pandas()
    assert list(df.columns) == lines[0].split(",")
    assert df["force_N"].iloc[200] == pytest.approx(res.force[200])
    # same inputs, same bytes
    path2 = tmp_path / "again.csv"
    Protocol.paper().simulate(W25).to_csv(path2)
    assert path.read_bytes() == path2.read_bytes()


def test_streaming_equals_batch_and_snapshot_restore() -> None:
    t, z = Protocol.paper().sample()
    res = simulate(t, z, W25)
    c = MudContact(W25)
    forces = [c.step(z[0], 123.0)]  # first dt is ignored
    snapshot = None
    for k in range(1, t.size):
        if k == 700:
            snapshot = c.state
        forces.append(c.step(z[k], t[k] - t[k - 1]))
    np.testing.assert_array_equal(forces, res.force)
    assert snapshot is not None and snapshot.mode == "CONTACT"
    c.state = snapshot  # roll back and replay: identical
    replay = [c.step(z[k], t[k] - t[k - 1]) for k in range(700, t.size)]
    np.testing.assert_array_equal(replay, res.force[700:])
    assert c.last.state == "NECKED"
    c.reset()
    assert not c.state.started
    assert c.step(0.01, 0.01) == pytest.approx(res.f_e2[100] * 0 + W25.alpha * (0.01 / 0.038) ** 0.54 * res.foot.area)


def test_last_before_the_first_step_and_after_a_reset_has_not_necked() -> None:
    """A new contact's ``last`` said ``necked=True`` (its outputs' zeros read as a neck offset of 0 s); it is the
    FREE, zero-force sample of a foot that has not necked, as a first step without necking reports."""
    c = MudContact(W25)
    assert c.last == mf.ContactSample(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, "FREE", False)
    c.step(-0.01, 0.01)
    assert c.last.necked is False
    c.step(0.005, 0.01)
    assert c.last.force > 0.0
    c.reset()  # `last` was the step before the reset: it is the fresh contact's again
    assert c.last == mf.ContactSample(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, "FREE", False)


@pytest.mark.parametrize(("bad", "named"), [(np.array(["exact"]), "ndarray"), (np.zeros((40, 40)), "ndarray"),
                                            (["exact"], "list"), (1, "int")])
def test_a_velocity_filter_that_is_not_a_name_or_a_filter_is_refused(bad: Any, named: str) -> None:
    """An array compared with "exact" elementwise: simulate raised numpy's ValueError (truth value of an array is
    ambiguous) for two elements, and np.array(["exact"]) was taken as the exact rule by every stepper."""
    t, z = np.arange(5) * 0.01, np.linspace(0.0, 0.01, 5)
    calls = [lambda: simulate(t, z, W25, velocity_filter=bad), lambda: MudContact(W25, velocity_filter=bad),
             lambda: mf.MudContacts(W25, 2, velocity_filter=bad)]
    for call in calls:
        with pytest.raises(InputError) as error:
            call()
        assert str(error.value) == f'velocity_filter must be "auto", "exact" or a VelocityFilter, got {named}'


def test_streaming_refuses_bad_steps() -> None:
    c = MudContact(W25)
    c.step(0.0, 0.0)
    with pytest.raises(InputError, match="dt must be within"):
        c.step(0.001, 0.0)
    with pytest.raises(InputError, match="depth must be finite"):
        c.step(float("nan"), 0.01)
    assert c.step(0.001, 0.01) > 0.0  # the refused calls changed nothing


@pytest.mark.parametrize(
    ("time", "depth", "message"),
    [
        ([0.0, 0.1, 0.1], [0, 0, 0], "time repeats at sample 2"),
        ([0.0, 0.2, 0.1], [0, 0, 0], "time goes backwards at sample 2"),
        ([0.0, 0.1], [0.0, float("nan")], "depth is not finite at sample 1"),
        ([float("nan"), 0.1], [0.0, 0.0], "time is not finite at sample 0"),
        ([-float("inf"), 0.1, 0.2], [0.0, 0.0, 0.0], "time is not finite at sample 0"),
        ([0.0, 0.1, float("inf")], [0.0, 0.0, 0.0], "time is not finite at sample 2"),
        ([float("inf")], [0.0], "time is not finite at sample 0"),
        ([0.0], [float("inf")], "depth is not finite at sample 0"),
        ([0.0, 0.1, 0.05, 0.2], [0.0, 0.0, float("nan"), 0.0], "depth is not finite at sample 2"),
        ([], [], "empty"),
        ([0.0, 0.1], [0.0], "same length"),
    ],
)
@pytest.mark.parametrize("velocity_filter", ["auto", "exact", VelocityFilter(3, 0.01)])
def test_simulate_refuses_bad_trajectories(
    time: list[float], depth: list[float], message: str, velocity_filter: str | VelocityFilter
) -> None:
    """The same message whether checked up front ("auto") or when the compiled loop refuses a sample."""
    with pytest.raises(InputError, match=message):
        simulate(time, depth, W25, velocity_filter=velocity_filter)


def test_starting_below_the_surface_is_relaxed_contact() -> None:
    res = simulate([0.0, 0.01], [0.01, 0.01], W25)
    assert res.state_names == ["CONTACT", "CONTACT"]
    expected = W25.alpha * (0.01 / 0.038) ** W25.beta * res.foot.area  # only f_e2, Eq. (4)
    assert res.force[0] == pytest.approx(expected, rel=1e-12)
    assert res.f_e1[0] == 0.0


# --- noisy measured trajectories (the branch choice must not chatter)


def _branch_switches(res: mf.SimulationResult) -> int:
    withdrawing = (res.state == 1) & (res.depth > 0) & (res.f_e2 == 0.0)
    return int(np.count_nonzero(np.diff(withdrawing.astype(int)) == 1))  # entries into withdrawal


def test_auto_filter_is_exact_on_clean_input() -> None:
    for w in TABLE_I:
        t, z = Protocol.paper(velocity=0.02).sample()
        auto = simulate(t, z, TABLE_I[w])
        assert auto.velocity_filter.is_exact
        np.testing.assert_array_equal(auto.force, simulate(t, z, TABLE_I[w], velocity_filter="exact").force)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_auto_filter_does_not_chatter_on_motion_capture_noise(seed: int) -> None:
    """0.05 mm RMS at 100 Hz: the raw difference has ~7 mm/s of noise, more than the 10 mm/s motion."""
    t, z = Protocol.paper().sample()
    clean = simulate(t, z, W25)
    noisy_z = z + np.random.default_rng(seed).normal(0.0, 5e-5, z.size)
    raw = simulate(t, noisy_z, W25, velocity_filter="exact")
    auto = simulate(t, noisy_z, W25)
    assert _branch_switches(raw) > 100  # the paper's raw sign chatters ...
    assert raw.necking_times.size > 1  # ... and breaks the neck again and again
    assert _branch_switches(auto) == 1  # one reversal, recognised once
    assert auto.necking_times.size == 1
    assert abs(auto.necking_times[0] - clean.necking_times[0]) < 0.05
    assert auto.velocity_filter.window == 10
    hold = (t > 2.2) & (t < 7.9)
    # during the hold the force follows the clean result to within the noise's effect (~0.1 N)
    assert np.max(np.abs(auto.force - clean.force)[hold]) < 0.6
    # the suction minimum is still -sigma_y * S
    assert auto.min_force == pytest.approx(clean.min_force, abs=0.5)


def test_estimate_depth_noise() -> None:
    t, z = Protocol.paper().sample()
    assert mf.estimate_depth_noise(t, z) < 1e-12
    noisy = z + np.random.default_rng(5).normal(0.0, 5e-5, z.size)
    assert mf.estimate_depth_noise(t, noisy) == pytest.approx(5e-5, rel=0.1)


def test_velocity_filter_for_noise_and_validation() -> None:
    vf = VelocityFilter.for_noise(5e-5, 0.01)
    assert vf.window == 10
    assert vf.deadband == pytest.approx(5 * math.sqrt(2) * 5e-5 / 0.1)
    assert VelocityFilter.for_noise(0.0, 0.01).is_exact
    with pytest.raises(InputError):
        VelocityFilter(0, 0.0)
    with pytest.raises(InputError):
        VelocityFilter(65, 0.0)
    with pytest.raises(InputError):
        VelocityFilter(3, -1.0)
    c = MudContact(W25, noise_std=5e-5, dt=0.01)
    assert c.velocity_filter == vf


@pytest.mark.parametrize(("kwargs", "words"), [
    # noise_std replaced the filter given, silently
    ({"noise_std": 5e-5, "dt": 0.01, "velocity_filter": VelocityFilter(3, 0.1)},
     "give velocity_filter or noise_std (with dt), not both"),
    ({"noise_std": 5e-5, "dt": 0.01, "velocity_filter": VelocityFilter.exact()},
     "give velocity_filter or noise_std (with dt)"),
    # dt without noise_std was ignored, even a negative one
    ({"dt": 0.01}, "dt is the nominal time step for noise_std; give noise_std too, or leave dt out"),
    ({"dt": -1.0, "velocity_filter": VelocityFilter(3, 0.1)}, "dt is the nominal time step for noise_std"),
])
def test_mud_contact_refuses_a_filter_argument_it_would_ignore(kwargs: dict[str, Any], words: str) -> None:
    with pytest.raises(InputError) as error:
        MudContact(W25, **kwargs)
    assert words in str(error.value) and "\n" not in str(error.value)


def test_rate_independence_of_the_exact_discretisation() -> None:
    """docs/model.md: the result depends on the sampling only through the input's interpolation."""
    r100 = Protocol.paper(rate=100.0).simulate(W25)
    r1k = Protocol.paper(rate=1000.0).simulate(W25)
    np.testing.assert_allclose(r1k.force[::10], r100.force, atol=1e-9 * r100.peak_force)
    np.testing.assert_allclose(r1k.necking_times, r100.necking_times, atol=1e-9)


def test_snapshot_restore_keeps_the_velocity_filter_history() -> None:
    """The smoothing filter's recent samples (kept outside the state row) are part of a snapshot."""
    vf = VelocityFilter(5, 0.002)
    t = np.arange(400) * 0.01
    z = 0.01 * np.sin(2.0 * t) + 0.004
    c = MudContact(W25, velocity_filter=vf)
    c.step(z[0], 0.0)
    for k in range(1, 200):
        c.step(z[k], t[k] - t[k - 1])
    snapshot = c.state
    assert snapshot.ring.size > 0
    first = [c.step(z[k], t[k] - t[k - 1]) for k in range(200, 400)]
    assert c.state != snapshot
    c.state = snapshot
    assert c.state == snapshot
    np.testing.assert_array_equal([c.step(z[k], t[k] - t[k - 1]) for k in range(200, 400)], first)
    np.testing.assert_array_equal(first, simulate(t, z, W25, velocity_filter=vf).force[200:])
    with pytest.raises(InputError, match="exact filter"):
        c.state = MudContact(W25).state


def test_stepper_refuses_a_window_without_a_ring() -> None:
    """A filter window > 1 needs a ring row; without one the step refuses rather than write out of bounds."""
    from mudforce import _kernel as K
    from mudforce._kernel import params_row

    prow = params_row(W25, mf.Foot.paper(), VelocityFilter(4, 0.0))[None, :]
    states = K.new_states(1)
    out = K.new_out(1)
    assert math.isnan(K.step(states, K.new_ring(1, 1), 0, prow, 0.01, 0.01, out, 0))
    assert K.state_of(states[0]).started == 0.0
    assert K.step(states, K.new_ring(1, 4), 0, prow, 0.01, 0.01, out, 0) == K.outputs(out).force[0] > 0.0


@pytest.mark.parametrize("window", [1, 6])
def test_full_output_loop_equals_simulate(window: int) -> None:
    """The full-output loop (calibration; simulate's other outputs) and simulate's own loop agree bit for bit."""
    from mudforce import _kernel as K
    from mudforce._kernel import params_row

    t, z = Protocol.paper().sample()
    z = z + 1e-5 * np.sin(37.0 * t)  # wiggles: reversals on the way in and out
    vf = VelocityFilter(window, 0.0) if window > 1 else VelocityFilter.exact()
    res = simulate(t, z, W25, velocity_filter=vf)
    out = K.new_out(t.size)
    assert K.run_batch(t, z, K.new_states(1), K.new_ring(1, window), params_row(W25, mf.Foot.paper(), vf)[None, :],
                       out) == -1
    rows = K.outputs(out)
    for row, name in (("force", "force"), ("f_e1", "f_e1"), ("f_e2", "f_e2"), ("f_s", "f_s"),
                      ("mud", "mud_displacement"), ("mud_velocity", "mud_velocity"), ("velocity", "velocity"),
                      ("state", "state")):
        np.testing.assert_array_equal(getattr(rows, row), getattr(res, name), err_msg=name)
    assert res.necking_times.size >= 1


@pytest.mark.parametrize("w", [0.15, 0.2, 0.25, 0.3, 0.35])
def test_constant_rate_fast_path_is_the_stepper(w: float) -> None:
    """simulate()'s loop for steps in which nothing happens gives the streaming stepper's numbers, bit for bit.

    A 1 kHz gait of several cycles (touchdown from above, intrusion, hold,
    withdrawal, necking, lift-off, clinging mud, touchdown again, with
    small reversals), with a stretch of jittered steps and one longer step
    in the middle, where the fast path must step aside.
    """
    params = mf.MudParameters.from_water_content(w)
    n = 6000
    t = np.arange(n) / 1000.0
    rng = np.random.default_rng(7)
    t[2500:2600] += rng.uniform(-2e-4, 2e-4, 100)  # jittered steps
    t[4000:] += 0.01  # one long step
    z = 0.03 * np.sin(2 * np.pi * 1.5 * t) - 0.005 + 2e-5 * np.sin(2 * np.pi * 40.0 * t)
    z[3000:3300] = z[3000]  # a hold
    res = simulate(t, z, params, velocity_filter="exact")
    assert {0, 1, 2} <= set(np.unique(res.state)) and res.necking_times.size >= 5
    c = MudContact(params)
    forces, states, mud = [], [], []
    for k in range(n):
        forces.append(c.step(z[k], t[k] - t[k - 1] if k else 0.0))
        last = c.last
        states.append(mf.STATE_NAMES.index(last.state))
        mud.append(last.mud_displacement)
    np.testing.assert_array_equal(forces, res.force)
    np.testing.assert_array_equal(states, res.state)
    np.testing.assert_array_equal(mud, res.mud_displacement)


def test_post_necking_response_is_flushed_once_decayed() -> None:
    """Past ln(1e250) / r after necking the filter's response is exactly zero, and never subnormal before."""
    import dataclasses

    from mudforce import _kernel as K

    params = dataclasses.replace(W25, zeta=0.5, omega_0=500.0)  # slowest decay r = 250 /s
    flush = K.neck_flush_age(0.5, 500.0)
    assert flush == pytest.approx(250.0 * math.log(10.0) / 250.0)
    t = np.arange(6001) / 1000.0
    z = np.where(t < 1.0, 0.01 * t, 0.01 - 0.01 * (t - 1.0))  # in 10 mm, then out and up for 5 s
    res = simulate(t, z, params, velocity_filter="exact")
    (tn,) = res.necking_times
    mv = res.mud_velocity
    late = t > tn + flush + 1e-3
    assert np.all(res.state[t > tn + 1e-3] == 2) and late.any()
    assert np.all(mv[late] == 0.0)
    assert np.all((mv == 0.0) | (np.abs(mv) > 1e-300))  # no subnormal numbers on the way
    # before the flush the recursion follows the closed form, Eq. (7)
    early = (t > tn + 1e-3) & (t < tn + 0.05)
    g = np.array([mf.model.equations.neck_filter_response(a, 0.5, 500.0)[0] for a in t[early] - tn])
    np.testing.assert_allclose(mv[early], mv[early][0] / g[0] * g, rtol=1e-9, atol=1e-15)


def test_result_owns_its_trajectory() -> None:
    """Changing the caller's arrays after simulate() changes nothing in the result (it copied them)."""
    t, z = Protocol.paper().sample()
    res = simulate(t, z, W25)
    fresh = simulate(t.copy(), z.copy(), W25)
    z[300] += 1e-3  # the caller's array
    t[400] += 1e-4
    assert not np.shares_memory(res.depth, z) and not np.shares_memory(res.time, t)
    assert not res.time.flags.writeable and not res.depth.flags.writeable
    np.testing.assert_array_equal(res.depth, fresh.depth)
    np.testing.assert_array_equal(res.f_e1, fresh.f_e1)  # computed on access, from the result's own copy
    np.testing.assert_array_equal(res.velocity, fresh.velocity)


def test_the_outputs_computed_on_access_are_read_only() -> None:
    """The docstring said they were read-only, but they were writable and cached: ``r.f_e1[-1] = 123`` changed what
    ``r.f_e1`` (and the CSV) gave afterwards (the rows were made read-only one by one, as temporary views). Now they
    are; the arrays the batch loop wrote stay the caller's own, writable, as the docstring now says."""
    t = np.linspace(0.0, 0.2, 21)
    res = simulate(t, 0.01 * np.sin(np.pi * t / 0.2), W25)
    for name in ("velocity", "mud_velocity", "f_e1", "f_e2", "f_s"):
        array = getattr(res, name)
        assert not array.flags.writeable, name
        with pytest.raises(ValueError, match="read-only"):
            array[-1] = 123.0
        with pytest.raises(ValueError):
            array.setflags(write=True)
        assert getattr(res, name) is array  # cached
    for name in ("force", "state", "mud_displacement", "necking_times"):
        assert getattr(res, name).flags.writeable, name
