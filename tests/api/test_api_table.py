"""docs/api.md's table of the public API names what the code has: every name in it resolves in its module."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

API = Path(__file__).resolve().parents[2] / "docs" / "api.md"
OPTIONAL = {"mudforce.jax": ("jax",), "mudforce.jax.domain": ("jax",), "mudforce.engines.mjx": ("jax", "mujoco"),
            "mudforce.engines.mjx3d": ("jax", "mujoco"), "mudforce.jax.contact3d": ("jax",),
            "mudforce.engines.mujoco": ("mujoco",)}


def table_rows() -> list[tuple[list[str], str]]:
    """``(names, module)`` of each row of the table (first two columns), from the section "The table"."""
    text = API.read_text(encoding="utf-8")
    section = text.split("## The table", 1)[1].split("\n## ", 1)[0]
    rows = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 5 or not cells[1].startswith("`mudforce"):
            continue
        rows.append((re.findall(r"`([^`]+)`", cells[0]), cells[1].strip("`")))
    return rows


def test_the_table_has_the_top_level_api() -> None:
    import mudforce

    listed = {name for names, module in table_rows() if module == "mudforce" for name in names}
    assert set(mudforce.__all__) - {"__version__"} <= {n.split(".")[0] for n in listed}


@pytest.mark.parametrize(("names", "module"), table_rows())
def test_every_name_in_the_table_resolves(names: list[str], module: str) -> None:
    for package in OPTIONAL.get(module, ()):
        pytest.importorskip(package)
    mod = importlib.import_module(module)
    for name in names:
        obj: object = mod
        for part in name.split("."):
            obj = getattr(obj, part)
        if "." not in name:
            assert name in mod.__all__, f"{module}.{name} is in docs/api.md but not in its __all__"
