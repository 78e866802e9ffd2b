"""Shared plumbing of the result objects' ``to_pandas`` and ``to_csv`` (one way for every result).

A result names its per-sample data under unit-suffixed column names in ``columns()`` (``time_s``,
``force_N``, ...); :func:`to_pandas` makes the :class:`pandas.DataFrame` of them, and :func:`write_text`
writes a CSV text atomically (:func:`mudforce.io.atomic_open`) after checking the path.
"""

from __future__ import annotations

import os
from typing import Any

__all__ = ["to_pandas", "write_text"]


def to_pandas(columns: dict[str, Any]) -> Any:
    """A :class:`pandas.DataFrame` of ``columns`` (name -> 1-D array), in their order (needs pandas)."""
    from mudforce._plumbing.optional import require

    pd = require("pandas", "pandas", "to_pandas()")
    return pd.DataFrame(columns)


def write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` to ``path`` atomically; InputError unless ``path`` is a file path."""
    from mudforce.errors import InputError
    from mudforce.io import atomic_open

    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"path must be a file path (str or os.PathLike), got {type(path).__name__}")
    with atomic_open(path, "w") as handle:
        handle.write(text)
