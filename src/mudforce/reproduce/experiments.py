"""The synthetic experiments of :mod:`mudforce.reproduce`: what is made (:class:`ReproduceConfig`) and making it.

No experimental data from Chen, Yi & Shan (arXiv:2403.02617) is public, so
the report works on data the project can make. For each water content,
speed and repeat, one trial of the paper's protocol (approach from 5 mm
above the surface, intrude to 20 mm, hold 6 s, withdraw to 20 mm above the
surface, 100 Hz) is made by :func:`mudforce.estimation.calibration.synthesize` from
Table I (interpolated) with force noise, depth noise and a force-sensor
bias. Each trial's mud is prepared afresh, so its parameters scatter about
the Table I row (lognormal, ``repeat_scatter`` relative standard deviation
on :data:`SCATTERED`): repeats differ as real repeats do, and the fit
cannot reach the noise floor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mudforce.errors import InputError, finite_number, number_within, real_array, true_or_false
from mudforce.estimation.calibration.dataset import Dataset, Trial
from mudforce.estimation.calibration.fit import FitOptions
from mudforce.estimation.calibration.synth import repeat_count, synthesize, trial_name
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.protocol import Protocol
from mudforce.reproduce._checks import check_seed

__all__ = ["SCATTERED", "ReproduceConfig", "make_experiments"]

#: Parameters that scatter from repeat to repeat in the synthetic experiments.
SCATTERED: tuple[str, ...] = ("k_m_i", "b_m_i", "k_m_w", "b_m_w", "alpha", "sigma_y")
#: Most samples the report's trials hold, all together [-]: as many as one ``mudforce synth`` writes (its
#: ``MAX_SAMPLES``), 89 times the full report's 56,385 (the quick one's 10,360); each is simulated, then fitted
#: again and again.
MAX_SAMPLES = 5_000_000
#: The protocol's approach from above the surface [m], as synthesize makes it (and to_dict records it).
_APPROACH = 0.005


def _is_reference(w: float) -> bool:
    """Whether ``w`` is the reference water content 0.25 of Figs. 2, 6 and 11, to float rounding (0.35 - 0.1 is
    0.24999999999999997): the one test of it, for the configuration's check and the figures' look-up."""
    return abs(w - 0.25) < 1e-9


def _distinct_labels(name: str, values: list[float], scale: float) -> None:
    """Refuse two values that print alike to 6 significant digits: ``summary.json`` keys them by ``f"{v:g}"`` and
    the trials are named by ``f"{v * scale:g}"`` (:func:`trial_name`); two alike were two trials of one name and one
    key that kept only the last one's numbers."""
    for label in (lambda v: f"{v:g}", lambda v: f"{v * scale:g}"):
        seen: dict[str, float] = {}
        for v in values:
            if label(v) in seen:
                raise InputError(f"{name} {seen[label(v)]!r} and {v!r} are the same to 6 significant digits "
                                 f"(both {v:g} in summary.json and the trials' names); give values that differ "
                                 "within 6 digits")
            seen[label(v)] = v


@dataclass(frozen=True)
class ReproduceConfig:
    """What :func:`reproduce` makes and how hard it fits.

    Attributes
    ----------
    water_contents : tuple of float
        Volume fractions [-]; must include the reference 0.25 (Figs. 2, 6, 11).
    velocities : tuple of float
        Intrusion and withdrawal speeds [m/s]; the first is the reference speed.
    repeats : int
        Trials per (water content, speed), in [1, :data:`mudforce.estimation.calibration.dataset.MAX_REPEATS`] (1000).
    rate : float
        Sampling rate [Hz]. All the trials together (water contents x speeds x repeats at this rate) hold at most
        :data:`MAX_SAMPLES` samples (5 million; the full report 56,385).
    repeat_scatter : float
        Relative standard deviation of the trial-to-trial scatter of
        :data:`SCATTERED` [-] (lognormal), in [0, 1].
    force_noise, depth_noise, bias : float
        Sensor imperfections: white force noise [N], white depth noise [m], force bias [N].
    fit_options : FitOptions
        Optimiser budget of the per-water-content fits.
    velocity_fit_options : FitOptions
        Optimiser budget of the per-speed fits (Fig. 10).
    seed : int
        Seeds the synthetic data and the fits.
    quick : bool
        Whether this is the reduced ``--quick`` configuration (recorded in the outputs).
    """

    water_contents: tuple[float, ...] = (0.15, 0.20, 0.25, 0.30, 0.35)
    velocities: tuple[float, ...] = (0.01, 0.02, 0.03, 0.04)
    repeats: int = 3
    rate: float = 100.0
    repeat_scatter: float = 0.02
    force_noise: float = 0.2
    depth_noise: float = 3e-5
    bias: float = 0.5
    fit_options: FitOptions = field(default_factory=FitOptions)
    velocity_fit_options: FitOptions = field(default_factory=FitOptions)
    seed: int = 0
    quick: bool = False

    def __post_init__(self) -> None:
        check_seed(self.seed)
        object.__setattr__(self, "quick", true_or_false(self.quick, "quick"))  # numpy's bool as bool (JSON)
        # checked here, not where they are first used (a TypeError or AttributeError in make_experiments, a
        # scatter of -1 taken as 0, repeats=10**400 run for ever, a repeated speed made once and fitted twice)
        for name, unit in (("water_contents", "-"), ("velocities", "m/s")):
            values = real_array(getattr(self, name), name, unit)
            if values.ndim != 1:
                raise InputError(f"{name} must be a sequence of numbers [{unit}], got shape {values.shape}")
            if np.unique(values).size != values.size:
                raise InputError(f"{name} repeats a value; give each once (each makes its own trials)")
            _distinct_labels(name, values.tolist(), 100.0 if name == "water_contents" else 1e3)
        if not any(_is_reference(w) for w in self.water_contents):
            raise InputError("the water contents must include 0.25 (the paper's Figs. 2, 6 and 11)")
        if len(self.velocities) < 1:
            raise InputError("reproduce needs at least one speed and one repeat")
        repeat_count(self.repeats)
        number_within(self.repeat_scatter, "repeat_scatter", 0.0, 1.0, "-")
        # what make_experiments refuses, refused here: it was refused there, after reproduce() had made the output
        # folder's parents, in messages that did not name the field (a rate of -1: 'sampling rate must be ...')
        for w in self.water_contents:
            MudParameters.from_water_content(w)  # within Table I's range
        for name, speeds in (("rate", (0.01,)), ("velocities", self.velocities)):
            for v in speeds:
                try:  # the protocol's own checks of the speed and the rate, as synthesize makes it
                    Protocol.paper(velocity=v, rate=self.rate)
                except InputError as exc:
                    raise InputError(f"{name}: {exc}") from None
        self._check_total()
        finite_number(self.force_noise, "force_noise", "N", nonnegative=True)
        finite_number(self.depth_noise, "depth_noise", "m", nonnegative=True)
        finite_number(self.bias, "bias", "N")
        for name in ("fit_options", "velocity_fit_options"):
            if not isinstance(getattr(self, name), FitOptions):
                raise InputError(f"{name} must be a FitOptions, got {type(getattr(self, name)).__name__}")

    def _check_total(self) -> None:
        """Refuse, before any work, trials that hold more than :data:`MAX_SAMPLES` samples together: each trial was
        bounded (the protocol's 10 million), but not their sum (a rate of 1e5 Hz at 1 and 2 mm/s with 1000 repeats:
        54.75 billion samples, accepted)."""
        per_speed = [math.ceil(Protocol.paper(velocity=v, rate=self.rate, approach=_APPROACH).duration * self.rate
                               - 1e-9) + 1 for v in self.velocities]  # the protocol's samples, as sample() makes them
        total = self.repeats * len(self.water_contents) * sum(per_speed)
        if total > MAX_SAMPLES:
            raise InputError(f"the report would simulate {total:,} samples ({len(self.water_contents)} water "
                             f"contents x {len(self.velocities)} speeds x {self.repeats} repeats at {self.rate:g} Hz), "
                             f"more than {MAX_SAMPLES:,}; lower the rate, the repeats or the number of speeds, or "
                             "raise the slowest speeds")

    @classmethod
    def full(cls, seed: int = 0) -> ReproduceConfig:
        """Five water contents x four speeds (10-40 mm/s) x three repeats at 100 Hz; default fit budget."""
        return cls(seed=seed)

    @classmethod
    def quick_config(cls, seed: int = 0) -> ReproduceConfig:
        """Five water contents x two speeds (10, 30 mm/s) x two repeats at 50 Hz, with a small optimiser budget."""
        small = FitOptions(starts=1, popsize=5, maxiter=8, max_nfev=60)
        return cls(velocities=(0.01, 0.03), repeats=2, rate=50.0, fit_options=small, velocity_fit_options=small,
                   seed=seed, quick=True)

    @property
    def reference_velocity(self) -> float:
        """The speed of the single-condition figures (Figs. 2, 6, 11) [m/s]."""
        return self.velocities[0]

    def to_dict(self) -> dict[str, Any]:
        """The configuration as JSON-ready values (SI)."""
        def opts(o: FitOptions) -> dict[str, Any]:
            return {"starts": o.starts, "popsize": o.popsize, "maxiter": o.maxiter, "tol": o.tol,
                    "max_nfev": o.max_nfev}

        return {
            "quick": self.quick, "seed": self.seed, "water_contents": list(self.water_contents),
            "velocities_m_s": list(self.velocities), "repeats": self.repeats,
            "repeat_scatter": self.repeat_scatter, "force_noise_N": self.force_noise,
            "depth_noise_m": self.depth_noise, "bias_N": self.bias,
            "protocol": {"depth_m": 0.02, "hold_s": 6.0, "approach_m": _APPROACH, "rise_m": 0.02,
                         "rate_Hz": self.rate},
            "fit_options": opts(self.fit_options), "velocity_fit_options": opts(self.velocity_fit_options),
        }


# ---------------------------------------------------------------------------- making the trials
def _scattered(params: MudParameters, rng: np.random.Generator, scatter: float) -> MudParameters:
    if scatter <= 0.0:
        return params
    factors = np.exp(scatter * rng.standard_normal(len(SCATTERED)))
    changes = {n: getattr(params, n) * float(f) for n, f in zip(SCATTERED, factors, strict=True)}
    return params.replace(**changes, source=f"{params.source}, scattered {scatter:.0%} for one trial")


def make_experiments(config: ReproduceConfig, foot: Foot | None = None) -> tuple[Dataset, dict[str, MudParameters]]:
    """The synthetic dataset: one trial per (water content, speed, repeat), each from freshly scattered mud.

    Returns
    -------
    dataset : Dataset
        Trials ordered by water content, speed, repeat; named like ``w25_v10_r1.csv``.
    truths : dict
        Trial name -> the parameters that trial was simulated with.
    """
    foot = Foot.paper() if foot is None else foot
    rng = np.random.default_rng([config.seed, 20240305])
    trials: dict[tuple[float, float, int], Trial] = {}
    truths: dict[str, MudParameters] = {}
    for vi, v in enumerate(config.velocities):
        for r in range(1, config.repeats + 1):
            params = {w: _scattered(MudParameters.from_water_content(w), rng, config.repeat_scatter)
                      for w in config.water_contents}
            made = synthesize(water_contents=config.water_contents, velocities=(v,), repeats=1,
                              force_noise=config.force_noise, depth_noise=config.depth_noise, bias=config.bias,
                              seed=config.seed * 1000 + vi * 100 + r, foot=foot, parameters=params,
                              rate=config.rate)
            for tr in made.trials:
                name = trial_name(tr.water_content, v, r)
                trials[(tr.water_content, v, r)] = Trial(name, tr.water_content, tr.time, tr.depth, tr.force, v, r)
                truths[name] = params[tr.water_content]
    ordered = tuple(trials[k] for k in sorted(trials))
    extra = {"synthetic": {"reproduce": config.to_dict()}}
    return Dataset(foot=foot, trials=ordered, source="mudforce reproduce", extra=extra), truths
