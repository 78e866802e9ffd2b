"""numba's on-disk cache, keyed on the content of the stepper's sources as well as each file.

numba keys a cached function on its own source file only (its time stamp
and size, or its hash in recent numba). But compiled functions here take
other files' code into their own machine code: ``inline="always"``
functions and small callees of :mod:`mudforce.model.equations`,
:mod:`mudforce._plumbing.pow` and the :mod:`mudforce._kernel` package end up inside
the loops of ``_kernel.loops``, ``dynamics``, ``mujoco``...;
:mod:`mudforce.engines.dynamics.rest_band` inside the built-in engine and the
MuJoCo adapter's step (:mod:`mudforce.engines.mujoco._step`), which is itself
inside :mod:`mudforce.engines.mujoco._fast`; and the engine's phase codes
(:class:`mudforce.engines.dynamics.result.Phase`) are constants in its code, as
are the input bounds of :mod:`mudforce.model.bounds` in :mod:`mudforce._kernel.bounds`
and the tracker's packed layout (:mod:`mudforce.estimation._tracker_layout`) in
its step (:mod:`mudforce.estimation._tracker_step`). So
after an edit of ``equations.py`` alone, their cached code would silently
be the old model.

The fix is at the cache's key: :func:`install` puts, in front of numba's
own cache locators, subclasses of them that serve mudforce's files only
and whose source stamp is numba's stamp for the file *plus* a hash of the
content of those shared sources (:data:`SOURCES`). A cache made from other
sources then simply does not match and is recompiled and overwritten, as
numba does for an edited file; no file is ever deleted. Installed
packages never change, so this only ever matters in a development
checkout. It needs only numba's locator classes and their
``get_source_stamp``; if a numba version lacks them, :func:`install` does
nothing and the cache is numba's own (a compile after an edit then needs
``NUMBA_CACHE_DIR`` pointed at a fresh folder, or the ``__pycache__``
folders removed by hand).

:func:`install` runs when ``mudforce`` is imported, before any of its
compiled functions is defined (numba picks a function's locator then).
"""

from __future__ import annotations

import functools
import hashlib
from pathlib import Path
from typing import Any

__all__ = ["SOURCES", "install", "source_fingerprint"]

_PACKAGE = Path(__file__).resolve().parents[1]
#: the sources compiled into other modules' code, relative to the package (globs)
SOURCES = ("_plumbing/pow.py", "model/equations.py", "_kernel/*.py", "engines/dynamics/rest_band.py",
           "engines/dynamics/result.py", "engines/mujoco/_step.py",
           "model/law3d.py", "model/granular.py",  # the 3-D law, compiled into step3d
           "model/bounds.py",  # the input bounds, constants in _kernel.bounds
           "estimation/_tracker_layout.py",  # the tracker's packed layout, constants in _tracker_step
           "estimation/nuisances.py")  # the force lag's low-pass, in identify's model and the tracker's step


@functools.lru_cache(maxsize=1)
def source_fingerprint() -> str:
    """SHA-256 of the content of :data:`SOURCES` (read once per process)."""
    digest = hashlib.sha256()
    for pattern in SOURCES:
        for path in sorted(_PACKAGE.glob(pattern)):
            digest.update(path.relative_to(_PACKAGE).as_posix().encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()


def _ours(py_file: str) -> bool:
    try:
        return Path(py_file).resolve().is_relative_to(_PACKAGE)
    except (OSError, ValueError):
        return False


def _keyed(base: Any) -> Any:
    """A subclass of numba's locator class ``base`` for mudforce's files, stamped with :func:`source_fingerprint`."""

    class Locator(base):  # type: ignore[misc, valid-type]
        def get_source_stamp(self) -> Any:
            return (super().get_source_stamp(), source_fingerprint())

        @classmethod
        def from_function(cls, py_func: Any, py_file: str) -> Any:
            if not _ours(py_file):
                return None
            return super().from_function(py_func, py_file)

    Locator.__name__ = Locator.__qualname__ = f"Mudforce{base.__name__}"
    return Locator


_installed = False


def install() -> None:
    """Put the content-keyed locators in front of numba's (once; see the module)."""
    global _installed
    if _installed:
        return
    _installed = True
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    mixin = getattr(caching, "_SourceFileBackedLocatorMixin", None)
    classes = getattr(impl, "_locator_classes", None)
    if mixin is None or not isinstance(classes, list):
        return
    ours = [_keyed(base) for base in classes if isinstance(base, type) and issubclass(base, mixin)]
    classes[:0] = ours
