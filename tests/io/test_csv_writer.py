"""The CSV writer (issue 20, item 9): Python's ``.12g`` byte for byte, at numpy speed, progress on a terminal only."""

from __future__ import annotations

import io
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import mudforce as mf
from mudforce.errors import InputError
from mudforce.io import tables
from mudforce.io._csvformat import format_rows, row_width
from mudforce.io.tables import write_csv
from mudforce.steppers.simulation import STATE_NAMES


def _python_lines(values: np.ndarray) -> list[str]:
    return [f"{x:.12g}" for x in values.tolist()]


def _compiled_lines(values: np.ndarray) -> tuple[list[str], np.ndarray]:
    vals = np.ascontiguousarray(values, dtype=np.float64).reshape(-1, 1)
    buf = np.empty(vals.shape[0] * row_width(1, 1), dtype=np.uint8)
    ends, hard = format_rows(vals, np.zeros(vals.shape[0], np.int64), np.zeros((0, 0), np.uint8),
                             np.zeros(0, np.int64), buf)
    starts = np.concatenate(([0], ends[:-1]))
    return [bytes(buf[a:b]).decode("ascii").rstrip("\n") for a, b in zip(starts, ends, strict=True)], hard


def _values() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(20)
    n = 40_000
    p10 = 10.0 ** np.arange(-300, 301)
    return {
        "any bits": rng.integers(0, 2**64, n, dtype=np.uint64).view(np.float64),
        "uniform": rng.uniform(-1.0, 1.0, n),
        "every magnitude": rng.lognormal(0.0, 40.0, n) * rng.choice([-1.0, 1.0], n),
        "powers of ten and neighbours": np.concatenate([p10, np.nextafter(p10, 0.0), np.nextafter(p10, np.inf)]),
        "integers": rng.integers(-10**14, 10**14, n).astype(np.float64),
        "twelve digits": np.round(rng.uniform(0.0, 1.0, n), 12) * 10.0 ** rng.integers(-8, 16, n),
        "ties": (rng.integers(10**11, 10**12, n) + 0.5) * 10.0 ** rng.integers(-15, 5, n),
        "next to a tie": np.nextafter((rng.integers(10**11, 10**12, n) + 0.5) * 1e-6, np.inf),
        "just under a power of ten": 10.0 ** rng.integers(-20, 20, n) * (1.0 - 10.0 ** -rng.uniform(11, 16, n)),
        "sample times": np.arange(n) * 1e-3,
        "special": np.array([0.0, -0.0, np.nan, -np.nan, np.inf, -np.inf, 5e-324, -5e-324, 2.2250738585072014e-308,
                             1.7976931348623157e308, 0.5, 1e-4, 9.99999999999e-5, 9.999999999995e-5,
                             999999999999.5, 99999999999.95, 123456789012.0, 1234567890123.0, 1e16, 1e-5]),
    }


@pytest.mark.parametrize("kind", list(_values()))
def test_the_compiled_format_is_pythons(kind: str) -> None:
    values = _values()[kind]
    lines, hard = _compiled_lines(values)
    expected = _python_lines(values)
    left = set(hard.tolist())
    assert all(lines[i] == "" for i in left)  # left to Python
    got = [line for i, line in enumerate(lines) if i not in left]
    assert got == [e for i, e in enumerate(expected) if i not in left]
    if kind in ("uniform", "every magnitude", "sample times", "twelve digits"):
        assert len(left) < 0.01 * values.size  # the compiled path does nearly all


def _old_to_csv(res: mf.SimulationResult) -> bytes:
    """SimulationResult.to_csv as it was: a Python loop, the reference of the format."""
    from mudforce.steppers.simulation import _CSV_COLUMNS

    names = [name for name, _ in _CSV_COLUMNS]
    block = np.column_stack([getattr(res, attr) for _, attr in _CSV_COLUMNS])
    lines = [",".join([*names, "state"])]
    for row, st in zip(block, res.state_names, strict=True):
        lines.append(",".join(f"{x:.12g}" for x in row) + f",{st}")
    return ("\n".join(lines) + "\n").encode("ascii")


def test_to_csv_is_byte_for_byte_the_python_format(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(tables, "WRITE_BLOCK", 500)  # several blocks, rows left to Python among them
    params = mf.MudParameters.from_water_content(0.25)
    res = mf.Protocol.paper(velocity=0.02, rise=0.03, rate=250.0, approach=0.005).simulate(params)
    assert set(res.state_names) == set(STATE_NAMES)  # FREE, CONTACT and NECKED rows
    res.to_csv(tmp_path / "new.csv")
    assert (tmp_path / "new.csv").read_bytes() == _old_to_csv(res)


def test_rows_left_to_python_are_spliced_in_place(tmp_path: Path) -> None:
    a = np.array([1.0, np.nan, 0.25, 2.5e-7, -np.inf, 1e300, 3.0])
    b = np.array([-0.0, 2.0, 125000000000.5, 4.0, 5.0, 6.0, 1e-300])
    codes = np.array([0, 1, 2, 0, 1, 2, 0])
    tables.write_csv(tmp_path / "x.csv", {"a_m": a, "b_N": b}, ("state", codes, ("FREE", "CONTACT", "NECKED")))
    names = ("FREE", "CONTACT", "NECKED")
    expected = "a_m,b_N,state\n" + "".join(f"{x:.12g},{y:.12g},{names[c]}\n"
                                          for x, y, c in zip(a, b, codes, strict=True))
    assert (tmp_path / "x.csv").read_text() == expected


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize(("tty", "quiet", "shown"), [(True, False, True), (True, True, False), (False, False, False)])
def test_progress_on_a_terminal_only_and_not_quiet(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, tty: bool,
                                                   quiet: bool, shown: bool) -> None:
    monkeypatch.setattr(tables, "_PROGRESS_ROWS", 10)
    monkeypatch.setattr(tables, "WRITE_BLOCK", 16)
    stream = _Terminal() if tty else io.StringIO()
    monkeypatch.setattr(sys, "stderr", stream)
    t = np.arange(100) / 100.0
    tables.write_csv(tmp_path / "p.csv", {"time_s": t}, quiet=quiet)
    assert ("writing p.csv" in stream.getvalue()) == shown
    assert (tmp_path / "p.csv").read_text() == "time_s\n" + "".join(f"{x:.12g}\n" for x in t)


def test_a_path_that_cannot_be_written_is_refused_in_one_line(tmp_path: Path) -> None:
    """result.to_csv / result.plot / MudParameters.save / write_csv into a folder that does not exist raised
    FileNotFoundError naming the writer's temporary file ("No such file or directory: '.../.mf-xf320772.tmp'"),
    and a path that is not one (None, 3) raised os.fspath's TypeError; now one-line InputErrors naming the
    path and its folder (atomic_open, which every writer goes through), and nothing is written."""
    pytest.importorskip("matplotlib")
    result = mf.simulate(np.linspace(0.0, 1.0, 11), np.linspace(-0.01, 0.02, 11),
                         mf.MudParameters.from_water_content(0.25))
    missing = tmp_path / "no" / "such"
    writers = {
        "to_csv": result.to_csv,
        "plot": result.plot,
        "save": mf.MudParameters.from_water_content(0.25).save,
        "write_csv": lambda path: tables.write_csv(path, {"a": np.zeros(2)}),
    }
    for name, write in writers.items():
        target = missing / ("out.png" if name == "plot" else "out.csv")  # a plot's name ends in .png
        with pytest.raises(mf.InputError) as info:
            write(target)
        text = str(info.value)
        if name == "plot":  # checked before drawing (io.check_output_path), in its words
            assert text == f"path: directory {str(missing)!r} does not exist", name
        else:
            assert text == f"cannot write {str(target)!r}: directory {str(missing)!r} does not exist", name
        for bad in (3, b"x.csv"):  # (a plot's: 'path: output must be ...', checked before drawing)
            with pytest.raises(mf.InputError, match=r"^(path: )?output must be a file path \(str or os.PathLike\), "
                                                   r"got "):
                write(bad)
    with pytest.raises(mf.InputError, match=r"^output must be a file path"):
        result.to_csv(None)  # type: ignore[arg-type]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("name", "words"), [
    ("x" * 300 + ".csv", "File name too long"),
    ("x" * 300 + "/out.csv", "File name too long"),
    ("a\x00b.csv", "the file name contains a NUL character"),
])
def test_a_name_the_file_system_cannot_take_is_refused_in_one_line(tmp_path: Path, name: str, words: str) -> None:
    """atomic_open (every writer: to_csv, save, write_csv) raised a bare OSError ([Errno 36] File name too long, from
    the symbolic-link check) for a name longer than the file system allows, and ValueError (embedded null byte) for a
    NUL; now one InputError naming the path, and nothing is written."""
    from mudforce.io import atomic_write_text

    for write in (lambda path: write_csv(path, {"a": np.zeros(2)}), lambda path: atomic_write_text(path, "a\n")):
        # (the folder's name, pytest's, is longer under xdist: a long name is shown shortened, the others whole)
        shown = ".{1,80}" if len(name) > 100 else ".+"
        with pytest.raises(InputError, match=f"^cannot write '{shown}': {words}$"):
            write(str(tmp_path / name))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("columns", "label", "words"), [
    # a code beyond the texts was read outside the compiled formatter's table: a segmentation fault
    ({"a": np.array([1.0, 2.0])}, ("state", np.array([0, 5_000_000]), ["A", "B"]), "label codes must be 2 integers"),
    # a negative code silently wrote another code's text; fewer codes than rows read past the codes
    ({"a": np.array([1.0, 2.0])}, ("state", np.array([0, -1]), ["A", "B"]), "within 0 to 1"),
    ({"a": np.array([1.0, 2.0])}, ("state", np.array([0]), ["A", "B"]), "of shape (1,)"),
    # a shorter column repeated values of the rows before in the rows it lacked
    ({"a": np.array([1.0, 2.0]), "b": np.array([7.0])}, None, "columns must be 1-D and of one length"),
    ({"a": np.ones((2, 2))}, None, "columns must be 1-D"),  # was a ValueError from numpy
    ({"a": ["1", "x"]}, None, "column a must be an array of real numbers"),  # "1" parsed, "x" a ValueError
    # a comma split the header or a label into two cells
    ({"a,b": np.array([1.0])}, None, "a column name must be printable ASCII text"),
    ({"a": np.array([1.0])}, ("s", np.array([0]), ["A,B"]), "a label text must be printable ASCII text"),
])
def test_bad_columns_and_labels_are_refused_before_the_file_is_touched(tmp_path: Path, columns: dict[str, Any],
                                                                       label: Any, words: str) -> None:
    path = tmp_path / "out.csv"
    path.write_text("kept\n")
    with pytest.raises(InputError) as error:
        write_csv(path, columns, label)
    assert words in str(error.value) and "\n" not in str(error.value)
    assert path.read_text() == "kept\n"
