"""mudforce.model.granular: Li et al.'s planar RFT and 3D-RFT per surface element, checked by values and symmetries."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.model import granular as G
from mudforce.model.baselines import branch_velocity, drft_force, granular_rft_force
from mudforce.model.foot import Foot

PI = math.pi
DOWN = [0.0, 0.0, -1.0]
UP = [0.0, 0.0, 1.0]
# the torch copy's disputed values (c2[16], c3[15], 0-based), rejected in the module docstring
TORCH_C2 = G.RFT3D_C2.copy()
TORCH_C2[16] = 0.18519
TORCH_C3 = G.RFT3D_C3.copy()
TORCH_C3[15] = -0.20770


def _random_elements(count: int, seed: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    normals = rng.normal(size=(count, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    centroids = rng.uniform(-0.05, 0.02, size=(count, 3))
    areas = rng.uniform(1e-5, 1e-4, size=count)
    velocities = rng.normal(scale=0.1, size=(count, 3))
    return centroids, normals, areas, velocities


def _rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# --- Li et al. 2013 ------------------------------------------------------------------------------------------------

def test_li_published_values_to_three_decimals() -> None:
    """The five values Li et al. give for the generic coefficients, and alpha_x = 0 for vertical motion."""
    cases = [((0.0, PI / 2), 1, 1.000), ((0.0, -PI / 2), 1, -0.250), ((PI / 2, 0.0), 0, 0.370),
             ((PI / 4, PI / 2), 1, 0.564), ((PI / 4, PI / 2), 0, 0.219), ((0.0, PI / 2), 0, 0.0),
             ((0.0, -PI / 2), 0, 0.0)]
    for (beta, gamma), component, expected in cases:
        assert round(float(G.rft_alpha(beta, gamma)[component]), 3) == expected, (beta, gamma, component)


def test_li_generic_coefficients_need_no_extra_scale() -> None:
    c = G.LI2013_GENERIC
    assert c.A00 + c.A10 + c.B01 + c.B11 + c.Bm11 == pytest.approx(1.0, abs=1e-12)


def test_li_out_of_range_angles_are_mirrored_and_periodic() -> None:
    beta = np.linspace(-PI / 2, PI / 2, 13)
    gamma = np.linspace(-PI / 2, PI / 2, 11)[:, None]
    ax, az = G.rft_alpha(beta, gamma)
    back_x, back_z = G.rft_alpha(-beta, PI - gamma)  # the same motion, mirrored x -> -x
    np.testing.assert_allclose(back_x, -ax, atol=1e-12)
    np.testing.assert_allclose(back_z, az, atol=1e-12)
    for shift in (PI, -PI):  # a plate has no side
        np.testing.assert_allclose(G.rft_alpha(beta + shift, gamma), (ax, az), atol=1e-12)
    np.testing.assert_allclose(G.rft_alpha(beta, gamma + 2 * PI), (ax, az), atol=1e-12)
    # straight down, alpha_x is odd and alpha_z even in beta
    down_x, down_z = G.rft_alpha(beta, PI / 2)
    np.testing.assert_allclose(down_x, -down_x[::-1], atol=1e-12)
    np.testing.assert_allclose(down_z, down_z[::-1], atol=1e-12)


def test_li_lower_face_leading_gets_more_lift_and_drag() -> None:
    """The sign convention of beta: the plate whose lower face leads a stroke is lifted and dragged more."""
    lead_x, lead_z = G.rft_alpha(PI / 4, 0.0)
    trail_x, trail_z = G.rft_alpha(-PI / 4, 0.0)
    assert (round(float(lead_z), 3), round(float(trail_z), 3)) == (0.363, 0.049)
    assert (round(float(lead_x), 3), round(float(trail_x), 3)) == (0.341, 0.165)


# --- 3D-RFT --------------------------------------------------------------------------------------------------------

def test_rft3d_coefficients_are_the_checked_copy_and_read_only() -> None:
    assert (G.RFT3D_C2[16], G.RFT3D_C3[15]) == (0.18589, -0.02730)
    assert all(c.shape == (20,) and not c.flags.writeable for c in (G.RFT3D_C1, G.RFT3D_C2, G.RFT3D_C3))


def test_rft3d_upward_facing_plate_pulled_up_is_resisted() -> None:
    """The sign test that decides c3[15]: the torch copy's value pushes the plate along its motion."""
    alpha = G.rft3d_alpha([UP], [[0.0, 0.0, 0.3]])
    assert alpha[0] == pytest.approx([0.0, 0.0, -0.07966], abs=1e-12)
    force = G.rft_element_forces([[0.0, 0.0, -0.02]], [UP], [1e-3], [[0.0, 0.0, 0.3]], scale=1e5)
    assert force[0] == pytest.approx([0.0, 0.0, -0.07966 * 1e5 * 0.02 * 1e-3], rel=1e-12)
    torch = G.rft3d_alpha([UP], [[0.0, 0.0, 0.3]], coefficients=(G.RFT3D_C1, TORCH_C2, TORCH_C3))
    assert torch[0, 2] == pytest.approx(0.10144, abs=1e-12)


def test_rft3d_positive_work_is_rare_and_small() -> None:
    """Over random leading elements the generic stress almost never pushes along the motion."""
    _, normals, _, velocities = _random_elements(20000, seed=3)
    velocities = np.where(np.einsum("ij,ij->i", normals, velocities)[:, None] < 0.0, -velocities, velocities)
    unit = velocities / np.linalg.norm(velocities, axis=1, keepdims=True)
    work = np.einsum("ij,ij->i", G.rft3d_alpha(normals, velocities), unit)
    assert (np.mean(work > 0.0) < 0.002, work.max() < 0.01) == (True, True)
    torch = np.einsum("ij,ij->i", G.rft3d_alpha(normals, velocities, (G.RFT3D_C1, TORCH_C2, TORCH_C3)), unit)
    assert (np.mean(torch > 0.0) > 0.005, torch.max() > 0.05) == (True, True)


def test_rft3d_frame_free_form_is_the_papers_local_frame() -> None:
    """alpha = f1 m + f2 v - f3 z equals alpha_r r + alpha_theta theta + alpha_z z, degenerate cases included."""
    _, normals, _, velocities = _random_elements(500, seed=1)
    special_n = [DOWN, UP, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.6, -0.8], [0.0, 0.6, -0.8], [0.6, 0.0, 0.8]]
    special_v = [[0, 0, -2.0], [0, 0, 3.0], [0, 0, -1.0], [1.0, 0, -1.0], [1.0, 0, -1.0], [0, 0, -1.0], [0, 0, 1.0]]
    n = np.vstack([normals, special_n])
    v = np.vstack([velocities, special_v])
    beta, gamma, psi = G.rft3d_angles(n, v)
    x1 = np.sin(gamma)
    x2 = np.cos(beta)
    x3 = np.cos(psi) * np.cos(gamma) * np.sin(beta) + np.sin(gamma) * np.cos(beta)
    basis = G.rft3d_basis(x1, x2, x3)
    f1, f2, f3 = basis @ G.RFT3D_C1, basis @ G.RFT3D_C2, basis @ G.RFT3D_C3
    a_r = f1 * np.sin(beta) * np.cos(psi) + f2 * np.cos(gamma)
    a_t = f1 * np.sin(beta) * np.sin(psi)
    a_z = -f1 * np.cos(beta) - f2 * np.sin(gamma) - f3
    unit = v / np.linalg.norm(v, axis=1, keepdims=True)
    horizontal = np.hypot(unit[:, 0], unit[:, 1]) > 1e-12
    r = np.where(horizontal[:, None], unit * [1, 1, 0], n * [1, 1, 0])
    r[np.linalg.norm(r, axis=1) < 1e-12] = [1.0, 0.0, 0.0]
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    theta = np.cross([0.0, 0.0, 1.0], r)
    framed = a_r[:, None] * r + a_t[:, None] * theta + a_z[:, None] * np.array(UP)
    np.testing.assert_allclose(G.rft3d_alpha(n, v), framed, atol=1e-12)
    assert np.all(np.abs(np.concatenate([beta, gamma, psi])) <= PI / 2 + 1e-12)


# --- element forces: reductions ------------------------------------------------------------------------------------

@pytest.mark.parametrize(("law", "alpha_down", "alpha_up"), [("li2013", 1.0, -0.25), ("rft3d", 0.87504, -0.07966)])
def test_horizontal_plate_down_and_up(law: str, alpha_down: float, alpha_up: float) -> None:
    """Sole pushed down: F_z = scale alpha_z(0, pi/2) |z| A; sole pulled up: trailing, 0; lid pulled up: resisted."""
    scale, depth, area = 2.0e5, 0.03, 2.5e-3
    centroid = [[0.01, -0.02, -depth]]
    down = G.rft_element_forces(centroid, [DOWN], [area], [[0.0, 0.0, -0.1]], scale=scale, law=law)
    np.testing.assert_allclose(down[0], [0.0, 0.0, scale * alpha_down * depth * area], rtol=1e-12, atol=1e-15)
    sole_up = G.rft_element_forces(centroid, [DOWN], [area], [[0.0, 0.0, 0.1]], scale=scale, law=law)
    assert np.all(sole_up == 0.0)
    lid_up = G.rft_element_forces(centroid, [UP], [area], [[0.0, 0.0, 0.1]], scale=scale, law=law)
    np.testing.assert_allclose(lid_up[0], [0.0, 0.0, scale * alpha_up * depth * area], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize(("law", "alpha"), [("li2013", [-0.370, 0.0, 0.037]), ("rft3d", [-0.22945, 0.0, 0.0887])])
def test_vertical_plate_moving_sideways(law: str, alpha: list[float]) -> None:
    forces = G.rft_element_forces([[0.0, 0.0, -0.05]], [[1.0, 0.0, 0.0]], [1e-3], [[0.2, 0.0, 0.0]], scale=1e5,
                                  law=law)
    np.testing.assert_allclose(forces[0], np.array(alpha) * 1e5 * 0.05 * 1e-3, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("law", G.LAWS)
def test_above_surface_trailing_or_at_rest_is_unloaded(law: str) -> None:
    centroids = [[0.0, 0.0, 0.011], [0.0, 0.0, 0.01], [0.0, 0.0, -0.02], [0.0, 0.0, -0.02]]
    normals = [DOWN, DOWN, UP, DOWN]
    velocities = [[0, 0, -1.0], [0, 0, -1.0], [0, 0, -1.0], [0, 0, 0.0]]
    forces = G.rft_element_forces(centroids, normals, [1e-3] * 4, velocities, 0.01, scale=1e5, law=law,
                                  inertial_drag=50.0)
    assert np.all(forces == 0.0)


@pytest.mark.parametrize("law", G.LAWS)
def test_yaw_rotation_and_mirror(law: str) -> None:
    centroids, normals, areas, velocities = _random_elements(300, seed=7)
    options = {"scale": 3e5, "law": law, "surface_friction": 0.4, "inertial_drag": 20.0}
    forces = G.rft_element_forces(centroids, normals, areas, velocities, 0.005, **options)
    assert np.count_nonzero(np.linalg.norm(forces, axis=1)) > 50
    for angle in (0.3, 2.0, -1.1):
        rot = _rotation_z(angle)
        turned = G.rft_element_forces(centroids @ rot.T, normals @ rot.T, areas, velocities @ rot.T, 0.005, **options)
        np.testing.assert_allclose(turned, forces @ rot.T, rtol=1e-9, atol=1e-12)
    mirror = np.diag([1.0, -1.0, 1.0])
    mirrored = G.rft_element_forces(centroids @ mirror, normals @ mirror, areas, velocities @ mirror, 0.005, **options)
    np.testing.assert_allclose(mirrored, forces @ mirror, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("law", G.LAWS)
def test_vectorised_equals_looped(law: str) -> None:
    centroids, normals, areas, velocities = _random_elements(40, seed=11)
    velocities[0] = [0.0, 0.0, -0.3]  # vertical motion
    normals[1] = DOWN
    options = {"scale": 1e5, "law": law, "surface_friction": 0.3, "inertial_drag": 10.0}
    together = G.rft_element_forces(centroids, normals, areas, velocities, **options)
    for i in range(len(areas)):
        alone = G.rft_element_forces(centroids[i:i + 1], normals[i:i + 1], areas[i:i + 1], velocities[i:i + 1],
                                     **options)
        assert np.array_equal(alone[0], together[i])


def test_friction_cap() -> None:
    _, normals, _, velocities = _random_elements(200, seed=5)
    free = G.rft_element_alpha(normals, velocities)
    capped = G.rft_element_alpha(normals, velocities, surface_friction=0.2)
    for alpha in (free, capped):
        assert np.array_equal(alpha == 0.0, free == 0.0)
    normal = np.einsum("ij,ij->i", capped, normals)
    tangential = np.linalg.norm(capped - normal[:, None] * normals, axis=1)
    assert np.all(tangential <= 0.2 * np.abs(normal) + 1e-12)
    smooth = G.rft_element_alpha(normals, velocities, surface_friction=0.0)
    np.testing.assert_allclose(np.cross(smooth, normals), 0.0, atol=1e-12)
    assert np.array_equal(G.rft_element_alpha(normals, velocities, surface_friction=1e9), free)


def test_inertial_drag_opposes_the_motion() -> None:
    """A buried box withdrawn at 0.5 m/s: its lid's drag points down (a public fork pushes it up)."""
    z = [[0.0, 0.0, -0.06], [0.0, 0.0, -0.04]]  # sole, lid
    normals = [DOWN, UP]
    for vz in (0.5, -0.5):
        quasi = G.rft_element_forces(z, normals, [1e-3] * 2, [[0, 0, vz]] * 2, scale=1e5)
        dynamic = G.rft_element_forces(z, normals, [1e-3] * 2, [[0, 0, vz]] * 2, scale=1e5, inertial_drag=100.0)
        drag = (dynamic - quasi).sum(axis=0)
        np.testing.assert_allclose(drag, [0.0, 0.0, -math.copysign(100.0 * 0.25 * 1e-3, vz)], rtol=1e-12)
    centroids, normals_r, areas, velocities = _random_elements(300, seed=9)
    extra = (G.rft_element_forces(centroids, normals_r, areas, velocities, scale=1e5, inertial_drag=50.0)
             - G.rft_element_forces(centroids, normals_r, areas, velocities, scale=1e5))
    assert np.all(np.einsum("ij,ij->i", extra, velocities) <= 0.0)


def test_wrench_sums_forces_and_torques() -> None:
    centroids = [[0.1, 0.0, -0.01], [-0.1, 0.0, -0.01]]
    forces = [[0.0, 0.0, 2.0], [0.0, 0.0, 1.0]]
    force, torque = G.rft_wrench(centroids, forces, point=[0.0, 0.0, -0.01])
    np.testing.assert_allclose(force, [0.0, 0.0, 3.0])
    np.testing.assert_allclose(torque, [0.0, -0.1, 0.0], atol=1e-15)


def test_medium_scale() -> None:
    assert G.medium_scale(1000.0, 0.5) == pytest.approx(1000.0 * 9.81 * 59.75, rel=1e-12)
    assert G.medium_scale(1500.0, 0.4, gravity=10.0) == pytest.approx(1500.0 * 10.0 * 31.056, rel=1e-12)


# --- the 1-D baselines as special cases ----------------------------------------------------------------------------

def _sole_trajectory() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.linspace(0.0, 1.0, 41)
    depth = 0.03 * np.sin(PI * t) - 0.005  # starts above the surface, down to 25 mm, back out
    depth[20:23] = depth[20]  # a rest at the bottom
    return t, depth, branch_velocity(t, depth)


@pytest.mark.parametrize(("law", "alpha_down"), [("li2013", 1.0), ("rft3d", 0.87504)])
def test_granular_rft_baseline_is_a_horizontal_sole(law: str, alpha_down: float) -> None:
    """granular_rft_force = the element law on the sole, scale = k_rft / alpha_z(0, pi/2), every sample.

    RFT is rate independent: only the direction of motion enters, and the baseline's branch rule (rest is
    intrusion) gives it on the rest samples, where the element law alone has no direction.
    """
    t, depth, v = _sole_trajectory()
    foot = Foot.paper()
    k_rft = 1.4e6
    direction = np.where(v >= 0.0, -1.0, 1.0)  # world z of the motion; v is positive down
    count = len(t)
    forces = G.rft_element_forces(np.column_stack([np.zeros(count), np.zeros(count), -depth]), [DOWN] * count,
                                  np.full(count, foot.area), np.column_stack([np.zeros((count, 2)), direction]),
                                  scale=k_rft / alpha_down, law=law)
    np.testing.assert_allclose(forces[:, 2], granular_rft_force(t, depth, k_rft, foot), rtol=1e-12, atol=1e-12)
    assert np.abs(forces[:, :2]).max() < 1e-12 * np.abs(forces[:, 2]).max()  # cos(pi/2) is not exactly 0
    assert np.count_nonzero(forces[:, 2]) > 10


def test_drft_baseline_on_intrusion_and_its_withdrawal_drag() -> None:
    """drft_force = sole + inertial drag while moving down; moving up, the baseline's drag (-lambda rho v^2 S) is
    on the sole, which trails, while the element law puts it on the faces that lead (the top of a buried foot)."""
    t, depth, v = _sole_trajectory()
    foot = Foot.paper()
    k_rft, lam, rho = 1.4e6, 0.013, 1840.0
    moving = v != 0.0
    count = int(moving.sum())
    forces = G.rft_element_forces(np.column_stack([np.zeros(count), np.zeros(count), -depth[moving]]),
                                  [DOWN] * count, np.full(count, foot.area),
                                  np.column_stack([np.zeros((count, 2)), -v[moving]]),
                                  scale=k_rft, law="li2013", inertial_drag=lam * rho)[:, 2]
    baseline = drft_force(t, depth, k_rft, lam, rho, foot)[moving]
    down = v[moving] > 0.0
    np.testing.assert_allclose(forces[down], baseline[down], rtol=1e-12, atol=1e-12)
    up = ~down
    withdrawal_drag = np.where(depth[moving] > 0.0, lam * rho * v[moving] * np.abs(v[moving]), 0.0) * foot.area
    np.testing.assert_allclose(forces[up], baseline[up] - withdrawal_drag[up], rtol=1e-12, atol=1e-12)
    assert np.count_nonzero(withdrawal_drag[up]) > 5


# --- bad input -----------------------------------------------------------------------------------------------------

@pytest.mark.parametrize(("change", "words"), [
    ({"normals": [[0.0, 0.0, -2.0]]}, "unit vectors"),
    ({"normals": [[0.0, 0.0]]}, "shape"),
    ({"areas": [-1e-3]}, "areas"),
    ({"areas": [1e-3, 1e-3]}, "shape (1,)"),
    ({"velocities": [[0.0, 0.0, math.nan]]}, "finite"),
    ({"centroids": "here"}, "real numbers"),
    ({"scale": 0.0}, "scale must be > 0"),
    ({"law": "drft"}, "law must be one of rft3d, li2013"),
    # an array compared equal elementwise: ["rft3d"] gave Li's law, two names numpy's ValueError
    ({"law": np.array(["rft3d"])}, "law must be one of rft3d, li2013, got ndarray"),
    ({"law": np.array(["rft3d", "li2013"])}, "law must be one of rft3d, li2013, got ndarray"),
    ({"surface_friction": -0.1}, "surface_friction"),
    ({"inertial_drag": math.inf}, "inertial_drag"),
    ({"surface_height": "0"}, "surface_height"),
])
def test_bad_input_is_one_line_and_changes_nothing(change: dict[str, object], words: str) -> None:
    arguments: dict[str, object] = {"centroids": np.array([[0.0, 0.0, -0.01]]), "normals": np.array([DOWN]),
                                    "areas": np.array([1e-3]), "velocities": np.array([[0.0, 0.0, -0.1]]),
                                    "scale": 1e5}
    arguments.update(change)
    before = {k: np.array(a, copy=True) for k, a in arguments.items() if isinstance(a, np.ndarray)}
    with pytest.raises(InputError) as error:
        G.rft_element_forces(**arguments)  # type: ignore[arg-type]
    assert words in str(error.value) and "\n" not in str(error.value)
    assert all(np.array_equal(arguments[k], a) for k, a in before.items())


def test_bad_angles_and_scales() -> None:
    for call in (lambda: G.rft_alpha(math.nan, 0.0), lambda: G.rft_alpha([0.0, 1.0], [0.0, 1.0, 2.0]),
                 lambda: G.medium_scale(1000.0, 0.0), lambda: G.rft3d_angles([DOWN], [[0.0, 0.0, 0.0]]),
                 lambda: G.rft3d_alpha([DOWN], [[0.0, 0.0, -1.0]], coefficients=(G.RFT3D_C1, G.RFT3D_C2)),
                 lambda: G.rft_wrench([[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], point=[0.0, 0.0])):
        with pytest.raises(InputError):
            call()


@pytest.mark.parametrize(("call", "words"), [
    # booleans among numbers were read as 0 and 1
    (lambda: G.rft_alpha([0.1, True], 0.5), "beta [rad] must be real numbers"),
    (lambda: G.rft3d_alpha([DOWN], [[0.0, 0.5, True]]), "velocities [m/s] must be real numbers"),
    (lambda: G.rft_element_forces([[0.0, 0.0, -0.1]] * 2, [DOWN] * 2, [True, 1e-4], [[0.0, 0.0, -1.0]] * 2,
                                  scale=1e5), "areas [m^2]"),
    (lambda: G.rft_wrench([[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], [True, 0, 0]), "point [m]"),
    # Li's coefficients unchecked: NaN gave NaN, a string a TypeError, an array an array of results
    (lambda: G.rft_alpha(0.1, 0.5, G.LI2013_GENERIC._replace(A00=math.nan)), "A00 = nan"),
    (lambda: G.rft_alpha(0.1, 0.5, G.LI2013_GENERIC._replace(A00="x")), "A00 = 'x'"),
    # a Python int beyond float64: OverflowError from math.isfinite
    (lambda: G.rft_alpha(0.1, 0.5, G.LI2013_GENERIC._replace(C11=10**400)), "C11 = an integer of 1329 bits"),
    (lambda: G.rft_element_alpha([DOWN], [[0.0, 0.0, -1.0]], law="li2013",
                                 li_coefficients=G.LI2013_GENERIC._replace(B01=np.ones(3))), "li_coefficients"),
    # the point's repr: over lines for a 2-D array, ValueError for a Python int of over 4300 digits
    (lambda: G.rft_wrench([[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], np.zeros((3, 3))), "got shape (3, 3)"),
    (lambda: G.rft_wrench([[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], [0, 0, 10**5000]), "point [m] must be 3 finite"),
    # |n|^2 overflowed with numpy's RuntimeWarning before the refusal
    (lambda: G.rft_element_alpha([[0.0, 0.0, -1e200]], [[0.0, 0.0, -1.0]]), "normals must be unit vectors"),
    (lambda: G.rft3d_angles([[1e300, 0.0, 0.0]], [[0.0, 0.0, -1.0]]), "normals must be unit vectors"),
    # 2 beta overflowed: refused as "the coefficients' sums beyond float64", not naming beta
    (lambda: G.rft_alpha([0.1, -1e308], 0.5), "beta [rad] must be within +-8.988e+307"),
    # rft3d_basis took anything np.asarray did: "1" as 1, NaN, None as NaN; a complex or a shape mismatch raised
    (lambda: G.rft3d_basis("1", 0.0, 0.0), "x1 [-] must be real numbers"),
    (lambda: G.rft3d_basis(math.nan, 0.0, 0.0), "x1 [-] must be finite"),
    (lambda: G.rft3d_basis(1j, 0.0, 0.0), "x1 [-] must be real numbers"),
    (lambda: G.rft3d_basis([1.0, 2.0], [1.0, 2.0, 3.0], 0.0), "must broadcast together"),
    # an xp that is neither numpy nor jax.numpy: AttributeError
    (lambda: G.rft3d_alpha([DOWN], [[0.0, 0.0, -1.0]], xp=math), "xp must be numpy or jax.numpy"),
    # |v|^2 overflowed: the direction became 0, and a foot moving up got the stress of one moving down
    (lambda: G.rft3d_alpha([DOWN], [[0.0, 0.0, 1e300]]), "velocities [m/s] must be within"),
    (lambda: G.rft3d_angles([DOWN], [[1e200, 1e200, -1e200]]), "velocities [m/s] must be within"),
    (lambda: G.rft_element_alpha([DOWN], [[1e200, 0.0, -1e200]], law="li2013"), "velocities [m/s] must be within"),
    # products of finite inputs overflowed: inf and NaN forces, returned
    (lambda: G.rft_element_forces([[0.0, 0.0, -1e308]], [DOWN], [1.0], [[0.0, 0.0, -1.0]], 1e308, scale=1e5),
     "forces [N] overflow"),
    (lambda: G.rft_wrench([[1e200, 0.0, 0.0]], [[0.0, 1e200, 0.0]]), "torque [N m] overflow"),
    # finite inputs whose sums and cubes overflowed: inf and NaN stresses returned, with numpy's warnings
    (lambda: G.rft_alpha(0.0, PI / 2, G.LiCoefficients(*[1e308] * 9)),
     "stresses per depth (alpha_x, alpha_z) overflow"),
    (lambda: G.rft3d_basis(1e200, 0.0, 0.0), "basis monomials overflow"),
    (lambda: G.rft3d_alpha([DOWN], [DOWN], coefficients=(np.full(20, 1e308),) * 3),
     "stresses per depth alpha overflow"),
    (lambda: G.rft_element_alpha([DOWN], [DOWN], law="li2013", li_coefficients=G.LiCoefficients(*[1e308] * 9)),
     "stresses per depth alpha overflow"),
    # mu ** 3 raised OverflowError; rho_c 1e300 gave inf
    (lambda: G.medium_scale(1000.0, 1e300), "medium_scale overflows"),
    (lambda: G.medium_scale(1e308, 10.0), "medium_scale overflows"),
])
def test_more_bad_input_is_one_line(call: Any, words: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow warning on the way to the refusal
        with pytest.raises(InputError) as error:
            call()
    assert words in str(error.value) and "\n" not in str(error.value)


@pytest.mark.parametrize("law", ["rft3d", "li2013"])
def test_a_tiny_velocity_has_its_direction(law: str) -> None:
    """RFT depends on the direction of motion only; below about 1e-154 m/s |v|^2 underflowed, and a moving element
    got the zero stress of one at rest (rft3d_angles refused its velocity as zero), or a direction rounded off."""
    _, normals, _, velocities = _random_elements(40, seed=3)
    for power in (-560, -600, -1000):  # about 1e-170 to 1e-302 m/s
        tiny = np.ldexp(velocities, power)  # the same directions, exactly
        assert np.all(np.abs(tiny).max(axis=1) > 0.0)
        np.testing.assert_array_equal(G.rft_element_alpha(normals, tiny, law=law),
                                      G.rft_element_alpha(normals, velocities, law=law))
        if law == "rft3d":
            np.testing.assert_array_equal(G.rft3d_alpha(normals, tiny), G.rft3d_alpha(normals, velocities))
            for got, want in zip(G.rft3d_angles(normals, tiny), G.rft3d_angles(normals, velocities), strict=True):
                np.testing.assert_array_equal(got, want)
    subnormal = np.ldexp([[3.0, 0.0, -4.0], [0.0, 0.0, -1.0]], -1074)  # 1.5e-323 ... m/s
    np.testing.assert_array_equal(G.rft_element_alpha([DOWN] * 2, subnormal, law=law),
                                  G.rft_element_alpha([DOWN] * 2, [[3.0, 0.0, -4.0], [0.0, 0.0, -1.0]], law=law))
    forces = G.rft_element_forces([[0.0, 0.0, -0.01]], [DOWN], [1e-4], [[0.0, 0.0, -1e-170]], scale=1e5,
                                  law=law, inertial_drag=1e3)
    assert forces[0, 2] == pytest.approx(G.rft_element_forces([[0.0, 0.0, -0.01]], [DOWN], [1e-4], [[0.0, 0.0, -1.0]],
                                                              scale=1e5, law=law)[0, 2], rel=1e-15)
