"""MudContacts: n feet stepped together equal n MudContact objects fed the same samples."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mudforce import Foot, MudContact, MudParameters
from mudforce import _kernel as K
from mudforce.errors import InputError
from mudforce.model.parameters import TABLE_I
from mudforce.steppers.many import MudContacts

W25 = MudParameters.from_water_content(0.25)


def _walks(seed: int, steps: int, n: int) -> np.ndarray:
    """Random depth walks around the surface [m]: intrusions, holds, withdrawals, necking."""
    rng = np.random.default_rng(seed)
    v = rng.normal(0.0, 0.02, (steps, n)) * (rng.random((steps, n)) < 0.7)
    return np.cumsum(v * 0.01, axis=0) + rng.uniform(-0.002, 0.01, n)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 6), dt=st.floats(1e-4, 0.05))
def test_equals_independent_contacts(seed: int, n: int, dt: float) -> None:
    rng = np.random.default_rng(seed)
    rows = list(TABLE_I.values())
    params = [rows[int(i)] for i in rng.integers(0, len(rows), n)]
    feet = [Foot.cuboid(float(a), float(b)) for a, b in rng.uniform(0.02, 0.08, (n, 2))]
    many = MudContacts(params, n, feet)
    single = [MudContact(p, f) for p, f in zip(params, feet, strict=True)]
    for depths in _walks(seed, 200, n):
        forces = many.step(depths, dt).copy()
        expected = [c.step(float(z), dt) for c, z in zip(single, depths, strict=True)]
        np.testing.assert_array_equal(forces, expected)  # bit for bit: the same compiled stepper
    for j in range(n):
        np.testing.assert_array_equal(many.state[j, : K.N_STATE], single[j].state.data)
    assert many.modes == [c.state.mode for c in single]


def test_gaits_at_a_constant_rate_equal_independent_contacts() -> None:
    """Feet on periodic gaits at 1 kHz: every contact state, neckings and clinging mud, bit for bit.

    At a constant rate most steps go through the stepper's path for steps
    in which nothing happens (``_kernel.quiet_step``); the streaming
    contacts always take the full step, so this checks one against the other.
    """
    rng = np.random.default_rng(5)
    n = 24
    params = [TABLE_I[w] for w in rng.choice(sorted(TABLE_I), n)]
    many = MudContacts(params, n)
    single = [MudContact(p) for p in params]
    t = np.arange(1500) * 1e-3
    depths = 0.008 + 0.012 * np.sin(2.0 * np.pi * rng.uniform(0.5, 3.0, n) * t[:, None] + rng.uniform(0, 6.3, n))
    seen = set()
    for z in depths:
        forces = many.step(z, 1e-3).copy()
        np.testing.assert_array_equal(forces, [c.step(float(d), 1e-3) for c, d in zip(single, z, strict=True)])
        seen.update(many.modes)
    assert seen == {"FREE", "CONTACT", "NECKED"}
    for j in range(n):
        np.testing.assert_array_equal(many.state[j, : K.N_STATE], single[j].state.data)


def test_parameter_array_for_domain_randomisation() -> None:
    rng = np.random.default_rng(1)
    base = W25.as_array()
    values = base * rng.uniform(0.8, 1.2, (4, base.size))
    values[:, 5] = np.clip(values[:, 5], 0.1, 1.0)  # beta stays in (0, 1]
    many = MudContacts(values, 4)
    single = [MudContact(MudParameters(*row.tolist())) for row in values]
    for depths in _walks(2, 100, 4):
        np.testing.assert_array_equal(many.step(depths, 0.01), [c.step(float(z), 0.01) for c, z in
                                                                 zip(single, depths, strict=True)])
    with pytest.raises(InputError, match="beta"):
        MudContacts(np.tile(np.r_[base[:5], 2.0, base[6:]], (2, 1)), 2)
    with pytest.raises(InputError, match="shape"):
        MudContacts(values[:, :5], 4)
    # a complex array lost its imaginary part (numpy's ComplexWarning), a boolean one read as 1.0, strings were
    # parsed and objects taken: each is refused in one line naming its dtype
    for bad in (values + 0j, values.astype(str), values.astype(object), np.ones((4, 11), dtype=bool)):
        with pytest.raises(InputError, match=r"^a parameter array must be an array of real numbers \[SI\], got "):
            MudContacts(bad, 4)


def test_reset_selected_feet() -> None:
    many = MudContacts(W25, 3)
    fresh = MudContact(W25)
    many.step(np.zeros(3), 0.01)
    for z in (0.005, 0.01, 0.012):
        many.step(np.full(3, z), 0.01)
    many.reset([1])
    assert many.modes == ["CONTACT", "FREE", "CONTACT"]
    kept = many.state[[0, 2], : K.N_STATE].copy()
    # foot 1 starts again from its next sample, like a fresh MudContact
    depths = np.array([0.012, 0.0, 0.012])
    f = many.step(depths, 0.01).copy()
    assert f[1] == fresh.step(0.0, 0.01)
    for z in (0.003, 0.006):
        f = many.step(np.array([0.012, z, 0.012]), 0.01).copy()
        assert f[1] == fresh.step(z, 0.01)
    assert not np.array_equal(kept, many.state[[0, 2], : K.N_STATE])  # the others went on relaxing
    mask = np.array([True, False, True])
    many.reset(mask)
    assert many.modes == ["FREE", "CONTACT", "FREE"]
    many.reset()
    assert many.modes == ["FREE"] * 3


def test_snapshot_restore_replays_exactly() -> None:
    many = MudContacts(W25, 2)
    walks = _walks(3, 60, 2)
    for depths in walks[:30]:
        many.step(depths, 0.01)
    snap = many.state
    first = np.array([many.step(d, 0.01).copy() for d in walks[30:]])
    many.state = snap
    second = np.array([many.step(d, 0.01).copy() for d in walks[30:]])
    np.testing.assert_array_equal(first, second)


def test_bad_input_is_refused() -> None:
    many = MudContacts(W25, 2)
    with pytest.raises(InputError, match="shape"):
        many.step(np.zeros(3), 0.01)
    many.step(np.zeros(2), 0.0)  # the first step ignores dt, as MudContact.step's does
    with pytest.raises(InputError, match="dt"):
        many.step(np.zeros(2), 0.0)
    many.step(np.zeros(2), 0.01)
    with pytest.raises(InputError, match="foot 1"):
        many.step(np.array([0.001, np.nan]), 0.01)
    with pytest.raises(InputError, match="n must be"):
        MudContacts(W25, 0)
    with pytest.raises(InputError, match="out of range"):
        many.reset([2])
    with pytest.raises(InputError, match="3 parameter sets"):
        MudContacts([W25] * 3, 2)
    # a string's characters and a mapping's keys were counted as feet: "got 5 feet for 2 contacts" for "paper"
    for foot in ("paper", {"a": Foot.paper(), "b": Foot.paper()}):
        with pytest.raises(InputError, match=f"foot must be a Foot or a sequence of Foot, got {type(foot).__name__}$"):
            MudContacts(W25, 2, foot)


def test_snapshot_restore_with_a_smoothing_filter() -> None:
    """A snapshot holds each foot's state row and its filter's recent samples; replays are exact."""
    from mudforce import VelocityFilter

    vf = VelocityFilter(6, 0.001)
    many = MudContacts(W25, 3, velocity_filter=vf)
    single = [MudContact(W25, velocity_filter=vf) for _ in range(3)]
    walks = _walks(4, 80, 3)
    for depths in walks[:40]:
        many.step(depths, 0.01)
        for c, z in zip(single, depths, strict=True):
            c.step(float(z), 0.01)
    snap = many.state
    assert snap.shape == (3, K.N_STATE + K.N_RING)
    np.testing.assert_array_equal(snap[1, K.N_STATE:], single[1].state.ring)
    first = np.array([many.step(d, 0.01).copy() for d in walks[40:]])
    expected = np.array([[c.step(float(z), 0.01) for c, z in zip(single, d, strict=True)] for d in walks[40:]])
    np.testing.assert_array_equal(first, expected)
    many.state = snap
    np.testing.assert_array_equal(np.array([many.step(d, 0.01).copy() for d in walks[40:]]), first)
    with pytest.raises(InputError, match="shape"):
        many.state = snap[:, : K.N_STATE]
    # one contact likewise: a filtered state into an exact contact dropped its history (read back, it differed)
    exact = MudContact(W25)
    before = exact.state
    with pytest.raises(InputError, match=r"^this contact's exact velocity rule keeps no history"):
        exact.state = single[0].state
    assert exact.state == before


@pytest.mark.parametrize("window", [1, 6])
def test_threads_give_the_same_forces_bit_for_bit(window: int) -> None:
    """Stepping the feet in slices on threads changes nothing: the feet are independent."""
    from mudforce import VelocityFilter

    vf = "exact" if window == 1 else VelocityFilter(window, 0.001)
    n = 37
    rng = np.random.default_rng(5)
    rows = list(TABLE_I.values())
    params = [rows[int(i)] for i in rng.integers(0, len(rows), n)]
    runs = [MudContacts(params, n, velocity_filter=vf, threads=t) for t in (1, 2, 5)]
    assert [c.threads for c in runs] == [1, 2, 5]
    for depths in _walks(6, 150, n):
        forces = [c.step(depths, 0.01).copy() for c in runs]
        np.testing.assert_array_equal(forces[1], forces[0])
        np.testing.assert_array_equal(forces[2], forces[0])
    for c in runs[1:]:
        np.testing.assert_array_equal(c.state, runs[0].state)
        np.testing.assert_array_equal(c.ring, runs[0].ring)
    # a refused foot in a later slice is reported by its index; the other feet step
    bad = np.full(n, 0.004)
    bad[30] = np.nan
    for c in runs:
        with pytest.raises(InputError, match="foot 30"):
            c.step(bad, 0.01)
    np.testing.assert_array_equal(runs[2].state, runs[0].state)


def test_threads_argument() -> None:
    assert MudContacts(W25, 3, threads=8).threads == 3  # at most one slice per foot
    assert MudContacts(W25, 10).threads == 1  # too few feet to pay for a launch
    assert "threads=1" in repr(MudContacts(W25, 2))
    for bad in (0, -1, 1.5, True):
        with pytest.raises(InputError, match="threads must be"):
            MudContacts(W25, 2, threads=bad)  # type: ignore[arg-type]


def test_a_forked_child_steps_on_one_thread() -> None:
    """GNU OpenMP is not fork-safe: a child forked after threads ran steps its feet on its own thread.

    Run in a fresh interpreter: this test process may hold other libraries' threads (JAX's), and a fork
    with those alive is itself unsafe, which is not what this test is about.
    """
    import os
    import subprocess
    import sys

    if not hasattr(os, "fork"):
        pytest.skip("no fork on this platform")
    script = """
import os, numpy as np
from mudforce import MudContacts, MudParameters, vectorized
W25 = MudParameters.from_water_content(0.25)
parent = MudContacts(W25, 8, threads=2)
parent.step(np.zeros(8), 0.01)
r, w = os.pipe()
pid = os.fork()
if pid == 0:
    try:
        child = MudContacts(W25, 4 * vectorized.FEET_PER_THREAD)
        f = parent.step(np.full(8, 0.003), 0.01)
        ok = vectorized._forked and child.threads == 1 and bool(np.all(f > 0))
        os.write(w, b"1" if ok else b"0")
    finally:
        os._exit(0)
os.close(w)
answer = os.read(r, 1)
os.waitpid(pid, 0)
print(answer.decode())
"""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, env=env,
                          check=False)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "1"


def test_reset_refuses_booleans_among_indices_and_nested_indices() -> None:
    """``reset([True, 2])`` reset feet 1 and 2 (True read as 1); ``reset([[0]])`` reset foot 0 (MudContacts3D's
    reset refuses it). Each should be one InputError and no foot reset."""
    from mudforce.model import shapes
    from mudforce.steppers.contact3d import MudContacts3D

    params = MudParameters.from_water_content(0.25)
    one_d = MudContacts(params, n=3)
    one_d.step(np.full(3, 0.01), 0.0)
    three_d = MudContacts3D(params, shapes.sphere(0.03, resolution=0.015), 3)
    three_d.step(np.zeros((3, 3)), np.tile([1.0, 0.0, 0.0, 0.0], (3, 1)), 0.0)
    for feet, modes in ((one_d, lambda: one_d.modes), (three_d, lambda: three_d.state.started.tolist())):
        before = modes()
        for bad in ([True, 2], [[0]], [[0], [0, 1]]):  # ragged: numpy's ValueError (inhomogeneous shape)
            with pytest.raises(InputError):
                feet.reset(bad)
            assert modes() == before


def test_a_restored_state_replays_bit_for_bit_when_the_step_length_wavers_in_its_last_bits() -> None:
    # steps of k/rate at t ~ 1000 s differ in their last bits: the stepper reuses its cache within 1e-9, and the
    # restore dropped it, so the replay's cache was for another length (forces off by ~1e-9 relative)
    t = 1000.0 + np.arange(1200) / 300.0
    z = 0.01 + 0.01 * np.sin(3.0 * t)
    dts = np.diff(t)
    k0 = 1 + int(np.flatnonzero(dts[400:] != dts[0])[0]) + 400  # a step whose length differs from the cached one
    feet = MudContacts([MudParameters.from_water_content(0.25), MudParameters.from_water_content(0.3)], 2)
    feet.step(np.full(2, z[0]), 0.01)
    for k in range(1, k0):
        feet.step(np.full(2, z[k]), float(dts[k - 1]))
    saved = feet.state
    first = np.array([feet.step(np.full(2, z[k]), float(dts[k - 1])) for k in range(k0, t.size)])
    feet.state = saved
    again = np.array([feet.step(np.full(2, z[k]), float(dts[k - 1])) for k in range(k0, t.size)])
    assert first.tobytes() == again.tobytes()


def test_a_reset_forgets_the_filter_history_so_the_state_is_a_fresh_ones() -> None:
    """reset() cleared the state rows but kept the filter's old samples: after a reset and three steps the state
    differed from a fresh contact's fed the same three (MudContact.state != the twin's, MudContacts.state's bytes
    differed) until the window had filled again; the forces were the same."""
    from mudforce import VelocityFilter

    vf = VelocityFilter.for_noise(5e-5, 0.01)
    depths = 0.01 + 0.002 * np.sin(np.arange(10.0))
    one, many = MudContact(W25, velocity_filter=vf), MudContacts(W25, 2, velocity_filter=vf)
    for z in depths:
        one.step(float(z), 0.01)
        many.step(np.full(2, z), 0.01)
    one.reset()
    many.reset([0])
    fresh, fresh_many = MudContact(W25, velocity_filter=vf), MudContacts(W25, 1, velocity_filter=vf)
    for z in depths[:3]:
        assert one.step(float(z), 0.01) == fresh.step(float(z), 0.01)
        many.step(np.full(2, z), 0.01)
        fresh_many.step(np.full(1, z), 0.01)
    assert one.state == fresh.state
    assert many.state[0].tobytes() == fresh_many.state[0].tobytes()


def test_strided_read_only_and_unaligned_depths_step_as_the_contiguous_ones_without_a_compile() -> None:
    """A strided or a read-only float64 array made numba compile another version of the step and of the depth check
    (1.75 and 1.9 s, once each); such arrays, and unaligned ones (which numba types as aligned), are now copied to
    the one compiled layout, as MudContacts3D's inputs are: the same forces, bit for bit, and no new version."""
    from mudforce.steppers import many

    params = MudParameters.from_water_content(0.25)
    path = np.linspace(0.0, 0.02, 8)[:, None] + np.linspace(0.0, 0.004, 6)  # 8 steps of 6 feet
    wide = np.repeat(path, 2, axis=1)  # each row strided: [:, ::2] is the path
    raw = np.zeros(path.size * 8 + 1, dtype=np.uint8)
    unaligned = raw[1:].view(np.float64).reshape(path.shape)
    unaligned[...] = path
    assert not unaligned.flags.aligned
    reference = MudContacts(params, 6, threads=1)
    expected = [reference.step(np.ascontiguousarray(row), 0.01) for row in path]
    read_only = path.copy()
    read_only.flags.writeable = False
    compiled = len(K.run_feet.overloads), len(many._depths_ok.overloads)
    for rows in (wide[:, ::2], read_only, unaligned):
        contacts = MudContacts(params, 6, threads=1)
        for row, forces in zip(rows, expected, strict=True):
            assert contacts.step(row, 0.01).tobytes() == forces.tobytes()
    assert (len(K.run_feet.overloads), len(many._depths_ok.overloads)) == compiled
