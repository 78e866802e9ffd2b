"""mypy (strict, configured in pyproject.toml) finds nothing in ``src/mudforce``.

A test rather than a separate step of the test command, so that under pytest-xdist it runs on one core
while the other runs tests (mypy is single-threaded: as a step of its own it left a core idle for its
20-25 s). ``ruff check src tests && mypy`` stays the developer's quick check (README, "Development").
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_mypy_finds_nothing() -> None:
    pytest.importorskip("mypy")
    if not (ROOT / "pyproject.toml").is_file() or not (ROOT / "src" / "mudforce").is_dir():
        pytest.skip("not a source checkout")
    proc = subprocess.run([sys.executable, "-m", "mypy"], cwd=ROOT, stdin=subprocess.DEVNULL, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-5000:] + proc.stderr[-2000:]
    assert "Success: no issues found" in proc.stdout
