"""Checks that ``mudforce reproduce`` makes before any heavy import: the seed and the output folder."""

from __future__ import annotations

from mudforce.errors import InputError
from mudforce.reproduce.output import check_report_dir as check_output_dir

__all__ = ["MAX_SEED", "check_output_dir", "check_seed"]

#: Largest accepted seed (seeds are combined with offsets inside and must stay below 2**63).
MAX_SEED = 2**32 - 1


def check_seed(seed: object) -> int:
    """``seed`` as an int in ``[0, MAX_SEED]``, or a one-line :class:`InputError`."""
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise InputError(f"seed must be an integer in [0, {MAX_SEED}], got {seed!r}")
    return seed
