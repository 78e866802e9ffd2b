"""Test configuration: reproducible Hypothesis runs on CI, a wider search on request."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import matplotlib
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
