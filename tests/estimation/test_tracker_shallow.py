"""MudTracker's interval widens with a shallow sinkage, and its estimate's quantiles are read exactly (issue 23,
point 5 online).

Every recording the tracker was confidently wrong on, on the sensor-chain bench's seeds 1 and 2, is a robot foot that
sinks 2-3.5 mm, read through a surface offset known to about 1.5 mm (half the step between two offset hypotheses):
the depth the force is read at is uncertain by half itself. The reported interval's blur is then widened by
``k sqrt(s^2 - 1)``, ``s = 4.5 sqrt(sd^2 + (step / 2)^2 + noise^2) / sinkage`` (``tracker._SHALLOW_WIDENING``; the
depth noise measured online in it since 2026-11-30), ``k = 2.5``
(``tracker._SHALLOW_GAIN``; was ``s`` at 5 and ``k`` 1, which left seed 3's robot on 16.7 % mud, sinking 3.1 mm,
confidently wrong under a lagged force); the estimate stays the fit's median, and the interval is the hull of the
plain and the widened one. Gait walks, 1-3 cm deep, have ``s`` below 1 and are not widened.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mudforce.estimation import _tracker_layout as tracker_layout
from mudforce.estimation._tracker_step import _blurred_quantiles
from mudforce.estimation.tracker import TrackResult, _blur_matrix, track
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import gait, walk
from mudforce.steppers.simulation import simulate


def _shallow_walk() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A gait path scaled to sink 3.9 mm, in mud of W = 18 %, with 0.2 N of force noise and a 0.3 N offset."""
    path = gait(3, duration=10.0)
    z = path.depth * 0.12
    f = np.asarray(simulate(path.time, z, MudParameters.from_water_content(0.18), Foot.paper(),
                            velocity_filter="exact").force)
    rng = np.random.default_rng(0)
    return path.time, z + rng.normal(0.0, 3e-5, z.size), f + rng.normal(0.0, 0.2, f.size) + 0.3


def test_a_shallow_sinkage_widens_the_interval_not_the_estimate(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(tracker_layout, "_HULL_MEMORY", 0.0)  # the intervals as read, not their hull over a second
    t, z, f = _shallow_walk()
    wide = track(t, z, f)
    monkeypatch.setattr(tracker_layout, "_SHALLOW_WIDENING", 0.0)  # read when a tracker is made
    plain = track(t, z, f)
    late = t >= 3.0
    assert np.array_equal(wide.water_content, plain.water_content)  # the fit's median either way
    assert np.all(wide.low <= plain.low) and np.all(wide.high >= plain.high)  # the hull: never narrower
    # measured: median width after 3 s 6.7 -> 17.5 points (17.2 before an end moved toward the grid's in proportion,
    # _END_REACH_FROM; 6.1 -> 17.0 before an interval near the grid's end
    # reached it, _END_REACH; 16.7 before the widened blurs' piled twins, 12.6 before the blurs of 9 and 13.5
    # discrepancies, 9.9-10.1 with s at 5 and k at 1); both cover 18 %
    assert np.median((plain.high - plain.low)[late]) == pytest.approx(0.0666, abs=0.003)
    assert np.median((wide.high - wide.low)[late]) == pytest.approx(0.1755, abs=0.003)
    assert np.all((wide.low[late] <= 0.18) & (0.18 <= wide.high[late]))


def test_the_widening_s_gain(monkeypatch: pytest.MonkeyPatch) -> None:
    # the same walk with the widening before issue 23's lag rows (s at 5, gain 1), then each constant alone: the
    # gain widens where s > 1, a smaller s widens less (both read when a tracker is made)
    monkeypatch.setattr(tracker_layout, "_HULL_MEMORY", 0.0)  # the intervals as read, not their hull over a second
    t, z, f = _shallow_walk()
    late = t >= 3.0
    widths = []
    for c, k in ((5.0, 1.0), (4.0, 1.0), (5.0, 2.5)):
        monkeypatch.setattr(tracker_layout, "_SHALLOW_WIDENING", c)
        monkeypatch.setattr(tracker_layout, "_SHALLOW_GAIN", k)
        r = track(t, z, f)
        widths.append(float(np.median((r.high - r.low)[late])))
    # measured: 10.4, 10.1 and 20.2 points since the twin bank runs the quick rule (10.2, 9.4, 20.2 with its 5-step
    # rule; 10.1, 9.2, 18.8 before the widened blurs' piled twins, the last 12.5 before the blurs of 9 and 13.5
    # discrepancies)
    assert widths == pytest.approx([0.1036, 0.1006, 0.2023], abs=0.003)
    assert widths[1] < widths[0] < widths[2]


def test_deep_walks_and_one_offset_are_not_widened(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(tracker_layout, "_HULL_MEMORY", 0.0)  # the intervals as read, not their hull over a second
    wk = walk(0.25, seed=3, duration=12.0, force_noise=0.2, bias=0.5)
    shallow = _shallow_walk()
    runs = [track(wk.time, wk.depth, wk.force), track(*shallow, depth_offsets=[0.0])]
    monkeypatch.setattr(tracker_layout, "_SHALLOW_WIDENING", 0.0)
    plain = [track(wk.time, wk.depth, wk.force), track(*shallow, depth_offsets=[0.0])]
    late = wk.time >= 3.0  # the walk sinks 1-3 cm: s < 1 once its first stances are in
    assert np.array_equal(runs[0].low[late], plain[0].low[late])
    assert np.array_equal(runs[0].high[late], plain[0].high[late])
    assert np.array_equal(runs[1].low, plain[1].low) and np.array_equal(runs[1].high, plain[1].high)


def test_blurred_quantiles_sum_in_row_order_skipping_empty_cells() -> None:
    grid = np.array([0.15 + 0.005 * k for k in range(41)])
    mids = 0.5 * (grid[1:] + grid[:-1])
    edges = np.concatenate(([grid[0] - 0.0025], mids, [grid[-1] + 0.0025]))
    blur = _blur_matrix(grid, edges, 0.015)
    rng = np.random.default_rng(3)
    p = rng.random(41) * (rng.random(41) < 0.3)
    p /= p.sum()
    q = np.zeros(41)
    mid, low, high = _blurred_quantiles(np.ascontiguousarray(blur.T), p, q, edges, 0.025)
    expected = []
    for g in range(41):  # the row-by-row product, in order, in Python's IEEE doubles
        acc = 0.0
        for h in range(41):
            acc += float(blur[g, h]) * float(p[h])
        expected.append(acc)
    assert q.tolist() == expected  # bit for bit
    assert low < mid < high


def test_a_shallow_foot_under_1mm_depth_noise_is_widened_by_the_noise_too() -> None:
    """The sensor-chain bench's seed 33, ``robot`` 5: the MuJoCo quadruped's front-left foot (a 50 mm disc) sinking
    about 4 mm into W = 15.70 % mud, MuJoCo's force, through the row "standard, all (-)" (offset -2 mm, drift -2 mm
    over 30 s, low-pass 10 ms, gain -5 %, depth noise 1 mm, 50 Hz; ``SensorChain(force_noise=0.2, ...)``), 30 s.

    Its surface offset sits on the +3 mm hypothesis (spread 0), so ``s`` read 1.5-2 from the offset alone, while the
    depth carries 1 mm of noise on a 4-mm sinkage: read 22-24 % in its first seconds with an interval that ended at
    15.7-16.0 %, it missed the truth unflagged on 77 of the 1351 samples after 3 s. With the depth noise in ``s`` it
    misses none (median width 14.6 -> 16.3 points); the estimate is the same. (With the rest band's spread under the
    depth noise, ``_REST_SPREAD``, it read 0.25 points wetter and missed 8 samples at 3.9-4.1 s by up to 0.24 points,
    its interval [15.9, 33.2] %; none since such an end reaches the grid's, ``_END_REACH``.)"""
    truth = 0.15697687763664256
    t, z, f = np.loadtxt(Path(__file__).parent / "data" / "robot_shallow_dry_standard_all_minus_seed33.csv",
                         delimiter=",", skiprows=1, unpack=True)
    r = track(t, z, f, Foot.disc(0.05))
    late = t >= 3.0
    assert np.all((r.low[late] <= truth) & (truth <= r.high[late]))  # measured: every one of the 1351
    assert np.median(r.water_content[late]) == pytest.approx(0.1715, abs=0.002)  # measured 17.15 % (17.25 before
    # _REST_SPREAD)


def test_an_interval_reaches_the_grids_end_where_its_tail_there_is_as_dense_as_it() -> None:
    """``_reach_ends``: an end moves to the grid's where the tail it leaves out (``half`` of the posterior) is at least
    ``_END_REACH`` times as dense as the interval (``1 - 2 half`` over its width), not at all where it is at most
    ``_END_REACH_FROM`` times, and in proportion between. The sensor-chain bench's seed 34 robot 0 (a MuJoCo foot 2 mm
    deep, 15.08 % mud, "standard, all (-)") read [15.31, 35.16] %: a flat posterior, whose equal tails left out
    15.08 %; it now reads the whole grid. A posterior peaked inside keeps its interval."""
    from mudforce.estimation._tracker_layout import _END_REACH, _END_REACH_FROM
    from mudforce.estimation._tracker_step import _reach_ends

    first, last, half = 0.1475, 0.3525, 0.025
    assert _reach_ends(0.1531, 0.3516, first, last, half) == (first, last)
    assert _reach_ends(0.17, 0.20, first, last, half) == (0.17, 0.20)  # 2.25 points from the end, 3 wide
    # at the limits: the tail's width half / (ratio * density inside)
    width = 0.03
    inside = (1.0 - 2.0 * half) / width
    full = half / (_END_REACH * inside)
    none = half / (_END_REACH_FROM * inside)
    assert _reach_ends(first + 0.99 * full, first + 0.99 * full + width, first, last, half)[0] == first
    assert _reach_ends(last - width - 0.99 * full, last - 0.99 * full, first, last, half)[1] == last
    assert _reach_ends(first + 1.01 * none, first + 1.01 * none + width, first, last, half)[0] == first + 1.01 * none
    # between, in proportion to the ratio: a tail twice as thin as at the full reach's limit moves the end half-way
    # for _END_REACH_FROM = _END_REACH / 2 (the end at a third of the way's gap, 0.5 of it moved)
    gap = half / (0.5 * (_END_REACH + _END_REACH_FROM) * inside)
    low = _reach_ends(first + gap, first + gap + width, first, last, half)[0]
    assert low == pytest.approx(first + 0.5 * gap, rel=1e-12)


def test_the_reach_toward_the_grids_end_is_continuous() -> None:
    """As the tail beyond an end thins, the end moves continuously: at most by its step's share of the sliver, not by
    the whole sliver at once (was a 2-point step in one sample, 14.75 -> 16.87 %, on the sensor-chain bench's seed
    90)."""
    from mudforce.estimation._tracker_step import _reach_ends

    first, last, half = 0.1475, 0.3525, 0.025
    lows = np.linspace(0.150, 0.200, 5001)  # 1e-5 apart
    reported = np.array([_reach_ends(low, 0.3525, first, last, half)[0] for low in lows])
    assert np.all(np.diff(reported) >= -1e-15)  # never moves back toward the end as the interval's end moves in
    assert np.max(np.diff(reported)) < 1e-3  # no jump: at most 0.1 points for a step of 1e-3 points


def _covered_unflagged(filename: str, truth: float) -> tuple[np.ndarray, TrackResult]:
    """A kept sensor-chain recording of the MuJoCo quadruped's foot (``data/filename``: ``time_s, depth_m,
    force_N``) tracked with its 50 mm disc: nothing flagged, and every sample's interval after 3 s holds ``truth``
    [-] (the tracker is never confidently wrong there). Returns the times [s] and the result."""
    t, z, f = np.loadtxt(Path(__file__).parent / "data" / filename, delimiter=",", skiprows=1, unpack=True)
    r = track(t, z, f, Foot.disc(0.05))
    late = t >= 3.0
    assert not r.misfit[late].any() and not r.changed.any()  # nothing flagged: the interval must hold the truth
    assert np.all((r.low[late] <= truth) & (truth <= r.high[late]))
    return t, r


def test_a_shallow_dry_foot_whose_tail_thins_is_not_left_out() -> None:
    """The sensor-chain bench's seed 90, ``robot`` 6: the MuJoCo quadruped's foot (a 50 mm disc) sinking 2.4-4.2 mm
    into W = 16.64 % mud, MuJoCo's force, through "standard, all (-)" (offset -2 mm, drift -2 mm over 30 s, low-pass
    10 ms, gain -5 %, depth noise 1 mm, 50 Hz), 30 s. Under 1 mm of depth noise it reads 26 % from its first second
    (clean, the same foot reads 17-18 %; offset 0 or +3 mm, it reads wet either way), with an interval of 18 points
    whose dry end left the truth out by up to 0.7 points from 3.00 to 3.42 s, unflagged (22 samples), after its end
    stepped from the grid's 14.75 % to 16.87 % in one sample at 2.76 s. With the end moved in proportion between
    ``_END_REACH_FROM`` and ``_END_REACH`` it misses none; the estimate is the same."""
    t, r = _covered_unflagged("robot_shallow_dry_standard_all_minus_seed90.csv", 0.1664156855131229)  # 1351 samples
    assert np.median(r.water_content[t >= 3.0]) == pytest.approx(0.1768, abs=0.002)  # measured 17.68 %


def test_a_wide_early_interval_holds_the_hull() -> None:
    """The sensor-chain bench's seed 103, ``robot`` 6: the MuJoCo quadruped's foot (a 50 mm disc, a bound) standing
    about 2 mm deep in W = 15.01 % mud (the grid's dry end), MuJoCo's force, through "standard, all (-)" (offset -2 mm,
    drift -2 mm over 30 s, low-pass 10 ms, gain -5 %, depth noise 1 mm, 50 Hz), 30 s. It reads 26 % from its first
    contact, with an interval of about [19.8, 32.3] % before the hull at 3.0-3.7 s. The hull's low end relaxed
    toward it from 15.2 % and left the truth out by up to 1.75 points at 3.44-3.68 s, unflagged (15 samples). An
    interval wider than half the grid now holds the hull in the stream's first ``_HULL_HOLD`` seconds of contact;
    the estimate is the same."""
    assert tracker_layout._HULL_HOLD == 3.0 and tracker_layout._HULL_WIDE == 0.5
    t, r = _covered_unflagged("robot_shallow_dry_standard_all_minus_seed103.csv", 0.1500968698063424)  # 1351
    held = (t >= 3.4) & (t <= 3.7)
    assert np.max(r.low[held]) < 0.1495  # measured: the grid's 14.75 %, and 14.92 % from 3.66 s (16.38 % before)
    assert np.median(r.water_content[held]) == pytest.approx(0.258, abs=0.002)  # measured 25.8 %: the same estimate


def test_a_clean_deep_walk_s_early_interval_is_not_held() -> None:
    """A clean walk 1-3 cm deep narrows under half the grid within about a second of contact: the hold of a wide
    early interval (``_HULL_HOLD``) leaves its reported interval as before (measured the same to 0.1 points at 1, 2,
    3 and 4 s)."""
    wk = walk(0.25, seed=3, duration=4.0, force_noise=0.2, bias=0.5)
    r = track(wk.time, wk.depth, wk.force)
    at = np.searchsorted(wk.time, [2.0, 3.0, 4.0 - 1e-9])
    assert r.low[at] == pytest.approx([0.214, 0.227, 0.232], abs=0.001)
    assert r.high[at] == pytest.approx([0.286, 0.273, 0.268], abs=0.001)


def test_a_shallow_foot_under_a_drifting_surface_is_not_left_out() -> None:
    """The sensor-chain bench's fresh seed 110, ``robot-model`` 4: the model's force along the MuJoCo quadruped's foot
    (a 50 mm disc) sinking 3.5-5.5 mm into W = 19.66 % mud, through "drift +2 mm / 30 s" (100 Hz), 30 s. The surface
    offset is read on the 0-mm hypothesis throughout while the surface drifts 1.6 mm by 24.6 s: more than half the
    3-mm step between two hypotheses, which the shallow widening held as the offset's resolution. The estimate drifts
    3 points dry, and with ``s`` at 4 times the ratio the interval's wet end left the truth out by up to 0.11 points
    at 24.63-25.03 s, unflagged (42 samples). At 4.5 times it misses none; the estimate is the same."""
    assert tracker_layout._SHALLOW_WIDENING == 4.5
    truth = 0.19664954190323725
    t, r = _covered_unflagged("robot_model_shallow_drift_plus_2mm_seed110.csv", truth)  # all 2701 samples after 3 s
    at = (t >= 24.6) & (t <= 25.05)
    assert np.min(r.high[at]) > truth + 0.001  # measured: the wet end at least 20.67 % there (19.55 % at 4 times)
    assert np.median(r.water_content[at]) == pytest.approx(0.168, abs=0.002)  # measured 16.8 %: the same estimate
