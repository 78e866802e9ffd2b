"""The fits run their dense algebra on one BLAS thread, and give the caller's setting back."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg  # noqa: F401  (loads scipy's BLAS too, so both libraries are limited)
from threadpoolctl import threadpool_info, threadpool_limits

from mudforce._plumbing.blas import one_blas_thread
from mudforce.estimation.calibration import fit_drag


def _blas_threads() -> list[int]:
    return [int(lib["num_threads"]) for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_one_thread_inside_nested_calls_and_the_callers_setting_after() -> None:
    seen: list[list[int]] = []

    @one_blas_thread
    def inner() -> None:
        seen.append(_blas_threads())

    @one_blas_thread
    def outer() -> None:
        inner()
        seen.append(_blas_threads())

    with threadpool_limits(limits=2, user_api="blas"):
        before = _blas_threads()
        outer()
        assert _blas_threads() == before
    assert seen and all(threads and set(threads) == {1} for threads in seen)


def test_an_entry_point_is_wrapped_and_still_fits() -> None:
    assert getattr(fit_drag, "__wrapped__", None) is not None
    v = np.linspace(0.01, 0.1, 20)
    fit = fit_drag(v, 0.4 * 1650.0 * 1.938e-3 * v**2 * (1.0 + 0.01 * np.sin(50 * v)), 1.938e-3, rho_m=1650.0)
    assert fit.lambda_ == pytest.approx(0.4, rel=0.05)
