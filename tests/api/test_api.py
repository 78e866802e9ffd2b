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


def test_the_version_is_the_package_s_and_the_0_2_series() -> None:
    """``mudforce.__version__`` is pyproject.toml's (one number, two places) and of the 0.2 series, in which the
    docs say the modules moved and the names changed (README, docs/api.md)."""
    import re
    from pathlib import Path

    pyproject = Path(__file__).resolve().parents[2] / "pyproject.toml"
    if not pyproject.is_file():
        pytest.skip("not a source checkout")
    declared = re.search(r'^version = "([^"]+)"$', pyproject.read_text(), re.MULTILINE)
    assert declared is not None and declared.group(1) == mudforce.__version__
    assert mudforce.__version__.startswith("0.2.")
