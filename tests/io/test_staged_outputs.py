"""Outputs staged and swapped in together (:class:`mudforce.io.StagedOutputs`), and what killed runs left behind.

The commit puts every output in place or none (a failed step swaps the
folders back); an interrupt lost earlier stops it; a file keeps its
permissions and a link stays a link; the leftovers of a killed run are
found by their exact names, so a target whose name holds ``*``, ``?`` or
``[`` gets its own removed and nobody else's touched (issue 20, item 8).
In-process; the refusals of ``fit --report`` are in tests/cli/test_fit_cli.py.
"""

from __future__ import annotations

import os
import signal
import threading
from pathlib import Path

import pytest

import mudforce.io
from mudforce._plumbing import interrupt as _interrupt
from mudforce.io import StagedOutputs, clean_stale
from mudforce.reproduce.output import StagedFolder
from mudforce.reproduce.output import clean_stale as clean_stale_reproduce
from tree_snapshot import snapshot

TAG = "mudforce-test"
OLD_REPORT = {"report.md": b"old report\n", "a.png": b"old png"}


def _old_pair(root: Path, fit: str = "fit.json", report: str = "rep") -> tuple[Path, Path]:
    (root / fit).write_bytes(b"old fit\n")
    (root / report).mkdir()
    for name, data in OLD_REPORT.items():
        (root / report / name).write_bytes(data)
    return root / fit, root / report


def _hidden(root: Path) -> list[str]:
    return sorted(n for n in os.listdir(root) if n.startswith("."))


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_commit_swaps_a_folder_and_a_file_together(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                    exchange: bool) -> None:
    if not exchange:
        monkeypatch.setattr(mudforce.io, "_exchange", lambda a, b: False)
    fit, report = _old_pair(tmp_path, "target.json")
    fit.chmod(0o640)
    (tmp_path / "link.json").symlink_to("target.json")
    with StagedOutputs(TAG, folders=[report], files=[tmp_path / "link.json"]) as staged:
        assert len(_hidden(tmp_path)) == 2  # one locked sibling per target (the link's target's)
        staged.staged_path(tmp_path / "link.json").write_text("new fit\n")
        (staged.staged_path(report) / "report.md").write_text("new report\n")
        assert fit.read_bytes() == b"old fit\n" and snapshot(report) == OLD_REPORT
        staged.commit()
    assert fit.read_text() == "new fit\n" and fit.stat().st_mode & 0o777 == 0o640
    assert os.readlink(tmp_path / "link.json") == "target.json"
    assert snapshot(report) == {"report.md": b"new report\n"}  # replaced whole: the old PNG is gone
    assert _hidden(tmp_path) == []


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_a_failed_commit_puts_the_old_pair_back(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                               exchange: bool) -> None:
    if not exchange:
        monkeypatch.setattr(mudforce.io, "_exchange", lambda a, b: False)
    fit, report = _old_pair(tmp_path)

    def full_disk(src: object, dst: object) -> None:
        raise OSError(28, "No space left on device", str(dst))

    with pytest.raises(OSError, match=f"^cannot write {fit}: No space left on device$"), \
            StagedOutputs(TAG, folders=[report], files=[fit]) as staged:
        staged.staged_path(fit).write_text("new fit\n")
        (staged.staged_path(report) / "report.md").write_text("new report\n")
        monkeypatch.setattr(mudforce.io.os, "replace", full_disk)  # the file's rename fails after the folder's swap
        staged.commit()
    monkeypatch.undo()
    assert fit.read_bytes() == b"old fit\n" and snapshot(report) == OLD_REPORT
    assert _hidden(tmp_path) == []


def test_a_lost_interrupt_stops_the_commit(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    fit, report = _old_pair(tmp_path)
    with pytest.raises(KeyboardInterrupt), StagedOutputs(TAG, folders=[report], files=[fit]) as staged:
        staged.staged_path(fit).write_text("new fit\n")
        monkeypatch.setattr(_interrupt, "_pending", True)  # came inside a callback and was lost
        staged.commit()
    assert fit.read_bytes() == b"old fit\n" and snapshot(report) == OLD_REPORT
    assert _hidden(tmp_path) == []


@pytest.mark.skipif(not hasattr(signal, "pthread_sigmask"), reason="needs POSIX signal masks")
def test_a_ctrl_c_while_staging_leaves_nothing_staged(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """SIGINT while the constructor stages is held back and delivered as the staging ends: the KeyboardInterrupt is
    raised past the staging, in the constructor, and what it staged goes with it (once seen from outside, in
    tests/cli/test_fit_report_interrupt.py: a ``.fit.json.mudforce-fit-new-*`` folder left behind)."""
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signals are handled in the main thread")
    fit, report = _old_pair(tmp_path)
    real = mudforce.io.clean_stale
    calls: list[Path] = []

    def clean_then_interrupt(path: Path, tag: str) -> list[Path]:
        calls.append(path)
        if len(calls) == 2:  # the file's sibling, the report's folder already staged
            os.kill(os.getpid(), signal.SIGINT)
        return real(path, tag)

    monkeypatch.setattr(mudforce.io, "clean_stale", clean_then_interrupt)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            StagedOutputs(TAG, folders=[report], files=[fit])
    finally:
        signal.signal(signal.SIGINT, previous)
    assert len(calls) == 2  # held back until both were staged
    assert fit.read_bytes() == b"old fit\n" and snapshot(report) == OLD_REPORT
    assert _hidden(tmp_path) == []


def test_a_long_file_name_is_staged_under_a_short_sibling(tmp_path: Path) -> None:
    name = "L" * 250 + ".json"
    with StagedOutputs(TAG, files=[tmp_path / name]) as staged:
        staged.staged_path(tmp_path / name).write_text("{}\n")
        assert all(len(n) < 255 for n in _hidden(tmp_path))
        staged.commit()
    assert (tmp_path / name).read_text() == "{}\n" and _hidden(tmp_path) == []


def test_leftovers_are_matched_by_their_exact_names(tmp_path: Path) -> None:
    """A name with glob characters: its own leftovers removed, another target's old folder not taken."""
    dead = tmp_path / f".rep[1].{TAG}-new-dead1234"
    dead.mkdir()
    (dead / "a.png").write_bytes(b"half")
    other_old = tmp_path / f".abc.{TAG}-old-dead5678"  # abc's old folder, left aside between two renames
    other_old.mkdir()
    not_ours = tmp_path / f".rep[1].{TAG}-new-x.{TAG}-new-dead0000"  # the leftover of a target 'rep[1].TAG-new-x'
    not_ours.mkdir()
    assert clean_stale(tmp_path / "a*", TAG) == [] and clean_stale(tmp_path / "re?[1]", TAG) == []
    assert clean_stale(tmp_path / "rep[1]", TAG) == [dead]
    assert _hidden(tmp_path) == sorted([other_old.name, not_ours.name])
    assert not (tmp_path / "a*").exists()
    assert clean_stale(tmp_path / "abc", TAG) == [other_old] and (tmp_path / "abc").is_dir()  # put back


def test_reproduce_removes_a_killed_runs_folder_of_a_glob_name(tmp_path: Path) -> None:
    """``reproduce --out 'out[1]'`` killed: the next run's staging removes its folder (a pattern missed it)."""
    out = tmp_path / "out[1]"
    dead = tmp_path / ".out[1].mudforce-reproduce-new-dead1234"
    dead.mkdir()
    (dead / "fig02_profile.png").write_bytes(b"half")
    with StagedFolder(out.resolve()) as running:
        assert _hidden(tmp_path) == [running.staged.name]
        assert clean_stale_reproduce(out.resolve()) == []  # a live run's folder is left alone
    assert _hidden(tmp_path) == []




def test_an_output_folder_name_too_long_is_refused_in_one_line(tmp_path: Path) -> None:
    """A folder name longer than the file system allows raised is_dir()'s or exists()'s OSError from the up-front
    checks (mudforce track --out LONG/a.csv, reproduce --out LONG, synth --out LONG exited 1, 'File name too long',
    as for a failing disk); now an InputError naming the option."""
    from mudforce.errors import InputError

    long = tmp_path / ("x" * 300)
    checks = [lambda: mudforce.io.check_output_path(str(long / "a.csv"), "--out"),
              lambda: mudforce.io.check_output_dir(long, "--out"),
              lambda: mudforce.io.check_replaceable_dir(long, "--out", {"report.md"}, "mudforce-test")]
    for check in checks:
        with pytest.raises(InputError, match=r"^--out:? '.{1,80}': File name too long$"):
            check()
    assert list(tmp_path.iterdir()) == []


def test_a_failed_write_is_named_by_its_output_and_sorted_by_one_rule(tmp_path: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """A full disk while an output was written raised a bare OSError ("No space left on device", no file named; or
    the hidden staged copy's name), where write_outputs raised InputError for any OSError. Now one rule: the path's
    fault (permission denied, ...) is InputError, the system's (no space, I/O error) an OSError; either says
    ``cannot write OUTPUT: WHY``, the output as given, and every output is left as it was."""
    from mudforce.errors import InputError
    from mudforce.io import atomic_write_text, check_output_dir, check_replaceable_dir, write_outputs

    fit, report = _old_pair(tmp_path)
    before = snapshot(tmp_path)
    real_fsync, real_mkdtemp = os.fsync, mudforce.io.tempfile.mkdtemp

    def fail(code: int, *args: object) -> None:
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(os, "fsync", lambda fd: fail(28))
    with pytest.raises(OSError, match=f"^cannot write {fit}: No space left on device$") as failure:
        atomic_write_text(fit, "new\n")
    assert failure.value.errno == 28 and failure.value.filename == str(fit) and not isinstance(failure.value,
                                                                                               InputError)
    with pytest.raises(OSError, match=f"^cannot write {report / 'report.md'}: No space left on device$"), \
            StagedOutputs(TAG, folders=[report]) as staged:  # a staged folder's file: by its output's path
        atomic_write_text(staged.staged_path(report) / "report.md", "new\n")
    png = tmp_path / "a.png"
    with pytest.raises(OSError, match=f"^cannot write {png}: Input/output error$"):  # the plot, not the CSV
        write_outputs(TAG, {fit: lambda path: path.write_text("new\n"), png: lambda path: fail(5)})
    monkeypatch.setattr(os, "fsync", lambda fd: fail(13))  # (a path's fault, as the system reports it)
    with pytest.raises(InputError, match=f"^cannot write {fit}: Permission denied$"):
        write_outputs(TAG, {fit: lambda path: atomic_write_text(path, "new\n")})
    monkeypatch.setattr(os, "fsync", real_fsync)

    def mkdtemp(*args: object, **kwargs: object) -> str:  # no room for a new folder
        if "-probe-" in str(kwargs.get("prefix")) or "-new-" in str(kwargs.get("prefix")):
            fail(122)  # EDQUOT
        return real_mkdtemp(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(mudforce.io.tempfile, "mkdtemp", mkdtemp)
    with pytest.raises(OSError, match=f"^cannot write {report}: Disk quota exceeded$"):
        StagedOutputs(TAG, folders=[report], files=[fit])
    with pytest.raises(OSError, match=f"^cannot write {report}: Disk quota exceeded$"):
        check_replaceable_dir(report, "--report", {"report.md"}, TAG)
    monkeypatch.setattr(mudforce.io.tempfile, "NamedTemporaryFile", lambda **kwargs: fail(28))
    with pytest.raises(OSError, match=f"^cannot write {report}: No space left on device$"):
        check_output_dir(report)
    monkeypatch.setattr(mudforce.io.tempfile, "NamedTemporaryFile", lambda **kwargs: fail(13))
    with pytest.raises(InputError, match=f"^--out {report}: cannot write there \\(Permission denied\\)$"):
        check_output_dir(report)
    assert snapshot(tmp_path) == before
