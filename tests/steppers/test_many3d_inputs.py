"""MudContacts3D.step's two ways in: the hot path (float64 arrays of the right shapes, a float dt, checked cheaply)
and the path that converts or refuses everything else give the same bits, and a refusal on either changes nothing.
"""

from __future__ import annotations

import numpy as np
import pytest

import mudforce as mf
from mudforce.errors import InputError
from mudforce.model import shapes
from mudforce.steppers.contact3d import ContactState3D, ContactStates3D, MudContacts3D

SHAPE = shapes.sphere(0.03, resolution=0.015)
DT = 1e-3


def _same(a: ContactStates3D, b: ContactStates3D) -> bool:
    return all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))


def _poses(k: int) -> tuple[np.ndarray, np.ndarray]:
    """Two feet at step ``k``: going down into the mud and sliding, tilted: positions [m], quaternions."""
    pos = np.array([[0.001 * k, 0.0, 0.01 - 0.001 * k], [0.0, -0.0005 * k, 0.005 - 0.0008 * k]])
    tilt = 0.02 * k
    quat = np.array([[np.cos(tilt), np.sin(tilt), 0.0, 0.0], [np.cos(tilt), 0.0, 0.0, np.sin(tilt)]])
    return pos, quat


def test_both_ways_in_give_the_same_bits_and_refusals_change_nothing() -> None:
    mud = mf.MudParameters.from_water_content(0.25)
    hot, other = MudContacts3D(mud, SHAPE, 2), MudContacts3D(mud, SHAPE, 2)
    out = (np.empty((2, 3)), np.empty((2, 3)))
    for k in range(8):
        pos, quat = _poses(k)
        dt = DT if k else 0.0
        forces, torques = hot.step(pos, quat, dt, out=out)  # the hot path
        assert forces is out[0] and torques is out[1]
        # lists, a numpy scalar dt and fresh outputs: the converting path
        f2, t2 = other.step(pos.tolist(), [tuple(r) for r in quat], np.float64(dt))
        assert np.array_equal(forces, f2) and np.array_equal(torques, t2)
    assert np.abs(out[0][:, 2]).max() > 0.0  # in the mud
    assert _same(hot.state, other.state)
    saved = hot.state
    pos, quat = _poses(8)
    readonly = np.empty((2, 3))
    readonly.flags.writeable = False
    for p, q, dt, kwargs, match in (
        (pos[:1], quat, DT, {}, "positions must have shape"),
        (pos, np.zeros((2, 4)), DT, {}, "foot 0: .*quaternion"),
        (pos.astype(np.float32), quat.astype(np.float32) * 1.1, DT, {}, "foot 0: .*quaternion"),
        (pos, quat, 2e3, {}, "dt must be within"),
        (pos, quat, "1ms", {}, "dt must be a real number"),
        (pos, quat, DT, {"out": [out[0], out[1]]}, "out must be a tuple"),
        (pos, quat, DT, {"out": (out[0], readonly)}, "out must be a tuple"),
        (pos, quat, DT, {"out": (out[0], np.empty((3, 3)))}, "out must be a tuple"),
    ):
        with pytest.raises(InputError, match=match):
            hot.step(p, q, dt, **kwargs)
        assert _same(hot.state, saved)
    # and then the step as if nothing had been refused
    got = hot.step(pos, quat, DT, out=out)
    want = other.step(pos, quat, DT)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])


def test_any_layout_gives_the_same_bits_without_compiling_the_step_again() -> None:
    """Strided, Fortran-ordered and read-only poses and a strided out take the checked path (copied to the one
    layout the compiled step has), give the hot path's bits, and compile nothing; a refused hot step (NaN, a
    quaternion off unit norm, dt = 0) leaves the feet and the given out as they were."""
    from mudforce._kernel import step3d

    mud = mf.MudParameters.from_water_content(0.25)
    hot, other = MudContacts3D(mud, SHAPE, 2), MudContacts3D(mud, SHAPE, 2)
    out = (np.empty((2, 3)), np.empty((2, 3)))
    wide = (np.empty((2, 6)), np.empty((2, 6)))
    strided = (wide[0][:, ::2], wide[1][:, ::2])
    for k in range(6):
        pos, quat = _poses(k)
        dt = DT if k else 0.0
        hot.step(pos, quat, dt, out=out)
        compiled = len(step3d.step_feet.overloads)
        p = np.zeros((2, 6))
        p[:, ::2] = pos
        q = np.asfortranarray(quat)
        q.flags.writeable = False
        got = other.step(p[:, ::2], q, dt, out=strided)
        assert got[0] is strided[0] and got[1] is strided[1]
        assert np.array_equal(got[0], out[0]) and np.array_equal(got[1], out[1])
        assert len(step3d.step_feet.overloads) == compiled
    assert _same(hot.state, other.state)
    saved = hot.state
    kept = (out[0].copy(), out[1].copy())
    pos, quat = _poses(6)
    bad_pos = pos.copy()
    bad_pos[1, 2] = np.nan
    for p, q, dt, match in ((bad_pos, quat, DT, "foot 1: position"), (pos, quat * 1.001, DT, "foot 0: .*norm 1"),
                            (pos, quat, 0.0, "dt must be within")):
        with pytest.raises(InputError, match=match):
            hot.step(p, q, dt, out=out)
        assert _same(hot.state, saved)
        assert np.array_equal(out[0], kept[0]) and np.array_equal(out[1], kept[1])


def test_a_foot_at_the_depth_bound_is_checked_element_by_element() -> None:
    """A foot whose reach cannot settle the +-100 m bound at once (the check by the farthest centroid) has every
    element checked: refused when one element is beyond, as the elements' own depths say (law3d, numpy), stepped
    when all are within; a refusal changes nothing."""
    from mudforce._kernel.bounds import MAX_DEPTH
    from mudforce.model import law3d

    mud = mf.MudParameters.from_water_content(0.25)
    feet = MudContacts3D(mud, SHAPE, 1)
    upright = np.array([[1.0, 0.0, 0.0, 0.0]])
    r = tuple(law3d.rotation_matrix(upright[0]).ravel().tolist())
    _, _, oz = law3d.rotate(r, *SHAPE.centroids.T)
    stepped = refused = 0
    for k, z in enumerate((-99.97, -99.98, -99.99, -99.9999, 99.98, 99.99, 99.97)):
        pos = np.array([[0.0, 0.0, z]])
        within = bool(np.all(np.abs(law3d.element_depth(0.0, z, oz)) <= MAX_DEPTH))
        saved = feet.state
        if within:
            forces, _ = feet.step(pos, upright, DT if k else 0.0)
            assert np.all(np.isfinite(forces))
            stepped += 1
        else:
            with pytest.raises(InputError, match=r"foot 0: .*100 m"):
                feet.step(pos, upright, DT)
            assert _same(feet.state, saved)
            refused += 1
    assert stepped >= 2 and refused >= 2


def test_an_out_pair_of_one_array_is_refused_and_changes_nothing() -> None:
    """``out=(a, a)`` wrote the torques over the forces and returned them as both (found 2026-11-29)."""
    import pickle

    import mudforce as mf
    from mudforce.errors import InputError
    from mudforce.model import shapes

    feet = mf.MudContacts3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04), 2)
    up = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    feet.step(np.zeros((2, 3)), up, 0.0)
    before = pickle.dumps(feet.state)
    a = np.zeros((2, 3))
    base = np.zeros((3, 3))
    for pair in ((a, a), (base[:2], base[1:])):
        with pytest.raises(InputError, match="share memory"):
            feet.step(np.full((2, 3), -1e-3), up, 0.01, out=pair)
        assert pickle.dumps(feet.state) == before


def test_an_out_pair_of_one_block_s_column_halves_is_taken() -> None:
    """``out=(w[:, :3], w[:, 3:])`` of one (n, 6) wrench block was refused, "out's two arrays share memory", which
    they do not (np.may_share_memory compared their bounds); now the step writes into them what it returns alone."""
    import mudforce as mf
    from mudforce.model import shapes

    feet = mf.MudContacts3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04), 2)
    up = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    feet.step(np.zeros((2, 3)), up, 0.0)
    saved = feet.state
    forces, torques = (a.copy() for a in feet.step(np.full((2, 3), -1e-3), up, 0.01))
    feet.state = saved
    wrench = np.zeros((2, 6))
    got = feet.step(np.full((2, 3), -1e-3), up, 0.01, out=(wrench[:, :3], wrench[:, 3:]))
    assert got[0].base is wrench and got[1].base is wrench and forces[0, 2] > 0.0
    assert np.array_equal(wrench, np.hstack((forces, torques)))


def test_resetting_no_feet_is_allowed_and_changes_nothing() -> None:
    """``reset([])`` was refused as "got float64" (numpy's dtype of an empty list); it resets no foot."""
    import pickle

    import mudforce as mf
    from mudforce.model import shapes

    params = mf.MudParameters.from_water_content(0.25)
    up = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    feet3d = mf.MudContacts3D(params, shapes.sphere(0.04), 2)
    feet3d.step(np.zeros((2, 3)), up, 0.0)
    feet1d = mf.MudContacts(params, n=2)
    feet1d.step(np.zeros(2), 0.0)
    for feet in (feet3d, feet1d):
        before = pickle.dumps(feet.state)
        feet.reset([])
        assert pickle.dumps(feet.state) == before


def _three_steps() -> tuple[mf.MudContact3D, MudContacts3D]:
    """One foot and two, each stepped three times along :func:`_poses` (the first foot's poses for the one)."""
    mud = mf.MudParameters.from_water_content(0.25)
    one, many = mf.MudContact3D(mud, SHAPE), MudContacts3D(mud, SHAPE, 2)
    for k in range(3):
        pos, quat = _poses(k)
        one.step(pos[0], quat[0], DT if k else 0.0)
        many.step(pos, quat, DT if k else 0.0)
    return one, many


@pytest.mark.parametrize("bad", [[1e155, 0.0, 0.0], [0.0, -2e4, 0.0], [1e4 * (1 + 1e-15), 0.0, 0.0]])
def test_a_foot_beyond_the_horizontal_bound_is_refused_on_every_path_and_changes_nothing(bad: list[float]) -> None:
    """A body origin beyond +-1e4 m in x or y (the readers' bound) is refused, on the hot path and off it, for
    one foot and many: at x = 1e155 m the force was infinite and the moment NaN, and the next step inherited it."""
    one, many = _three_steps()
    saved_one, saved_many = one.state, many.state
    pos, quat = _poses(3)
    far = np.array(bad)
    for position in (far, far.tolist()):  # the hot path and the converting one
        with pytest.raises(InputError, match=r"x and y must be within \+-10000 m of the world origin"):
            one.step(position, quat[0], DT)
        assert _same_one(one.state, saved_one)
    with pytest.raises(InputError, match=r"foot 1: position x and y must be within \+-10000 m"):
        many.step(np.vstack([pos[0], far]), quat, DT)
    assert _same(many.state, saved_many)
    edge = np.array([1e4, -1e4, pos[0, 2]])  # on the bound: accepted, and finite
    wrench = mf.MudContact3D(one.params, SHAPE).step(edge, quat[0], 0.0)
    assert np.all(np.isfinite(wrench.force)) and np.all(np.isfinite(wrench.torque))


def _same_one(a: ContactState3D, b: ContactState3D) -> bool:
    return (np.array_equal(a.slip, b.slip) and np.array_equal(a.centroids, b.centroids) and a.started == b.started
            and all(np.array_equal(x, y) for x, y in zip(np.atleast_1d(a.elements), np.atleast_1d(b.elements),
                                                          strict=True)))


def test_complex_and_boolean_poses_are_refused_as_every_array_input_is() -> None:
    """Poses are real numbers: a complex array (whose imaginary part float64 would drop) or a boolean one is
    refused with the API's one line, for one foot, many feet and simulate_3d, and nothing moves."""
    mud = mf.MudParameters.from_water_content(0.25)
    one, many = mf.MudContact3D(mud, SHAPE), MudContacts3D(mud, SHAPE, 2)
    pos, quat = _poses(1)
    one.step(pos[0], quat[0], 0.0)
    many.step(pos, quat, 0.0)
    saved_one, saved_many = one.state, many.state
    cases = [(pos[0].astype(complex), quat[0], "position must be 3 real numbers"),
             (np.array([True, False, False]), quat[0], "position must be 3 real numbers"),
             (pos[0], quat[0].astype(complex), "quaternion must be an array of real numbers"),
             (pos[0], np.array([True, False, False, False]), "quaternion must be an array of real numbers")]
    for position, quaternion, message in cases:
        with pytest.raises(InputError, match=message):
            one.step(position, quaternion, DT)
        assert _same_one(one.state, saved_one)
    with pytest.raises(InputError, match="positions must be an array of real numbers"):
        many.step(pos.astype(complex), quat, DT)
    with pytest.raises(InputError, match="quaternions must be an array of real numbers"):
        many.step(pos, quat.astype(bool), DT)
    assert _same(many.state, saved_many)
    t = np.array([0.0, DT])
    with pytest.raises(InputError, match="positions must be an array of real numbers"):
        mf.simulate_3d(t, np.zeros((2, 3), dtype=complex), np.tile([1.0, 0, 0, 0], (2, 1)), mud, SHAPE)
    with pytest.raises(InputError, match="time must be an array of real numbers"):
        mf.simulate_3d(t.astype(bool), np.zeros((2, 3)), np.tile([1.0, 0, 0, 0], (2, 1)), mud, SHAPE)


def test_a_restored_state_no_step_could_leave_is_refused_and_changes_nothing() -> None:
    """Slips and centroids are checked for size as well as finiteness (1e200 passed before)."""
    one, many = _three_steps()
    saved_one, saved_many = one.state, many.state
    for field, value in (("centroids", 1e200), ("slip", 2e4), ("centroids", -1e4 - 1.0)):
        bad_one = saved_one._replace(**{field: getattr(saved_one, field) + value})
        with pytest.raises(InputError, match="a state's slips must be finite and within"):
            one.state = bad_one
        assert _same_one(one.state, saved_one)
        bad_many = saved_many._replace(**{field: getattr(saved_many, field) + value})
        with pytest.raises(InputError, match="a state's slips must be finite and within"):
            many.state = bad_many
        assert _same(many.state, saved_many)
    one.state = saved_one  # a state a step left is accepted
    many.state = saved_many


def test_a_restored_state_of_another_shape_is_refused_and_changes_nothing() -> None:
    """A state of a sphere twice as large (as many elements) was taken, its centroids and slips stepped with this
    sphere's elements; a state's world centroids are its shape's turned and moved (each step writes them all)."""
    one, many = _three_steps()
    saved_one, saved_many = one.state, many.state
    other = mf.MudContact3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.06, resolution=0.03))
    assert other.shape.n == SHAPE.n
    for k in range(3):
        pos, quat = _poses(k)
        other.step(pos[0], quat[0], DT if k else 0.0)
    words = r"^a state's centroids{} are not this foot's shape turned and moved: a state of another shape; expected"
    with pytest.raises(InputError, match=words.format("")):
        one.state = other.state
    assert _same_one(one.state, saved_one)
    centroids = saved_many.centroids.copy()
    centroids[many.element_slice(1)] = other.state.centroids
    with pytest.raises(InputError, match=words.format(r" \(foot 1\)")):
        many.state = saved_many._replace(centroids=centroids)
    assert _same(many.state, saved_many)
    one.reset()  # a foot that has not started holds no pose: any centroids
    fresh = one.state
    one.state = fresh._replace(centroids=other.state.centroids)


def test_lateral_stiffness_and_shapes_are_bounded() -> None:
    mud = mf.MudParameters.from_water_content(0.25)
    for k in (0.0, -1.0, 1e12 * (1 + 1e-15), 1e300, float("inf"), float("nan"), True, 10**5000):  # 10**5000: its
        # repr in the message raised ValueError (Exceeds the limit (4300 digits))
        with pytest.raises(InputError, match=r"lateral_stiffness must be within \(0, 1e\+12\] \[Pa/m\]"):
            mf.MudContact3D(mud, SHAPE, lateral_stiffness=k)
        with pytest.raises(InputError, match=r"lateral_stiffness must be (within \(0, 1e\+12\] \[Pa/m\]|a number)"):
            MudContacts3D(mud, SHAPE, 2, lateral_stiffness=k)
    mf.MudContact3D(mud, SHAPE, lateral_stiffness=1e12)
    up = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(InputError, match="shape centroids must be within 10 m of the body origin"):
        shapes.Shape(np.array([[0.0, 0.0, 10.5]]), up, np.array([1e-3]), closed=False)
    with pytest.raises(InputError, match=r"shape areas must be at most 100 m\^2 each, got 1000.0 at element 0"):
        shapes.Shape(np.array([[0.0, 0.0, 0.0]]), up, np.array([1e3]), closed=False)
    shapes.Shape(np.array([[0.0, 0.0, 10.0]]), up, np.array([100.0]), closed=False)  # on the bounds


def test_element_slice_takes_an_integer_foot_only() -> None:
    """A foot that is not an integer (a float, a string, None, a bool) is refused with a one-line InputError, not
    numpy's or int()'s ValueError/TypeError, nor 0.7 read as foot 0; integers (numpy's too, negative from the end)
    are taken."""
    feet = MudContacts3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04), 2)
    per = feet.n_elements // 2
    assert feet.element_slice(1) == slice(per, 2 * per) == feet.element_slice(np.int64(-1))
    for bad in (0.7, 1.0, "a", None, True):
        with pytest.raises(InputError, match=r"foot must be an integer index 0\.\.1, got ") as info:
            feet.element_slice(bad)
        assert "\n" not in str(info.value)
    with pytest.raises(InputError, match=r"foot index out of range 0\.\.1: 2"):
        feet.element_slice(2)


def test_a_bad_element_row_in_a_restored_state_names_the_element() -> None:
    """A state's element rows are elements (of all feet, concatenated), not feet: a bad row 5 was refused as
    "a state (foot 5)" for two feet; now "a state (element 5)", and nothing changes."""
    many = MudContacts3D(mf.MudParameters.from_water_content(0.25), SHAPE, 2)
    for k in range(3):
        many.step(*_poses(k), DT if k else 0.0)
    saved = many.state
    bad = np.array(saved.elements)
    bad[5, 0] = np.nan
    with pytest.raises(InputError) as info:
        many.state = saved._replace(elements=bad)
    assert str(info.value).startswith("a state (element 5): holds a value that is not finite"), str(info.value)
    assert _same(many.state, saved)


def test_a_ragged_started_in_a_restored_state_is_refused_in_one_line() -> None:
    """``started=[[True], [True, False]]`` raised numpy's ValueError ("inhomogeneous shape")."""
    feet = MudContacts3D(mf.MudParameters.from_water_content(0.25), SHAPE, 2)
    saved = feet.state
    with pytest.raises(InputError, match=r"a state's started must be an array of bool of shape \(2,\), got list"):
        feet.state = saved._replace(started=[[True], [True, False]])  # type: ignore[arg-type]
    assert _same(feet.state, saved)


def test_a_nested_list_of_feet_is_refused_in_one_line() -> None:
    """``reset([[0]])`` raised TypeError ("only 0-dimensional arrays can be converted to Python scalars")."""
    feet = MudContacts3D(mf.MudParameters.from_water_content(0.25), SHAPE, 2)
    feet.step(np.zeros((2, 3)), np.tile([1.0, 0.0, 0.0, 0.0], (2, 1)), 0.0)
    before = feet.state
    with pytest.raises(InputError, match=r"boolean mask of shape \(2,\), got an array of shape \(1, 1\)"):
        feet.reset([[0]])
    assert _same(feet.state, before)
    feet.reset([1])
    assert feet.state.started.tolist() == [True, False]


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"surface_heights": {0: 0.0, 1: 0.1}}, "surface_heights must be a number [m] or a sequence of them, one per "
                                             "foot, got dict"),  # its keys were the heights, 0 and 1 m
    ({"surface_heights": {0.0, 0.1}}, "surface_heights must be a number [m] or a sequence of them, one per foot, "
                                      "got set"),  # in the set's order, not the caller's
    ({"widths": {0.03: "a", 0.04: "b"}}, "widths must be a number [m] or a sequence of them, one per foot, got dict"),
    # a bad width was refused as "foot width must be ...", not naming the argument
    ({"widths": [True, 0.03]}, "widths must be a number [m], got bool"),
    ({"widths": [0.03, 1e-9]}, "widths must be within [0.0001, 10] m, got 1e-09"),
    ({"lateral_stiffness": frozenset({1e5, 2e5})}, "lateral_stiffness must be a number [Pa/m] or a sequence of "
                                                   "them, one per foot, got frozenset"),
    ({"params": {"mud": mf.MudParameters.from_water_content(0.25)}},
     "params must be a MudParameters or a sequence of them, one per foot, got dict"),
])
def test_per_foot_values_in_a_mapping_or_a_set_are_refused(kwargs: dict[str, object], words: str) -> None:
    args: dict[str, object] = {"params": mf.MudParameters.from_water_content(0.25), "shapes": SHAPE, "n": 2, **kwargs}
    with pytest.raises(InputError) as info:
        MudContacts3D(**args)  # type: ignore[arg-type]
    assert str(info.value) == words


def test_masked_poses_and_depths_are_read_as_every_other_array_input_reads_them() -> None:
    """errors.real_array's rule on the feet's hot paths: MudContacts3D stepped a masked position's masked value
    (numba's dispatcher takes a masked array as its data), and both it and MudContacts raised numba's own
    NumbaTypeError on a masked array before their first step; a masked value is refused, nothing moved, and a masked
    array without one is read as its data."""
    params = mf.MudParameters.from_water_content(0.25)
    upright = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    toes, feet = MudContacts3D(params, shapes.sphere(0.04), 2), mf.MudContacts(params, n=2)
    toes.step(np.ma.masked_array(np.zeros((2, 3))), upright, 0.0)  # no masked value: its data
    feet.step(np.ma.masked_array(np.zeros(2)), 0.0)
    before, before_1d = toes.state, feet.state
    message = r"must be an array of real numbers \[m\], got a masked array with 1 masked value\(s\)"
    with pytest.raises(InputError, match="^positions " + message):
        toes.step(np.ma.masked_array(np.full((2, 3), -0.01), mask=[[0, 0, 1], [0, 0, 0]]), upright, 0.01)
    with pytest.raises(InputError, match="^depths " + message):
        feet.step(np.ma.masked_array([0.01, 0.01], mask=[0, 1]), 0.01)
    assert np.array_equal(toes.state.elements, before.elements) and np.array_equal(feet.state, before_1d)
