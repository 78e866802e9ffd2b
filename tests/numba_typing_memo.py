"""A memo on numba's resolution of a call's type, for the warm-up's two processes only (speed plumbing, no physics).

numba types every operator, ``math`` call and ``@overload``-ed function of a compiled function by trying, one
after another, every typing template registered for it (about forty for ``+``), recording why each that does not
fit failed; and for an overload compiled ``inline="always"`` (the 3-D law, :mod:`mudforce.model.law3d`) it
re-derives and re-types the implementation's IR at every call site. Nothing of that is remembered between call
sites, so the same ``float64 * float64`` is resolved thousands of times: 2 ms each, most of the warm-up's CPU.

:func:`install` wraps ``numba.core.types.functions.Function.get_call_type`` with a memo keyed on what numba's
own cache of overload implementations is keyed on (``_OverloadFunctionTemplate._get_impl``): the function
type, the typing context, the argument types (literal types are types of their own), the keywords, and the
compiler flags in force (``ConfigStack``). A resolution that fails is not remembered (numba raises as before).
Each resolution also leaves the inline IR and compiled-overload entries that numba's later passes read, in the
templates' class-level tables keyed by the argument types; a hit puts back the entries of its own first
resolution, so those passes read what a fresh resolution under the same flags would have left.

The machine code is the same: every compiled function of both warm-up halves, compiled with and without the
memo in fresh caches, gave the same instructions (their assembly, numba's generated symbol names aside;
2026-11-30, numba 0.63). The workers only load that cache; whatever one compiles itself is compiled without the
memo. The warm-up's CPU, both halves: 110 -> 87 s. Where numba's internals differ from what this expects,
:func:`install` does nothing and the warm-up compiles as before.
"""

from __future__ import annotations

from typing import Any

__all__ = ["install"]


def install() -> bool:
    """Put the memo in place (once per process); whether it is in place."""
    try:
        from numba.core import targetconfig
        from numba.core.types import functions
    except ImportError:
        return False
    cls = functions.Function
    original = getattr(cls, "get_call_type", None)
    if original is None or getattr(original, "_mudforce_memo", False):
        return original is not None
    if not hasattr(targetconfig.ConfigStack, "top_or_none"):
        return False
    memo: dict[Any, tuple[Any, list[tuple[Any, str, Any]]]] = {}
    tables = ("_inline_overloads", "_compiled_overloads")

    def get_call_type(self: Any, context: Any, args: Any, kws: Any) -> Any:
        try:
            key = (self, context, tuple(args), tuple(sorted(kws.items())), targetconfig.ConfigStack.top_or_none())
            hit = memo.get(key)
        except TypeError:  # an unhashable argument type: numba's own way
            return original(self, context, args, kws)
        if hit is not None:
            sig, entries = hit
            for template, table, entry in entries:
                getattr(template, table)[sig.args] = entry
            return sig
        sig = original(self, context, args, kws)
        if sig is not None:
            entries = [(template, table, getattr(template, table)[sig.args]) for template in self.templates
                       for table in tables if sig.args in getattr(template, table, {})]
            memo[key] = (sig, entries)
        return sig

    get_call_type._mudforce_memo = True  # type: ignore[attr-defined]
    cls.get_call_type = get_call_type
    return True
