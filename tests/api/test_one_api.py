"""One API: every result has ``to_pandas``/``to_csv``/``plot`` where they make sense, and every stateful object
saves and restores its state one way, ``.state`` (read a read-only snapshot; assign it back to restore).

Cheap on purpose: short walks and drops; the numbers themselves are tested where they are made.
"""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mudforce import InputError, MudContact, MudContacts, MudParameters, MudTracker, MudTrackers, simulate
from mudforce.engines.dynamics import FootResult, NaiveDrop, naive_drop, simulate_foot
from mudforce.estimation.tracker import TrackerState, TrackResult, track
from mudforce.motions.gait import walk

W25 = MudParameters.from_water_content(0.25)


@pytest.fixture(scope="module")
def tracked() -> TrackResult:
    w = walk(0.25, seed=1, duration=3.0, force_noise=0.3, bias=0.5)
    return track(w.time, w.depth, w.force)


def test_track_result_to_csv_is_the_track_command_s_file(tracked: TrackResult, tmp_path: Path) -> None:
    from mudforce.cli.track import COLUMNS

    assert TrackResult.COLUMNS == COLUMNS
    path = tmp_path / "t.csv"
    tracked.to_csv(path)
    lines = path.read_text().splitlines()
    assert lines[0] == ",".join(COLUMNS) and len(lines) == tracked.time.size + 1
    k = tracked.time.size // 2
    row = lines[1 + k].split(",")
    assert [float(x) for x in row[:6]] == [tracked.time[k], tracked.water_content[k], tracked.low[k],
                                           tracked.high[k], tracked.force_predicted[k], tracked.force[k]]
    assert row[6] == str(int(tracked.changed[k])) and row[7] == str(int(tracked._misfit()[k]))
    with pytest.raises(InputError, match="path must be a file path"):
        tracked.to_csv(3)  # type: ignore[arg-type]


def test_track_result_to_pandas_and_plot(tracked: TrackResult, tmp_path: Path) -> None:
    pytest.importorskip("pandas")
    df = tracked.to_pandas()
    assert list(df.columns) == list(TrackResult.COLUMNS)
    assert np.array_equal(df["water_content_low"].to_numpy(), tracked.low)
    pytest.importorskip("matplotlib")
    fig = tracked.plot(tmp_path / "t.png", title="walk")
    assert (tmp_path / "t.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and len(fig.axes) == 2
    with pytest.raises(InputError, match="path must be a file path"):
        tracked.plot(3)  # type: ignore[arg-type]


def test_track_result_says_whether_the_model_missed_and_whether_the_interval_reaches_the_family_s_end(
        tracked: TrackResult) -> None:
    """The misfit flag over the recording and the family's edge were worked out by `mudforce track`'s summary alone: a
    Python user of track() saw neither (a force of noise alone: 34.0 % [27.1, 35.2], flagged on 70 % of the samples).
    Now model_misses_data and family_edge, against the ends of the grid the tracker ran on."""
    assert not tracked.model_misses_data and tracked.family_edge == ""
    assert tracked.water_content_range == (0.15, 0.35)
    told_little = track([0.0, 0.01], [0.0, 0.0], [0.0, 0.0], water_contents=[0.2, 0.25, 0.3])
    assert told_little.water_content_range == (0.2, 0.3) and told_little.family_edge == "both"


def test_foot_result_to_pandas_has_the_csv_columns(tmp_path: Path) -> None:
    pytest.importorskip("pandas")
    res = simulate_foot(5.0, W25, duration=0.05, height=0.001)
    assert isinstance(res, FootResult)
    res.to_csv(tmp_path / "f.csv")
    header = (tmp_path / "f.csv").read_text().splitlines()[0].split(",")
    df = res.to_pandas()
    assert list(df.columns) == header == ["time_s", "depth_m", "velocity_m_s", "force_N", "state"]
    assert np.array_equal(df["force_N"].to_numpy(), res.force) and df["state"].tolist() == res.phase_names


def test_naive_drop_is_a_result_that_unpacks_as_before(tmp_path: Path) -> None:
    res = naive_drop(5.0, W25, duration=0.02)
    assert isinstance(res, NaiveDrop)
    t, z, f = res
    assert t is res.time and z is res.depth and f is res.force and t.size == 20
    res.to_csv(tmp_path / "n.csv")
    lines = (tmp_path / "n.csv").read_text().splitlines()
    assert lines[0] == "time_s,depth_m,force_N" and len(lines) == 21
    assert [float(x) for x in lines[-1].split(",")] == pytest.approx([t[-1], z[-1], f[-1]], rel=1e-11)
    # height [m] above the surface, as every drop's start: the foot falls freely before it touches
    high = naive_drop(5.0, W25, duration=0.02, height=0.01)
    assert high.depth[0] < 0.0 and np.all(high.force[high.depth <= 0.0] == 0.0)
    pytest.importorskip("pandas")
    assert list(res.to_pandas().columns) == ["time_s", "depth_m", "force_N"]


def test_drops_start_at_height_everywhere() -> None:
    """The same argument has the same name and meaning: ``height`` [m] above the surface, ``dt`` [s]."""
    from mudforce.engines.dynamics import exact_drop

    functions = [simulate_foot, naive_drop, exact_drop]
    for module in ("mudforce.engines.mujoco", "mudforce.engines.mjx"):
        try:
            functions.append(__import__(module, fromlist=["simulate_drop"]).simulate_drop)
        except ImportError:
            pass
    for fn in functions:
        names = list(inspect.signature(fn).parameters)
        assert names[:3] == ["mass", "params", "foot"], fn
        assert "height" in names and "dt" in names and "timestep" not in names, fn
    assert simulate_foot(5.0, W25, duration=0.01, height=0.02).depth[0] == -0.02


def test_every_stateful_object_saves_and_restores_through_state() -> None:
    one = MudContact(W25)
    many = MudContacts(W25, 2)
    for z in (0.0, 0.002, 0.004):
        one.step(z, 0.01)
        many.step(np.array([z, z / 2]), 0.01)
    saved_one, saved_many = one.state, many.state
    with pytest.raises(ValueError, match="read-only"):
        saved_many[0, 0] = 1.0
    a, b = one.step(0.005, 0.01), many.step(np.array([0.005, 0.003]), 0.01)
    one.state, many.state = saved_one, saved_many
    assert one.step(0.005, 0.01) == a and np.array_equal(many.step(np.array([0.005, 0.003]), 0.01), b)


def _walked_tracker(samples: int) -> tuple[Any, np.ndarray, MudTracker]:
    """A 2-s walk in 22 % mud, its time steps [s], and a tracker updated with its first ``samples`` samples."""
    w = walk(0.22, seed=2, duration=2.0, force_noise=0.3)
    tracker = MudTracker()
    dt = np.diff(w.time, prepend=w.time[0])
    for k in range(samples):
        tracker.update(w.depth[k], w.force[k], dt[k])
    return w, dt, tracker


def test_tracker_state_replays_exactly_and_a_refused_restore_changes_nothing() -> None:
    w, dt, tracker = _walked_tracker(100)
    saved = tracker.state
    assert isinstance(saved, TrackerState) and saved.started
    first = [tracker.update(w.depth[k], w.force[k], dt[k]) for k in range(100, 150)]
    tracker.state = saved
    assert [tracker.update(w.depth[k], w.force[k], dt[k]) for k in range(100, 150)] == first
    before = tracker.state
    other = MudTrackers(1, water_contents=[0.2, 0.3]).state
    for bad in (None, other, saved.bank):
        with pytest.raises(InputError, match="TrackerState"):
            tracker.state = bad  # type: ignore[assignment]
    bank = np.array(before.bank)
    bank[0, 1] = 7.0  # a contact mode the stepper never makes
    garbage = TrackerState(bank, before.log_posterior, before.posterior, before.aux, True, before.key,
                           before.twin)
    with pytest.raises(InputError, match="expected a state taken from a contact"):
        tracker.state = garbage
    after = tracker.state
    for name in ("bank", "log_posterior", "posterior", "aux"):
        assert np.array_equal(getattr(after, name), getattr(before, name), equal_nan=True), name
        # the twin bank's (restored first, then put back when the first bank's restore is refused)
        assert np.array_equal(getattr(after.twin, name), getattr(before.twin, name), equal_nan=True), name
    # many feet: the same protocol
    feet = MudTrackers(2)
    feet.update([0.0, 0.0], [0.1, 0.2], 0.01)
    snap = feet.state
    x = feet.update([0.001, 0.002], [1.0, 2.0], 0.01)
    feet.state = snap
    y = feet.update([0.001, 0.002], [1.0, 2.0], 0.01)
    assert np.array_equal(x.water_content, y.water_content) and np.array_equal(x.low, y.low)


def test_a_tracker_state_no_update_makes_is_refused_and_changes_nothing() -> None:
    """Restored tracker states are checked as strictly as fresh ones: a posterior that is not a distribution (its
    quantiles were taken as they were: a silently wrong estimate), a negative variance or time, a lag off the
    hypotheses' range, an anchor outside its interval, or the reported interval's hull with its ends crossed (or,
    in the twin, which keeps none, one end set) is refused, for the first bank and the twin alike."""
    from mudforce.estimation import _tracker_layout as tracker_layout

    _, _, tracker = _walked_tracker(150)
    before = tracker.state
    assert not np.isnan(before.aux[0, tracker_layout._A_ANCHOR])  # an anchor is set, so its interval is checked

    def edited(state: TrackerState, name: str, column: int | None, value: float) -> TrackerState:
        arrays = {key: np.array(getattr(state, key)) for key in ("posterior", "aux")}
        if column is None:
            arrays[name][0, :2] = (value, 1.0 - value - arrays[name][0, 2:].sum())  # still sums to 1
        else:
            arrays[name][0, column] = value
        return TrackerState(state.bank, state.log_posterior, arrays["posterior"], arrays["aux"], state.started,
                            state.key, state.twin)

    cases = [("posterior", None, -0.25, "posterior is not probabilities"),
             ("aux", tracker_layout._A_VAR, -1.0, "force noise variance is negative"),
             ("aux", tracker_layout._A_CONTACT, -1.0, "contact time is negative"),
             ("aux", tracker_layout._A_LAG, 0.5, "force lag is not within"),
             ("aux", tracker_layout._A_QUICK, 0.5, "branch rule flag is not 0 or 1"),
             ("aux", tracker_layout._A_ANCHOR_HIGH, before.aux[0, tracker_layout._A_ANCHOR] - 0.01,
              "anchor lies outside its interval"),
             ("aux", tracker_layout._A_HULL_LOW, before.aux[0, tracker_layout._A_HULL_HIGH] + 0.01,
              "hull has its ends crossed")]
    for name, column, value, message in cases:
        with pytest.raises(InputError, match=message):
            tracker.state = edited(before, name, column, value)
        assert before.twin is not None
        with pytest.raises(InputError, match=message):
            tracker.state = TrackerState(before.bank, before.log_posterior, before.posterior, before.aux,
                                         before.started, before.key, edited(before.twin, name, column, value))
        after = tracker.state
        for key in ("bank", "log_posterior", "posterior", "aux"):
            assert np.array_equal(getattr(after, key), getattr(before, key), equal_nan=True), key
            assert np.array_equal(getattr(after.twin, key), getattr(before.twin, key), equal_nan=True), key
    tracker.state = before  # its own state is accepted


@pytest.mark.parametrize("title", [pytest.param(10**5000, id="10**5000"), np.zeros((2, 2)), b"walk"])
def test_a_plot_title_that_is_not_a_str_is_refused_in_one_line(tracked: TrackResult, title: Any) -> None:
    """``if title:`` raised numpy's ValueError (truth value ambiguous) for an array, matplotlib's str() of 10**5000
    ValueError (4300 digits), and bytes were drawn as "b'walk'": each is refused before anything is drawn."""
    from mudforce import Protocol

    time, depth = Protocol.paper().sample()
    for plot in (simulate(time, depth, W25).plot, tracked.plot,
                 simulate_foot(5.0, W25, duration=0.05, height=0.001).plot):
        with pytest.raises(InputError, match=r"^title must be a str or None, got "):
            plot(title=title)


def test_a_plot_of_a_result_of_another_kind_is_refused_in_one_line(tracked: TrackResult) -> None:
    """plot_result of a TrackResult, a dict or None, and plot_track of a SimulationResult, were AttributeErrors ('dict'
    object has no attribute 'time', no attribute 'changed'): each is refused before anything is drawn."""
    from mudforce import Protocol
    from mudforce.estimation.tracking_plots import plot_track
    from mudforce.steppers.plots import plot_result

    time, depth = Protocol.paper().sample()
    simulated = simulate(time, depth, W25)
    for wrong in (tracked, {"time": time}, None):
        with pytest.raises(InputError, match=r"^result must be a SimulationResult \(from mudforce.simulate\), got "):
            plot_result(wrong)  # type: ignore[arg-type]
    for wrong in (simulated, None):
        with pytest.raises(InputError, match=r"^result must be a TrackResult \(from .*\), got [A-Za-z]+$"):
            plot_track(wrong)  # type: ignore[arg-type]


def test_a_plot_to_a_name_that_is_no_png_is_refused_in_one_line(tracked: TrackResult, tmp_path: Path) -> None:
    """plot_result, plot_track (and the results' .plot) and tracking_figure wrote PNG bytes into a.pdf, fig.svg or
    a name without a suffix; each is refused before anything is drawn (tracking_figure: before its walk)."""
    from mudforce import Protocol
    from mudforce.estimation.tracking_plots import tracking_figure

    time, depth = Protocol.paper().sample()
    simulated = simulate(time, depth, W25)
    for plot in (simulated.plot, tracked.plot, tracking_figure):
        for name in ("a.pdf", "fig.svg", "figure"):
            with pytest.raises(InputError, match=rf"^path: '.*{name}' must end in .png \(only PNG is written\)$"):
                plot(tmp_path / name)
    assert list(tmp_path.iterdir()) == []


def test_a_tracking_plot_s_truth_and_water_contents_are_checked_in_one_line(tracked: TrackResult) -> None:
    """plot_track's truth of another length than the result's was matplotlib's ValueError ('x and y must have same
    first dimension', not naming truth), a str truth 'could not convert string to float'; tracking_figure's
    water_content=0.25 a TypeError ('float' object is not iterable), "ab" a ValueError: each now names its argument,
    before anything is drawn or simulated."""
    from mudforce.estimation.tracking_plots import plot_track, tracking_figure

    n = tracked.time.size
    for truth, got in ((np.ones(5), r"got shape \(5,\)"), (0.25, r"got shape \(\)")):
        with pytest.raises(InputError, match=rf"^truth must hold one water content per sample \[-\], shape \({n},\), "
                                             rf"{got}$"):
            plot_track(tracked, truth=truth)
    with pytest.raises(InputError, match=r"^truth must be an array of real numbers \[-\], got str"):
        plot_track(tracked, truth="a")
    with pytest.raises(InputError, match=r"^water_content must be a sequence of water contents \[-\] \(before and "
                                         r"after the change\), got shape \(\)$"):
        tracking_figure(water_content=0.25)  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"^water_content must be an array of real numbers \[-\], got str"):
        tracking_figure(water_content="ab")  # type: ignore[arg-type]
