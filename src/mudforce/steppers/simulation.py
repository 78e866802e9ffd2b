"""Batch simulation of a prescribed foot trajectory, and its result."""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mudforce import _kernel as K
from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MAX_TIME, MIN_DT, check_times, out_of_bounds
from mudforce._plumbing.jit import njit
from mudforce.errors import InputError, real_array
from mudforce.model.bounds import check_depths
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.velocity import (
    DepthNoise,
    VelocityFilter,
    choose_velocity_filter,
    resolve_velocity_filter,
)

if TYPE_CHECKING:
    import pandas

__all__ = ["MAX_DEPTH", "MAX_DT", "MAX_TIME", "MIN_DT", "STATE_NAMES", "SimulationResult", "simulate"]

# MAX_DEPTH [m], MIN_DT and MAX_DT [s] and MAX_TIME [s], the bounds on the inputs, are public here and
# defined (and documented) in mudforce._kernel.bounds, because the compiled stepper takes them in too

#: Contact state codes in :attr:`SimulationResult.state`: 0 FREE, 1 CONTACT, 2 NECKED.
STATE_NAMES: tuple[str, ...] = K.STATE_NAMES

#: samples on the nonlinear spring collected before their forces are computed in one vectorised pass
SPRING_BLOCK = 512

_CSV_COLUMNS = (
    ("time_s", "time"),
    ("depth_m", "depth"),
    ("velocity_m_s", "velocity"),
    ("mud_displacement_m", "mud_displacement"),
    ("mud_velocity_m_s", "mud_velocity"),
    ("f_e1_Pa", "f_e1"),
    ("f_e2_Pa", "f_e2"),
    ("f_s_Pa", "f_s"),
    ("force_N", "force"),
)


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """The model's response to a sampled trajectory; all arrays have one entry per sample.

    The batch loop writes the force, the contact state and the mud
    displacement; the other arrays (stress components, velocities) are
    computed on first access, all together, by running the trajectory
    again through the stepper's full-output loop, so they are the
    stepper's values bit for bit and cost nothing until asked for (three to
    four times the batch's own time when they are). Those computed on
    access (``velocity``, ``mud_velocity``, ``f_e1``, ``f_e2``, ``f_s``) are
    read-only, cached once for all. ``time`` and ``depth`` are the result's
    own read-only arrays (copies of the caller's when they were the
    caller's), so the outputs computed on access always belong to them. The
    arrays the batch loop wrote (``force``, ``state``, ``mud_displacement``,
    ``necking_times``) are the caller's own, writable (a library that
    refuses a read-only buffer takes them as they are); writing into them
    changes no other output.

    Attributes
    ----------
    time : ndarray
        Sample times [s].
    depth : ndarray
        Foot depth ``z_i`` below the surface [m], positive down.
    velocity : ndarray
        Foot velocity estimate used for the branch choice [m/s] (the raw
        backward difference for the exact filter; 0 at the first sample).
    mud_displacement : ndarray
        Mud displacement ``z_m`` of the Maxwell element [m], Eq. (3).
    mud_velocity : ndarray
        ``dz_m/dt`` [m/s] (after necking, ``v_m0 g(t - t_n)``, Eq. (7)).
    f_e1, f_e2, f_s : ndarray
        Visco-elastic, nonlinear-spring and drag stresses [Pa], Eqs. (2), (4), (5).
    force : ndarray
        Total vertical force on the foot [N], positive up (resistance), Eq. (8) times area.
    state : ndarray of int8
        Contact state per sample: 0 FREE, 1 CONTACT, 2 NECKED.
    necking_times : ndarray
        Instants at which the neck broke [s], located inside the step.
    params : MudParameters
        The parameters used.
    foot : Foot
        The foot used.
    velocity_filter : VelocityFilter
        The branch-velocity filter used (resolved from ``"auto"``).
    depth_noise : DepthNoise or None
        The depth noise ``"auto"`` found and chose the filter by
        (:func:`~mudforce.model.velocity.analyse_depth_noise`); None when the
        filter was given.
    """

    time: np.ndarray
    depth: np.ndarray
    mud_displacement: np.ndarray
    force: np.ndarray
    state: np.ndarray
    necking_times: np.ndarray
    params: MudParameters
    foot: Foot
    velocity_filter: VelocityFilter = field(default_factory=VelocityFilter.exact)
    depth_noise: DepthNoise | None = None
    # the stepper's constants, for the outputs computed on access (see _derived)
    _params_row: np.ndarray = field(default_factory=lambda: np.empty((1, K.N_PARAMS)), repr=False)
    _cache: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        # own time and depth read-only, so that nobody can change the trajectory under the results
        for name in ("time", "depth"):
            arr = getattr(self, name)
            if not isinstance(arr, np.ndarray) or arr.flags.writeable or not arr.flags.owndata:
                arr = np.array(arr, dtype=np.float64)
                arr.setflags(write=False)
                object.__setattr__(self, name, arr)

    def _derived(self, name: str) -> np.ndarray:
        """An output :func:`simulate` did not keep, computed with its siblings on first access.

        The stepper runs the trajectory again writing every output
        (``_kernel.run_batch``): the same function on the same samples, so
        the same numbers, bit for bit, as a :class:`~mudforce.MudContact`
        fed them.
        """
        if not self._cache:
            block = K.new_out(self.time.size)
            K.run_batch(self.time, self.depth, K.new_states(1), K.new_ring(1, self.velocity_filter.window),
                        self._params_row, block)
            block.setflags(write=False)  # (its rows, the outputs, are views of it: read-only too, for good)
            out = K.outputs(block)
            self._cache.update(f_e1=out.f_e1, f_e2=out.f_e2, f_s=out.f_s, mud_velocity=out.mud_velocity,
                               velocity=out.velocity)
        return self._cache[name]

    @property
    def velocity(self) -> np.ndarray:
        """Foot velocity estimate used for the branch choice [m/s] (0 at the first sample)."""
        return self._derived("velocity")

    @property
    def mud_velocity(self) -> np.ndarray:
        """``dz_m/dt`` [m/s], Eq. (3); after necking ``v_m0 g(t - t_n)``, Eq. (7)."""
        return self._derived("mud_velocity")

    @property
    def f_e1(self) -> np.ndarray:
        """Visco-elastic stress [Pa], Eq. (2) (after necking the damper's ``b_m_w dz_m/dt``)."""
        return self._derived("f_e1")

    @property
    def f_e2(self) -> np.ndarray:
        """Nonlinear-spring stress [Pa], Eq. (4) (intrusion branch only)."""
        return self._derived("f_e2")

    @property
    def f_s(self) -> np.ndarray:
        """Drag stress [Pa], Eq. (5) (below the surface only)."""
        return self._derived("f_s")

    def __iter__(self) -> Iterator[np.ndarray]:
        """Unpack as ``time, force``."""
        return iter((self.time, self.force))

    def __len__(self) -> int:
        return int(self.time.shape[0])

    @property
    def state_names(self) -> list[str]:
        """The contact state of each sample as ``"FREE"``, ``"CONTACT"`` or ``"NECKED"``."""
        return [STATE_NAMES[s] for s in self.state]

    @property
    def peak_force(self) -> float:
        """Largest resistance force [N]."""
        return float(np.max(self.force))

    @property
    def min_force(self) -> float:
        """Most negative (suction) force [N]."""
        return float(np.min(self.force))

    def columns(self) -> dict[str, Any]:
        """The per-sample data under unit-suffixed column names (``time_s``, ``force_N``, ...)."""
        data: dict[str, Any] = {name: getattr(self, attr) for name, attr in _CSV_COLUMNS}
        data["state"] = np.array(self.state_names, dtype=object)
        return data

    def to_pandas(self) -> pandas.DataFrame:
        """A :class:`pandas.DataFrame` with the columns of :meth:`to_csv` (needs pandas)."""
        from mudforce._plumbing.optional import require

        pd = require("pandas", "pandas", "to_pandas()")
        return pd.DataFrame(self.columns())

    def to_csv(self, path: str | os.PathLike[str], *, quiet: bool = False) -> None:
        """Write the samples as CSV, atomically (:func:`mudforce.io.tables.write_csv`: ``.12g``, numpy speed).

        Columns: ``time_s, depth_m, velocity_m_s, mud_displacement_m,
        mud_velocity_m_s, f_e1_Pa, f_e2_Pa, f_s_Pa, force_N, state``.
        A long write shows progress on a terminal (stderr) unless ``quiet``.
        """
        from mudforce.io.tables import write_csv

        write_csv(path, {name: getattr(self, attr) for name, attr in _CSV_COLUMNS},
                  ("state", self.state, STATE_NAMES), quiet=quiet)

    def plot(self, path: str | os.PathLike[str] | None = None, *, title: str | None = None) -> Any:
        """Plot force over time and over depth, with the contact states (needs matplotlib).

        Parameters
        ----------
        path : path-like, optional
            Save the figure there (PNG, atomically) instead of only returning it.
        title : str, optional
            Figure title.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from mudforce.steppers.plots import plot_result

        return plot_result(self, path, title=title)


def _as_arrays(time: Any, depth: Any) -> tuple[np.ndarray, np.ndarray]:
    """The trajectory as contiguous float64 arrays of one shape (values are checked by :func:`_check_values`)."""
    t = real_array(time, "time", "s")  # refuses complex, boolean, string and object arrays
    z = real_array(depth, "depth", "m")
    if t.ndim != 1 or z.ndim != 1:
        raise InputError(f"time and depth must be 1-D arrays, got shapes {t.shape} and {z.shape}")
    if t.shape != z.shape:
        raise InputError(f"time and depth must have the same length, got {t.size} and {z.size}")
    if t.size == 0:
        raise InputError("the trajectory is empty; expected at least one sample")
    return np.ascontiguousarray(t), np.ascontiguousarray(z)


@njit(cache=True, nogil=True, error_model="numpy")
def _values_ok(t: np.ndarray, z: np.ndarray) -> bool:
    """True if all times and depths are finite and within bounds and every step within [MIN_DT, MAX_DT] (one pass).

    Speed plumbing: the failures are or-ed without an early exit, so that the
    loop vectorises (~0.5 ns a sample instead of ~1.6); every comparison is
    False for NaN, so a NaN fails.
    """
    n = t.shape[0]
    if n == 0:
        return True
    bad = out_of_bounds(t[0], z[0], MIN_DT)
    for k in range(1, n):
        bad |= out_of_bounds(t[k], z[k], t[k] - t[k - 1])
    return not bad


def _check_values(t: np.ndarray, z: np.ndarray) -> None:
    """Raise :class:`InputError` naming the first bad time or depth, or the first step out of bounds."""
    if _values_ok(t, z):
        return
    check_depths(z)  # the depths first: a sample whose depth is bad says so even where the step before it is refused
    check_times(t)


_NO_COPY = np.empty(0, dtype=np.float64)


class CompactRun:
    """The compiled batch loop (``_kernel.run_batch_compact``) over one trajectory, on work arrays made once.

    Speed plumbing: a fit runs the same trajectory tens of thousands of
    times with other constants; the arrays the loop writes (and its state,
    velocity history and spring scratch, reset before each run) are made
    here once instead of at every run. The loop writes every output it
    returns whatever the arrays held, so each run gives what a fresh one
    (:func:`run_compact`) gives, bit for bit.

    Parameters
    ----------
    t, z : ndarray
        Sample times [s] and depths [m], float64 (copied if not contiguous; values not checked here).
    window : int
        The velocity filter's window [steps].

    Attributes
    ----------
    time, depth : ndarray
        The trajectory as the loop reads it (contiguous float64) [s], [m].
    force : ndarray
        The last run's force [N] (overwritten by the next run).
    state : ndarray of int8
        The last run's contact state per sample.
    mud : ndarray
        The last run's ``z_m`` [m].
    """

    __slots__ = ("_counts", "_fresh", "_neck_index", "_neck_offset", "_ring", "_scratch", "_states", "depth",
                 "force", "mud", "state", "time")

    def __init__(self, t: np.ndarray, z: np.ndarray, window: int) -> None:
        # one compiled specialisation: a strided column (a table's) would compile the loop a second time (~15 s cold)
        self.time = np.ascontiguousarray(t, dtype=np.float64)
        self.depth = np.ascontiguousarray(z, dtype=np.float64)
        n = self.time.size
        self.state = np.empty(n, dtype=np.int8)
        self.mud = np.empty(n, dtype=np.float64)
        # written at neckings only (pages never touched cost nothing)
        self._neck_index = np.empty(n, dtype=np.int64)
        self._neck_offset = np.empty(n, dtype=np.float64)
        self._counts = np.zeros(1, dtype=np.int64)
        self.force = np.empty(n, dtype=np.float64)
        self._fresh = K.new_states(1)
        self._states = self._fresh.copy()
        self._ring = K.new_ring(1, window)
        self._scratch = K.new_spring_scratch(SPRING_BLOCK)

    def run(self, prow: np.ndarray, time_out: np.ndarray = _NO_COPY, depth_out: np.ndarray = _NO_COPY) -> int:
        """Run the loop from a fresh state with the constants ``prow`` (shape ``(1, N_PARAMS)``, :func:`params_row`).

        ``time_out`` and ``depth_out`` are :func:`run_compact`'s. Returns the
        first sample the stepper refused (the outputs are then valid before
        it) or -1.
        """
        np.copyto(self._states, self._fresh)
        if self._ring.size:
            self._ring.fill(0.0)
        self._counts[0] = 0
        return int(K.run_batch_compact(self.time, self.depth, self._states, self._ring, prow, self.state, self.mud,
                                       self._neck_index, self._neck_offset, self._counts, self.force,
                                       *self._scratch, time_out, depth_out))

    def necking_times(self) -> np.ndarray:
        """The instants at which the last run's neck broke [s], located inside the step."""
        necks = int(self._counts[0])
        out: np.ndarray = self.time[self._neck_index[:necks] - 1] + self._neck_offset[:necks]
        return out


def run_compact(t: np.ndarray, z: np.ndarray, prow: np.ndarray, window: int, time_out: np.ndarray = _NO_COPY,
                depth_out: np.ndarray = _NO_COPY) -> tuple[int, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The compiled batch loop (``_kernel.run_batch_compact``) over a trajectory, on fresh arrays.

    Parameters
    ----------
    t, z : ndarray
        Sample times [s] and depths [m], float64 (copied if not contiguous; values not checked here).
    prow : ndarray
        The stepper's constants, shape ``(1, N_PARAMS)`` (:func:`params_row`).
    window : int
        The velocity filter's window [steps].
    time_out, depth_out : ndarray, optional
        Of ``t``'s length: they receive copies of ``t`` and ``z``, made in
        the loop that reads them anyway (cheaper than a copy of its own).

    Returns
    -------
    tuple
        ``(bad, force [N], state (int8), z_m [m], necking times [s])``;
        ``bad`` is the first sample the stepper refused (the arrays are
        then valid before it) or -1.
    """
    work = CompactRun(t, z, window)
    bad = work.run(prow, time_out, depth_out)
    return bad, work.force, work.state, work.mud, work.necking_times()


def simulate(
    time: Any,
    depth: Any,
    params: MudParameters,
    foot: Foot | None = None,
    *,
    velocity_filter: VelocityFilter | str = "auto",
) -> SimulationResult:
    """Simulate the mud force on a foot following a prescribed trajectory.

    Exact for the first-order-hold input as docs/model.md defines
    it: closed-form Maxwell steps (Eq. (3)), the necking instant located
    inside the step (Eq. (9)), and the closed-form decay after necking
    (Eq. (7)).

    Parameters
    ----------
    time : array_like
        Sample times [s], within +-1e9 s, strictly increasing, each step
        within [1e-9, 1e3] s (:data:`MIN_DT`, :data:`MAX_DT`).
    depth : array_like
        Foot depth below the undisturbed surface [m], positive down, within
        +-100 m (:data:`MAX_DEPTH`).
    params : MudParameters
        Mud parameters, e.g. ``MudParameters.from_water_content(0.25)``.
    foot : Foot, optional
        Foot geometry; the paper's 51 x 38 mm cuboid by default.
    velocity_filter : {"auto", "exact"} or VelocityFilter
        How the intrusion/withdrawal branch is chosen. ``"auto"`` (default)
        tells the depth's white noise from its motion: clean input, smooth
        or not, gets the paper's exact rule, noisy input a smoothing secant
        with a deadband (:mod:`mudforce.model.velocity`); the result's
        ``velocity_filter`` and ``depth_noise`` say what was chosen and why.

    Returns
    -------
    SimulationResult

    Examples
    --------
    >>> import mudforce
    >>> t, z = mudforce.Protocol.paper().sample()
    >>> res = mudforce.simulate(t, z, mudforce.MudParameters.from_water_content(0.25))
    >>> round(res.peak_force, 1)
    59.5
    """
    t, z = _as_arrays(time, depth)
    # the result owns its time and depth: the caller's arrays are copied (in the loop), new ones kept
    callers = any(isinstance(given, np.ndarray) and np.may_share_memory(arr, given)
                  for arr, given in ((t, time), (z, depth)))
    if not (callers and (isinstance(velocity_filter, VelocityFilter)
                         or (isinstance(velocity_filter, str) and velocity_filter == "exact"))):
        # bounds, in a pass of their own: "auto" estimates the noise from valid samples only, and
        # arrays of our own are not copied; the compiled loop holds every sample it copies to them
        _check_values(t, z)
    foot = Foot.paper() if foot is None else foot
    noise: DepthNoise | None = None
    if isinstance(velocity_filter, str) and velocity_filter == "auto":
        vf, noise = choose_velocity_filter(t, z)
    else:
        vf = resolve_velocity_filter(velocity_filter, t, z)
    prow = K.params_row(params, foot, vf)[None, :]
    own_t, own_z = (np.empty_like(t), np.empty_like(z)) if callers else (t, z)
    copies = (own_t, own_z) if callers else (_NO_COPY, _NO_COPY)
    bad, force, state, mud, necking_times = run_compact(t, z, prow, vf.window, *copies)
    if bad >= 0:
        # the loop refuses a sample out of bounds (checking copies) or one the step cannot take: name why
        _check_values(t, z)
        raise InputError(f"sample {bad} could not be stepped (time {float(t[bad])!r}, depth {float(z[bad])!r})")
    # no bound can be stated for every path: check what leaves (the sum is finite only if every force is,
    # barring an overflow of the sum itself, which then takes the slow path and passes)
    if not np.isfinite(np.add.reduce(force)) and not np.isfinite(force).all():
        k = int(np.flatnonzero(~np.isfinite(force))[0])
        raise InputError(f"the force is not finite at sample {k} (t = {t[k]:g} s); the inputs are outside what "
                         "the model can represent")
    own_t.setflags(write=False)
    own_z.setflags(write=False)
    return SimulationResult(
        time=own_t,
        depth=own_z,
        mud_displacement=mud,
        force=force,
        state=state,
        necking_times=necking_times,
        params=params,
        foot=foot,
        velocity_filter=vf,
        depth_noise=noise,
        _params_row=prow,
    )
