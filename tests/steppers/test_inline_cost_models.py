"""The kernel's numba inlining cost models (speed plumbing, docs/speed.md "Issue 19 point 4") still select their sites.

They decide from source lines and the name of the function being compiled; a refactoring that moved
``sign``'s call out of ``quiet_step`` or renamed ``run_batch_compiled`` would silently lose the speed.
No compile: the models are asked as numba asks them, with stand-ins for its IR.
"""

from __future__ import annotations

import inspect
from types import SimpleNamespace

from mudforce._kernel import loops, transitions


def _site(function: object, text: str) -> SimpleNamespace:
    """A stand-in for numba's call expression at the line of ``function``'s source that contains ``text``."""
    py = function.py_func  # type: ignore[attr-defined]
    lines, first = inspect.getsourcelines(py)
    (offset,) = [i for i, line in enumerate(lines) if text in line]
    return SimpleNamespace(loc=SimpleNamespace(filename=py.__code__.co_filename, line=first + offset))


def _ir(name: str) -> SimpleNamespace:
    return SimpleNamespace(func_id=SimpleNamespace(func_name=name))


def test_sign_is_inlined_into_quiet_step_only() -> None:
    model = transitions._in_quiet_step
    assert model(_site(transitions.quiet_step, "d = sign(v)"), _ir("run_batch_compact"), None)
    assert not model(_site(transitions._direction, "return sign(velocity)"), _ir("run_batch_compact"), None)


def test_the_transitions_are_inlined_into_the_full_output_loop_only() -> None:
    model = transitions._in_full_output_loop
    site = _site(transitions.free_step, "return _moved(")
    assert model(site, _ir(loops.run_batch_compiled.py_func.__name__), None)
    for other in ("run_batch_compact", "run_feet", "stream_step", "step_feet"):
        assert not model(site, _ir(other), None)
