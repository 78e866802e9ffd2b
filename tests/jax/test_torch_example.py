"""examples/torch_dlpack.py runs (only where torch is installed: it is not part of the test extra)."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest

pytest.importorskip("jax")
pytest.importorskip("torch")


def test_torch_dlpack_example_runs() -> None:
    path = Path(__file__).resolve().parents[2] / "examples" / "torch_dlpack.py"
    spec = importlib.util.spec_from_file_location("torch_dlpack_example", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    stats = module.main(["--n", "256", "--calls", "5"])
    assert math.isfinite(stats["per_call_s"]) and stats["max_force_N"] > 0.0
    assert stats["zero_copy"] == 1.0  # torch -> JAX and JAX -> torch share memory: no host copy
