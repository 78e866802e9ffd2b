"""A test of the mud's family on a stream: identify's misfit flag on the last seconds of a foot's samples.

:class:`~mudforce.estimation.tracker.MudTracker`'s own misfit flag is cheap
(a few microseconds a sample) and quiet on in-family mud, but it is not a
test of the family: it forgets with the posterior, and along a robot's paths
at 50 Hz the in-family misfit it reads reaches the off-family muds'
(docs/estimation.md, "MudTracker's flag on clean and off-family recordings").
The family test that the sensor-chain bench measures is
:func:`~mudforce.estimation.calibration.identify_water_content`'s
(``model_misses_data``: the whole window at one water content, its
nuisances fitted and its noise floors read from the data). :class:`FamilyCheck`
runs that test online: it keeps the last two ``window`` seconds of samples
and, every ``every`` seconds of the stream, identifies the last ``window``
seconds and back to the foot's last touchdown before them
(:meth:`FamilyCheck.samples`), and reports the verdict
(:class:`FamilyVerdict`). :func:`check_family` does the same over a
whole recording, and ``track(..., family_window=...)`` (``mudforce track
--family-check``) carries the verdicts beside the tracker's estimates.

Nothing here is new physics or a new statistic: each verdict is identify's
on the window, as ``mudforce identify`` on a CSV of those samples would give
it. The cost is identify's (about 0.3 s for 10 s of samples at 50 Hz, 1.6 s
at 1 kHz on one core), so a controller calls :meth:`FamilyCheck.update` in
its loop (it only stores the sample until a check is due) or, to keep the
loop's time bounded, :meth:`FamilyCheck.push` there and
:meth:`FamilyCheck.check` from a slower thread.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mudforce._kernel.bounds import MAX_DEPTH, MAX_TIME, MIN_DT
from mudforce.errors import InputError, positive_number, real_array, real_number
from mudforce.estimation._tracker_layout import MAX_FORCE
from mudforce.estimation._tracker_step import _check_bounds
from mudforce.estimation.nuisances import DEFAULT_FORCE_GAIN_UNCERTAINTY
from mudforce.model.bounds import check_finite, check_times
from mudforce.model.foot import Foot

__all__ = [
    "DEFAULT_FAMILY_EVERY",
    "DEFAULT_FAMILY_WINDOW",
    "SWING_CLEARANCE",
    "FamilyCheck",
    "FamilyVerdict",
    "check_family",
]

#: The samples each check identifies: the last 10 s of the stream [s] (identify's flag is measured on 10-s
#: recordings: docs/estimation.md, "The misfit flag").
DEFAULT_FAMILY_WINDOW = 10.0
#: How often a check runs [s] of the stream's time.
DEFAULT_FAMILY_EVERY = 2.5
#: How far above the surface a swing must rise for its touchdown to start a window [m] (a surface offset of up to
#: 5 mm lifts no stance that far; :meth:`FamilyCheck.samples`).
SWING_CLEARANCE = 5e-3


@dataclass(frozen=True)
class FamilyVerdict:
    """identify's reading of one window of a stream.

    Attributes
    ----------
    time : float
        The window's last sample [s] on the stream's clock (the first sample at 0, then the sum of the ``dt``).
    start : float
        The window's first sample [s], same clock (NaN where no window could start: ``reason`` says why).
    samples : int
        Samples in the window [-].
    model_misses_data : bool or None
        identify's misfit flag on the window (:attr:`Identification.model_misses_data
        <mudforce.estimation.calibration.Identification.model_misses_data>`): True, the mud under the foot is not
        one of the family's, or the sensor chain is off; False, the window fits the family; None, the window told
        nothing (identify refused it, e.g. the foot never reached the mud: ``reason`` says why).
    water_content : float
        identify's estimate on the window [-] (NaN where refused).
    low, high : float
        Its 95 % interval [-] (NaN where refused).
    misfit_ratio : float
        The window's RMS residual over its noise floor [-] (NaN where refused).
    reason : str
        identify's refusal, or its warnings joined by ``"; "`` ("" when it gave none).
    """

    time: float
    start: float
    samples: int
    model_misses_data: bool | None
    water_content: float = math.nan
    low: float = math.nan
    high: float = math.nan
    misfit_ratio: float = math.nan
    reason: str = ""


def _options(window: Any, every: Any, force_gain_uncertainty: Any) -> tuple[float, float, float]:
    w = positive_number(window, "family window", "s")
    e = positive_number(every, "family check interval", "s")
    if w > MAX_TIME or e > MAX_TIME:
        raise InputError(f"the family window and check interval must be at most {MAX_TIME:g} s, got {w:g} and {e:g}")
    from mudforce.estimation.nuisances import check_force_gain_uncertainty

    check_force_gain_uncertainty(force_gain_uncertainty)
    return w, e, float(force_gain_uncertainty)


class FamilyCheck:
    """identify's misfit flag, online, on the last ``window`` seconds of one foot's samples.

    Parameters
    ----------
    foot : Foot, optional
        The foot (the paper's cuboid by default).
    window : float
        The samples each check identifies: the last ``window`` seconds [s] (default 10), and back to the foot's
        last touchdown from a swing before them, at most ``window`` seconds more (:meth:`samples`).
    every : float
        The first check runs when the stream's clock reaches ``window``, the next each ``every`` seconds [s] after
        (default 2.5).
    force_gain_uncertainty : float
        As for :func:`~mudforce.estimation.calibration.identify_water_content` [-] (default 5 %).

    Examples
    --------
    >>> from mudforce.estimation.family_check import FamilyCheck
    >>> from mudforce.motions.gait import walk
    >>> w = walk(0.25, seed=3, duration=6.0, force_noise=0.2, rate=50.0)
    >>> check = FamilyCheck(window=5.0, every=5.0)
    >>> verdicts = [check.update(z, f, dt) for z, f, dt in zip(w.depth, w.force, [0.0, *(w.time[1:] - w.time[:-1])])]
    >>> check.last is None or check.last.model_misses_data in (False, None)
    True
    """

    def __init__(self, foot: Foot | None = None, *, window: float = DEFAULT_FAMILY_WINDOW,
                 every: float = DEFAULT_FAMILY_EVERY,
                 force_gain_uncertainty: float = DEFAULT_FORCE_GAIN_UNCERTAINTY) -> None:
        if foot is not None and not isinstance(foot, Foot):
            raise InputError(f"foot must be a Foot or None, got {type(foot).__name__}")
        self.foot = Foot.paper() if foot is None else foot
        self.window, self.every, self.force_gain_uncertainty = _options(window, every, force_gain_uncertainty)
        self.reset()

    def reset(self) -> None:
        """Forget every sample and verdict: the next sample is a first one."""
        self._data = np.empty((3, 256), dtype=np.float64)  # time [s], depth [m], force [N]
        self._lo = 0  # the first sample still held
        self._n = 0  # one past the last
        self._whole = True  # the stream's first sample is still held
        self._clock = 0.0
        self._due = self.window  # the first check holds a whole window
        self._last: FamilyVerdict | None = None

    @property
    def last(self) -> FamilyVerdict | None:
        """The latest verdict (None before the first check)."""
        return self._last

    def __len__(self) -> int:
        """The samples held [-]."""
        return self._n - self._lo

    def push(self, depth: float, force: float, dt: float) -> bool:
        """Store one sample; no check runs. Returns True when a check is due (call :meth:`check`).

        Parameters
        ----------
        depth : float
            Foot depth below the surface [m], positive down (as :meth:`MudTracker.update
            <mudforce.estimation.tracker.MudTracker.update>` takes it), within +-100 m.
        force : float
            Measured vertical force [N], positive up, within +-1e7 N.
        dt : float
            Time since the previous sample [s], within [1e-9, 1e9]; ignored on the first sample.

        A sample refused (not a real number, not finite, beyond the bounds) raises
        :class:`~mudforce.errors.InputError` and changes nothing.
        """
        z = real_number(depth, "depth [m]")
        f = real_number(force, "force [N]")
        step = real_number(dt, "dt [s]")
        if not abs(z) <= MAX_DEPTH or not abs(f) <= MAX_FORCE:
            raise InputError(f"depth and force must be finite, within +-{MAX_DEPTH:g} m and +-{MAX_FORCE:g} N, "
                             f"got {z!r} and {f!r}")
        first = self._n == 0
        if not first and not MIN_DT <= step <= MAX_TIME:
            raise InputError(f"dt must be within [{MIN_DT:g}, {MAX_TIME:g}] s after the first sample, got {step!r}")
        clock = 0.0 if first else self._clock + step
        if self._n == self._data.shape[1]:
            self._make_room(clock)
        self._data[:, self._n] = clock, z, f
        self._n += 1
        self._clock = clock
        return clock >= self._due

    def _make_room(self, clock: float) -> None:
        """Drop the samples older than two windows (as of ``clock``; a window starts at most one window before its
        last ``window`` seconds), then grow the store if it is still full."""
        times = self._data[0, self._lo:self._n]
        keep = self._lo + int(np.searchsorted(times, clock - 2.0 * self.window, side="right"))
        held = self._n - keep
        size = self._data.shape[1] if held < self._data.shape[1] // 2 else 2 * self._data.shape[1]
        data = np.empty((3, size), dtype=np.float64)
        data[:, :held] = self._data[:, keep:self._n]
        self._whole = self._whole and keep == self._lo
        self._data, self._lo, self._n = data, 0, held

    def _first(self) -> int | None:
        """The window's first sample's index in the store, or None where no start is found (see :meth:`samples`)."""
        lo, n = self._lo, self._n
        times, depths = self._data[0, lo:n], self._data[1, lo:n]
        begin = int(np.searchsorted(times, self._clock - 2.0 * self.window, side="right"))
        end = int(np.searchsorted(times, self._clock - self.window, side="right"))  # the lead: [begin, end)
        opens = self._whole and begin == 0 and depths[0] <= 0.0  # the stream's first sample, above the surface
        if end == 0:  # the stream is younger than the window
            return lo if opens else None
        k = np.arange(begin, min(end, n - 1))
        for last in k[(depths[k] <= 0.0) & (depths[k + 1] > 0.0)][::-1].tolist():  # touchdowns, the latest first
            deeper = begin + np.flatnonzero(depths[begin:last] > 0.0)
            top = int(deeper[-1]) + 1 if deeper.size else begin  # the run above the surface that ends at `last`,
            # within the lead (held samples older than it may be dropped at any time: the answer must not depend on it)
            if float(np.min(depths[top:last + 1])) <= -SWING_CLEARANCE:
                return lo + int(last)
        return lo if opens else None

    def samples(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The window's samples (copies): time [s] on the stream's clock, depth [m], force [N]; empty where no
        start is found.

        The window ends at the latest sample and starts at the foot's last sample above the surface (depth <= 0)
        before a touchdown, the latest such touchdown among the ``window`` seconds before the last ``window``
        seconds whose swing rose :data:`SWING_CLEARANCE` (5 mm) or more above the surface; failing one, the
        stream's first sample if it is among them and above the surface (as it is when the stream is younger than
        the window). identify starts its model with the foot free of the mud, and the model's mud forgets its
        past exactly there: a foot that moves down above the surface ends the neck's decay (Eq. (7)) and touches
        down into fresh mud (docs/model.md). A window begun in a stance read a foot pushed in at once, and one
        begun at a swing's top the decay of a neck that still pulled 2 N: both were flagged on clean in-family
        walks (docs/estimation.md, "The family check online"). The clearance holds a swing apart from a stance
        that a surface offset of up to 5 mm lifts above the recorded surface."""
        first = self._first()
        if first is None:
            return np.empty(0), np.empty(0), np.empty(0)
        t, z, f = (self._data[i, first:self._n].copy() for i in range(3))
        return t, z, f

    def check(self) -> FamilyVerdict:
        """Identify the samples of the last ``window`` seconds now; return (and keep) the verdict.

        Raises
        ------
        InputError
            Before the first sample.
        """
        if self._n == 0:
            raise InputError("FamilyCheck.check: no sample yet; expected update(depth [m], force [N], dt [s]) first")
        t, z, f = self.samples()
        w = self.window
        self._last = _verdict(t, z, f, self.foot, self.force_gain_uncertainty) if t.size else FamilyVerdict(
            self._clock, math.nan, 0, None, reason=f"no swing {SWING_CLEARANCE * 1e3:g} mm above the surface touched "
            f"down in the {w:g} s before the last {w:g} s: a window starts where the mud forgets (a touchdown)")
        self._advance_due()
        return self._last

    def _advance_due(self) -> None:
        """The next check is due ``every`` seconds after the last due time past now (a long gap skips the missed
        ones)."""
        while self._due <= self._clock:
            self._due += self.every

    def update(self, depth: float, force: float, dt: float) -> FamilyVerdict | None:
        """Store one sample (as :meth:`push`) and, when a check is due, run it: the new verdict, else None."""
        return self.check() if self.push(depth, force, dt) else None

    def __repr__(self) -> str:
        return f"FamilyCheck(window={self.window:g} s, every={self.every:g} s, {len(self)} samples held)"


def _verdict(t: np.ndarray, z: np.ndarray, f: np.ndarray, foot: Foot, gain: float) -> FamilyVerdict:
    """identify on one window's samples (refused: a verdict of None with the refusal)."""
    import warnings

    from mudforce.estimation.calibration import identify_water_content
    from mudforce.estimation.calibration.dataset import Trial

    start, end = float(t[0]), float(t[-1])
    try:
        with warnings.catch_warnings():  # its warnings are the verdict's reason, not the caller's to see again
            warnings.simplefilter("ignore")
            res = identify_water_content(Trial("window", math.nan, t, z, f), foot, force_gain_uncertainty=gain)
    except InputError as err:
        return FamilyVerdict(end, start, t.size, None, reason=str(err))
    return FamilyVerdict(end, start, t.size, bool(res.model_misses_data), float(res.water_content),
                         float(res.interval[0]), float(res.interval[1]), float(res.misfit_ratio),
                         "; ".join(res.warnings))


def check_family(time: Any, depth: Any, force: Any, foot: Foot | None = None, *,
                 window: float = DEFAULT_FAMILY_WINDOW, every: float = DEFAULT_FAMILY_EVERY,
                 force_gain_uncertainty: float = DEFAULT_FORCE_GAIN_UNCERTAINTY,
                 quiet: bool = True) -> list[tuple[int, FamilyVerdict]]:
    """Run a :class:`FamilyCheck` over a whole recording (the same verdicts as online).

    Parameters
    ----------
    time, depth, force : array_like
        Sample times [s] (strictly increasing), foot depths [m] (positive down), measured forces [N].
    foot, window, every, force_gain_uncertainty
        As for :class:`FamilyCheck`.
    quiet : bool
        No progress line (default); False: one on stderr when it is a terminal (each check is an identify).

    Returns
    -------
    list of (int, FamilyVerdict)
        Each check's sample index (the window's last sample) and verdict, in order.
    """
    t = real_array(time, "time", "s")
    z = real_array(depth, "depth", "m")
    f = real_array(force, "force", "N")
    if t.ndim != 1 or t.shape != z.shape or t.shape != f.shape or t.size < 1:
        raise InputError(f"time, depth and force must be 1-D of one length >= 1, got {t.shape}, {z.shape}, {f.shape}")
    check_times(t, max_dt=MAX_TIME)  # every sample checked before the first identify runs
    check_finite(z, "depth", "m")
    check_finite(f, "force", "N")
    _check_bounds(z, f, MAX_DEPTH, t)
    return _feed(FamilyCheck(foot, window=window, every=every, force_gain_uncertainty=force_gain_uncertainty),
                 t, z, f, quiet)


def _feed(checker: FamilyCheck, t: np.ndarray, z: np.ndarray, f: np.ndarray,
          quiet: bool = True) -> list[tuple[int, FamilyVerdict]]:
    """``checker`` fed a checked recording sample by sample: each check's sample index and verdict (with a progress
    line on a terminal unless ``quiet``: each check is an identify)."""
    from mudforce._plumbing.progress import Progress

    out = []
    steps = np.diff(t, prepend=t[0])
    span = float(t[-1] - t[0])
    due = 0 if span < checker.window else int((span - checker.window) // checker.every) + 1
    with Progress(due, "family check", quiet=quiet) as progress:
        for k in range(t.size):
            verdict = checker.update(float(z[k]), float(f[k]), float(steps[k]))
            if verdict is not None:
                out.append((k, verdict))
                progress.update(1, f"at {verdict.time:.4g} s")
    return out


def _flags(checks: Sequence[tuple[int, FamilyVerdict]], m: int) -> np.ndarray:
    """Per sample of ``m``: the latest informative verdict's flag at or before it (False before the first; a
    verdict of None leaves the flag as it was)."""
    flags = np.zeros(m, dtype=bool)
    for (k, verdict), end in zip(checks, [*(c[0] for c in checks[1:]), m], strict=True):
        flags[k:end] = (flags[k - 1] if k else False) if verdict.model_misses_data is None \
            else verdict.model_misses_data
    return flags
