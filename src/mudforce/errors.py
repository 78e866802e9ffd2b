"""The package's exception for bad input, and the checks of single values that several modules share."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["MAX_FEET", "MAX_SEED", "InputError", "feet_count", "finite_number", "holds_boolean", "is_integer",
           "is_real", "number_within", "positive_int", "positive_number", "real_array", "real_number", "seed_int",
           "shown", "true_or_false"]

#: Largest seed accepted [-]: what numpy's generators take as one 32-bit word.
MAX_SEED = 2**32 - 1

#: Most feet one stepper or tracker holds [-] (ours): ten million 1-D feet are a few GB of state; past this a count
#: is a mistake, which would otherwise end in numpy's MemoryError or OverflowError when the state is allocated.
MAX_FEET = 10**7


class InputError(ValueError):
    """Bad input: a value, file, unit or parameter the model cannot accept.

    The message is one line that names the problem and shows what is
    expected. The command line prints it and exits with status 2.
    """


def shown(value: Any) -> str:
    """``value`` as a message shows it: its ``repr``, but an integer past 15 digits as ``1e+20`` and one past 300
    digits as its size in bits (Python refuses to print an integer of over 4,300 digits: ValueError), a value
    holding such an integer (a list's item) by its type, a repr that spans lines (a 2-D array's) on one line, a
    repr of over 160 characters by its first 80 and what it is (``[Foot(area=...... (a list of 64 items)``), and a
    numpy scalar as the Python number it holds (``-0.0``, not ``np.float64(-0.0)``)."""
    if isinstance(value, (np.floating, np.bool_)):
        value = value.item()
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        count = int(value)
        if abs(count) < 10**15:
            return repr(count)
        if abs(count) < 10**300:
            return f"{count:.3g}"
        return f"{'a negative' if count < 0 else 'an'} integer of {count.bit_length()} bits"
    try:
        text = repr(value)
    except ValueError:  # an integer of over 4,300 digits inside it (a list's item): repr raised
        return f"a {type(value).__name__} holding an integer too long to show"
    text = " ".join(text.split()) if "\n" in text else text
    if len(text) > _SHOWN_MOST:  # a long list's repr (64 Foot objects: 4,600 characters) on one line: its start
        try:
            size = f" of {len(value)} items" if not isinstance(value, (str, bytes)) else f" of {len(value)} characters"
        except TypeError:  # (no len)
            size = ""
        text = f"{text[:_SHOWN_HEAD]}... (a {type(value).__name__}{size})"
    return text


_SHOWN_MOST = 160  # characters of a repr shown whole; a longer one is cut to its first _SHOWN_HEAD
_SHOWN_HEAD = 80


def positive_int(value: Any, name: str, alternative: str = "") -> int:
    """``value`` as an ``int`` if it is an integer >= 1 (Python or numpy, not ``bool``), else :class:`InputError`.

    Parameters
    ----------
    value : Any
        A count: feet, threads, jobs, substeps, repeats [-].
    name : str
        What it counts, for the message (``"the number of feet n"``).
    alternative : str
        What else the caller accepts, for the message (``" or None (automatic)"``).
    """
    if not is_integer(value) or value < 1:
        raise InputError(f"{name} must be an integer >= 1{alternative}, got {shown(value)}")
    return int(value)


def feet_count(value: Any, name: str = "the number of feet n") -> int:
    """``value`` as a number of feet: an integer in [1, :data:`MAX_FEET`] (not ``bool``), else :class:`InputError`."""
    count = positive_int(value, name)
    if count > MAX_FEET:
        raise InputError(f"{name} must be at most {MAX_FEET} (one object's feet), got {shown(count)}")
    return count


def seed_int(value: Any, name: str = "--seed") -> int:
    """``value`` as a seed: an integer in [0, :data:`MAX_SEED`] (not bool), else :class:`InputError`."""
    if not is_integer(value) or not 0 <= value <= MAX_SEED:
        raise InputError(f"{name} must be an integer in [0, {MAX_SEED}], got {shown(value)}")
    return int(value)


def true_or_false(value: Any, name: str) -> bool:
    """``value`` as a ``bool`` if it is ``True`` or ``False`` (Python's or numpy's), else :class:`InputError`.

    A boolean option is not read by its truth value: ``"no"`` (true), ``None``, ``0`` or an array are refused.

    Parameters
    ----------
    value : Any
        The option's value.
    name : str
        The option, for the message (``"quiet"``).
    """
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} must be True or False, got {shown(value)}")
    return bool(value)


def is_integer(value: Any) -> bool:
    """Whether ``value`` is a Python or numpy integer (not ``bool``; not a float, even a whole one: ``int(0.7)``
    would read it as 0): the one integer type test of the checks here and of the package's counts and indices."""
    return not isinstance(value, bool) and isinstance(value, (int, np.integer))


def is_real(value: Any) -> bool:
    """Whether ``value`` is a Python or numpy real number (not ``bool``): the one type test of the checks here."""
    return not isinstance(value, bool) and isinstance(value, (int, float, np.integer, np.floating))


def real_number(value: Any, name: str) -> float:
    """``value`` as a ``float`` if it is a real number, else :class:`InputError`; no check of its range.

    A real number is a Python or numpy integer or float (not ``bool``), or
    a 0-d numpy array of an integer or float dtype. NaN and infinities
    pass: the caller checks the bounds.

    Parameters
    ----------
    value : Any
        The value to check, in the caller's unit.
    name : str
        What it is, for the message (``"depth"``).

    Returns
    -------
    float
        ``value`` in the caller's unit.
    """
    if not is_real(value):
        if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iuf":
            return float(value)
        raise InputError(f"{name} must be a real number, got {type(value).__name__}")
    return _as_float(value, name)


def _as_float(value: Any, name: str) -> float:
    """``float(value)`` of a real number (:func:`is_real`); one line for a Python int beyond float64, for which
    ``float()`` raises OverflowError (its size, not its digits: a repr of 10**5000 raises ValueError)."""
    try:
        return float(value)
    except OverflowError:
        raise InputError(f"{name} must be a real number within float64's range (+-1.8e308), got "
                         f"{shown(int(value))}") from None


def real_array(value: Any, name: str, unit: str, *, must: str | None = None) -> np.ndarray:
    """``value`` as a float64 array if it holds real numbers, else :class:`InputError`; no check of shape or range.

    The one conversion of the API's array inputs (time, depths, forces, ...):
    a sequence or array of Python or numpy integers or floats. Complex
    numbers (whose imaginary part ``float64`` would drop with only a
    warning), booleans (also mixed among numbers in a list, which numpy
    would read as 0 and 1), strings (which numpy would parse) and objects are
    refused with one line naming the dtype; a masked array with a masked
    value is refused (its masked values were read as numbers), one without
    is read as its data. NaN and infinities pass: the caller checks the
    bounds.

    Parameters
    ----------
    value : Any
        The array, in ``unit``.
    name : str
        What it is, for the message (``"time"``).
    unit : str
        Its unit, for the message (``"s"``).
    must : str, optional
        The message's words before ``", got <what value holds>"``, for a caller that says what it expects in its own
        words (``"position must be 3 real numbers [m]"``); by default
        ``"<name> must be an array of real numbers [<unit>]"``.

    Returns
    -------
    ndarray of float64
        ``value`` [``unit``]: ``value`` itself if it is already a float64 array.
    """
    if isinstance(value, np.ma.MaskedArray):  # its masked values were read as numbers (float64: kept, mask and all)
        masked = int(np.ma.count_masked(value))
        if masked:
            raise InputError(f"{_must(name, unit, must)}, got a masked array with {masked} masked value(s); fill or "
                             "drop them first")
        value = value.data
    if isinstance(value, np.ndarray) and value.dtype == np.float64:
        return value
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):  # ragged nesting, objects numpy cannot hold
        raise InputError(f"{_must(name, unit, must)}, got {type(value).__name__}") from None
    if arr.dtype.kind not in "iuf":
        kind = {"c": "complex", "b": "boolean", "U": "string", "S": "bytes", "O": "object"}.get(arr.dtype.kind, "")
        what = f"{kind} values (dtype {arr.dtype})" if kind else f"dtype {arr.dtype}"
        raise InputError(f"{_must(name, unit, must)}, got {what}")
    if not isinstance(value, np.ndarray) and holds_boolean(value):  # numpy reads [0.1, True] as [0.1, 1.0]
        raise InputError(f"{_must(name, unit, must)}, got a sequence holding booleans (True/False among the "
                         "numbers)")
    return np.asarray(arr, dtype=np.float64)


def _must(name: str, unit: str, must: str | None) -> str:
    """real_array's words before ", got ...": ``must``, or by default those of an array of real numbers."""
    return f"{name} must be an array of real numbers [{unit}]" if must is None else must


def holds_boolean(value: Any) -> bool:
    """Whether a (nested) list or tuple holds a ``bool``, a numpy boolean or a boolean array anywhere."""
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, (bool, np.bool_)):
            return True
        if isinstance(item, (list, tuple)):
            stack.extend(item)
        elif isinstance(item, np.ndarray) and item.dtype.kind == "b":
            return True
    return False


def finite_number(value: Any, name: str, unit: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    """``value`` as a finite ``float`` (a Python or numpy real number, not ``bool`` or ``str``), else InputError.

    Parameters
    ----------
    value : Any
        The value to check, in ``unit``.
    name : str
        What it is, for the message (``"mass"``).
    unit : str
        Its unit, for the message (``"kg"``).
    positive : bool
        Also require ``value > 0``.
    nonnegative : bool
        Also require ``value >= 0``.

    Returns
    -------
    float
        ``value`` [``unit``].
    """
    if not is_real(value):
        raise InputError(f"{name} must be a number [{unit}], got {type(value).__name__} {shown(value)}")
    number = _as_float(value, name)
    if not math.isfinite(number):
        raise InputError(f"{name} must be finite [{unit}], got {shown(value)}")
    if positive and number <= 0.0:
        raise InputError(f"{name} must be > 0 [{unit}], got {shown(value)}")
    if nonnegative and number < 0.0:
        raise InputError(f"{name} must be >= 0 [{unit}], got {shown(value)}")
    return number


def number_within(value: Any, name: str, lo: float, hi: float, unit: str) -> float:
    """``value`` as a ``float`` in ``[lo, hi]`` (a Python or numpy real number, not ``bool``), else InputError.

    Parameters
    ----------
    value : Any
        The value to check.
    name : str
        What it is, for the message (``"cuboid length"``).
    lo, hi : float
        The accepted range, in ``unit``.
    unit : str
        Its unit, for the message (``"m"``).
    """
    if not is_real(value):
        raise InputError(f"{name} must be a number [{unit}], got {type(value).__name__}")
    number = _as_float(value, name)
    if not (math.isfinite(number) and lo <= number <= hi):
        raise InputError(f"{name} must be within [{lo:g}, {hi:g}] {unit}, got {shown(value)}")
    return number


def positive_number(value: Any, name: str, unit: str) -> float:
    """``value`` as a finite ``float`` > 0 (a Python or numpy real number, not ``bool``), else :class:`InputError`.

    Parameters
    ----------
    value : Any
        The value to check.
    name : str
        What it is, for the message (``"hold duration"``).
    unit : str
        Its unit, for the message (``"s"``).
    """
    if not is_real(value):
        raise InputError(f"{name} must be a number [{unit}], got {shown(value)}")
    number = _as_float(value, name)
    if not (math.isfinite(number) and number > 0.0):
        raise InputError(f"{name} must be finite and > 0 [{unit}], got {shown(value)}")
    return number
