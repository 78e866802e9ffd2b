"""Modules that moved in 0.2 (the layout by concept): each old import path still works for one release and
warns with the new one.

An import system hook, not a copy: ``import mudforce.equations`` gives the very module
``mudforce.model.equations`` (the same object, so a monkeypatch on either name is seen through both), under a
:class:`DeprecationWarning`. Submodules follow their package (``mudforce.calibration.fit`` is
``mudforce.estimation.calibration.fit``). The table is ``docs/api.md`` ("Moved in 0.2").
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
import types
import warnings
from collections.abc import Sequence

__all__ = ["MOVED", "install", "new_name"]

# old module -> new module; a submodule of an old package moves with it
MOVED: dict[str, str] = {
    "mudforce.baselines": "mudforce.model.baselines",
    "mudforce.calibration": "mudforce.estimation.calibration",
    "mudforce.commands": "mudforce.cli",
    "mudforce.contact": "mudforce.steppers.contact",
    "mudforce.contact3d": "mudforce.steppers.contact3d",
    "mudforce.dynamics": "mudforce.engines.dynamics",
    "mudforce.equations": "mudforce.model.equations",
    "mudforce.foot": "mudforce.model.foot",
    "mudforce.gait": "mudforce.motions.gait",
    "mudforce.granular": "mudforce.model.granular",
    "mudforce.jax3d": "mudforce.jax.contact3d",
    "mudforce.law3d": "mudforce.model.law3d",
    "mudforce.mjx": "mudforce.engines.mjx",
    "mudforce.mujoco": "mudforce.engines.mujoco",
    "mudforce.parameters": "mudforce.model.parameters",
    "mudforce.plotting": "mudforce.io.plotting",
    "mudforce.progress": "mudforce._plumbing.progress",
    "mudforce.protocol": "mudforce.motions.protocol",
    "mudforce.quadruped": "mudforce.motions.quadruped",
    "mudforce.reference": "mudforce.references.trajectory",
    "mudforce.reference3d": "mudforce.references.contact3d",
    "mudforce.reference_drop": "mudforce.references.drop",
    "mudforce.sensor_chain": "mudforce.motions.sensor_chain",
    "mudforce.shapes": "mudforce.model.shapes",
    "mudforce.simulation": "mudforce.steppers.simulation",
    "mudforce.tables": "mudforce.io.tables",
    "mudforce.tracker": "mudforce.estimation.tracker",
    "mudforce.tracking_plots": "mudforce.estimation.tracking_plots",
    "mudforce.units": "mudforce.io.units",
    "mudforce.vectorized": "mudforce.steppers.many",
    "mudforce.velocity": "mudforce.model.velocity",
}


def new_name(old: str) -> str | None:
    """The module that ``old`` (a dotted module name) now is, or None when it did not move."""
    head, tail = old, ""
    while head:
        if head in MOVED:
            return MOVED[head] + tail
        head, _, last = head.rpartition(".")
        tail = "." + last + tail
    return None


class _Alias(importlib.abc.Loader):
    """Loads an old name as the new module itself (one object, two names)."""

    def __init__(self, old: str, new: str) -> None:
        self.old, self.new = old, new
        self._spec: importlib.machinery.ModuleSpec | None = None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        warnings.warn(f"the module {self.old} moved to {self.new}; the old name will be removed in the next "
                      f"release", DeprecationWarning, stacklevel=8)
        module = importlib.import_module(self.new)
        self._spec = module.__spec__
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        # the import system wrote the alias's spec onto the module: give it back its own
        module.__spec__ = self._spec


class _Finder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname: str, path: Sequence[str] | None = None,
                  target: types.ModuleType | None = None) -> importlib.machinery.ModuleSpec | None:
        if not fullname.startswith("mudforce."):
            return None
        new = new_name(fullname)
        if new is None:
            return None
        return importlib.util.spec_from_loader(fullname, _Alias(fullname, new))


_FINDER = _Finder()


def install() -> None:
    """Put the hook first on ``sys.meta_path`` (once): before the path finder, which would otherwise load an old
    package's submodule a second time from the moved package's folder."""
    if _FINDER not in sys.meta_path:
        sys.meta_path.insert(0, _FINDER)
