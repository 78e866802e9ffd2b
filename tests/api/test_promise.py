"""README's promise section states the bounds the code enforces (and the code enforces them)."""

from __future__ import annotations

import re
from pathlib import Path

from mudforce._kernel.bounds import MAX_HORIZONTAL
from mudforce.cli.synth import DEPTH_NOISE_SIGMAS, MAX_BIAS, MAX_FORCE_NOISE, MAX_SAMPLES, MAX_TRIALS
from mudforce.estimation.calibration.models import CHEN2024
from mudforce.io.tables import COLUMN_LIMITS
from mudforce.model.foot import AREA_RANGE, SIZE_RANGE
from mudforce.model.law3d import MAX_LATERAL_STIFFNESS
from mudforce.model.parameters import PARAMETER_RANGES, TABLE_I
from mudforce.steppers.simulation import MAX_DEPTH, MAX_DT, MIN_DT

README = Path(__file__).resolve().parents[2] / "README.md"


def _f(x: float) -> str:
    """A number as the README writes it: ``100``, ``1e-9``, ``1e12``."""
    if x == 0 or 1e-2 <= abs(x) < 1e3:
        return f"{x:g}"
    mantissa, exponent = f"{x:.0e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _section() -> str:
    text = README.read_text(encoding="utf-8")
    start = text.index("### The promise")
    return text[start:text.index("\n## ", start)]


def test_promise_states_the_bounds_in_force() -> None:
    section = _section()
    assert f"within ±{_f(MAX_DEPTH)} m" in section
    assert f"{_f(MIN_DT)} s to {_f(MAX_DT)} s" in section
    assert f"{_f(SIZE_RANGE[0])} m to {_f(SIZE_RANGE[1])} m" in section
    assert f"{_f(AREA_RANGE[0])} m² to {_f(AREA_RANGE[1])} m²" in section
    assert f"within ±{_f(MAX_HORIZONTAL)} m of the world origin" in section
    assert all(COLUMN_LIMITS[f"position {axis}"] == MAX_HORIZONTAL for axis in "xyz")  # the readers' bound
    assert f"within {_f(SIZE_RANGE[1])} m of the body origin, of area at most {_f(AREA_RANGE[1])} m²" in section
    assert f"above 0 up to {_f(MAX_LATERAL_STIFFNESS)} Pa/m" in section
    rows = {
        ("k_m_i", "b_m_i", "k_m_w", "b_m_w"): "{lo} to {hi} (SI)",
        ("alpha",): "{lo} Pa to {hi} Pa /",
        ("beta",): "/ {lo} to {hi} |",
        ("sigma_y",): "{lo} Pa to {hi} Pa",
        ("zeta",): "{lo} to {hi} /",
        ("omega_0",): "{lo} rad/s to {hi} rad/s",
        ("rho_m",): "{lo} to {hi} kg/m³",
        ("lambda",): "/ {lo} to {hi} |",
    }
    for names, pattern in rows.items():
        for name in names:
            lo, hi = PARAMETER_RANGES[name]
            text = pattern.format(lo=_f(lo), hi=_f(hi))
            assert text in section, (name, text)
    for quantity, unit in (("time", "s"), ("depth", "m"), ("force", "N"), ("velocity", "m/s")):
        assert re.search(rf"\\\|{quantity}\\\| <= {_f(COLUMN_LIMITS[quantity])} {re.escape(unit)}\b", section), quantity
    assert f"{MAX_TRIALS}" in section and f"{MAX_SAMPLES // 1_000_000} million samples" in section
    words = " ".join(section.split())  # the prose, line breaks aside
    assert f"force noise at most {_f(MAX_FORCE_NOISE)} N, a bias within ±{_f(MAX_BIAS)} N" in words
    assert f"depths plus {DEPTH_NOISE_SIGMAS} standard deviations" in words


def test_table_i_and_the_fitters_box_lie_inside_the_bounds() -> None:
    """Every Table I value and every value the fit explores is a valid parameter."""
    for params in TABLE_I.values():
        for name, value in params.to_dict().items():
            lo, hi = PARAMETER_RANGES[name]
            assert lo <= value <= hi, name
    for name, (lo, hi) in CHEN2024.bounds.items():
        plo, phi = PARAMETER_RANGES[name]
        # the fit works on logarithms: its bounds must survive exp(log(bound)) rounding
        assert (plo < lo * (1 - 1e-12) and hi * (1 + 1e-12) <= phi) or (name == "beta" and hi == phi == 1.0), name
