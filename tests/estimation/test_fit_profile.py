"""fit's standard errors where the cost is not quadratic: the profile likelihood widens them (issue 23).

At 50 Hz the withdrawal relaxation b_m_w / k_m_w is barely seen before the
neck breaks: the cost rises steeply below the best b_m_w and hardly at all
above it. The Jacobian's standard error then excluded the truth by 8 of
them, with no warning.
"""

from __future__ import annotations

from mudforce.estimation.calibration import FitOptions, fit_condition, synthesize
from mudforce.model.parameters import MudParameters

FAST = FitOptions(popsize=10, maxiter=40)


def test_b_m_w_at_50_hz_is_within_3_standard_errors_or_warned() -> None:
    ds = synthesize(water_contents=[0.3], velocities=[0.01, 0.02], repeats=1, seed=4, rate=50.0)
    fit = fit_condition(ds.trials, ds.foot, seed=0, options=FAST)
    truth = MudParameters.table_i(0.3).to_dict()
    for n in fit.free:
        se = fit.stderr[n]
        assert se is not None
        off = abs(fit.parameters[n] - truth[n]) / se
        warned = any(w.startswith(n + " ") for w in fit.warnings)
        assert off < 3.0 or warned, f"{n}: {fit.parameters[n]:.4g} +- {se:.3g}, truth {truth[n]:.4g}"
    # the value the Jacobian alone gave (0.49e6 +- 0.11e6, 8 s.e. from 1.4e6) is kept; only its error widens
    assert fit.parameters["b_m_w"] < 0.8e6
    assert fit.stderr["b_m_w"] > 0.3e6
    assert any(w.startswith("b_m_w is poorly determined") for w in fit.warnings)
