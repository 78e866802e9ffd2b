"""The CSV reader's memory grows as the numbers do, not as Python objects (issue 15, item 5); an empty name is
refused as one."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.io import load_json
from mudforce.io.tables import read_columns, read_trajectory


def test_a_ragged_row_is_counted_in_words(tmp_path: Path) -> None:
    """'row 2 has 1 fields' was the message of a row with one cell."""
    path = tmp_path / "short.csv"
    path.write_text("time_s,depth_m\n0\n0.01,0.001\n")
    with pytest.raises(InputError, match=r"row 2 has 1 field, the header has 2; rows must not be ragged$"):
        read_trajectory(path)


@pytest.mark.parametrize("name", ["", " "])
def test_an_empty_name_is_refused_as_one(name: str) -> None:
    """Path('') is '.': the readers said ".: is a directory; expected a CSV file" (load_json: "a parameter file")."""
    with pytest.raises(InputError, match=f"^empty file name '{name}'; expected a CSV file$"):
        read_trajectory(name)
    with pytest.raises(InputError, match=f"^empty file name '{name}'; expected a CSV file$"):
        read_columns(name, {"time": (("time_s", 1.0),)})
    with pytest.raises(InputError, match=f"^empty file name '{name}'; expected a parameter file$"):
        load_json(name, "parameter file")


def test_reading_a_long_trajectory_takes_memory_in_proportion_to_the_numbers(tmp_path: Path) -> None:
    """20,000 rows: peak allocation below 100 bytes a row (two float64 columns and a line number are 24;
    a reader that keeps the rows as Python lists of strings takes ~250). tracemalloc slows the reader
    about tenfold, hence no more rows."""
    n = 20_000
    time = np.arange(n) * 1e-3
    depth = 0.02 * np.sin(time)
    path = tmp_path / "long.csv"
    with path.open("w") as handle:
        handle.write("time_s,depth_m\n")
        handle.writelines(f"{t:.6f},{z:.8f}\n" for t, z in zip(time, depth, strict=True))
    tracemalloc.start()
    try:
        t, z = read_trajectory(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert t.size == n and np.allclose(z, depth, atol=1e-8)
    assert peak < 100 * n, peak / n


def test_a_wide_header_is_refused_with_its_duplicates_named_as_before(tmp_path: Path) -> None:
    """A transposed recording (one row per quantity): its header of 40,000 times was checked for names given twice
    by a list.count per name, 18 s before 'missing column'; now one count (about 15 ms, measured, not asserted: the
    suite's own time would show a return of the quadratic check). Duplicates as before."""
    times = [repr(0.01 * k) for k in range(40_000)]
    path = tmp_path / "transposed.csv"
    path.write_text("\n".join(",".join(row) for row in (times, ["0"] * len(times), ["1"] * len(times))) + "\n")
    with pytest.raises(InputError, match=r"missing column time_s or time_ms; the header is '0\.0,0\.01,"):
        read_trajectory(path)
    path.write_text("depth_m,b,time_s,b,depth_m\n0,0,0,0,0\n")
    with pytest.raises(InputError, match="column b appears more than once in the header; each column must be "):
        read_trajectory(path)


def test_a_name_the_file_system_cannot_take_is_refused_in_one_line(tmp_path: Path) -> None:
    """A name longer than the file system allows raised Path.exists()'s OSError (mudforce track and simulate exited 1,
    'File name too long', as for a failing disk); a NUL said 'file not found' with the NUL printed raw, and
    is_pose_trajectory raised ValueError (embedded null byte) where it answers False for what it cannot read."""
    from mudforce.io.tables import is_pose_trajectory

    long = tmp_path / ("x" * 300 + ".csv")
    with pytest.raises(InputError, match=r"^\S+x\.csv: cannot read \(File name too long\)$"):
        read_trajectory(long)
    with pytest.raises(InputError, match=r"^the file name 'a\\x00b\.csv' contains a NUL character; expected a CSV "):
        read_trajectory("a\x00b.csv")
    assert is_pose_trajectory("a\x00b.csv") is False


@pytest.mark.parametrize(("path", "message"), [
    (3, "path must be a file name, got int; expected a fit result"),
    (None, "path must be a file name, got NoneType; expected a fit result"),
    ("a\x00b.json", r"the file name 'a\\x00b\.json' contains a NUL character; expected a fit result"),
])
def test_load_json_refuses_what_is_no_file_name_in_one_line(path: object, message: str) -> None:
    """load_json (and so load_fit) raised Path()'s TypeError for 3 or None, and stat()'s ValueError (embedded null
    byte) for a NUL; MudParameters.load checked the first itself."""
    with pytest.raises(InputError, match=f"^{message}$"):
        load_json(path, "fit result")  # type: ignore[arg-type]


def test_time_that_goes_backwards_is_shown_in_seconds_said_so(tmp_path: Path) -> None:
    """A time_ms column's 10 then 5 was shown as '(0.01 then 0.005)', values in seconds under the file's column in
    milliseconds; now with their unit, as model.bounds.check_times words it."""
    path = tmp_path / "back.csv"
    path.write_text("time_ms,depth_mm\n0,0\n10,0\n5,0\n")
    with pytest.raises(InputError, match=r"back\.csv: row 4, column time_ms: time goes backwards \(0\.01 s then "
                                         r"0\.005 s\); expected strictly increasing time$"):
        read_trajectory(path)
