"""The model's input bounds (:mod:`mudforce.model.bounds`) as the compiled loops take them: :func:`out_of_bounds`.

The constants are the model's, imported here so that the compiled loops take them into their machine code and the
Python paths that import them from here keep working; :func:`out_of_bounds` is the one test of a sample against
them, for the compiled loops and for ``simulation``'s pass over a whole trajectory.
"""

from __future__ import annotations

from mudforce._kernel.layout import _compiled
from mudforce.model.bounds import MAX_DEPTH, MAX_DT, MAX_HORIZONTAL, MAX_TIME, MIN_DT, check_times

__all__ = ["MAX_DEPTH", "MAX_DT", "MAX_HORIZONTAL", "MAX_TIME", "MIN_DT", "check_times", "out_of_bounds"]


@_compiled(inline="always")
def out_of_bounds(time: float, depth: float, step: float) -> bool:
    """Whether a sample's time [s] or depth [m], or the step before it [s], is outside the bounds (True for NaN).

    Branch-free (``|``, not ``or``), so that a loop or-ing it over samples
    vectorises; pass ``MIN_DT`` as the step of a first sample, which has none.
    """
    return ((not abs(time) <= MAX_TIME) | (not abs(depth) <= MAX_DEPTH) | (not step >= MIN_DT)
            | (not step <= MAX_DT))
