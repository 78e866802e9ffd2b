"""The inputs the model accepts: bounds on depth, time step, time and horizontal position.

Written once here, in the physics layer, so that every path refuses the same inputs: the compiled loops (which
take these constants into their machine code through :mod:`mudforce._kernel.bounds`), the Python checks in front
of them, and the baselines (:mod:`mudforce.model.baselines`). :mod:`mudforce.steppers.simulation` re-exports them
as the public :data:`~mudforce.steppers.simulation.MAX_DEPTH`, :data:`~mudforce.steppers.simulation.MIN_DT`,
:data:`~mudforce.steppers.simulation.MAX_DT` and :data:`~mudforce.steppers.simulation.MAX_TIME`. Inside these
bounds every output is finite (``tests/api/test_promise.py``). :func:`check_times` words the refusal of sample
times, for ``simulate``, ``simulate_3d``, ``fit_3d`` and the baselines alike, :func:`check_depths` that of a
trajectory's depths, for ``simulate`` and the baselines; :func:`bounded_depth` that of one
depth or height (a protocol's depths, a drop's height, a surface height), for every path that takes one;
:func:`check_finite` that of a recording's column that is not finite (in their words), for those and the tracker;
:func:`check_gravity` that of a drop's gravity, for the engines' drops and the exact one.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mudforce.errors import InputError, finite_number, shown

__all__ = ["MAX_DEPTH", "MAX_DT", "MAX_GRAVITY", "MAX_HORIZONTAL", "MAX_OUTPUT_SAMPLES", "MAX_TIME", "MIN_DT",
           "bounded_depth", "check_depths", "check_finite", "check_gravity", "check_step", "check_times",
           "max_samples"]

#: Largest foot depth (or height above the surface) accepted [m]: |z| <= 100 m. A mud model
#: for a foot means nothing beyond it, and it keeps ``(z/H)^beta``, ``k z`` and ``dz/dt`` finite.
MAX_DEPTH = 100.0
#: Largest horizontal distance of a 3-D foot's body origin from the world origin, on each of x and y [m]:
#: 10 km, as the readers' bound on a position column (``mudforce.io.tables.COLUMN_LIMITS``). It keeps the
#: horizontal velocities, the drag's ``v^2`` and the moments finite (a foot at x = 1e155 m gave an infinite
#: force, whose NaN moment then reached the next step); float64 resolves 2e-12 m there.
MAX_HORIZONTAL = 1e4
#: Shortest time step accepted [s]: 1 ns. Shorter steps sample nothing a sensor or a control
#: loop can, approach the rounding of sample times (one ulp of 1e6 s is 1.2e-10 s), and, far
#: enough down, let ``dz/dt`` and the drag ``v^2`` of Eq. (5) overflow (1e-320 s: infinite).
MIN_DT = 1e-9
#: Longest time step accepted [s]: 1000 s.
MAX_DT = 1e3
#: Largest |time| accepted [s] (~30 years; one ulp of 1e9 s is 1.2e-7 s, so short steps that
#: late are refused as repeated times or as shorter than MIN_DT rather than rounded silently).
MAX_TIME = 1e9
#: Most output samples one simulated drop may produce (``duration / dt + 1``): 8 bytes x 6 arrays x 1e8 = 4.8 GB.
MAX_OUTPUT_SAMPLES = 100_000_000


#: Strongest gravity a drop takes [m/s^2]: 1e4, about 1000 g, beyond the geotechnical centrifuges that test soils and
#: muds (a few hundred g); the weight of a 1000 kg foot there is a recording's force bound, 1e7 N
#: (``mudforce.io.tables.COLUMN_LIMITS``). Beyond, the foot leaves the model's depth bound at once, or the solution
#: overflowed (1e200 m/s^2 was refused as a step too long for the foot: "use a heavier foot").
MAX_GRAVITY = 1e4


def check_gravity(gravity: Any, *, positive: bool = False) -> float:
    """A drop's ``gravity`` [m/s^2] as a float within [0, :data:`MAX_GRAVITY`] (``positive``: above 0), else
    InputError: the one check of every drop's gravity (the engines' and the exact drop's).

    Positive pulls the foot down, into the mud (every drop's depth is positive down). A negative one is refused:
    it is MuJoCo's sign (``gravity="0 0 -9.81"``) given by habit, which threw a 5 kg foot 1.23 m up instead of
    dropping it; an upward load is a negative ``applied_force`` (:func:`mudforce.engines.dynamics.simulate_foot`).
    Zero is taken: a foot moved by its applied force alone.
    """
    g = finite_number(gravity, "gravity", "m/s^2")
    if positive and g == 0.0:
        raise InputError("gravity must be > 0 [m/s^2] for the exact drop, got 0")
    if not 0.0 <= g <= MAX_GRAVITY:
        raise InputError(f"gravity must be within [0, {MAX_GRAVITY:g}] m/s^2 (positive pulls the foot down, into "
                         f"the mud), got {shown(gravity)}")
    return g


def max_samples(duration: float, dt: float) -> int:
    """Number of output samples ``floor(duration / dt) + 1`` of a drop of ``duration`` [s] in steps ``dt`` [s] (both
    checked finite and > 0 by the caller), at least 2 (a duration of at least one step) and at most
    :data:`MAX_OUTPUT_SAMPLES`, else InputError (a duration under ``dt`` returned the start alone): the words every
    drop, built-in, MuJoCo, MJX and exact, refuses its duration in."""
    ratio = duration / dt
    if not ratio >= 1.0 - 1e-9:
        raise InputError(f"duration {duration:g} s is shorter than one step (dt = {dt:g} s): the result would hold "
                         "the start alone; expected a duration of at least dt")
    if not ratio < MAX_OUTPUT_SAMPLES:
        raise InputError(f"duration / dt = {ratio:.3g} samples is too many (at most {MAX_OUTPUT_SAMPLES:.0e}); "
                         "use a shorter duration or a longer dt")
    return math.floor(ratio + 1e-9) + 1


def check_finite(values: np.ndarray, name: str, unit: str) -> None:
    """Refuse a recording's column ``values`` (float64, 1-D) that is not finite: one line naming the first bad
    sample, ``name`` and its ``unit``, the words of :func:`check_times` and :func:`check_depths`."""
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise InputError(f"{name} is not finite at sample {bad[0]} ({float(values[bad[0]])!r}); "
                         f"expected numbers [{unit}]")


def check_step(dt: float) -> None:
    """Refuse a step ``dt`` [s] (a float) outside [:data:`MIN_DT`, :data:`MAX_DT`] (NaN too): one line, the words
    every stepper and engine refuses a step in."""
    if not MIN_DT <= dt <= MAX_DT:
        raise InputError(f"dt must be within [{MIN_DT:g}, {MAX_DT:g}] s, got {dt!r}")


def check_times(t: np.ndarray, max_dt: float = MAX_DT) -> None:
    """Refuse sample times [s] (float64, 1-D) that are not finite, beyond +-:data:`MAX_TIME` (where a step of 1 ms
    would lose its digits), or not stepping by [:data:`MIN_DT`, ``max_dt``]: one line naming the first bad
    sample, for :func:`mudforce.simulate` and :func:`mudforce.simulate_3d` alike (and :func:`mudforce.track`, whose
    tracker takes gaps of up to :data:`MAX_TIME`, as ``MudTracker.update`` does: ``max_dt=MAX_TIME``)."""
    check_finite(t, "time", "s")
    bad = np.flatnonzero(np.abs(t) > MAX_TIME)
    if bad.size:
        raise InputError(f"time at sample {bad[0]} ({float(t[bad[0]])!r} s) is beyond +-{MAX_TIME:g} s")
    steps = np.diff(t)
    bad = np.flatnonzero(~((steps >= MIN_DT) & (steps <= max_dt)))
    if not bad.size:
        return
    i = int(bad[0]) + 1
    if steps[i - 1] <= 0.0:
        what = "repeats" if steps[i - 1] == 0.0 else "goes backwards"
        raise InputError(f"time {what} at sample {i} ({float(t[i - 1])!r} s then {float(t[i])!r} s); "
                         "expected strictly increasing time")
    # repr: a step just outside a bound must not print as the bound
    # the sample by its 0-based index and its time, which says where it is in any indexing
    raise InputError(f"the time step before sample {i} (t = {float(t[i])!r} s) is {float(steps[i - 1])!r} s; "
                     f"expected steps within [{MIN_DT:g}, {max_dt:g}] s")


def check_depths(z: np.ndarray) -> None:
    """Refuse a trajectory's depths [m] (float64, 1-D) that are not finite or beyond +-:data:`MAX_DEPTH`: one line
    naming the first bad sample, for :func:`mudforce.simulate` and the baselines alike."""
    check_finite(z, "depth", "m")
    bad = np.flatnonzero(np.abs(z) > MAX_DEPTH)
    if bad.size:
        raise InputError(f"depth at sample {bad[0]} ({float(z[bad[0]])!r} m) is beyond +-{MAX_DEPTH:g} m; "
                         "expected depths [m] within that")


def bounded_depth(value: Any, name: str, *, of: str = "") -> float:
    """``value`` [m] as a float if it is a finite real number within +-:data:`MAX_DEPTH` (what every stepper
    accepts as a depth), else one line naming ``name``: for a depth, a height above the surface and a surface
    height alike (``of``, e.g. ``" of the mud surface"``, says what the bound is taken from).

    Parameters
    ----------
    value : Any
        The depth or height [m].
    name : str
        What it is, for the message (``"surface_height"``).
    of : str
        Words after the bound in the message.
    """
    number = finite_number(value, name, "m")
    if not abs(number) <= MAX_DEPTH:
        raise InputError(f"{name} must be within +-{MAX_DEPTH:g} m{of}, got {shown(value)}")
    return number
