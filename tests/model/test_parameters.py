"""Parameter sets: Table I, interpolation, validation, JSON round trip; the foot."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mudforce import TABLE_I, Foot, InputError, MudParameters
from mudforce.model.parameters import PARAMETER_NAMES, TABLE_I_WATER_CONTENTS

# Table I of Chen, Yi & Shan (2024), W = 25 %, converted by hand to SI
# (MPa = 1e6 Pa, kPa = 1e3 Pa); rho_m and lambda from Section III-A.
W25_SI = {
    "k_m_i": 0.26e6,
    "b_m_i": 0.29e6,
    "k_m_w": 1.21e6,
    "b_m_w": 1.35e6,
    "alpha": 0.04e6,
    "beta": 0.54,
    "sigma_y": 6e3,
    "zeta": 0.49,
    "omega_0": 2.23,
    "rho_m": 1.84e3,
    "lambda": 0.013,
}


def test_table_i_row_in_si() -> None:
    p = MudParameters.from_water_content(0.25)
    for key, value in W25_SI.items():
        assert p.to_dict()[key] == pytest.approx(value, rel=1e-12), key
    assert "arXiv:2403.02617" in p.source and "Table I" in p.source


@pytest.mark.parametrize(("bad", "named"), [("0.25", "str"), (None, "NoneType"), (0.25 + 0j, "complex"),
                                            (np.array([0.25]), "ndarray"), (True, "bool")])
def test_table_i_takes_a_number_only(bad: object, named: str) -> None:
    """table_i compared abs(water_content - w) as given: a str or None raised TypeError, a complex 0.25 + 0j and an
    array [0.25] were taken as 25 %, True was read as a water content of 1; from_water_content's words now."""
    with pytest.raises(InputError) as error:
        MudParameters.table_i(bad)  # type: ignore[arg-type]
    assert str(error.value) == f"water content must be a number (a fraction: 0.25 means 25%), got {named}"
    assert MudParameters.table_i(np.float32(0.25)) == MudParameters.table_i(0.25) == TABLE_I[0.25]


@pytest.mark.parametrize("w", TABLE_I_WATER_CONTENTS)
def test_exact_at_the_five_table_values(w: float) -> None:
    assert MudParameters.from_water_content(w) == TABLE_I[w]
    # 15 % row, sigma_y = 17 kPa; 35 % row, zeta = 0.81 (Table I)
    assert TABLE_I[0.15].sigma_y == pytest.approx(17e3)
    assert TABLE_I[0.35].zeta == pytest.approx(0.81)


def test_interpolation_is_log_linear_between_rows() -> None:
    mid = MudParameters.from_water_content(0.225)
    lo, hi = TABLE_I[0.20], TABLE_I[0.25]
    for name in PARAMETER_NAMES:
        key = "lambda_" if name == "lambda" else name
        expected = math.sqrt(getattr(lo, key) * getattr(hi, key))  # geometric mean at the midpoint
        assert getattr(mid, key) == pytest.approx(expected, rel=1e-12), name
    assert "interpolation" in mid.source


def test_interpolation_stays_within_neighbouring_rows() -> None:
    for w in np.linspace(0.15, 0.35, 81):
        p = MudParameters.from_water_content(float(w))
        assert 0.0 < p.beta <= 1.0
        i = min(int((w - 0.15) // 0.05), 3)
        a, b = TABLE_I[TABLE_I_WATER_CONTENTS[i]], TABLE_I[TABLE_I_WATER_CONTENTS[i + 1]]
        for key in ("k_m_i", "alpha", "sigma_y", "zeta"):
            lo, hi = sorted((getattr(a, key), getattr(b, key)))
            assert lo * (1 - 1e-12) <= getattr(p, key) <= hi * (1 + 1e-12)


@pytest.mark.parametrize("w", [0.1, 0.149, 0.351, 0.9, float("nan")])
def test_out_of_range_water_content_names_the_range(w: float) -> None:
    with pytest.raises(InputError, match=r"\[0.15, 0.35\]"):
        MudParameters.from_water_content(w)


def test_a_refused_water_content_is_shown_in_full() -> None:
    """The messages showed the water content with :g (6 digits; now 12, the range's tolerance being 1e-12): 0.3500001
    was "water content 0.35 is outside Table I's range [0.15, 0.35]", and table_i(0.2000001) or a float32 0.3 "Table
    I has no row for water content 0.2"."""
    for call, w, message in (
        (MudParameters.from_water_content, 0.3500001,
         "water content 0.3500001 is outside Table I's range [0.15, 0.35] (a fraction: 0.25 means 25%)"),
        (MudParameters.table_i, 0.2000001, "Table I has no row for water content 0.2000001; rows are "),
        (MudParameters.table_i, np.float32(0.3), "Table I has no row for water content 0.300000011921;"),
    ):
        with pytest.raises(InputError) as error:
            call(w)  # type: ignore[operator]
        assert str(error.value).startswith(message)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"k_m_i": -1.0}, r"k_m_i must be within \[0.001, 1e\+12\]"),
        ({"b_m_w": 0.0}, "b_m_w must be within"),
        ({"alpha": -1.0}, "alpha must be within"),
        ({"sigma_y": -5.0}, "sigma_y must be within"),
        ({"omega_0": 0.0}, "omega_0 must be within"),
        ({"rho_m": 0.0}, "rho_m must be within"),
        ({"zeta": 0.0}, "zeta must be within"),
        ({"beta": 0.0}, r"beta must be within \[0.001, 1\]"),
        ({"beta": 1.5}, r"beta must be within \[0.001, 1\]"),
        ({"lambda": -0.1}, r"lambda must be within \[0, 10000\]"),
        ({"k_m_i": 1e-320}, "k_m_i must be within"),
        ({"zeta": 1e160}, "zeta must be within"),
        ({"omega_0": 1e160}, "omega_0 must be within"),
        ({"k_m_w": float("inf")}, "must be finite"),
        ({"alpha": float("nan")}, "must be finite"),
    ],
)
def test_validation_refuses(change: dict[str, float], message: str) -> None:
    with pytest.raises(InputError, match=message):
        TABLE_I[0.25].replace(**change)


def test_overdamped_and_zero_drag_are_valid() -> None:
    p = TABLE_I[0.25].replace(zeta=3.0, lambda_=0.0, beta=1.0)
    assert p.zeta == 3.0 and p.lambda_ == 0.0


def test_json_round_trip(tmp_path: object) -> None:
    import pathlib

    path = pathlib.Path(str(tmp_path)) / "p.json"
    p = MudParameters.from_water_content(0.3)
    p.save(path)
    data = json.loads(path.read_text())
    assert list(data) == list(PARAMETER_NAMES)  # flat, the 11 keys, in order, "lambda" not "lambda_"
    q = MudParameters.load(path)
    assert q == p
    assert q.to_dict() == p.to_dict()


def test_from_dict_refuses_unknown_and_missing_keys() -> None:
    d = TABLE_I[0.25].to_dict()
    with pytest.raises(InputError, match="unknown parameter key"):
        MudParameters.from_dict({**d, "k_mi": 1.0})
    with pytest.raises(InputError, match=r"^unknown parameter key\(s\) 3, k_mi; expected k_m_i, "):
        MudParameters.from_dict({**d, "k_mi": 1.0, 3: 2.0})  # keys of two types: named, not numpy's TypeError
    # an int key or source of 5,001 digits: their repr or str raised ValueError (Exceeds the limit (4300 digits));
    # a source that is not a str was read as its str ("None")
    with pytest.raises(InputError, match=r"^unknown parameter key\(s\) an integer of 16610 bits; expected k_m_i, "):
        MudParameters.from_dict({**d, 10**5000: 2.0})
    for source in (10**5000, None, ["a"]):
        with pytest.raises(InputError, match=r"^source must be a str, got "):
            MudParameters.from_dict({**d, "source": source})
        with pytest.raises(InputError, match=r"^source must be a str, got "):
            MudParameters.from_dict(d, source=source)  # type: ignore[arg-type]
    del d["sigma_y"]
    with pytest.raises(InputError, match=r"missing parameter key.*sigma_y"):
        MudParameters.from_dict(d)


def test_replace_refuses_unknown_names_in_one_line() -> None:
    """replace(k_mi=...) (a typo) raised dataclasses' TypeError "__init__() got an unexpected keyword argument";
    now an InputError naming it and the names expected; lambda and lambda_ both still work."""
    p = TABLE_I[0.25]
    for changes, message in (({"k_mi": 1.0}, "unknown parameter(s) k_mi; expected some of k_m_i, "),
                             ({"lambda": 0.1, "lambda_": 0.2}, "give lambda or lambda_, not both")):
        with pytest.raises(InputError) as info:
            p.replace(**changes)
        assert str(info.value).startswith(message) and "\n" not in str(info.value)
    assert p.replace(**{"lambda": 0.02}).lambda_ == p.replace(lambda_=0.02).lambda_ == 0.02
    assert p.replace(source="mine").source == "mine"


def test_critical_withdrawal_velocity() -> None:
    # sigma_y / b_m_w: 6 kPa / 1.35 MPa s/m = 4.44 mm/s at W = 25 % (Table I)
    assert TABLE_I[0.25].critical_withdrawal_velocity == pytest.approx(6e3 / 1.35e6)


def test_foot_shapes() -> None:
    f = Foot.cuboid()
    assert f.area == pytest.approx(0.051 * 0.038) and f.width == 0.038
    d = Foot.disc(0.05)
    assert d.area == pytest.approx(math.pi * 0.025**2) and d.width == 0.05
    assert Foot(area=1e-3, width=0.02).area == 1e-3
    with pytest.raises(InputError):
        Foot.disc(-1.0)
    with pytest.raises(InputError):
        Foot(area=0.0, width=0.01)
