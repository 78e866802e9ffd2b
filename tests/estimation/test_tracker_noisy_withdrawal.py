"""Under a noisy depth the bank's branch rule holds its deadband above its secant's noise (issue 23, point 5 online:
never confidently wrong).

The recording (``tests/estimation/data``): the sensor-chain bench's seed 70, gait walk 7 (the paper's cuboid foot),
26.32 % mud, "depth noise 1 mm", 100 Hz, 30 s. The bank steps on the depth's three-sample mean (about 0.58 mm of
noise), whose 10-step secant carries about 8 mm/s of noise, while the rule's deadband is made for 0.03 mm (2.1 mm/s).
At 26.20 s, in a slow withdrawal, the secant read +2.7 mm/s for one sample: every model went from its neck back to
contact and necked again at a 17-mm strain (+16, then -38 N, where the sensor read 1 N), the drier models came back
to the sensor first, and the estimate went 26 -> 19.5 %, its interval leaving the truth out for 1.2 s (120 samples),
unflagged. The deadband is now held at one standard deviation of that noise (``_SMOOTH_DEADBAND_SIGMAS``): none.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mudforce.estimation.tracker import track

TRUTH = 0.26316188294412474  # [-]
DATA = Path(__file__).parent / "data" / "gait_depth_noise_1mm_withdrawal_seed70.csv"


def test_a_noisy_slow_withdrawal_does_not_re_neck_the_models() -> None:
    t, z, f = np.loadtxt(DATA, delimiter=",", skiprows=1, unpack=True)
    r = track(t, z, f)  # the paper's foot
    late = t >= 3.0
    flagged = r.misfit | r.changed
    covered = (r.low <= TRUTH) & (TRUTH <= r.high)
    assert int(np.sum(late & ~covered & ~flagged)) == 0  # measured 0 (120 before)
    withdrawal = (t >= 26.0) & (t <= 27.0)
    assert np.all(np.abs(r.force_predicted[withdrawal]) < 10.0)  # measured at most 4.5 N (52, then -38 N, before)
    assert np.median(r.water_content[t >= 26.0]) == pytest.approx(0.2582, abs=0.005)  # measured 25.82 %
