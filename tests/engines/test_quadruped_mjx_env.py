"""examples/quadruped_mjx_env.py at a tiny size: 2 worlds, 10 control steps (50 physics steps), one compile.

Finite, the same for the same seed, and each world's own mud shows: the wetter world's toes sink deeper.
"""

from __future__ import annotations

import numpy as np
import pytest

from jax_compile import light
from load_example import load_example

pytest.importorskip("jax")
pytest.importorskip("mujoco.mjx")


@pytest.fixture(scope="module")
def example():  # type: ignore[no-untyped-def]
    return load_example("quadruped_mjx_env")


def test_the_environment_is_finite_reproducible_and_each_world_has_its_own_mud(example) -> None:  # type: ignore[no-untyped-def]
    env = example.QuadrupedMudEnv((0.15, 0.30))
    rollout = example.compile_rollout(env, 2, 10, light())  # numbers, not speed
    first, again, other = rollout(0), rollout(0), rollout(1)  # seed 0: W = 27.6 % and 15.1 %
    for key in ("sinkage", "slip", "energy", "x", "water_content"):
        assert np.isfinite(first[key]).all()
        np.testing.assert_array_equal(first[key], again[key])  # same seed, same worlds, bit for bit
    assert not np.array_equal(first["water_content"], other["water_content"])
    w = first["water_content"]
    assert ((0.15 <= w) & (w <= 0.30)).all() and abs(w[0] - w[1]) > 0.01
    deepest = first["sinkage"].max(axis=1)
    assert 0.0 < deepest.min() < 0.05  # 11.6 kg on four 50 mm toes, 0.1 s: millimetres to centimetres
    assert deepest[np.argmax(w)] > deepest[np.argmin(w)]  # the wetter mud lets the toes sink deeper
    assert not first["done"].any()


@pytest.mark.parametrize(("argv", "message"), [
    (["--worlds", "0"], "--worlds must be from 1 to 16384, got 0"),
    # no bound: 10**12 worlds aborted the process in XLA (a check failure), after the imports and the tracing
    (["--worlds", "16385"], "--worlds must be from 1 to 16384, got 16385"),
    (["--worlds", "16384", "--duration", "600"], "16384 worlds for --duration 600 s would record 983,040,000 control "
                                                  "steps (worlds x steps), more than 134,217,728; lower --worlds or "
                                                  "--duration"),
    (["--duration", "nan"], "--duration must be within (0, 600] s, got nan"),
    (["--seed", "-1"], "--seed must be an integer in [0, 4294967295], got -1"),
    # was matplotlib's ValueError after the compile and the run, a traceback
    (["--plot", "env.xyz"], "--plot: 'env.xyz' must end in .png (only PNG is written)"),
])
def test_the_command_line_refuses_bad_values_before_compiling(example, argv, message, capsys) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(SystemExit) as info:
        example.main(argv)
    assert info.value.code == 2 and capsys.readouterr().err.strip().endswith(message)
