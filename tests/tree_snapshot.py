"""A folder's content as a dict, to assert that nothing under it changed (shared by the CLI harness and the
in-process tests of staged outputs; a module of its own, so that tests outside tests/cli need not import the
CLI harness)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["snapshot"]


def snapshot(directory: Path) -> dict[str, bytes | str]:
    """Every entry under ``directory``: file content, or ``-> target`` for a symbolic link."""
    out: dict[str, bytes | str] = {}
    for p in sorted(directory.rglob("*")):
        rel = str(p.relative_to(directory))
        if p.is_symlink():
            out[rel] = "-> " + os.readlink(p)
        elif p.is_file():
            out[rel] = p.read_bytes()
    return out
