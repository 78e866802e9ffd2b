"""Reading measured data from CSV files, with one-line errors that name file, row and column.

Columns carry their unit in the header (``time_s``, ``depth_m``,
``depth_mm``, ``force_N``); values are returned in SI.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from mudforce.errors import InputError

__all__ = ["COLUMN_UNITS", "read_columns", "read_trajectory"]

#: Accepted header spellings per quantity, with the factor to SI.
COLUMN_UNITS: dict[str, tuple[tuple[str, float], ...]] = {
    "time": (("time_s", 1.0), ("time_ms", 1e-3)),
    "depth": (("depth_m", 1.0), ("depth_mm", 1e-3)),
    "force": (("force_N", 1.0),),
    "velocity": (("velocity_m_s", 1.0), ("velocity_mm_s", 1e-3)),
}


def _clip(text: str, limit: int = 60) -> str:
    """``text`` cut to ``limit`` characters, so that a garbage file still gives a one-line, short message."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _expected(spellings: Sequence[tuple[str, float]]) -> str:
    return " or ".join(s for s, _ in spellings)


def read_columns(
    path: str | os.PathLike[str],
    columns: Mapping[str, Sequence[tuple[str, float]]],
    *,
    optional: Mapping[str, Sequence[tuple[str, float]]] | None = None,
    keep_text: Sequence[str] = (),
    matched: dict[str, str] | None = None,
) -> dict[str, np.ndarray]:
    """Read named numeric columns from a CSV file with a header row.

    Parameters
    ----------
    path : path-like
        The CSV file.
    columns : mapping
        Quantity name -> accepted ``(header, factor_to_SI)`` spellings; all required.
    optional : mapping, optional
        The same, for columns that may be absent.
    keep_text : sequence of str
        Header names returned as arrays of strings, unconverted (if present).
    matched : dict, optional
        Filled with the header each quantity was read from (``{"time": "time_ms"}``),
        for messages about the values that name the file's own column.

    Returns
    -------
    dict of str to ndarray
        One float64 array [SI] per quantity found, one str array per
        ``keep_text`` column, and under ``"line"`` each data row's line
        number in the file (blank lines are skipped, so rows are not ``k + 2``).

    Raises
    ------
    InputError
        Missing, unreadable, empty, header-only, ragged or non-numeric files,
        and NaN or infinite values, each with file, row and column.
    """
    p = Path(path)
    if not p.exists():
        raise InputError(f"{p}: file not found")
    if p.is_dir():
        raise InputError(f"{p}: is a directory; expected a CSV file")
    try:
        with p.open(newline="", encoding="utf-8") as handle:
            rows = list(csv.reader(handle))
    except UnicodeDecodeError:
        raise InputError(f"{p}: not a text CSV file (cannot decode as UTF-8)") from None
    except csv.Error as exc:
        raise InputError(f"{p}: not a valid CSV file ({exc})") from None
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None
    # keep each row's 1-based line number in the file for messages (blank lines are skipped)
    numbered = [(i + 1, r) for i, r in enumerate(rows) if r and any(c.strip() for c in r)]
    lines = [n for n, _ in numbered]
    rows = [r for _, r in numbered]
    wanted = {**columns, **(optional or {})}
    example = ",".join(spellings[0][0] for spellings in columns.values())
    if not rows:
        raise InputError(f"{p}: file is empty; expected a header row like {example} and data rows")
    header = [c.strip().lstrip("\ufeff") for c in rows[0]]
    index: dict[str, tuple[int, float, str]] = {}
    for quantity, spellings in wanted.items():
        for spelling, factor in spellings:
            if spelling in header:
                index[quantity] = (header.index(spelling), factor, spelling)
                break
        else:
            if quantity in columns:
                raise InputError(
                    f"{p}: missing column {_expected(spellings)}; the header is {_clip(','.join(header))!r}, "
                    f"expected e.g. {example}"
                )
    text_index = {name: header.index(name) for name in keep_text if name in header}
    data = rows[1:]
    if not data:
        raise InputError(
            f"{p}: has a header but no data rows; expected rows of numbers under {_clip(','.join(header))}"
        )
    out = {q: np.empty(len(data), dtype=np.float64) for q in index}
    texts: dict[str, list[str]] = {name: [] for name in text_index}
    for r, row in enumerate(data):
        line = lines[r + 1]
        if len(row) != len(header):
            raise InputError(
                f"{p}: row {line} has {len(row)} fields, the header has {len(header)}; rows must not be ragged"
            )
        for quantity, (col, factor, spelling) in index.items():
            cell = row[col].strip()
            try:
                value = float(cell)
            except ValueError:
                raise InputError(f"{p}: row {line}, column {spelling}: {_clip(cell)!r} is not a number") from None
            if not math.isfinite(value):
                raise InputError(
                    f"{p}: row {line}, column {spelling}: {_clip(cell)!r} is not finite; expected a number"
                )
            out[quantity][r] = value * factor
        for name, col in text_index.items():
            texts[name].append(row[col].strip())
    if matched is not None:
        matched.update({quantity: spelling for quantity, (_, _, spelling) in index.items()})
    result: dict[str, np.ndarray] = dict(out)
    result["line"] = np.array(lines[1:], dtype=np.int64)  # each data row's line number in the file
    for name, values in texts.items():
        result[name] = np.array(values, dtype=object)
    return result


def check_time(
    path: str | os.PathLike[str], time: np.ndarray, column: str = "time_s", lines: np.ndarray | None = None
) -> None:
    """Refuse time that repeats or goes backwards, naming the row (``lines``: from :func:`read_columns`)."""
    steps = np.diff(time)
    bad = np.flatnonzero(steps <= 0.0)
    if bad.size:
        i = int(bad[0])
        what = "repeats" if steps[i] == 0.0 else "goes backwards"
        row = int(lines[i + 1]) if lines is not None else i + 3
        raise InputError(
            f"{path}: row {row}, column {column}: time {what} ({time[i]:g} then {time[i + 1]:g}); "
            f"expected strictly increasing time"
        )


def read_trajectory(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read a prescribed trajectory: columns ``time_s`` and ``depth_m`` (or ``depth_mm``).

    Returns
    -------
    time : ndarray
        [s], strictly increasing.
    depth : ndarray
        [m], positive below the surface.
    """
    matched: dict[str, str] = {}
    cols = read_columns(path, {"time": COLUMN_UNITS["time"], "depth": COLUMN_UNITS["depth"]}, matched=matched)
    check_time(path, cols["time"], matched["time"], lines=cols["line"])
    return cols["time"], cols["depth"]
