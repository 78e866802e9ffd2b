"""Speed plumbing only: compiled steps called from Python with one table of array addresses, not many arrays.

From Python every argument of a compiled call costs: numba's dispatcher spends ~0.4 us on the call and ~0.05-0.1
us an array resolving types, and even its compiled entry point (:func:`entry_point`) ~0.05 us an array unboxing
it. A step that works on many arrays its caller owns for life (a contact's own rows and outputs) therefore takes
one int64 table of their raw addresses and shapes (:func:`address_table`), turned back into array views inside
compiled code (:func:`voidptr`, ``numba.carray``), and is called through its entry point, which skips the
dispatcher's type resolution: its caller checks the types the table does not fix.

A table is only safe while every array in it stays alive and in place: its owner holds them all and never
replaces one (it writes in place). Nothing here is physics.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numba import types
from numba.extending import intrinsic
from numba.np.numpy_support import carray  # numba.carray

from mudforce._kernel.layout import _compiled

__all__ = ["address_table", "entry_point", "f64_1d", "f64_2d", "i64_2d", "voidptr"]


def _voidptr_typing(typingctx: Any, address: Any) -> Any:
    """Typing and code of :data:`voidptr`."""
    if not isinstance(address, types.Integer):
        return None

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.inttoptr(args[0], context.get_value_type(types.voidptr))

    return types.voidptr(address), codegen


#: In compiled code, the raw pointer at an integer address (numba has no public cast from an integer to a pointer).
voidptr: Any = intrinsic(_voidptr_typing)


# views of the arrays in slot k of a table (no copies; carray builds an array on the memory as is), inlined into
# their callers; with numba's reference counting (``_nrt=True``), which the carray views need
@_compiled(inline="always", _nrt=True)
def f64_1d(table: np.ndarray, k: int) -> np.ndarray:
    """The 1-D float64 array in slot ``k`` of an address table (:func:`address_table`), as a view."""
    return carray(voidptr(table[3 * k]), table[3 * k + 1], np.float64)


@_compiled(inline="always", _nrt=True)
def f64_2d(table: np.ndarray, k: int) -> np.ndarray:
    """The (rows, columns) float64 array in slot ``k`` of an address table, as a view."""
    return carray(voidptr(table[3 * k]), (table[3 * k + 1], table[3 * k + 2]), np.float64)


@_compiled(inline="always", _nrt=True)
def i64_2d(table: np.ndarray, k: int) -> np.ndarray:
    """The (rows, columns) int64 array in slot ``k`` of an address table, as a view."""
    return carray(voidptr(table[3 * k]), (table[3 * k + 1], table[3 * k + 2]), np.int64)


def address_table(arrays: Sequence[np.ndarray]) -> np.ndarray:
    """An int64 table of ``arrays``: slot ``k`` is (address, rows, columns) of array ``k`` (columns 1 for a 1-D
    array). Each must be a writable, C-contiguous float64 or int64 array of 1 or 2 dimensions (the compiled side
    trusts the table: a wrong entry would be read as garbage, or written over)."""
    table = np.zeros(3 * len(arrays), dtype=np.int64)
    for k, a in enumerate(arrays):
        if (a.dtype not in (np.float64, np.int64) or not a.flags.c_contiguous or not a.flags.writeable
                or a.ndim not in (1, 2)):
            raise RuntimeError(f"array {k} of an address table is not a writable C-contiguous float64 or int64 "
                               "array of 1 or 2 dimensions")
        table[3 * k] = a.ctypes.data
        table[3 * k + 1] = a.shape[0]
        table[3 * k + 2] = a.shape[1] if a.ndim == 2 else 1
    return table


def entry_point(dispatcher: Any, signature: tuple[Any, ...]) -> Any:
    """``dispatcher``'s compiled code for ``signature`` (numba types), callable without numba's dispatcher
    (``Dispatcher.compile``, which also loads from numba's cache, returns it); ``dispatcher`` itself if numba
    gives none. The caller checks that its arguments have those types: the entry point does not."""
    entry = dispatcher.compile(signature)
    return entry if callable(entry) else dispatcher
