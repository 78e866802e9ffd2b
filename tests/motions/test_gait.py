"""The gait generator and simulated walks: deterministic, bounded, and through every contact state."""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.motions.gait import gait, walk


def test_same_seed_same_gait_bit_for_bit() -> None:
    a, b = gait(7, duration=10.0, jitter=0.3), gait(7, duration=10.0, jitter=0.3)
    assert a.time.tobytes() == b.time.tobytes() and a.depth.tobytes() == b.depth.tobytes()
    assert gait(8, duration=10.0).depth.tobytes() != a.depth.tobytes()


def test_gait_steps_in_and_out_of_the_mud() -> None:
    g = gait(3, duration=20.0)
    assert np.all(np.diff(g.time) > 0) and g.time[0] == 0.0
    assert g.depth[0] < 0 and g.depth.max() > 0.009 and g.depth.max() < 0.04
    assert len(g.swings) >= 3  # several steps
    # above the surface at every swing apex
    for s in g.swings:
        assert np.interp(s, g.time, g.depth) < 0


def test_walk_necks_and_changes_mud_at_a_swing() -> None:
    w = walk((0.2, 0.3), change_times=(10.0,), seed=1, duration=20.0, bias=0.5, force_noise=0.0, depth_noise=0.0)
    assert len(w.changes) == 1 and w.changes[0] >= 10.0
    assert set(np.unique(w.water_content)) == {0.2, 0.3}
    assert w.force_true.min() < -1.0  # suction
    np.testing.assert_allclose(w.force - w.force_true, 0.5)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"seed": -1}, "seed"), ({"seed": 2**70}, r"seed must be an integer in \[0, 4294967295\]"),
     ({"seed": True}, "seed"), ({"duration": 0.0}, "duration"), ({"rate": float("nan")}, "rate")],
)
def test_gait_refuses_bad_input(kwargs: dict[str, float], match: str) -> None:
    with pytest.raises(InputError, match=match):
        gait(**kwargs)  # type: ignore[arg-type]


def test_walk_needs_one_change_time_per_change() -> None:
    with pytest.raises(InputError, match="one change time per change"):
        walk((0.2, 0.3))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"water_content": (0.2, 0.25, 0.3), "change_times": "58"}, "change_times"),  # read as 5 s and 8 s
     ({"water_content": (0.2, 0.3), "change_times": (True,)}, "change_times"),  # read as 1 s
     ({"water_content": "0.25"}, "water_content"),
     ({"water_content": [[0.25]]}, "water_content"),  # TypeError
     ({"water_content": True}, "water_content"),
     ({"water_content": ()}, "water_content")],
)
def test_walk_refuses_text_and_booleans_for_numbers(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(InputError, match=match):
        walk(duration=25.0, **kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize("change", [0.0, -5.0])
def test_walk_refuses_a_change_at_its_first_swing_apex(change: float) -> None:
    # the walk starts at a swing apex: the first mud had no samples, refused as 'the trajectory is empty'
    with pytest.raises(InputError, match=r"falls on the walk's first swing apex.*water content 0.2 would have no"):
        walk((0.2, 0.3), change_times=(change,), duration=5.0)


def test_walk_takes_a_0d_array_as_one_water_content() -> None:  # TypeError: iteration over a 0-d array
    a = walk(np.array(0.25), duration=5.0)
    b = walk(0.25, duration=5.0)
    assert a.force.tobytes() == b.force.tobytes() and a.water_content.tobytes() == b.water_content.tobytes()
