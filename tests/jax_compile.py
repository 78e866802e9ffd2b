"""XLA's light compilation for the JAX and MJX tests: they check numbers, and compiling is most of their cost.

:func:`light` gives the options (what ``jax.jit(..., compiler_options=...)`` and
``jit(f).lower(...).compile(...)`` take) and :func:`light_jit` jits with them:

- ``xla_cpu_use_fusion_emitters: False``: XLA:CPU's older loop emitters. A cold compile of mudforce's
  scans is 2 to 3 times cheaper, and alone it leaves the results bit for bit (measured on the 1-D stepper's
  scan, float64: forces equal to the default compile's);
- ``xla_backend_optimization_level: 0`` and ``xla_llvm_disable_expensive_passes: True``: no LLVM
  optimisation. Cheaper again; the code runs slower, which the tests' short runs do not notice, and the
  order of the operations changes (measured: 6e-14 N on forces of tens of newtons).

So a test that asserts bit-for-bit equality of two JAX runs compiles BOTH with these options, and the
tolerances against the CPU paths (1e-12 of the peak and wider) are untouched. An option this XLA does not
know is left out (checked once per process, on a trivial function). Tests import this module like
``mudforce_cli_harness`` (``tests/`` is on ``sys.path``); jax is imported only when it is called. A
subprocess (the command line) gets the same options through ``XLA_FLAGS`` (:func:`light_env`).
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable
from typing import Any

__all__ = ["WANTED", "light", "light_env", "light_jit"]

WANTED: dict[str, Any] = {"xla_cpu_use_fusion_emitters": False, "xla_backend_optimization_level": 0,
                          "xla_llvm_disable_expensive_passes": True}


@functools.cache
def light() -> dict[str, Any]:
    """The options of :data:`WANTED` that this XLA accepts."""
    import jax
    import jax.numpy as jnp

    kept = {}
    for name, value in WANTED.items():
        try:
            jax.jit(lambda x: x + 1.0).lower(jnp.zeros(2)).compile({name: value})
        except Exception as err:  # XLA's own error type moves between jax versions
            if "No such compile option" not in str(err):
                raise
        else:
            kept[name] = value
    return kept


def light_jit(fun: Callable[..., Any], **kwargs: Any) -> Any:
    """``jax.jit(fun, **kwargs)`` compiled with :func:`light`'s options (once per argument shapes and dtypes)."""
    import jax

    return jax.jit(fun, compiler_options=light(), **kwargs)


def light_env(env: dict[str, str] | None = None) -> dict[str, str]:
    """``env`` (default: this process's environment) with :func:`light`'s options added to ``XLA_FLAGS``, for a
    subprocess whose own jit calls then compile light too."""
    env = dict(os.environ if env is None else env)
    flags = [f"--{name}={str(value).lower()}" for name, value in light().items()]
    env["XLA_FLAGS"] = " ".join([env.get("XLA_FLAGS", ""), *flags]).strip()
    return env
