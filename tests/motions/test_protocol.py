"""Protocols: a bad option is refused in one line, never read as another number."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.motions.protocol import Hold, Intrude, Protocol, Withdraw


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


def test_a_rate_that_samples_past_a_moving_step_is_refused() -> None:
    """simulate --rate 0.001Hz sampled the paper's protocol at 0 and 1000 s: a foot that never entered the mud (peak
    force 0 N, exit 0). A sample interval longer than an intrusion or withdrawal is refused; a hold may be cut."""
    with pytest.raises(InputError, match=r"^sampling rate 0.001 Hz samples every 1000 s, longer than step 1 \(Intrude, "
                                         r"2 s\), which the samples would cut; expected a rate of at least 0.5 Hz$"):
        Protocol.paper(depth=0.02, velocity=0.01, rate=0.001)
    steps = (Intrude(depth=0.02, velocity=0.01), Hold(duration=0.1), Withdraw(velocity=0.1, rise=0.0))
    with pytest.raises(InputError, match=r"step 3 \(Withdraw, 0.2 s\).* at least 5 Hz$"):
        Protocol(steps, rate=4.0)
    assert Protocol(steps, rate=5.0).sample()[0].size == 13  # the hold, shorter than a sample, may be cut
