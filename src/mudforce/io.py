"""File output that never leaves a half-written file behind."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from mudforce.errors import InputError

__all__ = ["atomic_open", "atomic_write_text", "check_output_dir", "check_output_path"]


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w", encoding: str | None = "utf-8") -> Iterator[IO]:  # type: ignore[type-arg]
    """Open a temporary file beside ``path``; rename it onto ``path`` on success.

    If the block raises, the temporary file is removed and an existing
    ``path`` is left untouched.
    """
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=directory)
    try:
        # mkstemp makes the file private (0600); give it the usual 0666 & ~umask
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        binary = "b" in mode
        with os.fdopen(fd, mode, encoding=None if binary else encoding, newline=None if binary else "") as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` to ``path`` through :func:`atomic_open`."""
    with atomic_open(path, "w") as handle:
        handle.write(text)


def check_output_path(text: str | os.PathLike[str], option: str, *, suffix: str | None = None) -> Path:
    """Refuse an output file that cannot be written, before any work is done.

    Parameters
    ----------
    text : str or path-like
        The path as given.
    option : str
        The option's name, for the message (``"--out"``).
    suffix : str, optional
        Required file extension (``".png"``), compared case-free.

    Raises
    ------
    InputError
        Empty name, ``-``, wrong extension, a directory, a missing or
        unwritable directory, or an existing unwritable file.
    """
    if not str(text).strip():
        raise InputError(f"{option}: empty file name; expected a file name")
    if str(text).strip() == "-":
        raise InputError(f"{option}: writing to stdout ('-') is not supported; expected a file name")
    path = Path(text)
    if suffix is not None and path.suffix.lower() != suffix:
        raise InputError(f"{option}: {str(path)!r} must end in {suffix} (only {suffix[1:].upper()} is written)")
    if path.is_dir():
        raise InputError(f"{option}: {str(path)!r} is a directory; expected a file name")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{option}: directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{option}: directory {str(parent)!r} is not writable")
    if path.exists() and not os.access(path, os.W_OK):
        raise InputError(f"{option}: {str(path)!r} exists and is not writable")
    return path


def check_output_dir(out: str | os.PathLike[str], option: str = "--out") -> Path:
    """Create the output folder ``out`` if needed and make sure files can be written there.

    Raises
    ------
    InputError
        If ``out`` is an existing file, cannot be created, or is not writable.
    """
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {path}: exists and is not a directory")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {path}: cannot create the directory ({exc.strerror or exc})") from None
    try:
        with tempfile.NamedTemporaryFile(dir=path, prefix=".mudforce-write-test."):
            pass
    except OSError as exc:
        raise InputError(f"{option} {path}: cannot write there ({exc.strerror or exc})") from None
    return path
