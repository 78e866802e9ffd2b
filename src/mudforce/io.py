"""File input and output at the package's edges: outputs written atomically to what the user named,
never onto an input, and JSON that is read and written strictly.

The one mechanism every command shares (``mudforce.commands.*``):

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
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import stat
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import IO, Any

from mudforce.errors import InputError

__all__ = [
    "MAX_JSON_BYTES",
    "atomic_open",
    "atomic_write_text",
    "check_output_dir",
    "check_output_path",
    "dumps_json",
    "load_json",
    "refuse_overwriting_inputs",
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
    """
    target = write_target(path)
    _refuse_special(target, "output", str(path))
    directory = target.parent if str(target.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=_TMP_PREFIX, suffix=_TMP_SUFFIX, dir=directory)
    try:
        # mkstemp makes the file private (0600); keep an existing target's permissions, else 0666 & ~umask
        try:
            permissions = stat.S_IMODE(target.stat().st_mode)
        except OSError:
            umask = os.umask(0)
            os.umask(umask)
            permissions = 0o666 & ~umask
        os.chmod(tmp, permissions)
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


def _name_max(directory: Path) -> int:
    try:
        return int(os.pathconf(directory, "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):
        return 255


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
    if given_parent.is_dir() and len(os.fsencode(path.name)) > _name_max(given_parent):
        raise InputError(f"{option}: the file name {path.name[:40]!r}... is longer than the file system "
                         f"allows ({_name_max(given_parent)} bytes)")
    try:
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
    """
    if out is None or not str(out).strip():
        raise InputError(f"{option}: empty folder name; expected a folder name")
    if "\x00" in str(out):
        raise InputError(f"{option}: the folder name contains a NUL character")
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {path}: exists and is not a directory")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {path}: cannot create the directory ({exc.strerror or exc})") from None
    try:
        with tempfile.NamedTemporaryFile(dir=path, prefix=_TMP_PREFIX):
            pass
    except OSError as exc:
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
        or is one.

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
    for option, folder in dirs:
        for what, source in ins:
            if _inside(source, folder):
                raise InputError(f"{option} {str(folder)!r} holds the input {what} {str(source)!r}; "
                                 "its files could be overwritten: choose another folder")


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
    p = Path(path)
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
