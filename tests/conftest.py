"""Test configuration: reproducible Hypothesis runs on CI, a wider search on request."""

from __future__ import annotations

import os

import matplotlib
from hypothesis import settings

matplotlib.use("Agg")

# CI (and anyone who sets CI=true) runs the same examples every time; a
# developer's run explores new ones (MUDFORCE_EXAMPLES sets how many).
settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
