"""Keep numba's on-disk cache honest when the stepper's source changes.

numba keys a cached function on its own source file only. Functions in other
modules compile the stepper ``_kernel.step`` (and the equations) into their own
machine code (``dynamics``, ``mujoco``, ``calibration.models``, ``_kernel``'s own
loops use ``equations``), so after an edit of ``_kernel.py`` or
``equations.py`` alone their cached code would silently be the old model.
:func:`refresh` fingerprints those two files and, when the fingerprint
changes, deletes the package's numba cache files so that everything
recompiles once. Installed packages never change, so this only ever acts in
a development checkout. It does nothing when ``NUMBA_CACHE_DIR`` points
elsewhere or the package folder is read-only.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
from pathlib import Path

__all__ = ["refresh"]

_PACKAGE = Path(__file__).resolve().parent
_SOURCES = ("_kernel.py", "equations.py", "_pow.py")
_STAMP = _PACKAGE / "__pycache__" / "numba-kernel.stamp"


def _fingerprint() -> str:
    digest = hashlib.sha256()
    for name in _SOURCES:
        digest.update((_PACKAGE / name).read_bytes())
    return digest.hexdigest()


def refresh() -> None:
    """Delete stale numba cache files if the stepper's source changed since they were made."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    try:
        current = _fingerprint()
        if _STAMP.exists() and _STAMP.read_text(encoding="ascii").strip() == current:
            return
        for pattern in ("*.nbi", "*.nbc"):
            for path in _PACKAGE.rglob(f"__pycache__/{pattern}"):
                with contextlib.suppress(OSError):
                    path.unlink()
        _STAMP.parent.mkdir(exist_ok=True)
        tmp = _STAMP.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(current + "\n", encoding="ascii")
        os.replace(tmp, _STAMP)
    except OSError:
        pass  # a read-only install: nothing is stale there
