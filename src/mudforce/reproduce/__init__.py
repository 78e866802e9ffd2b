"""Regenerate the paper's figures and tables from the model and synthetic experiments, with granular baselines.

``mudforce reproduce --out DIR`` (or :func:`reproduce`) makes synthetic
experiments of the paper's protocol with :func:`mudforce.estimation.calibration.synthesize`,
fits the model back per water content and per speed, fits the baselines of
:mod:`mudforce.model.baselines` to the same data, and writes ``DIR/report.html``
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
    from mudforce.reproduce.experiments import SCATTERED, ReproduceConfig, make_experiments
    from mudforce.reproduce.jobs import VELOCITY_FREE
    from mudforce.reproduce.report import ReproduceResult, Terminated, reproduce
    from mudforce.reproduce.summary import POORLY_DETERMINED, determined

__all__ = [
    "MAX_SEED",
    "POORLY_DETERMINED",
    "SCATTERED",
    "VELOCITY_FREE",
    "ReproduceConfig",
    "ReproduceResult",
    "Terminated",
    "check_output_dir",
    "check_seed",
    "determined",
    "make_experiments",
    "reproduce",
]

#: Where each heavy name lives (imported on first use).
_LAZY = {
    "POORLY_DETERMINED": "summary", "SCATTERED": "experiments", "VELOCITY_FREE": "jobs",
    "ReproduceConfig": "experiments", "ReproduceResult": "report", "Terminated": "report",
    "determined": "summary", "make_experiments": "experiments", "reproduce": "report",
}


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module 'mudforce.reproduce' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"mudforce.reproduce.{_LAZY[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
