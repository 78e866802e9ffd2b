"""Choosing the intrusion or withdrawal branch from a measured, noisy depth.

The model switches branch on the sign of the foot velocity (Eq. (8)'s
``w(dz_i)``). Motion capture with 0.05 mm RMS noise at 100 Hz gives a
raw-difference velocity noise of about 7 mm/s, more than a 10 mm/s motion,
so the raw sign chatters during a hold, and every false withdrawal sample
drops the whole nonlinear-spring force. The branch is therefore chosen from
a :class:`VelocityFilter`:

* a causal secant over the last ``window`` steps,
  ``v_hat = (z_k - z_{k-N}) / (t_k - t_{k-N})``, a positive-weighted
  average of the raw step velocities, so it never overshoots (a clean
  intrusion followed by a hold never reads as withdrawal);
* a Schmitt-trigger deadband: the direction becomes "down" above
  ``+deadband``, "up" below ``-deadband``, and is kept until ``|v_hat|``
  falls below half the band; in between the foot is at rest (intrusion
  branch, the paper's ``sign(0) = +1``).

``VelocityFilter.exact()`` (``window=1, deadband=0``) is the paper's model
to the letter. Only the branch choice uses the filter: the Maxwell element
and the drag always see the sampled depth itself, first-order hold.

The cost of robustness is latency: after a reversal the new direction is
recognised once the secant passes the deadband, after roughly
``5 sqrt(2) sigma / (v dt)`` samples (about 3.5 samples for 0.05 mm noise,
10 mm/s and 100 Hz), whatever the window, plus half the window.

Which rule a whole trajectory gets (``velocity_filter="auto"``, the default
of :func:`~mudforce.simulate` and ``mudforce simulate`` / ``track``) is
decided from the data by :func:`analyse_depth_noise`. Noise and motion
differ in how their differences scale with the order: white noise has the
same level at every order, a motion sampled finely enough falls by about
``omega dt / 2`` an order. A line through three samples alone cannot tell
them apart: on a smooth curve it reads the curvature as noise. So clean
input of any shape (a sine, a spline, a simulator's output, the paper's
piecewise-linear protocol) gets the exact rule and exactly the model's
force, and only a white component found above :data:`NOISE_FLOOR_M` brings
in the filter. :func:`choose_velocity_filter` returns the rule with the
:class:`DepthNoise` it assumed; :class:`~mudforce.SimulationResult` keeps
both, and the commands print them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mudforce.errors import InputError, is_real, real_array, real_number, shown
from mudforce.model.bounds import MAX_DEPTH, MIN_DT, check_finite, check_times

#: The longest smoothing window [steps] (the compiled steppers keep ``MAX_WINDOW + 1`` samples of depth).
MAX_WINDOW = 64

__all__ = [
    "MAX_NOISE_ORDER",
    "MAX_WINDOW",
    "MIN_NOISE_SAMPLES",
    "NOISE_FLOOR_M",
    "SLOWEST_MOTION",
    "DepthNoise",
    "VelocityFilter",
    "analyse_depth_noise",
    "auto_velocity_filter",
    "choose_velocity_filter",
    "describe_velocity_rule",
    "estimate_depth_noise",
    "resolve_velocity_filter",
]

#: Depth noise [m] below which a trajectory counts as clean (1 nm, far below any motion capture).
NOISE_FLOOR_M = 1e-9

_MAX_NOISE_SAMPLES = 200_000

#: The first quartile of |X| for a standard normal X (the 62.5 % point of the normal) [-].
_QUARTILE_OF_HALF_NORMAL = 0.31863936396437514

#: Highest order of differences searched for the depth noise [-] (:func:`analyse_depth_noise`).
MAX_NOISE_ORDER = 10

#: Fewest samples in which noise is told from motion [-]; shorter records are taken as clean.
MIN_NOISE_SAMPLES = 20

#: Fewest residuals of an order that its noise level is compared on [-].
_MIN_RESIDUALS = 16

#: Ratio of successive orders' noise levels at or above which the residual is white noise [-] (for
#: 100 residuals or more; fewer residuals scatter more and get a lower bar, :func:`_white_ratio`).
WHITE_RATIO = 0.7
# Fewest steps between still samples that make a depth quantised (:func:`analyse_depth_noise`) [-]: a clean
# motion has one at each corner between holds, a few per stop.
_MIN_QUANTISED_STEPS = 10

#: Deadband in standard deviations of the filtered velocity noise.
DEADBAND_SIGMAS = 5.0

#: The slowest motion [m/s] a noise filter must tell from rest (1 mm/s): it sets the window's length.
SLOWEST_MOTION = 1e-3


def _finite_at_least_zero(value: Any, name: str, unit: str, *, positive: bool = False) -> float:
    """``value`` as a float if it is a finite real number >= 0 (> 0 if ``positive``), else one line naming ``name``
    (a Python int beyond float64 in :func:`~mudforce.errors.real_number`'s words: math.isfinite raised
    OverflowError for it)."""
    number = real_number(value, name) if is_real(value) else math.nan
    if not math.isfinite(number) or number < 0.0 or (positive and number == 0.0):
        raise InputError(f"{name} must be finite and {'> 0' if positive else '>= 0'} [{unit}], got {shown(value)}")
    return number


@dataclass(frozen=True)
class VelocityFilter:
    """How the branch velocity is estimated from sampled depth.

    Parameters
    ----------
    window : int
        Secant length in steps, 1 to 64; 1 is the raw difference [-].
    deadband : float
        Half-width of the at-rest band of the velocity estimate [m/s], >= 0.
    """

    window: int = 1
    deadband: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.window, bool) or not isinstance(self.window, (int, np.integer)):
            raise InputError(f"velocity filter window must be an integer number of steps, got {shown(self.window)}")
        if not 1 <= int(self.window) <= MAX_WINDOW:
            raise InputError(f"velocity filter window must be 1..{MAX_WINDOW} steps, got {shown(self.window)}")
        _finite_at_least_zero(self.deadband, "velocity filter deadband", "m/s")
        object.__setattr__(self, "window", int(self.window))
        object.__setattr__(self, "deadband", float(self.deadband))

    @classmethod
    def exact(cls) -> VelocityFilter:
        """The paper's rule: the sign of the raw step velocity."""
        return cls(1, 0.0)

    @classmethod
    def for_noise(cls, noise_std: float, dt: float, window_s: float = 0.1) -> VelocityFilter:
        """A filter for white depth noise of ``noise_std`` [m] sampled every ``dt`` [s].

        The deadband is 5 standard deviations of the secant's velocity
        noise, ``5 sqrt(2) noise_std / (window dt)`` [m/s]. The window is the
        shortest whose deadband is at most :data:`SLOWEST_MOTION` (1 mm/s),
        but no longer than ``window_s`` [s] (and 1 to 64 steps): a longer
        window only delays the branch switch by half its length, while the
        deadband's own delay after a reversal, ``5 sqrt(2) noise_std /
        (2 v dt)`` steps at speed ``v``, does not depend on it. Motion
        capture (tens of um at 100 Hz) fills ``window_s``; small noise gets
        a short window. ``noise_std <= 1 nm`` gives :meth:`exact`.
        """
        # the arithmetic below on these Python floats: a float32 argument took it in float32 (NumPy's promotion),
        # its deadband then 3e-8 off the float value's
        noise = _finite_at_least_zero(noise_std, "noise level", "m")
        step = _finite_at_least_zero(dt, "time step", "s", positive=True)
        span = _finite_at_least_zero(window_s, "velocity window", "s", positive=True)
        # within these the deadband is finite (< 1e12 m/s); a denormal step or a noise of 1e308 m overflowed it
        if noise > MAX_DEPTH:
            raise InputError(f"noise level must be within [0, {MAX_DEPTH:g}] m (the depths' bound), "
                             f"got {shown(noise_std)}")
        if step < MIN_DT:
            raise InputError(f"time step must be at least {MIN_DT:g} s (the steppers' shortest step), got {shown(dt)}")
        if noise <= NOISE_FLOOR_M:
            return cls.exact()
        # the ratios capped before they are rounded to steps: round(inf) and math.ceil(inf) raise OverflowError
        longest = int(min(MAX_WINDOW, max(2, round(min(span / step, MAX_WINDOW)))))
        needed = math.ceil(min(DEADBAND_SIGMAS * math.sqrt(2.0) * noise / (step * SLOWEST_MOTION), MAX_WINDOW))
        window = int(min(longest, max(1, needed)))
        deadband = DEADBAND_SIGMAS * math.sqrt(2.0) * noise / (window * step)
        return cls(window, deadband)

    @property
    def is_exact(self) -> bool:
        """True when this is the paper's raw-sign rule."""
        return self.window == 1 and self.deadband == 0.0


@dataclass(frozen=True)
class DepthNoise:
    """What :func:`analyse_depth_noise` found in a sampled depth.

    Attributes
    ----------
    std : float
        Standard deviation of the white noise on the depth [m]; when no
        white component was found above the motion (``white`` false and
        ``std > NOISE_FLOOR_M``), an upper bound on it.
    order : int
        Order of the differences the estimate comes from [-] (2 for a
        piecewise-linear motion, higher for a curved one).
    white : bool
        True when a white component above :data:`NOISE_FLOOR_M` was told
        apart from the motion: the depth is noisy. False for clean input.
    samples : int
        Number of samples analysed [-].
    quantum : float
        The step of a quantised depth [m] (an encoder's, or a depth written with few digits), 0 if none was found:
        the depth then holds still between steps of one quantum while the foot moves, and ``std`` is the
        quantisation's, ``quantum / sqrt(12)`` (``white`` true: the filter's rule).
    """

    std: float
    order: int
    white: bool
    samples: int
    quantum: float = 0.0

    @property
    def clean(self) -> bool:
        """True when no noise above :data:`NOISE_FLOOR_M` was found: the paper's exact rule applies."""
        return not self.white

    def describe(self) -> str:
        """One line: what was found, in mm."""
        if self.quantum > 0.0:
            return (f"quantised depth: steps of {self.quantum * 1e3:.3g} mm between still samples, taken as noise of "
                    f"{self.std * 1e3:.3g} mm")
        if self.white:
            return f"depth noise {self.std * 1e3:.3g} mm (white, from order-{self.order} differences)"
        if self.samples < MIN_NOISE_SAMPLES:
            return f"too few samples ({self.samples}) to tell noise from motion: taken as clean"
        if self.std <= NOISE_FLOOR_M:
            return (f"clean: no depth noise above {NOISE_FLOOR_M * 1e3:g} mm "
                    f"(order-{self.order} differences: {self.std * 1e3:.2g} mm)")
        return (f"clean: no white noise told apart from the motion up to order {self.order} "
                f"(differences of {self.std * 1e3:.3g} mm are motion)")


def _check_record(time: np.ndarray, depth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Float64 copies of a time and depth record, refused if they cannot be analysed."""
    t = real_array(time, "time", "s")
    z = real_array(depth, "depth", "m")
    if t.ndim != 1 or z.ndim != 1 or t.size != z.size:
        raise InputError(f"time and depth must be 1-D arrays of one length, got shapes {t.shape} and {z.shape}")
    check_times(t)  # simulate's refusal and words: finite, within +-MAX_TIME, steps within [MIN_DT, MAX_DT]
    check_finite(z, "depth", "m")
    return t, z


def _residuals(t: np.ndarray, z: np.ndarray, k: int) -> np.ndarray:
    """Each sample's miss from the degree ``k - 1`` polynomial through the ``k`` samples before it [m].

    Rows of ``t`` and ``z`` are independent runs of consecutive samples.
    Zero for a polynomial motion of degree below ``k``; for white noise of
    standard deviation ``sigma`` on a uniform grid, the ``k``-th difference,
    of standard deviation ``sqrt(C(2k, k)) sigma``.
    """
    if k == 2:  # the line through the two samples before (the one form of it, for bit-equal estimates)
        h0 = t[:, 1:-1] - t[:, :-2]
        h1 = t[:, 2:] - t[:, 1:-1]
        line: np.ndarray = z[:, 2:] - (z[:, 1:-1] + (z[:, 1:-1] - z[:, :-2]) * (h1 / h0))
        return line
    d = z
    for j in range(1, k + 1):  # divided differences, Newton's form
        d = (d[:, 1:] - d[:, :-1]) / (t[:, j:] - t[:, :-j])
    m = t.shape[1] - k
    w = np.ones_like(d)
    for j in range(k):
        w = w * (t[:, k:] - t[:, j:j + m])
    out: np.ndarray = d * w
    return out


def _sigma(t: np.ndarray, z: np.ndarray, k: int) -> tuple[float, float]:
    """The noise's standard deviation as order-``k`` residuals see it [m], twice.

    First from their median absolute deviation (the estimate); then from
    the first quartile of the absolute deviations, which still holds when
    up to three quarters of the residuals touch a kink of the motion (a
    gait at 20 Hz: a touchdown every few samples, each kink reaching
    ``k + 1`` residuals), for telling noise from motion.
    """
    r = _residuals(t, z, k).ravel()
    dev = np.abs(r - np.median(r))
    norm = math.sqrt(math.comb(2 * k, k))
    mad = float(np.median(dev))
    quartile = float(np.quantile(dev, 0.25))
    return 1.4826 * mad / norm, quartile / _QUARTILE_OF_HALF_NORMAL / norm


def _quantum(z: np.ndarray) -> float:
    """The step of a quantised depth [m], or 0 if the depth does not look quantised.

    A depth read in steps of ``q`` (an encoder's count, a depth written with few digits) holds still between
    steps while the foot moves slower than ``q`` a sample: its differences are runs of exact zeros broken by
    single steps. Its order-``k`` residuals are then mostly exactly zero, so :func:`analyse_depth_noise`'s
    estimate read it as clean, and the exact rule took each still run for a stop (a 1 mm/s withdrawal read to
    0.1 mm at 100 Hz: the intrusion branch's 52 N where the motion gives -0.3 N). A clean motion holds still only
    where it stops (a hold), and its steps between still samples are the few corners of the motion. So: at least
    :data:`_MIN_QUANTISED_STEPS` steps, and at least a tenth of the steps, each between two still samples; the
    quantum is their median size (:func:`analyse_depth_noise` takes it when its noise, ``quantum / sqrt(12)``, is
    above :data:`NOISE_FLOOR_M`).
    """
    d = np.diff(z)
    still = d == 0.0
    lone = ~still[1:-1] & still[:-2] & still[2:]  # a step between two still samples
    count = int(lone.sum())
    if count < _MIN_QUANTISED_STEPS or count < 0.1 * int((~still).sum()):
        return 0.0
    return float(np.median(np.abs(d[1:-1][lone])))


def _white_ratio(residuals: int) -> float:
    """Least ratio ``sigma_{k+1} / sigma_k`` taken as white noise, for ``residuals`` residuals [-].

    For white noise the ratio is 1 with a spread of about ``0.6 / sqrt(n)``
    (its 0.5 % quantile is about ``1 - 2.3 / sqrt(n)``, measured); for a
    motion resolved by the sampling it is about ``sin(omega dt / 2)``.
    """
    return min(WHITE_RATIO, max(0.5, 1.0 - 3.0 / math.sqrt(residuals)))


def analyse_depth_noise(time: np.ndarray, depth: np.ndarray) -> DepthNoise:
    """Tell white noise on a sampled depth from the motion, and measure it.

    For orders ``k = 2, 3, ...`` :data:`MAX_NOISE_ORDER`, each sample's miss
    from the polynomial of degree ``k - 1`` through the ``k`` samples before
    it (on a uniform grid, the ``k``-th difference) gives a robust noise
    level ``sigma_k``: the median absolute deviation, scaled for a Gaussian
    and for the difference's variance ``C(2k, k) sigma^2``. The median
    ignores the few samples at kinks of a piecewise-smooth motion.

    White noise gives the same ``sigma_k`` at every order; a smooth motion
    gives ``sigma_k`` falling by about ``sin(omega dt / 2)`` an order. The
    first order at which ``sigma_{k+1} / sigma_k`` stays near 1 is where the
    noise shows, and its ``sigma_k`` is the estimate (order 2, the line
    through the two samples before, for a piecewise-linear motion). A
    ``sigma_k`` at or below :data:`NOISE_FLOOR_M` means clean input. A
    motion whose ``sigma_k`` never levels off up to the highest order is
    taken as clean too: nothing in it is told apart from the motion.

    Parameters
    ----------
    time : array
        Sample times [s], strictly increasing.
    depth : array
        Foot depth [m].

    Returns
    -------
    DepthNoise
    """
    t, z = _check_record(time, depth)
    n = z.size
    if n < MIN_NOISE_SAMPLES:
        return DepthNoise(0.0, 2, False, int(n))
    quantum = _quantum(z)
    # a quantum of rounding (a depth held within an ulp: steps of 3.5e-18 m about 16 mm) is below the noise floor
    if quantum / math.sqrt(12.0) > NOISE_FLOOR_M:
        return DepthNoise(quantum / math.sqrt(12.0), 1, True, int(n), quantum)
    if n > _MAX_NOISE_SAMPLES:
        # a deterministic, evenly spread subset of runs of consecutive samples is plenty
        # for a noise level and keeps this O(200k) for long recordings
        run = MAX_NOISE_ORDER + 2
        starts = np.linspace(0, n - run, _MAX_NOISE_SAMPLES // run).astype(np.int64)
        idx = starts[:, None] + np.arange(run)[None, :]
        rows_t, rows_z = t[idx], z[idx]
    else:
        rows_t, rows_z = t[None, :], z[None, :]
    sigma, robust = _sigma(rows_t, rows_z, 2)
    smallest = sigma
    # the highest order whose next order still has _MIN_RESIDUALS residuals to compare with
    rows, cols = rows_t.shape
    top = min(MAX_NOISE_ORDER, cols - 1 - -(-_MIN_RESIDUALS // rows))
    for k in range(2, MAX_NOISE_ORDER + 1):
        if min(sigma, robust) <= NOISE_FLOOR_M:
            return DepthNoise(min(sigma, robust), k, False, int(n))
        if k >= top:
            break
        higher, higher_robust = _sigma(rows_t, rows_z, k + 1)
        residuals = rows * (cols - k - 1)
        bar = _white_ratio(residuals)
        if higher >= bar * sigma and higher_robust >= bar * robust:
            return DepthNoise(sigma, k, True, int(n))
        sigma, robust = higher, higher_robust
        smallest = min(smallest, sigma)
    return DepthNoise(smallest, k, False, int(n))


def estimate_depth_noise(time: np.ndarray, depth: np.ndarray) -> float:
    """Robust estimate of white noise on a sampled depth [m] (:func:`analyse_depth_noise`'s ``std``).

    Parameters
    ----------
    time : array
        Sample times [s], strictly increasing.
    depth : array
        Foot depth [m].
    """
    return analyse_depth_noise(time, depth).std


def choose_velocity_filter(time: np.ndarray, depth: np.ndarray) -> tuple[VelocityFilter, DepthNoise]:
    """The default branch rule for a whole trajectory, and the noise it assumed.

    Clean input (:attr:`DepthNoise.clean`) gets the paper's exact rule, so
    the force is exactly the model's; noisy input gets
    :meth:`VelocityFilter.for_noise` at the mean step.

    Parameters
    ----------
    time : array
        Sample times [s], strictly increasing.
    depth : array
        Foot depth [m].
    """
    noise = analyse_depth_noise(time, depth)
    if not noise.white:
        return VelocityFilter.exact(), noise
    t = np.asarray(time, dtype=np.float64)
    dt = float(t[-1] - t[0]) / (t.size - 1)  # mean step
    # depths of +-100 m at random read as noise of up to ~120 m (more on an uneven grid), which for_noise refuses
    # as a noise level beyond the depths' bound: the filter for the largest noise the depths can hold
    if noise.quantum > 0.0:  # the shortest window whose secant reads 1 mm/s above the quantisation, up to 64 steps
        return VelocityFilter.for_noise(min(noise.std, MAX_DEPTH), dt, window_s=MAX_WINDOW * dt), noise
    return VelocityFilter.for_noise(min(noise.std, MAX_DEPTH), dt), noise


def auto_velocity_filter(time: np.ndarray, depth: np.ndarray) -> VelocityFilter:
    """The default filter for a whole trajectory: exact if clean, robust if noisy (:func:`choose_velocity_filter`)."""
    return choose_velocity_filter(time, depth)[0]


def describe_velocity_rule(velocity_filter: VelocityFilter, noise: DepthNoise | None = None) -> str:
    """One line for a report: which branch rule was used and, if it was chosen from the data, why."""
    if velocity_filter.is_exact:
        rule = "exact (the sign of each step, the paper's rule)"
    else:
        rule = (f"filtered (secant over {velocity_filter.window} steps, "
                f"deadband {velocity_filter.deadband * 1e3:.3g} mm/s)")
    return rule if noise is None else f"{rule}; {noise.describe()}"


def resolve_velocity_filter(
    velocity_filter: VelocityFilter | str, time: np.ndarray | None = None, depth: np.ndarray | None = None
) -> VelocityFilter:
    """Turn ``"auto"``, ``"exact"`` or a :class:`VelocityFilter` into a filter."""
    if isinstance(velocity_filter, VelocityFilter):
        return velocity_filter
    if not isinstance(velocity_filter, str):  # an array compared with "exact" elementwise: ambiguous, or [True]
        raise InputError(f'velocity_filter must be "auto", "exact" or a VelocityFilter, '
                         f'got {type(velocity_filter).__name__}')  # an array's repr has many lines
    if velocity_filter == "exact":
        return VelocityFilter.exact()
    if velocity_filter == "auto":
        if time is None or depth is None:
            raise InputError('velocity_filter="auto" needs the whole trajectory; use "exact" or a VelocityFilter')
        return auto_velocity_filter(time, depth)
    raise InputError(f'velocity_filter must be "auto", "exact" or a VelocityFilter, got {velocity_filter!r}')
