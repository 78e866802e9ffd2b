"""examples/torch_dlpack.py runs (only where torch is installed: it is not part of the test extra); its options are
refused before torch and JAX are imported, so that part runs everywhere."""

from __future__ import annotations

import math
import sys

import pytest

from load_example import load_example


@pytest.mark.parametrize(("argv", "message"), [
    # was a ZeroDivisionError after the compile and the warm-up
    (["--calls", "0"], "--calls must be from 1 to 10000, got 0"),
    (["--calls", "10001"], "--calls must be from 1 to 10000, got 10001"),
    (["--n", "0"], "--n must be from 1 to 10000000, got 0"),
    (["--n", "-5"], "--n must be from 1 to 10000000, got -5"),
    (["--n", "10000001"], "--n must be from 1 to 10000000, got 10000001"),
    (["--n", "10000000", "--calls", "200"], "would hold 2,080,000,000 depths, more than 268,435,456; lower --n or "
                                            "--calls"),
])
def test_bad_options_are_refused_in_one_line_before_torch_is_imported(argv: list[str], message: str,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    module = load_example("torch_dlpack")
    before = set(sys.modules)
    with pytest.raises(SystemExit) as info:
        module.main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert info.value.code == 2 and err[-1].endswith(message), err
    assert not {"torch", "jax"} & (set(sys.modules) - before)  # refused before either was imported here


def test_torch_dlpack_example_runs() -> None:
    pytest.importorskip("jax")
    pytest.importorskip("torch")
    module = load_example("torch_dlpack")
    stats = module.main(["--n", "256", "--calls", "5"])
    assert math.isfinite(stats["per_call_s"]) and stats["max_force_N"] > 0.0
    assert stats["zero_copy"] == 1.0  # torch -> JAX and JAX -> torch share memory: no host copy
