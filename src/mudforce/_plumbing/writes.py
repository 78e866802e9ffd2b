"""What a failed write is: bad input, or a failure of the system; either names the file, in one line.

One rule for every output (:mod:`mudforce.io`'s writers, and so every command of :mod:`mudforce.cli`):

* a failure of the system while writing (no space left, an I/O error, a quota exceeded, a file too large, no
  memory: :data:`SYSTEM_ERRNOS`) is the system's, :class:`WriteFailure`, an :class:`OSError` whose message names
  the file (exit status 1);
* any other refusal is because of the path the user gave (a folder that does not exist or is not writable, a name
  too long, a path that is a directory or runs through a file, permission denied, a read-only file system): bad
  input, :class:`~mudforce.errors.InputError` (the command line's exit status 2).

Plumbing; no physics, no units.
"""

from __future__ import annotations

import errno
import os

from mudforce.errors import InputError

__all__ = ["SYSTEM_ERRNOS", "WriteFailure", "is_path_error", "write_error"]

#: The ``errno`` values of a write that the system failed (exit status 1); every other refusal is the path's (a
#: folder through a file, ``EEXIST``, as much as a missing one, ``ENOENT``: bad input, exit status 2).
SYSTEM_ERRNOS = frozenset({
    errno.ENOSPC, errno.EDQUOT, errno.EIO, errno.EFBIG, errno.ENOMEM, errno.ENOBUFS, errno.ESTALE, errno.EAGAIN,
})


class WriteFailure(OSError):
    """The system failed while an output was written (no space left, an I/O error, a quota exceeded).

    An :class:`OSError` with the failure's ``errno`` and ``strerror``, and the output as ``filename``; ``str()``
    is one line naming it: ``cannot write g5.csv: No space left on device``.
    """

    def __str__(self) -> str:
        return f"cannot write {self.filename}: {self.strerror}"


def is_path_error(exc: OSError) -> bool:
    """Whether ``exc`` refused a write for the path given, not as a failure of the system (:data:`SYSTEM_ERRNOS`)."""
    return exc.errno not in SYSTEM_ERRNOS


def write_error(exc: OSError, path: str | os.PathLike[str]) -> InputError | WriteFailure:
    """The error to raise for ``exc``, met while writing the output ``path`` (named as the user named it).

    :class:`InputError` ``cannot write PATH: WHY`` if the path was refused (:func:`is_path_error`), else
    :class:`WriteFailure` with ``exc``'s ``errno`` and ``PATH`` as its file name; a :class:`WriteFailure` met while
    writing a staged copy is named again by the output it stands for.
    """
    name = os.fspath(path)
    shown = name if name.isprintable() else repr(name)
    why = exc.strerror or str(exc) or exc.__class__.__name__
    if is_path_error(exc):
        return InputError(f"cannot write {shown}: {why}")
    return WriteFailure(exc.errno, why, shown)
