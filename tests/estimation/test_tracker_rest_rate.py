"""MudTracker reads a foot at rest the same at any rate, and its misfit flag holds both branch rules (issue 23).

The rest test reads the depth's step over at least 10 ms (``_REST_SPAN``): a step's depth noise does not shrink with
the sample interval while the rest speed's allowance (5 mm/s times it) does, so at 1 kHz a foot standing under 30 um
of noise was read as moving on most of its samples and the models' branch forces scored against a load anywhere in
the rest band. The misfit flag is raised where the first bank's average and the twin bank's are both over the
threshold: the family holds both branch rules, as the reported interval does.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mudforce import MudTrackers
from mudforce.estimation._tracker_layout import (
    _A_CONTACT,
    _A_MISFIT,
    _A_MISFIT_T,
    _O_MISFIT,
    _REST_SPAN,
    MISFIT_THRESHOLD,
)
from mudforce.estimation._tracker_step import _rest_step
from mudforce.estimation.tracker import track
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.steppers.simulation import simulate


def _press_and_hold(rate: float, cycles: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Each cycle waits 0.2 s, presses the foot 20 mm in over 0.4 s, holds it still 1 s, lifts it out over 0.3 s."""
    def n(seconds: float) -> int:
        return round(seconds * rate)

    parts = []
    for _ in range(cycles):
        parts += [np.zeros(n(0.2)), np.linspace(0.0, 0.02, n(0.4)), np.full(n(1.0), 0.02),
                  np.linspace(0.02, -0.01, n(0.3)), np.full(n(0.2), -0.01)]
    z = np.concatenate(parts)
    return np.arange(z.size) / rate, z


@pytest.mark.parametrize("rate", [100.0, 1000.0])
def test_a_held_foot_under_depth_noise_reads_the_same_at_100_hz_and_1_khz(rate: float) -> None:
    # held still, the foot carries half the intrusion branch's force (inside the rest band), under 30 um of depth
    # noise and 0.2 N of force noise. At 1 kHz the one-sample rest test read most held samples as moving: 26.62 %
    # at the end for 25 %, where 100 Hz reads 24.97 %; over 10 ms, 25.05 %.
    t, z = _press_and_hold(rate)
    mud = MudParameters.from_water_content(0.25)
    force = np.asarray(simulate(t, z, mud, Foot.paper(), velocity_filter="exact").force)
    held = np.concatenate([[False], np.diff(z) == 0.0]) & (z > 0.0)
    force = np.where(held, 0.5 * force, force)
    rng = np.random.default_rng(5)
    r = track(t, z + rng.normal(0.0, 3e-5, z.size), force + rng.normal(0.0, 0.2, z.size))
    assert abs(r.water_content[-1] - 0.25) < 0.002
    assert np.all((r.low <= 0.25) & (0.25 <= r.high))
    assert not r.model_misses_data


def test_the_rest_test_reads_a_step_of_at_least_10_ms() -> None:
    assert _REST_SPAN == 0.01
    bank = MudTrackers(1, twin=False)
    depths = 0.01 + 1e-4 * np.arange(40)  # 0.1 mm a sample at 1 kHz: 0.1 m/s
    for k, d in enumerate(depths):
        bank._depths[0] = d
        bank._forces[0] = 0.0
        bank._step(1e-3 if k else 1.0)
    ring = bank._bank.ring
    M = bank._P.shape[1]
    step, span = _rest_step(0, 1e-4, 1e-3, ring, M)  # at 1 kHz: the step from the depth 10 samples before
    assert span == pytest.approx(0.01, rel=1e-9) and step == pytest.approx(1e-3, rel=1e-9)
    assert _rest_step(0, 2e-4, 0.01, ring, M) == (2e-4, 0.01)  # at 100 Hz: the sample's own step
    assert _rest_step(0, 2e-4, 0.02, ring, M) == (2e-4, 0.02)
    fresh = MudTrackers(1, twin=False)  # a ring that holds no depth 10 ms old: the sample's own step
    assert _rest_step(0, 3e-5, 1e-3, fresh._bank.ring, M) == (3e-5, 1e-3)


def test_the_misfit_flag_is_raised_only_where_the_twin_bank_s_is_too() -> None:
    t, z = _press_and_hold(100.0, cycles=2)
    force = np.asarray(simulate(t, z, MudParameters.from_water_content(0.25), Foot.paper(),
                                velocity_filter="exact").force)
    k0 = int(np.argmax(z >= 0.02)) + 5  # a sample into the first hold: every model in contact

    def flag_after(first: float, twin: float | None) -> bool:
        bank = MudTrackers(1, twin=twin is not None)
        for k in range(k0):
            bank._depths[0] = z[k]
            bank._forces[0] = force[k]
            bank._step(0.01 if k else 1.0)
        for b, average in ((bank, first), (bank._twin, twin)):
            if b is not None and average is not None:
                b._aux[0, _A_CONTACT] = b._aux[0, _A_MISFIT_T] = 5.0
                b._aux[0, _A_MISFIT] = average
        bank._depths[0] = z[k0]
        bank._forces[0] = force[k0]
        bank._step(0.01)
        if bank._twin is not None:
            assert bool(bank._twin._out[0, _O_MISFIT]) == (twin == high)  # the twin's own flag, on its own average
        return bool(bank._out[0, _O_MISFIT])

    high = 2.0 * MISFIT_THRESHOLD
    assert flag_after(high, high)
    assert not flag_after(high, 0.0)  # the twin bank's rule fits: in the family
    assert not flag_after(0.0, high)  # the first bank's fits
    assert not flag_after(0.0, 0.0)
    assert flag_after(high, None)  # no twin (twin=False): the first bank's flag alone
    assert math.isnan(MudTrackers(1, twin=False)._guard[0, 2])
