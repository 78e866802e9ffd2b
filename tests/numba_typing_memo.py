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
Each resolution also leaves what numba's later passes read, keyed by the argument types: the implementation's
key (the lowering's), and the inline IR and compiled-overload entries in the templates' class-level tables; a hit
puts back those of its own first resolution, so those passes read what a fresh resolution under the same flags
would have left.

The machine code is the same: every compiled function of both warm-up halves, compiled with and without the
memo in fresh caches, gave the same instructions (their assembly, numba's generated symbol names aside;
2026-11-30, numba 0.68.1). The workers only load that cache; whatever one compiles itself is compiled without the
memo. The warm-up's CPU, both halves: 104-108 -> 86-91 s. Where numba's internals differ from what this expects,
:func:`install` does nothing and the warm-up compiles as before; so does ``MUDFORCE_NO_TYPING_MEMO=1``.

``python tests/numba_typing_memo.py check`` repeats that comparison (after a numba upgrade, say): both warm-up
halves compiled in fresh caches with and without the memo, each function's assembly compared; exit status 1 and
the functions named if any differs (a few minutes of CPU).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

__all__ = ["check", "install"]

#: What differs between two compiles of the same code: numba's generated symbol names (they carry a counter of
#: compiles) and the length of a string constant holding one.
_NAMES = re.compile(r"_ZN[\w$.]+|B\d+v\d+B|\$\d+|\.L(tmp|BB|CPI|func_end|__unnamed_)[\d_]+")


def install() -> bool:
    """Put the memo in place (once per process); whether it is in place."""
    if os.environ.get("MUDFORCE_NO_TYPING_MEMO"):
        return False
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
    memo: dict[Any, tuple[Any, Any, list[tuple[Any, str, Any]]]] = {}
    tables = ("_inline_overloads", "_compiled_overloads")

    def get_call_type(self: Any, context: Any, args: Any, kws: Any) -> Any:
        try:
            key = (self, context, tuple(args), tuple(sorted(kws.items())), targetconfig.ConfigStack.top_or_none())
            hit = memo.get(key)
        except TypeError:  # an unhashable argument type: numba's own way
            return original(self, context, args, kws)
        if hit is not None:
            sig, impl_key, entries = hit
            self._impl_keys[sig.args] = impl_key  # what the lowering of this call looks up, as numba sets it
            for template, table, entry in entries:
                getattr(template, table)[sig.args] = entry
            return sig
        sig = original(self, context, args, kws)
        if sig is not None:
            entries = [(template, table, getattr(template, table)[sig.args]) for template in self.templates
                       for table in tables if sig.args in getattr(template, table, {})]
            memo[key] = (sig, self._impl_keys[sig.args], entries)
        return sig

    get_call_type._mudforce_memo = True  # type: ignore[attr-defined]
    cls.get_call_type = get_call_type
    return True


def _dump(part: str, out: str) -> None:
    """Run warm-up half ``part`` in this process and write each compiled function's normalised assembly's hash."""
    import gc
    import runpy

    tests = Path(__file__).resolve().parent
    sys.path[:0] = [str(tests.parent / "src"), str(tests)]
    sys.argv = ["numba_warmup.py", part]
    try:
        runpy.run_path(str(tests / "numba_warmup.py"), run_name="__main__")
    except SystemExit:
        pass
    from numba.core.registry import CPUDispatcher

    hashes = {}
    for obj in gc.get_objects():
        if isinstance(obj, CPUDispatcher):
            for sig, cres in obj.overloads.items():
                lines = [_NAMES.sub("S", line) for line in cres.library.get_asm_str().splitlines()
                         if not line.strip().startswith(("#", ".file", ".ident", '.size\t".const'))]
                name = f"{obj.py_func.__module__}.{obj.py_func.__qualname__}{sig}"
                hashes[name] = hashlib.sha1("\n".join(lines).encode()).hexdigest()
    Path(out).write_text(json.dumps(hashes, sort_keys=True))


def check() -> int:
    """Compile both warm-up halves in fresh caches with and without the memo; 0 if every function's assembly is
    the same, else 1 (the differing functions printed)."""
    differ = 0
    with tempfile.TemporaryDirectory(prefix="mudforce-memo-check-") as folder:
        for part in ("a", "b"):
            found = []
            for memo in (False, True):
                out = os.path.join(folder, f"{part}{int(memo)}.json")
                env = {**os.environ, "NUMBA_CACHE_DIR": os.path.join(folder, f"cache{part}{int(memo)}")}
                if not memo:
                    env["MUDFORCE_NO_TYPING_MEMO"] = "1"
                else:
                    env.pop("MUDFORCE_NO_TYPING_MEMO", None)
                subprocess.run([sys.executable, __file__, "dump", part, out], env=env, check=True,
                               stdin=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                found.append(json.loads(Path(out).read_text()))
            plain, memoised = found
            names = sorted(set(plain) | set(memoised))
            bad = [n for n in names if plain.get(n) != memoised.get(n)]
            print(f"half {part}: {len(names)} compiled functions, {len(bad)} differ")
            for name in bad:
                print(f"  differs: {name[:200]}")
            differ += len(bad)
    return 1 if differ else 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["dump"]:
        _dump(sys.argv[2], sys.argv[3])
    elif sys.argv[1:] == ["check"]:
        sys.exit(check())
    else:
        sys.exit("usage: python tests/numba_typing_memo.py check")
