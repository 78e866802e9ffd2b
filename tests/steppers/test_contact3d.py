"""MudContact3D: the paper in its own case, symmetries, holding, sliding, peeling, bad input
(mudforce.steppers.contact3d)."""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

import mudforce as mf
from mudforce.errors import InputError
from mudforce.model import law3d, shapes
from mudforce.steppers.contact3d import MAX_ELEMENT_SAMPLES, MudContact3D, simulate_3d

WATER = (0.15, 0.20, 0.25, 0.30, 0.35)
UPRIGHT = np.array([1.0, 0.0, 0.0, 0.0])
SOLE = shapes.sole(mf.Foot.paper(), resolution=0.01)  # 20 elements: the reduction holds at any resolution
SPHERE = shapes.sphere(0.04, resolution=0.008)


def _vertical(depth: np.ndarray, yaw: float = 0.0, lift: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Poses of a foot whose body origin is at ``depth`` below a surface at height ``lift`` (z up), yawed."""
    pos = np.zeros((depth.size, 3))
    pos[:, 2] = lift - depth
    quat = np.tile([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)], (depth.size, 1))
    return pos, quat


def _push_pull_repush() -> tuple[np.ndarray, np.ndarray]:
    """1 kHz: in to 20 mm, hold, a fast pull that necks below the surface, a re-push, out (every transition)."""
    t = np.arange(1500) * 1e-3
    z = np.interp(t, [0.0, 0.2, 0.4, 0.485, 0.9, 1.5], [-2e-3, 20e-3, 20e-3, 3e-3, 10e-3, -5e-3])
    return t, z


@pytest.mark.parametrize("water", WATER)
def test_a_sole_moved_vertically_is_the_paper(water: float) -> None:
    """The issue's case: the 1-D force to 1e-9 of the peak, no sideways force, no torque."""
    params = mf.MudParameters.from_water_content(water)
    for t, z in (mf.Protocol.paper(rate=50.0).sample(), _push_pull_repush()):
        one = mf.simulate(t, z, params, velocity_filter="exact")
        pos, quat = _vertical(z)
        res = simulate_3d(t, pos, quat, params, SOLE)
        peak = float(np.max(np.abs(one.force)))
        assert np.max(np.abs(res.force[:, 2] - one.force)) <= 1e-9 * peak
        assert np.all(res.force[:, :2] == 0.0)
        assert np.max(np.abs(res.torque)) <= 1e-12 * peak * 0.05  # rounding of a symmetric sum [N m]
    assert one.necking_times.size >= 1  # the push-pull-repush necks and re-pushes


def test_yaw_and_the_world_frame_change_nothing() -> None:
    params = mf.MudParameters.from_water_content(0.25)
    t, z = mf.Protocol.paper(rate=50.0).sample()
    base = simulate_3d(t, *_vertical(z), params, SOLE)
    yawed = simulate_3d(t, *_vertical(z, yaw=0.7), params, SOLE)
    pos, quat = _vertical(z, lift=0.3)
    pos[:, :2] += [1.5, -2.0]
    moved = simulate_3d(t, pos, quat, params, SOLE, surface_height=0.3)
    peak = float(np.max(np.abs(base.force)))
    for other in (yawed, moved):
        np.testing.assert_allclose(other.force, base.force, rtol=0, atol=1e-9 * peak)
        np.testing.assert_allclose(other.torque, base.torque, rtol=0, atol=1e-9 * peak * 0.05)
    # the result's arrays are the caller's own, writable, as its docstring says (SimulationResult's stresses are not)
    assert all(a.flags.writeable for a in (moved.time, moved.force, moved.torque))
    assert not np.shares_memory(moved.time, t) and not np.shares_memory(moved.force, pos)


def _settled(contact: MudContact3D, depth: float, steps: int = 200, dt: float = 0.01) -> None:
    """Push the foot in at 10 mm/s to ``depth`` and hold it there for ``steps`` steps."""
    n_in = round(depth / 0.01 / dt)
    for k in range(n_in + 1):
        contact.step([0.0, 0.0, -k * 0.01 * dt], UPRIGHT, dt)
    for _ in range(steps):
        contact.step([0.0, 0.0, -depth], UPRIGHT, dt)


def test_a_small_sideways_load_is_held_elastically_and_a_large_one_yields() -> None:
    params = mf.MudParameters.from_water_content(0.25)
    contact = MudContact3D(params, SOLE)
    _settled(contact, 0.01)
    area = SOLE.total_area
    k = params.k_m_w
    # displaced 0.1 mm and held: the elastic traction, constant (no creep)
    for _ in range(100):
        w = contact.step([1e-4, 0.0, -0.01], UPRIGHT, 0.01)
        assert w.force[0] == pytest.approx(-k * 1e-4 * area, rel=1e-12)
        assert w.force[1] == 0.0
    # dragged 20 mm at 10 mm/s: it yields at the shear capacity sigma_y S (a sole has no leading face)
    for j in range(1, 201):
        w = contact.step([1e-4 + j * 1e-4, 0.0, -0.01], UPRIGHT, 0.01)
    drag = params.lambda_ * params.rho_m * 0.0  # the sole's faces do not face the motion
    assert w.force[0] == pytest.approx(-(params.sigma_y * area + drag), rel=1e-12)
    # stopped: it keeps the load it yielded at (elastic-plastic memory), then unloads elastically
    w = contact.step([1e-4 + 200 * 1e-4 - 1e-3, 0.0, -0.01], UPRIGHT, 0.01)
    assert w.force[0] == pytest.approx(-(params.sigma_y - k * 1e-3) * area, rel=1e-9)


def test_a_sliding_sphere_is_resisted_and_mirrored() -> None:
    params = mf.MudParameters.from_water_content(0.25)
    results = []
    for sign in (1.0, -1.0):
        contact = MudContact3D(params, SPHERE)
        _settled(contact, 0.03, steps=50)
        for j in range(1, 101):
            w = contact.step([sign * j * 2e-4, 0.0, -0.03], UPRIGHT, 0.01)
        results.append(w)
    plus, minus = results
    assert plus.force[0] < 0.0  # against the motion
    assert minus.force[0] == pytest.approx(-plus.force[0], rel=1e-9)
    assert abs(plus.force[1]) <= 1e-9 * abs(plus.force[0])
    assert minus.force[2] == pytest.approx(plus.force[2], rel=1e-9)
    # the leading half bears against the motion: more than shear alone on the sphere's girth
    assert -plus.force[0] > params.sigma_y * 0.5 * SPHERE.total_area / math.pi


def test_dissipation_over_a_closed_horizontal_cycle() -> None:
    """The mud does no net work on a foot taken round a closed horizontal loop at depth: it only takes energy."""
    params = mf.MudParameters.from_water_content(0.20)
    contact = MudContact3D(params, SPHERE)
    _settled(contact, 0.025, steps=20)
    work = 0.0
    previous = np.array([0.0, 0.0, -0.025])
    for theta in np.linspace(0.0, 4.0 * math.pi, 401)[1:]:
        pos = np.array([0.01 * math.sin(theta), 0.01 * (1.0 - math.cos(theta)), -0.025])
        w = contact.step(pos, UPRIGHT, 0.01)
        work += float(w.force[:2] @ (pos - previous)[:2])
        previous = pos
    assert work < 0.0


def test_a_tilted_sole_peels_element_by_element() -> None:
    """Tilted 20 degrees and pulled out, the deep end necks last: the neck breaks element by element."""
    params = mf.MudParameters.from_water_content(0.25)
    tilt = math.radians(20.0)
    quat = [math.cos(tilt / 2), 0.0, math.sin(tilt / 2), 0.0]
    contact = MudContact3D(params, SOLE)
    dt = 0.005
    path = np.concatenate([np.linspace(0.0, 0.02, 200), np.full(200, 0.02), np.linspace(0.02, -0.03, 50)])
    necked = []
    for z in path:
        contact.step([0.0, 0.0, -z], quat, dt)
        necked.append(sum(m == "NECKED" for m in contact.modes))
    counts = sorted(set(necked))
    assert counts[0] == 0 and counts[-1] == SOLE.n
    assert len(counts) > 3  # not all at once


@pytest.mark.parametrize("degrees", [10.0, 30.0, 60.0])
def test_a_tilted_sole_moved_vertically_leans_as_rft3d_does(degrees: float) -> None:
    """Tilted and moved straight down, held, pulled out: its force is the paper's vertical force turned by 3D-RFT.

    Every element has the same normal and no horizontal motion (no slip), so the sideways force is the
    vertical one times 3D-RFT's ``alpha_x / alpha_z`` for that plate pushed down (the 20-term fits:
    ``rft3d_alpha``), under suction too (the sign follows the vertical force's); and the independent reference
    (which takes ``rft3d_alpha`` itself) agrees to 1e-9 of the peak in every component.
    """
    from mudforce.model.granular import rft3d_alpha
    from mudforce.references.contact3d import reference_simulate_3d

    params = mf.MudParameters.from_water_content(0.25)
    tilt = math.radians(degrees)
    t, z = _push_pull_repush()
    t, z = t[::10], z[::10]
    pos, _ = _vertical(z)
    quat = np.tile([math.cos(tilt / 2), 0.0, math.sin(tilt / 2), 0.0], (t.size, 1))
    res = simulate_3d(t, pos, quat, params, SOLE)
    normal = law3d.rotation_matrix(quat[0]) @ [0.0, 0.0, -1.0]
    alpha = rft3d_alpha(normal[None], np.array([[0.0, 0.0, -1.0]]))[0]
    peak = float(np.max(np.abs(res.force)))
    assert np.max(np.abs(res.force[:, 0] - alpha[0] / alpha[2] * res.force[:, 2])) <= 1e-12 * peak
    assert np.all(res.force[:, 1] == 0.0)
    assert np.min(res.force[:, 2]) < 0.0 < np.max(res.force[:, 2])  # pushed and sucked: both signs lean
    # 3D-RFT's plate pushed down is pushed away from the side its normal leans to: 0.30 to 0.38 of the vertical
    # force per unit of the normal's horizontal part (law3d.vertical_lean)
    ratio = float(res.force[:, 0] @ res.force[:, 2]) / float(res.force[:, 2] @ res.force[:, 2])
    assert -0.38 < ratio / normal[0] < -0.30
    ref = reference_simulate_3d(t, pos, quat, params, SOLE)
    assert np.max(np.abs(res.force - ref.force)) <= 1e-9 * peak
    assert np.max(np.abs(res.torque - ref.torque)) <= 1e-9 * peak * 0.2


def test_bad_input_is_refused_and_changes_nothing() -> None:
    params = mf.MudParameters.from_water_content(0.25)
    contact = MudContact3D(params, SOLE)
    _settled(contact, 0.01, steps=5)
    saved = contact.state
    for position, quaternion, dt, match in (
        ([0.0, math.nan, -0.01], UPRIGHT, 0.01, "position"),
        ([0.0, 0.0, -0.01], [2.0, 0.0, 0.0, 0.0], 0.01, "norm 1"),
        ([0.0, 0.0, -0.01], [1.0, 0.0, math.inf, 0.0], 0.01, "quaternion"),
        ([0.0, 0.0, -0.01], UPRIGHT, 0.0, "dt"),
        # a Python int beyond float64: OverflowError from float(dt)
        ([0.0, 0.0, -0.01], UPRIGHT, 10**400, r"dt must be within \[1e-09, 1000\] s after the first step, got an "),
        ([0.0, 0.0, -0.01], UPRIGHT, 10**5000, "got an integer of 16610 bits"),
        ([0.0, 0.0, -200.0], UPRIGHT, 0.01, "depth"),
        ([0.0, 0.0], UPRIGHT, 0.01, "position"),
        # the pose's repr in the message: over lines for a 2-D array, ValueError (4300 digits) for 10**5000
        (np.zeros((4, 4)), UPRIGHT, 0.01, r"position must be 3 finite numbers \[m\], got shape \(4, 4\)$"),
        ([0.0, 0.0, 10**5000], UPRIGHT, 0.01, r"position must be 3 real numbers \[m\], got object values"),
        ([0.0, 0.0, -0.01], np.eye(4), 0.01, r"quaternion must be 4 finite numbers \(w, x, y, z\), got shape"),
        ([0.0, 0.0, -0.01], [1e200, 0.0, 0.0, 0.0], 0.01, "got norm inf"),  # with numpy's overflow warning
    ):
        with pytest.raises(InputError, match=match) as info, warnings.catch_warnings():
            warnings.simplefilter("error")
            contact.step(position, quaternion, dt)
        assert "\n" not in str(info.value)
        after = contact.state
        np.testing.assert_array_equal(after.elements, saved.elements)
        np.testing.assert_array_equal(after.slip, saved.slip)
        np.testing.assert_array_equal(after.centroids, saved.centroids)
    with pytest.raises(InputError, match="width"):
        MudContact3D(params, shapes.Shape(SOLE.centroids, SOLE.normals, SOLE.areas))
    with pytest.raises(InputError, match="Shape"):
        MudContact3D(params, mf.Foot.paper())  # type: ignore[arg-type]


def test_state_restores_and_replays_bit_for_bit() -> None:
    params = mf.MudParameters.from_water_content(0.30)
    contact = MudContact3D(params, SPHERE)
    _settled(contact, 0.02, steps=10)
    saved = contact.state
    path = [([j * 1e-4, -j * 5e-5, -0.02 + j * 1e-4], UPRIGHT) for j in range(1, 60)]
    first = [contact.step(p, q, 0.01) for p, q in path]
    contact.state = saved
    again = [contact.step(p, q, 0.01) for p, q in path]
    for a, b in zip(first, again, strict=True):
        np.testing.assert_array_equal(a.force, b.force)
        np.testing.assert_array_equal(a.torque, b.torque)


def test_a_reset_clears_the_element_forces_as_a_new_contact_has_them() -> None:
    """After reset() element_forces still held the last step's (a 40 mm sphere at 10 mm: Fz summing to 13.6 N), as
    MudContact.last did before 754f9f7; now zeros, as a new contact's, and a kept array keeps its values."""
    contact = MudContact3D(mf.MudParameters.from_water_content(0.25), SPHERE)
    contact.step([0.0, 0.0, 0.02], UPRIGHT, 0.0)
    contact.step([0.0, 0.0, 0.01], UPRIGHT, 0.01)
    kept = contact.element_forces
    total = float(kept[:, 2].sum())
    assert total > 1.0
    contact.reset()
    assert contact.element_forces.shape == (SPHERE.n, 3) and not contact.element_forces.any()
    assert float(kept[:, 2].sum()) == total


@pytest.mark.parametrize("many", [False, True])
def test_a_restore_replays_bit_for_bit_when_the_step_length_wavers_in_its_last_bits(many: bool) -> None:
    # steps of k/rate at t ~ 1000 s differ in their last bits; the restore dropped the step-length cache, so the
    # replay's was for another length than the first run's (forces off by ~1e-10 N)
    t = 1000.0 + np.arange(700) / 300.0
    z = -0.01 - 0.01 * np.sin(3.0 * t)
    dts = np.diff(t)
    k0 = 1 + int(np.flatnonzero(dts[400:] != dts[0])[0]) + 400
    params = mf.MudParameters.from_water_content(0.25)
    if many:
        feet = mf.MudContacts3D(params, SPHERE, n=1)

        def step(k: int, dt: float) -> np.ndarray:
            return np.hstack(feet.step(np.array([[0.0, 0.0, z[k]]]), np.array([UPRIGHT]), dt))
    else:
        foot = MudContact3D(params, SPHERE)

        def step(k: int, dt: float) -> np.ndarray:
            w = foot.step([0.0, 0.0, z[k]], UPRIGHT, dt)
            return np.hstack((w.force, w.torque))
    contact = feet if many else foot
    step(0, 0.01)
    for k in range(1, k0):
        step(k, float(dts[k - 1]))
    saved = contact.state
    first = np.array([step(k, float(dts[k - 1])) for k in range(k0, t.size)])
    contact.state = saved  # type: ignore[assignment]
    again = np.array([step(k, float(dts[k - 1])) for k in range(k0, t.size)])
    assert first.tobytes() == again.tobytes()


def test_an_element_on_the_axis_of_a_turn_stays_at_rest() -> None:
    """Turning about an axis through an element moves it by rounding only (~1e-18 m): it keeps its branch.

    Without law3d.settle_depth the element's depth jitters by 1.7e-18 m and the paper's sign rule sends it
    to the withdrawal branch on some steps, dropping the nonlinear spring.
    """
    params = mf.MudParameters.from_water_content(0.25)
    rng = np.random.default_rng(0)
    for _ in range(3):  # the third of these axes rounds (found by search)
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        radius = rng.uniform(0.005, 0.03)
    centroids = np.array([radius * axis, [-0.01, 0.01, 0.0], [0.01, -0.01, 0.0]])
    shape = shapes.Shape(centroids, np.tile([0.0, 0.0, -1.0], (3, 1)), np.full(3, 1e-4), width=0.03)
    turned = MudContact3D(params, shape)
    still = MudContact3D(params, shape)
    _settled(turned, 0.01, steps=10)
    _settled(still, 0.01, steps=10)
    jitter = []
    for k in range(1, 200):
        angle = 0.3 * math.sin(0.1 * k)
        quat = [math.cos(angle / 2), *(math.sin(angle / 2) * axis)]
        rotated = law3d.rotation_matrix(quat) @ centroids[0]
        jitter.append(float(rotated[2] - centroids[0, 2]))
        turned.step([0.0, 0.0, -0.01], quat, 0.01)
        still.step([0.0, 0.0, -0.01], UPRIGHT, 0.01)
        assert turned.modes[0] == still.modes[0] == "CONTACT"
        normals = turned.shape.normals @ law3d.rotation_matrix(quat).T
        stress = turned.element_forces[0, 2] / law3d.vertical_weight(normals[:, 2])[0]
        assert stress == pytest.approx(still.element_forces[0, 2], rel=1e-12)
    assert max(map(abs, jitter)) > 0.0  # the rounding is there


def test_many_feet_settle_an_element_turned_about_as_one_foot_does() -> None:
    """MudContacts3D's compiled step applies the same rounding rule (law3d.settle_depth) as MudContact3D."""
    params = mf.MudParameters.from_water_content(0.25)
    rng = np.random.default_rng(0)
    for _ in range(3):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        radius = rng.uniform(0.005, 0.03)
    centroids = np.array([radius * axis, [-0.01, 0.01, 0.0], [0.01, -0.01, 0.0]])
    shape = shapes.Shape(centroids, np.tile([0.0, 0.0, -1.0], (3, 1)), np.full(3, 1e-4), width=0.03)
    one = MudContact3D(params, shape)
    many = mf.MudContacts3D(params, shape, 1)
    poses = [([0.0, 0.0, -k * 1e-4], UPRIGHT) for k in range(101)]
    for k in range(1, 150):
        angle = 0.3 * math.sin(0.1 * k)
        poses.append(([0.0, 0.0, -0.01], [math.cos(angle / 2), *(math.sin(angle / 2) * axis)]))
    for k, (position, quat) in enumerate(poses):
        w = one.step(position, quat, 0.01 if k else 0.0)
        forces, _ = many.step(np.array([position]), np.array([quat]), 0.01 if k else 0.0)
        assert forces[0] == pytest.approx(w.force, rel=1e-12, abs=1e-12)


def test_the_compiled_step_is_the_numpy_step_bit_for_bit_and_refuses_as_it_does() -> None:
    """MudContact3D.step runs float64 poses through MudContacts3D's compiled step (step3d.step_feet): every wrench,
    element force and state equals the numpy step's (its reference, _step_numpy) to the bit, through first steps, a
    reset, a restored state and uneven dt; a bad pose, a zero dt or a depth out of bounds given as float64
    arrays (the compiled step's own checks) is refused with the numpy step's error, changing nothing."""
    params = mf.MudParameters.from_water_content(0.25)
    for shape in (SPHERE, SOLE):
        fast, slow = MudContact3D(params, shape, 0.002), MudContact3D(params, shape, 0.002)
        peak = sideways = 0.0
        for k in range(120):
            if k == 70:
                fast.reset()
                slow.reset()
            if k == 90:
                fast.state = slow.state
            tilt = 0.3 * math.sin(k / 15)
            position = np.array([0.02 * math.sin(k / 20), 0.001 * k, 0.01 - 0.025 * math.sin(k / 25)])
            quaternion = np.array([math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0])
            dt = 1e-3 * (1.5 if k % 4 == 0 else 1.0)
            a = fast.step(position, quaternion, dt)
            b = slow._step_numpy(position, quaternion, dt)
            assert np.array_equal(a.force, b.force) and np.array_equal(a.torque, b.torque)
            assert np.array_equal(fast.element_forces, slow.element_forces)
            for x, y in zip(fast.state, slow.state, strict=True):
                assert np.array_equal(x, y)
            peak = max(peak, a.force[2])
            sideways = max(sideways, np.abs(fast.element_forces[:, :2]).max())
        assert fast._fixed is not None  # the compiled step was taken
        assert peak > 1.0 and sideways > 0.0  # in the mud, sliding
    saved, forces = fast.state, fast.element_forces
    down = np.array([0.0, 0.0, -0.01])
    for position, quaternion, dt, match in (
        (np.array([0.0, math.nan, -0.01]), UPRIGHT, 0.01, "position"),
        (down, np.array([1.001, 0.0, 0.0, 0.0]), 0.01, "norm 1"),
        (down, np.array([1.0, 0.0, math.inf, 0.0]), 0.01, "quaternion"),
        (down, UPRIGHT, 0.0, "dt"),
        (np.array([0.0, 0.0, -200.0]), UPRIGHT, 0.01, "depth"),
        (np.zeros(2), UPRIGHT, 0.01, "position"),
        (down, UPRIGHT[:3], 0.01, "quaternion"),
    ):
        with pytest.raises(InputError, match=match):
            fast.step(position, quaternion, dt)
        for x, y in zip(fast.state, saved, strict=True):
            assert np.array_equal(x, y)
        assert fast.element_forces is forces


def test_poses_of_any_layout_and_type_step_as_the_numpy_step() -> None:
    """MudContact3D.step's hot path (step3d.step_one through its entry point, which takes float64 vectors of any
    strides) and its conversions: a pose given as a strided view, a read-only array, a column of a Fortran array,
    float32, int or big-endian arrays, an offset view or lists steps as the numpy step does, bit for bit, step after
    step; a pose of the wrong length or dimensions (a (1, 3) position too) is refused with its error and changes
    nothing."""
    params = mf.MudParameters.from_water_content(0.25)
    fast, slow = MudContact3D(params, SPHERE), MudContact3D(params, SPHERE)
    table = np.asfortranarray(np.zeros((3, 4)))

    def forms(position: np.ndarray, quaternion: np.ndarray, k: int) -> tuple[object, object]:
        wide = np.zeros((3, 2))
        wide[:, 0] = position
        frozen = quaternion.copy()
        frozen.flags.writeable = False
        table[:, 1] = position
        kind = k % 7
        if kind == 0:
            return wide[:, 0], frozen  # strided, read-only
        if kind == 1:
            return table[:, 1], quaternion.astype(">f8")  # a Fortran column (contiguous), big-endian
        if kind == 2:
            return position.astype(np.float32).astype(np.float64)[::1], quaternion.tolist()
        if kind == 3:
            return np.concatenate(([7.0], position))[1:], quaternion  # an offset view
        if kind == 4:
            return position.tolist(), quaternion[::-1][::-1]  # a reversed view reversed again: strides -8 then 8
        if kind == 5:
            return position, np.array([1, 0, 0, 0])  # int
        return position, quaternion

    for k in range(60):
        tilt = 0.2 * math.sin(k / 9)
        position = np.array([0.001 * k, 0.0005 * k, 0.012 - 0.0006 * k])
        quaternion = np.array([math.cos(tilt / 2), 0.0, math.sin(tilt / 2), 0.0])
        p, q = forms(position, quaternion, k)
        a = fast.step(p, q, 1e-3)
        b = slow._step_numpy(p, q, 1e-3)
        assert np.array_equal(a.force, b.force) and np.array_equal(a.torque, b.torque)
        assert np.array_equal(fast.element_forces, slow.element_forces)
    assert fast._entry is not None and a.force[2] > 0.0  # the entry point was taken, in the mud
    saved = fast.state
    for p, q, match in ((np.zeros(4), UPRIGHT, "position"), (np.zeros((3, 1)), UPRIGHT, "position"),
                        (np.zeros((1, 3)), UPRIGHT, "position"),
                        (np.zeros(3), np.zeros((4, 1)), "quaternion"), (np.zeros(3)[::2], UPRIGHT, "position")):
        with pytest.raises(InputError, match=match):
            fast.step(p, q, 1e-3)
        for x, y in zip(fast.state, saved, strict=True):
            assert np.array_equal(x, y)


def test_elements_with_caches_of_other_step_lengths_step_as_the_numpy_step() -> None:
    """The compiled step keeps one step-length cache per lane block and sends an element whose own cache is for
    another step length through the state machine: a state whose elements were stepped with two step lengths
    (half of them from another history) steps as the numpy step does, bit for bit, at either length, then a
    third."""
    params = mf.MudParameters.from_water_content(0.25)
    a, b = MudContact3D(params, SPHERE), MudContact3D(params, SPHERE)
    for k in range(30):
        position = np.array([0.0005 * k, 0.0, 0.01 - 0.0007 * k])
        a.step(position, UPRIGHT, 1e-3 if k else 0.0)
        b.step(position, UPRIGHT, 1.5e-3 if k else 0.0)
    mixed = a.state
    elements = mixed.elements.copy()
    elements[::2] = b.state.elements[::2]  # every other element's state and cache from the other history
    mixed = mixed._replace(elements=elements)
    fast, slow = MudContact3D(params, SPHERE), MudContact3D(params, SPHERE)
    fast.state = mixed
    slow.state = mixed
    for k in range(30, 60):
        position = np.array([0.0005 * k, 0.0002 * (k - 30), 0.01 - 0.0007 * k])
        dt = 1e-3 if k < 45 else 1.5e-3 if k < 55 else 2e-3  # the first step of each length: caches differ
        w, v = fast.step(position, UPRIGHT, dt), slow._step_numpy(position, UPRIGHT, dt)
        assert np.array_equal(w.force, v.force) and np.array_equal(w.torque, v.torque)
        for x, y in zip(fast.state, slow.state, strict=True):
            assert np.array_equal(x, y)
    assert w.force[2] > 1.0


def test_the_bearing_scale_scales_the_bearing_on_every_path() -> None:
    """bearing_scale multiplies the sideways bearing (law3d.bearing_stress): the compiled step equals the numpy step
    bit for bit at 0.3, MudContacts3D with a scale per foot equals MudContact3D, a sphere slid sideways meets less
    resistance at 0.3 than at 1 and more than the shear alone (0), the vertical force is the same at all three, and a
    scale out of [0, 1e3] or not a number is refused in one line."""
    params = mf.MudParameters.from_water_content(0.25)
    scales = (0.0, 0.3, 1.0)
    fast = [MudContact3D(params, SPHERE, bearing_scale=b) for b in scales]
    slow = MudContact3D(params, SPHERE, bearing_scale=0.3)
    many = mf.MudContacts3D(params, SPHERE, 3, bearing_scale=list(scales))
    sideways = np.zeros(3)
    for k in range(80):
        position = np.array([0.0004 * max(k - 20, 0), 0.0, 0.01 - 0.0008 * min(k, 25)])
        got = [c.step(position, UPRIGHT, 1e-3 if k else 0.0) for c in fast]
        b = slow._step_numpy(position, UPRIGHT, 1e-3 if k else 0.0)
        assert np.array_equal(got[1].force, b.force) and np.array_equal(got[1].torque, b.torque)
        forces, torques = many.step(np.tile(position, (3, 1)), np.tile(UPRIGHT, (3, 1)), 1e-3 if k else 0.0)
        for f in range(3):
            assert np.array_equal(forces[f], got[f].force) and np.array_equal(torques[f], got[f].torque)
        assert got[0].force[2] == got[1].force[2] == got[2].force[2]
        sideways = np.maximum(sideways, [-w.force[0] for w in got])
    assert 0.0 < sideways[0] < sideways[1] < sideways[2]
    assert fast[1].bearing_scale == 0.3
    for bad in (-0.1, 2e3, math.nan, "1"):
        with pytest.raises(InputError, match=r"^bearing_scale must be within \[0, 1000\]") as err:
            MudContact3D(params, SPHERE, bearing_scale=bad)  # type: ignore[arg-type]
        assert "\n" not in str(err.value)


def test_the_outputs_are_reused_only_when_no_one_holds_them() -> None:
    """MudContact3D.step's hot path reuses its output arrays (two sets in turn) only while no one holds any part
    of a set: a loop that keeps each Wrench until the next step makes no new arrays, and every result kept (the
    Wrench, its force, a view of its torque's block, the element forces or a column of them, every Wrench of
    several steps) keeps its values, which are the numpy step's, bit for bit; once the kept results are let go,
    the sets are reused again."""
    params = mf.MudParameters.from_water_content(0.25)
    fast, slow = MudContact3D(params, SPHERE), MudContact3D(params, SPHERE)
    kept: list[tuple[np.ndarray, np.ndarray]] = []
    seen: list[int] = []
    w = None
    for k in range(16):
        position = np.array([0.001 * k, 0.0, 0.01 - 0.002 * k])
        w = fast.step(position, UPRIGHT, 1e-3)
        b = slow._step_numpy(position, UPRIGHT, 1e-3)
        assert np.array_equal(w.force, b.force) and np.array_equal(w.torque, b.torque)
        assert np.array_equal(fast.element_forces, slow.element_forces)
        seen.append(id(w))
        held = {9: w.force, 10: w.torque.base[1:], 11: fast.element_forces, 12: fast.element_forces[:, 2]}.get(k)
        if held is not None:
            kept.append((held, held.copy()))
    every = []  # then every Wrench kept (new outputs each step), then let go, and held to the next step again
    for k in range(16, 90):
        position = np.array([0.0005 * k, 0.0, 0.01 - 0.0005 * k])
        w = fast.step(position, UPRIGHT, 1e-3)
        b = slow._step_numpy(position, UPRIGHT, 1e-3)
        assert np.array_equal(w.force, b.force) and np.array_equal(fast.element_forces, slow.element_forces)
        seen.append(id(w))
        if k < 24:
            every.append((w, b, fast.element_forces))
        elif k == 24:
            for a, c, forces in every:
                assert np.array_equal(a.force, c.force) and np.array_equal(a.torque, c.torque)
                assert forces.shape == (SPHERE.n, 3) and forces[:, 2].sum() == pytest.approx(a.force[2], rel=1e-9)
            every.clear()
    assert len(set(seen[2:9])) == 2  # w held from one step to the next: the two sets in turn, nothing new made
    assert len(set(seen[9:16])) > 2  # results kept: new outputs
    assert len(set(seen[-8:])) == 2  # reused again (a new set every 32 steps while none is free)
    for array, values in kept:
        assert np.array_equal(array, values)
    assert w is not None and w.force[2] > 0.0  # in the mud


def test_the_compiled_step_is_the_many_feet_step_and_compiles_nothing_of_its_own() -> None:
    """MudContact3D's compiled step is MudContacts3D's compiled code (one compile for both): once a MudContacts3D
    has stepped, a MudContact3D's steps add no compiled version; it takes the compiled step from its first step
    on, for lists and a numpy scalar dt too (converted as the numpy step converts them)."""
    from mudforce._kernel import step3d

    params = mf.MudParameters.from_water_content(0.25)
    many = mf.MudContacts3D(params, SPHERE, 1)
    many.step(np.array([[0.0, 0.0, 0.01]]), UPRIGHT[None], 0.0)
    compiled = len(step3d.step_feet.overloads)
    one = MudContact3D(params, SPHERE)
    numpy_steps = []
    reference = one._step_numpy

    def counted(*args: object) -> object:
        numpy_steps.append(1)
        return reference(*args)

    one._step_numpy = counted  # type: ignore[method-assign]
    for k in range(4):
        one.step(np.array([0.0, 0.0, 0.01 - 0.004 * k]), UPRIGHT, 1e-3)
    one.step([0.0, 0.001, -0.007], UPRIGHT.tolist(), np.float64(1e-3))
    assert not numpy_steps and len(step3d.step_feet.overloads) == compiled
    assert one.element_forces.shape == (SPHERE.n, 3) and one.element_forces[:, 2].sum() > 0.0


def test_a_foot_beyond_the_depth_bound_is_refused_in_the_words_of_one_foot() -> None:
    """One foot far below (or above) the surface is refused naming the foot's position, not "depth of foot 94"
    (the elements' own stepper, where each element is a "foot"), and nothing moves."""
    contact = MudContact3D(mf.MudParameters.from_water_content(0.25), SPHERE)
    _settled(contact, 0.01, steps=3)
    saved = contact.state
    for z in (-100.0, -1e4, 1e300):
        for position in ([0.0, 0.0, z], np.array([0.0, 0.0, z])):
            with pytest.raises(InputError) as info:
                contact.step(position, UPRIGHT, 0.01)
            text = str(info.value)
            assert re.fullmatch(r"element \d+ would be at depth \S+ m, beyond \+-100 m of the surface "
                                r"\(position \[0\.0, 0\.0, \S+\] \[m\]\); the foot was not stepped", text), text
            after = contact.state
            np.testing.assert_array_equal(after.elements, saved.elements)
            np.testing.assert_array_equal(after.centroids, saved.centroids)


def test_a_mangled_state_is_refused_in_one_line_and_changes_nothing() -> None:
    """A saved state whose slips or centroids are not real numbers, or whose ``started`` is not a bool, is refused
    with a one-line InputError (not numpy's ValueError or TypeError, nor complex numbers cut to their real part,
    nor "no" read as True), and the contact is left as it was."""
    contact = MudContact3D(mf.MudParameters.from_water_content(0.25), SPHERE)
    _settled(contact, 0.01, steps=3)
    saved = contact.state
    n = SPHERE.n
    for change, match in (
        ({"slip": "abc"}, "slips must be an array of real numbers"),
        ({"slip": saved.slip + 1e-9j}, "slips must be an array of real numbers .*complex"),
        ({"centroids": [[object()] * 3] * n}, "centroids must be an array of real numbers"),
        ({"started": np.array([True, False])}, "started must be True or False"),
        ({"started": "no"}, "started must be True or False"),
        ({"started": None}, "started must be True or False"),
    ):
        with pytest.raises(InputError, match=match) as info:
            contact.state = saved._replace(**change)
        assert "\n" not in str(info.value)
        for x, y in zip(contact.state, saved, strict=True):
            assert np.array_equal(x, y)
    contact.state = saved._replace(started=np.bool_(True))  # numpy's bool is a bool
    contact.state = saved._replace(slip=saved.slip.tolist(), centroids=saved.centroids.tolist())  # lists of numbers
    assert np.array_equal(contact.state.slip, saved.slip) and np.array_equal(contact.state.centroids, saved.centroids)


def test_simulate_3d_names_the_sample_a_bad_input_is_at() -> None:
    """simulate_3d refuses a bad time, step, position or quaternion naming the sample (in simulate's words: the one
    check_times of _kernel.bounds words both), not in
    the words of a single step (\"dt must be within ... after the first step\") that leave the row to be guessed;
    and a time beyond +-1e9 s, where a millisecond step would lose its digits, is refused as simulate refuses it."""
    params = mf.MudParameters.from_water_content(0.25)
    m = 12
    t = np.arange(m) * 0.01
    pos, quat = _vertical(np.linspace(-0.02, 0.01, m))
    bad_pos, bad_quat = pos.copy(), quat.copy()
    bad_pos[7, 1] = math.nan
    bad_quat[4] = [2.0, 0.0, 0.0, 0.0]
    for call, message in (
        (lambda: simulate_3d(np.where(np.arange(m) == 3, t[2], t), pos, quat, params, SPHERE),
         "time repeats at sample 3 (0.02 s then 0.02 s); expected strictly increasing time"),
        (lambda: simulate_3d(t[::-1], pos, quat, params, SPHERE), "time goes backwards at sample 1 (0.11 s then 0.1"),
        (lambda: simulate_3d(t * 1e-8, pos, quat, params, SPHERE),
         "the time step before sample 1 (t = 1e-10 s) is 1e-10 s; expected steps within [1e-09, 1000] s"),
        (lambda: simulate_3d(np.where(np.arange(m) == 5, math.nan, t), pos, quat, params, SPHERE),
         "time is not finite at sample 5 (nan); expected numbers [s]"),
        (lambda: simulate_3d(t + 1e12, pos, quat, params, SPHERE), "time at sample 0 (1000000000000.0 s) is beyond "
         "+-1e+09 s"),
        (lambda: simulate_3d(t, bad_pos, quat, params, SPHERE), "sample 7 (t = 0.07 s): position must be 3 finite"),
        (lambda: simulate_3d(t, pos, bad_quat, params, SPHERE), "sample 4 (t = 0.04 s): a quaternion must have norm 1"),
        # no sample: it said they "must agree" (they did)
        (lambda: simulate_3d([], np.zeros((0, 3)), np.zeros((0, 4)), params, SPHERE), "the motion is empty"),
    ):
        with pytest.raises(InputError) as info:
            call()
        assert str(info.value).startswith(message), str(info.value)
        assert "\n" not in str(info.value)
    ok = simulate_3d(t + 1e9 - 1.0, pos, quat, params, SPHERE)  # up to the bound: as from 0
    np.testing.assert_allclose(ok.force, simulate_3d(t, pos, quat, params, SPHERE).force, rtol=1e-6, atol=1e-9)


def test_quaternions_in_ros_order_are_warned_of() -> None:
    """An upright foot's quaternions in ROS's and scipy's (x, y, z, w) order, (0, 0, 0, 1) or (0, 0, sin, cos) for a
    yaw, read as (w, x, y, z) are half turns: a sole yawed 0.7 rad so given peaked at 44.6 N instead of 59.5 N at
    25 % (tilted 40 degrees), silently. Now a warning when every pose is one (w within +-0.1); valid poses are not
    warned of, and the result is the same bits as before."""
    params = mf.MudParameters.from_water_content(0.25)
    t = np.arange(4) * 0.01
    pos, upright = _vertical(np.array([-0.002, 0.004, 0.008, 0.004]))
    yaw = 0.7
    ros = np.tile([0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)], (4, 1))
    with pytest.warns(RuntimeWarning, match=r"every quaternion has w = q\[0\] within \+-0\.1 .*give \(w, x, y, z\)"):
        given = simulate_3d(t, pos, ros, params, SPHERE)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        near = np.tile([0.11, 0.0, 0.0, math.sqrt(1.0 - 0.11**2)], (4, 1))  # just beyond the band
        for quat in (upright, np.roll(ros, 1, axis=1), -upright, near):
            simulate_3d(t, pos, quat, params, SPHERE)
        with pytest.raises(InputError, match="norm 1"):  # refused, not warned of
            simulate_3d(t, pos, np.zeros((4, 4)), params, SPHERE)
    contact = MudContact3D(params, SPHERE)
    for k in range(4):  # the warning changes nothing: the steps' bits
        wrench = contact.step(pos[k], ros[k], float(t[k] - t[k - 1]) if k else 0.0)
        assert np.array_equal(wrench.force, given.force[k]) and np.array_equal(wrench.torque, given.torque[k])


def test_a_bad_element_state_is_refused_in_elements_words() -> None:
    """A saved state whose element rows are bad is refused naming the element (a single 3-D contact has one foot,
    so "a state (foot 3)" from the elements' 1-D stepper misled), and a wrong number of element rows is refused
    for this contact's elements, not as "a state of 188 feet"; the contact is left as it was."""
    contact = MudContact3D(mf.MudParameters.from_water_content(0.25), SPHERE)
    _settled(contact, 0.01, steps=3)
    saved = contact.state
    n = SPHERE.n
    bad = np.array(saved.elements)
    bad[3, 0] = math.nan
    for elements, message in (
        (bad, "a state (element 3): holds a value that is not finite"),
        (saved.elements[:2], f"a state of this {n}-element foot has element states of shape ({n}, "),
        ("x", "a state's elements must be an array of real numbers"),
    ):
        with pytest.raises(InputError) as info:
            contact.state = saved._replace(elements=elements)
        text = str(info.value)
        assert text.startswith(message), text
        assert "foot 3" not in text and " feet" not in text and "\n" not in text
        for x, y in zip(contact.state, saved, strict=True):
            assert np.array_equal(x, y)


def test_simulate_3d_refuses_element_forces_that_would_not_fit_in_memory() -> None:
    """elements=True for 37 623 samples of a 5 316-element foot asked numpy for 4.8 GB at once (a MemoryError
    traceback, or swap); refused in one line before any step, and the same motion without elements runs."""
    shape = shapes.sphere(0.1, resolution=0.0025)
    m = MAX_ELEMENT_SAMPLES // shape.n + 1
    time = np.arange(m) * 1e-3
    positions = np.broadcast_to([0.0, 0.0, 0.2], (m, 3))
    quaternions = np.broadcast_to([1.0, 0.0, 0.0, 0.0], (m, 4))
    mud = mf.MudParameters.from_water_content(0.25)
    with pytest.raises(InputError, match=r"elements=True would keep .* element forces") as error:
        simulate_3d(time, positions, quaternions, mud, shape, elements=True)
    assert "\n" not in str(error.value)
    short = simulate_3d(time[:3], positions[:3], quaternions[:3], mud, shape, elements=True)
    assert short.element_forces is not None and short.element_forces.shape == (3, shape.n, 3)


@pytest.mark.parametrize(("width", "words"), [
    (True, "width must be a number [m], got bool"),
    ("3cm", "width must be a number [m], got str"),
    (1e-9, "width must be within [0.0001, 10] m, got 1e-09"),
])
def test_a_bad_width_is_refused_by_its_name(width: object, words: str) -> None:
    """Was refused as "foot width must be ...", a Foot's words, not the argument's (as surface_height's are)."""
    with pytest.raises(InputError) as info:
        MudContact3D(mf.MudParameters.from_water_content(0.25), SPHERE, width=width)  # type: ignore[arg-type]
    assert str(info.value) == words


@pytest.mark.parametrize(("position", "got"), [
    (np.array([0.0, 0.0, 1e-3j]), "complex values (dtype complex128)"),
    ([0.0, True, 0.0], "a sequence holding booleans (True/False among the numbers)"),
    (np.ma.masked_array([0.0, 0.0, -0.01], mask=[False, True, False]),
     "a masked array with 1 masked value(s); fill or drop them first"),
    ([[0.0], [0.0, -0.01]], "list"),
    (["0", "0", "0"], "string values (dtype <U1)"),
])
def test_a_position_that_is_not_real_numbers_is_refused_in_the_contacts_words(position: object, got: str) -> None:
    """The message was real_array's with its words before ", got " cut off and replaced (str(error).rpartition):
    real_array now takes the words, and the message is the same."""
    contact = MudContact3D(mf.MudParameters.from_water_content(0.25), SOLE)
    with pytest.raises(InputError, match=f"^{re.escape(f'position must be 3 real numbers [m], got {got}')}$"):
        contact.step(position, UPRIGHT, 0.01)
