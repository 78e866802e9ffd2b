"""MudTracker's interval widens at a low rate (issue 23, point 5 online: the sensor-chain bench's "hard, all").

Between two samples at a low rate the model follows an interpolated path, and its force at a lift-off (the neck's
start and decay) or a strike depends on what the foot did there: on seed 4 a wet robot (33.9 %) at 20 Hz under a
+5 mm offset and a 10 + 10 ms lag read 30.4 % with a 3.6-point interval, unflagged, its offset and lag known or not.
The reported interval's blur is widened by ``_RATE_WIDENING sqrt(k - 1)``, ``k = round(dt / 10 ms)`` (2 at 50 Hz, 5
at 20 Hz), in quadrature with the misfit's and the shallow sinkage's; the estimate stays the fit's median and
100 Hz is untouched.
"""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.estimation import _tracker_layout as tracker_layout
from mudforce.estimation.tracker import TrackResult, track
from mudforce.motions.gait import walk

Runs = dict[int, tuple[np.ndarray, TrackResult, TrackResult]]


@pytest.fixture(scope="module")
def runs() -> Runs:
    """A 12-s walk on 25 % mud at 100, 50 and 20 Hz (every 1st, 2nd, 5th sample), tracked with and without."""
    wk = walk(0.25, seed=3, duration=12.0, force_noise=0.2, bias=0.5)
    out: Runs = {}
    patch = pytest.MonkeyPatch()
    try:
        for stride in (1, 2, 5):
            t, z, f = wk.time[::stride], wk.depth[::stride], wk.force[::stride]
            wide = track(t, z, f)
            patch.setattr(tracker_layout, "_RATE_WIDENING", 0.0)  # read when a tracker is made
            plain = track(t, z, f)
            patch.undo()
            out[stride] = (t, wide, plain)
    finally:
        patch.undo()
    return out


def _width(r: TrackResult, late: np.ndarray) -> float:
    return float(np.median((r.high - r.low)[late]))


def test_a_low_rate_widens_the_interval_not_the_estimate(runs: Runs) -> None:
    for stride in (2, 5):
        t, wide, plain = runs[stride]
        late = t >= 3.0
        assert np.array_equal(wide.water_content, plain.water_content)
        assert np.array_equal(wide.changed, plain.changed)
        assert np.all(wide.low <= plain.low) and np.all(wide.high >= plain.high)
        assert np.all((wide.low[late] <= 0.25) & (0.25 <= wide.high[late]))
    # measured: median width after 3 s 3.1 points plain at both rates; 6.0 at 50 Hz (blur factor 2: sqrt(1 + 1.5^2)
    # = 1.80 rounded up to the next of _BLUR_FACTORS), 11.8 at 20 Hz (factor 4: sqrt(1 + 4 1.5^2) = 3.16); 4.4 and 8.9
    # with _RATE_WIDENING at 1 (factors 1.5 and 3)
    t50, wide50, plain50 = runs[2]
    t20, wide20, plain20 = runs[5]
    assert _width(plain50, t50 >= 3.0) == pytest.approx(0.0310, abs=0.002)
    assert _width(wide50, t50 >= 3.0) == pytest.approx(0.0596, abs=0.002)
    assert _width(plain20, t20 >= 3.0) == pytest.approx(0.0310, abs=0.002)
    assert _width(wide20, t20 >= 3.0) == pytest.approx(0.1179, abs=0.002)


def test_100_hz_is_not_widened(runs: Runs) -> None:
    _, wide, plain = runs[1]
    assert np.array_equal(wide.low, plain.low) and np.array_equal(wide.high, plain.high)
