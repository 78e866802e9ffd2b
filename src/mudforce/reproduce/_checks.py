"""Checks that ``mudforce reproduce`` makes before any heavy import: the seed and the output folder."""

from __future__ import annotations

from mudforce.errors import MAX_SEED, seed_int
from mudforce.reproduce.output import check_report_dir as check_output_dir

__all__ = ["MAX_SEED", "check_output_dir", "check_seed"]

# MAX_SEED (2**32 - 1, from mudforce.errors): seeds are combined with offsets inside and must stay below 2**63.


def check_seed(seed: object) -> int:
    """``seed`` as an int in ``[0, MAX_SEED]`` (Python or numpy, not ``bool``), or a one-line :class:`InputError`."""
    return seed_int(seed, "seed")
