"""``numba.njit`` and ``numba.extending.overload`` with the decorated function's own signature for mypy
(plumbing: no physics).

mypy reads numba's own sources (150 modules, about 5 s of a cold check) only to type ``njit``'s
dispatchers; pyproject.toml has it skip them, and every compiled function of mudforce is decorated
through :func:`njit` here (and each compiled form of a Python function through :func:`overload`), whose
annotation keeps the function's signature. At run time they are numba's own, with the same arguments.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import numba
import numba.extending

__all__ = ["njit", "overload"]

_F = TypeVar("_F", bound=Callable[..., Any])


def njit(**options: Any) -> Callable[[_F], _F]:
    """``numba.njit(**options)``, typed so that the compiled function keeps its signature."""
    decorator: Callable[[_F], _F] = numba.njit(**options)
    return decorator


def overload(function: Callable[..., Any], **options: Any) -> Callable[[_F], _F]:
    """``numba.extending.overload(function, **options)``: the decorated implementation keeps its signature."""
    decorator: Callable[[_F], _F] = numba.extending.overload(function, **options)
    return decorator
