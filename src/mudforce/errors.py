"""The package's exception for bad input."""

from __future__ import annotations

__all__ = ["InputError"]


class InputError(ValueError):
    """Bad input: a value, file, unit or parameter the model cannot accept.

    The message is one line that names the problem and shows what is
    expected. The command line prints it and exits with status 2.
    """
