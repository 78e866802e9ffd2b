"""Where the stepper keeps a foot: the rows, their columns, and the values read from them.

Why rows of plain float64 arrays
--------------------------------
A foot's state is one row ``states[j, :]`` of a float64 array, its constants
one row ``params[j, :]``, the history of its smoothing velocity filter one
row ``ring[j, :]``. Thousands of feet (:class:`~mudforce.MudContacts`) are
then three arrays that one compiled loop walks, with no Python object per
foot, and a snapshot for a rollout is a copy of an array.

The state row holds only what every step reads (20 doubles), so the states
of thousands of feet stay in the CPU's cache; the ring (132 doubles, a
ring buffer of the filter's last samples, so that adding one costs one
write) would otherwise be most of it, and the exact filter (window 1),
which keeps no history, passes a ring with no columns.

Why values (registers) in between
---------------------------------
The compiled code does not work on the rows directly: :func:`load_state`
reads a row into a :class:`State` value (a NamedTuple of floats), the step
computes a new value, and :func:`store_state` writes it back. The batch
loops keep the value in registers through a whole trajectory (array stores
could alias the outputs, so the compiler would otherwise reload every field
on every sample). The contact state (:class:`ContactMode`) is an int in the
value and a float only in the row. The Maxwell extension ``z_i - z_m`` is
carried whole, not rebuilt from ``z_m``, which is rounded.

The columns
-----------
Callers outside the kernel use the functions and NamedTuples here, not
the column indices: in Python :func:`state_of`, :func:`params_of`,
:func:`state_column`, :func:`state_core`, :func:`forget_cache`,
:func:`outputs`, :func:`make_params`; in compiled code :func:`load_state`,
:func:`store_state`, :func:`load_params`, :func:`state_from_row`,
:func:`params_from_row`, :func:`forget_row_cache`. The indices
(``S_*`` state, ``P_*`` params, ``R_*`` ring, ``O_*`` outputs) are the
kernel's own: the order of :class:`State`'s fields is the order of the
``S_*`` columns, :class:`Params`'s that of ``P_*``, :class:`Outputs`'s
that of ``O_*``. Outputs are column-major, ``out[O_FORCE, k]`` being
sample ``k``'s force, so a batch's arrays are contiguous rows.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from enum import IntEnum
from typing import Any, NamedTuple, TypeVar

import numpy as np

from mudforce._plumbing import cache as _cache
from mudforce._plumbing.jit import njit
from mudforce.model.equations import array_form, relaxation_time
from mudforce.model.law3d import root, select
from mudforce.model.velocity import MAX_WINDOW

_cache.install()  # numba's cache keyed on the shared sources' content (see mudforce._plumbing.cache)

__all__ = [
    "CONTACT",
    "FREE",
    "MAX_WINDOW",
    "NECKED",
    "N_CORE",
    "N_OUT",
    "N_PARAMS",
    "N_RING",
    "N_STATE",
    "STATE_NAMES",
    "Cache",
    "ContactMode",
    "Outputs",
    "Params",
    "State",
    "forget_cache",
    "forget_row_cache",
    "invalid_rows",
    "load_cache",
    "load_params",
    "load_state",
    "make_params",
    "neck_flush_age",
    "new_out",
    "new_ring",
    "new_states",
    "outputs",
    "params_from_row",
    "params_of",
    "ring_width",
    "state_column",
    "state_core",
    "state_from_row",
    "state_of",
    "store_cache",
    "store_state",
]

_F = TypeVar("_F", bound=Callable[..., Any])


def _compiled(inline: str | Callable[..., bool] = "never", **overrides: Any) -> Callable[[_F], _F]:
    """``numba.njit`` for the stepper: cached, releases the GIL, no reference counting, IEEE division.

    ``_nrt=False``: the stepper allocates nothing, and without numba's
    reference counting its array arguments cost no atomic increments per
    call (a 2-3x difference per sample). ``error_model="numpy"``: a
    division is a division, without Python's check for a zero divisor,
    which is a branch that keeps loops from vectorising (the stepper
    validates its inputs before it divides by them). ``inline="always"`` compiles a
    function into each caller's loop; ``inline`` may also be numba's cost model, a callable
    ``(expr, caller_ir, callee_ir) -> bool`` asked at each call site. ``overrides`` replace these options
    (the MuJoCo adapter's per-step functions keep the GIL, for one). Typed
    so that the compiled functions keep their signatures for mypy.
    """
    options: dict[str, Any] = {"cache": True, "nogil": True, "_nrt": False, "error_model": "numpy", "inline": inline,
                               **overrides}
    decorator: Callable[[_F], _F] = njit(**options)
    return decorator


class ContactMode(IntEnum):
    """The contact state machine's states (docs/model.md's table), as stored in a state row and in ``state`` outputs.

    Named "mode" (the field :attr:`State.mode`) so as not to be confused with
    :class:`mudforce.ContactState`, the public snapshot of a foot's whole state.
    """

    FREE = 0  #: above the surface, no force; ``z_m`` follows ``z_i``
    CONTACT = 1  #: in the mud, on the intrusion or the withdrawal branch
    NECKED = 2  #: the neck broke while withdrawing; the mud decays freely, Eq. (7)


# the same values as plain ints, for the compiled code (an int compares with no conversion)
FREE = int(ContactMode.FREE)
CONTACT = int(ContactMode.CONTACT)
NECKED = int(ContactMode.NECKED)
STATE_NAMES: tuple[str, ...] = tuple(s.name for s in ContactMode)

# params row
P_K_I = 0
P_B_I = 1
P_K_W = 2
P_B_W = 3
P_ALPHA = 4
P_BETA = 5
P_SIGMA_Y = 6
P_ZETA = 7
P_OMEGA_0 = 8
P_RHO_M = 9
P_LAMBDA = 10
P_AREA = 11
P_WIDTH = 12
P_WINDOW = 13
P_DEADBAND = 14
P_TAU_I = 15
P_TAU_W = 16
P_NECK_FLUSH = 17  # age after necking [s] past which Eq. (7)'s filter response is flushed to zero
N_PARAMS = 18

# state row
S_STARTED = 0
S_MODE = 1
S_TIME = 2  # time since the first sample [s]
S_DEPTH = 3  # z_i at the last sample [m]
S_MUD = 4  # z_m at the last sample [m]
S_NECK_AGE = 5  # time since necking [s]
S_NECK_V = 6  # v_m0, mud velocity at necking [m/s]
S_NECK_Z = 7  # z_m at necking [m]
S_DIRECTION = 8  # -1 up, 0 rest, +1 down
S_VELOCITY = 9  # velocity estimate at the last sample [m/s]
S_NECK_G = 10  # g(age): normalised mud velocity after necking, Eq. (7)
S_NECK_GI = 11  # G(age) = integral of g [s]
S_STRAIN = 12  # z_i - z_m at the last sample in CONTACT [m] (carried whole: z_m is rounded)
# a cache of what the step length allows to precompute (not state: recomputed when missing)
S_CACHE_DT = 13  # step length the cached values are for
S_CACHE_DECAY_I = 14  # exp(-dt / tau_i)
S_CACHE_DECAY_W = 15  # exp(-dt / tau_w)
S_CACHE_PHI = 16  # 4 entries: transition matrix of Eq. (7)'s filter over one step
N_STATE = S_CACHE_PHI + 4
N_CORE = S_CACHE_DT  # the state proper: columns 0 .. N_CORE - 1

# ring row: the smoothing differentiator's last samples (for filter windows > 1)
RING = MAX_WINDOW + 1  # holds window + 1 samples, so windows up to MAX_WINDOW steps
R_N = 0  # number of samples held
R_HEAD = 1  # index of the newest sample
R_Z = 2  # RING depths [m]
R_T = R_Z + RING  # RING times [s]
N_RING = R_T + RING

# output rows (``out`` is column-major: ``out[O_FORCE, k]`` is sample k's force)
O_FORCE = 0
O_F_E1 = 1
O_F_E2 = 2
O_F_S = 3
O_MUD = 4
O_MUD_VELOCITY = 5
O_VELOCITY = 6
O_STATE = 7
O_NECK_OFFSET = 8  # time from the step's start to necking [s], NaN if none
N_OUT = 9


class State(NamedTuple):
    """A foot's state as values: columns ``0 .. N_CORE - 1`` of a state row, in the order of the ``S_*`` indices."""

    started: float  #: 0 before the first sample, 1 after
    mode: int  #: :class:`ContactMode`
    time: float  #: time since the first sample [s]
    depth: float  #: ``z_i`` at the last sample [m]
    mud: float  #: ``z_m`` at the last sample [m]
    neck_age: float  #: time since necking [s]
    neck_v: float  #: ``v_m0``, the mud velocity at necking [m/s]
    neck_z: float  #: ``z_m`` at necking [m]
    direction: float  #: branch direction at the last sample: -1 up, 0 rest, +1 down
    velocity: float  #: branch velocity estimate at the last sample [m/s]
    neck_g: float  #: ``g(age)``, Eq. (7)'s normalised mud velocity [-]
    neck_gi: float  #: ``G(age)``, its integral [s]
    strain: float  #: ``z_i - z_m`` in CONTACT [m]


class Cache(NamedTuple):
    """What a constant step length lets a foot precompute: columns ``S_CACHE_*`` of a state row."""

    dt: float  #: the step length it is for [s] (-1: none)
    decay_i: float  #: ``exp(-dt / tau_i)``
    decay_w: float  #: ``exp(-dt / tau_w)``
    phi0: float  #: Eq. (7)'s one-step transition matrix (:func:`mudforce.model.equations.neck_filter_transition`)
    phi1: float
    phi2: float
    phi3: float


class Params(NamedTuple):
    """A foot's constants as values (the fields of a params row, in the order of the ``P_*`` indices)."""

    k_i: float
    b_i: float
    k_w: float
    b_w: float
    alpha: float
    beta: float
    sigma_y: float
    zeta: float
    omega_0: float
    rho_m: float
    lam: float
    area: float
    width: float
    window: float
    deadband: float
    tau_i: float
    tau_w: float
    neck_flush: float


class Outputs(NamedTuple):
    """The rows of an output block (:func:`new_out`), or the values of one of its columns (:func:`outputs`)."""

    force: Any  #: force [N], Eqs. (1), (8) times the area
    f_e1: Any  #: visco-elastic stress [Pa], Eq. (2)
    f_e2: Any  #: nonlinear-spring stress [Pa], Eq. (4)
    f_s: Any  #: drag stress [Pa], Eq. (5)
    mud: Any  #: ``z_m`` [m]
    mud_velocity: Any  #: ``dz_m/dt`` [m/s]
    velocity: Any  #: branch velocity estimate [m/s]
    state: Any  #: :class:`ContactMode` (as a float)
    neck_offset: Any  #: time from the step's start to necking [s], NaN if none


def make_params(values: np.ndarray, area: float, width: float, window: int, deadband: float) -> np.ndarray:
    """One params row from the 11 model values [SI], the foot's area [m^2] and width [m], and the velocity filter."""
    row = np.empty(N_PARAMS, dtype=np.float64)
    row[:11] = values
    row[P_AREA] = area
    row[P_WIDTH] = width
    row[P_WINDOW] = float(window)
    row[P_DEADBAND] = float(deadband)
    tau = array_form(relaxation_time)  # Eq. (3), as every path computes it
    row[P_TAU_I] = tau(row[P_K_I], row[P_B_I])
    row[P_TAU_W] = tau(row[P_K_W], row[P_B_W])
    row[P_NECK_FLUSH] = float(neck_flush_age(row[P_ZETA], row[P_OMEGA_0]))
    return row


def neck_flush_age(zeta: Any, omega_0: Any) -> Any:
    """The age after necking [s] at which Eq. (7)'s filter response has decayed below 1e-250 [-].

    Its slowest mode decays as ``exp(-r t)``, ``r = zeta omega_0`` up to
    critical damping and ``omega_0 (zeta - sqrt(zeta^2 - 1))`` beyond
    (written ``omega_0 / (zeta + sqrt(zeta^2 - 1))``, which does not cancel).
    Past ``ln(1e250) / r`` the stepper sets the response to zero: it is
    nothing physically, and left alone it would go on into subnormal
    numbers, which are slow. Deciding by the age rather than by the values
    keeps the test off the filter update's chain of dependent operations.

    This one source runs on floats and, for :func:`mudforce.jax.neck_flush_age`,
    on JAX arrays (``select`` and ``root`` are ``where`` and ``sqrt`` there; the
    unselected branch's square root is of 1, so that no NaN reaches a gradient).
    """
    over = zeta > 1.0
    rate = select(over, omega_0 / (zeta + root(select(over, zeta * zeta - 1.0, 1.0))), zeta * omega_0)
    return 250.0 * math.log(10.0) / rate


def new_states(n: int) -> np.ndarray:
    """``n`` fresh state rows (not started: the first step sets the initial sample)."""
    states = np.zeros((n, N_STATE), dtype=np.float64)
    states[:, S_CACHE_DT] = -1.0
    return states


def ring_width(window: int) -> int:
    """Columns of a ring row for a velocity filter of ``window`` steps: none for ``window <= 1``."""
    return N_RING if window > 1 else 0


def new_ring(n: int, window: int) -> np.ndarray:
    """``n`` ring rows for a velocity filter of ``window`` steps (the first step fills them)."""
    return np.zeros((n, ring_width(window)), dtype=np.float64)


def new_out(n: int) -> np.ndarray:
    """Outputs of ``n`` samples or feet: ``N_OUT`` contiguous rows of ``n`` (column ``k`` per step)."""
    return np.empty((N_OUT, n), dtype=np.float64)


def outputs(out: np.ndarray) -> Outputs:
    """The rows of an output block by name (views), or of one column ``out[:, k]`` the values."""
    return Outputs(*out)


def state_column(states: np.ndarray, name: str) -> np.ndarray:
    """Field ``name`` of :class:`State` (e.g. ``"depth"``) in every row of ``states`` (a view; 0-d for one row)."""
    return states[..., State._fields.index(name)]


def state_core(states: np.ndarray) -> np.ndarray:
    """The state proper of each row (a view), without the step-length cache, which is not state."""
    return states[..., :N_CORE]


def forget_cache(states: np.ndarray) -> None:
    """Drop the step-length cache of every row of ``states`` (in place): the next step recomputes it.

    For a state restored under other constants (the cached decays are the old ones').
    """
    states[..., S_CACHE_DT] = -1.0


def invalid_rows(states: np.ndarray, ring: np.ndarray, max_depth: float,
                 max_speed: float = math.inf, max_time: float = math.inf) -> list[tuple[str, np.ndarray]]:
    """Which rows of ``states`` (and of the filter histories ``ring``) the stepper could never have made.

    For validating a restored state as strictly as a fresh one
    (:func:`mudforce.steppers.contact.check_states` words the error).

    Parameters
    ----------
    states : ndarray, shape (n, N_STATE)
        State rows.
    ring : ndarray, shape (n, 0 or N_RING)
        The velocity filter's histories.
    max_depth : float
        Largest ``|z_i|`` a state may hold [m].
    max_speed : float
        Largest velocity a state may hold [m/s] (the foot's estimate and the mud's at necking): the stepper's
        whole depth range in its shortest step.
    max_time : float
        Latest time a state may hold [s] (a recording's bound on a time).

    Returns
    -------
    list of (str, ndarray of bool)
        Each check's message and its per-row failure mask, in the order they are checked.
    """
    started, mode, direction = states[:, S_STARTED], states[:, S_MODE], states[:, S_DIRECTION]
    decays = states[:, [S_CACHE_DECAY_I, S_CACHE_DECAY_W]]
    checks = [
        ("holds a value that is not finite", ~np.isfinite(states).all(axis=1) | ~np.isfinite(ring).all(axis=1)),
        ("started is not 0 or 1", ~np.isin(started, (0.0, 1.0))),
        ("mode is not 0 (FREE), 1 (CONTACT) or 2 (NECKED)", ~np.isin(mode, (0.0, 1.0, 2.0))),
        ("direction is not -1, 0 or 1", ~np.isin(direction, (-1.0, 0.0, 1.0))),
        ("time is negative", states[:, S_TIME] < 0.0),
        (f"time is beyond {max_time:g} s", states[:, S_TIME] > max_time),
        (f"depth is beyond +-{max_depth:g} m", np.abs(states[:, S_DEPTH]) > max_depth),
        # z_i - z_m: the mud relaxes toward depths within +-max_depth, so the strain stays within twice that
        (f"Maxwell strain is beyond +-{2.0 * max_depth:g} m", np.abs(states[:, S_STRAIN]) > 2.0 * max_depth),
        (f"a velocity is beyond +-{max_speed:g} m/s",
         (np.abs(states[:, S_VELOCITY]) > max_speed) | (np.abs(states[:, S_NECK_V]) > max_speed)),
        # Eq. (7)'s normalised response: |g| <= 1 (the mass-spring-damper's energy only decays from g(0) = 1) and
        # |G| <= the age (the integral of g); a margin for rounding
        ("the neck's filter state is beyond its response (|g| <= 1, |G| <= the neck's age)",
         (np.abs(states[:, S_NECK_G]) > 1.0 + 1e-9)
         | (np.abs(states[:, S_NECK_GI]) > states[:, S_NECK_AGE] * (1.0 + 1e-6) + 1e-12)),
        ("neck age is negative", states[:, S_NECK_AGE] < 0.0),
        ("cached decays are outside [0, 1]", ((decays < 0.0) | (decays > 1.0)).any(axis=1)),
    ]
    if ring.shape[1]:
        count, head = ring[:, R_N], ring[:, R_HEAD]
        checks.append(("filter history is corrupt", (count != np.round(count)) | (count < 0) | (count > RING)
                       | (head != np.round(head)) | (head < 0) | (head >= RING)))
    return checks


def state_of(row: np.ndarray) -> State:
    """One state row (1-D) as a :class:`State` (Python; compiled code uses :func:`load_state`)."""
    return State(float(row[S_STARTED]), int(row[S_MODE]), *(float(x) for x in row[S_TIME:N_CORE]))


def params_of(row: np.ndarray) -> Params:
    """One params row (1-D) as :class:`Params` (Python; compiled code uses :func:`load_params`)."""
    return Params(*(float(x) for x in row[:N_PARAMS]))


@_compiled(inline="always")
def load_state(states: np.ndarray, j: int) -> State:
    """Row ``j`` of ``states`` as a :class:`State`."""
    r = states[j]
    return State(r[0], int(r[1]), r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12])


@_compiled(inline="always")
def state_from_row(r: np.ndarray) -> State:
    """One state row (1-D) as a :class:`State`, in compiled code (:func:`state_of` in Python)."""
    return State(r[0], int(r[1]), r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12])


@_compiled(inline="always")
def params_from_row(r: np.ndarray) -> Params:
    """One params row (1-D) as :class:`Params`, in compiled code (:func:`params_of` in Python)."""
    return Params(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12], r[13], r[14],
                  r[15], r[16], r[17])


@_compiled(inline="always")
def forget_row_cache(states: np.ndarray, j: int) -> None:
    """:func:`forget_cache` of row ``j`` only, in compiled code."""
    states[j, S_CACHE_DT] = -1.0


@_compiled(inline="always")
def store_state(states: np.ndarray, j: int, s: State) -> None:
    """Write ``s`` to row ``j`` of ``states``."""
    r = states[j]
    r[0] = s.started
    r[1] = float(s.mode)
    r[2] = s.time
    r[3] = s.depth
    r[4] = s.mud
    r[5] = s.neck_age
    r[6] = s.neck_v
    r[7] = s.neck_z
    r[8] = s.direction
    r[9] = s.velocity
    r[10] = s.neck_g
    r[11] = s.neck_gi
    r[12] = s.strain


@_compiled(inline="always")
def load_cache(states: np.ndarray, j: int) -> Cache:
    """The step-length cache of row ``j`` of ``states``."""
    r = states[j]
    return Cache(r[13], r[14], r[15], r[16], r[17], r[18], r[19])


@_compiled(inline="always")
def store_cache(states: np.ndarray, j: int, c: Cache) -> None:
    """Write the step-length cache ``c`` to row ``j`` of ``states``."""
    r = states[j]
    r[13] = c.dt
    r[14] = c.decay_i
    r[15] = c.decay_w
    r[16] = c.phi0
    r[17] = c.phi1
    r[18] = c.phi2
    r[19] = c.phi3


@_compiled(inline="always")
def load_params(params: np.ndarray, j: int) -> Params:
    """Row ``j`` of ``params`` as :class:`Params`."""
    r = params[j]
    return Params(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12], r[13], r[14],
                  r[15], r[16], r[17])
