"""Cleaning a measured trial before fitting: the motion's corners, and the force sensor's bias.

Real intrusion data is messy (see ``docs/calibration.md``):

* motion capture adds noise to the depth, and the model's branch switch
  (intrusion or withdrawal, Eq. (8)) must happen at the right sample: at
  the start of withdrawal the force drops by the whole ``f_e2 S`` (tens of
  newtons) from one sample to the next;
* the force/torque sensor has a bias.

Because every trial is an intrude/hold/withdraw motion, the whole depth
trace pins down its corners far better than any local velocity estimate:
:func:`fit_motion` fits a continuous piecewise-linear motion (rest, down at
constant speed, hold, up at constant speed, rest) by least squares with
free breakpoints. Its corners are located to a small fraction of a sample
and the fitted motion, evaluated at the sample times, is a noise-free depth
that the model can follow with the exact branch rule. :func:`tare` then
removes the sensor bias using the samples before the foot touches the
surface (where the true force is zero).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from scipy.ndimage import median_filter
from scipy.optimize import least_squares

from mudforce._plumbing.jit import njit
from mudforce.errors import InputError, is_real, real_array, shown
from mudforce.estimation.calibration.branches import (
    creep_withdrawals,
    denoise_depth,
    estimate_force_noise,
    estimate_quiet_noise,
    label_branches,
    rest_steps,
)
from mudforce.estimation.calibration.dataset import Trial
from mudforce.model.velocity import estimate_depth_noise

__all__ = [
    "CLEAN_DEPTH_M",
    "MAX_DEPTH_NOISE_M",
    "MIN_PRECONTACT_SAMPLES",
    "Motion",
    "PreparedTrial",
    "fit_motion",
    "is_protocol",
    "motion_covariance",
    "noise_floor",
    "noise_floor_parts",
    "prepare_trial",
    "snap_reversal",
    "tare",
    "tare_correction",
]

#: Fewest samples before surface contact that :func:`tare` accepts [-].
MIN_PRECONTACT_SAMPLES = 3
#: Depth noise [m] below which a trial of any motion counts as noise-free (0.1 um; motion capture gives ~30 um).
CLEAN_DEPTH_M = 1e-7
#: Largest depth noise :func:`prepare_trial` accepts as known [m] (10 mm: beyond it the depth tells nothing).
MAX_DEPTH_NOISE_M = 0.01


@dataclass(frozen=True)
class Motion:
    """A fitted intrude/hold/withdraw motion: piecewise linear through four corners.

    Attributes
    ----------
    corner_time : tuple of 4 floats
        Start of the descent, end of the descent (bottom), start of the
        withdrawal (the reversal), end of the withdrawal [s]. The foot rests
        before the first and after the last.
    start_depth, hold_depth, end_depth : float
        Depth before the descent, during the hold, and after the withdrawal [m],
        positive below the surface.
    depth_noise : float
        RMS of the measured depth about the fitted motion [m].
    """

    corner_time: tuple[float, float, float, float]
    start_depth: float
    hold_depth: float
    end_depth: float
    depth_noise: float

    def vector(self) -> np.ndarray:
        """The seven motion parameters: the four corner times [s], then the three depths [m]."""
        return np.array([*self.corner_time, self.start_depth, self.hold_depth, self.end_depth])

    def from_vector(self, vector: np.ndarray) -> Motion:
        """A motion with the parameters of :meth:`vector` replaced (same noise)."""
        v = [float(x) for x in vector]
        return Motion((v[0], v[1], v[2], v[3]), v[4], v[5], v[6], self.depth_noise)

    def depth_at(self, time: np.ndarray) -> np.ndarray:
        """The fitted depth at ``time`` [s] -> [m]."""
        z = (self.start_depth, self.hold_depth, self.hold_depth, self.end_depth)
        return np.interp(np.asarray(time, dtype=np.float64), self.corner_time, z)

    @property
    def reversal_time(self) -> float:
        """Start of the withdrawal [s]."""
        return self.corner_time[2]

    @property
    def intrusion_velocity(self) -> float:
        """Descent speed [m/s], > 0."""
        ta, tb = self.corner_time[:2]
        return (self.hold_depth - self.start_depth) / max(tb - ta, 1e-12)

    @property
    def withdrawal_velocity(self) -> float:
        """Withdrawal speed [m/s], > 0 (upward)."""
        tc, td = self.corner_time[2:]
        return (self.hold_depth - self.end_depth) / max(td - tc, 1e-12)

    @property
    def contact_time(self) -> float:
        """When the descending foot reaches the surface (depth 0) [s]."""
        ta, tb = self.corner_time[:2]
        frac = (0.0 - self.start_depth) / (self.hold_depth - self.start_depth)
        return ta + frac * (tb - ta)


def _basis(time: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Columns for start, hold and end depth of a continuous piecewise-linear motion."""
    c = np.sort(corners)
    # keep the corners strictly increasing so that np.interp is well defined
    c = c + np.arange(4) * 1e-12
    return np.column_stack([
        np.interp(time, c, (1.0, 0.0, 0.0, 0.0)),
        np.interp(time, c, (0.0, 1.0, 1.0, 0.0)),
        np.interp(time, c, (0.0, 0.0, 0.0, 1.0)),
    ])


def _levels(time: np.ndarray, depth: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    a = _basis(time, corners)
    levels, *_ = np.linalg.lstsq(a, depth, rcond=None)
    return levels, depth - a @ levels


def fit_motion(time: np.ndarray, depth: np.ndarray, *, name: str = "trial") -> Motion:
    """Fit an intrude/hold/withdraw motion to a measured depth trace.

    Parameters
    ----------
    time : ndarray
        Sample times [s], strictly increasing.
    depth : ndarray
        Measured depth [m], positive below the surface, with white noise.
    name : str
        The trial's name, for error messages.

    Returns
    -------
    Motion

    Notes
    -----
    The three depths enter linearly and are solved for exactly at each
    trial of the corners (variable projection); the four corner times are
    found by bounded nonlinear least squares started from a median-filtered
    guess. The corners come out to a few hundredths of a sample for
    0.03 mm depth noise at 10 mm/s and 100 Hz (``tests/estimation/test_calibration.py``).
    """
    t = real_array(time, "time", "s")
    z = real_array(depth, "depth", "m")
    smooth = median_filter(z, size=5, mode="nearest")
    deepest = float(np.max(smooth))
    if deepest <= 0.0:
        raise InputError(f"{name}: the foot never goes below the surface (deepest {deepest * 1e3:.3g} mm); "
                         "expected an intrude/hold/withdraw trial")
    noise = estimate_depth_noise(t, z)
    span = deepest - float(np.min(smooth))
    threshold = max(4.0 * noise, 0.02 * span, 1e-7)
    held = np.flatnonzero(smooth >= deepest - threshold)
    ib, ic = int(held[0]), int(held[-1])
    if ib == 0 or ic >= t.size - 1:
        raise InputError(f"{name}: the depth trace does not go down, hold and come back up; "
                         "expected an intrude/hold/withdraw trial starting above the surface")
    z_start = float(np.median(smooth[:3]))
    z_end = float(np.median(smooth[-3:]))
    before = np.flatnonzero(smooth[:ib] <= z_start + threshold)
    after = np.flatnonzero(smooth[ic:] <= z_end + threshold)
    ia = int(before[-1]) if before.size else 0
    id_ = ic + int(after[0]) if after.size else t.size - 1
    x0 = np.array([t[ia], t[ib], t[ic], t[id_]])
    dt = float(np.median(np.diff(t)))
    lo, hi = float(t[0]), float(t[-1])
    x0 = np.clip(x0, lo, hi)

    def residuals(corners: np.ndarray) -> np.ndarray:
        return _levels(t, z, corners)[1]

    sol = least_squares(residuals, x0, bounds=(lo, hi), x_scale=dt, diff_step=1e-3 * dt / max(abs(hi), 1.0),
                        xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=400)
    corners = np.sort(sol.x)
    levels, res = _levels(t, z, corners)
    motion = Motion(
        corner_time=(float(corners[0]), float(corners[1]), float(corners[2]), float(corners[3])),
        start_depth=float(levels[0]),
        hold_depth=float(levels[1]),
        end_depth=float(levels[2]),
        depth_noise=float(np.sqrt(np.mean(res**2))),
    )
    if motion.start_depth >= 0.0:
        raise InputError(f"{name}: the trial starts {motion.start_depth * 1e3:.3g} mm below the surface; expected "
                         "the foot above it at the start (the force bias is tared from pre-contact samples)")
    if motion.hold_depth <= 0.0 or motion.intrusion_velocity <= 0.0 or motion.withdrawal_velocity <= 0.0:
        raise InputError(f"{name}: the depth trace is not an intrude/hold/withdraw motion "
                         f"(fitted hold depth {motion.hold_depth * 1e3:.3g} mm)")
    return motion


def motion_covariance(time: np.ndarray, motion: Motion) -> np.ndarray:
    """Covariance of :meth:`Motion.vector` from the depth fit, ``sigma_z^2 (J^T J)^-1`` (7 x 7) [s, m].

    ``J`` is the derivative of the fitted depth at the samples with respect
    to the seven motion parameters and ``sigma_z`` the RMS depth residual.
    Zero for a noise-free depth.
    """
    t = real_array(time, "time", "s")
    dt = float(np.median(np.diff(t)))
    v0 = motion.vector()
    steps = np.array([1e-4 * dt] * 4 + [1e-6] * 3)
    cols = []
    for j, h in enumerate(steps):
        e = np.zeros(7)
        e[j] = h
        cols.append((motion.from_vector(v0 + e).depth_at(t) - motion.from_vector(v0 - e).depth_at(t)) / (2 * h))
    jac = np.column_stack(cols)
    cov: np.ndarray = motion.depth_noise**2 * np.linalg.pinv(jac.T @ jac)
    return cov


def tare(time: np.ndarray, force: np.ndarray, motion: Motion, *, name: str = "trial") -> tuple[float, float, int]:
    """The force sensor's bias and noise from the samples before surface contact.

    Parameters
    ----------
    time : ndarray
        Sample times [s].
    force : ndarray
        Measured force [N].
    motion : Motion
        The trial's fitted motion (gives the contact instant).
    name : str
        The trial's name, for error messages.

    Returns
    -------
    bias : float
        Mean force before contact [N]; subtract it from ``force``.
    noise : float
        Standard deviation of the force before contact [N].
    count : int
        Number of pre-contact samples [-]; ``bias`` has the standard error ``noise / sqrt(count)``.
    """
    t = real_array(time, "time", "s")
    dt = float(np.median(np.diff(t)))
    pre = t < motion.contact_time - 0.5 * dt
    n = int(np.count_nonzero(pre))
    if n < MIN_PRECONTACT_SAMPLES:
        raise InputError(f"{name}: only {n} samples before the foot reaches the surface at "
                         f"{motion.contact_time:.3f} s; the force bias is tared from at least "
                         f"{MIN_PRECONTACT_SAMPLES} pre-contact samples: start with the foot above the surface")
    f = real_array(force, "force", "N")[pre]
    return float(np.mean(f)), float(np.std(f, ddof=1)), n


def tare_correction(residual: np.ndarray, precontact: int) -> float:
    """The force offset [N] that best explains a fit's ``residual`` (model - tared force), given the tare.

    The tare (the mean of ``precontact`` samples of noise ``sigma``) leaves
    an unknown offset ``b`` with prior ``N(0, sigma^2 / precontact)``; with
    residuals of the same ``sigma`` its posterior mode is
    ``-sum(residual) / (n + precontact)``. Fits profile these offsets out
    (variable projection) and add the prior as one residual row
    ``b sqrt(precontact)`` per trial, so that their standard errors include
    the tare's uncertainty. Subtract the offset from the tared force (add
    it to the bias).
    """
    # no rows and no tare (a trial starting in the mud that never withdraws, in the withdrawal window): no offset
    return -float(np.add.reduce(residual)) / max(residual.size + precontact, 1)  # np.sum's sum, without its dispatch


@dataclass(frozen=True, eq=False)
class PreparedTrial:
    """A trial ready for fitting: tared force and the fitted, noise-free motion at the sample times.

    Attributes
    ----------
    trial : Trial
        The measured trial.
    motion : Motion or None
        Its fitted intrude/hold/withdraw motion (protocol trials); None for
        a trial of any other motion (the general path).
    depth : ndarray
        The depth the model follows [m]: ``motion.depth_at(trial.time)``,
        or the branch-consistent denoised depth of
        :func:`~mudforce.estimation.calibration.branches.denoise_depth`.
    force : ndarray
        Measured force minus the bias [N].
    bias : float
        The sensor bias removed [N] (0 when it is estimated by the fit instead).
    force_noise : float
        Force noise [N]: from the pre-contact samples (protocol), else from
        the force's high-frequency content
        (:func:`~mudforce.estimation.calibration.branches.estimate_force_noise`).
    precontact : int
        Number of samples the bias was tared from [-]; 0 when the trial
        starts in the mud and the fit estimates the bias as a free parameter.
    motion_covariance : ndarray or None
        Covariance of ``motion.vector()`` (7 x 7) [s, m], see :func:`motion_covariance`.
    reversal_index : int
        Number of samples before the first withdrawal (samples
        ``[:reversal_index]`` are approach, intrusion and hold).
    reversal_time : float
        The first reversal (start of the first withdrawal in the mud) [s]; NaN if none.
    velocity : float
        Intrusion speed [m/s]: the protocol's descent, else the median
        downward speed while the foot moves down in the mud (NaN if it never does).
    depth_noise : float
        Noise left on :attr:`depth` [m]: the measured depth noise on the
        general path (the denoised depth keeps most of it), 0 for a fitted
        protocol motion (whose uncertainty enters through ``motion_covariance``).
    unresolved_depth : float
        The depth's high-frequency content above its white noise [m] (``sqrt(whole^2 - quiet^2)``, the
        differences over the whole record against those of its quietest stretches): a foot's ringing and impacts
        the rate does not resolve, which the branch labels and the denoising follow as motion and the noise floor
        holds as the model's error at this rate (:func:`noise_floor`). 0 unless prepared with
        ``depth_noise_from="quiet"`` and the noise estimated.
    touchdown : tuple of 2 int, or None
        For a trial that starts in the mud (general path), the samples ``[a, b)`` of its first touchdown from
        above: ``a`` the last sample clear of the surface before it, reached by a step down (so the model is
        FREE there, whatever came before), ``b`` the end of the first withdrawal step in the mud after it. The
        fit's intrusion stage fits these samples, simulated from ``a``, instead of ``[:reversal_index]``
        (a sway of relaxed mud, which hardly shows the intrusion parameters). None otherwise.
    """

    trial: Trial
    motion: Motion | None
    depth: np.ndarray
    force: np.ndarray
    bias: float
    force_noise: float
    precontact: int
    motion_covariance: np.ndarray | None
    reversal_index: int
    reversal_time: float = math.nan
    velocity: float = math.nan
    depth_noise: float = 0.0
    touchdown: tuple[int, int] | None = None
    unresolved_depth: float = 0.0

    @property
    def intrusion_window(self) -> tuple[int, int]:
        """The samples ``[a, b)`` the intrusion stage fits: :attr:`touchdown`, else ``[0, reversal_index)`` [-]."""
        return self.touchdown if self.touchdown is not None else (0, self.reversal_index)

    @property
    def bias_estimated(self) -> bool:
        """True when the bias is a free parameter of the fit (no pre-contact samples to tare from)."""
        return self.precontact == 0

    @property
    def time(self) -> np.ndarray:
        """Sample times [s]."""
        return self.trial.time

    @property
    def bias_stderr(self) -> float:
        """Standard error of the tare :attr:`bias` [N] (infinite when the bias is estimated by the fit)."""
        return self.force_noise / math.sqrt(self.precontact) if self.precontact else math.inf


def snap_reversal(time: np.ndarray, force: np.ndarray, motion: Motion, *, ambiguity: float = 0.25) -> Motion:
    """Settle which sample is the first of the withdrawal when the motion alone cannot tell.

    The model's force drops by the whole ``f_e2 S`` (tens of newtons) at
    the first sample of the withdrawal branch, so one misassigned sample
    costs that much. When the fitted reversal lies within ``ambiguity``
    sample steps of a sample time, the depth cannot tell on which side of
    that sample the reversal is (on a uniform grid the true reversal often
    falls exactly on a sample); the force can: the first withdrawal sample
    is the one with the larger force drop. The reversal is moved just
    inside the interval that the force picks.

    Parameters
    ----------
    time : ndarray
        Sample times [s].
    force : ndarray
        Measured force [N].
    motion : Motion
        The fitted motion.
    ambiguity : float
        Distance from a sample, in sample steps, below which the force decides [-].
    """
    t = np.asarray(time, dtype=np.float64)
    f = np.asarray(force, dtype=np.float64)
    tr = motion.reversal_time
    j = int(np.argmin(np.abs(t - tr)))  # the sample nearest the reversal
    if j < 2 or j >= t.size - 1:
        return motion
    dt = t[j + 1] - t[j]
    if abs(t[j] - tr) > ambiguity * dt:
        return motion
    # first withdrawal sample: j (reversal inside (t[j-1], t[j])) or j + 1 (inside (t[j], t[j+1]))
    drop_j = f[j] - f[j - 1]
    drop_next = f[j + 1] - f[j]
    eps = 1e-3 * dt
    new = t[j] - eps if drop_j < drop_next else t[j] + eps
    ta, tb, _, td = motion.corner_time
    if not tb < new < td:
        return motion
    return replace(motion, corner_time=(ta, tb, float(new), td))


@njit(cache=True, nogil=True)
def _increasing_sse(z: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """``out[k]``: the least sum of squares [m^2] of ``z[:k] - g`` over non-decreasing ``g`` (``k = 0 .. n``).

    Pool-adjacent-violators run once along ``z``, the blocks' sums of squares kept as it goes (merging blocks of
    ``n1, n2`` samples and means ``m1, m2`` adds ``n1 n2 / (n1 + n2) (m1 - m2)^2``).
    """
    n = z.size
    out = np.zeros(n + 1)
    mean = np.empty(n)
    count = np.empty(n)
    top = 0
    total = 0.0
    for i in range(n):
        mean[top] = z[i]
        count[top] = 1.0
        top += 1
        while top > 1 and mean[top - 2] > mean[top - 1]:
            n1, n2 = count[top - 2], count[top - 1]
            d = mean[top - 2] - mean[top - 1]
            total += n1 * n2 / (n1 + n2) * d * d
            mean[top - 2] = (n1 * mean[top - 2] + n2 * mean[top - 1]) / (n1 + n2)
            count[top - 2] = n1 + n2
            top -= 1
        out[i + 1] = total
    return out


def _unimodal_rms(depth: np.ndarray) -> float:
    """The least RMS [m] of ``depth`` about any sequence that rises and then falls (unimodal regression).

    Every intrude/hold/withdraw motion that :func:`fit_motion` accepts (start and end below the hold) rises and
    then falls, so its RMS depth residual is at least this: a floor that tells a gait from a protocol without the
    corner search (speed plumbing for :func:`is_protocol`; the answer is the same).
    """
    z = np.asarray(depth, dtype=float)
    if z.size == 0:
        return 0.0
    rising = _increasing_sse(np.ascontiguousarray(z))
    falling = _increasing_sse(np.ascontiguousarray(z[::-1]))[::-1]
    return math.sqrt(max(float(np.min(rising + falling)), 0.0) / z.size)


def is_protocol(trial: Trial) -> Motion | None:
    """The trial's fitted motion if it is an intrude/hold/withdraw protocol starting above the surface, else None.

    A protocol is recognised when :func:`fit_motion` succeeds and the depth
    lies on the fitted piecewise-linear motion to within 1.5 times the
    depth noise (a sway, a second step or a re-push leaves far more). A
    depth farther than that from every rise-then-fall (:func:`_unimodal_rms`)
    is no protocol without the fit.
    """
    noise = estimate_depth_noise(trial.time, trial.depth)
    limit = 1.5 * noise + 1e-7
    if _unimodal_rms(trial.depth) > limit * (1.0 + 1e-6):  # (a margin far above the sums' rounding)
        return None
    try:
        motion = fit_motion(trial.time, trial.depth, name=trial.name)
    except InputError:
        return None
    if motion.depth_noise > limit:
        return None
    return motion


def _prepare_protocol(trial: Trial, motion: Motion) -> PreparedTrial:
    motion = snap_reversal(trial.time, trial.force, motion)
    bias, noise, count = tare(trial.time, trial.force, motion, name=trial.name)
    return PreparedTrial(
        trial=trial,
        motion=motion,
        depth=motion.depth_at(trial.time),
        force=trial.force - bias,
        bias=bias,
        force_noise=noise,
        precontact=count,
        motion_covariance=motion_covariance(trial.time, motion),
        reversal_index=int(np.searchsorted(trial.time, motion.reversal_time, side="right")),
        reversal_time=motion.reversal_time,
        velocity=motion.intrusion_velocity,
    )


def _prepare_general(trial: Trial, known_depth_noise: float | None = None, quiet: bool = False) -> PreparedTrial:
    t, z, f = trial.time, trial.depth, trial.force
    # third divided differences: blind to the stances' smooth sway, unlike a line through three samples
    depth_noise = estimate_force_noise(t, z) if known_depth_noise is None else known_depth_noise
    unresolved = 0.0
    if quiet and known_depth_noise is None:  # the noise of the quietest stretches; the rest is motion
        white = estimate_quiet_noise(t, z)
        unresolved = math.sqrt(max(depth_noise**2 - white**2, 0.0))
        depth_noise = white
    if depth_noise < CLEAN_DEPTH_M:  # a computed, noise-free trajectory: the paper's exact rule
        depth_noise = 0.0
    # the sensor's noise where the force is simplest: the foot clear of the mud (a robot's foot in the mud flicks
    # between the rest band's edges between the samples, which the differences would take for noise)
    force_noise = estimate_force_noise(t, f, where=z < -3.0 * depth_noise if depth_noise > 0.0 else z < 0.0)
    labels = label_branches(t, z, f, depth_noise=depth_noise, force_noise=force_noise)
    labels = creep_withdrawals(t, z, labels, depth_noise)
    labels = rest_steps(t, z, labels, depth_noise, f, force_noise)
    depth = denoise_depth(z, labels, t if depth_noise > 0.0 else None, noise=depth_noise)
    inside = depth > 0.0
    if not np.any(inside):
        raise InputError(f"{trial.name}: the foot never goes below the surface (deepest "
                         f"{float(np.max(depth)) * 1e3:.3g} mm); nothing to fit")
    first_in = int(np.argmax(inside))
    bias, count = 0.0, 0
    if first_in >= MIN_PRECONTACT_SAMPLES:  # tare from the samples before the first contact
        bias, count = float(np.mean(f[:first_in])), first_in
    withdrawing = np.flatnonzero((labels < 0) & inside[:-1])
    reversal_index = int(withdrawing[0]) + 1 if withdrawing.size else t.size
    down = (labels > 0) & inside[:-1] & (np.diff(depth) > 0)
    speeds = np.diff(depth)[down] / np.diff(t)[down]
    touchdown = _first_touchdown(depth, inside, withdrawing) if first_in == 0 else None
    return PreparedTrial(
        trial=trial,
        motion=None,
        depth=depth,
        force=f - bias,
        bias=bias,
        force_noise=force_noise,
        precontact=count,
        motion_covariance=None,
        reversal_index=reversal_index,
        reversal_time=float(t[reversal_index - 1]) if withdrawing.size else math.nan,
        velocity=float(np.median(speeds)) if speeds.size else math.nan,
        depth_noise=depth_noise,
        touchdown=touchdown,
        unresolved_depth=unresolved,
    )


def _first_touchdown(depth: np.ndarray, inside: np.ndarray, withdrawing: np.ndarray) -> tuple[int, int] | None:
    """Samples ``[a, b)`` of the first touchdown from above, from a sample where the model is FREE (ours).

    ``a``: the last sample clear of the surface (``depth <= 0``) before an entry, reached by a step down: by
    the contact state machine (docs/model.md) a step down that ends clear of the surface leaves the model
    FREE from any state, so the force from ``a`` on does not depend on what came before it. ``b``: one past
    the first withdrawal step in the mud after ``a`` (the end of the trial if none; ``withdrawing``: the indices of
    the withdrawal steps in the mud, ascending). None without such an entry.
    """
    steps = np.diff(depth)
    entries = np.flatnonzero(~inside[1:-1] & inside[2:] & (steps[:-1] > 0.0)) + 1
    if not entries.size:
        return None
    a = int(entries[0])
    later = withdrawing[withdrawing >= a]
    return a, (int(later[0]) + 1 if later.size else depth.size)


def prepare_trial(trial: Trial, *, protocol: bool | None = None, depth_noise: float | None = None,
                  depth_noise_from: str = "all") -> PreparedTrial:
    """Ready a trial for fitting: the depth the model follows, the branch at every step, the force tared.

    Parameters
    ----------
    trial : Trial
        A trial of any motion.
    protocol : bool, optional
        None (default): use the protocol refinement when the trial is an
        intrude/hold/withdraw protocol (:func:`is_protocol`), else the general
        path. True: require a protocol. False: always the general path.
    depth_noise : float, optional
        The depth's noise [m] (standard deviation), when the recording system knows it (the surface estimate's
        and the leg kinematics'); used on the general path in place of the estimate from the depth's third
        differences. At 50-100 Hz a robot foot's ringing and impacts between the samples make those differences
        read 2-60 times the true noise (docs/estimation.md), and the branch labels then distrust real steps of
        millimetres. None (default): estimated. A protocol trial fits its own motion and ignores it.
    depth_noise_from : str
        How the depth noise is estimated when not given: ``"all"`` (default; fit's), from the third differences
        over the whole record
        (:func:`~mudforce.estimation.calibration.branches.estimate_force_noise`); ``"quiet"`` (identify's), from
        its quietest stretches (:func:`~mudforce.estimation.calibration.branches.estimate_quiet_noise`), the
        excess of the whole over it kept as :attr:`PreparedTrial.unresolved_depth`.

    Notes
    -----
    The general path (:mod:`mudforce.estimation.calibration.branches`) labels each
    step's branch from the depth and the force's jumps, follows a denoised
    depth consistent with those labels, tares the force from the samples
    before the first contact when the trial starts above the surface
    (otherwise the fit estimates the bias), and measures the force noise
    from the force's high-frequency content. The protocol refinement fits
    the four corners of the motion and carries their uncertainty into the
    standard errors (``docs/calibration.md``).
    """
    if depth_noise_from not in ("all", "quiet"):
        raise InputError(f'{trial.name}: depth_noise_from must be "all" or "quiet", got {depth_noise_from!r}')
    if depth_noise is not None and not (is_real(depth_noise) and 0.0 <= depth_noise <= MAX_DEPTH_NOISE_M):
        # the value in metres where it is one ('1' was "got '1' m", 10**5000 "got an integer of 16610 bits m")
        got = (f"{shown(depth_noise)} m" if is_real(depth_noise) and abs(depth_noise) < 1e300
               else shown(depth_noise) if is_real(depth_noise) else type(depth_noise).__name__)
        raise InputError(f"{trial.name}: depth noise must be between 0 and {MAX_DEPTH_NOISE_M * 1e3:g} mm "
                         f"(e.g. 0.03 mm, given in metres: 3e-05), got {got}")
    if protocol is not None and not isinstance(protocol, (bool, np.bool_)):
        raise InputError(f"{trial.name}: protocol must be True, False or None, got {protocol!r}")
    quiet = depth_noise_from == "quiet"
    if protocol is not None and not protocol:
        return _prepare_general(trial, depth_noise, quiet)
    if protocol:
        motion = fit_motion(trial.time, trial.depth, name=trial.name)
        return _prepare_protocol(trial, motion)
    found = is_protocol(trial)
    return _prepare_protocol(trial, found) if found is not None else _prepare_general(trial, depth_noise, quiet)


def noise_floor(prepared: PreparedTrial, force: np.ndarray, force_at: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """Per-sample variance [N^2] a perfect model would still leave: force noise plus depth noise carried through.

    ``force_at(depth) -> force [N]`` is the fitted model on the trial's
    time; its sensitivity to the depth (central difference over 1 um)
    times :attr:`PreparedTrial.depth_noise` is the part of the residual
    that the depth noise explains (``force`` is the model force at the
    trial's depth, unused beyond its size). Its mean square root over all
    samples is the floor that an RMSE can reach. The depth's unresolved
    motion (:attr:`PreparedTrial.unresolved_depth`, ours) is carried through
    the same sensitivity: at this rate the model cannot follow it, and it is
    a model error at the data's rate, not another mud.
    """
    return noise_floor_parts(prepared, force, force_at)[0]


def noise_floor_parts(prepared: PreparedTrial, force: np.ndarray,
                      force_at: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """:func:`noise_floor`'s per-sample variance [N^2], and the depth noise's own part of it [N^2].

    The second is ``(dF/dz * depth_noise)^2``: the share of the floor that
    is error in the depth, the regressor, rather than in the force (what
    :func:`mudforce.estimation.calibration.fit_condition` warns of when it
    is most of the floor).
    """
    h = 1e-6
    variance = np.full(force.size, prepared.force_noise**2 if math.isfinite(prepared.force_noise) else 0.0)
    depth_part = np.zeros(force.size)
    if prepared.depth_noise > 0.0 or prepared.unresolved_depth > 0.0:
        sens = (force_at(prepared.depth + h) - force_at(prepared.depth - h)) / (2.0 * h)
        if prepared.unresolved_depth > 0.0:
            variance = variance + (sens * prepared.unresolved_depth) ** 2
        depth_part = (sens * prepared.depth_noise) ** 2
        variance = variance + depth_part
    return variance, depth_part


#: The share of the samples of clear intrusion whose force lies below its tare from which a trial's force reads as
#: sign-flipped [-] (ours): in the family the mud pushes back on a foot going in (none of those samples lies below on
#: the test suite's and synthesize's trials); a force of noise alone puts about half there.
_FLIPPED_SHARE = 0.9
#: Fewest samples of clear intrusion the sign check reads [-].
_FLIPPED_MIN_SAMPLES = 5


def _force_sign_share(prepared: PreparedTrial) -> tuple[float, int]:
    """The share [-] of the samples of clear intrusion (the foot going down, deeper than half the trial's deepest)
    whose force lies below its tare, and their count [-]; (NaN, 0) where it cannot be read (no tare: the trial never
    leaves the mud)."""
    z, f = prepared.depth, prepared.force
    deepest = float(np.max(z)) if z.size else 0.0
    if not deepest > 0.0:
        return math.nan, 0
    if prepared.precontact:
        level = 0.0  # the force is tared from the samples before contact
    else:  # the foot above the surface later on, if ever
        free = z < -3.0 * prepared.depth_noise if prepared.depth_noise > 0.0 else z < 0.0
        if np.count_nonzero(free) < MIN_PRECONTACT_SAMPLES:
            return math.nan, 0
        level = float(np.median(f[free]))
    step = np.diff(z)
    clear = np.flatnonzero((step > 3.0 * prepared.depth_noise) & (step > 0.0) & (z[1:] > 0.5 * deepest)) + 1
    if clear.size == 0:
        return math.nan, 0
    return float(np.mean(f[clear] < level)), int(clear.size)


def _force_sign_warning(prepared: PreparedTrial) -> str:
    """One line where the trial's force looks sign-flipped (most samples of clear intrusion below the tare), else
    ``""``: identify's and fit's check, read before their fits' general misfit message."""
    share, count = _force_sign_share(prepared)
    if count < _FLIPPED_MIN_SAMPLES or not share >= _FLIPPED_SHARE:
        return ""
    return (f"{prepared.trial.name}: the force lies below its tare on {share:.0%} of the {count} samples where the "
            "foot goes down well below the surface: it looks sign-flipped; mudforce expects the force + up (the mud "
            "pushing back on a foot going in reads positive): negate the force column if compression reads negative")
