"""The naive explicit coupling of a foot with the mud, for comparison with the engine (:func:`naive_drop`).

A simulator that takes the branch from the sign of the last velocity and
applies the force explicitly puts the full intrusion force on a foot that
has just stopped, throws it up onto the withdrawal branch, then drops it
back: it chatters every step and, as the intrusion branch carries the
weight only on the way down, ratchets the foot deeper. The built-in engine
(:mod:`mudforce.engines.dynamics.engine`) and the MuJoCo adapter avoid both with the
rest band (:mod:`mudforce.engines.dynamics.rest_band`).
"""

from __future__ import annotations

import os
from typing import Any, NamedTuple

import numpy as np

from mudforce import _kernel as K
from mudforce._kernel import params_row
from mudforce.engines._checks import check_finite_output, check_foot, check_params
from mudforce.engines.dynamics.result import GRAVITY
from mudforce.errors import finite_number
from mudforce.model.bounds import bounded_depth, check_gravity, check_step, max_samples
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.velocity import VelocityFilter

__all__ = ["NaiveDrop", "naive_drop"]


def _naive(buf: np.ndarray, m: float, g: float, z0: float, dt: float, n: int, depth: np.ndarray,
           force: np.ndarray) -> None:
    """Semi-implicit Euler with the force of the last sample's branch, one :func:`~mudforce._kernel.stream_step`
    a step: the streaming path's own compiled step (a Python loop: the comparison is not worth compiling the
    whole state machine once more, ~15 s on a cold start; 5 s of a drop at 1 ms run in a few ms)."""
    step = K.stream_step
    z = z0
    v = 0.0
    f = step(buf, z, dt)
    for k in range(n):
        v += dt * (g - f / m)
        z += dt * v
        f = step(buf, z, dt)
        depth[k] = z
        force[k] = f


class NaiveDrop(NamedTuple):
    """What :func:`naive_drop` returns; unpacks as ``time, depth, force``.

    Attributes
    ----------
    time : ndarray
        Sample times [s] (``dt, 2 dt, ...``).
    depth : ndarray
        Foot depth ``z_i`` [m], positive down.
    force : ndarray
        Mud force on the foot [N], positive up.
    """

    time: np.ndarray
    depth: np.ndarray
    force: np.ndarray

    def columns(self) -> dict[str, np.ndarray]:
        """The per-sample data under unit-suffixed names: ``time_s, depth_m, force_N``."""
        return {"time_s": self.time, "depth_m": self.depth, "force_N": self.force}

    def to_pandas(self) -> Any:
        """A :class:`pandas.DataFrame` with the columns of :meth:`to_csv` (needs pandas)."""
        from mudforce.io.results import to_pandas

        return to_pandas(self.columns())

    def to_csv(self, path: str | os.PathLike[str]) -> None:
        """Write ``time_s, depth_m, force_N`` as CSV, atomically (the number format of :class:`FootResult`)."""
        from mudforce.io.results import write_text

        lines = ["time_s,depth_m,force_N"]
        for t, z, f in zip(self.time.tolist(), self.depth.tolist(), self.force.tolist(), strict=True):
            lines.append(f"{t:.9g},{z + 0.0:.12g},{f:.12g}")
        write_text(path, "\n".join(lines) + "\n")


def naive_drop(mass: float, params: MudParameters, foot: Foot | None = None, *, duration: float = 8.0,
               dt: float = 1e-3, height: float = 0.0, gravity: float = GRAVITY) -> NaiveDrop:
    """The naive explicit coupling this module warns about: a :class:`NaiveDrop` ``(time [s], depth [m], force [N])``.

    Each step integrates ``m dv/dt = m g - F`` with the force the streaming
    model returned for the previous sample; the branch follows the sign of
    the last step's velocity. For comparison only: it chatters and ratchets.

    Parameters
    ----------
    mass : float
        Foot mass [kg], > 0.
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry; the paper's cuboid by default.
    duration : float
        Simulated time [s], at least ``dt`` (at most 1e8 steps).
    dt : float
        Time step [s], > 0.
    height : float
        Release height of the foot's bottom above the mud surface [m], positive up (negative: inside fresh mud).
    gravity : float
        Gravitational acceleration [m/s^2], positive down, within [0, 1e4] (as :func:`simulate_foot`).

    Raises
    ------
    InputError
        For inputs of the wrong type or out of bounds, and if the result is
        not finite (a foot too light for the step diverges).
    """
    params = check_params(params)
    foot = check_foot(foot)
    mass = finite_number(mass, "mass", "kg", positive=True)
    duration = finite_number(duration, "duration", "s", positive=True)
    dt = finite_number(dt, "dt", "s", positive=True)
    # the stepper's bounds, as simulate_foot refuses them: beyond, its refusal came back as "the naive engine's
    # solution is not finite ... use a heavier foot or a shorter step"
    z0 = 0.0 - bounded_depth(height, "height", of=" of the mud surface")  # (0.0 - 0.0 is +0.0)
    gravity = check_gravity(gravity)
    check_step(dt)
    max_samples(duration, dt)
    buf = K.new_stream_buffer(params_row(params, foot, VelocityFilter.exact()))
    n = round(duration / dt)  # at least 1: max_samples refuses a duration under one step
    depth = np.empty(n)
    force = np.empty(n)
    _naive(buf, mass, gravity, z0, dt, n, depth, force)
    time = np.arange(1, n + 1) * dt
    check_finite_output("naive", time, depth, force)
    return NaiveDrop(time, depth, force)
