"""MudContacts3D: many feet equal independent MudContact3D feet, per-foot muds, refusals change nothing, state, reset.

Also the law's one source (mudforce.model.law3d) compiled and on arrays, bit for bit, and its bearing against
mudforce.model.granular's 3D-RFT.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudforce as mf
from mudforce._kernel import step3d as S3
from mudforce.errors import InputError
from mudforce.model import granular, law3d, shapes
from mudforce.model.equations import nonlinear_spring_stress
from mudforce.steppers.contact3d import ContactStates3D, MudContact3D, MudContacts3D

SPHERE = shapes.sphere(0.04, resolution=0.012)  # 56 elements
SOLE = shapes.sole(mf.Foot.paper(), resolution=0.01)  # 20
FINE = shapes.sphere(0.04, resolution=0.006)  # 196: four lane blocks
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


# ---------------------------------------------------------------- one law: compiled, on arrays, on floats
def test_the_law_is_one_source_compiled_and_on_arrays_bit_for_bit() -> None:
    rng = np.random.default_rng(7)
    n = 300
    normals = _unit(rng, n)
    normals[:20] = [0.0, 0.0, -1.0]  # soles
    normals[20:40, 2] = 0.0  # walls
    normals[20:40] /= np.linalg.norm(normals[20:40], axis=1)[:, None]
    slip = rng.normal(scale=1e-3, size=(n, 2))
    moved = rng.normal(scale=1e-3, size=(n, 2))
    slip[:10] = 0.0
    moved[:10] = 0.0  # an element that does not slip
    depth = rng.uniform(-0.01, 0.05, n)
    stress = rng.normal(scale=2e3, size=n)
    spring = rng.uniform(0.0, 3e3, n)
    area = rng.uniform(1e-5, 1e-4, n)
    k, sigma_y = 3e5, 1.2e3
    ox, oy, oz = normals[:, 1].copy(), normals[:, 2].copy(), normals[:, 0].copy()  # some offsets [m]
    out = np.empty((n, 8))  # compiled: the kernel's loop over element_force and moment (MudContact3D's)
    columns = [np.ascontiguousarray(c) for c in (*normals.T, *moved.T)]  # MudContact3D's types: no new compile
    # (MudContact3D's compiled step passes rows of one writable work array: the same types)
    S3.element_forces(stress, spring, area, *columns[:3], ox, oy, oz, depth, slip, *columns[3:], 500.0, k, sigma_y,
                      MUD.lambda_, MUD.rho_m, out)
    sx, sy, fx, fy, fz = law3d.element_force(stress, spring, area, *normals.T, depth, *slip.T, *moved.T, 500.0, True,
                                             k, sigma_y, MUD.lambda_, MUD.rho_m)
    arrays = np.stack([sx, sy, fx, fy, fz, *law3d.moment(ox, oy, oz, fx, fy, fz)], axis=1)
    assert np.array_equal(out, arrays)  # the same source, the same IEEE operations: the same bits
    # on floats from Python too, and Eq. (4) is the 1-D law's (its shared power), bit for bit
    assert law3d.element_force(stress[50], spring[50], area[50], *normals[50], depth[50], *slip[50], *moved[50],
                               500.0, True, k, sigma_y, MUD.lambda_, MUD.rho_m)[2] == out[50, 2]
    assert np.array_equal(law3d.spring_stress(depth, 2e4, 0.5, 0.04),
                          [nonlinear_spring_stress(2e4, 0.5, z, 0.04) for z in depth])
    # the law did something on these elements: yielding and elastic ones, sideways forces; above the surface no
    # slip, and sideways only the vertical stress's own part (3D-RFT's direction: law3d.vertical_element_force)
    above = depth <= 0.0
    lean = law3d.vertical_lean(normals[:, 2]) * out[:, 4]
    assert np.all(out[above, :2] == 0.0) and np.count_nonzero(out[:, 2]) > n // 2
    assert np.array_equal(out[above, 2:4], (lean[:, None] * normals[:, :2])[above])


def test_the_bearing_is_granulars_rft3d_alpha_for_a_horizontal_slip() -> None:
    rng = np.random.default_rng(8)
    n = 300
    normals = _unit(rng, n)
    normals[20:30] = [0.0, 0.0, 1.0]
    normals[30:40] = [0.0, 0.0, -1.0]
    angle = rng.uniform(0, 2 * np.pi, n)
    direction = np.stack([np.cos(angle), np.sin(angle), np.zeros(n)], axis=1)
    alpha = granular.rft3d_alpha(normals, direction)
    leading = np.einsum("ij,ij->i", normals, direction) > 0.0
    want = np.where(leading, np.maximum(-np.einsum("ij,ij->i", alpha, direction), 0.0) / law3d.FLAT_PLATE_ALPHA, 0.0)
    got = law3d.bearing_factor(*normals.T, direction[:, 0], direction[:, 1])
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-15)
    assert np.count_nonzero(got) > n // 3
    along = normals - np.einsum("ij,ij->i", normals, direction)[:, None] * 0.0
    shear = law3d.shear_fraction(*normals.T, direction[:, 0], direction[:, 1])
    tangential = direction - np.einsum("ij,ij->i", direction, along)[:, None] * normals
    np.testing.assert_allclose(shear, np.linalg.norm(tangential, axis=1), rtol=0, atol=1e-15)


def test_the_rotation_is_the_quaternions() -> None:
    rng = np.random.default_rng(9)
    q = rng.normal(size=(200, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    q[100:] *= 1.0 + rng.uniform(-9e-7, 9e-7, size=(100, 1))  # within the tolerance: normalised
    q[0] = [1.0, 0.0, 0.0, 0.0]
    v = rng.normal(size=3)
    for row in q:
        u = row / np.linalg.norm(row)
        w, axis = u[0], u[1:]
        want = v + 2.0 * w * np.cross(axis, v) + 2.0 * np.cross(axis, np.cross(axis, v))  # q v q*
        np.testing.assert_allclose(law3d.rotation_matrix(row) @ v, want, rtol=0, atol=1e-14)
    assert np.array_equal(law3d.rotation_matrix(q[0]), np.eye(3))
    assert np.array_equal(np.reshape(law3d.rotation(*q[5]), (3, 3)), law3d.rotation_matrix(q[5]))


# ---------------------------------------------------------------- many feet = independent feet
def test_many_feet_are_independent_mudcontact3d_feet_with_their_own_muds() -> None:
    """Feet of several shapes (one of more elements than a lane block holds), muds, surfaces and stiffnesses,
    stepped together: each foot's wrench is that of a MudContacts3D of that foot alone and that of a MudContact3D,
    bit for bit (both sum the elements in element order, as MudContact3D's numpy step does)."""
    rng = np.random.default_rng(1)
    steps = 250
    feet = [SPHERE, SOLE, BOX, SPHERE, FINE]
    assert FINE.n > 2 * S3.LANES
    muds = [mf.MudParameters.from_water_content(w) for w in (0.20, 0.25, 0.30, 0.35, 0.28)]
    heights = [0.0, 0.01, -0.005, 0.0, 0.002]
    stiffness = [None, 2e5, None, 5e5, None]
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
    assert np.array_equal(force, expected) and np.array_equal(torque, expected_torque)
    # the walk exercised the law: sideways forces, yielding, necking, and the muds differ
    assert np.max(np.abs(force[:, :, :2])) > 0.2 * np.max(np.abs(force[:, :, 2]))
    assert "NECKED" in many.modes
    assert not np.array_equal(force[:, 0], force[:, 3])


def test_kernel_rows_follow_the_feet_as_they_are_stepped() -> None:
    """kernel_rows' read-only views show the elements' 1-D rows as the feet are stepped (the compiled step keeps
    the states in its lanes and, once the views are asked for, writes the rows after every step): they equal
    the state's rows step after step, and hold FREE, CONTACT and NECKED elements along the walk."""
    rng = np.random.default_rng(1)
    pos, quat = _walk(rng, 250)
    feet = MudContacts3D(MUD, SPHERE, 1)
    states, rows = feet.kernel_rows()
    assert not states.flags.writeable and not rows.flags.writeable
    seen = set()
    for k in range(250):
        feet.step(pos[k][None], quat[k][None], DT if k else 0.0)
        assert np.array_equal(states, feet.state.elements[:, :states.shape[1]])
        seen |= set(states[:, 1].tolist())
    assert seen == {0.0, 1.0, 2.0}


@pytest.mark.parametrize("sizes", [(1, 3), (5, 8), (9, 63), (64, 65), (130, 7)])
def test_feet_of_any_number_of_elements_step_as_the_numpy_step(sizes: tuple[int, int]) -> None:
    """The compiled step keeps a foot's elements in lanes of four, blocks of 64 (the last ones padded): feet of 1
    to 130 elements, two of different sizes stepped together, give each foot's numpy step (MudContact3D's
    reference) bit for bit, wrench and state, through touchdown, sliding, tilting and lift-off."""
    rng = np.random.default_rng(sum(sizes))
    feet = []
    for n in sizes:  # n elements on a sphere of 40 mm, random places, areas summing to its area
        normals = _unit(rng, n)
        feet.append(shapes.Shape(normals * 0.02, normals, np.full(n, math.pi * 0.04 ** 2 / n), name=f"{n} elements",
                                 width=0.04))
    many = MudContacts3D(MUD, feet)
    ref = [MudContact3D(MUD, shape) for shape in feet]
    pos, quat = _walk(rng, 60)
    peak = np.zeros(3)
    for k in range(60):
        dt = DT if k else 0.0
        forces, torques = many.step(np.stack([pos[k], pos[k] + 0.003]), np.stack([quat[k], quat[k]]), dt)
        peak = np.maximum(peak, np.abs(forces).max(axis=0))
        for f in range(2):
            w = ref[f]._step_numpy(pos[k] + 0.003 * f, quat[k], dt)
            assert np.array_equal(forces[f], w.force) and np.array_equal(torques[f], w.torque)
    state = many.state
    for f in range(2):
        rows = many.element_slice(f)
        assert np.array_equal(state.elements[rows], ref[f].state.elements)
        assert np.array_equal(state.slip[rows], ref[f].state.slip)
    assert peak[2] > 0.1 and max(peak[0], peak[1]) > 0.0  # in the mud, loaded sideways


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


def test_the_outputs_without_out_are_reused_only_when_no_one_holds_them() -> None:
    """MudContacts3D.step without out= reuses its output arrays (two pairs in turn) only while no one holds
    either array of a pair: a loop that keeps each step's results until the next makes no new arrays, and results
    kept (an array, a view of one, the returned tuple) keep their values, which are those of a step with out=."""
    feet, ref = MudContacts3D(MUD, SOLE, 2), MudContacts3D(MUD, SOLE, 2)
    quats = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    out = (np.empty((2, 3)), np.empty((2, 3)))
    kept: list[tuple[np.ndarray, np.ndarray]] = []
    seen: list[int] = []
    for k in range(14):
        positions = np.array([[0.001 * k, 0.0, 0.004 - 0.001 * k], [0.0, -0.001 * k, 0.003 - 0.001 * k]])
        forces, torques = result = feet.step(positions, quats, DT)
        ref.step(positions, quats, DT, out=out)
        assert np.array_equal(forces, out[0]) and np.array_equal(torques, out[1])
        seen.append(id(forces))
        held = {8: forces, 9: torques[:, 2], 10: result[0]}.get(k)
        if held is not None:
            kept.append((held, held.copy()))
        del result
    assert len(set(seen[2:8])) == 2  # the two pairs in turn
    assert len(set(seen[8:])) > 2  # results kept: new arrays
    for array, values in kept:
        assert np.array_equal(array, values)
    assert forces[:, 2].min() > 0.0  # in the mud


@settings(max_examples=200, deadline=None)
@given(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1), st.floats(-1e7, 1e7), st.floats(1e-8, 1.0))
def test_the_vertical_stress_leans_boundedly_and_away_from_the_normals_lean(x: float, y: float, z: float,
                                                                           stress: float, area: float) -> None:
    """law3d.vertical_element_force on any unit normal and finite stress: finite; the sideways part is the vertical
    one times 0.015-0.44 of the normal's horizontal part, against it for a push (f_z > 0), with it under suction."""
    norm = math.sqrt(x * x + y * y + z * z)
    if norm < 1e-6:
        return
    nx, ny, nz = x / norm, y / norm, z / norm
    fx, fy, fz = law3d.vertical_element_force(stress, area, nx, ny, nz)
    assert all(math.isfinite(v) for v in (fx, fy, fz))
    lean = float(law3d.vertical_lean(nz))
    assert -0.44 <= lean <= -0.015
    assert fx * nx + fy * ny == pytest.approx(lean * fz * (nx * nx + ny * ny), rel=1e-12, abs=1e-300)
    assert (fx * nx + fy * ny) * fz <= 0.0  # away from the normal's lean when pushed, towards it when sucked
