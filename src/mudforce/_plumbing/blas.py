"""One BLAS thread for the estimators' dense algebra (speed plumbing, no physics).

The fits hand tall, narrow Jacobians (thousands of samples by a few
parameters) to LAPACK through scipy's ``least_squares`` (an SVD every
iteration) and numpy's ``pinv``. OpenBLAS splits such a matrix over every
core, and on a small machine that is far slower than one thread: on 2 cores
an SVD of a 3000 x 9 Jacobian took 34 ms with OpenBLAS's default threads
while another process was busy, 0.7 ms with one; ``mudforce reproduce
--quick`` took 63 s of CPU against 21 s. Worse, with ``--jobs N`` or with
several processes at once each one spins up its own BLAS threads, and the
cores are oversubscribed. One thread also makes the results independent of
the machine's core count (OpenBLAS blocks its sums by thread).

:func:`one_blas_thread` wraps the public entry points of estimation:
inside, BLAS libraries loaded by numpy and scipy run on one thread
(`threadpoolctl <https://github.com/joblib/threadpoolctl>`_, the mechanism
scikit-learn and joblib use); outside, the caller's settings are untouched.
Nested calls cost nothing.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["one_blas_thread"]

F = TypeVar("F", bound=Callable[..., Any])

_depth = threading.local()


def one_blas_thread(func: F) -> F:
    """``func`` with the BLAS libraries limited to one thread while it runs (a no-op when nested)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        depth = getattr(_depth, "value", 0)
        if depth:
            return func(*args, **kwargs)
        from threadpoolctl import threadpool_limits

        _depth.value = 1
        try:
            with threadpool_limits(limits=1, user_api="blas"):
                return func(*args, **kwargs)
        finally:
            _depth.value = 0

    return wrapper  # type: ignore[return-value]
