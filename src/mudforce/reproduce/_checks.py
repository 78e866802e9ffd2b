"""Checks that ``mudforce reproduce`` makes before any heavy import: the seed and the output folder."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from mudforce.errors import InputError

__all__ = ["MAX_SEED", "check_output_dir", "check_seed"]

#: Largest accepted seed (seeds are combined with offsets inside and must stay below 2**63).
MAX_SEED = 2**32 - 1


def check_seed(seed: object) -> int:
    """``seed`` as an int in ``[0, MAX_SEED]``, or a one-line :class:`InputError`."""
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise InputError(f"seed must be an integer in [0, {MAX_SEED}], got {seed!r}")
    return seed


def check_output_dir(out: str | os.PathLike[str]) -> Path:
    """Create ``out`` if needed and make sure files can be written there; one-line :class:`InputError` if not."""
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise InputError(f"--out {path}: exists and is not a directory")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out {path}: cannot create the directory ({exc.strerror or exc})") from None
    try:
        with tempfile.NamedTemporaryFile(dir=path, prefix=".mudforce-write-test."):
            pass
    except OSError as exc:
        raise InputError(f"--out {path}: cannot write there ({exc.strerror or exc})") from None
    return path
