"""A reused work for the compiled batch loop (``simulation.CompactRun``) gives a fresh run's numbers, bit for bit.

The fit runs one trajectory tens of thousands of times on work arrays made
once; each run must give exactly what :func:`simulation.run_compact` (fresh
arrays) gives, whatever the runs before it left there: other constants, a
refused sample, another filter window.
"""

from __future__ import annotations

import numpy as np

import mudforce as mf
from mudforce import _kernel as K
from mudforce.estimation.calibration.models import CHEN2024, _chen_force, _chen_row, trajectory_force
from mudforce.steppers import simulation as S

FOOT = mf.Foot.paper()


def _rows(window: int) -> list[np.ndarray]:
    rows = []
    for w in (0.15, 0.25, 0.35, 0.25):  # the last repeats the second: a run after others gives the same
        values = mf.MudParameters.from_water_content(w).as_array()
        rows.append(K.make_params(values, FOOT.area, FOOT.width, window, 0.0)[None, :])
    return rows


def _same(work: S.CompactRun, bad: int, fresh: tuple[int, np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    assert bad == fresh[0]
    end = bad if bad >= 0 else work.time.size  # valid before a refused sample
    for mine, theirs in zip((work.force, work.state, work.mud), fresh[1:4], strict=True):
        assert mine[:end].tobytes() == theirs[:end].tobytes()
    assert work.necking_times().tobytes() == fresh[4].tobytes()


def test_a_reused_work_gives_a_fresh_runs_numbers() -> None:
    t, z = mf.Protocol.paper().sample()
    short = slice(0, t.size // 3)
    for window in (1, 4):  # the exact rule, and a filter with a velocity history to reset
        works = [S.CompactRun(t, z, window), S.CompactRun(t[short], z[short], window)]  # two lengths
        for row in _rows(window):
            for work in works:
                _same(work, work.run(row), S.run_compact(work.time, work.depth, row, window))
        assert works[0].necking_times().size  # the paper's trial necks: its times are compared


def test_a_refused_sample_leaves_nothing_behind() -> None:
    t, z = mf.Protocol.paper().sample()
    z_bad = z.copy()
    z_bad[z.size // 2] = np.nan
    bad_work, good_work = S.CompactRun(t, z_bad, 1), S.CompactRun(t, z, 1)
    for row in _rows(1):
        bad = bad_work.run(row)
        assert bad == z.size // 2
        _same(bad_work, bad, S.run_compact(t, z_bad, row, 1))
        _same(good_work, good_work.run(row), S.run_compact(t, z, row, 1))


def test_trajectory_force_is_the_models_force() -> None:
    """The fit's force along one trajectory (work arrays, the refused samples' 1e6) is ``CHEN2024.force``'s."""
    t, z = mf.Protocol.paper().sample()
    z_bad = z.copy()
    z_bad[z.size // 2] = np.nan
    for depth in (z, z_bad, z):
        force = trajectory_force(CHEN2024, FOOT, t, depth)
        for w in (0.15, 0.35, 0.15):
            values = CHEN2024.vector(mf.MudParameters.from_water_content(w).to_dict())
            assert force(values).tobytes() == _chen_force(t, depth, values, FOOT).tobytes()


def test_the_kept_constants_are_the_vectors_own() -> None:
    """``models._chen_row`` keeps the last vector's row: every vector and foot, in any order, gets its own."""
    feet = (FOOT, mf.Foot.disc(0.05))
    for w, foot in ((0.15, FOOT), (0.15, FOOT), (0.35, FOOT), (0.15, feet[1]), (0.15, FOOT), (0.35, feet[1])):
        values = mf.MudParameters.from_water_content(w).as_array()
        expected = K.make_params(values, foot.area, foot.width, 1, 0.0)
        assert _chen_row(values, foot).tobytes() == expected.tobytes()
