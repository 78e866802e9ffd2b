"""FamilyCheck: identify's misfit flag online, on the last window of a stream (issue 23, point 4 online).

Each verdict is identify's on the window's samples (the same bits); the window is the last ``window`` seconds and
back to the foot's highest sample in the ``every`` seconds before them (checked against a brute force over random
clocks); in-family walks read in the family and a granular law F = kz along the same path off it; a refused sample
changes nothing; ``track(..., family_window=...)`` carries the verdicts per sample.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mudforce.errors import InputError
from mudforce.estimation.calibration import identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.family_check import SWING_CLEARANCE, FamilyCheck, FamilyVerdict, _flags, check_family
from mudforce.estimation.tracker import track
from mudforce.motions.gait import walk


def _window(clock: list[float], depth: list[float], window: float, whole: bool = True) -> tuple[int, int] | None:
    """The brute force: the window's first and one-past-last sample index in the whole stream so far (None: no
    start), from the rule's words in FamilyCheck.samples."""
    now = clock[-1]
    lead = [i for i, c in enumerate(clock) if now - 2.0 * window < c <= now - window]
    younger = all(c > now - window for c in clock)
    opens = whole and depth[0] <= 0.0 and (younger or (bool(lead) and lead[0] == 0))
    for last in reversed(lead):
        if last + 1 < len(depth) and depth[last] <= 0.0 < depth[last + 1]:
            top = last
            while top - 1 in lead and depth[top - 1] <= 0.0:
                top -= 1
            if min(depth[top:last + 1]) <= -SWING_CLEARANCE:
                return last, len(clock)
    return (0, len(clock)) if opens else None


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.floats(1e-3, 0.4), st.floats(-0.02, 0.02)), min_size=1, max_size=600),
       st.floats(0.05, 3.0), st.floats(0.01, 2.0))
def test_the_window_is_the_last_seconds_back_to_the_last_swing_s_top(
        samples: list[tuple[float, float]], window: float, every: float) -> None:
    check = FamilyCheck(window=window, every=every)
    clock: list[float] = []
    depth: list[float] = []
    for k, (dt, z) in enumerate(samples):
        check.push(z, 0.5 * k, dt)
        clock.append(0.0 if k == 0 else clock[-1] + dt)  # the stream's clock, summed in the same order
        depth.append(z)
        t, zz, ff = check.samples()
        span = _window(clock, depth, window)
        if span is None:
            assert t.size == zz.size == ff.size == 0
            continue
        first, end = span
        assert t.tolist() == clock[first:end]
        assert zz.tolist() == depth[first:end]
        assert ff.tolist() == [0.5 * i for i in range(first, end)]
    assert len(check) <= len(samples)


def test_a_check_is_due_at_the_window_then_every_interval() -> None:
    check = FamilyCheck(window=1.0, every=0.25)
    due = [k for k in range(33) if check.push(0.0, 0.0, 0.0625)]  # steps exact in binary: the clock k / 16 s
    # push() only says a check is due, from the clock's reaching the window on; it stays due until check() runs
    assert due == list(range(16, 33))
    check.reset()
    seen = []
    for k in range(33):
        if check.push(0.0, 0.0, 0.0625):
            check._advance_due()  # what check() does after identify
            seen.append(k)
    assert seen == [16, 20, 24, 28, 32]
    check.reset()
    check.push(0.0, 0.0, 0.0)
    assert check.push(0.0, 0.0, 3.3) and (check._advance_due() or check._due == 3.5)  # a gap skips the missed ones


def test_each_verdict_is_identify_s_on_the_window() -> None:
    w = walk(0.22, seed=5, duration=13.0, force_noise=0.2, bias=0.4, rate=50.0)
    checks = check_family(w.time, w.depth, w.force, window=10.0, every=2.5)
    assert [k for k, _ in checks] == [500, 625]  # at 10 s and 12.5 s
    clock = np.concatenate([[0.0], np.cumsum(np.diff(w.time))]).tolist()
    for k, verdict in checks:
        span = _window(clock[:k + 1], w.depth[:k + 1].tolist(), 10.0)
        assert span is not None
        first, end = span
        res = identify_water_content(Trial("window", math.nan, np.array(clock[first:end]), w.depth[first:end],
                                           w.force[first:end]))
        assert verdict.model_misses_data is res.model_misses_data is False
        assert (verdict.water_content, verdict.low, verdict.high) == (res.water_content, *res.interval)
        assert verdict.misfit_ratio == res.misfit_ratio and verdict.samples == end - first
        assert abs(verdict.water_content - 0.22) < 0.01 and verdict.low <= 0.22 <= verdict.high


def test_an_in_family_walk_reads_in_the_family_and_a_granular_law_off_it() -> None:
    w = walk(0.27, seed=8, duration=15.0, force_noise=0.2, bias=-0.3, rate=100.0)
    fine = track(w.time, w.depth, w.force, family_window=10.0, family_every=2.5)
    assert [v.model_misses_data for _, v in fine.family_checks] == [False, False, False]
    assert fine.family_misfit is not None and not fine.family_misfit.any()
    kz = float(np.max(w.force)) / float(np.max(w.depth)) * np.maximum(w.depth, 0.0)
    off = track(w.time, w.depth, kz, family_window=10.0, family_every=2.5)
    assert [v.model_misses_data for _, v in off.family_checks] == [True, True, True]
    first = off.family_checks[0][0]
    assert off.family_misfit is not None
    assert not off.family_misfit[:first].any() and off.family_misfit[first:].all()  # causal: from the check on
    assert off.model_misses_data
    # the tracker's own estimates are the same with the check or without it
    plain = track(w.time, w.depth, kz)
    np.testing.assert_array_equal(plain.water_content, off.water_content)
    assert plain.family_misfit is None and plain.family_checks == ()
    assert "family_misfit" in off.columns() and "family_misfit" not in plain.columns()
    lines = off._csv_text().splitlines()
    assert lines[0].endswith(",force_bias_N,family_misfit") and lines[-1].endswith(",1")
    assert plain._csv_text().splitlines()[0].endswith(",force_bias_N")


def test_a_window_that_tells_nothing_leaves_the_flag_as_it_was() -> None:
    none = FamilyVerdict(1.0, 0.0, 5, None, reason="no contact")
    yes = FamilyVerdict(1.0, 0.0, 5, True)
    no = FamilyVerdict(1.0, 0.0, 5, False)
    assert _flags([(2, yes), (4, none), (6, no)], 8).tolist() == [False, False, True, True, True, True, False, False]
    assert _flags([(0, none), (3, yes)], 5).tolist() == [False, False, False, True, True]
    # a foot that never reaches the mud: identify refuses, the verdict says why
    check = FamilyCheck(window=1.0, every=1.0)
    verdicts = [check.update(-0.01, 0.1 * (k % 3), 0.01) for k in range(120)]
    told = [v for v in verdicts if v is not None]
    assert len(told) == 1 and told[0].model_misses_data is None and told[0].reason


BAD_SAMPLES = [(math.nan, 0.0, 0.01), (0.0, math.inf, 0.01), (1e3, 0.0, 0.01), (0.0, 1e8, 0.01), (0.0, 0.0, 0.0),
               (0.0, 0.0, -0.01), (0.0, 0.0, math.nan), ("1", 0.0, 0.01), (0.0, True, 0.01), (0.0, 0.0, 2e9)]


@pytest.mark.parametrize("sample", BAD_SAMPLES)
def test_a_refused_sample_changes_nothing(sample: tuple[object, object, object]) -> None:
    check = FamilyCheck(window=0.5, every=0.1)
    for k in range(80):
        check.update(0.001 * (k % 7), 0.0, 0.01)
    before = (check.samples(), len(check), check._clock, check._due, check.last)
    with pytest.raises(InputError) as err:
        check.push(*sample)  # type: ignore[arg-type]
    assert "\n" not in str(err.value)
    after = (check.samples(), len(check), check._clock, check._due, check.last)
    assert all(np.array_equal(a, b) for a, b in zip(before[0], after[0], strict=True)) and before[1:] == after[1:]


def test_bad_options_and_a_check_before_any_sample_are_refused_in_one_line() -> None:
    for kwargs, words in (({"window": 0.0}, "family window"), ({"every": math.nan}, "family check interval"),
                          ({"window": 2e9}, "at most"), ({"force_gain_uncertainty": 0.7}, "gain")):
        with pytest.raises(InputError, match=words):
            FamilyCheck(**kwargs)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="no sample yet"):
        FamilyCheck().check()
    with pytest.raises(InputError, match="family window"):
        track([0.0, 0.01], [0.0, 0.0], [0.0, 0.0], family_window=-1.0)
    with pytest.raises(InputError, match="depth at sample 1"):
        check_family([0.0, 0.01], [0.0, 1e3], [0.0, 0.0])
