"""Regenerate the paper's figures and tables from the model and synthetic experiments, with granular baselines.

``mudforce reproduce --out DIR`` (or :func:`reproduce`) makes synthetic
experiments of the paper's protocol with :func:`mudforce.calibration.synthesize`,
fits the model back per water content and per speed, fits the baselines of
:mod:`mudforce.baselines` to the same data, and writes ``DIR/report.html``
with its PNG figures (each captioned with the figure of Chen, Yi & Shan,
arXiv:2403.02617, that it corresponds to) and ``DIR/summary.json``. See
:mod:`mudforce.reproduce.report` for what is computed and how.

The heavy parts (numba, scipy, matplotlib) load on first use, so that the
command line's option checks answer at once.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from mudforce.reproduce._checks import MAX_SEED, check_output_dir, check_seed

if TYPE_CHECKING:
    from mudforce.reproduce.report import (
        POORLY_DETERMINED,
        SCATTERED,
        VELOCITY_FREE,
        ReproduceConfig,
        ReproduceResult,
        determined,
        make_experiments,
        reproduce,
    )

__all__ = [
    "MAX_SEED",
    "POORLY_DETERMINED",
    "SCATTERED",
    "VELOCITY_FREE",
    "ReproduceConfig",
    "ReproduceResult",
    "check_output_dir",
    "check_seed",
    "determined",
    "make_experiments",
    "reproduce",
]

_LAZY = frozenset(__all__) - {"MAX_SEED", "check_output_dir", "check_seed"}


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module 'mudforce.reproduce' has no attribute {name!r}")
    value = getattr(importlib.import_module("mudforce.reproduce.report"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
