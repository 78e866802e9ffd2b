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

from mudforce.contact import ContactSample, ContactState, MudContact
from mudforce.errors import InputError
from mudforce.foot import Foot
from mudforce.parameters import CHEN2024, PARAMETER_NAMES, TABLE_I, MudParameters
from mudforce.protocol import Hold, Intrude, Protocol, Withdraw
from mudforce.simulation import STATE_NAMES, SimulationResult, simulate
from mudforce.velocity import VelocityFilter, estimate_depth_noise

__version__ = "0.1.0"

__all__ = [
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
    "MudParameters",
    "Protocol",
    "SimulationResult",
    "VelocityFilter",
    "Withdraw",
    "__version__",
    "estimate_depth_noise",
    "simulate",
]
