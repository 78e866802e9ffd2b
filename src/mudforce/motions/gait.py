"""Robot-like foot motions and walks on mud, for testing estimation and tracking.

The lab protocol of the paper (intrude, hold, withdraw) is not what a legged
robot's foot does. :func:`gait` makes the depth trajectory of a foot that
walks: each step cycle is a swing above the surface, a touchdown at some
speed to some depth, a stance with sway, sometimes a partial withdrawal and
a re-push at another speed, and a lift-off back to the swing height. Every
random choice is drawn from a seeded generator, so the same seed gives the
same trajectory, bit for bit.

:func:`walk` simulates the mud force along such a gait, exactly, with
sensor imperfections (white force and depth noise, a constant force bias)
and optionally mud that changes partway: the terrain switches to the next
water content at the first swing (foot above the surface) after each
change time, as when a robot walks from one patch of mud onto another.

The depth is piecewise linear between the motion's breakpoints plus a
smooth sway during stance (zero at the stance's ends), sampled at
``rate`` with optional time-stamp jitter.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mudforce.errors import InputError, number_within, real_array, seed_int, true_or_false
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters

__all__ = ["Gait", "Walk", "gait", "walk"]

# Ranges of the random choices (SI). Chosen to cover what a small legged
# robot's foot does on soft ground: touchdown and lift-off at 1-6 cm/s,
# stance sinkage of 1-3 cm, stances of about a second or two.
_SWING_HEIGHT = (0.005, 0.02)  # [m] apex above the surface
_SWING_TIME = (0.3, 0.8)  # [s] half a swing (apex to touchdown start)
_TOUCHDOWN_SPEED = (0.01, 0.06)  # [m/s]
_STANCE_DEPTH = (0.01, 0.03)  # [m]
_STANCE_TIME = (1.0, 3.0)  # [s]
_SWAY_AMPLITUDE = (0.0, 0.0015)  # [m]
_SWAY_FREQUENCY = (0.5, 2.0)  # [Hz]
_REPUSH_PROBABILITY = 0.5
_REPUSH_RISE = (0.003, 0.008)  # [m] partial withdrawal before a re-push
_LIFT_SPEED = (0.015, 0.06)  # [m/s]


@dataclass(frozen=True)
class Gait:
    """A foot's depth trajectory made by :func:`gait`.

    Attributes
    ----------
    time : numpy.ndarray
        Sample times [s], strictly increasing, starting at 0.
    depth : numpy.ndarray
        Foot depth below the undisturbed surface [m], positive down (exact, noise-free).
    swings : tuple of float
        Times [s] of each swing apex (foot above the surface, the mud left
        behind): the boundaries between step cycles, where :func:`walk`
        may change the mud.
    """

    time: np.ndarray
    depth: np.ndarray
    swings: tuple[float, ...]


def gait(
    seed: int = 0,
    *,
    duration: float = 25.0,
    rate: float = 100.0,
    jitter: float = 0.0,
    start_below: bool = False,
) -> Gait:
    """The depth of a foot stepping on mud: touchdowns, stances with sway, re-pushes, lift-offs.

    Parameters
    ----------
    seed : int
        Seed of every random choice, in [0, 2^32 - 1]; the same seed gives the same gait.
    duration : float
        Length of the trajectory [s], within [1, 3600].
    rate : float
        Mean sampling rate [Hz], within [10, 1e5].
    jitter : float
        Time-stamp jitter as a fraction of the sample period [-], within
        [0, 0.4]: each time stamp moves by a uniform draw of at most this.
    start_below : bool
        Start in stance, below the surface (the mud relaxed around the
        foot), instead of at a swing apex above it.

    Returns
    -------
    Gait
        Times [s], depths [m] and the swing apexes [s].
    """
    seed = seed_int(seed, "seed")  # every seed's bound: [0, 2^32 - 1] (2**70 was taken here alone)
    duration = number_within(duration, "duration", 1.0, 3600.0, "s")
    rate = number_within(rate, "rate", 10.0, 1e5, "Hz")
    jitter = number_within(jitter, "jitter", 0.0, 0.4, "of a sample period")
    start_below = true_or_false(start_below, "start_below")
    rng = np.random.default_rng(seed)

    def draw(bounds: tuple[float, float]) -> float:
        return float(rng.uniform(*bounds))

    # breakpoints of the piecewise-linear part, and the stances' sway
    times: list[float] = [0.0]
    depths: list[float] = []
    sways: list[tuple[float, float, float, int]] = []  # (start, end, amplitude, half-periods)
    swings: list[float] = []
    t = 0.0
    if start_below:
        depths.append(draw(_STANCE_DEPTH))
    else:
        depths.append(-draw(_SWING_HEIGHT))
        swings.append(0.0)

    def move_to(target: float, speed: float) -> None:
        nonlocal t
        t += abs(target - depths[-1]) / speed
        times.append(t)
        depths.append(target)

    def stance() -> None:
        nonlocal t
        length = draw(_STANCE_TIME)
        amplitude = draw(_SWAY_AMPLITUDE)
        half_periods = max(1, round(2.0 * draw(_SWAY_FREQUENCY) * length))
        sways.append((t, t + length, amplitude, half_periods))
        t += length
        times.append(t)
        depths.append(depths[-1])

    first = True
    while t < duration:
        if not (first and start_below):
            # swing down to the surface, then touch down
            half_swing = draw(_SWING_TIME)
            t += half_swing
            times.append(t)
            depths.append(0.0)
            move_to(draw(_STANCE_DEPTH), draw(_TOUCHDOWN_SPEED))
        first = False
        stance()
        if rng.uniform() < _REPUSH_PROBABILITY:
            stance_depth = depths[-1]
            move_to(max(stance_depth - draw(_REPUSH_RISE), 0.002), draw(_LIFT_SPEED))
            move_to(min(stance_depth + draw(_REPUSH_RISE), _STANCE_DEPTH[1] + 0.005), draw(_TOUCHDOWN_SPEED))
            stance()
        # lift off to the next apex
        move_to(-draw(_SWING_HEIGHT), draw(_LIFT_SPEED))
        t += draw(_SWING_TIME)
        times.append(t)
        depths.append(depths[-1])
        swings.append(t)

    n = math.floor(duration * rate) + 1
    sample_times = np.arange(n) / rate
    if jitter > 0.0:
        sample_times[1:-1] += rng.uniform(-jitter, jitter, n - 2) / rate
    depth = np.interp(sample_times, np.asarray(times), np.asarray(depths))
    for start, end, amplitude, half_periods in sways:
        inside = (sample_times > start) & (sample_times < end)
        phase = (sample_times[inside] - start) / (end - start)
        depth[inside] += amplitude * np.sin(math.pi * half_periods * phase)
    return Gait(sample_times, depth, tuple(s for s in swings if s <= sample_times[-1]))


@dataclass(frozen=True)
class Walk:
    """A simulated walk on mud, as a robot's sensors would record it (from :func:`walk`).

    Attributes
    ----------
    time : numpy.ndarray
        Sample times [s].
    depth : numpy.ndarray
        Measured foot depth [m] (true depth plus white noise).
    force : numpy.ndarray
        Measured vertical force [N] (true force plus bias plus white noise).
    depth_true, force_true : numpy.ndarray
        The noise-free depth [m] and force [N].
    water_content : numpy.ndarray
        The true water content under the foot at each sample [-].
    changes : tuple of float
        Times [s] at which the mud changed (swing apexes).
    params : tuple of MudParameters
        The mud of each patch, in order.
    """

    time: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    depth_true: np.ndarray
    force_true: np.ndarray
    water_content: np.ndarray
    changes: tuple[float, ...]
    params: tuple[MudParameters, ...]


def walk(
    water_content: float | Sequence[float] = 0.25,
    *,
    change_times: Sequence[float] = (),
    seed: int = 0,
    duration: float = 25.0,
    rate: float = 100.0,
    jitter: float = 0.0,
    start_below: bool = False,
    foot: Foot | None = None,
    force_noise: float = 0.2,
    depth_noise: float = 3e-5,
    bias: float = 0.0,
) -> Walk:
    """Simulate a foot walking on mud, optionally onto other mud partway, with sensor noise.

    Parameters
    ----------
    water_content : float or sequence of float
        Water content of each mud patch in turn [-] (Table I, interpolated),
        within the Table I range.
    change_times : sequence of float
        One time [s] per change of mud (``len(water_content) - 1`` of
        them, increasing): the mud changes at the first swing apex at or
        after each.
    seed : int
        Seed of the gait and of the noise, in [0, 2^32 - 1].
    duration, rate, jitter, start_below
        As in :func:`gait`: length [s], rate [Hz], time-stamp jitter [-],
        start in stance below the surface.
    foot : Foot, optional
        The foot; the paper's 51 x 38 mm cuboid by default.
    force_noise : float
        Standard deviation of white force noise [N], >= 0.
    depth_noise : float
        Standard deviation of white depth noise [m], >= 0.
    bias : float
        Constant force-sensor offset [N].

    Returns
    -------
    Walk
    """
    from mudforce.steppers.simulation import simulate

    # one conversion each: a string was read letter by letter ("58": change times 5 s and 8 s), True as 1
    given = real_array(water_content, "water_content", "-")
    if given.ndim > 1 or not given.size:
        raise InputError(f"water_content must be one water content [-] or a list of them, got shape {given.shape}")
    contents = tuple(given.reshape(-1).tolist())
    times = real_array(change_times, "change_times", "s")
    if times.ndim != 1:
        raise InputError(f"change_times must be a list of times [s], got shape {times.shape}")
    changes = tuple(times.tolist())
    if len(changes) != len(contents) - 1:
        raise InputError(
            f"walk needs one change time per change of mud: {len(contents)} water contents, "
            f"{len(changes)} change times; expected {len(contents) - 1}"
        )
    if any(not math.isfinite(c) for c in changes) or any(b <= a for a, b in itertools.pairwise(changes)):
        raise InputError(f"change times must be finite and increasing [s], got {changes!r}")
    for name, value in (("force noise", force_noise), ("depth noise", depth_noise)):
        number_within(value, name, 0.0, 1e3, "N" if name == "force noise" else "m")
    number_within(bias, "bias", -1e4, 1e4, "N")
    foot = Foot.paper() if foot is None else foot
    params = tuple(MudParameters.from_water_content(float(w)) for w in contents)
    path = gait(seed, duration=duration, rate=rate, jitter=jitter, start_below=start_below)
    time, depth = path.time, path.depth

    # the mud changes at the first swing apex at or after each change time
    switch_times: list[float] = []
    for c in changes:
        later = [s for s in path.swings if s >= c and (not switch_times or s > switch_times[-1])]
        if not later:
            raise InputError(f"no swing after the change time {c:g} s within the walk's {duration:g} s")
        switch_times.append(later[0])
    if switch_times and switch_times[0] <= time[0]:  # the first mud had no samples: "the trajectory is empty"
        raise InputError(f"the change time {changes[0]:g} s falls on the walk's first swing apex, at its start: water "
                         f"content {contents[0]:g} would have no samples; expected change times after 0 s")
    bounds = [0, *(int(np.searchsorted(time, s)) for s in switch_times), time.size]
    force = np.empty_like(time)
    truth = np.empty_like(time)
    for k, p in enumerate(params):
        lo, hi = bounds[k], bounds[k + 1]
        force[lo:hi] = simulate(time[lo:hi], depth[lo:hi], p, foot, velocity_filter="exact").force
        truth[lo:hi] = contents[k]
    rng = np.random.default_rng([seed, 1])
    measured_force = force + bias + force_noise * rng.standard_normal(time.size)
    measured_depth = depth + depth_noise * rng.standard_normal(time.size)
    return Walk(time, measured_depth, measured_force, depth, force, truth, tuple(switch_times), params)
