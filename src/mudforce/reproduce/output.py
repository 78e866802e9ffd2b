"""The report's folder of :mod:`mudforce.reproduce`: checked first, built aside, swapped in whole.

``mudforce reproduce --out DIR`` replaces the folder ``DIR`` as a whole, so
that a run stopped at any point (Ctrl-C, SIGTERM, even SIGKILL or a power
cut) leaves either the old report or the new one in ``DIR``, never a mix:

1. :func:`check_report_dir` refuses, before any work, a ``DIR`` that is a
   file, that holds anything but an earlier report (``report.html``,
   ``summary.json``, PNGs), or that overlaps the mudforce package (whose
   files are the report's inputs): what is in ``DIR`` is replaced.
2. :class:`StagedFolder` builds the report in a sibling folder
   ``.DIR.mudforce-reproduce-new-XXXXXXXX`` (hidden), locked with
   ``flock`` for as long as the run (and its workers) live.
3. :meth:`StagedFolder.commit` swaps it in: on Linux with one atomic
   ``renameat2(RENAME_EXCHANGE)``; elsewhere by renaming ``DIR`` aside
   (``.DIR.mudforce-reproduce-old-XXXXXXXX``), then the new folder in.
   The old report is then deleted.

Each run first removes the siblings that earlier killed runs left (those
whose lock nobody holds); an old report left renamed aside between the two
renames of step 3 is put back if ``DIR`` is missing.

``mudforce synth --out DIR`` replaces its dataset folder the same way
(``check_report_dir(..., foreign=..., what="synth dataset")``, ``StagedFolder(...,
tag="mudforce-synth")``): one mechanism for every command that writes a folder.

File-system plumbing (no physics).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import stat
import sys
import tempfile
import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from types import TracebackType

from mudforce.errors import InputError

__all__ = ["REPORT_FILES", "StagedFolder", "check_report_dir", "clean_stale"]

#: What a report folder may hold besides its PNG figures.
REPORT_FILES = frozenset({"report.html", "summary.json"})

_TAG = "mudforce-reproduce"
_RENAME_EXCHANGE = 2  # renameat2(2) flag
_AT_FDCWD = -100


def _sibling_prefix(path: Path, kind: str, tag: str = _TAG) -> str:
    return f".{path.name}.{tag}-{kind}-"


def _is_report_entry(name: str) -> bool:
    """A file a report folder may hold: its own files, PNG figures, atomic writers' leftovers (``.*.tmp``)."""
    return name in REPORT_FILES or name.lower().endswith(".png") or (name.startswith(".") and name.endswith(".tmp"))


def _package_dir() -> Path:
    return Path(__file__).resolve().parent.parent


def _foreign_to_report(path: Path) -> list[str]:
    """The entries of folder ``path`` that an earlier report did not write, sorted by name."""
    return sorted(p.name for p in path.iterdir() if not (_is_report_entry(p.name) and p.is_file()))


def check_report_dir(out: str | os.PathLike[str], option: str = "--out", *,
                     foreign: Callable[[Path], list[str]] = _foreign_to_report, what: str = "report",
                     tag: str = _TAG) -> Path:
    """The report folder ``out`` as an absolute path, after checking that it can be replaced whole.

    Parameters
    ----------
    out : path-like
        The folder (need not exist; its parent is created if needed).
    option : str
        The option's name, for the message.
    foreign : callable, optional
        Folder -> the names of its entries that an earlier output of the
        command did not write (sorted); any makes the folder refused. By
        default, anything but ``report.html``, ``summary.json`` and PNGs.
    what : str
        What the folder holds, for the messages (``"report"``, ``"synth dataset"``).
    tag : str
        Names the hidden sibling that probes the parent folder, as :class:`StagedFolder`'s ``tag``.

    Returns
    -------
    Path
        ``out`` resolved (symbolic links followed).

    Raises
    ------
    InputError
        If ``out`` is a file or a mount point, holds anything but an earlier
        output (``foreign``), overlaps the mudforce package, or its parent
        folder cannot be created or written.
    """
    given = str(out)
    if not given.strip():
        raise InputError(f"{option}: empty folder name; expected a folder for the {what}")
    path = Path(out).resolve()
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {given}: exists and is not a directory")
    if path.parent == path:
        raise InputError(f"{option} {given}: the root folder cannot hold a {what}; expected a folder below it")
    package = _package_dir()
    if path == package or package in path.parents or path in package.parents:
        raise InputError(f"{option} {given}: overlaps the mudforce package ({package}), whose files are the "
                         f"{what}'s inputs; expected a folder outside it")
    if path.is_dir() and os.path.ismount(path):
        raise InputError(f"{option} {given}: is a mount point, which cannot be replaced whole; expected a folder "
                         "inside it")
    if path.is_dir():
        try:
            others = foreign(path)
        except OSError as exc:
            raise InputError(f"{option} {given}: cannot list the folder ({exc.strerror or exc})") from None
        if others:
            more = f" and {len(others) - 1} more" if len(others) > 1 else ""
            raise InputError(f"{option} {given}: holds {others[0][:80]!r}{more}, not part of a mudforce {what} (the "
                             f"folder is replaced whole); expected a new or empty folder, or an earlier {what}'s")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {given}: cannot create its parent folder ({exc.strerror or exc})") from None
    try:
        probe = tempfile.mkdtemp(prefix=_sibling_prefix(path, "probe", tag), dir=path.parent)
        with contextlib.suppress(FileNotFoundError):  # a concurrent clean_stale may have taken it
            os.rmdir(probe)
    except OSError as exc:
        raise InputError(f"{option} {given}: cannot write beside it in {path.parent} "
                         f"({exc.strerror or exc})") from None
    return path


# ---------------------------------------------------------------------------- locks
def _lock(path: Path) -> int | None:
    """An open descriptor of folder ``path`` holding an exclusive ``flock``; None where flock is unavailable."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        return None
    fd = os.open(path, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise
    return fd


def _unused(path: Path) -> bool:
    """Whether nobody holds the lock of folder ``path`` (its run ended); False where that cannot be told."""
    try:
        fd = _lock(path)
    except OSError:
        return False
    if fd is None:  # pragma: no cover - not POSIX
        return False
    os.close(fd)
    return True


def clean_stale(path: Path, tag: str = _TAG) -> list[Path]:
    """Remove what killed runs left beside report folder ``path``; put back an old report left aside.

    Only siblings named by this module (with ``tag``: ``"mudforce-reproduce"``,
    ``"mudforce-synth"``) and locked by nobody are touched.

    Returns
    -------
    list of Path
        The siblings removed or put back.
    """
    done = []
    parent = path.parent
    with contextlib.suppress(OSError):
        for kind in ("old", "new", "probe"):
            for sibling in sorted(parent.glob(_sibling_prefix(path, kind, tag) + "*")):
                if not sibling.is_dir() or sibling.is_symlink() or not _unused(sibling):
                    continue
                if kind == "old" and not path.exists():
                    os.rename(sibling, path)  # the run died between its two renames: the old report is back
                else:
                    shutil.rmtree(sibling, ignore_errors=True)
                done.append(sibling)
    return done


# ---------------------------------------------------------------------------- the swap
@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGTERM and SIGINT back inside (main thread, POSIX); they are delivered on leaving."""
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    held = {signal.SIGTERM, signal.SIGINT}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _exchange(a: Path, b: Path) -> bool:
    """Swap folders ``a`` and ``b`` atomically (Linux ``renameat2``); False where that is not available."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):  # pragma: no cover - glibc < 2.28 or another libc
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (38, 22, 95):  # ENOSYS, EINVAL (file system without exchange), EOPNOTSUPP
        return False
    raise OSError(err, os.strerror(err), str(b))


class StagedFolder:
    """A hidden sibling folder where a report is built, then swapped in for ``path`` whole.

    Use as a context manager: leaving it with an exception removes the
    staged folder and leaves ``path`` as it was; :meth:`commit` swaps.

    Parameters
    ----------
    path : Path
        The report folder, as :func:`check_report_dir` returns it.
    tag : str
        Names the hidden siblings (``.DIR.TAG-new-XXXXXXXX``): the command's, e.g. ``"mudforce-synth"``.
    """

    def __init__(self, path: Path, tag: str = _TAG) -> None:
        self.path = path
        self.tag = tag
        clean_stale(path, tag)
        self.staged = Path(tempfile.mkdtemp(prefix=_sibling_prefix(path, "new", tag), dir=path.parent))
        umask = os.umask(0)
        os.umask(umask)
        with contextlib.suppress(OSError):
            mode = stat.S_IMODE(os.stat(path).st_mode) if path.is_dir() else 0o777 & ~umask
            os.chmod(self.staged, mode)
        self._fd = _lock(self.staged)
        self.committed = False

    def __enter__(self) -> StagedFolder:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if not self.committed:
            shutil.rmtree(self.staged, ignore_errors=True)
        self._release()

    def _release(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def commit(self) -> None:
        """Put the staged folder in place of ``path`` (one atomic step where the system allows), drop the old.

        SIGTERM and SIGINT are held back meanwhile (where the system allows),
        so that they act before the swap or after it, never between its steps.
        """
        with _signals_held():
            self._swap()
            self.committed = True
            self._release()

    def _swap(self) -> None:
        path = self.path
        if not path.exists():
            os.rename(self.staged, path)
        elif _exchange(self.staged, path):
            shutil.rmtree(self.staged, ignore_errors=True)  # now the old report
        else:
            aside = Path(tempfile.mkdtemp(prefix=_sibling_prefix(path, "old", self.tag), dir=path.parent))
            os.rmdir(aside)
            fd = _lock(path)  # the old report, aside, stays recognisably in use until deleted
            try:
                os.rename(path, aside)
                try:
                    os.rename(self.staged, path)
                except OSError:
                    os.rename(aside, path)
                    raise
                shutil.rmtree(aside, ignore_errors=True)
            finally:
                if fd is not None:
                    os.close(fd)
