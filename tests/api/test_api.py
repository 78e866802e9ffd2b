"""The top-level API resolves, lazily, and its entry point refuses unknown keywords.

Every public module's ``__all__`` (``mudforce``'s included) is pinned once, in ``test_public_all.py``.
"""

from __future__ import annotations

import inspect

import pytest

import mudforce


def test_every_public_name_resolves() -> None:
    for name in mudforce.__all__:
        assert getattr(mudforce, name) is not None
    with pytest.raises(AttributeError):
        mudforce.does_not_exist  # noqa: B018


def test_simulate_signature_refuses_unknown_keywords() -> None:
    sig = inspect.signature(mudforce.simulate)
    assert list(sig.parameters)[:4] == ["time", "depth", "params", "foot"]
    with pytest.raises(TypeError):
        mudforce.simulate([0.0], [0.0], mudforce.TABLE_I[0.25], velocity_filer="exact")  # type: ignore[call-arg]
