"""MudContacts3D: many feet equal independent MudContact3D feet, per-foot muds, refusals change nothing, state, reset.

Also the compiled law (mudforce._kernel.element3d) against its numpy namesakes in mudforce.model.law3d and
mudforce.model.granular, element by element.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudforce as mf
from mudforce._kernel import element3d as E
from mudforce.errors import InputError
from mudforce.model import granular, law3d, shapes
from mudforce.model.equations import nonlinear_spring_stress
from mudforce.steppers.contact3d import ContactStates3D, MudContact3D, MudContacts3D

SPHERE = shapes.sphere(0.04, resolution=0.012)  # 56 elements
SOLE = shapes.sole(mf.Foot.paper(), resolution=0.01)  # 20
BOX = shapes.box(0.05, 0.03, 0.02, resolution=0.012)
MUD = mf.MudParameters.from_water_content(0.25)
DT = 2e-3


def _unit(rng: np.random.Generator, n: int) -> np.ndarray:
    v = rng.normal(size=(n, 3))
    out: np.ndarray = v / np.linalg.norm(v, axis=1)[:, None]
    return out


def _walk(rng: np.random.Generator, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """A foot that goes in, slides (yielding), tilts about a random axis and comes out: positions, quaternions."""
    t = np.arange(steps) * DT
    f = rng.uniform(1.5, 3.0)
    w = 2 * np.pi * f * t + rng.uniform(0, 2 * np.pi)
    pos = np.stack([0.03 * np.cos(w), 0.015 * np.sin(w + 1.0), 0.002 + 0.025 * np.sin(w)], axis=1)
    axis = _unit(rng, 1)[0]
    angle = 0.4 * np.sin(w + 0.5)
    quat = np.concatenate([np.cos(angle / 2)[:, None], np.sin(angle / 2)[:, None] * axis], axis=1)
    return pos, quat


# ---------------------------------------------------------------- the compiled law, element by element
def test_the_compiled_law_is_law3d_element_by_element() -> None:
    rng = np.random.default_rng(7)
    n = 300
    normals = _unit(rng, n)
    normals[:20] = [0.0, 0.0, -1.0]  # soles
    normals[20:40, 2] = 0.0  # walls
    normals[20:40] /= np.linalg.norm(normals[20:40], axis=1)[:, None]
    angle = rng.uniform(0, 2 * np.pi, n)
    direction = np.stack([np.cos(angle), np.sin(angle), np.zeros(n)], axis=1)
    direction[:10] = 0.0  # an element that does not slip
    slip = rng.normal(scale=1e-3, size=(n, 2))
    capacity = rng.uniform(0.0, 2e3, n)
    velocity = rng.normal(scale=0.05, size=(n, 2))
    depth = rng.uniform(-0.01, 0.05, n)
    k, sigma_y = 3e5, 1.2e3

    shear = [E.shear_fraction(*normals[i], *direction[i, :2]) for i in range(n)]
    bearing = [E.bearing_factor(*normals[i], *direction[i, :2]) for i in range(n)]
    weight = [E.vertical_weight(normals[i, 2]) for i in range(n)]
    spring = [nonlinear_spring_stress(MUD.alpha, MUD.beta, depth[i], 0.038) for i in range(n)]
    returned = np.array([E.lateral_return_map(slip[i, 0], slip[i, 1], k, capacity[i]) for i in range(n)])
    drag = np.array([E.horizontal_drag(MUD.lambda_, MUD.rho_m, *normals[i, :2], *velocity[i]) for i in range(n)])
    cap = [E.lateral_capacity(sigma_y, shear[i], spring[i], bearing[i]) for i in range(n)]

    # the same expressions in the same order: bit for bit
    assert np.array_equal(weight, law3d.vertical_weight(normals))
    kept, traction = law3d.lateral_return_map(slip, k, capacity)
    assert np.array_equal(returned[:, :2], kept) and np.array_equal(returned[:, 2:], traction)
    assert np.array_equal(drag, law3d.horizontal_drag(MUD.lambda_, MUD.rho_m, normals, velocity))
    assert np.array_equal(cap, law3d.lateral_capacity(sigma_y, np.array(shear), np.array(spring),
                                                      np.array(bearing)))
    # numpy sums in its own order (einsum, pow): a few ulp
    np.testing.assert_allclose(shear, law3d.shear_fraction(normals, direction), rtol=0, atol=1e-15)
    np.testing.assert_allclose(bearing, law3d.bearing_factor(normals, direction), rtol=0, atol=1e-15)
    assert np.count_nonzero(bearing) > n // 3
    reference = law3d.spring_stress(depth, MUD.alpha, MUD.beta, 0.038)
    np.testing.assert_allclose(spring, reference, rtol=3e-16, atol=0)
    assert np.array_equal(np.array(spring) == 0.0, reference == 0.0)


def test_the_compiled_cubic_fit_is_granulars_rft3d_alpha() -> None:
    rng = np.random.default_rng(8)
    n = 300
    normals = _unit(rng, n)
    velocities = rng.normal(size=(n, 3))
    velocities[:10, :2] = 0.0  # straight down or up
    velocities[10:20] = 0.0  # at rest
    normals[20:30] = [0.0, 0.0, 1.0]
    ours = np.array([E.rft3d_alpha(*normals[i], *velocities[i]) for i in range(n)])
    np.testing.assert_allclose(ours, granular.rft3d_alpha(normals, velocities), rtol=0, atol=1e-15)
    assert np.all(ours[10:20] == 0.0)


def test_the_compiled_rotation_is_law3d_bit_for_bit() -> None:
    rng = np.random.default_rng(9)
    q = rng.normal(size=(200, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    q[100:] *= 1.0 + rng.uniform(-9e-7, 9e-7, size=(100, 1))  # within the tolerance: normalised
    q[0] = [1.0, 0.0, 0.0, 0.0]
    for row in q:
        assert np.array_equal(np.reshape(E.rotation(*row), (3, 3)), law3d.rotation_matrix(row))


# ---------------------------------------------------------------- many feet = independent feet
def test_many_feet_are_independent_mudcontact3d_feet_with_their_own_muds() -> None:
    rng = np.random.default_rng(1)
    steps = 250
    feet = [SPHERE, SOLE, BOX, SPHERE]
    muds = [mf.MudParameters.from_water_content(w) for w in (0.20, 0.25, 0.30, 0.35)]
    heights = [0.0, 0.01, -0.005, 0.0]
    stiffness = [None, 2e5, None, 5e5]
    walks = [_walk(rng, steps) for _ in feet]
    for f, h in enumerate(heights):
        walks[f][0][:, 2] += h
    pos = np.stack([w[0] for w in walks], axis=1)
    quat = np.stack([w[1] for w in walks], axis=1)
    many = MudContacts3D(muds, feet, surface_heights=heights, lateral_stiffness=stiffness)
    alone = [MudContacts3D(muds[f], feet[f], 1, surface_heights=heights[f], lateral_stiffness=stiffness[f])
             for f in range(len(feet))]
    ref = [MudContact3D(muds[f], feet[f], heights[f], lateral_stiffness=stiffness[f]) for f in range(len(feet))]
    force = np.empty((steps, len(feet), 3))
    torque = np.empty((steps, len(feet), 3))
    expected = np.empty_like(force)
    expected_torque = np.empty_like(torque)
    for k in range(steps):
        dt = DT if k else 0.0
        force[k], torque[k] = many.step(pos[k], quat[k], dt)
        for f in range(len(feet)):
            a, b = alone[f].step(pos[k, f:f + 1], quat[k, f:f + 1], dt)
            assert np.array_equal(a[0], force[k, f]) and np.array_equal(b[0], torque[k, f])  # the others change nothing
            w = ref[f].step(pos[k, f], quat[k, f], dt)
            expected[k, f], expected_torque[k, f] = w.force, w.torque
    peak = np.max(np.abs(expected), axis=(0, 2))
    assert np.all(peak > 1.0)
    for f in range(len(feet)):
        assert np.max(np.abs(force[:, f] - expected[:, f])) <= 1e-12 * peak[f]
        assert np.max(np.abs(torque[:, f] - expected_torque[:, f])) <= 1e-12 * peak[f] * 0.05  # arm <= 50 mm
    # the walk exercised the law: sideways forces, yielding, necking, and the muds differ
    assert np.max(np.abs(force[:, :, :2])) > 0.2 * np.max(np.abs(force[:, :, 2]))
    assert "NECKED" in many.modes
    assert not np.array_equal(force[:, 0], force[:, 3])


def test_threads_give_the_same_bits_with_feet_of_unequal_sizes() -> None:
    rng = np.random.default_rng(5)
    feet = [SPHERE] * 2 + [SOLE] * 9  # the slices of feet hold unequal numbers of elements
    pos, quat = _walk(rng, 60)
    pos = np.repeat(pos[:, None, :], len(feet), axis=1) + rng.normal(scale=2e-3, size=(1, len(feet), 3))
    quat = np.repeat(quat[:, None, :], len(feet), axis=1)
    one = MudContacts3D(MUD, feet, threads=1)
    three = MudContacts3D(MUD, feet, threads=3)
    assert three.threads == 3
    for k in range(60):
        a, b = one.step(pos[k], quat[k], DT if k else 0.0), three.step(pos[k], quat[k], DT if k else 0.0)
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert np.max(np.abs(a[0])) > 1.0
    bad = pos[59].copy()
    bad[10, 0] = math.nan
    saved = three.state
    with pytest.raises(InputError, match="foot 10"):
        three.step(bad, quat[59], DT)
    assert _same_state(three.state, saved)


# ---------------------------------------------------------------- refused input changes nothing
def _settled_feet(n: int) -> tuple[MudContacts3D, np.ndarray, np.ndarray]:
    contacts = MudContacts3D(MUD, SPHERE, n)
    rng = np.random.default_rng(n)
    pos, quat = _walk(rng, 40)
    pos = np.repeat(pos[:, None, :], n, axis=1) + rng.normal(scale=1e-3, size=(1, n, 3))
    quat = np.repeat(quat[:, None, :], n, axis=1)
    for k in range(30):
        contacts.step(pos[k], quat[k], DT if k else 0.0)
    return contacts, pos[30], quat[30]


def _same_state(a: ContactStates3D, b: ContactStates3D) -> bool:
    return all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))


def test_a_nan_at_foot_k_of_16_is_refused_and_no_foot_moves() -> None:
    contacts, pos, quat = _settled_feet(16)
    saved = contacts.state
    for k in (0, 7, 15):
        for what in ("position", "quaternion"):
            p, q = pos.copy(), quat.copy()
            (p if what == "position" else q)[k, 1] = math.nan
            with pytest.raises(InputError, match=f"foot {k}: .*{what}.*no foot was stepped"):
                contacts.step(p, q, DT)
            assert _same_state(contacts.state, saved)
    out = (np.full((16, 3), 7.0), np.full((16, 3), 7.0))
    for p, q, dt, kwargs, match in (
        (pos, quat * 1.01, DT, {}, "foot 0: .*norm 1"),
        (pos + np.array([0.0, 0.0, -200.0]), quat, DT, {}, "foot 0: .*100 m"),
        (pos, quat, 0.0, {}, "dt"),
        (pos, quat, math.nan, {}, "dt"),
        (pos[:15], quat, DT, {}, "positions .*shape"),
        (pos, quat[:, :3], DT, {}, "quaternions .*shape"),
        (pos.astype(complex), quat, DT, {}, "positions"),
        (pos, quat, DT, {"out": (np.empty((16, 3)),)}, "out"),
        (pos, quat, DT, {"out": (np.empty((16, 3)), np.empty((16, 3), dtype=np.float32))}, "out"),
        (pos, quat, DT, {"out": out}, None),
    ):
        if match is None:
            continue
        with pytest.raises(InputError, match=match):
            contacts.step(p, q, dt, **kwargs)
        assert _same_state(contacts.state, saved)
    # and the step, retried, is the step that would have been taken
    twin, _, _ = _settled_feet(16)
    got = contacts.step(pos, quat, DT, out=out)
    assert got[0] is out[0] and got[1] is out[1]
    want = twin.step(pos, quat, DT)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])


_finite = st.floats(-0.2, 0.2, allow_nan=False)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(_finite, _finite, st.floats(-0.05, 0.1), st.floats(-1, 1), st.floats(-1, 1),
                          st.floats(-1, 1), st.floats(-1, 1)), min_size=3, max_size=3),
       st.floats(1e-4, 0.05), st.integers(0, 2))
def test_any_finite_poses_give_a_finite_wrench(poses: list[tuple[float, ...]], dt: float, bad: int) -> None:
    contacts = MudContacts3D(MUD, [SPHERE, SOLE, BOX])
    upright = np.tile([1.0, 0.0, 0.0, 0.0], (3, 1))
    start = np.array([[0.0, 0.0, -0.01]] * 3)
    contacts.step(start, upright, 0.0)
    contacts.step(start + np.array([0.001, 0.0, -0.002]), upright, dt)
    pos = np.array([p[:3] for p in poses])
    quat = np.array([p[3:] for p in poses])
    norm = np.linalg.norm(quat, axis=1)
    quat = np.where(norm[:, None] > 1e-3, quat / np.maximum(norm, 1e-3)[:, None], upright)
    forces, torques = contacts.step(pos, quat, dt)
    assert np.all(np.isfinite(forces)) and np.all(np.isfinite(torques))
    saved = contacts.state
    pos[bad, 2] = math.inf
    with pytest.raises(InputError, match=f"foot {bad}"):
        contacts.step(pos, quat, dt)
    assert _same_state(contacts.state, saved)


# ---------------------------------------------------------------- state and reset
def test_state_restores_and_replays_bit_for_bit() -> None:
    rng = np.random.default_rng(3)
    pos, quat = _walk(rng, 120)
    pos = np.stack([pos, pos[::-1]], axis=1)
    quat = np.stack([quat, quat[::-1]], axis=1)
    contacts = MudContacts3D([MUD, mf.MudParameters.from_water_content(0.3)], [SPHERE, BOX])
    for k in range(40):
        contacts.step(pos[k], quat[k], DT if k else 0.0)
    saved = contacts.state
    first = [contacts.step(pos[k], quat[k], DT) for k in range(40, 120)]
    contacts.state = saved
    again = [contacts.step(pos[k], quat[k], DT) for k in range(40, 120)]
    for (f1, t1), (f2, t2) in zip(first, again, strict=True):
        assert np.array_equal(f1, f2) and np.array_equal(t1, t2)
    now = contacts.state
    for broken in (saved._replace(slip=saved.slip[:-1]), saved._replace(started=np.ones(3, bool)),
                   saved._replace(centroids=saved.centroids * math.nan),
                   saved._replace(elements=saved.elements * -1.0)):
        with pytest.raises(InputError):
            contacts.state = broken
        assert _same_state(contacts.state, now)
    with pytest.raises(InputError, match="ContactStates3D"):
        contacts.state = tuple(saved)  # type: ignore[assignment]
    assert contacts.element_slice(1) == slice(SPHERE.n, SPHERE.n + BOX.n)


def test_reset_some_feet_starts_them_afresh_and_leaves_the_others() -> None:
    rng = np.random.default_rng(4)
    pos, quat = _walk(rng, 60)
    pos = np.repeat(pos[:, None, :], 3, axis=1)
    quat = np.repeat(quat[:, None, :], 3, axis=1)
    contacts = MudContacts3D(MUD, SPHERE, 3)
    untouched = MudContacts3D(MUD, SPHERE, 3)
    for k in range(30):
        contacts.step(pos[k], quat[k], DT if k else 0.0)
        untouched.step(pos[k], quat[k], DT if k else 0.0)
    contacts.reset([1])
    assert contacts.state.started.tolist() == [True, False, True]
    fresh = MudContacts3D(MUD, SPHERE, 1)
    for k in range(30, 60):
        f, t = contacts.step(pos[k], quat[k], DT)
        g, u = untouched.step(pos[k], quat[k], DT)
        h, v = fresh.step(pos[k, 1:2], quat[k, 1:2], DT if k > 30 else 0.0)
        assert np.array_equal(f[[0, 2]], g[[0, 2]]) and np.array_equal(t[[0, 2]], u[[0, 2]])
        assert np.array_equal(f[1], h[0]) and np.array_equal(t[1], v[0])
    contacts.reset(np.array([True, True, True]))
    assert not contacts.state.started.any()
    contacts.step(pos[0], quat[0], math.nan)  # every foot's first step: dt is ignored
    contacts.reset()
    for bad in ([5], np.array([True]), ["a"]):
        with pytest.raises(InputError):
            contacts.reset(bad)


def test_constructor_refuses_what_it_cannot_use() -> None:
    for args, kwargs, match in (
        ((MUD, SPHERE), {}, "give n"),
        (([MUD, MUD], [SPHERE] * 3), {}, "3 shapes for 2 feet"),
        ((MUD, SPHERE, 2), {"surface_heights": [0.0]}, "1 surface_heights for 2 feet"),
        ((MUD, SPHERE, 2), {"lateral_stiffness": -1.0}, "lateral_stiffness"),
        ((MUD, SPHERE, 2), {"surface_heights": 500.0}, "surface_height"),
        ((MUD, mf.Foot.paper(), 2), {}, "Shape"),
        (("mud", SPHERE, 2), {}, "MudParameters"),
        ((MUD, shapes.Shape(SOLE.centroids, SOLE.normals, SOLE.areas), 2), {}, "width"),
        ((MUD, SPHERE, 0), {}, "n"),
    ):
        with pytest.raises(InputError, match=match):
            MudContacts3D(*args, **kwargs)
