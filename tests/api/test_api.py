"""The public API is pinned: a change to it must be deliberate (edit this list with it)."""

from __future__ import annotations

import importlib
import inspect

import pytest

import mudforce

PUBLIC = {
    "CHEN2024",
    "PARAMETER_NAMES",
    "STATE_NAMES",
    "TABLE_I",
    "ContactSample",
    "ContactState",
    "Foot",
    "Hold",
    "InputError",
    "Intrude",
    "MudContact",
    "MudContact3D",
    "MudContacts",
    "MudContacts3D",
    "MudParameters",
    "MudTracker",
    "MudTrackers",
    "Protocol",
    "SimulationResult",
    "TrackEstimate",
    "TrackEstimates",
    "VelocityFilter",
    "Withdraw",
    "Wrench",
    "__version__",
    "estimate_depth_noise",
    "simulate",
    "simulate_3d",
}


def test_all_is_pinned() -> None:
    assert set(mudforce.__all__) == PUBLIC


def test_every_public_name_resolves() -> None:
    for name in mudforce.__all__:
        assert getattr(mudforce, name) is not None
    with pytest.raises(AttributeError):
        mudforce.does_not_exist  # noqa: B018


@pytest.mark.parametrize(
    "module",
    ["parameters", "foot", "protocol", "simulation", "contact", "velocity", "equations", "units", "tables", "io",
     "plotting", "reproduce", "reproduce.experiments", "reproduce.jobs", "reproduce.summary", "reproduce.figures",
     "reproduce.html", "reproduce.output", "reproduce.report"],
)
def test_modules_declare_all(module: str) -> None:
    mod = importlib.import_module(f"mudforce.{module}")
    assert isinstance(mod.__all__, list)
    for name in mod.__all__:
        assert hasattr(mod, name), f"{module}.{name}"


def test_simulate_signature_refuses_unknown_keywords() -> None:
    sig = inspect.signature(mudforce.simulate)
    assert list(sig.parameters)[:4] == ["time", "depth", "params", "foot"]
    with pytest.raises(TypeError):
        mudforce.simulate([0.0], [0.0], mudforce.TABLE_I[0.25], velocity_filer="exact")  # type: ignore[call-arg]
