"""The kernel's layout API: contact states, rows and their named views, and numba's cache key."""

from __future__ import annotations

import numpy as np

import mudforce as mf
from mudforce import _kernel as K
from mudforce._kernel import layout, params_row
from mudforce._plumbing import cache as _cache


def test_contact_state_codes_are_pinned() -> None:
    """The codes are stored in state rows, snapshots and SimulationResult.state: they must never change."""
    assert [(s.name, int(s)) for s in K.ContactMode] == [("FREE", 0), ("CONTACT", 1), ("NECKED", 2)]
    assert (layout.FREE, layout.CONTACT, layout.NECKED) == (0, 1, 2)
    assert K.STATE_NAMES == ("FREE", "CONTACT", "NECKED") == mf.STATE_NAMES


def test_named_views_follow_the_columns() -> None:
    row = np.arange(K.N_STATE, dtype=np.float64)
    s = K.state_of(row)
    assert s == K.State(*range(layout.N_CORE)) and isinstance(s.mode, int)
    for name in K.State._fields:
        assert K.state_column(row, name) == getattr(s, name) == row[getattr(layout, "S_" + name.upper())]
    assert K.state_core(row).tolist() == list(range(layout.N_CORE))
    states = np.tile(row, (3, 1))
    K.forget_cache(states)
    assert (states[:, layout.S_CACHE_DT] == -1.0).all() and (states[:, : layout.N_CORE] == row[: layout.N_CORE]).all()
    out = np.arange(layout.N_OUT * 2, dtype=np.float64).reshape(layout.N_OUT, 2)
    o = K.outputs(out)
    for name in K.Outputs._fields:
        index = getattr(layout, "O_" + {"mud": "MUD", "state": "STATE"}.get(name, name.upper()))
        np.testing.assert_array_equal(getattr(o, name), out[index])
    assert K.outputs(out[:, 1]).f_s == out[layout.O_F_S, 1]


def test_params_row_as_values() -> None:
    prow = params_row(mf.MudParameters.from_water_content(0.25), mf.Foot.paper(), mf.VelocityFilter.exact())
    p = K.params_of(prow)
    assert p.k_i == prow[layout.P_K_I] and p.neck_flush == prow[layout.P_NECK_FLUSH]
    assert p.tau_w == p.b_w / p.k_w and p == K.load_params(prow[None, :], 0) == K.params_from_row(prow)
    states = K.new_states(2)
    states[1, : layout.N_CORE] = np.arange(layout.N_CORE)
    assert K.state_from_row(states[1]) == K.state_of(states[1]) == K.load_state(states, 1)
    states[:, layout.S_CACHE_DT] = 0.5
    K.forget_row_cache(states, 1)
    assert states[:, layout.S_CACHE_DT].tolist() == [0.5, -1.0]


def test_run_batch_from_a_later_sample_is_the_tail_of_a_whole_run() -> None:
    t = np.arange(400) / 1000.0
    z = 0.02 * np.sin(2 * np.pi * 2.0 * t)
    prow = params_row(mf.MudParameters.from_water_content(0.25), mf.Foot.paper(), mf.VelocityFilter.exact())[None]
    whole = K.new_out(t.size)
    K.run_batch(t, z, K.new_states(1), K.new_ring(1, 1), prow, whole)
    first = 150
    states = K.new_states(1)
    K.run_batch(t[:first], z[:first], states, K.new_ring(1, 1), prow, K.new_out(first))  # keeps its cache
    tail = K.new_out(t.size - first)
    assert K.run_batch(t, z, states, K.new_ring(1, 1), prow, tail, first) == -1
    np.testing.assert_array_equal(tail, whole[:, first:])


def test_numba_cache_is_keyed_on_the_shared_sources() -> None:
    """A compiled function's cache stamp carries the hash of the sources inlined into it (no files deleted)."""
    locator = K.loops.run_batch_compiled._cache._impl._locator
    assert type(locator).__name__.startswith("Mudforce")
    assert locator.get_source_stamp()[1] == _cache.source_fingerprint()
    assert all(any(_cache._PACKAGE.glob(pattern)) for pattern in _cache.SOURCES)  # none renamed away
    assert not hasattr(_cache, "refresh")


def test_every_name_a_compiled_function_takes_from_another_file_is_keyed() -> None:
    """numba freezes another module's constants and inlines its callees into a compiled function's cached code, and
    keys that code on the function's own file: every mudforce name that a compiled function (decorated ``njit``,
    ``_compiled`` or ``overload``) reads from another file must come from one of :data:`_cache.SOURCES`, or an edit
    of that file alone leaves the cached code silently the old one (the tracker's layout was not, until
    2026-12-01). The decorators themselves and the error classes (raised by name) are exempt."""
    import ast
    from pathlib import Path

    package = _cache._PACKAGE
    keyed = {p.resolve() for pattern in _cache.SOURCES for p in package.glob(pattern)}
    exempt = {(package / "_plumbing" / "jit.py").resolve(), (package / "errors.py").resolve()}
    decorators = {"njit", "_compiled", "overload"}

    def decorator_name(node: ast.expr) -> str:
        while isinstance(node, ast.Call):
            node = node.func
        return node.attr if isinstance(node, ast.Attribute) else node.id if isinstance(node, ast.Name) else ""

    def source(module: str) -> Path | None:
        path = package.joinpath(*module.split(".")[1:])
        for candidate in (path.with_suffix(".py"), path / "__init__.py"):
            if candidate.exists():
                return candidate.resolve()
        return None

    unkeyed = []
    for path in sorted(package.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        imported: dict[str, Path | None] = {}
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "mudforce":
                for alias in node.names:
                    imported[alias.asname or alias.name] = (source(f"{node.module}.{alias.name}")
                                                            or source(node.module))
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.split(".")[0] == "mudforce":
                        imported[alias.asname or alias.name.split(".")[0]] = source(alias.name)
        for node in ast.walk(tree):
            if not (isinstance(node, ast.FunctionDef) and any(decorator_name(d) in decorators
                                                              for d in node.decorator_list)):
                continue
            body = [n for statement in node.body for n in ast.walk(statement)]
            for name in sorted({n.id for n in body if isinstance(n, ast.Name)} & imported.keys()):
                target = imported[name]
                if target is not None and target != path.resolve() and target not in keyed | exempt:
                    unkeyed.append(f"{path.relative_to(package)}:{node.name} reads {name} from "
                                   f"{target.relative_to(package)}")
    assert not unkeyed, unkeyed
