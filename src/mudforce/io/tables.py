"""Reading measured data from CSV files, with one-line errors that name file, row and column; writing columns.

Columns carry their unit in the header (``time_s``, ``depth_m``,
``depth_mm``, ``force_N``, ``x_m``); values are returned in SI. A trajectory
is either a depth (:func:`read_trajectory`, 1-D) or poses
(:func:`read_poses`, 3-D: position and quaternion). :func:`write_csv`
writes columns of numbers (``.12g``) at numpy speed.
"""

from __future__ import annotations

import csv
import math
import os
import re
from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mudforce.errors import InputError, is_real, real_array, true_or_false

__all__ = ["COLUMN_LIMITS", "COLUMN_UNITS", "NUMBER", "POSE_COLUMNS", "WRITE_BLOCK", "is_pose_trajectory",
           "read_columns", "read_poses", "read_trajectory", "write_csv"]

#: Accepted header spellings per quantity, with the factor to SI.
COLUMN_UNITS: dict[str, tuple[tuple[str, float], ...]] = {
    "time": (("time_s", 1.0), ("time_ms", 1e-3)),
    "depth": (("depth_m", 1.0), ("depth_mm", 1e-3)),
    "force": (("force_N", 1.0),),
    "velocity": (("velocity_m_s", 1.0), ("velocity_mm_s", 1e-3)),
}


#: Largest magnitude accepted per quantity [SI]: bounds of physical sense that keep every
#: later product finite (a 1e300 N bias would otherwise reach a fit as ``inf``).
COLUMN_LIMITS: dict[str, float] = {
    "time": 1e9,  # [s], ~30 years
    "depth": 100.0,  # [m], the model's depth bound (mudforce.steppers.simulation.MAX_DEPTH)
    "force": 1e7,  # [N], ~1000 t
    "velocity": 1e3,  # [m/s]
    "water_content": 1.0,  # [-]
    **{f"position {axis}": 1e4 for axis in "xyz"},  # [m], 10 km from the world origin
}

#: The columns of a pose trajectory (:func:`read_poses`), quantity -> accepted spellings with the factor
#: to SI: time, the body origin's position (world frame, z up) and its orientation as a unit quaternion
#: ``(w, x, y, z)`` (MuJoCo's order, no unit).
POSE_COLUMNS: dict[str, tuple[tuple[str, float], ...]] = {
    "time": COLUMN_UNITS["time"],
    **{f"position {axis}": ((f"{axis}_m", 1.0), (f"{axis}_mm", 1e-3)) for axis in "xyz"},
    **{f"quaternion {part}": ((f"q{part}", 1.0),) for part in "wxyz"},
}

#: Rows read into Python lists before they are packed into float64 arrays (memory stays ~8 bytes a value).
_CHUNK = 8192

#: Rows :func:`write_csv` formats at a time [-] (a few MB of text); progress is shown per block.
WRITE_BLOCK = 1 << 16
#: Rows from which :func:`write_csv` shows progress on a terminal [-] (~1 s of writing).
_PROGRESS_ROWS = 1 << 21

#: A decimal number as the readers accept it: plain ASCII, no "1_0", no non-ASCII digits, no hex, no nan or inf.
NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NONFINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", flags=re.IGNORECASE)


def _clip(text: str, limit: int = 60) -> str:
    """``text`` cut to ``limit`` characters, so that a garbage file still gives a one-line, short message."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _expected(spellings: Sequence[tuple[str, float]]) -> str:
    return " or ".join(s for s, _ in spellings)


def _number(p: Path, line: int, spelling: str, cell: str) -> float:
    """The value of one cell, or :class:`InputError` naming file, row and column."""
    if NUMBER.fullmatch(cell) is None:
        if _NONFINITE.fullmatch(cell):
            raise InputError(f"{p}: row {line}, column {spelling}: {_clip(cell)!r} is not finite; expected a number")
        raise InputError(f"{p}: row {line}, column {spelling}: {_clip(cell)!r} is not a number "
                         "(plain ASCII decimal, e.g. 0.25 or 2.5e-1)")
    return float(cell)


def _cell_text(text: Any, what: str) -> str:
    """``text`` if it is a string a CSV cell can hold as it is (printable ASCII, no comma or quote), else
    InputError (a comma split the header or a label into two cells)."""
    if not (isinstance(text, str) and text.isascii() and text.isprintable() and not any(c in text for c in ',"')):
        raise InputError(f"{what} must be printable ASCII text without commas or quotes, got {text!r}")
    return text


def read_columns(
    path: str | os.PathLike[str],
    columns: Mapping[str, Sequence[tuple[str, float]]],
    *,
    optional: Mapping[str, Sequence[tuple[str, float]]] | None = None,
    keep_text: Sequence[str] = (),
    matched: dict[str, str] | None = None,
) -> dict[str, np.ndarray]:
    """Read named numeric columns from a CSV file with a header row.

    The file is read row by row and packed into float64 arrays in chunks,
    so memory grows as the numbers do (8 bytes each), not as Python objects.

    Parameters
    ----------
    path : path-like
        The CSV file (UTF-8; a byte-order mark is accepted).
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
        Missing, unreadable, empty, header-only, ragged or non-numeric files;
        a column named twice, or two spellings of one quantity
        (``depth_m`` beside ``depth_mm``); NaN, infinite values and values
        beyond :data:`COLUMN_LIMITS`; each with file, row and column.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"path must be a file name, got {type(path).__name__}")
    from mudforce.io import check_input_name

    p = check_input_name(path, "a CSV file")  # ("is a directory" said nothing of an empty name, "file not found"
    # printed a NUL raw)
    try:
        found, folder = p.exists(), p.is_dir()
    except OSError as exc:  # a name too long for the file system: exists() raised it, and the command exited 1
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None
    if not found:
        raise InputError(f"{p}: file not found")
    if folder:
        raise InputError(f"{p}: is a directory; expected a CSV file")
    wanted = {**columns, **(optional or {})}
    example = ",".join(spellings[0][0] for spellings in columns.values())
    try:
        with p.open(newline="", encoding="utf-8-sig") as handle:
            return _read(p, csv.reader(handle), columns, wanted, example, keep_text, matched)
    except UnicodeDecodeError:
        raise InputError(f"{p}: not a text CSV file (cannot decode as UTF-8)") from None
    except csv.Error as exc:
        raise InputError(f"{p}: not a valid CSV file ({_clip(str(exc))})") from None
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None


def _header(reader: Iterator[list[str]]) -> list[str] | None:
    """The first row with a non-blank cell, its cells stripped (the header); None if there is none."""
    for row in reader:
        if row and any(c.strip() for c in row):
            return [c.strip() for c in row]
    return None


def _read(
    p: Path,
    reader: Iterator[list[str]],
    columns: Mapping[str, Sequence[tuple[str, float]]],
    wanted: Mapping[str, Sequence[tuple[str, float]]],
    example: str,
    keep_text: Sequence[str],
    matched: dict[str, str] | None,
) -> dict[str, np.ndarray]:
    header = _header(reader)
    if header is None:
        raise InputError(f"{p}: file is empty; expected a header row like {example} and data rows")
    # counted once each (list.count per name was quadratic: a transposed recording's header of 40,000 times took 18 s)
    duplicates = sorted(h for h, k in Counter(h for h in header if h).items() if k > 1)
    if duplicates:
        raise InputError(f"{p}: column {duplicates[0]} appears more than once in the header; "
                         "each column must be named once")
    index: dict[str, tuple[int, float, str]] = {}
    for quantity, spellings in wanted.items():
        present = [(s, f) for s, f in spellings if s in header]
        if len(present) > 1:
            raise InputError(f"{p}: columns {' and '.join(s for s, _ in present)} both give the {quantity}; "
                             "keep one of them")
        if present:
            spelling, factor = present[0]
            index[quantity] = (header.index(spelling), factor, spelling)
        elif quantity in columns:
            raise InputError(
                f"{p}: missing column {_expected(spellings)}; the header is {_clip(','.join(header))!r}, "
                f"expected e.g. {example}"
            )
    text_index = {name: header.index(name) for name in keep_text if name in header}
    limits = {q: COLUMN_LIMITS.get(q, math.inf) for q in index}
    chunks: dict[str, list[np.ndarray]] = {q: [] for q in index}
    values: dict[str, list[float]] = {q: [] for q in index}
    line_chunks: list[np.ndarray] = []
    lines: list[int] = []
    texts: dict[str, list[str]] = {name: [] for name in text_index}
    width = len(header)

    def pack() -> None:
        for q in index:
            chunks[q].append(np.array(values[q], dtype=np.float64))
            values[q].clear()
        line_chunks.append(np.array(lines, dtype=np.int64))
        lines.clear()

    for row in reader:
        line = reader.line_num  # type: ignore[attr-defined]
        if not row or not any(c.strip() for c in row):
            continue
        if len(row) != width:
            raise InputError(
                f"{p}: row {line} has {len(row)} field{'' if len(row) == 1 else 's'}, the header has {width}; "
                "rows must not be ragged"
            )
        for quantity, (col, factor, spelling) in index.items():
            cell = row[col].strip()
            value = _number(p, line, spelling, cell) * factor
            if not abs(value) <= limits[quantity]:
                raise InputError(f"{p}: row {line}, column {spelling}: {_clip(cell)!r} is beyond the accepted "
                                 f"magnitude {limits[quantity]:g} (SI) for a {quantity}")
            values[quantity].append(value)
        for name, col in text_index.items():
            texts[name].append(row[col].strip())
        lines.append(line)
        if len(lines) >= _CHUNK:
            pack()
    pack()
    line_numbers = np.concatenate(line_chunks)
    if not line_numbers.size:
        raise InputError(
            f"{p}: has a header but no data rows; expected rows of numbers under {_clip(','.join(header))}"
        )
    if matched is not None:
        matched.update({quantity: spelling for quantity, (_, _, spelling) in index.items()})
    result: dict[str, np.ndarray] = {q: np.concatenate(chunks[q]) for q in index}
    result["line"] = line_numbers  # each data row's line number in the file
    for name, texts_of in texts.items():
        result[name] = np.array(texts_of, dtype=object)
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
            # in seconds, said so (a time_ms column's 10 then 5 read '(0.01 then 0.005)'), as model.bounds.check_times
            f"{path}: row {row}, column {column}: time {what} ({float(time[i])!r} s then {float(time[i + 1])!r} s); "
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


def is_pose_trajectory(path: str | os.PathLike[str]) -> bool:
    """Whether the header of the CSV file ``path`` names a pose column (``x_m``, ``qw``, ...: :data:`POSE_COLUMNS`).

    A file that cannot be read as CSV is not one (False): the reader it is
    then given says what is wrong with it. A header naming both a depth
    column and a pose column is refused (:class:`InputError`): a trajectory
    is either 1-D or 3-D.
    """
    try:
        with Path(path).open(newline="", encoding="utf-8-sig") as handle:
            header = _header(csv.reader(handle))
    except (OSError, UnicodeDecodeError, csv.Error, TypeError, ValueError):  # ValueError: a NUL in the name
        return False
    if header is None:
        return False
    spellings = {s for q, ss in POSE_COLUMNS.items() if q != "time" for s, _ in ss}
    poses = [h for h in header if h in spellings]
    depths = [h for h in header if h in {s for s, _ in COLUMN_UNITS["depth"]}]
    if poses and depths:
        raise InputError(f"{path}: the header names both {depths[0]} (a depth trajectory) and {poses[0]} (poses); "
                         "keep time_s with depth_m, or time_s,x_m,y_m,z_m,qw,qx,qy,qz")
    return bool(poses)


def read_poses(
    path: str | os.PathLike[str], *, quaternion_tolerance: float | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a pose trajectory: columns ``time_s, x_m, y_m, z_m, qw, qx, qy, qz`` (:data:`POSE_COLUMNS`).

    Time may be ``time_ms`` and each position ``x_mm`` (etc.); the columns
    may come in any order, and other columns are ignored. Every error is one
    line naming the file, row and column (:func:`read_columns`).

    Parameters
    ----------
    path : path-like
        The CSV file.
    quaternion_tolerance : float or None
        Refuse, naming its row, a quaternion whose norm differs from 1 by more
        than this [-]; pass :data:`mudforce.model.law3d.QUATERNION_TOLERANCE`
        to refuse what the 3-D law would. None: only an all-zero quaternion is
        refused here.

    Returns
    -------
    time : ndarray, shape (m,)
        [s], strictly increasing.
    positions : ndarray, shape (m, 3)
        The body origin [m], world frame, z up.
    quaternions : ndarray, shape (m, 4)
        The orientation ``(w, x, y, z)`` [-], as in the file (not normalised).
    """
    tol = math.inf
    if quaternion_tolerance is not None:  # checked before the file: -1 or NaN refused every row in the file's words
        if not is_real(quaternion_tolerance) or not float(quaternion_tolerance) >= 0.0:
            raise InputError(f"quaternion_tolerance must be a number >= 0 [-] or None, got {quaternion_tolerance!r}")
        tol = float(quaternion_tolerance)
    matched: dict[str, str] = {}
    cols = read_columns(path, POSE_COLUMNS, matched=matched)
    check_time(path, cols["time"], matched["time"], lines=cols["line"])
    positions = np.stack([cols[f"position {axis}"] for axis in "xyz"], axis=1)
    quaternions = np.stack([cols[f"quaternion {part}"] for part in "wxyz"], axis=1)
    with np.errstate(over="ignore"):
        norms = np.sqrt(np.einsum("ij,ij->i", quaternions, quaternions))
    bad = np.flatnonzero(~(np.abs(norms - 1.0) <= tol) | (norms == 0.0))
    if bad.size:
        k = int(bad[0])
        q = ", ".join(f"{v:.9g}" for v in quaternions[k].tolist())
        within = f" (within {tol:g})" if math.isfinite(tol) else ""
        raise InputError(f"{path}: row {int(cols['line'][k])}, columns qw,qx,qy,qz: the quaternion ({q}) has norm "
                         f"{float(norms[k]):.9g}; expected a unit quaternion{within}, (w, x, y, z) as MuJoCo's")
    return cols["time"], positions, quaternions


def write_csv(
    path: str | os.PathLike[str],
    columns: Mapping[str, np.ndarray],
    label: tuple[str, np.ndarray, Sequence[str]] | None = None,
    *,
    quiet: bool = False,
) -> None:
    """Write columns of numbers as CSV, atomically, each number as ``f"{x:.12g}"``; at numpy speed.

    The lines are exactly those of ``",".join(f"{x:.12g}" for x in row)``
    (plus ``"," + label``), made by a compiled formatter
    (:mod:`mudforce.io._csvformat`, which leaves the rare values whose
    rounding it cannot vouch for to Python), in blocks of
    :data:`WRITE_BLOCK` rows. Long writes show progress on a terminal
    (stderr) unless ``quiet``.

    Parameters
    ----------
    path : path-like
        The file; written to a temporary file and renamed onto it (:func:`mudforce.io.atomic_open`).
    columns : mapping of str to ndarray
        Header name (with its unit, ``force_N``) -> values, one per row, in the names' order.
    label : (str, ndarray of int, sequence of str), optional
        A last column of text: its name, each row's code, and the text of each code (ASCII, no comma).
    quiet : bool
        Show no progress.
    """
    from mudforce._plumbing.progress import Progress
    from mudforce.io import atomic_open
    from mudforce.io._csvformat import format_rows, row_width

    quiet = true_or_false(quiet, "quiet")
    # checked before the file is opened: the compiled formatter indexes by these without bounds checks (a label
    # code beyond the texts, or fewer codes than rows, read outside its arrays: a crash, or other rows' text), and a
    # shorter column repeated its last block's values in the rows it lacked
    names = list(columns)
    for name in names:
        _cell_text(name, "a column name")
    arrays = [real_array(columns[name], f"column {name}", "SI") for name in names]
    n = int(arrays[0].shape[0]) if arrays and arrays[0].ndim == 1 else 0
    if any(a.ndim != 1 or a.shape[0] != n for a in arrays):
        raise InputError(f"columns must be 1-D and of one length (one value per row), got shapes "
                         f"{[a.shape for a in arrays]}")
    if label is None:
        codes = np.zeros(n, dtype=np.int64)
        texts: list[bytes] = []
    else:
        if not (isinstance(label, tuple) and len(label) == 3):
            raise InputError("label must be (name, codes, texts): a column name, each row's code and the text of "
                             f"each code, got {type(label).__name__}")
        texts = [_cell_text(text, "a label text").encode("ascii") for text in label[2]]
        names.append(_cell_text(label[0], "a column name"))
        codes = np.asarray(label[1])
        if codes.dtype.kind not in "iu" or codes.shape != (n,) or not np.all((codes >= 0) & (codes < len(texts))):
            raise InputError(f"label codes must be {n} integers (one per row) within 0 to {len(texts) - 1} (one per "
                             f"text), got {codes.dtype} of shape {codes.shape}")
        codes = codes.astype(np.int64)
    width = max((len(t) for t in texts), default=0)
    table = np.zeros((len(texts), width), dtype=np.uint8)
    for k, text in enumerate(texts):
        table[k, : len(text)] = np.frombuffer(text, dtype=np.uint8)
    lengths = np.array([len(t) for t in texts], dtype=np.int64)
    block = min(WRITE_BLOCK, max(n, 1))
    buffer = np.empty(block * row_width(len(arrays), width + 1), dtype=np.uint8)
    rows = np.empty((block, len(arrays)), dtype=np.float64)
    blocks = -(-n // block)
    with atomic_open(path, "wb") as handle, Progress(blocks, f"writing {Path(path).name}",
                                                     quiet=quiet or n < _PROGRESS_ROWS) as progress:
        handle.write((",".join(names) + "\n").encode("ascii"))
        for lo in range(0, n, block):
            hi = min(lo + block, n)
            part = rows[: hi - lo]
            for c, arr in enumerate(arrays):
                part[:, c] = arr[lo:hi]
            ends, hard = format_rows(part, codes[lo:hi], table, lengths, buffer)
            done = 0
            for r in hard.tolist():  # rows Python formats (about one in 500): spliced in at their place
                start = int(ends[r - 1]) if r else 0
                handle.write(buffer[done:start].data)
                line = ",".join(f"{x:.12g}" for x in part[r].tolist())
                handle.write((line + ("," + texts[codes[lo + r]].decode("ascii") if texts else "") + "\n"
                              ).encode("ascii"))
                done = start
            handle.write(buffer[done:int(ends[-1])].data)
            progress.update()
