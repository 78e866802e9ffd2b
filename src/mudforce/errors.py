"""The package's exception for bad input, and the one check that several modules share."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["MAX_SEED", "InputError", "positive_int", "seed_int"]

#: Largest seed accepted [-]: what numpy's generators take as one 32-bit word.
MAX_SEED = 2**32 - 1


class InputError(ValueError):
    """Bad input: a value, file, unit or parameter the model cannot accept.

    The message is one line that names the problem and shows what is
    expected. The command line prints it and exits with status 2.
    """


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
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(f"{name} must be an integer >= 1{alternative}, got {value!r}")
    return int(value)


def seed_int(value: Any, name: str = "--seed") -> int:
    """``value`` as a seed: an integer in [0, :data:`MAX_SEED`] (not bool), else :class:`InputError`."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value <= MAX_SEED:
        raise InputError(f"{name} must be an integer in [0, {MAX_SEED}], got {value!r}")
    return int(value)
