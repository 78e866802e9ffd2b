"""Protocols: a bad option is refused in one line, never read as another number."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.motions.protocol import Hold, Intrude, Protocol


@pytest.mark.parametrize("approach", [True, "0.01", np.array([0.01]), float("nan"), -0.01])
def test_paper_refuses_an_approach_that_is_no_height(approach: Any) -> None:
    # True was read as a 1 m approach; a string or an array raised TypeError
    with pytest.raises(InputError, match="approach height"):
        Protocol.paper(approach=approach)


def test_paper_takes_a_numpy_approach() -> None:
    assert Protocol.paper(approach=np.float64(0.005)).start_depth == -0.005


@pytest.mark.parametrize("steps", [5, None, "ihw"])
def test_protocol_refuses_steps_that_are_no_sequence(steps: Any) -> None:
    with pytest.raises(InputError, match="steps must be a sequence"):
        Protocol(steps)


def test_a_zero_rise_ends_at_zero_not_minus_zero() -> None:
    # the withdraw target was -rise: with rise=0 the last depth was -0.0, which a CSV wrote as '-0'
    _, depth = Protocol.paper(rise=0.0).sample()
    assert depth[-1] == 0.0 and not np.signbit(depth[-1])


def test_a_start_depth_of_minus_zero_starts_at_zero() -> None:
    # it was kept: the samples before the first step moved were -0.0 (a CSV's '-0', other bytes than a start at 0)
    _, depth = Protocol((Hold(0.5), Intrude(0.01, 0.02)), rate=10.0, start_depth=-0.0).sample()
    assert not np.any(np.signbit(depth))
