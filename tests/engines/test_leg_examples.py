"""examples/mujoco_leg_in_mud.py and examples/mjx_hoppers_in_mud.py: the leg steps at a small size, and both
refuse bad options in one line with exit status 2 (the hoppers' example crashed in a reshape on a run shorter than
two step cycles, and a water content outside Table I was a traceback in both)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from load_example import load_example

pytest.importorskip("mujoco")


def _refused(main, argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:  # type: ignore[no-untyped-def]
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    return capsys.readouterr().err.strip().splitlines()[-1]


def test_the_leg_steps_in_mud_and_on_granular_ground(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    leg = load_example("mujoco_leg_in_mud")
    out = tmp_path / "leg.png"
    leg.main(["--cycles", "1", "--out", str(out)])
    printed = capsys.readouterr().out
    assert out.is_file() and "step 1: work lost to mud" in printed
    found = re.search(r"step 1: work lost to mud +([0-9.]+) J, to granular ground \(linear RFT\) +([0-9.]+) J",
                      printed)
    assert found is not None, printed
    mud, sand = float(found.group(1)), float(found.group(2))
    assert mud > sand > 0.0  # the mud takes more than the granular ground (suction, relaxation)
    message = _refused(leg.main, ["--water-content", "50%", "--out", str(out)], capsys)
    assert message.endswith("water content 0.5 is outside Table I's range [0.15, 0.35] (a fraction: 0.25 means 25%)")
    # no bound: 10**9 steps was numpy's MemoryError (8.73 TiB) after compiling, 10**5 ran for hours
    message = _refused(leg.main, ["--cycles", "501", "--out", str(out)], capsys)
    assert message.endswith("--cycles must be at most 500 (600 s of stepping), got 501")


@pytest.mark.parametrize(("argv", "message"), [
    (["--duration", "0.5"], "--duration must be from 1.33 s (two step cycles) to 600 s, got 0.5"),
    (["--worlds", "0"], "--worlds must be from 1 to 16384, got 0"),
    # no bound: 10**12 worlds was numpy's MemoryError (7.28 TiB), a traceback
    (["--worlds", "16385"], "--worlds must be from 1 to 16384, got 16385"),
    (["--worlds", "16384", "--duration", "600"], "--worlds 16384 for --duration 600 s would record 9,830,400,000 "
                                                  "samples (worlds x 1 ms steps), more than 134,217,728; lower "
                                                  "--worlds or --duration"),
    (["--water", "0.1", "0.2"], "--water must be two fractions within Table I's range [0.15, 0.35], got [0.1, 0.2]"),
])
def test_the_hoppers_refuse_bad_options_before_compiling(argv: list[str], message: str,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("mujoco.mjx")
    hoppers = load_example("mjx_hoppers_in_mud")
    assert _refused(hoppers.main, [*argv, "--out", ""], capsys).endswith(message)


def test_the_examples_refuse_an_unwritable_out_before_simulating(tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    """A --out that could not be written was found only when the figure was saved, after the whole simulation: a
    missing folder a FileNotFoundError, leg.xyz matplotlib's ValueError ('Format 'xyz' is not supported'), each a
    traceback; a folder (--out /tmp) was saved as /tmp.png with 'wrote /tmp' printed. Each is one line, exit 2."""
    pytest.importorskip("mujoco.mjx")
    leg = load_example("mujoco_leg_in_mud")
    hoppers = load_example("mjx_hoppers_in_mud")
    for out, message in ((tmp_path / "none" / "leg.png", "does not exist"),
                         (tmp_path / "leg.xyz", "must end in .png (only PNG is written)"),
                         (tmp_path, "must end in .png (only PNG is written)")):
        for main in (leg.main, hoppers.main):
            refused = _refused(main, ["--out", str(out)], capsys)
            assert "--out: " in refused and refused.endswith(message), refused
    assert _refused(leg.main, ["--out", ""], capsys).endswith("--out: empty file name; expected a file name")
    assert list(tmp_path.iterdir()) == []
