"""examples/torch_dlpack.py runs (only where torch is installed: it is not part of the test extra)."""

from __future__ import annotations

import math

import pytest

from load_example import load_example

pytest.importorskip("jax")
pytest.importorskip("torch")


def test_torch_dlpack_example_runs() -> None:
    module = load_example("torch_dlpack")
    stats = module.main(["--n", "256", "--calls", "5"])
    assert math.isfinite(stats["per_call_s"]) and stats["max_force_N"] > 0.0
    assert stats["zero_copy"] == 1.0  # torch -> JAX and JAX -> torch share memory: no host copy
