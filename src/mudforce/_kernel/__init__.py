"""The one compiled stepper that every path (batch, streaming, many feet, the engines) runs.

Where to look
-------------
* The physics is :mod:`mudforce.model.equations`: every formula (the Maxwell
  step, the branch stresses, the neck, Eq. (7)'s filter), each naming the
  paper's equation. Change the model there.
* :mod:`~mudforce._kernel.transitions` is the contact state machine of
  docs/model.md (FREE / CONTACT / NECKED): :func:`advance`, a short
  dispatcher over named transitions (``touchdown``, ``intrusion_step``,
  ``withdrawal_step`` with ``neck``, ``necked_step``, ``leave_necked``),
  and the force of a sample (``stress_parts``, ``sample_outputs``).
* :mod:`~mudforce._kernel.layout` is where a foot's state lives (a row of
  a float64 array, read into a :class:`State` value) and why; callers
  outside the kernel read and write rows through its functions
  (``state_of``, ``state_column``, ``forget_cache``, ``outputs``,
  ``make_params``), not through column indices.
* :mod:`~mudforce._kernel.loops` is speed plumbing only: the loops over
  samples and feet (``step``, ``run_batch``, ``run_batch_compact``,
  ``run_feet``), none of which computes physics of its own.
* :mod:`~mudforce._kernel.step3d` is the speed plumbing of
  :class:`mudforce.steppers.contact3d.MudContacts3D`, which runs ``run_feet`` on
  every element and the 3-D law on top: :mod:`mudforce.model.law3d`'s own
  functions, which numba compiles in (law3d registers them with it).

Rule for new code: the nonlinear spring, Eq. (4), is evaluated only through
:func:`mudforce.model.equations.nonlinear_spring_stress` (its power is
:func:`mudforce._plumbing.pow.power`), so that every path, vectorised or not, gives
the same bits. The force is summed only by
:func:`mudforce.model.equations.total_stress`.

The names below are what the rest of mudforce takes from the kernel
(``from mudforce import _kernel as K; K.step(...)``): the loops, the
layout's values and functions, and the sizes of its rows (``N_STATE``,
``N_PARAMS``, ``N_RING``, ``MAX_WINDOW``) for callers that check or
split them. Not the column indices (``S_*``, ``P_*``, ``R_*``, ``O_*``)
or the contact states as ints: those are the kernel's own, in
:mod:`~mudforce._kernel.layout`. The transitions are in
:mod:`~mudforce._kernel.transitions`.
"""

from __future__ import annotations

import numpy as np

from mudforce._kernel.layout import (
    MAX_WINDOW,
    N_PARAMS,
    N_RING,
    N_STATE,
    STATE_NAMES,
    Cache,
    ContactMode,
    Outputs,
    Params,
    State,
    _compiled,
    forget_cache,
    forget_row_cache,
    invalid_rows,
    load_cache,
    load_params,
    load_state,
    make_params,
    neck_flush_age,
    new_out,
    new_ring,
    new_states,
    outputs,
    params_from_row,
    params_of,
    state_column,
    state_core,
    state_from_row,
    state_of,
)
from mudforce._kernel.loops import (
    new_feet_scratch,
    new_spring_scratch,
    new_stream_buffer,
    run_batch,
    run_batch_compact,
    run_feet,
    run_feet_threads,
    step,
    stream_parts,
    stream_step,
)
from mudforce.errors import InputError
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.velocity import VelocityFilter

__all__ = [  # what the rest of mudforce uses (this package is private: not the public API)
    "MAX_WINDOW",
    "N_PARAMS",
    "N_RING",
    "N_STATE",
    "STATE_NAMES",
    "Cache",
    "ContactMode",
    "Outputs",
    "Params",
    "State",
    "_compiled",
    "forget_cache",
    "forget_row_cache",
    "invalid_rows",
    "load_cache",
    "load_params",
    "load_state",
    "make_params",
    "neck_flush_age",
    "new_feet_scratch",
    "new_out",
    "new_ring",
    "new_spring_scratch",
    "new_states",
    "new_stream_buffer",
    "outputs",
    "params_from_row",
    "params_of",
    "run_batch",
    "run_batch_compact",
    "run_feet",
    "run_feet_threads",
    "state_column",
    "state_core",
    "state_from_row",
    "state_of",
    "step",
    "stream_parts",
    "stream_step",
]


def params_row(params: MudParameters, foot: Foot, velocity_filter: VelocityFilter) -> np.ndarray:
    """The compiled stepper's constants for one foot."""
    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    if not isinstance(foot, Foot):
        raise InputError(f"foot must be a Foot, got {type(foot).__name__}")
    return make_params(params.as_array(), foot.area, foot.width, velocity_filter.window, velocity_filter.deadband)
