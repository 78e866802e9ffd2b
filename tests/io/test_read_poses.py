"""`read_poses`: a pose trajectory (time, position, unit quaternion) read as strictly as `read_trajectory`."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.io.tables import is_pose_trajectory, read_poses
from mudforce.model.law3d import QUATERNION_TOLERANCE

HEADER = "time_s,x_m,y_m,z_m,qw,qx,qy,qz"
ROWS = ["0,0,0,0.02,1,0,0,0", "0.01,0.001,-0.002,0.01,0.6,0.8,0,0", "0.02,0.002,-0.004,0,0,0,0,1"]


def _csv(tmp_path: Path, text: str, name: str = "p.csv") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_values_in_si_in_any_column_order_and_in_mm(tmp_path: Path) -> None:
    time, pos, quat = read_poses(_csv(tmp_path, HEADER + "\n" + "\n".join(ROWS) + "\n"))
    np.testing.assert_array_equal(time, [0.0, 0.01, 0.02])
    np.testing.assert_array_equal(pos, [[0, 0, 0.02], [0.001, -0.002, 0.01], [0.002, -0.004, 0.0]])
    np.testing.assert_array_equal(quat, [[1, 0, 0, 0], [0.6, 0.8, 0, 0], [0, 0, 0, 1]])
    # milliseconds and millimetres, shuffled columns, an extra column ignored
    text = "qz,note,z_mm,qw,time_ms,y_mm,qx,x_mm,qy\n0,a,20,1,0,0,0,0,0\n0,b,10,0.6,10,-2,0.8,1,0\n"
    time2, pos2, quat2 = read_poses(_csv(tmp_path, text, "mm.csv"), quaternion_tolerance=QUATERNION_TOLERANCE)
    np.testing.assert_allclose(time2, [0.0, 0.01], rtol=1e-15)
    np.testing.assert_allclose(pos2, [[0, 0, 0.02], [0.001, -0.002, 0.01]], rtol=1e-15)
    np.testing.assert_array_equal(quat2, [[1, 0, 0, 0], [0.6, 0.8, 0, 0]])


@pytest.mark.parametrize(("text", "words"), [
    ("time_s,x_m,y_m,z_m,qw,qx,qy\n0,0,0,0,1,0,0\n", ("missing column qz", "time_s,x_m,y_m,z_m,qw,qx,qy,qz")),
    ("time_s,x_cm,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n", ("missing column x_m or x_mm", "x_cm")),
    (HEADER + "\n0,0,0,0,1,0,0,0\n0.1,0,nan,0,1,0,0,0\n", ("row 3, column y_m", "not finite")),
    (HEADER + "\n0,0,0,0,1,0,0,0\n0,0,0,0,1,0,0,0\n", ("row 3, column time_s", "repeats")),
    (HEADER + "\n0.2,0,0,0,1,0,0,0\n0.1,0,0,0,1,0,0,0\n", ("row 3, column time_s", "goes backwards")),
    (HEADER + "\n0,0,0,0,1,0,0,0\n0.1,0,0,0,0,0,0,0\n", ("row 3, columns qw,qx,qy,qz", "norm 0")),
    (HEADER + "\n0,0,0,0,1,0,0\n", ("row 2 has 7 fields",)),
    (HEADER + "\n0,0,0,1e5,1,0,0,0\n", ("row 2, column z_m", "beyond", "position z")),
    ("time_s,x_m,x_mm,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,0,1,0,0,0\n", ("x_m and x_mm both give the position x",)),
    (HEADER + "\n", ("no data rows",)),
])
def test_bad_files_are_refused_in_one_line_naming_row_and_column(tmp_path: Path, text: str,
                                                                 words: tuple[str, ...]) -> None:
    with pytest.raises(InputError) as info:
        read_poses(_csv(tmp_path, text))
    message = str(info.value)
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)


def test_a_non_unit_quaternion_is_refused_at_the_tolerance_given(tmp_path: Path) -> None:
    off = 1.0 + 10 * QUATERNION_TOLERANCE
    path = _csv(tmp_path, f"{HEADER}\n0,0,0,0,1,0,0,0\n0.1,0,0,0,{off!r},0,0,0\n")
    assert read_poses(path)[2][1, 0] == off  # no tolerance: left to the 3-D law (simulate_3d refuses it)
    with pytest.raises(InputError, match=r"row 3, columns qw,qx,qy,qz: the quaternion \(1\.00001, 0, 0, 0\) has "
                                         r"norm 1\.00001; expected a unit quaternion \(within 1e-06\)"):
        read_poses(path, quaternion_tolerance=QUATERNION_TOLERANCE)
    near = 1.0 + 0.5 * QUATERNION_TOLERANCE  # within: accepted as it is (the 3-D law normalises it)
    path.write_text(f"{HEADER}\n0,0,0,0,{near!r},0,0,0\n")
    assert read_poses(path, quaternion_tolerance=QUATERNION_TOLERANCE)[2][0, 0] == near


def test_which_trajectory_a_header_is(tmp_path: Path) -> None:
    assert is_pose_trajectory(_csv(tmp_path, HEADER + "\n" + ROWS[0] + "\n"))
    assert is_pose_trajectory(_csv(tmp_path, "\n\ntime_s,x_mm\n0,0\n"))  # a pose column: read_poses says what lacks
    assert not is_pose_trajectory(_csv(tmp_path, "time_s,depth_mm\n0,0\n"))
    assert not is_pose_trajectory(tmp_path / "absent.csv")  # the reader it is given says what is wrong
    assert not is_pose_trajectory(_csv(tmp_path, ""))
    with pytest.raises(InputError, match=r"names both depth_m .* and z_m"):
        is_pose_trajectory(_csv(tmp_path, "time_s,depth_m,z_m\n0,0,0\n"))


@pytest.mark.parametrize("tolerance", ["1e-6", True, -1.0, float("nan"), [1e-6]])
def test_a_bad_quaternion_tolerance_is_refused_in_its_own_words(tmp_path: Path, tolerance: object) -> None:
    """"1e-6" and True were taken (as 1e-6 and 1), -1 and NaN refused every row in the file's words ("the quaternion
    (1, 0, 0, 0) has norm 1; expected a unit quaternion"), a list raised TypeError."""
    path = _csv(tmp_path, "time_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0.03,1,0,0,0\n0.01,0,0,0.02,1,0,0,0\n")
    with pytest.raises(InputError, match=r"quaternion_tolerance must be a number >= 0 \[-\] or None"):
        read_poses(path, quaternion_tolerance=tolerance)  # type: ignore[arg-type]
    assert read_poses(path, quaternion_tolerance=float("inf"))[2].shape == (2, 4)  # inf: no check, as None
    assert read_poses(path, quaternion_tolerance=0)[2].shape == (2, 4)
