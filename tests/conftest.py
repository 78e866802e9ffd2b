"""Test configuration: reproducible Hypothesis runs on CI, a wider search on request."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import matplotlib
import pytest
from hypothesis import settings

matplotlib.use("Agg")

# tests/ on the import path, so that any test folder can `from mudforce_cli_harness import run_cli`
# (the one subprocess harness; there are no __init__.py files, and pytest only inserts each test's own folder)
_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

# CI (and anyone who sets CI=true) runs the same examples every time; a
# developer's run explores new ones (MUDFORCE_EXAMPLES sets how many).
settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


def _distributed(config: pytest.Config) -> bool:
    """Whether this is pytest-xdist's controller of two or more workers (not a worker, not a plain run)."""
    if hasattr(config, "workerinput"):
        return False
    workers = getattr(config.option, "numprocesses", None)
    if workers in ("auto", "logical"):
        return (os.cpu_count() or 1) > 1
    return isinstance(workers, int) and workers > 1


def pytest_configure(config: pytest.Config) -> None:
    """Before the workers start, compile the numba kernels once into the on-disk cache (tests/numba_warmup.py).

    Each worker would otherwise compile the same kernels itself on a clean
    clone (about 100 s of CPU each). The two halves run at once, one per
    core; with a warm cache they only load it. ``MUDFORCE_NO_WARMUP=1`` skips it.
    """
    if not _distributed(config) or os.environ.get("MUDFORCE_NO_WARMUP"):
        return
    script = Path(__file__).resolve().parent / "numba_warmup.py"
    from mudforce_cli_harness import cli_env  # the package under test first on the path, as every subprocess

    env = cli_env()
    halves = [subprocess.Popen([sys.executable, str(script), part], env=env, stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True) for part in ("a", "b")]
    for proc in halves:
        _, err = proc.communicate()
        lines = [line for line in err.splitlines() if line.startswith("numba warm-up") and "failed" in line]
        for line in lines:
            print(line, file=sys.stderr)
