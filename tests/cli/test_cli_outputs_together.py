"""A command's outputs are written all or none, and options that do not apply are refused (found 2026-11-29).

- ``simulate``, ``track`` and ``drop`` with ``--plot``: the CSV is not replaced when the PNG beside it cannot be
  written (they were written one after the other, and a refused plot left the new CSV in place of the old);
- ``fit`` into a folder that takes no file: one line naming ``--out``'s file, exit 2 (it was exit 1, naming a
  temporary file);
- ``synth`` without ``--motion gait``: ``--duration``, ``--jitter`` and ``--start-below`` are refused, not ignored
  (``--duration xyz`` wrote a dataset); with it, ``--velocities``, ``--depth``, ``--hold`` and ``--approach`` are;
- ``mudforce`` with no command, and a subcommand's unknown option: one line each, naming the parser they belong to;
- a full disk while ``synth`` or ``fit --report`` writes: exit 1, one line naming the file (found 2026-12-01).

The write failures need a folder that passes the up-front check (``os.access``) yet refuses to create files: Linux's
``/sys`` for root, who passes every ``os.access`` check, as in CI; elsewhere those cases are skipped.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest

from mudforce.estimation.calibration.synth import synthesize
from mudforce_cli_harness import assert_refused, run_batch
from tree_snapshot import snapshot

PREVIOUS = b"previous output, must survive any error\n"


def _refusing_folder() -> Path | None:
    """A folder ``os.access`` calls writable in which no file can be made, or None."""
    folder = Path("/sys")
    if not (folder.is_dir() and os.access(folder, os.W_OK | os.X_OK)):
        return None
    try:
        with tempfile.NamedTemporaryFile(dir=folder):
            return None  # (writable after all)
    except OSError:
        return folder


REFUSING = _refusing_folder()


@pytest.mark.skipif(REFUSING is None, reason="needs a folder that os.access calls writable but refuses files")
def test_a_plot_or_fit_that_cannot_be_written_leaves_every_output_as_it_was(tmp_path: Path) -> None:
    assert REFUSING is not None
    synthesize(tmp_path / "ds", velocities=(0.04,), repeats=1, seed=1, hold=0.5)
    trial = next(p for p in sorted((tmp_path / "ds").iterdir()) if p.suffix == ".csv")
    for name in ("s.csv", "t.csv", "d.csv"):
        (tmp_path / name).write_bytes(PREVIOUS)
    before = snapshot(tmp_path)
    png = str(REFUSING / "mudforce-test.png")
    cases = [
        ["simulate", "--water-content", "25%", "--out", "s.csv", "--plot", png, "--quiet"],
        ["track", str(trial), "--out", "t.csv", "--plot", png, "--quiet"],
        ["drop", "--water-content", "25%", "--mass", "5kg", "--duration", "0.2s", "--out", "d.csv", "--plot", png],
        ["fit", "ds", "--out", str(REFUSING / "mudforce-test.json"), "--quiet"],
    ]
    runs = run_batch([(argv, tmp_path) for argv in cases])
    for argv, run in zip(cases, runs, strict=True):
        assert_refused(run, "cannot write", str(REFUSING / "mudforce-test"))
        assert ".tmp" not in run.stderr and "-new-" not in run.stderr, (argv, run.stderr)  # the output, not a temp
    assert snapshot(tmp_path) == before  # the CSVs as they were, nothing staged left behind


def test_synth_refuses_gait_options_for_the_protocol_and_protocol_options_for_a_gait(tmp_path: Path) -> None:
    base = ["synth", "--quiet", "--repeats", "1", "--velocities", "40mm/s", "--hold", "0.2s", "--out", "g"]
    extra = [["--duration", "xyz"], ["--duration", "10s"], ["--jitter", "nan"], ["--jitter", "0.1"],
             ["--start-below", "always"]]
    # with a gait, the protocol's options were ignored: --hold 100s wrote the same walks as no --hold
    gait = ["synth", "--quiet", "--repeats", "1", "--motion", "gait", "--duration", "2s", "--out", "g"]
    protocol = [["--hold", "100s"], ["--velocities", "1mm/s"], ["--depth", "50mm"], ["--approach", "30mm"]]
    runs = run_batch([([*base, *e], tmp_path) for e in extra] + [([*gait, *e], tmp_path) for e in protocol]
                     + [([*gait[:-4], "--duration", "xyz", "--out", "g"], tmp_path)])  # gait's --duration replaced
    for e, run in zip(extra + protocol, runs, strict=False):
        assert_refused(run, e[0], "--motion gait only" if e in extra else "--motion protocol only")
    assert_refused(runs[-1], "--duration: cannot read 'xyz'")  # with gait, checked as a duration
    assert not (tmp_path / "g").exists()


def test_no_command_and_a_subcommand_s_unknown_option_are_one_line_naming_the_right_parser(tmp_path: Path) -> None:
    runs = run_batch([([], tmp_path), (["params", "--bogus"], tmp_path), (["--bogus"], tmp_path)])
    assert_refused(runs[0], "a command is required", "simulate", "reproduce")  # was the whole help, 28 lines
    assert_refused(runs[1], "mudforce params: error: unrecognized arguments: --bogus", "mudforce params --help")
    assert_refused(runs[2], "mudforce: error: unrecognized arguments: --bogus")


def test_a_full_disk_in_a_staged_folder_is_exit_1_naming_the_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """``synth``, ``fit --report`` (and ``reproduce``: the same staged folder) let a full disk's OSError escape as
    ``mudforce synth: error: No space left on device``, naming no file, where ``fit`` alone, ``track`` or ``drop``
    said ``cannot write FILE: ...``. Now every command: a write refused for its path is exit 2, the system's failure
    exit 1, either one line naming the output (a folder's file by its path), every output as it was. (In process;
    the fit replaced by a canned result, the report by one file: the writes are what is tested.)"""
    from types import SimpleNamespace

    import mudforce.estimation.calibration.fit as fitting
    import mudforce.estimation.calibration.report as report
    from mudforce.cli import main
    from mudforce.io import atomic_write_text

    monkeypatch.chdir(tmp_path)
    synth = ["synth", "--quiet", "--repeats", "1", "--velocities", "40mm/s", "--hold", "0.2s", "--out", "ds"]
    assert main(synth) == 0
    trial = next(p.name for p in sorted((tmp_path / "ds").iterdir()) if p.suffix == ".csv")
    (tmp_path / "fit.json").write_bytes(PREVIOUS)
    (tmp_path / "rep").mkdir()
    (tmp_path / "rep" / "report.md").write_bytes(PREVIOUS)
    before = snapshot(tmp_path)
    capsys.readouterr()
    monkeypatch.setattr(fitting, "fit_dataset", lambda *a, **k: SimpleNamespace(
        conditions=[], save=lambda path: atomic_write_text(path, "{}\n")))
    monkeypatch.setattr(report, "write_report", lambda result, folder, **k: atomic_write_text(folder / "report.md",
                                                                                             "new\n"))
    calls: list[int] = []

    def full(fd: int) -> None:  # the disk fills after fit.json's first write: report.md fails
        calls.append(fd)
        if len(calls) > 1:
            raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    assert main(["fit", "ds", "--out", "fit.json", "--report", "rep", "--quiet"]) == 1
    assert capsys.readouterr().err == (f"mudforce fit: error: cannot write {tmp_path.resolve() / 'rep' / 'report.md'}"
                                       ": No space left on device\n")
    assert main([*synth, "--force", "--seed", "2"]) == 1
    assert capsys.readouterr().err == (f"mudforce synth: error: cannot write {tmp_path.resolve() / 'ds' / trial}: "
                                       "No space left on device\n")
    assert snapshot(tmp_path) == before  # the old fit, report and dataset, nothing staged left beside them
