"""Import optional dependencies with a clear message when they are missing."""

from __future__ import annotations

import importlib
from types import ModuleType

from mudforce.errors import InputError

__all__ = ["MissingDependencyError", "require"]


class MissingDependencyError(InputError, ImportError):
    """An optional dependency needed for a feature is not installed."""


def require(module: str, extra: str, feature: str) -> ModuleType:
    """Import ``module`` or raise a one-line error naming the pip extra to install."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingDependencyError(
            f"{feature} needs {module.split('.')[0]}, which is not installed; "
            f"install it with: pip install 'mudforce[{extra}]'"
        ) from None
