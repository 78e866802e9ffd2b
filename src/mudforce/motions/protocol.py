"""Prescribed foot motions as typed steps: intrude, hold, withdraw.

A :class:`Protocol` is a start depth, a list of steps and a sampling rate.
Its samples are at exactly ``t_k = k / rate`` and its depth is piecewise
linear between the steps' breakpoints. A protocol is bounded by what
:func:`mudforce.simulate` accepts, so that its samples are always
simulated: depths within +-100 m (:data:`~mudforce.steppers.simulation.MAX_DEPTH`),
a rate within [:data:`MIN_RATE`, :data:`MAX_RATE`], at most
:data:`MAX_SAMPLES` samples, none after 1e9 s
(:data:`~mudforce.steppers.simulation.MAX_TIME`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Union

import numpy as np

from mudforce._kernel.bounds import MAX_DT, MAX_TIME
from mudforce.errors import InputError, finite_number, positive_number
from mudforce.model.bounds import bounded_depth

if TYPE_CHECKING:
    from mudforce.model.foot import Foot
    from mudforce.model.parameters import MudParameters
    from mudforce.steppers.simulation import SimulationResult

__all__ = ["MAX_RATE", "MAX_SAMPLES", "MIN_RATE", "Hold", "Intrude", "Protocol", "Step", "Withdraw"]

#: Largest number of samples a protocol may produce [-] (memory guard: ~1 GB of a simulation's arrays).
MAX_SAMPLES = 10_000_000
#: Lowest sampling rate [Hz]: one sample per :data:`~mudforce.steppers.simulation.MAX_DT` (1000 s).
MIN_RATE = 1.0 / MAX_DT
#: Highest sampling rate [Hz]: 100 MHz. Not 1 GHz (1 / ``MIN_DT``): samples at ``k / rate`` carry rounding
#: of ~1e-9 relative in their steps, which at 1 GHz would fall just under simulate()'s 1 ns.
MAX_RATE = 1e8


@dataclass(frozen=True)
class Intrude:
    """Move down at constant speed to an absolute depth.

    Parameters
    ----------
    velocity : float
        Speed, > 0 [m/s].
    depth : float
        Target depth below the surface [m]; must be deeper than where the step starts.
    """

    velocity: float
    depth: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "velocity", positive_number(self.velocity, "intrusion velocity", "m/s"))
        object.__setattr__(self, "depth", bounded_depth(self.depth, "intrusion depth"))


@dataclass(frozen=True)
class Hold:
    """Keep the foot still.

    Parameters
    ----------
    duration : float
        Hold time, > 0 [s].
    """

    duration: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "duration", positive_number(self.duration, "hold duration", "s"))


@dataclass(frozen=True)
class Withdraw:
    """Move up at constant speed until the foot is ``rise`` above the surface.

    Parameters
    ----------
    velocity : float
        Speed, > 0 [m/s].
    rise : float
        Final height of the foot's bottom above the surface, >= 0 [m]
        (the final depth is ``-rise``).
    """

    velocity: float
    rise: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "velocity", positive_number(self.velocity, "withdrawal velocity", "m/s"))
        object.__setattr__(self, "rise", bounded_depth(self.rise, "withdrawal rise"))
        if self.rise < 0.0:
            raise InputError(f"withdrawal rise must be >= 0 [m], got {self.rise!r}")


Step = Union[Intrude, Hold, Withdraw]


@dataclass(frozen=True)
class Protocol:
    """A sampled, piecewise-linear foot motion.

    Parameters
    ----------
    steps : tuple of Intrude, Hold, Withdraw
        The motion, in order.
    rate : float
        Sampling rate [Hz]; samples are at ``k / rate`` [s]; within
        [:data:`MIN_RATE`, :data:`MAX_RATE`] (1e-3 Hz to 1e8 Hz).
    start_depth : float
        Depth at ``t = 0`` [m]; negative is above the surface; within +-100 m.

    Raises
    ------
    InputError
        For a motion :func:`mudforce.simulate` would refuse (a depth beyond
        +-100 m, a rate outside the range, a sample after 1e9 s), more
        than :data:`MAX_SAMPLES` samples, or a rate whose sample interval is
        longer than an intrusion or withdrawal step (whose corners the
        sampled path would cut).
    """

    steps: tuple[Step, ...]
    rate: float = 100.0
    start_depth: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.steps, (str, bytes)) or not isinstance(self.steps, Iterable):  # tuple(5): a TypeError
            raise InputError(f"steps must be a sequence of Intrude, Hold and Withdraw, got {type(self.steps).__name__}")
        object.__setattr__(self, "steps", tuple(self.steps))
        rate = positive_number(self.rate, "sampling rate", "Hz")
        if not MIN_RATE <= rate <= MAX_RATE:
            raise InputError(f"sampling rate must be within [{MIN_RATE:g}, {MAX_RATE:g}] Hz (steps simulate() "
                             f"accepts), got {self.rate!r}")
        object.__setattr__(self, "rate", rate)
        # + 0.0: a start depth of -0.0 sampled as -0.0 until the first step moved, which a CSV wrote as '-0'
        object.__setattr__(self, "start_depth", bounded_depth(self.start_depth, "start depth") + 0.0)
        if not self.steps:
            raise InputError("a protocol needs at least one step (Intrude, Hold or Withdraw)")
        bt, _ = self.breakpoints()  # validates the sequence
        # a moving step shorter than a sample interval is cut by the sampled path, which the model then simulates
        # instead: simulate --rate 0.001Hz sampled the paper's protocol at 0 and 1000 s, a foot that never entered
        # (peak force 0 N, exit 0)
        lengths = np.diff(bt)
        moving = [i for i, st in enumerate(self.steps) if not isinstance(st, Hold)]
        if moving:
            i = min(moving, key=lambda k: lengths[k])
            if lengths[i] * self.rate < 1.0:
                raise InputError(f"sampling rate {self.rate:g} Hz samples every {1.0 / self.rate:.4g} s, longer than "
                                 f"step {i + 1} ({type(self.steps[i]).__name__}, {lengths[i]:.4g} s), which the "
                                 f"samples would cut; expected a rate of at least {1.0 / lengths[i]:.4g} Hz")
        n = self._samples(float(bt[-1]))
        if not n <= MAX_SAMPLES:
            raise InputError(f"sampling rate: {self.rate:g} Hz over the {float(bt[-1]):.4g} s motion is {n:.3g} "
                             f"samples, more than {MAX_SAMPLES:,}; lower the rate or shorten the motion")
        if not (n - 1) / self.rate <= MAX_TIME:
            raise InputError(f"the motion lasts {float(bt[-1]):.4g} s, its last sample beyond simulate()'s "
                             f"{MAX_TIME:g} s; shorten the holds or raise the speeds")

    def _samples(self, duration: float) -> float:
        """Number of samples covering ``duration`` [s] (a float: it may be huge or infinite before the check)."""
        return float(math.ceil(duration * self.rate - 1e-9) + 1) if math.isfinite(duration * self.rate) else math.inf

    @classmethod
    def paper(
        cls,
        depth: float = 0.02,
        velocity: float = 0.01,
        hold: float = 6.0,
        rise: float = 0.02,
        rate: float = 100.0,
        approach: float = 0.0,
    ) -> Protocol:
        """The paper's experiment (Section II-A), with the project's defaults.

        Intrude to ``depth`` [m] at ``velocity`` [m/s], hold for ``hold`` [s],
        withdraw at the same speed until ``rise`` [m] above the surface,
        sampled at ``rate`` [Hz]. ``approach`` [m] starts the foot that far
        above the surface (0: at the surface).
        """
        approach = finite_number(approach, "approach height", "m", nonnegative=True)  # True is no 1 m
        return cls(
            (Intrude(velocity, depth), Hold(hold), Withdraw(velocity, rise)),
            rate=rate,
            start_depth=-approach if approach > 0.0 else 0.0,
        )

    def breakpoints(self) -> tuple[np.ndarray, np.ndarray]:
        """Times [s] and depths [m] of the corners of the motion."""
        times = [0.0]
        depths = [self.start_depth]
        for i, st in enumerate(self.steps):
            here = depths[-1]
            if isinstance(st, Intrude):
                if st.depth <= here:
                    raise InputError(
                        f"step {i + 1} (Intrude to {st.depth:g} m) must go deeper than {here:g} m"
                    )
                times.append(times[-1] + (st.depth - here) / st.velocity)
                depths.append(st.depth)
            elif isinstance(st, Hold):
                times.append(times[-1] + st.duration)
                depths.append(here)
            elif isinstance(st, Withdraw):
                target = 0.0 - st.rise  # not -rise: a zero rise ends at 0, not at -0.0
                if target >= here:
                    raise InputError(
                        f"step {i + 1} (Withdraw to {st.rise:g} m above the surface) must go up from {here:g} m"
                    )
                times.append(times[-1] + (here - target) / st.velocity)
                depths.append(target)
            else:
                raise InputError(f"step {i + 1} is {st!r}; expected Intrude, Hold or Withdraw")
        return np.array(times), np.array(depths)

    @property
    def duration(self) -> float:
        """Total time of the motion [s]."""
        return float(self.breakpoints()[0][-1])

    def sample(self) -> tuple[np.ndarray, np.ndarray]:
        """Sample times ``k / rate`` [s] and depths [m], covering the whole motion.

        The last sample is the first grid point at or after the end of the
        motion (the foot stays at its final depth).
        """
        bt, bz = self.breakpoints()
        n = int(self._samples(float(bt[-1])))  # at most MAX_SAMPLES (checked on construction)
        time = np.arange(n, dtype=np.float64) / self.rate
        depth = np.interp(time, bt, bz)
        return time, depth

    def simulate(self, params: MudParameters, foot: Foot | None = None) -> SimulationResult:
        """Sample the motion and run :func:`mudforce.simulate` on it."""
        from mudforce.steppers.simulation import simulate

        time, depth = self.sample()
        return simulate(time, depth, params, foot)
