"""mudforce.references.drop.exact_drop_3d: the paper's sole drops as the 1-D exact drop; its force is the 3-D law's."""

from __future__ import annotations

import numpy as np
import pytest

from mudforce import MudParameters
from mudforce.errors import InputError
from mudforce.model import shapes
from mudforce.model.foot import Foot
from mudforce.references.drop import exact_drop, exact_drop_3d


@pytest.mark.parametrize(("water", "mass"), [(0.15, 10.0), (0.25, 15.0)])
def test_the_paper_s_sole_drops_as_the_1d_exact_drop(water: float, mass: float) -> None:
    """To solver tolerance (rtol 1e-11): W = 15 % sticks for good, W = 25 % at 15 kg creeps (stick, slip, ...).

    Measured: depth within 5e-11 relative, force within 3e-8 N.
    """
    params = MudParameters.from_water_content(water)
    one = exact_drop(mass, params, duration=0.5)
    three = exact_drop_3d(mass, params, shapes.sole(Foot.paper(), resolution=0.01), duration=0.5)
    assert [e[1] for e in three.events] == [e[1] for e in one.events]
    assert three.end_depth == pytest.approx(one.end_depth, rel=1e-9) and three.at_rest == one.at_rest
    np.testing.assert_allclose(three.depth, one.depth, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(three.force, one.force, rtol=0.0, atol=1e-6 * np.max(np.abs(one.force)))


def test_a_sphere_s_drop_force_is_the_3d_law_along_its_own_motion() -> None:
    """Until it stops, the drop's force is MudContact3D's (the compiled law) on the drop's own poses, 0.1 ms apart.

    The law takes the depth linear between poses: measured within 1.1e-7 of the peak (5e-6 N).
    """
    from mudforce.steppers.contact3d import simulate_3d

    params = MudParameters.from_water_content(0.20)
    sphere = shapes.sphere(0.04, resolution=0.01)
    ref = exact_drop_3d(2.0, params, sphere, bottom=-0.02, duration=0.06, dt=1e-4)
    assert [e[1] for e in ref.events][:2] == ["FREE", "INTRUSION"] and ref.events[-1][1] == "INTRUSION"
    pos = np.zeros((ref.time.size, 3))
    pos[:, 2] = -ref.depth + 0.02
    res = simulate_3d(ref.time, pos, np.tile([1.0, 0.0, 0.0, 0.0], (ref.time.size, 1)), params, sphere)
    force = np.asarray(res.force)
    peak = float(np.max(ref.force))
    assert peak > 2.0 * 9.81
    np.testing.assert_allclose(force[:, 2], ref.force, rtol=0.0, atol=1e-6 * peak)
    assert np.max(np.abs(force[:, :2])) <= 1e-9 * peak


def test_bad_input_is_refused_in_one_line() -> None:
    params = MudParameters.from_water_content(0.20)
    sphere = shapes.sphere(0.04, resolution=0.01)
    for call, match in ((lambda: exact_drop_3d(2.0, params, "sphere"), "Shape"),  # type: ignore[arg-type]
                        (lambda: exact_drop_3d(2.0, params, sphere, orientation=(1.0, 1.0, 0.0, 0.0)), "unit"),
                        (lambda: exact_drop_3d(-2.0, params, sphere), "mass"),
                        # a 2-D orientation's repr spans lines
                        (lambda: exact_drop_3d(2.0, params, sphere, orientation=np.eye(4)), "unit quaternion"),
                        # the sphere's lower half below the surface at release: it fell 1.23 m in 0.5 s, no force
                        (lambda: exact_drop_3d(2.0, params, sphere, bottom=0.0), "0.0192388 m below the surface"),
                        (lambda: exact_drop_3d(2.0, params, sphere, bottom=0.1, height=0.05), "below the surface"),
                        (lambda: exact_drop_3d(2.0, params, sphere, bottom=1e300), "bottom must be within"),
                        # tilted 0.3 rad, a box was dropped straight as if symmetric (rest 7.09 mm), its torque left
                        # out; so was a capsule tilted 0.5 rad (11.97 mm)
                        (lambda: exact_drop_3d(2.0, params, shapes.box(0.03, 0.03, 0.03, resolution=0.01),
                                               orientation=(np.cos(0.15), np.sin(0.15), 0.0, 0.0)),
                         r"^exact_drop_3d drops a foot with no torque from the mud: at this orientation the loaded "
                         r"elements at z = 0\.00512056 m \(from the body origin, world axes\) bear 0\.0173 m off the "
                         r"vertical through it; expected a shape symmetric about that vertical"),
                        (lambda: exact_drop_3d(2.0, params, shapes.capsule(0.03, 0.06, resolution=0.01),
                                               orientation=(np.cos(0.25), np.sin(0.25), 0.0, 0.0)), "no torque")):
        with pytest.raises(InputError, match=match) as err:
            call()
        assert "\n" not in str(err.value)
