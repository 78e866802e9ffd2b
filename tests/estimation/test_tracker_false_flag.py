"""A false change flag does not leave a narrow interval clear of the truth (issue 23, point 5 online).

The recording (``tests/estimation/data``): the sensor-chain bench's fresh seed 64, the MuJoCo robot's foot 2 with the
model's force, 18.56 % mud, the depth read 2 mm shallow, 100 Hz. The foot sinks under 5 mm; the posterior flips
between a dry and a wet mode, and at 24.33 s the change flag fires at the wet one (a false flag: the mud never
changes). The reported interval was the hull of the last second of intervals, started afresh at a flag: 60 samples
after it (0.6 s) read [22.9, 35.25] % with nothing flagged, confidently wrong. The hull now holds through a flag and
forgets in its own time: 4 samples; and since 2026-12-03 it holds its ends unrelaxed for its own time after the
estimate jumps from one mode to the other (``_HULL_JUMP``): none.
"""

from __future__ import annotations

import numpy as np

from mudforce.estimation.calibration import load_trial
from mudforce.estimation.tracker import track
from robot_recording import DATA, ROBOT_FOOT

TRUTH = 0.18556556357710352  # [-]


def test_a_false_flag_keeps_the_interval_it_had() -> None:
    trial = load_trial(DATA / "robot_model_shallow_offset_minus2mm_false_flag_seed64.csv", TRUTH)
    r = track(trial.time, trial.depth, trial.force, ROBOT_FOOT)
    flags = np.flatnonzero(r.changed)
    assert trial.time[flags].tolist() == [24.33]  # the false flag (the mud never changes)
    assert r.low[flags[0]] <= TRUTH <= r.high[flags[0]]  # the interval at the flag still holds the truth
    late = trial.time >= 3.0
    wrong = late & ~((r.low <= TRUTH) & (TRUTH <= r.high)) & ~r.changed & ~r.misfit
    assert int(wrong.sum()) == 0  # measured 0 since the hull holds its ends after a jump of the estimate
    # (_HULL_JUMP); 4 before (0.04 s, 0.57 s after the flag); 60 when the hull started afresh
