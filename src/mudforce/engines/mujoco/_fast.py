"""Speed plumbing of the MuJoCo adapter: calling its compiled per-step work from Python for ~0.1 us.

Nothing here is physics; :mod:`mudforce.engines.mujoco._step` has what the calls do.
:class:`mudforce.engines.mujoco.MudAdapter` calls :func:`before_step` and
:func:`after_step` around every ``mj_step`` of the user's loop, so their
call overhead is a visible part of a small robot's step. The tricks:

* one argument per call: an int64 table of the raw addresses and shapes of
  the arrays the step works on (:func:`address_table`), turned back into
  array views inside compiled code (:func:`mudforce._kernel.addresses.f64_2d` and its kin);
* the compiled entry point called directly, without numba's dispatcher
  (:func:`direct`).

The table is only safe while every array in it stays alive and in place:
the adapter holds them all, never replaces one (it writes in place), and
MuJoCo's buffers do not move for the life of the model and data.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numba import typeof

from mudforce import _kernel as K
from mudforce._kernel import addresses
from mudforce._kernel.addresses import f64_1d, f64_2d, i64_2d
from mudforce.engines.mujoco._step import apply_mud, commit_and_prepare

__all__ = [
    "N_TABLE",
    "SLOT_CONF",
    "SLOT_FRICTIONLOSS",
    "SLOT_INTS",
    "SLOT_OUT",
    "SLOT_PARAMS",
    "SLOT_SITE_POS",
    "SLOT_SITE_XPOS",
    "SLOT_STATES",
    "SLOT_WORK",
    "SLOT_XFRC",
    "SLOT_XIPOS",
    "address_table",
    "after_step",
    "before_step",
    "direct",
]

# The per-step calls take a single argument, an int64 table of the addresses and shapes of the
# arrays they work on, because from Python every argument costs: numba's dispatcher spends
# ~0.15 us per array resolving types, and even its compiled entry point ~0.05 us per array
# unboxing it; with one small argument a call costs ~0.1 us. Slot k of the table is
# (address, rows, columns) of array k (columns 1 for 1-D arrays). All are C-contiguous
# float64 except the int64 ``ints``. The adapter keeps every array alive and never replaces
# one, and MuJoCo's buffers do not move for the life of the model and data.
SLOT_STATES, SLOT_PARAMS, SLOT_OUT, SLOT_INTS, SLOT_CONF, SLOT_WORK = 0, 1, 2, 3, 4, 5
SLOT_SITE_XPOS, SLOT_XIPOS, SLOT_XFRC, SLOT_SITE_POS, SLOT_FRICTIONLOSS = 6, 7, 8, 9, 10
# compiled with the stepper's options (K._compiled) but keeping the GIL (releasing and taking it back
# would cost more than it frees), and with numba's reference counting (``_nrt=True``), which the
# carray views need
N_TABLE = 11


@K._compiled(nogil=False, _nrt=True)
def before_step(table: np.ndarray) -> None:
    """:func:`apply_mud` on the arrays in ``table`` (slots ``SLOT_*``)."""
    apply_mud(f64_2d(table, SLOT_XFRC), i64_2d(table, SLOT_INTS), f64_2d(table, SLOT_WORK))


@K._compiled(nogil=False, _nrt=True)
def after_step(table: np.ndarray) -> None:
    """:func:`commit_and_prepare` on the arrays in ``table`` (slots ``SLOT_*``)."""
    commit_and_prepare(f64_2d(table, SLOT_STATES), f64_2d(table, SLOT_PARAMS), f64_2d(table, SLOT_OUT),
                       i64_2d(table, SLOT_INTS), f64_1d(table, SLOT_CONF), f64_2d(table, SLOT_WORK),
                       f64_2d(table, SLOT_SITE_XPOS), f64_2d(table, SLOT_XIPOS), f64_2d(table, SLOT_XFRC),
                       f64_2d(table, SLOT_SITE_POS), f64_1d(table, SLOT_FRICTIONLOSS))


def address_table(arrays: Sequence[np.ndarray]) -> np.ndarray:
    """The table of :func:`before_step`/:func:`after_step` for ``arrays`` in slot order
    (:func:`mudforce._kernel.addresses.address_table`, each slot's dtype checked first: ``ints`` int64, the others
    float64)."""
    for k, a in enumerate(arrays):
        # the compiled side trusts these (a wrong one would be read as garbage, or written over)
        expected = np.int64 if k == SLOT_INTS else np.float64
        if a.dtype != expected:
            raise RuntimeError(f"array {k} of the MuJoCo adapter is not a writeable C-contiguous "
                               f"{np.dtype(expected)} array of 1 or 2 dimensions")
    table = np.zeros(3 * N_TABLE, dtype=np.int64)
    table[:3 * len(arrays)] = addresses.address_table(arrays)
    return table


def direct(fn: Any, table: np.ndarray) -> Any:
    """``fn``'s compiled code for a table, callable without numba's dispatcher (or ``fn`` itself):
    :func:`mudforce._kernel.addresses.entry_point` for the table's type.

    Calling it skips the dispatcher's type resolution, ~0.2 us per call,
    most of the adapter's overhead per step.
    """
    return addresses.entry_point(fn, (typeof(table),))
