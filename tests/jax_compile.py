"""XLA's light compilation for the JAX and MJX tests: they check numbers, and compiling is most of their cost.

``LIGHT`` turns off XLA's expensive LLVM passes and the backend's optimisation (what
``jax.jit(..., compiler_options=LIGHT)`` and ``jit(f).lower(...).compile(LIGHT)`` take): a cold compile of
mudforce's scans is 15-35 % cheaper, and the code is slower to run, which the tests' short runs do not notice.
The results are not bit for bit those of the default compile (measured: 7e-15 N on forces of tens of newtons,
the order of the operations changes), so a test that asserts bit-for-bit equality of two JAX runs compiles
BOTH with the same options. Tests import it like ``mudforce_cli_harness`` (``tests/`` is on ``sys.path``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["LIGHT", "light_jit"]

LIGHT: dict[str, Any] = {"xla_backend_optimization_level": 0, "xla_llvm_disable_expensive_passes": True}


def light_jit(fun: Callable[..., Any], **kwargs: Any) -> Any:
    """``jax.jit(fun, **kwargs)`` compiled with :data:`LIGHT` (once per argument shapes and dtypes, as jit)."""
    import jax

    return jax.jit(fun, compiler_options=LIGHT, **kwargs)
