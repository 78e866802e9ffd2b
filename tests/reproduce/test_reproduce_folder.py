"""The report folder of ``mudforce reproduce``: refused inputs, the whole-folder swap, stale leftovers."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import mudforce
import mudforce.io
from mudforce.errors import InputError
from mudforce.reproduce.output import StagedFolder, check_report_dir, clean_stale
from mudforce_cli_harness import run_cli

OLD = {"report.html": "old report\n", "summary.json": "{}\n", "fig02_profile.png": "old png"}


def _fill(path: Path, files: dict[str, str]) -> None:
    path.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (path / name).write_text(text)


def _content(path: Path) -> dict[str, str]:
    return {p.name: p.read_text() for p in path.iterdir()}


def _siblings(path: Path) -> list[str]:
    return sorted(p.name for p in path.parent.iterdir() if p.name.startswith(f".{path.name}."))


def test_accepts_new_empty_and_earlier_report(tmp_path: Path) -> None:
    assert check_report_dir(tmp_path / "new" / "deeper") == (tmp_path / "new" / "deeper").resolve()
    (tmp_path / "empty").mkdir()
    check_report_dir(tmp_path / "empty")
    _fill(tmp_path / "old", {**OLD, ".report.html.x1y2.tmp": ""})
    check_report_dir(tmp_path / "old")
    assert not _siblings(tmp_path / "old")  # the write probe left nothing


def test_refuses_a_folder_with_other_files_a_file_and_the_package(tmp_path: Path) -> None:
    _fill(tmp_path / "mixed", {**OLD, "notes.txt": "mine"})
    with pytest.raises(InputError, match=r"'notes\.txt', not part of a mudforce report"):
        check_report_dir(tmp_path / "mixed")
    (tmp_path / "mixed" / "notes.txt").unlink()
    (tmp_path / "mixed" / "sub").mkdir()
    with pytest.raises(InputError, match="'sub'"):
        check_report_dir(tmp_path / "mixed")
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="not a directory"):
        check_report_dir(tmp_path / "file")
    if os.path.ismount("/proc"):
        with pytest.raises(InputError, match="mount point"):
            check_report_dir("/proc")
    package = Path(mudforce.__file__).resolve().parent
    for inside in (package, package / "reproduce" / "templates", package.parent):
        with pytest.raises(InputError, match="overlaps the mudforce package"):
            check_report_dir(inside)


def test_cli_refuses_the_package_templates_folder(tmp_path: Path) -> None:
    templates = Path(mudforce.__file__).resolve().parent / "reproduce" / "templates"
    before = sorted(p.name for p in templates.iterdir())
    proc = run_cli(["reproduce", "--quick", "--out", str(templates)], timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "overlaps the mudforce package" in proc.stderr
    assert sorted(p.name for p in templates.iterdir()) == before


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_commit_replaces_the_folder_whole(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, exchange: bool) -> None:
    if not exchange:
        monkeypatch.setattr(mudforce.io, "_exchange", lambda a, b: False)
    out = tmp_path / "out"
    _fill(out, OLD)
    with StagedFolder(check_report_dir(out)) as staged:
        (staged.staged / "report.html").write_text("new report\n")
        assert _content(out) == OLD
        staged.commit()
    assert _content(out) == {"report.html": "new report\n"}
    assert not _siblings(out)
    with StagedFolder(check_report_dir(tmp_path / "fresh")) as staged:
        (staged.staged / "summary.json").write_text("{}\n")
        staged.commit()
    assert _content(tmp_path / "fresh") == {"summary.json": "{}\n"}


def test_an_error_leaves_the_old_report(tmp_path: Path) -> None:
    out = tmp_path / "out"
    _fill(out, OLD)
    with pytest.raises(RuntimeError), StagedFolder(check_report_dir(out)) as staged:
        (staged.staged / "report.html").write_text("half")
        raise RuntimeError("stopped")
    assert _content(out) == OLD
    assert not _siblings(out)


def test_stale_leftovers_are_removed_or_put_back(tmp_path: Path) -> None:
    out = tmp_path / "out"
    # a killed run's unfinished folder, and an old report left aside between two renames (no report in place)
    _fill(tmp_path / ".out.mudforce-reproduce-new-dead1234", {"fig02_profile.png": "half"})
    _fill(tmp_path / ".out.mudforce-reproduce-old-dead5678", OLD)
    (tmp_path / ".other.mudforce-reproduce-new-keep0000").mkdir()  # another folder's: not ours to touch
    with StagedFolder(out.resolve()) as running:  # a new run cleans up first
        assert _content(out) == OLD
        assert _siblings(out) == [running.staged.name]
        assert clean_stale(out.resolve()) == []  # a live run holds its lock: left alone
        assert running.staged.is_dir()
    assert sorted(os.listdir(tmp_path)) == [".other.mudforce-reproduce-new-keep0000", "out"]
