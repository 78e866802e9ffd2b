"""mudforce: the reduced-order mud resistive-force model of Chen, Yi & Shan (2024).

Simulate the vertical force that mud exerts on a robot's foot pushed in and
pulled out (arXiv:2403.02617): visco-elastic relaxation, a nonlinear spring,
velocity-squared drag, cohesive suction, and necking at the yield stress.

Quick start::

    import mudforce
    params = mudforce.MudParameters.from_water_content(0.25)
    time, depth = mudforce.Protocol.paper().sample()
    result = mudforce.simulate(time, depth, params)
    print(result.peak_force)

All quantities are SI: m, s, N, Pa, kg/m^3.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from mudforce.errors import InputError
    from mudforce.estimation.tracker import MudTracker, MudTrackers, TrackEstimate, TrackEstimates
    from mudforce.model.foot import Foot
    from mudforce.model.parameters import CITATION, PARAMETER_NAMES, TABLE_I, MudParameters
    from mudforce.model.velocity import VelocityFilter, estimate_depth_noise
    from mudforce.motions.protocol import Hold, Intrude, Protocol, Withdraw
    from mudforce.steppers.contact import ContactSample, ContactState, MudContact
    from mudforce.steppers.contact3d import MudContact3D, MudContacts3D, Wrench, simulate_3d
    from mudforce.steppers.many import MudContacts
    from mudforce.steppers.simulation import STATE_NAMES, SimulationResult, simulate

from mudforce._plumbing import moved as _moved

_moved.install()  # the old module paths of 0.1 (docs/api.md, "Moved in 0.2")

# Public names are imported on first use (PEP 562), so that `import mudforce`
# and the command line's error paths do not pay for compiling anything.
_LAZY = {
    "ContactSample": "mudforce.steppers.contact",
    "ContactState": "mudforce.steppers.contact",
    "MudContact": "mudforce.steppers.contact",
    "MudContact3D": "mudforce.steppers.contact3d",
    "MudContacts3D": "mudforce.steppers.contact3d",
    "Wrench": "mudforce.steppers.contact3d",
    "simulate_3d": "mudforce.steppers.contact3d",
    "InputError": "mudforce.errors",
    "Foot": "mudforce.model.foot",
    "CITATION": "mudforce.model.parameters",
    "PARAMETER_NAMES": "mudforce.model.parameters",
    "TABLE_I": "mudforce.model.parameters",
    "MudParameters": "mudforce.model.parameters",
    "Hold": "mudforce.motions.protocol",
    "Intrude": "mudforce.motions.protocol",
    "Protocol": "mudforce.motions.protocol",
    "Withdraw": "mudforce.motions.protocol",
    "STATE_NAMES": "mudforce.steppers.simulation",
    "SimulationResult": "mudforce.steppers.simulation",
    "simulate": "mudforce.steppers.simulation",
    "MudContacts": "mudforce.steppers.many",
    "MudTracker": "mudforce.estimation.tracker",
    "MudTrackers": "mudforce.estimation.tracker",
    "TrackEstimate": "mudforce.estimation.tracker",
    "TrackEstimates": "mudforce.estimation.tracker",
    "VelocityFilter": "mudforce.model.velocity",
    "estimate_depth_noise": "mudforce.model.velocity",
}


# deprecated names (docs/api.md, "Renamed in 0.2"): old -> new; each use warns, and is not cached
_RENAMED = {"CHEN2024": "CITATION"}


def __getattr__(name: str) -> Any:
    if name in _RENAMED:
        from mudforce._plumbing.deprecation import warn_renamed

        warn_renamed(f"mudforce.{name}", f"mudforce.{_RENAMED[name]}")
        name = _RENAMED[name]
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'mudforce' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


#: the 0.2 series in development (README: what moved and was renamed in 0.2); pyproject.toml says the same
__version__ = "0.2.0.dev0"

__all__ = [
    "CITATION",
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
]
