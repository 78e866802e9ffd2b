"""The layout by concept holds: packages import only downward, never sideways into a front end, and never a
private module or name of another package.

The packages of ``src/mudforce``, from the bottom up (a package may import from a lower rank only):

====  ==========================================  ======================================================
rank  package                                     what it is
====  ==========================================  ======================================================
0     ``errors``                                  the one-line input error and its checks
1     ``_plumbing``                               shared plumbing, no physics
2     ``io``                                      files, tables, units, figures as files
3     ``model``                                   the physics layer: every equation and rule, once
4     ``_kernel``                                 the compiled control flow (speed plumbing)
5     ``steppers``, ``jax``, ``references``       the model stepped: CPU, JAX, independent solvers
6     ``engines``                                 the built-in engine, MuJoCo, MJX
7     ``motions``                                 motions and recordings that drive the model
8     ``estimation``                              calibration and tracking
9     ``cli``, ``reproduce``                      the front ends
10    ``mudforce`` (``__init__``, ``__main__``)   the package's own names
====  ==========================================  ======================================================

Imports under ``if TYPE_CHECKING:`` are annotations, not dependencies, and are not counted. The batch front
end :mod:`mudforce.steppers.simulation` is imported by nothing at its own rank or below. Private modules
(a dotted part starting with ``_``) and private names are used only inside the package that holds them;
``_kernel`` and ``_plumbing`` are the shared layers and say so.
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"
RANK = {
    "errors": 0, "_plumbing": 1, "io": 2, "model": 3, "_kernel": 4, "steppers": 5, "jax": 5, "references": 5,
    "engines": 6, "motions": 7, "estimation": 8, "cli": 9, "reproduce": 9, "": 10, "__main__": 10,
}
SHARED = {"_kernel", "_plumbing"}
FRONT_ENDS = {"mudforce.steppers.simulation": 7}  # the lowest rank that may import it
ALLOWED_SIDEWAYS = {("cli", "reproduce")}  # `mudforce reproduce` is a command


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {_module_name(p): p for p in sorted((SRC / "mudforce").rglob("*.py"))}


def _top(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def _type_checking_lines(tree: ast.Module) -> set[int]:
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for child in node.body:
                lines.update(range(child.lineno, (child.end_lineno or child.lineno) + 1))
    return lines


def _imports(module: str) -> list[tuple[str, str, int]]:
    """``(target module, imported name or "", line)`` for every runtime import of ``mudforce`` code."""
    tree = ast.parse(MODULES[module].read_text(encoding="utf-8"))
    skip = _type_checking_lines(tree)
    found: list[tuple[str, str, int]] = []
    for node in ast.walk(tree):
        if getattr(node, "lineno", None) in skip:
            continue
        if isinstance(node, ast.Import):
            found += [(a.name, "", node.lineno) for a in node.names if a.name.split(".")[0] == "mudforce"]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module \
                and node.module.split(".")[0] == "mudforce":
            for a in node.names:
                sub = f"{node.module}.{a.name}"
                found.append((sub, "", node.lineno) if sub in MODULES else (node.module, a.name, node.lineno))
    return found


def _violations() -> list[str]:
    bad: list[str] = []
    for module in MODULES:
        own = _top(module)
        for target, name, line in _imports(module):
            if target == "mudforce" and name == "__version__":
                continue  # the package's version, read by the front ends
            where = f"{module}:{line} imports {target}{'.' + name if name else ''}"
            top = _top(target)
            if top == own:
                pass
            elif RANK[top] > RANK[own] or (RANK[top] == RANK[own] and (own, top) not in ALLOWED_SIDEWAYS):
                bad.append(f"{where}: upward or sideways ({own} rank {RANK[own]}, {top} rank {RANK[top]})")
            if target in FRONT_ENDS and RANK[own] < FRONT_ENDS[target]:
                bad.append(f"{where}: into a front end")
            parts = target.split(".")
            for k, part in enumerate(parts[1:], start=1):
                holder = ".".join(parts[:k])  # the package that holds the private part
                if part.startswith("_") and not (k == 1 and part in SHARED) \
                        and not (module == holder or module.startswith(holder + ".")):
                    bad.append(f"{where}: a private module of another package")
            if name.startswith("_") and own != top and top not in SHARED:
                bad.append(f"{where}: a private name of another package")
    return bad


def test_every_package_has_a_rank() -> None:
    assert {_top(m) for m in MODULES} <= set(RANK)


def test_imports_go_down_only_and_private_stays_home() -> None:
    assert _violations() == []


def test_the_rules_catch_what_they_forbid() -> None:
    """The checker itself: each kind of violation, planted, is reported."""
    global MODULES
    saved = MODULES
    planted = SRC / "mudforce" / "model" / "_planted_for_test.py"
    try:
        MODULES = {**saved, "mudforce.model._planted_for_test": planted}
        planted.write_text("from mudforce.steppers.simulation import simulate\n"
                           "from mudforce.engines._checks import check_mass\n"
                           "from mudforce.io.tables import _private\n", encoding="utf-8")
        found = "\n".join(v for v in _violations() if "_planted_for_test" in v)
    finally:
        planted.unlink()
        MODULES = saved
    for kind in ("upward or sideways", "into a front end", "a private module of another package",
                 "a private name of another package"):
        assert kind in found


def test_tests_mirror_the_source() -> None:
    """Each test folder is named after a package of src/mudforce (api: the package's own names)."""
    tests = Path(__file__).resolve().parents[1]
    folders = {p.name for p in tests.iterdir() if p.is_dir() and not p.name.startswith((".", "__"))}
    packages = {p.name.lstrip("_") for p in (SRC / "mudforce").iterdir() if p.is_dir() and not p.name.startswith("__")}
    assert folders - {"api"} <= packages


def test_command_line_tests_are_in_one_place() -> None:
    """Every test that runs the command line is in tests/cli/ (tests/reproduce/: the ``reproduce`` command):
    no other test file imports the subprocess harness."""
    tests = Path(__file__).resolve().parents[1]
    homes = {tests / "cli", tests / "reproduce"}
    elsewhere = []
    for path in sorted(tests.rglob("test*.py")):
        if path.parent in homes:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            if any(n.split(".")[0] == "mudforce_cli_harness" for n in names):
                elsewhere.append(str(path.relative_to(tests)))
    assert elsewhere == []
