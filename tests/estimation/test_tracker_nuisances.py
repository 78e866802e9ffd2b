"""MudTracker on what a robot records (issue 23): a foot at rest is a band, not a branch; the misfit flag."""

from __future__ import annotations

import numpy as np
import pytest

from mudforce.estimation.tracker import MISFIT_THRESHOLD, MudTracker, track
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import walk
from mudforce.steppers.simulation import simulate


def _press_and_hold(cycles: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """100 Hz: each cycle presses the foot 20 mm in over 0.4 s, holds it still 1 s, lifts it out and waits."""
    parts = []
    for _ in range(cycles):
        parts += [np.zeros(20), np.linspace(0.0, 0.02, 40), np.full(100, 0.02), np.linspace(0.02, -0.01, 30),
                  np.full(20, -0.01)]
    z = np.concatenate(parts)
    return np.arange(z.size) * 0.01, z


def test_a_foot_at_rest_carries_any_load_in_the_band() -> None:
    # while held still, the foot carries half the intrusion branch's force (inside the rest band): an engine's
    # stuck foot. Read as the branch, that is softer mud; read as the band, it says nothing against the truth.
    t, z = _press_and_hold()
    mud = MudParameters.from_water_content(0.25)
    force = np.asarray(simulate(t, z, mud, Foot.paper(), velocity_filter="exact").force)
    held = np.concatenate([[False], np.diff(z) == 0.0]) & (z > 0.0)
    force = np.where(held, 0.5 * force, force)
    r = track(t, z, force, velocity_filter="exact")
    assert r.low[-1] <= 0.25 <= r.high[-1]
    assert abs(r.water_content[-1] - 0.25) <= 0.015
    assert r.misfit is not None and not r.misfit.any()


def test_misfit_flag_quiet_in_family_and_fires_on_a_gross_miss() -> None:
    w = walk(0.25, seed=3, duration=8.0, force_noise=0.2, bias=0.5)
    ok = track(w.time, w.depth, w.force)
    assert ok.misfit is not None and not ok.misfit.any()
    # a force that has nothing to do with the depth: constant 40 N whenever the foot is in the mud
    wrong = np.where(w.depth > 0.0, 40.0, 0.0) + 0.5
    bad = track(w.time, w.depth, wrong)
    assert bad.misfit is not None and bad.misfit[-1]
    assert MISFIT_THRESHOLD > 1.0


def test_estimate_carries_the_flag() -> None:
    tracker = MudTracker()
    e = tracker.update(0.0, 0.0, 0.01)
    assert e.misfit is False
    with pytest.raises(AttributeError):
        e.misfit = True  # type: ignore[misc]


def test_interval_widens_with_the_misfit_average() -> None:
    """A misfit average above its reference widens the reported interval (a scale mixture), not the change flag's."""
    import dataclasses

    from mudforce.estimation import _tracker_layout as tracker_layout
    from mudforce.estimation import tracker as T
    from mudforce.motions.gait import walk

    wk = walk(0.25, seed=3, duration=6.0, force_noise=0.2, bias=0.5)
    tracker = T.MudTracker()
    previous = wk.time[0]
    for t, z, f in zip(wk.time.tolist()[:-1], wk.depth.tolist()[:-1], wk.force.tolist()[:-1], strict=True):
        tracker.update(z, f, t - previous)
        previous = t
    state = tracker.state
    last = (float(wk.depth[-1]), float(wk.force[-1]), float(wk.time[-1] - previous))
    plain = tracker.update(*last)
    aux = np.array(state.aux)
    for ratio, factor in ((1.0, 1.0), (9.0 * tracker_layout._MISFIT_BLUR_REF, 3.0)):
        aux[0, tracker_layout._A_MISFIT] = ratio
        tracker.state = dataclasses.replace(state, aux=aux)
        est = tracker.update(*last)
        if factor == 1.0:
            assert (est.low, est.high) == (plain.low, plain.high)  # nothing widened below the reference
        else:  # the blur's spread x3: the interval about three times wider (the fit's own width adds a little)
            assert 2.5 * (plain.high - plain.low) <= est.high - est.low <= 3.2 * (plain.high - plain.low)
            assert est.low <= plain.low and est.high >= plain.high
