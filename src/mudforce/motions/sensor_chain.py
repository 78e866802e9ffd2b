"""A robot's sensor chain: corrupting a clean, finely sampled recording as a legged robot's sensors would.

On a robot the foot's depth comes from leg kinematics and an estimate of
where the mud's surface is, and the force from joint torques or a foot
sensor. :func:`apply` takes a *clean* recording (the true depth [m] and the
true force [N], simulated on a fine time grid along the true path) and
returns what such a robot would record, at its own sample rate:

depth (positive down)
    ``depth + depth_offset + drift(t) + noise``: the surface estimate is
    ``depth_offset`` [m] too high (a positive offset reads every depth
    deeper), it drifts, and the reading carries white noise of standard
    deviation ``depth_noise`` [m].
drift
    The surface estimate's error grows linearly, ``drift`` [m] per
    ``drift_time`` [s] (signed: a negative drift reads ever shallower),
    plus a smooth wander: a sinusoid of amplitude ``|drift| / 8``, a
    period drawn in ``[drift_time / 4, drift_time]`` and a random phase,
    shifted to start at zero. Hence ``drift(t0) = 0`` and
    ``|drift(t) - drift (t - t0) / drift_time| <= |drift| / 4`` at every time.
force
    ``gain * lowpass(delayed force) + force_bias + noise``: delayed by
    ``force_delay`` [s] (the first sample held before the recording),
    then through a first-order low-pass of time constant ``force_lowpass``
    [s] (DC gain 1, started in steady state, exact for a force linear
    between the fine samples), scaled by ``force_gain`` [-] (1.05 reads 5 %
    high), offset by ``force_bias`` [N], with white noise of standard
    deviation ``force_noise`` [N].
sampling
    At ``rate`` [Hz], from the recording's first time: samples
    ``t0 + k / rate`` up to its last time, each the corrupted signal at that
    instant (linear between fine samples, exact when the instant is a fine
    sample); the noise is drawn per output sample. No anti-aliasing beyond
    ``force_lowpass``: impacts and vibration between the samples are simply
    not seen, as on a robot. ``rate=None`` keeps the input's time stamps.

The model must be simulated on the fine true path *before* this: at the
sample rate the model is not the model of the true path (a touchdown
between two samples, a reversal seen late).

Every random draw comes from ``numpy.random.default_rng([seed, k])`` with
one ``k`` per corruption (depth noise, force noise, drift), so the same
seed gives the same recording bit for bit, and switching one corruption on
or off does not change the draws of another.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from mudforce.errors import InputError, number_within, real_array, seed_int
from mudforce.io.tables import COLUMN_LIMITS
from mudforce.model.bounds import MAX_DEPTH, check_times

__all__ = ["LIMITS", "SensorChain", "apply", "drift_path"]

#: The accepted range of each field of :class:`SensorChain` (SI, inclusive): name -> (lo, hi, unit).
LIMITS: dict[str, tuple[float, float, str]] = {
    "depth_offset": (-0.1, 0.1, "m"),
    "depth_noise": (0.0, 0.01, "m"),
    "drift": (-0.1, 0.1, "m"),
    "drift_time": (1.0, 3600.0, "s"),
    "force_delay": (0.0, 1.0, "s"),
    "force_lowpass": (0.0, 1.0, "s"),
    "force_gain": (0.5, 2.0, "-"),
    "force_bias": (-1e4, 1e4, "N"),
    "force_noise": (0.0, 1e3, "N"),
    "rate": (1.0, 1e5, "Hz"),
}

# the streams of default_rng([seed, k]), one per corruption
_DEPTH_NOISE, _FORCE_NOISE, _DRIFT = 1, 2, 3


@dataclass(frozen=True)
class SensorChain:
    """The corruptions of a robot's depth and force sensors (see the module's docstring for the order).

    Parameters
    ----------
    depth_offset : float
        Error of the surface-height estimate [m]; a positive offset reads every depth deeper.
    depth_noise : float
        White depth noise, standard deviation [m], >= 0.
    drift : float
        Drift of the surface estimate [m] per ``drift_time`` (signed), plus a smooth wander of at most ``|drift| / 4``.
    drift_time : float
        The time over which ``drift`` builds up [s] (the issue's "2 mm over 30 s" is ``drift=0.002, drift_time=30``).
    force_delay : float
        Pure delay of the force [s], >= 0.
    force_lowpass : float
        Time constant of a first-order low-pass on the force [s], >= 0 (0: none).
    force_gain : float
        Gain of the force sensor [-] (1.05 = +5 %), within [0.5, 2].
    force_bias : float
        Constant force offset [N].
    force_noise : float
        White force noise, standard deviation [N], >= 0.
    rate : float or None
        Sample rate of the recording [Hz]; ``None`` keeps the input's time stamps.

    Every field is checked against :data:`LIMITS`; a bad one raises a one-line :class:`InputError`.
    """

    depth_offset: float = 0.0
    depth_noise: float = 0.0
    drift: float = 0.0
    drift_time: float = 30.0
    force_delay: float = 0.0
    force_lowpass: float = 0.0
    force_gain: float = 1.0
    force_bias: float = 0.0
    force_noise: float = 0.0
    rate: float | None = None

    def __post_init__(self) -> None:
        for name, (lo, hi, unit) in LIMITS.items():
            value = getattr(self, name)
            if name == "rate" and value is None:
                continue
            object.__setattr__(self, name, number_within(value, f"sensor chain {name}", lo, hi, unit))

    @property
    def is_clean(self) -> bool:
        """True when the chain changes nothing (no corruption, the input's time stamps kept)."""
        return self == SensorChain()

    def to_dict(self) -> dict[str, Any]:
        """The fields with their units in the keys, for a dataset's manifest (``depth_offset_m``, ``rate_Hz``, ...)."""
        units = {"m": "_m", "s": "_s", "N": "_N", "Hz": "_Hz", "-": ""}
        return {f"{name}{units[LIMITS[name][2]]}": value for name, value in asdict(self).items()}


def drift_path(time: np.ndarray, chain: SensorChain, seed: int) -> np.ndarray:
    """The depth error [m] of the drifting surface estimate at ``time`` [s] (zero at ``time[0]``).

    A linear ramp of ``chain.drift`` per ``chain.drift_time`` plus a sinusoid of
    amplitude ``|drift| / 8``, period in ``[drift_time / 4, drift_time]`` and
    random phase (from ``seed``), shifted to start at zero.
    """
    # checked as apply() checks a recording's time: [] raised IndexError, text ValueError, a NaN came back as NaN
    if not isinstance(chain, SensorChain):
        raise InputError(f"chain must be a SensorChain, got {type(chain).__name__}")
    given = real_array(time, "time", "s")
    if given.ndim != 1 or not given.size:
        raise InputError(f"time must be 1-D with at least one sample [s], got shape {given.shape}")
    check_times(given)
    t = given - float(given[0])
    if chain.drift == 0.0:
        return np.zeros_like(t)
    rng = np.random.default_rng([seed_int(seed, "seed"), _DRIFT])
    period = float(rng.uniform(0.25, 1.0)) * chain.drift_time
    phase = float(rng.uniform(0.0, 2.0 * math.pi))
    amplitude = abs(chain.drift) / 8.0
    wander = amplitude * (np.sin(2.0 * math.pi * t / period + phase) - math.sin(phase))
    out: np.ndarray = chain.drift * t / chain.drift_time + wander
    return out


def _lowpass(time: np.ndarray, x: np.ndarray, tau: float) -> np.ndarray:
    """First-order low-pass ``tau y' + y = x``, exact for ``x`` linear between samples, from ``y = x[0]``."""
    y: np.ndarray = np.empty_like(x)
    if tau == 0.0:
        y[:] = x
        return y
    y[0] = x[0]
    h = np.diff(time)
    a = np.exp(-h / tau)
    # y(t+h) = a y + (1 - a) x0 + (x1 - x0) (1 - tau (1 - a) / h)
    ramp = 1.0 - tau * (1.0 - a) / h
    for k in range(x.size - 1):
        y[k + 1] = a[k] * y[k] + (1.0 - a[k]) * x[k] + (x[k + 1] - x[k]) * ramp[k]
    return y


def _check_recording(time: Any, depth: Any, force: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    # real numbers only (numpy parsed strings and read booleans as 0 and 1), and bounded as the readers bound a
    # recording, so that the gain and the bias keep the force finite (1e308 N times a gain of 2 was inf)
    t, z, f = (real_array(a, name, unit) for a, name, unit in ((time, "time", "s"), (depth, "depth", "m"),
                                                               (force, "force", "N")))
    if t.ndim != 1 or t.shape != z.shape or t.shape != f.shape or t.size < 2:
        raise InputError(f"time, depth and force must be 1-D of one length >= 2, got shapes {t.shape}, {z.shape}, "
                         f"{f.shape}")
    check_times(t)  # simulate's refusal and words: finite, within +-MAX_TIME, steps within [MIN_DT, MAX_DT]
    for name, a, unit, bound in (("depth", z, "m", MAX_DEPTH), ("force", f, "N", COLUMN_LIMITS["force"])):
        if not np.all(np.isfinite(a)):
            bad = int(np.argmin(np.isfinite(a)))
            raise InputError(f"{name} must be finite [{unit}]; sample {bad} is {float(a[bad])!r}")
        beyond = np.flatnonzero(np.abs(a) > bound)
        if beyond.size:
            raise InputError(f"{name} must be within +-{bound:g} {unit}; sample {int(beyond[0])} is "
                             f"{float(a[beyond[0]])!r}")
    return t, z, f


def apply(time: Any, depth: Any, force: Any, chain: SensorChain,
          seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What a robot's sensors would record of a clean, finely sampled foot recording.

    Parameters
    ----------
    time : array_like
        Fine sample times [s], strictly increasing (at least 2).
    depth : array_like
        True foot depth below the true surface [m], positive down.
    force : array_like
        True vertical mud force [N], the model simulated on this fine path.
    chain : SensorChain
        The corruptions; ``chain.rate`` must not exceed the input's finest rate
        (the model has to be simulated finer than it is sampled).
    seed : int
        Seed of the noise and the drift's wander, within [0, 2**32 - 1].

    Returns
    -------
    (time, depth, force) : tuple of numpy.ndarray
        The recording [s], [m], [N] at ``chain.rate`` (or at the input's time stamps).
    """
    if not isinstance(chain, SensorChain):
        raise InputError(f"chain must be a SensorChain, got {type(chain).__name__}")
    seed = seed_int(seed, "seed")
    t, z, f = _check_recording(time, depth, force)
    if chain.force_delay > 0.0:
        f = np.interp(t - chain.force_delay, t, f)  # before the first sample: the first sample, held
    f = chain.force_gain * _lowpass(t, f, chain.force_lowpass) + chain.force_bias
    z = z + chain.depth_offset + drift_path(t, chain, seed)
    if chain.rate is None:
        out_t = t.copy()
    else:
        fine = float(np.min(np.diff(t)))
        if chain.rate * fine > 1.0 + 1e-9:
            raise InputError(f"sensor chain rate {chain.rate:g} Hz is finer than the clean recording's "
                             f"{1.0 / fine:.6g} Hz; simulate the model on a finer path than it is sampled")
        n = math.floor((t[-1] - t[0]) * chain.rate + 1e-9) + 1
        if n < 2:
            raise InputError(f"sensor chain rate {chain.rate:g} Hz gives fewer than 2 samples over the "
                             f"recording's {t[-1] - t[0]:.6g} s; expected a longer recording or a higher rate")
        out_t = t[0] + np.arange(n) / chain.rate
        f = np.interp(out_t, t, f)
        z = np.interp(out_t, t, z)
    if chain.depth_noise > 0.0:
        z = z + chain.depth_noise * np.random.default_rng([seed, _DEPTH_NOISE]).standard_normal(out_t.size)
    if chain.force_noise > 0.0:
        f = f + chain.force_noise * np.random.default_rng([seed, _FORCE_NOISE]).standard_normal(out_t.size)
    return out_t, z, f
