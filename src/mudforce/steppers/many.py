"""Many feet at once: the streaming contact vectorised over feet.

:class:`MudContacts` holds ``n`` contact states as the rows of one array
and steps all of them with one call to the compiled stepper
(:func:`mudforce._kernel.run_feet`), with no Python loop over feet. Each foot
may have its own mud parameters and foot geometry (one params row each), for
domain randomisation in reinforcement learning. Feeding foot ``j`` the same
samples as a :class:`mudforce.MudContact` gives bit-for-bit the same force.

Threads: with thousands of feet the step splits the feet into contiguous
slices stepped on numba's threads (:func:`mudforce._kernel.run_feet_threads`),
one slice per thread. The feet are independent, so the forces are the same
bit for bit with any number of threads. Only numba's OpenMP and TBB
threading layers launch fast enough to pay (~6 us per step); with its
fallback "workqueue" layer (~140 us per launch), and in a process forked
after threads were used (GNU OpenMP is not fork-safe), the automatic choice
is one thread.
"""

from __future__ import annotations

import functools
import os
import threading
from collections.abc import Mapping, Sequence
from collections.abc import Set as AbstractSet
from typing import Any

import numba
import numba.np.ufunc.parallel
import numpy as np

from mudforce import _kernel as K
from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MIN_DT
from mudforce._kernel.layout import STATE_NAMES
from mudforce._plumbing.deprecation import warn_renamed
from mudforce._plumbing.jit import njit
from mudforce.errors import InputError, feet_count, positive_int, real_array, real_number
from mudforce.model.bounds import check_step
from mudforce.model.foot import Foot
from mudforce.model.parameters import PARAMETER_NAMES, MudParameters
from mudforce.model.velocity import VelocityFilter, resolve_velocity_filter
from mudforce.steppers.contact import _restore_rows, check_states

__all__ = ["MudContacts"]

#: feet per thread below which splitting the step does not pay for the launch (~6 us)
FEET_PER_THREAD = 1024

# numba's workqueue layer must not be entered by two Python threads at once;
# held around every threaded step (uncontended: ~0.1 us against ~50 us per step)
_launch_lock = threading.Lock()
_forked = False


def _mark_forked() -> None:
    global _forked
    _forked = True


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_mark_forked)


@functools.lru_cache(maxsize=1)
def _serial_code_first() -> None:
    """Load :func:`~mudforce._kernel.run_feet`'s own machine code before :func:`~mudforce._kernel.run_feet_threads`'s.

    Speed plumbing, not physics (the bits are the same either way). numba links a copy of ``run_feet`` into
    ``run_feet_threads`` and optimises it again there; that copy is a weak symbol, which the JIT linker
    resolves to a ``run_feet`` already loaded in the process if there is one. Loaded first (from numba's cache,
    as in every process after the first), ``run_feet_threads`` kept its own copy, which LLVM's second
    optimisation made about 7 % slower per foot than ``run_feet`` itself. A call on no feet, with the types
    ``MudContacts`` passes, loads (or compiles, as a cold ``run_feet_threads`` does anyway) ``run_feet`` first.
    """
    scratch, index = K.new_feet_scratch(0, 1)
    K.run_feet(K.new_states(0), K.new_ring(0, 1), np.zeros((0, K.N_PARAMS)), np.zeros(0), 1.0, np.zeros(0),
               scratch[0], index[0])


@functools.lru_cache(maxsize=1)
def _fast_threading_layer() -> bool:
    """Whether numba's threading layer launches fast enough (OpenMP or TBB) to step feet on threads."""
    _serial_code_first()
    states = K.new_states(2)
    K.run_feet_threads(states, K.new_ring(2, 1), np.zeros((2, K.N_PARAMS)), np.zeros(2), 1.0, np.zeros(2),
                       *K.new_feet_scratch(2, 2), np.zeros(2, dtype=np.int64))
    layer: str = numba.np.ufunc.parallel.threading_layer()
    return layer in ("omp", "tbb")


def _resolve_threads(threads: int | None, n: int) -> int:
    """Number of slices to step ``n`` feet in: ``threads`` if given, else automatic (see the module docstring)."""
    if threads is not None:
        return min(positive_int(threads, "threads", " or None (automatic)"), n)
    auto = min(int(numba.get_num_threads()), n // FEET_PER_THREAD)
    if auto <= 1 or _forked or not _fast_threading_layer():
        return 1
    return auto


def _param_rows(
    params: MudParameters | Sequence[MudParameters] | np.ndarray,
    n: int,
    foot: Foot | Sequence[Foot] | None,
    vf: VelocityFilter,
) -> np.ndarray:
    feet: list[Foot]
    if foot is None:
        feet = [Foot.paper()] * n
    elif isinstance(foot, Foot):
        feet = [foot] * n
    elif isinstance(foot, (str, bytes, Mapping, AbstractSet)):  # its characters or keys, counted as feet
        raise InputError(f"foot must be a Foot or a sequence of Foot, got {type(foot).__name__}")
    else:
        try:
            feet = list(foot)
        except TypeError:
            raise InputError(f"foot must be a Foot or a sequence of Foot, got {type(foot).__name__}") from None
        if len(feet) != n:
            raise InputError(f"got {len(feet)} feet for {n} contacts; give one Foot or one per contact")
        for f in feet:
            if not isinstance(f, Foot):
                raise InputError(f"foot must be a Foot or a sequence of Foot, got an element {type(f).__name__}")
    if isinstance(params, MudParameters):
        values = np.tile(params.as_array(), (n, 1))
    elif isinstance(params, np.ndarray):
        # real numbers only: complex (imaginary part dropped), boolean (1.0), string (parsed) and object arrays passed
        values = np.array(real_array(params, "a parameter array", "SI"))
        if values.ndim == 1:
            values = np.tile(values, (n, 1))
        if values.shape != (n, len(PARAMETER_NAMES)):
            raise InputError(
                f"a parameter array must have shape ({n}, {len(PARAMETER_NAMES)}) "
                f"(columns {', '.join(PARAMETER_NAMES)}, SI), got {values.shape}"
            )
        # validate every row through MudParameters (positivity, beta in (0, 1], ...)
        for row in values:
            MudParameters(*row.tolist())
    elif isinstance(params, (str, bytes)) or not isinstance(params, Sequence):
        raise InputError("params must be MudParameters, a sequence of them or an (n, 11) array, "
                         f"got {type(params).__name__}")
    else:
        plist = list(params)
        if len(plist) != n:
            raise InputError(f"got {len(plist)} parameter sets for {n} contacts; give one or one per contact")
        for p in plist:
            if not isinstance(p, MudParameters):
                raise InputError(f"params must be MudParameters, got {type(p).__name__}")
        values = np.array([p.as_array() for p in plist], dtype=np.float64)
    rows = np.empty((n, K.N_PARAMS), dtype=np.float64)
    for j in range(n):
        rows[j] = K.make_params(values[j], feet[j].area, feet[j].width, vf.window, vf.deadband)
    return rows


@njit(cache=True, nogil=True, error_model="numpy")
def _depths_ok(z: np.ndarray) -> bool:
    """True if every depth is finite and within +-MAX_DEPTH [m] (one pass over the feet).

    Speed plumbing: the failures are or-ed without an early exit, so the loop
    vectorises (a comparison is False for NaN, so a NaN fails).
    """
    bad = False
    for k in range(z.shape[0]):
        bad |= not abs(z[k]) <= MAX_DEPTH
    return not bad


_FLOAT64 = np.dtype(np.float64)  # numpy's own instance: a float64 array's dtype is this very object


def _plain(a: np.ndarray) -> np.ndarray:
    """``a`` if it is C-contiguous, aligned and writable, else such a copy of it: the one layout the compiled steps
    are compiled for (numba compiles another version of a step for a strided, read-only or unaligned array, for
    seconds, once)."""
    flags = a.flags
    return a if flags.c_contiguous and flags.aligned and flags.writeable else np.array(a, order="C")


def _chosen_feet(feet: Any, n: int) -> np.ndarray:
    """The feet a ``reset(feet)`` names, as indices in ``0 .. n - 1`` (every foot for None); else one-line InputError.

    ``feet`` is an int, a sequence of ints (negative ones count from the end), or a boolean mask of shape (n,).
    """
    if feet is None:
        return np.arange(n)
    if isinstance(feet, (list, tuple)) and any(isinstance(x, (bool, np.bool_)) for x in feet) \
            and not all(isinstance(x, (bool, np.bool_)) for x in feet):  # numpy reads [True, 2] as [1, 2]
        raise InputError(f"feet mixes booleans and indices: {list(feet)!r}; expected indices, or a boolean mask of "
                         f"shape ({n},)")
    try:
        idx = np.asarray(feet)
    except (TypeError, ValueError):  # ragged nesting ([[0], [0, 1]]): numpy's ValueError
        raise InputError(f"feet must be an index, a list of indices or a boolean mask of shape ({n},), got a "
                         f"ragged {type(feet).__name__}") from None
    if idx.ndim > 1:
        raise InputError(f"feet must be an index, a list of indices or a boolean mask of shape ({n},), got an array "
                         f"of shape {idx.shape}")
    if idx.dtype == np.bool_:
        if idx.shape != (n,):
            raise InputError(f"a reset mask must have shape ({n},), got {idx.shape}")
        return np.flatnonzero(idx)
    if idx.size == 0 and idx.ndim == 1:  # no feet (an empty list is float64 to numpy): nothing to reset
        return np.zeros(0, dtype=np.int64)
    if not np.issubdtype(idx.dtype, np.integer):
        raise InputError(f"feet must be indices or a boolean mask, got {idx.dtype}")
    if idx.size and (idx.min() < -n or idx.max() >= n):
        raise InputError(f"foot index out of range 0..{n - 1}: {idx.tolist()}")
    return np.atleast_1d(idx) % n


class MudContacts:
    """The mud force on ``n`` feet, all stepped together, one sample at a time.

    Parameters
    ----------
    params : MudParameters, sequence of MudParameters, or ndarray
        One parameter set for all feet, one per foot, or an array of shape
        ``(n, 11)`` (or ``(11,)``) in :data:`mudforce.PARAMETER_NAMES` order,
        SI units, for domain randomisation. Every row is validated.
    n : int
        Number of feet, >= 1.
    foot : Foot or sequence of Foot, optional
        Foot geometry, shared or one per foot; the paper's 51 x 38 mm cuboid by default.
    velocity_filter : "exact" or VelocityFilter
        Branch-velocity filter shared by all feet (default: the paper's exact rule).
    threads : int, optional
        Step the feet in this many slices on numba's threads. By default one
        per core (``numba.get_num_threads()``) if there are at least
        :data:`FEET_PER_THREAD` feet per thread and numba's threading layer is
        OpenMP or TBB, else 1. The forces do not depend on it.

    Notes
    -----
    Foot ``j`` is row ``j`` of one state array and one parameter array, and
    every step runs the compiled stepper of :class:`mudforce.MudContact`
    over all rows in one compiled loop, so the result is exactly that of
    ``n`` independent :class:`~mudforce.MudContact` objects. :meth:`step`
    returns a new force array (or fills ``out=``).

    Examples
    --------
    >>> import numpy as np
    >>> from mudforce import MudParameters
    >>> from mudforce.steppers.many import MudContacts
    >>> feet = MudContacts(MudParameters.from_water_content(0.25), 3)
    >>> feet.step(np.zeros(3), 0.01).tolist()
    [0.0, 0.0, 0.0]
    >>> bool((feet.step(np.full(3, 1e-4), 0.01) > 0).all())
    True
    """

    def __init__(
        self,
        params: MudParameters | Sequence[MudParameters] | np.ndarray,
        n: int,
        foot: Foot | Sequence[Foot] | None = None,
        *,
        velocity_filter: VelocityFilter | str = "exact",
        threads: int | None = None,
    ) -> None:
        self.n = feet_count(n)
        self.velocity_filter = resolve_velocity_filter(velocity_filter)
        self.params_array = _param_rows(params, self.n, foot, self.velocity_filter)
        self._states = K.new_states(self.n)  # the live rows (kernel layout); save and restore with .state
        #: the velocity filter's recent samples, one row per foot (no columns for the exact filter)
        self.ring = K.new_ring(self.n, self.velocity_filter.window)
        #: the last step's forces [N] (the step writes them here)
        self.forces: np.ndarray = np.zeros(self.n, dtype=np.float64)
        #: slices the feet are stepped in, one per thread (1: the calling thread only)
        self.threads = _resolve_threads(threads, self.n)
        if self.threads > 1:
            _serial_code_first()
        self._chunks = np.empty(self.threads, dtype=np.int64)
        # where the feet on the nonlinear spring wait for their vectorised pass, one block per slice
        self._scratch, self._index = K.new_feet_scratch(self.n, self.threads)

    def step(self, depths: Any, dt: float, *, out: np.ndarray | None = None) -> np.ndarray:
        """Advance every foot to its next depth sample; return the forces [N].

        Every input is checked before any foot moves: a refused step leaves
        every foot exactly as it was, so it can be retried.

        Parameters
        ----------
        depths : array_like, shape (n,)
            Foot depths below the surface [m], positive down, each within
            +-100 m (:data:`mudforce.steppers.simulation.MAX_DEPTH`).
        dt : float
            Time since the previous sample [s], within [1e-9, 1e3]
            (:data:`~mudforce.steppers.simulation.MIN_DT`: shorter steps would let
            ``dz/dt`` and the drag overflow; ignored by a foot's first step
            after creation or :meth:`reset`).
        out : ndarray, shape (n,), float64, optional
            Write the forces here instead of into a new array (no allocation).

        Returns
        -------
        ndarray, shape (n,)
            Vertical mud force on each foot [N], positive up: a new array,
            or ``out``.
        """
        # refuses complex, boolean, string and object arrays (a C-contiguous, aligned, writable float64 array passes
        # as it is; a masked one, a subclass, goes to real_array, which refuses masked values: numba raised its own
        # TypeError on it); a strided, read-only or unaligned one is copied to that layout (_plain), the same values
        # (dtype "is": numpy's own float64 instance, a float64 array's dtype; an equal other one takes the long way)
        z = depths if type(depths) is np.ndarray and depths.dtype is _FLOAT64 and depths.flags.carray else _plain(
            real_array(depths, "depths", "m"))
        if z.shape != (self.n,):
            raise InputError(f"depths must have shape ({self.n},), got {z.shape}")
        if type(dt) is not float:
            dt = real_number(dt, "dt")
        # dt is ignored by a foot's first step (as MudContact.step ignores it): refused only if a foot has started
        if not MIN_DT <= dt <= MAX_DT and K.state_column(self._states, "started").any():
            check_step(dt)
        if out is not None and not (isinstance(out, np.ndarray) and out.dtype == np.float64
                                    and out.shape == (self.n,) and out.flags.writeable):
            raise InputError(f"out must be a writable float64 array of shape ({self.n},)")
        if not _depths_ok(z):  # check every foot before any moves
            bad = int(np.flatnonzero(~(np.abs(z) <= MAX_DEPTH))[0])
            raise InputError(f"depth of foot {bad} must be finite and within [-{MAX_DEPTH:g}, {MAX_DEPTH:g}] m, "
                             f"got {float(z[bad])!r}; no foot was stepped")
        if self.threads > 1 and not _forked:
            with _launch_lock:
                bad = K.run_feet_threads(self._states, self.ring, self.params_array, z, dt, self.forces,
                                         self._scratch, self._index, self._chunks)
        else:
            bad = K.run_feet(self._states, self.ring, self.params_array, z, dt, self.forces, self._scratch[0],
                             self._index[0])
        if bad >= 0:  # pragma: no cover - every input the kernel refuses was refused above
            raise InputError(f"depth of foot {bad} must be finite [m], got {z[bad]!r}")
        if out is None:
            forces: np.ndarray = self.forces.copy()
            return forces
        out[:] = self.forces
        return out

    def reset(self, feet: Any = None) -> None:
        """Forget the history of some feet (all by default).

        Parameters
        ----------
        feet : int, sequence of int, or boolean mask of shape (n,), optional
            Which feet to reset; their next :meth:`step` sets their initial sample.
        """
        chosen = _chosen_feet(feet, self.n)
        self._states[chosen] = K.new_states(1)[0]
        self.ring[chosen] = 0.0  # their filter's old samples too: their state is then a fresh foot's

    @property
    def modes(self) -> list[str]:
        """Each foot's contact state: ``"FREE"``, ``"CONTACT"`` or ``"NECKED"``."""
        return [STATE_NAMES[int(m)] for m in K.state_column(self._states, "mode")]

    @property
    def depths(self) -> np.ndarray:
        """Each foot's depth at its last sample [m] (a copy)."""
        return np.array(K.state_column(self._states, "depth"), dtype=np.float64)

    @property
    def state(self) -> np.ndarray:
        """A snapshot of all feet's states (a read-only copy); assign one back to restore them (rollouts, resets).

        Row ``j`` is foot ``j``'s state row (layout of :mod:`mudforce._kernel`)
        followed by its velocity filter's history (which the exact filter
        does not keep). A restored state is validated as strictly as a fresh
        one: a wrong shape or a row the stepper never makes
        (:func:`mudforce.steppers.contact.check_states`) is refused with an
        :class:`~mudforce.InputError`, and no foot is then changed.
        """
        snapshot = np.hstack((self._states, self.ring))
        snapshot.setflags(write=False)
        return snapshot

    @state.setter
    def state(self, value: np.ndarray) -> None:
        arr = real_array(value, "a state", "SI")
        shape = (self.n, K.N_STATE + self.ring.shape[1])
        if arr.shape != shape:
            raise InputError(f"a state of {self.n} feet has shape {shape}, got {arr.shape}")
        check_states(arr[:, : K.N_STATE], arr[:, K.N_STATE :], "a state")
        _restore_rows(self._states, self.ring, self.params_array, arr)

    @property
    def states(self) -> np.ndarray:
        """Deprecated: the live state rows; save and restore with :attr:`state`."""
        warn_renamed("MudContacts.states", "MudContacts.state")
        return self._states

    def snapshot(self) -> np.ndarray:
        """Deprecated: :attr:`state`."""
        warn_renamed("MudContacts.snapshot()", "MudContacts.state")
        return np.hstack((self._states, self.ring))

    def restore(self, snapshot: np.ndarray) -> None:
        """Deprecated: assign to :attr:`state`."""
        warn_renamed("MudContacts.restore(snapshot)", "MudContacts.state = snapshot")
        self.state = snapshot

    def __len__(self) -> int:
        return self.n

    def __repr__(self) -> str:
        return f"MudContacts(n={self.n}, threads={self.threads})"
