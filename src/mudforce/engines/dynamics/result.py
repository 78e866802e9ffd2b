"""What a simulated foot did: :class:`FootResult`, and the phase codes of the coupled foot (:class:`Phase`).

The phases are those of the hybrid system of :mod:`mudforce.engines.dynamics`: a
foot out of the mud (FREE), sinking on the intrusion branch (INTRUSION),
rising on the withdrawal branch (WITHDRAWAL), held at rest inside the rest
band (STUCK), or rising after the neck broke (NECKED, Eqs. (7), (9)). They
are not the contact states of the stepper (:mod:`mudforce._kernel`'s FREE,
CONTACT, NECKED), which know nothing of the foot's mass.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any

import numpy as np

from mudforce.errors import finite_number

__all__ = ["GRAVITY", "PHASE_NAMES", "REST_SPEED", "FootResult", "Phase", "check_path"]

#: Standard gravity [m/s^2] (MuJoCo's default ``0 0 -9.81``).
GRAVITY = 9.81

#: Speed [m/s] at or below which a foot counts as at rest (MuJoCo's ``STICK_VELOCITY``; the built-in engine's
#: stuck foot has speed exactly 0).
REST_SPEED = 1e-4


class Phase(IntEnum):
    """Phase of a foot coupled with the mud; the codes stored in :attr:`FootResult.phase`."""

    #: Out of the mud, no force.
    FREE = 0
    #: Moving down, on the intrusion branch (Eqs. (2)-(5) with ``k_m_i, b_m_i``).
    INTRUSION = 1
    #: Moving up, on the withdrawal branch (Eqs. (2), (3), (5) with ``k_m_w, b_m_w``).
    WITHDRAWAL = 2
    #: At rest inside the rest band; the force is the load carried.
    STUCK = 3
    #: Moving up after necking (Eq. (9)): the post-necking force, Eq. (7).
    NECKED = 4


#: Phase names, indexed by the codes in :attr:`FootResult.phase` (the ``state`` column of the CSV).
PHASE_NAMES: tuple[str, ...] = tuple(p.name for p in Phase)


@dataclass(frozen=True, eq=False)
class FootResult:
    """A simulated foot in mud: one entry per output sample.

    Attributes
    ----------
    time : ndarray
        Sample times [s].
    depth : ndarray
        Foot depth ``z_i`` [m], positive down.
    velocity : ndarray
        Foot velocity ``dz_i/dt`` [m/s], positive down.
    force : ndarray
        Mud force on the foot [N], positive up (while STUCK: the load carried).
    phase : ndarray of int8
        :class:`Phase` codes (names in :data:`PHASE_NAMES`): FREE, INTRUSION, WITHDRAWAL, STUCK, NECKED.
    mass : float
        Foot mass [kg].
    gravity : float
        Gravity [m/s^2].
    engine : str
        ``"builtin"``, ``"mujoco"`` or ``"mjx"``.
    events : int
        Number of located events (builtin engine; 0 otherwise).
    strain : ndarray
        Maxwell strain ``z_i - z_m`` [m] (NaN where an engine does not report it).
    """

    time: np.ndarray
    depth: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    phase: np.ndarray
    mass: float
    gravity: float = GRAVITY
    engine: str = "builtin"
    events: int = 0
    strain: np.ndarray = field(default_factory=lambda: np.empty(0))

    @property
    def phase_names(self) -> list[str]:
        """Each sample's phase as a name."""
        return [PHASE_NAMES[int(c)] for c in self.phase]

    @property
    def at_rest(self) -> bool:
        """Whether the foot is at rest in the mud at the last sample: STUCK, speed at most :data:`REST_SPEED`."""
        return int(self.phase[-1]) == Phase.STUCK and abs(float(self.velocity[-1])) <= REST_SPEED

    @property
    def end_depth(self) -> float:
        """Depth at the last sample [m], whether or not the foot is at rest there."""
        return float(self.depth[-1])

    @property
    def rest_depth(self) -> float:
        """Depth where the foot rests at the last sample [m]; NaN if it is still moving there (:attr:`at_rest`).

        Use :attr:`end_depth` for the last sample's depth in any case.
        """
        return float(self.depth[-1]) if self.at_rest else float("nan")

    def force_std(self, last: float = 1.0) -> float:
        """Standard deviation of the force over the last ``last`` seconds [N] (``last`` > 0 [s])."""
        last = finite_number(last, "last", "s", positive=True)
        sel = self.time >= self.time[-1] - last - 1e-12
        return float(np.std(self.force[sel]))

    def columns(self) -> dict[str, Any]:
        """The per-sample data under the names of :meth:`to_csv`: ``time_s, depth_m, velocity_m_s, force_N, state``."""
        return {"time_s": self.time, "depth_m": self.depth, "velocity_m_s": self.velocity, "force_N": self.force,
                "state": np.array(self.phase_names, dtype=object)}

    def to_pandas(self) -> Any:
        """A :class:`pandas.DataFrame` with the columns of :meth:`to_csv` (needs pandas)."""
        from mudforce.io.results import to_pandas

        return to_pandas(self.columns())

    def to_csv(self, path: str | os.PathLike[str]) -> None:
        """Write ``time_s, depth_m, velocity_m_s, force_N, state`` as CSV, atomically."""
        from mudforce.io import atomic_open

        check_path(path, "path")
        names = self.phase_names
        with atomic_open(path, "w") as handle:
            handle.write("time_s,depth_m,velocity_m_s,force_N,state\n")
            for i in range(self.time.size):
                handle.write(f"{self.time[i]:.9g},{self.depth[i] + 0.0:.12g},{self.velocity[i] + 0.0:.12g},"
                             f"{self.force[i]:.12g},{names[i]}\n")

    def plot(self, path: str | os.PathLike[str] | None = None, *, title: str | None = None) -> Any:
        """Depth, velocity and force over time, phases shaded (needs matplotlib); saved as PNG if ``path``.

        See :func:`mudforce.engines.dynamics.plots.plot_foot_result`.
        """
        from mudforce.engines.dynamics.plots import plot_foot_result

        if path is not None:
            check_path(path, "path")
        return plot_foot_result(self, path, title=title)


def check_path(path: Any, name: str) -> None:
    """InputError unless ``path`` is a ``str`` or ``os.PathLike`` (a file to write)."""
    if not isinstance(path, (str, os.PathLike)):
        from mudforce.errors import InputError

        raise InputError(f"{name} must be a file path (str or os.PathLike), got {type(path).__name__}")
