"""Streaming: one foot, one sample at a time, for a control loop."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from mudforce import _kernel as K
from mudforce._kernel.bounds import MAX_DEPTH, MIN_DT
from mudforce._kernel.layout import S_CACHE_DT, STATE_NAMES, store_cache
from mudforce._kernel.transitions import step_cache
from mudforce.errors import InputError, real_array, real_number
from mudforce.model.bounds import MAX_TIME, check_step
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.velocity import VelocityFilter, resolve_velocity_filter

__all__ = ["ContactSample", "ContactState", "MudContact", "check_states"]


def check_states(states: np.ndarray, ring: np.ndarray, what: str = "a contact state", unit: str = "foot") -> None:
    """Refuse state rows (and filter histories) that the stepper never makes: restored states are
    validated as strictly as fresh ones.

    Parameters
    ----------
    states : ndarray, shape (n, N_STATE)
        Rows of :mod:`mudforce._kernel`'s state layout.
    ring : ndarray, shape (n, 0 or N_RING)
        The velocity filter's histories.
    what : str
        For the message.
    unit : str
        What a row is, for the message ("foot"; "element" for a 3-D contact's elements).

    Raises
    ------
    InputError
        Naming the first bad row and field: a non-finite value, ``started``
        not 0 or 1, a mode not 0, 1, 2, a direction not -1, 0, 1, a negative
        time or neck age, a depth beyond +-100 m, a Maxwell strain beyond +-200 m, a velocity beyond 200 m in
        1 ns, Eq. (7)'s filter state beyond its response, cached decays outside [0, 1],
        a filter history whose count or head is not a valid index.
    """
    checks = K.invalid_rows(states, ring, MAX_DEPTH, 2.0 * MAX_DEPTH / MIN_DT, MAX_TIME)
    for message, bad in checks:
        rows = np.flatnonzero(bad)
        if rows.size:
            where = f"{what} ({unit} {rows[0]})" if states.shape[0] > 1 else what
            raise InputError(f"{where}: {message}; expected a state taken from a contact")


def _recompute_caches(states: np.ndarray, params: np.ndarray) -> None:
    """Each state row's step-length cache recomputed, by the stepper's own code, for the step length ``dt`` [s] it
    holds, with its row of ``params`` (rows without a cache are left so); what a restored state needs.

    A replay is then the same bits: the stepper reuses a cache within 1e-9 of its step length, so a cache dropped
    instead was recomputed for the next step's length, which may differ from the cached one in the last bits (and
    so did the forces after it, by ~1e-9 relative); and cached decays edited within [0, 1] are recomputed, not used
    as given. Once per distinct parameter row and length.
    """
    rows = np.flatnonzero(states[:, S_CACHE_DT] > 0.0)  # finite: checked (check_states)
    if not rows.size:
        return
    keys = np.ascontiguousarray(np.hstack((params[rows], states[rows, S_CACHE_DT : S_CACHE_DT + 1])))
    rowwise = keys.view(np.dtype((np.void, keys.itemsize * keys.shape[1]))).ravel()  # each row's bytes, one key
    _, first, where = np.unique(rowwise, return_index=True, return_inverse=True)
    caches = np.zeros((first.size, K.N_STATE), dtype=np.float64)
    none = K.Cache(-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    table = np.ascontiguousarray(keys[first, :-1])
    for k in range(first.size):
        store_cache(caches, k, step_cache(none, K.load_params(table, k), float(keys[first[k], -1])))
    states[rows, S_CACHE_DT:] = caches[where.reshape(-1), S_CACHE_DT:]


def _restore_rows(states: np.ndarray, ring: np.ndarray, params: np.ndarray, saved: np.ndarray) -> None:
    """Write a checked state ``saved`` (its state columns, then its ring's) into ``states`` and ``ring``, and
    recompute their step-length caches (:func:`_recompute_caches`): every stepper's restore, after its checks."""
    states[:] = saved[:, :K.N_STATE]
    ring[:] = saved[:, K.N_STATE:]
    _recompute_caches(states, params)


class ContactSample(NamedTuple):
    """Everything the last step computed (units as in :class:`SimulationResult`)."""

    force: float  #: total force [N], positive up
    f_e1: float  #: visco-elastic stress [Pa], Eq. (2)
    f_e2: float  #: nonlinear-spring stress [Pa], Eq. (4)
    f_s: float  #: drag stress [Pa], Eq. (5)
    mud_displacement: float  #: z_m [m]
    mud_velocity: float  #: dz_m/dt [m/s]
    velocity: float  #: branch velocity estimate [m/s]
    state: str  #: "FREE", "CONTACT" or "NECKED"
    necked: bool  #: True if the neck broke during this step


@dataclass(frozen=True, eq=False)
class ContactState:
    """A snapshot of one foot's contact state, for save and restore in rollouts.

    Read it from :attr:`MudContact.state` and assign it back to restore.
    The snapshot is a copy: later steps do not change it.
    """

    #: the state row of :mod:`mudforce._kernel`
    data: np.ndarray
    #: the params row the snapshot was taken with (keeps the step-length cache valid on restore)
    params_key: bytes = b""
    #: the velocity filter's recent samples (empty for the exact filter, which keeps none)
    ring: np.ndarray = field(default_factory=lambda: np.empty(0))

    def __post_init__(self) -> None:
        arr = np.array(real_array(self.data, "a contact state", "SI"))  # always private copies
        if arr.shape != (K.N_STATE,):
            raise InputError(f"a contact state has {K.N_STATE} values, got shape {arr.shape}")
        ring = np.array(real_array(self.ring, "a contact state's filter history", "SI")).ravel()
        if ring.size not in (0, K.N_RING):
            raise InputError(f"a contact state's filter history has 0 or {K.N_RING} values, got {ring.size}")
        if not isinstance(self.params_key, bytes):
            raise InputError(f"params_key must be bytes, got {type(self.params_key).__name__}")
        check_states(arr[None, :], ring[None, :])
        arr.setflags(write=False)
        ring.setflags(write=False)
        object.__setattr__(self, "data", arr)
        object.__setattr__(self, "ring", ring)

    @property
    def started(self) -> bool:
        """False before the first sample."""
        return bool(K.state_column(self.data, "started"))

    @property
    def mode(self) -> str:
        """``"FREE"``, ``"CONTACT"`` or ``"NECKED"``."""
        return STATE_NAMES[int(K.state_column(self.data, "mode"))]

    @property
    def time(self) -> float:
        """Time since the first sample [s]."""
        return float(K.state_column(self.data, "time"))

    @property
    def depth(self) -> float:
        """Foot depth at the last sample [m]."""
        return float(K.state_column(self.data, "depth"))

    @property
    def mud_displacement(self) -> float:
        """Mud displacement ``z_m`` at the last sample [m]."""
        return float(K.state_column(self.data, "mud"))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ContactState):
            return NotImplemented
        # the step-length cache is not state
        same = np.array_equal(K.state_core(self.data), K.state_core(other.data))
        return bool(same) and np.array_equal(self.ring, other.ring)

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (
            f"ContactState(mode={self.mode!r}, time={self.time:g} s, depth={self.depth:g} m, "
            f"mud_displacement={self.mud_displacement:g} m)"
        )


class MudContact:
    """The mud force on one foot, stepped one sample at a time.

    Runs the same compiled stepper as :func:`mudforce.simulate`, so feeding
    it a trajectory's samples gives exactly the batch result.

    Parameters
    ----------
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry; the paper's 51 x 38 mm cuboid by default.
    velocity_filter : "exact" or VelocityFilter
        Branch-velocity filter. A stream cannot look ahead to estimate its
        noise, so the default is the paper's exact rule; for measured depth
        pass ``noise_std`` or a :class:`VelocityFilter`.
    noise_std : float, optional
        Depth noise [m]; with ``dt``, builds ``VelocityFilter.for_noise(noise_std, dt)``.
    dt : float, optional
        Nominal time step [s], needed with ``noise_std`` (and refused without it).

    Examples
    --------
    >>> from mudforce import MudContact, MudParameters
    >>> contact = MudContact(MudParameters.from_water_content(0.25))
    >>> contact.step(0.0, 0.01)   # first sample: sets the initial state
    0.0
    >>> round(contact.step(0.0001, 0.01), 3) > 0
    True
    """

    def __init__(
        self,
        params: MudParameters,
        foot: Foot | None = None,
        *,
        velocity_filter: VelocityFilter | str = "exact",
        noise_std: float | None = None,
        dt: float | None = None,
    ) -> None:
        self.params = params
        self.foot = Foot.paper() if foot is None else foot
        if noise_std is not None:
            if dt is None:
                raise InputError("noise_std needs the nominal time step dt [s]")
            if not (isinstance(velocity_filter, str) and velocity_filter == "exact"):  # not the default
                raise InputError("give velocity_filter or noise_std (with dt), not both: noise_std builds the filter")
            velocity_filter = VelocityFilter.for_noise(noise_std, dt)
        elif dt is not None:
            raise InputError("dt is the nominal time step for noise_std; give noise_std too, or leave dt out")
        self.velocity_filter = resolve_velocity_filter(velocity_filter)
        self._params = K.params_row(params, self.foot, self.velocity_filter)
        self._buf = K.new_stream_buffer(self._params)
        # views into the one buffer the compiled step sees
        self._states, _, self._out, self._ring = K.stream_parts(self._buf)
        self._clear_last()
        self._step = K.stream_step

    def _clear_last(self) -> None:
        """:attr:`last` as before any step: zeros, and no neck (a step writes NaN for none)."""
        self._out[:] = 0.0
        K.outputs(self._out).neck_offset[:] = np.nan

    def step(self, depth: float, dt: float) -> float:
        """Advance to the next depth sample and return the force [N].

        Parameters
        ----------
        depth : float
            Foot depth below the surface [m], positive down, within +-100 m
            (:data:`mudforce.steppers.simulation.MAX_DEPTH`).
        dt : float
            Time since the previous sample [s], within [1e-9, 1e3]
            (:data:`~mudforce.steppers.simulation.MIN_DT`: shorter steps would let
            ``dz/dt`` and the drag overflow); ignored on the first call,
            which sets the initial sample.

        Raises
        ------
        InputError
            For a depth or step out of range or not a number; the state
            is then exactly as it was.
        """
        if type(depth) is not float or type(dt) is not float:
            depth, dt = real_number(depth, "depth"), real_number(dt, "dt")
        # the compiled step refuses (NaN, state unchanged) a depth or a step out of bounds: no check here
        # on the 0.2 us path; a NaN force is then told apart from a refusal below
        force: float = self._step(self._buf, depth, dt)
        if force != force:
            self._refuse(depth, dt)
        return force

    def _refuse(self, depth: float, dt: float) -> None:
        """Raise for a bad depth or step (a step's length is ignored on the first call); else return."""
        if not (math.isfinite(depth) and abs(depth) <= MAX_DEPTH):
            raise InputError(f"depth must be finite and within [-{MAX_DEPTH:g}, {MAX_DEPTH:g}] m, got {depth!r}")
        if K.state_column(self._states, "started")[0] != 0.0:
            check_step(dt)

    @property
    def last(self) -> ContactSample:
        """The components of the last step."""
        out = K.outputs(self._out[:, 0])
        return ContactSample(
            force=float(out.force),
            f_e1=float(out.f_e1),
            f_e2=float(out.f_e2),
            f_s=float(out.f_s),
            mud_displacement=float(out.mud),
            mud_velocity=float(out.mud_velocity),
            velocity=float(out.velocity),
            state=STATE_NAMES[int(out.state)],
            necked=bool(np.isfinite(out.neck_offset)),
        )

    def reset(self) -> None:
        """Forget the history: the next call to :meth:`step` sets the initial sample, and :attr:`last` is as
        before any step."""
        self._states[:] = K.new_states(1)
        self._ring[:] = 0.0  # the filter's old samples too: the state is then a fresh contact's, bit for bit
        self._clear_last()

    @property
    def state(self) -> ContactState:
        """A snapshot of the contact state; assign one back to restore it."""
        return ContactState(self._states[0], self._params.tobytes(), self._ring[0])

    @state.setter
    def state(self, value: ContactState) -> None:
        if not isinstance(value, ContactState):
            raise InputError(f"state must be a ContactState (from MudContact.state), got {type(value).__name__}")
        if self._ring.size:
            if value.ring.size != self._ring.size:
                raise InputError("this contact's velocity filter needs the history of one with a window > 1; "
                                 "the state was taken with the exact filter")
            self._ring[0] = value.ring
        elif value.ring.size:  # as MudContacts refuses it: its history was dropped, and the state read back differed
            raise InputError("this contact's exact velocity rule keeps no history; the state was taken with a "
                             "velocity filter (a window > 1): restore it into a contact with that filter")
        self._states[0] = value.data
        _recompute_caches(self._states, self._params[None, :])  # this contact's parameters; a replay: same bits

    def __repr__(self) -> str:
        return f"MudContact({self.params.source!r}, foot={self.foot.shape!r}, state={self.state.mode})"
