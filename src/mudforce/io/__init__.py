"""File input and output at the package's edges: outputs written atomically to what the user named,
never onto an input, and JSON that is read and written strictly.

The one mechanism every command shares (``mudforce.cli.*``):

1. :func:`check_output_path` / :func:`check_output_dir` for each output, before any work:
   refuses an empty name, ``-``, a directory, a FIFO or device, a missing
   or unwritable folder, a name the file system cannot hold;
2. :func:`refuse_overwriting_inputs` with every output and every input
   (a manifest's trial files included), before any work: refuses an
   output that is an input (the same file through links or other names,
   compared with :func:`os.path.samefile` and resolved paths), an output
   folder that holds an input, and two outputs that are one file;
3. :func:`atomic_open` to write: a temporary file with a short name beside
   the link's *target*, renamed onto it, so a symbolic link stays a link and
   its target gets the new content; on an error the old file is untouched.

Outputs that must change together (``reproduce --out DIR``'s folder,
``fit --out FIT.json --report DIR``'s file and folder) are built aside and
swapped in at the end, so that a run stopped at any point (Ctrl-C, SIGTERM,
SIGKILL, a power cut) leaves the old outputs or the new ones, never a mix:

4. :func:`check_replaceable_dir` refuses, before any work, a folder that
   holds anything but an earlier output of the same kind (it is replaced
   whole);
5. :class:`StagedOutputs` builds each output in a hidden sibling folder
   ``.NAME.TAG-new-XXXXXXXX`` beside its target, locked with ``flock`` for
   as long as the run (and its forked workers) live, and
   :meth:`StagedOutputs.commit` swaps them all in, with SIGINT and SIGTERM
   held back (folders: one atomic ``renameat2(RENAME_EXCHANGE)`` on Linux,
   else two renames; then files, by one rename each);
6. each run first removes, with :func:`clean_stale`, the siblings of its
   targets that earlier killed runs left (those no live process locks),
   and puts back an old folder left aside between two renames.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import re
import shutil
import stat
import sys
import tempfile
from collections.abc import Callable, Collection, Iterable, Iterator
from pathlib import Path
from types import TracebackType
from typing import IO, Any, TypeVar

from mudforce._plumbing import interrupt as _interrupt
from mudforce._plumbing.writes import WriteFailure, is_path_error, write_error
from mudforce.errors import InputError

__all__ = [
    "MAX_JSON_BYTES",
    "StagedOutputs",
    "atomic_open",
    "atomic_write_text",
    "check_input_name",
    "check_output_dir",
    "check_output_path",
    "check_replaceable_dir",
    "clean_stale",
    "dumps_json",
    "load_json",
    "refuse_overwriting_inputs",
    "write_outputs",
    "write_target",
]

#: Largest JSON input (a parameter file, a manifest) read [bytes]: 64 MiB.
MAX_JSON_BYTES = 64 * 2**20
#: Longest integer literal accepted in a JSON input [digits] (larger ones are no physical value).
_MAX_INT_DIGITS = 20
#: The temporary file's name beside the target: fixed length, whatever the target's name.
_TMP_PREFIX = ".mf-"
_TMP_SUFFIX = ".tmp"


def write_target(path: str | os.PathLike[str]) -> Path:
    """Where writing ``path`` really goes: the final target of a symbolic link (chains too), else ``path``.

    A dangling link resolves to the file it names, which is created.
    """
    p = Path(os.fspath(path))
    if p.is_symlink():
        return Path(os.path.realpath(p))
    return p


def _permissions(target: Path, default: int) -> int:
    """An existing ``target``'s permission bits, else ``default & ~umask`` (what a new file or folder gets)."""
    try:
        return stat.S_IMODE(target.stat().st_mode)
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return default & ~umask


def _refuse_special(path: Path, option: str, shown: str) -> None:
    try:
        mode = path.stat().st_mode
    except OSError:
        return  # does not exist (yet)
    if stat.S_ISDIR(mode):
        raise InputError(f"{option}: {shown!r} is a directory; expected a file name")
    if not stat.S_ISREG(mode):
        raise InputError(f"{option}: {shown!r} is not a regular file (a FIFO, socket or device); "
                         "expected a file name")


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w", encoding: str | None = "utf-8") -> Iterator[IO]:  # type: ignore[type-arg]
    """Open a temporary file beside ``path``'s target; rename it onto the target on success.

    A symbolic link is written through: its target gets the new content and
    the link stays. The temporary name is short (``.mf-XXXXXXXX.tmp``), so
    any name the file system accepts for ``path`` works. If the block
    raises, the temporary file is removed and an existing file is left
    untouched. A FIFO, socket or device is refused (:class:`InputError`).

    An :class:`OSError` met on the way (the block's own included) names
    ``path`` as given, by one rule (:mod:`mudforce._plumbing.writes`): a
    write refused because of the path (a folder that does not exist or is
    not writable, a name too long, permission denied) is bad input,
    :class:`InputError` ``cannot write PATH: WHY``; a failure of the
    system (no space left, an I/O error, a quota exceeded) an
    :class:`OSError` whose message is ``cannot write PATH: WHY``.
    """
    if not isinstance(path, (str, os.PathLike)) or not str(path).strip():
        raise InputError(f"output must be a file path (str or os.PathLike), got {type(path).__name__} {path!r}")
    if "\x00" in str(path):  # stat() raised ValueError (embedded null byte)
        raise InputError(f"cannot write {str(path)[:80]!r}: the file name contains a NUL character")
    try:
        target = write_target(path)
    except OSError as exc:  # a name longer than the file system allows: is_symlink() raised it, a bare OSError
        raise InputError(f"cannot write {str(path)[:80]!r}: {exc.strerror or exc}") from None
    _refuse_special(target, "output", str(path))
    directory = target.parent if str(target.parent) else Path(".")
    try:
        fd, tmp = tempfile.mkstemp(prefix=_TMP_PREFIX, suffix=_TMP_SUFFIX, dir=directory)
    except (FileNotFoundError, NotADirectoryError, PermissionError) as exc:  # named by the path, not the temporary
        problem = "does not exist" if not directory.is_dir() else f"cannot hold a new file ({exc.strerror})"
        raise InputError(f"cannot write {str(path)!r}: directory {str(directory)!r} {problem}") from None
    except OSError as exc:  # a full disk, a quota, a read-only file system: named by the path, not the temporary
        raise write_error(exc, path) from None
    try:
        # mkstemp makes the file private (0600); keep an existing target's permissions, else 0666 & ~umask
        os.chmod(tmp, _permissions(target, 0o666))
        binary = "b" in mode
        with os.fdopen(fd, mode, encoding=None if binary else encoding, newline=None if binary else "") as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError) and not isinstance(exc, WriteFailure):  # (one already named stays so)
            raise write_error(exc, path) from None
        raise


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` to ``path`` through :func:`atomic_open`."""
    with atomic_open(path, "w") as handle:
        handle.write(text)


def _name_max(directory: Path) -> int:
    try:
        return int(os.pathconf(directory, "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):
        return 255


def check_input_name(path: str | os.PathLike[str], expected: str) -> Path:
    """``path`` (a str or path-like) as a :class:`~pathlib.Path`, after the checks of its name that every reader
    makes, each in one line ending in ``expected`` (``"a CSV file"``): an empty name (``Path("")`` is ``"."``, a
    directory) and a NUL character (``stat()`` raised ValueError; the name was printed raw). The readers:
    :func:`load_json`, :func:`mudforce.io.tables.read_columns`,
    :func:`mudforce.estimation.calibration.dataset.load_dataset`."""
    name = os.fspath(path)
    if not name.strip():
        raise InputError(f"empty file name {name!r}; expected {expected}")
    if "\x00" in name:
        clipped = name if len(name) <= 60 else name[:57] + "..."
        raise InputError(f"the file name {clipped!r} contains a NUL character; expected {expected}")
    return Path(path)


def check_output_path(text: str | os.PathLike[str] | None, option: str, *, suffix: str | None = None) -> Path:
    """Refuse an output file that cannot be written, before any work is done.

    Parameters
    ----------
    text : str or path-like
        The path as given.
    option : str
        The option's name, for the message (``"--out"``).
    suffix : str, optional
        Required file extension (``".png"``), compared case-free.

    Returns
    -------
    Path
        The path as given (a symbolic link stays one: :func:`atomic_open`
        writes through it to its target).

    Raises
    ------
    InputError
        Empty name, ``-``, wrong extension, a directory, a FIFO or device,
        a missing or unwritable directory, a name too long for the file
        system, or an existing unwritable file.
    """
    if text is not None and not isinstance(text, (str, os.PathLike)):  # Path(3) raised a bare TypeError
        raise InputError(f"{option}: output must be a file path (str or os.PathLike), got {type(text).__name__} "
                         f"{text!r}")
    if text is None or not str(text).strip():
        raise InputError(f"{option}: empty file name; expected a file name")
    if str(text).strip() == "-":
        raise InputError(f"{option}: writing to stdout ('-') is not supported; expected a file name")
    if "\x00" in str(text):
        raise InputError(f"{option}: the file name contains a NUL character")
    path = Path(text)
    shown = str(path)
    if suffix is not None and path.suffix.lower() != suffix:
        raise InputError(f"{option}: {shown!r} must end in {suffix} (only {suffix[1:].upper()} is written)")
    if str(text).endswith(("/", os.sep)) or path.name in ("", ".", ".."):
        raise InputError(f"{option}: {shown!r} names a directory; expected a file name")
    given_parent = path.parent if str(path.parent) else Path(".")
    try:  # (is_dir() raises a folder name longer than the file system allows: the command exited 1)
        if given_parent.is_dir() and len(os.fsencode(path.name)) > _name_max(given_parent):
            raise InputError(f"{option}: the file name {path.name[:40]!r}... is longer than the file system "
                             f"allows ({_name_max(given_parent)} bytes)")
        target = write_target(path)
    except OSError as exc:
        raise InputError(f"{option}: {shown[:80]!r}: {exc.strerror or exc}") from None
    _refuse_special(target, option, shown)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{option}: directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{option}: directory {str(parent)!r} is not writable")
    if len(os.fsencode(target.name)) > _name_max(parent):
        raise InputError(f"{option}: the file name {target.name[:40]!r}... is longer than the file system "
                         f"allows ({_name_max(parent)} bytes)")
    if target.exists() and not os.access(target, os.W_OK):
        raise InputError(f"{option}: {shown!r} exists and is not writable")
    return path


def check_output_dir(out: str | os.PathLike[str] | None, option: str = "--out") -> Path:
    """Create the output folder ``out`` if needed and make sure files can be written there.

    Raises
    ------
    InputError
        If ``out`` is empty, an existing file, cannot be created, or is not writable.
    OSError
        If the system fails while the folder is made or tried (no space left, an I/O error), naming it
        (:func:`atomic_open`'s rule).
    """
    if out is None or not str(out).strip():
        raise InputError(f"{option}: empty folder name; expected a folder name")
    if "\x00" in str(out):
        raise InputError(f"{option}: the folder name contains a NUL character")
    path = Path(out)
    try:  # (exists() raises a name longer than the file system allows: the command exited 1)
        if path.exists() and not path.is_dir():
            raise InputError(f"{option} {path}: exists and is not a directory")
    except OSError as exc:
        raise InputError(f"{option} {str(path)[:80]!r}: {exc.strerror or exc}") from None
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        if not is_path_error(exc):  # a full disk, an I/O error: the system's failure, not the name's
            raise write_error(exc, path) from None
        raise InputError(f"{option} {path}: cannot create the directory ({exc.strerror or exc})") from None
    try:
        with tempfile.NamedTemporaryFile(dir=path, prefix=_TMP_PREFIX):
            pass
    except OSError as exc:
        if not is_path_error(exc):
            raise write_error(exc, path) from None
        raise InputError(f"{option} {path}: cannot write there ({exc.strerror or exc})") from None
    return path


def _same(a: Path, b: Path) -> bool:
    """Whether two paths are one file: the same inode if both exist, else the same resolved path."""
    with contextlib.suppress(OSError):
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    return os.path.realpath(a) == os.path.realpath(b)


def _inside(path: Path, folder: Path) -> bool:
    real, root = Path(os.path.realpath(path)), Path(os.path.realpath(folder))
    return real == root or root in real.parents


def refuse_overwriting_inputs(
    outputs: Iterable[tuple[str, str | os.PathLike[str] | None]],
    inputs: Iterable[tuple[str, str | os.PathLike[str] | None]],
    folders: Iterable[tuple[str, str | os.PathLike[str] | None]] = (),
) -> None:
    """Refuse, before any work, outputs that would overwrite an input or each other.

    Parameters
    ----------
    outputs : iterable of (option, path)
        Output files (``None`` entries are skipped).
    inputs : iterable of (what, path)
        Every file or folder read: option values, a manifest and the trial
        files it lists.
    folders : iterable of (option, path)
        Output folders (a report directory): refused if one holds an input
        or an output file, or is one.

    Raises
    ------
    InputError
        Naming the output, the input and what to do.
    """
    outs = [(o, Path(p)) for o, p in outputs if p is not None]
    ins = [(w, Path(p)) for w, p in inputs if p is not None]
    dirs = [(o, Path(p)) for o, p in folders if p is not None]
    for i, (option, out) in enumerate(outs):
        for what, source in ins:
            if _same(out, source):
                raise InputError(f"{option} {str(out)!r} is the input {what} {str(source)!r}; "
                                 "it would be overwritten: choose another output name")
        for other, second in outs[i + 1:]:
            if _same(out, second):
                raise InputError(f"{option} and {other} name the same file {str(out)!r}; give two different names")
        for other, folder in dirs:
            if _same(out, folder):
                raise InputError(f"{option} {str(out)!r} is the {other} folder; give two different names")
            if _inside(out, folder):
                raise InputError(f"{option} {str(out)!r} is inside the {other} folder {str(folder)!r}, which is "
                                 "replaced whole; choose a file outside it")
    for option, folder in dirs:
        for what, source in ins:
            if _inside(source, folder):
                raise InputError(f"{option} {str(folder)!r} holds the input {what} {str(source)!r}; "
                                 "its files could be overwritten: choose another folder")


# ---------------------------------------------------------------------------- outputs staged and swapped in together
_RENAME_EXCHANGE = 2  # renameat2(2) flag
_AT_FDCWD = -100
#: The random part of a name made by :func:`tempfile.mkdtemp`.
_RANDOM_PART = re.compile(r"[a-z0-9_]{8}")
#: Longest target name kept whole in a sibling's name [bytes]; a longer one is shortened and hashed.
_SIBLING_NAME_MAX = 160


def _sibling_prefix(path: Path, tag: str, kind: str) -> str:
    """``.NAME.TAG-KIND-``: the start of the name of a sibling of ``path`` (a long NAME shortened, with a hash)."""
    name = path.name
    if len(os.fsencode(name)) > _SIBLING_NAME_MAX:
        digest = hashlib.sha256(os.fsencode(name)).hexdigest()[:12]
        name = os.fsdecode(os.fsencode(name)[:_SIBLING_NAME_MAX // 2]) + "~" + digest
    return f".{name}.{tag}-{kind}-"


def _siblings(path: Path, tag: str, kind: str) -> list[Path]:
    """The siblings of ``path`` of this ``kind`` (exact names: a name with ``*`` or ``[`` in it is no pattern)."""
    prefix = _sibling_prefix(path, tag, kind)
    parent = path.parent
    try:
        names = os.listdir(parent)
    except OSError:
        return []
    return [parent / n for n in sorted(names)
            if n.startswith(prefix) and _RANDOM_PART.fullmatch(n[len(prefix):]) is not None]


def _package_dir() -> Path:
    return Path(__file__).resolve().parents[1]


def check_replaceable_dir(out: str | os.PathLike[str], option: str, files: Collection[str], tag: str, *,
                          foreign: Callable[[Path], list[str]] | None = None, what: str = "report") -> Path:
    """The output folder ``out`` as an absolute path, after checking that it can be replaced whole.

    Parameters
    ----------
    out : path-like
        The folder (need not exist; its parent is created if needed).
    option : str
        The option's name, for the message (``"--report"``).
    files : collection of str
        The names an earlier output holds besides PNG figures (``{"report.md"}``).
    tag : str
        The command's tag in its staged siblings' names (``"mudforce-fit"``).
    foreign : callable, optional
        ``foreign(folder)`` lists, sorted, the entries of an existing folder
        that an earlier output did not write, for a command whose outputs a
        list of names cannot describe (``mudforce synth``: the CSV files its
        manifest lists); by default, what ``files`` and PNGs do not cover.
    what : str
        What the folder holds, for the messages (``"report"``, ``"synth dataset"``).

    Returns
    -------
    Path
        ``out`` resolved (symbolic links followed).

    Raises
    ------
    InputError
        If ``out`` is a file or a mount point, holds anything but an earlier
        output (``files``, PNGs, an atomic writer's ``.*.tmp`` leftover),
        overlaps the mudforce package, or its parent folder cannot be
        created or written.
    OSError
        If the system fails while the parent folder is made or tried (no space left, an I/O error), naming
        ``out`` (:func:`atomic_open`'s rule).
    """
    if not isinstance(out, (str, os.PathLike)):  # reproduce(out=5) raised a bare TypeError from Path()
        raise InputError(f"{option}: a folder is a path (str or os.PathLike), got {type(out).__name__}")
    given = str(out)
    if not given.strip():
        raise InputError(f"{option}: empty folder name; expected a folder for the {what}")
    if "\x00" in given:
        raise InputError(f"{option}: the folder name contains a NUL character")
    path = Path(out).resolve()
    try:  # (exists() raises a name longer than the file system allows: the command exited 1)
        if path.exists() and not path.is_dir():
            raise InputError(f"{option} {given}: exists and is not a directory")
    except OSError as exc:
        raise InputError(f"{option} {given[:80]!r}: {exc.strerror or exc}") from None
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

        def ours(p: Path) -> bool:
            name = p.name
            known = name in files or name.lower().endswith(".png") or (name.startswith(".") and name.endswith(".tmp"))
            return known and p.is_file()

        try:
            others = foreign(path) if foreign is not None else sorted(p.name for p in path.iterdir() if not ours(p))
        except OSError as exc:
            raise InputError(f"{option} {given}: cannot list the folder ({exc.strerror or exc})") from None
        if others:
            more = f" and {len(others) - 1} more" if len(others) > 1 else ""
            raise InputError(f"{option} {given}: holds {others[0][:80]!r}{more}, not part of a mudforce {what} (the "
                             f"folder is replaced whole); expected a new or empty folder, or an earlier {what}'s")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        if not is_path_error(exc):  # a full disk, an I/O error: the system's failure, not the name's
            raise write_error(exc, given) from None
        raise InputError(f"{option} {given}: cannot create its parent folder ({exc.strerror or exc})") from None
    try:
        probe = tempfile.mkdtemp(prefix=_sibling_prefix(path, tag, "probe"), dir=path.parent)
        with contextlib.suppress(FileNotFoundError):  # a concurrent clean_stale may have taken it
            os.rmdir(probe)
    except OSError as exc:
        if not is_path_error(exc):
            raise write_error(exc, given) from None
        raise InputError(f"{option} {given}: cannot write beside it in {path.parent} "
                         f"({exc.strerror or exc})") from None
    return path


def _lock(path: Path) -> int | None:
    """An open descriptor of folder ``path`` holding an exclusive ``flock``; None where flock is unavailable.

    The descriptor is not inherited by programs started with ``exec``, but a
    forked worker shares it: the lock lasts while any of them lives.
    """
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


def clean_stale(path: Path, tag: str) -> list[Path]:
    """Remove what killed runs tagged ``tag`` left beside output ``path``; put back an old folder left aside.

    Only folders named ``.NAME.TAG-{new,old,probe}-XXXXXXXX`` (``NAME`` being
    ``path``'s, exactly) and locked by no live process are touched.

    Parameters
    ----------
    path : Path
        An output (folder or file) as its run names it (a file's link target).
    tag : str
        The command's tag (``"mudforce-reproduce"``, ``"mudforce-fit"``).

    Returns
    -------
    list of Path
        The siblings removed or put back.
    """
    done = []
    for kind in ("old", "new", "probe"):
        for sibling in _siblings(path, tag, kind):
            with contextlib.suppress(OSError):
                if not sibling.is_dir() or sibling.is_symlink() or not _unused(sibling):
                    continue
                if kind == "old" and not os.path.lexists(path):
                    os.rename(sibling, path)  # the run died between its two renames: the old folder is back
                else:
                    shutil.rmtree(sibling, ignore_errors=True)
                done.append(sibling)
    return done


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


_Staged = TypeVar("_Staged", bound="StagedOutputs")


class StagedOutputs:
    """Outputs built in hidden sibling folders, then swapped in together: folders whole, files by a rename.

    Use as a context manager: write each output at :meth:`staged_path`,
    then :meth:`commit`; leaving without a commit (an error, Ctrl-C)
    removes what was staged and leaves every target as it was. Each target
    ``T`` gets a sibling folder ``.T.TAG-new-XXXXXXXX`` (beside a link's
    target), locked with ``flock`` until the commit or the end of the
    process, so that :func:`clean_stale`, which every new run calls first
    for each of its targets, removes it only once its run is gone.

    A failure met while staging, swapping in, or writing into a staged copy
    (an :class:`OSError` naming a file in it: :func:`atomic_open`'s) names
    the output as given, not its hidden copy, by :func:`atomic_open`'s rule:
    :class:`InputError` for a path refused, an :class:`OSError`
    ``cannot write OUTPUT: WHY`` for a failure of the system.

    Parameters
    ----------
    tag : str
        The command's tag in the siblings' names (``"mudforce-fit"``).
    folders : iterable of Path
        Output folders, replaced whole (checked with :func:`check_replaceable_dir`).
    files : iterable of path-like
        Output files (checked with :func:`check_output_path`), replaced by
        one rename each after the folders; an existing file's permissions are kept.
    """

    def __init__(self, tag: str, folders: Iterable[Path] = (), files: Iterable[str | os.PathLike[str]] = ()) -> None:
        self.tag = tag
        self.committed = False
        self._folders: dict[Path, Path] = {}  # target -> staged folder
        self._files: dict[Path, tuple[Path, Path]] = {}  # as given -> (target, staged folder holding it)
        self._locks: list[int] = []
        # made whole or not at all. The signals held while staging are delivered as the ``with`` ends, so the
        # KeyboardInterrupt of a Ctrl-C that came meanwhile is raised there, past the staging: the ``try`` holds
        # the ``with``, so that it too removes what was staged (no ``__exit__`` runs for an object whose
        # constructor raised)
        doing: Path | None = None  # the output being staged, named by a failure
        try:
            with _interrupt.held():
                for folder in folders:
                    target = doing = Path(folder)
                    self._folders[target] = self._stage(target, folder=True)
                for file in files:
                    doing = Path(file)
                    target = write_target(file)
                    self._files[Path(file)] = (target, self._stage(target, folder=False))
        except BaseException as exc:
            with _interrupt.held():  # a second Ctrl-C does not leave the staged folders half-removed
                self._discard()
            if isinstance(exc, OSError) and not isinstance(exc, WriteFailure) and doing is not None:
                raise write_error(exc, doing) from None
            raise

    def _stage(self, target: Path, *, folder: bool) -> Path:
        """A new locked sibling folder for ``target``, after removing what killed runs left beside it."""
        clean_stale(target, self.tag)
        directory = target.parent if str(target.parent) else Path(".")
        staged = Path(tempfile.mkdtemp(prefix=_sibling_prefix(target, self.tag, "new"), dir=directory))
        if folder:  # it becomes the output: an existing folder's permissions, else a new folder's (mkdtemp: 0700)
            with contextlib.suppress(OSError):
                os.chmod(staged, _permissions(target, 0o777))
        try:
            fd = _lock(staged)
        except BaseException:
            shutil.rmtree(staged, ignore_errors=True)
            raise
        if fd is not None:
            self._locks.append(fd)
        return staged

    def staged_path(self, path: str | os.PathLike[str]) -> Path:
        """Where to write the output named ``path`` (as given to the constructor): a folder, or a file's path."""
        key = Path(path)
        if key in self._folders:
            return self._folders[key]
        target, staged = self._files[key]
        return staged / target.name

    def __enter__(self: _Staged) -> _Staged:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if not self.committed:
            with _interrupt.held():  # a second Ctrl-C does not leave the staged folders half-removed
                self._discard()
        if isinstance(exc, OSError):
            output = self._output_of(exc)
            if output is not None:  # a write into a staged copy failed: named by the output it stands for
                raise write_error(exc, output) from None

    def _output_of(self, exc: OSError) -> Path | None:
        """The output (as given) whose staged copy holds ``exc``'s file; None if it names none."""
        if not exc.filename or not isinstance(exc.filename, (str, os.PathLike)):
            return None
        name = Path(os.fsdecode(exc.filename))
        for target, staged in self._folders.items():
            if name == staged or staged in name.parents:
                return target / name.relative_to(staged)
        for given, (target, staged) in self._files.items():
            if name == staged / target.name:
                return given
        return None

    def _discard(self) -> None:
        for staged in [*self._folders.values(), *(s for _, s in self._files.values())]:
            shutil.rmtree(staged, ignore_errors=True)
        self._release()

    def _release(self) -> None:
        for fd in self._locks:
            with contextlib.suppress(OSError):
                os.close(fd)
        self._locks = []

    def commit(self) -> None:
        """Swap every staged output in for its target, then drop the old folders.

        SIGTERM and SIGINT are held back meanwhile (where the system allows),
        so that they act before the swap or after it, never between its
        steps; an interrupt that came earlier and was lost (see
        :mod:`mudforce._plumbing.interrupt`) stops the commit. The folders are
        swapped first, then the files renamed; if a step fails
        (:class:`OSError`), the folders already swapped are swapped back.
        Only a SIGKILL or a power cut between two steps (microseconds) can
        leave one output new and another old; a folder then left aside is
        put back by the next run's :func:`clean_stale`.
        """
        with _interrupt.held():
            _interrupt.check()
            undo: list[Callable[[], None]] = []
            old: list[tuple[Path, int | None]] = []  # old folders to drop, each with the lock marking it in use
            doing: Path | None = None  # the output being swapped in, named by a failure
            try:
                for target, staged in self._folders.items():
                    doing = target
                    self._swap(staged, target, undo, old)
                for given, (target, staged) in self._files.items():
                    doing = given
                    new = staged / target.name
                    os.chmod(new, _permissions(target, 0o666))  # an existing file's permissions kept
                    os.replace(new, target)
            except BaseException as exc:
                for step in reversed(undo):
                    with contextlib.suppress(OSError):
                        step()
                for _, fd in old:
                    if fd is not None:
                        os.close(fd)
                if isinstance(exc, OSError) and not isinstance(exc, WriteFailure) and doing is not None:
                    raise write_error(exc, doing) from None
                raise
            self.committed = True
            self._release()
            for folder, fd in old:
                shutil.rmtree(folder, ignore_errors=True)
                if fd is not None:
                    os.close(fd)
            for _, staged in self._files.values():
                shutil.rmtree(staged, ignore_errors=True)

    def _swap(self, staged: Path, target: Path, undo: list[Callable[[], None]],
              old: list[tuple[Path, int | None]]) -> None:
        """Put folder ``staged`` in place of ``target``; add how to undo it and the old folder to drop."""
        if not target.exists():
            os.rename(staged, target)
            undo.append(lambda: os.rename(target, staged))
        elif _exchange(staged, target):

            def exchange_back() -> None:
                _exchange(staged, target)

            undo.append(exchange_back)
            old.append((staged, None))  # ``staged`` now names the old folder
        else:
            aside = Path(tempfile.mkdtemp(prefix=_sibling_prefix(target, self.tag, "old"), dir=target.parent))
            os.rmdir(aside)
            fd = _lock(target)  # the old folder, aside, stays recognisably in use until deleted
            try:
                os.rename(target, aside)
                try:
                    os.rename(staged, target)
                except OSError:
                    os.rename(aside, target)
                    raise
            except BaseException:
                if fd is not None:
                    os.close(fd)
                raise

            def back() -> None:
                os.rename(target, staged)
                os.rename(aside, target)

            undo.append(back)
            old.append((aside, fd))

# ---------------------------------------------------------------------------- JSON
def _parse_int(text: str) -> int:
    if len(text.lstrip("-")) > _MAX_INT_DIGITS:
        raise InputError(f"an integer of {len(text.lstrip('-'))} digits; expected a number of physical size")
    return int(text)


def _parse_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise InputError(f"{text[:30]!r} overflows a float; expected a number of physical size")
    return value


def _parse_constant(text: str) -> Any:
    raise InputError(f"{text} is not a JSON number; expected a finite number")


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object's members as a dict; a key given twice is refused (``json`` would keep the last)."""
    obj: dict[str, Any] = {}
    for key, value in pairs:
        if key in obj:
            raise InputError(f"the key {key[:60]!r} appears twice in one object (JSON readers disagree on which "
                             "one counts); expected each key once")
        obj[key] = value
    return obj


def load_json(path: str | os.PathLike[str], what: str, example: str = "") -> Any:
    """Read a JSON file strictly: UTF-8 (a BOM accepted), at most :data:`MAX_JSON_BYTES`, finite numbers only,
    each key once per object.

    ``NaN``/``Infinity`` tokens, integers of more than 20 digits, floats
    that overflow, a key repeated in one object (``{"alpha": 3e4, "alpha": 1.0}``:
    the ``json`` module would silently keep the last) and nesting too deep
    for the parser are refused with one line naming the file, as are
    missing, unreadable and malformed files. Every JSON file the package
    reads goes through here (parameter files, dataset manifests, ``fit.json``).

    Parameters
    ----------
    path : path-like
        The file.
    what : str
        What it is, for messages (``"parameter file"``).
    example : str
        What is expected, for the malformed-JSON message.
    """
    if not isinstance(path, (str, os.PathLike)):  # Path(3) raised a bare TypeError (load_fit(3), load_json(None))
        raise InputError(f"path must be a file name, got {type(path).__name__}; expected a {what}")
    p = check_input_name(path, f"a {what}")
    hint = f"; expected {example}" if example else ""
    try:
        size = p.stat().st_size
        if p.is_dir():
            raise InputError(f"{p}: is a directory; expected a {what}")
        if size > MAX_JSON_BYTES:
            raise InputError(f"{p}: {size} bytes is too large for a {what} (at most {MAX_JSON_BYTES} bytes)")
        text = p.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(f"{p}: {what} not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read the {what} ({exc.__class__.__name__})") from None
    try:
        return json.loads(text, parse_int=_parse_int, parse_float=_parse_float, parse_constant=_parse_constant,
                          object_pairs_hook=_unique_keys)
    except json.JSONDecodeError as exc:
        raise InputError(f"{p}: malformed JSON at line {exc.lineno}, column {exc.colno}: {exc.msg}{hint}") from None
    except InputError as exc:
        raise InputError(f"{p}: {exc}") from None
    except RecursionError:
        raise InputError(f"{p}: nested too deeply to be a {what}{hint}") from None


def dumps_json(data: Any, indent: int | None = 2) -> str:
    """``json.dumps`` that refuses NaN and infinities (which are not JSON): :class:`InputError` instead.

    Every JSON the package writes goes through here, so a non-finite number
    never leaves it as an ``Infinity`` token.
    """
    try:
        return json.dumps(data, indent=indent, allow_nan=False)
    except ValueError:
        raise InputError("a result is not finite (NaN or infinite) and cannot be written as JSON; "
                         "check the input for extreme values") from None


def write_outputs(tag: str, writers: dict[Path | None, Callable[[Path], Any] | None]) -> None:
    """Write a command's output files all or none: one atomically, several staged and swapped in together.

    Parameters
    ----------
    tag : str
        The command's tag in staged siblings' names (``"mudforce-simulate"``), as :class:`StagedOutputs` takes.
    writers : dict
        Each output path (checked with :func:`check_output_path`) and the function that writes it, given the
        path to write; an entry whose path or function is None is left out.

    Raises
    ------
    InputError
        An output refused because of its path (a folder that does not exist or is not writable, a name too long,
        permission denied), naming it, with every output as it was: a CSV is not replaced when its plot beside it
        cannot be written.
    OSError
        A failure of the system while writing (no space left, an I/O error, a quota exceeded), in one line naming
        the output, ``cannot write OUTPUT: WHY``, with every output as it was (:func:`atomic_open`'s rule).
    """
    jobs = [(Path(path), write) for path, write in writers.items() if path is not None and write is not None]
    if not jobs:
        return
    if len(jobs) == 1:
        path, write = jobs[0]
        _write_one(write, path, path)  # an atomic write of its own (atomic_open)
        return
    with StagedOutputs(tag, files=[path for path, _ in jobs]) as staged:
        for path, write in jobs:
            _write_one(write, staged.staged_path(path), path)
        staged.commit()


def _write_one(write: Callable[[Path], Any], where: Path, path: Path) -> None:
    """``write(where)``, an :class:`OSError` it raises named by the output ``path`` (atomic_open's rule)."""
    try:
        write(where)
    except WriteFailure as exc:
        if where == path:
            raise
        raise write_error(exc, path) from None  # written staged: named by the output, not its hidden copy
    except OSError as exc:
        raise write_error(exc, path) from None
