"""Deprecated names kept for one release: each use warns with a :class:`DeprecationWarning` naming the new name.

Three kinds of rename, three helpers:

* a module attribute: :func:`module_getattr` builds the module's ``__getattr__`` (PEP 562) from a table
  ``old name -> (new name, its value)``; the old name is not in ``__all__``;
* a keyword argument: :func:`renamed_keywords` wraps a function so that ``old=...`` still works (the wrapper
  only looks at keyword arguments, so positional calls cost one dictionary test);
* a method or property: written out in the class with :func:`warn_renamed`.

The table of every rename is ``docs/api.md`` ("Renamed in 0.2").
"""

from __future__ import annotations

import functools
import importlib
import warnings
from collections.abc import Callable
from typing import Any, ParamSpec, TypeVar

__all__ = ["module_getattr", "renamed_keywords", "warn_renamed"]

P = ParamSpec("P")
R = TypeVar("R")


def warn_renamed(old: str, new: str, *, stacklevel: int = 3) -> None:
    """Warn that ``old`` is deprecated in favour of ``new`` (a :class:`DeprecationWarning` at the caller)."""
    warnings.warn(f"{old} is deprecated and will be removed in the next release; use {new}",
                  DeprecationWarning, stacklevel=stacklevel)


def module_getattr(module: str, renamed: dict[str, tuple[str, str]]) -> Callable[[str], Any]:
    """A module ``__getattr__`` resolving deprecated names.

    ``renamed`` maps each old name to ``(new dotted name as shown to the user, "module:attribute" where
    the value lives)``; the value is imported on use, and each use warns.
    """

    def __getattr__(name: str) -> Any:
        entry = renamed.get(name)
        if entry is None:
            raise AttributeError(f"module {module!r} has no attribute {name!r}")
        new, where = entry
        warn_renamed(f"{module}.{name}", new)
        source, attribute = where.split(":")
        return getattr(importlib.import_module(source), attribute)

    return __getattr__


def renamed_keywords(**renamed: str) -> Callable[[Callable[P, R]], Callable[P, R]]:
    """Accept each old keyword ``old=new`` as a deprecated alias of ``new`` (warning; both at once is refused)."""

    def decorate(func: Callable[P, R]) -> Callable[P, R]:
        qualname = func.__qualname__

        @functools.wraps(func)
        def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
            if kwargs:
                used = [old for old in renamed if old in kwargs]
                if used:
                    from mudforce.errors import InputError

                    for old in used:
                        if renamed[old] in kwargs:
                            raise InputError(f"{qualname}: give {renamed[old]}= only ({old}= is its deprecated name)")
                    olds = "=, ".join(used) + "="
                    news = "=, ".join(renamed[old] for old in used) + "="
                    warn_renamed(f"{qualname}({olds})" if len(used) > 1 else f"{qualname}({olds}...)", news)
                    for old in used:
                        kwargs[renamed[old]] = kwargs.pop(old)
            return func(*args, **kwargs)

        return wrapper

    return decorate
