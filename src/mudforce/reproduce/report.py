"""The report of :mod:`mudforce.reproduce`: synthetic experiments, fits, figures, ``report.html``, ``summary.json``.

No experimental data from Chen, Yi & Shan (arXiv:2403.02617) is public, so
:func:`reproduce` works the way the paper did, on data the project can make:

1. **Synthetic experiments.** For each water content, speed and repeat, one
   trial of the paper's protocol (approach from 5 mm above the surface,
   intrude to 20 mm, hold 6 s, withdraw to 20 mm above the surface, 100 Hz)
   is made by :func:`mudforce.calibration.synthesize` from Table I
   (interpolated) with force noise, depth noise and a force-sensor bias.
   Each trial's mud is prepared afresh, so its parameters scatter about the
   Table I row (lognormal, ``repeat_scatter`` relative standard deviation on
   ``k_m_i, b_m_i, k_m_w, b_m_w, alpha, sigma_y``): repeats differ as real
   repeats do, and the fit cannot reach the noise floor.
2. **Calibration.** The paper's model is fitted per water content (all
   speeds: "Table I as fitted") and per (water content, speed) (Fig. 10)
   with :func:`mudforce.calibration.fit_condition`; the baselines of
   :mod:`mudforce.baselines` are fitted on the same trials.
3. **Report.** ``report.html`` with PNG figures beside it, each captioned
   with the paper's figure it corresponds to, and ``summary.json``.

Everything is deterministic for a given seed: the fits are seeded, the
figures are rendered without timestamps or version metadata, and the
numbers in ``summary.json`` are rounded to 6 significant digits. Parallel
fits (``jobs > 1``) give the same result as serial ones.
"""

from __future__ import annotations

import html
import json
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mudforce.baselines import BASELINE_NAMES, granular_rft_force
from mudforce.calibration.dataset import Dataset, Trial
from mudforce.calibration.fit import ConditionFit, FitOptions, TrialFit, fit_condition
from mudforce.calibration.report import error_profile
from mudforce.calibration.synth import synthesize, trial_name
from mudforce.errors import InputError, positive_int
from mudforce.foot import Foot
from mudforce.io import atomic_write_text
from mudforce.parameters import CHEN2024, TABLE_I, TABLE_I_RMSE_N, MudParameters
from mudforce.progress import Progress
from mudforce.reproduce._checks import check_output_dir, check_seed
from mudforce.simulation import simulate

__all__ = [
    "POORLY_DETERMINED",
    "SCATTERED",
    "VELOCITY_FREE",
    "ReproduceConfig",
    "ReproduceResult",
    "determined",
    "make_experiments",
    "reproduce",
]

#: Parameters that scatter from repeat to repeat in the synthetic experiments.
SCATTERED: tuple[str, ...] = ("k_m_i", "b_m_i", "k_m_w", "b_m_w", "alpha", "sigma_y")

#: Paper units for display: name -> (factor from SI, unit).
_PAPER_UNITS: dict[str, tuple[float, str]] = {
    "k_m_i": (1e-6, "MPa/m"), "b_m_i": (1e-6, "MPa s/m"), "k_m_w": (1e-6, "MPa/m"), "b_m_w": (1e-6, "MPa s/m"),
    "alpha": (1e-6, "MPa"), "beta": (1.0, "-"), "sigma_y": (1e-3, "kPa"), "zeta": (1.0, "-"),
    "omega_0": (1.0, "rad/s"),
}
_NINE = tuple(_PAPER_UNITS)
_MODEL_LABELS = {"mud_model": "mud model (Chen et al.)", "granular_rft": "granular RFT", "drft": "dynamic RFT",
                 "maxwell_only": "Maxwell only"}
_W_COLOURS = {0.15: "#1b4f72", 0.20: "#2e86c1", 0.25: "#28b463", 0.30: "#f39c12", 0.35: "#c0392b"}


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
        Trials per (water content, speed).
    rate : float
        Sampling rate [Hz].
    repeat_scatter : float
        Relative standard deviation of the trial-to-trial scatter of
        :data:`SCATTERED` [-] (lognormal).
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
        if not any(abs(w - 0.25) < 1e-9 for w in self.water_contents):
            raise InputError("the water contents must include 0.25 (the paper's Figs. 2, 6 and 11)")
        if not self.velocities or self.repeats < 1:
            raise InputError("reproduce needs at least one speed and one repeat")

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
            "protocol": {"depth_m": 0.02, "hold_s": 6.0, "approach_m": 0.005, "rise_m": 0.02, "rate_Hz": self.rate},
            "fit_options": opts(self.fit_options), "velocity_fit_options": opts(self.velocity_fit_options),
        }


@dataclass(frozen=True, eq=False)
class ReproduceResult:
    """What :func:`reproduce` computed and wrote.

    Attributes
    ----------
    config : ReproduceConfig
    dataset : Dataset
        The synthetic experiments.
    truths : dict
        Trial name -> the :class:`MudParameters` it was made with.
    table_fits : dict
        Water content -> fit of the paper's model on all its trials.
    velocity_fits : dict
        (water content, speed) -> fit of the paper's model on that condition's trials.
    baseline_fits : dict
        Baseline name -> water content -> fit.
    summary : dict
        The content of ``summary.json``.
    figures : list of (file, paper figure, caption)
    """

    config: ReproduceConfig
    dataset: Dataset
    truths: dict[str, MudParameters]
    table_fits: dict[float, ConditionFit]
    velocity_fits: dict[tuple[float, float], ConditionFit]
    baseline_fits: dict[str, dict[float, ConditionFit]]
    summary: dict[str, Any]
    figures: list[tuple[str, str, str]]


# ---------------------------------------------------------------------------- synthetic experiments
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


# ---------------------------------------------------------------------------- fits
_Job = tuple[str, str, float, float]  # (kind, model, water content [-], speed [m/s]; 0 for all speeds)

#: Parameters fitted per speed (Fig. 10); the others are held at the water content's fit.
VELOCITY_FREE: tuple[str, ...] = ("alpha", "beta", "sigma_y")


@dataclass(frozen=True, eq=False)
class _Work:
    job: _Job
    trials: tuple[Trial, ...]
    seed: int
    options: FitOptions
    fixed: Mapping[str, float] | None = None
    start: Mapping[str, float] | None = None


def _fit_job(work: _Work, foot: Foot) -> ConditionFit:
    if work.fixed is None:
        return fit_condition(work.trials, foot, model=work.job[1], seed=work.seed, options=work.options)
    return fit_condition(work.trials, foot, model=work.job[1], free=VELOCITY_FREE, fixed=work.fixed,
                         start=work.start, seed=work.seed, options=work.options)


def _first_jobs(config: ReproduceConfig, dataset: Dataset) -> list[_Work]:
    """The paper's model per water content (all speeds), then the baselines, longest first."""
    out: list[_Work] = []
    conditions = dataset.conditions()
    for i, (w, trials) in enumerate(conditions.items()):
        out.append(_Work(("table", "chen2024", w, 0.0), trials, config.seed + 104729 * i, config.fit_options))
    for name in BASELINE_NAMES:
        for i, (w, trials) in enumerate(conditions.items()):
            out.append(_Work(("baseline", name, w, 0.0), trials, config.seed + 104729 * i, config.fit_options))
    return out


def _velocity_jobs(config: ReproduceConfig, dataset: Dataset, w: float, table_fit: ConditionFit) -> list[_Work]:
    """Each speed of water content ``w`` on its own, from (and around) the water content's fit."""
    conditions = dataset.conditions()
    i = list(conditions).index(w)
    fixed = {n: v for n, v in table_fit.parameters.items() if n not in VELOCITY_FREE}
    start = {**fixed, **{n: table_fit.parameters[n] for n in VELOCITY_FREE}}
    out = []
    for j, v in enumerate(config.velocities):
        group = tuple(t for t in conditions[w] if t.velocity == v)
        out.append(_Work(("velocity", "chen2024", w, v), group, config.seed + 15485863 * (10 * i + j + 1),
                         config.velocity_fit_options, fixed, start))
    return out


def _count_fits(config: ReproduceConfig, dataset: Dataset) -> int:
    n_w = len(dataset.conditions())
    return n_w * (1 + len(BASELINE_NAMES) + len(config.velocities))


def _note(job: _Job) -> str:
    kind, model, w, v = job
    return f"{model} W={w:.0%}" + (f" {v * 1e3:g}mm/s" if kind == "velocity" else "")


def _run_fits(config: ReproduceConfig, dataset: Dataset, pool: Any, progress: Progress) -> dict[_Job, ConditionFit]:
    """Every fit; in ``pool`` (an executor) if given, else here. Per-speed fits follow their water content's."""
    results: dict[_Job, ConditionFit] = {}
    foot = dataset.foot
    if pool is None:
        queue = _first_jobs(config, dataset)
        while queue:
            work = queue.pop(0)
            results[work.job] = fit = _fit_job(work, foot)
            if work.job[0] == "table":
                queue = _velocity_jobs(config, dataset, work.job[2], fit) + queue
            progress.update(1, _note(work.job))
        return results
    from concurrent.futures import FIRST_COMPLETED, wait

    pending = {pool.submit(_fit_job, work, foot): work for work in _first_jobs(config, dataset)}
    while pending:
        done, _ = wait(pending, return_when=FIRST_COMPLETED)
        for future in done:
            work = pending.pop(future)
            results[work.job] = fit = future.result()
            if work.job[0] == "table":
                for extra in _velocity_jobs(config, dataset, work.job[2], fit):
                    pending[pool.submit(_fit_job, extra, foot)] = extra
            progress.update(1, _note(work.job))
    return results


def _executor(jobs: int) -> Any:
    """A process pool of ``jobs`` workers (forked where the platform allows), or None for ``jobs == 1``."""
    if jobs <= 1:
        return None
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else None)
    return ProcessPoolExecutor(max_workers=jobs, mp_context=context)


# ---------------------------------------------------------------------------- numbers
def _round(x: Any) -> Any:
    """Floats to 6 significant digits (NaN/inf to None), recursively."""
    if isinstance(x, bool) or x is None or isinstance(x, (int, str)):
        return x
    if isinstance(x, (float, np.floating)):
        v = float(x)
        return float(f"{v:.6g}") if math.isfinite(v) else None
    if isinstance(x, Mapping):
        return {str(k): _round(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_round(v) for v in x]
    if isinstance(x, np.ndarray):
        return [_round(v) for v in x.tolist()]
    raise TypeError(f"cannot put {type(x).__name__} in summary.json")


#: Relative standard error above which a fitted value is drawn and listed as not determined [-].
POORLY_DETERMINED = 0.25


def determined(fit: ConditionFit, name: str) -> bool:
    """Whether the data determines parameter ``name`` of ``fit``.

    True when it was fitted, has a standard error below
    :data:`POORLY_DETERMINED` of its value, and is not at a bound of the model.
    """
    from mudforce.calibration.models import get_model

    se = fit.stderr.get(name)
    value = fit.parameters[name]
    if name not in fit.free or se is None or not math.isfinite(se) or se > POORLY_DETERMINED * abs(value):
        return False
    lo, hi = get_model(fit.model).bounds[name]
    return lo * 1.001 < value < hi * 0.999


def _pooled_rmse(fits: Sequence[ConditionFit]) -> float:
    res = np.concatenate([t.residual for f in fits for t in f.trials])
    return float(np.sqrt(np.mean(res**2)))


def _rmse_with(params: MudParameters, fit: ConditionFit, foot: Foot) -> float:
    """RMSE [N] of fixed parameters on a condition's (tared) trials."""
    res = [simulate(t.time, t.depth, params, foot, velocity_filter="exact").force - t.force for t in fit.trials]
    r = np.concatenate(res)
    return float(np.sqrt(np.mean(r**2)))


def _necks(params: MudParameters, velocity: float, foot: Foot) -> bool:
    from mudforce.protocol import Protocol

    t, z = Protocol.paper(velocity=velocity, approach=0.005).sample()
    return bool(simulate(t, z, params, foot, velocity_filter="exact").necking_times.size)


def _summary(config: ReproduceConfig, dataset: Dataset, table: dict[float, ConditionFit],
             by_speed: dict[tuple[float, float], ConditionFit], baselines: dict[str, dict[float, ConditionFit]],
             figures: list[tuple[str, str, str]]) -> dict[str, Any]:
    from mudforce import __version__

    foot = dataset.foot
    rows = []
    critical = []
    for w, fit in table.items():
        paper = MudParameters.from_water_content(w)
        fitted = fit.mud_parameters()
        in_table = any(abs(w - tw) < 1e-9 for tw in TABLE_I)
        rows.append({
            "water_content": w,
            "fitted": {n: fit.parameters[n] for n in (*_NINE, "rho_m", "lambda")},
            "stderr": {n: fit.stderr.get(n) for n in _NINE},
            "determined": {n: determined(fit, n) for n in _NINE},
            "paper": paper.to_dict(),
            "rmse_N": fit.rmse,
            "force_noise_N": fit.force_noise,
            "paper_parameters_rmse_N": _rmse_with(paper, fit, foot),
            "paper_reported_rmse_N": TABLE_I_RMSE_N.get(round(w, 2)) if in_table else None,
            "trials": len(fit.trials),
            "warnings": list(fit.warnings),
        })
        critical.append({
            "water_content": w,
            "fitted_m_s": fitted.critical_withdrawal_velocity,
            "fitted_determined": determined(fit, "sigma_y") and determined(fit, "b_m_w"),
            "paper_m_s": paper.critical_withdrawal_velocity,
            "necks_at_m_s": {f"{v:g}": _necks(paper, v, foot) for v in config.velocities},
        })
    base: dict[str, Any] = {"mud_model": {
        "model": "chen2024",
        "rmse_N": _pooled_rmse(list(table.values())),
        "rmse_N_by_water_content": {f"{w:g}": f.rmse for w, f in table.items()},
        "parameters_by_water_content": {f"{w:g}": f.parameters for w, f in table.items()},
    }}
    for name, fits in baselines.items():
        base[name] = {
            "model": name,
            "rmse_N": _pooled_rmse(list(fits.values())),
            "rmse_N_by_water_content": {f"{w:g}": f.rmse for w, f in fits.items()},
            "parameters_by_water_content": {f"{w:g}": f.parameters for w, f in fits.items()},
        }
    per_speed = [{"water_content": w, "velocity_m_s": v, "rmse_N": f.rmse,
                  **{n: f.parameters[n] for n in ("alpha", "beta", "sigma_y")},
                  "stderr": {n: f.stderr.get(n) for n in ("alpha", "beta", "sigma_y")},
                  "determined": {n: determined(f, n) for n in ("alpha", "beta", "sigma_y")}}
                 for (w, v), f in by_speed.items()]
    summary = {
        "mudforce_version": __version__,
        "paper": CHEN2024,
        "units": "SI (m, s, N, Pa, kg/m^3); water content as a fraction",
        "config": config.to_dict(),
        "table_i": rows,
        "critical_withdrawal_velocity": critical,
        "velocity_fits": per_speed,
        "baselines": base,
        "figures": [{"file": f, "paper_figure": p, "caption": c} for f, p, c in figures],
    }
    out: dict[str, Any] = _round(summary)
    return out


# ---------------------------------------------------------------------------- figures
def _figure(nrows: int, ncols: int, width: float, height: float) -> tuple[Any, np.ndarray]:
    from mudforce._optional import require

    require("matplotlib", "plot", "mudforce reproduce")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    axes = np.asarray(fig.subplots(nrows, ncols, squeeze=False))
    return fig, axes


def _norm_time(t: np.ndarray) -> np.ndarray:
    out: np.ndarray = (t - t[0]) / (t[-1] - t[0])
    return out


def _reference_trials(fit: ConditionFit, v: float) -> list[TrialFit]:
    return [t for t in fit.trials if t.nominal_velocity == v]


def _w_colour(w: float) -> str:
    for key, c in _W_COLOURS.items():
        if abs(key - w) < 1e-9:
            return c
    return "0.3"


def _log_axis(ax: Any) -> None:
    """A log y axis labelled 1, 2, 5, 10, ... in plain numbers."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    ax.set_yscale("log")
    ax.yaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda y, _: f"{y:g}"))
    ax.yaxis.set_minor_formatter(NullFormatter())


def _fig02(table: dict[float, ConditionFit], v: float) -> Any:
    trials = _reference_trials(table[0.25], v)
    fig, axes = _figure(1, 2, 10.0, 3.8)
    s = _norm_time(trials[0].time)
    forces = np.array([t.force for t in trials])
    scale = float(np.max(np.abs(forces.mean(axis=0))))
    mean, std = forces.mean(axis=0) / scale, forces.std(axis=0, ddof=1) / scale
    model = trials[0].fitted / scale
    zn = trials[0].depth / float(np.max(trials[0].depth))
    ax = axes[0, 0]
    ax.fill_between(s, mean - std, mean + std, color="#85c1e9", lw=0, label="±1 sd")
    ax.plot(s, mean, color="#1b4f72", lw=1.2, label=f"mean of {len(trials)} trials")
    ax.plot(s, model, color="k", lw=0.8, ls="--", label="model (fitted)")
    ax.set_xlabel("normalised process time [-]")
    ax.set_ylabel("normalised force [-]")
    ax.set_title("(a) time domain", fontsize="medium")
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.legend(fontsize="small")
    # the repeats differ most around necking: zoom there so that the band shows
    window = (s >= 0.69) & (s <= 0.86)
    inset = ax.inset_axes((0.3, 0.22, 0.36, 0.42))
    inset.fill_between(s[window], (mean - std)[window], (mean + std)[window], color="#85c1e9", lw=0)
    inset.plot(s[window], mean[window], color="#1b4f72", lw=1.0)
    inset.plot(s[window], model[window], color="k", lw=0.7, ls="--")
    inset.axhline(0.0, color="0.6", lw=0.5)
    inset.set_title("zoom: suction and necking", fontsize="x-small")
    inset.tick_params(labelsize="x-small")
    ax = axes[0, 1]
    ax.fill_between(zn, mean - std, mean + std, color="#85c1e9", lw=0, label="±1 sd")
    ax.plot(zn, mean, color="#1b4f72", lw=1.2, label="mean")
    ax.plot(zn, model, color="k", lw=0.8, ls="--", label="model (fitted)")
    ax.set_xlabel("normalised intrusion depth $z_i / z_{max}$ [-]")
    ax.set_ylabel("normalised force [-]")
    ax.set_title("(b) depth domain", fontsize="medium")
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.axvline(0.0, color="0.6", lw=0.5)
    ax.legend(fontsize="small")
    fig.suptitle(f"Typical resistive-force profile, W = 25 %, {v * 1e3:g} mm/s (cf. paper Fig. 2a, 2b)")
    return fig


def _fig06(table: dict[float, ConditionFit], dataset: Dataset, v: float) -> Any:
    fit = table[0.25]
    trials = _reference_trials(fit, v)
    params = fit.mud_parameters()
    first = trials[0]
    res = simulate(first.time, first.depth, params, dataset.foot, velocity_filter="exact")
    raw = next(t for t in dataset.trials if t.name == first.name)
    fig, axes = _figure(1, 3, 13.0, 3.8)
    ax = axes[0, 0]
    for i, t in enumerate(trials):
        ax.plot(t.time, t.force, ".", ms=1.2, color="0.55", label="measured (synthetic)" if i == 0 else None)
    ax.plot(res.time, res.force, color="#c0392b", lw=1.1, label="model (fitted)")
    for tn in res.necking_times:
        ax.axvline(tn, color="#c0392b", ls=":", lw=0.8)
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("force on foot [N] (+ up)")
    ax.set_title("(a) force: experiment and model", fontsize="medium")
    ax.legend(fontsize="small")
    ax = axes[0, 1]
    measured_v = np.gradient(raw.depth, raw.time)
    ax.plot(raw.time, measured_v * 1e3, color="0.75", lw=0.5, label=r"$\dot z_i$ from measured $z_i$")
    ax.plot(res.time, np.gradient(res.depth, res.time) * 1e3, color="k", lw=1.0, label=r"$\dot z_i$ (fitted motion)")
    ax.plot(res.time, res.mud_velocity * 1e3, color="#2471a3", lw=1.0, label=r"$\dot z_m$ (model)")
    ax.axhline(0.0, color="0.6", lw=0.5)
    lim = 2.5 * v * 1e3
    ax.set_ylim(-lim, lim)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("velocity [mm/s] (+ down)")
    ax.set_title("(b) intruder and mud velocity", fontsize="medium")
    ax.legend(fontsize="small")
    ax = axes[0, 2]
    ax.plot(raw.time, raw.depth * 1e3, color="0.75", lw=0.6, label="$z_i$ measured")
    ax.plot(res.time, res.depth * 1e3, color="k", lw=1.0, label="$z_i$ (fitted motion)")
    ax.plot(res.time, res.mud_displacement * 1e3, color="#2471a3", lw=1.0, ls="-.", label="$z_m$ (model)")
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.invert_yaxis()
    ax.set_xlabel("time [s]")
    ax.set_ylabel("displacement [mm] (+ down)")
    ax.set_title("(c) intruder and mud displacement", fontsize="medium")
    ax.legend(fontsize="small")
    fig.suptitle(f"Model validation, W = 25 %, {v * 1e3:g} mm/s (cf. paper Fig. 6a-c)")
    return fig


def _fig07(table: dict[float, ConditionFit], v: float) -> Any:
    fig, axes = _figure(1, 1, 7.0, 4.2)
    ax = axes[0, 0]
    for w, fit in table.items():
        trials = _reference_trials(fit, v)
        s, mean, std = error_profile(trials)
        c = _w_colour(w)
        ax.fill_between(s, mean - std, mean + std, color=c, alpha=0.2, lw=0)
        ax.plot(s, mean, color=c, lw=1.0, label=f"W = {w:.0%} ({len(trials)} trials)")
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set_xlabel("normalised process time [-]")
    ax.set_ylabel("model - measured force [N]")
    ax.set_title(f"Error profiles, mean ± 1 sd over repeats, {v * 1e3:g} mm/s (cf. paper Fig. 7)", fontsize="medium")
    ax.legend(fontsize="small", ncols=2)
    return fig


def _trend(ax: Any, table: dict[float, ConditionFit], name: str) -> None:
    scale, unit = _PAPER_UNITS[name]
    ws = np.array(list(table))
    vals = np.array([table[w].parameters[name] for w in ws]) * scale
    ses = np.array([np.nan if table[w].stderr.get(name) is None else table[w].stderr[name] for w in ws],
                   dtype=np.float64) * scale
    paper = np.array([getattr(MudParameters.from_water_content(w), name) for w in ws]) * scale
    ok = np.array([determined(table[w], name) for w in ws])
    ax.plot(ws * 100, paper, "s--", color="0.45", ms=5, mfc="none", lw=0.8, label="paper, Table I")
    ax.errorbar(ws[ok] * 100, vals[ok], yerr=ses[ok], fmt="o", color="#c0392b", ms=4, capsize=2,
                label="fitted ± 1 se")
    if np.any(~ok):
        ax.plot(ws[~ok] * 100, vals[~ok], "o", color="#c0392b", mfc="none", ms=5, label="fitted, not determined")
    ax.set_xlabel("water content W [%]")
    ax.set_ylabel(f"{_SYMBOL[name]} [{unit}]")


_SYMBOL = {"k_m_i": r"$k_m^i$", "b_m_i": r"$b_m^i$", "k_m_w": r"$k_m^w$", "b_m_w": r"$b_m^w$", "alpha": r"$\alpha$",
           "beta": r"$\beta$", "sigma_y": r"$\sigma_y$", "zeta": r"$\zeta$", "omega_0": r"$\omega_0$"}


def _fig08(table: dict[float, ConditionFit]) -> Any:
    fig, axes = _figure(2, 2, 8.5, 6.0)
    for ax, name in zip(axes.ravel(), ("k_m_i", "b_m_i", "zeta", "omega_0"), strict=True):
        _trend(ax, table, name)
    axes[0, 0].legend(fontsize="small")
    fig.suptitle(r"$k_m^i$, $b_m^i$ (top) and filter $\zeta$, $\omega_0$ (bottom) against W (cf. paper Fig. 8)")
    return fig


def _fig09(table: dict[float, ConditionFit]) -> Any:
    fig, axes = _figure(1, 3, 12.0, 3.6)
    for ax, name, tag in zip(axes.ravel(), ("alpha", "beta", "sigma_y"), "abc", strict=True):
        _trend(ax, table, name)
        ax.set_title(f"({tag})", fontsize="medium")
    axes[0, 0].legend(fontsize="small")
    fig.suptitle(r"Stiffness $\alpha$, exponent $\beta$ and yield stress $\sigma_y$ against W (cf. paper Fig. 9)")
    return fig


def _fig10(by_speed: dict[tuple[float, float], ConditionFit]) -> Any:
    fig, axes = _figure(1, 3, 12.0, 3.8)
    ws = sorted({w for w, _ in by_speed})
    for ax, name, tag in zip(axes.ravel(), ("alpha", "beta", "sigma_y"), "abc", strict=True):
        scale, unit = _PAPER_UNITS[name]
        for w in ws:
            keys = sorted(k for k in by_speed if k[0] == w)
            vs = np.array([k[1] for k in keys]) * 1e3
            vals = np.array([by_speed[k].parameters[name] for k in keys]) * scale
            ses = np.array([np.nan if by_speed[k].stderr.get(name) is None else by_speed[k].stderr[name]
                            for k in keys], dtype=np.float64) * scale
            ok = np.array([determined(by_speed[k], name) for k in keys])
            c = _w_colour(w)
            ax.plot(vs, vals, "-", color=c, lw=0.8)
            ax.errorbar(vs[ok], vals[ok], yerr=ses[ok], fmt="o", color=c, ms=4, capsize=2, label=f"W = {w:.0%}")
            if np.any(~ok):
                ax.plot(vs[~ok], vals[~ok], "o", color=c, mfc="none", ms=6)
        if name != "beta":
            _log_axis(ax)
        ax.set_xlabel("intrusion/withdrawal speed [mm/s]")
        ax.set_ylabel(f"{_SYMBOL[name]} [{unit}]")
        ax.set_title(f"({tag})", fontsize="medium")
    axes[0, 0].legend(fontsize="small")
    fig.suptitle(r"$\alpha$, $\beta$, $\sigma_y$ fitted per speed (cf. paper Fig. 10); open: not determined")
    return fig


def _fig11(table: dict[float, ConditionFit], v: float, foot: Foot) -> Any:
    trials = _reference_trials(table[0.25], v)
    t0 = trials[0]
    mean = np.mean([t.force for t in trials], axis=0)
    s = _norm_time(t0.time)
    zn = t0.depth / float(np.max(t0.depth))
    mud_scale = float(np.max(np.abs(mean)))
    # granular media: linear RFT; k_rft only scales the force, so dry and wet sand coincide once normalised
    sand = granular_rft_force(t0.time, t0.depth, 1.0, foot)
    sand_n = sand / float(np.max(np.abs(sand)))
    fig, axes = _figure(1, 2, 10.0, 3.8)
    for ax, x, xlabel, tag in ((axes[0, 0], s, "normalised process time [-]", "(a) time domain"),
                               (axes[0, 1], zn, "normalised intrusion depth $z_i / z_{max}$ [-]",
                                "(b) depth domain")):
        ax.plot(x, mean / mud_scale, color="#7d3c98", lw=1.2, label="mud, W = 25 % (synthetic, mean)")
        ax.plot(x, t0.fitted / mud_scale, color="k", lw=0.8, ls="--", label="mud model")
        ax.plot(x, sand_n, color="#b9770e", lw=1.2, label="dry / wet sand (granular RFT)")
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("normalised force [-]")
        ax.set_title(tag, fontsize="medium")
    axes[0, 0].legend(fontsize="small")
    fig.suptitle("Mud against granular media, normalised by their maxima (cf. paper Fig. 11)")
    return fig


def _fig_critical(table: dict[float, ConditionFit], config: ReproduceConfig) -> Any:
    fig, axes = _figure(1, 1, 7.0, 4.2)
    ax = axes[0, 0]
    ws = np.array(list(table))
    fitted = np.array([table[w].mud_parameters().critical_withdrawal_velocity for w in ws]) * 1e3
    paper = np.array([MudParameters.from_water_content(w).critical_withdrawal_velocity for w in ws]) * 1e3
    ok = np.array([determined(table[w], "sigma_y") and determined(table[w], "b_m_w") for w in ws])
    ax.plot(ws * 100, paper, "s--", color="0.45", mfc="none", label=r"paper, Table I: $\sigma_y / b_m^w$")
    ax.plot(ws[ok] * 100, fitted[ok], "o-", color="#c0392b", label="fitted")
    if np.any(~ok):  # not drawn: an undetermined b_m_w can be anything up to its bound
        missing = ", ".join(f"{w:.0%}" for w in ws[~ok])
        ax.plot([], [], " ", label=f"fitted: not determined at W = {missing} (not drawn)")
    ax.set_xticks(ws * 100, [f"{w * 100:g}" for w in ws])
    for i, v in enumerate(config.velocities):
        ax.axhline(v * 1e3, color="#2471a3", lw=0.6, ls=":")
        x, ha = (ws[-1] * 100, "right") if i % 2 == 0 else (ws[0] * 100, "left")
        ax.text(x, v * 1e3, f" {v * 1e3:g} mm/s ", va="bottom", ha=ha, fontsize="small", color="#2471a3")
    _log_axis(ax)
    ax.set_xlabel("water content W [%]")
    ax.set_ylabel("critical withdrawal speed [mm/s]")
    ax.set_title("Necking needs a withdrawal faster than $\\sigma_y / b_m^w$ (dotted: speeds tested)\n"
                 "(from paper Table I and Sec. II-B; no figure in the paper)", fontsize="medium")
    ax.legend(fontsize="small")
    return fig


def _fig_baselines(table: dict[float, ConditionFit], baselines: dict[str, dict[float, ConditionFit]],
                   v: float) -> Any:
    fig, axes = _figure(1, 2, 12.0, 4.0)
    ax = axes[0, 0]
    ref = _reference_trials(table[0.25], v)[0]
    ax.plot(ref.time, ref.force, ".", ms=1.2, color="0.6", label="measured (synthetic)")
    ax.plot(ref.time, ref.fitted, color="k", lw=1.1, label=_MODEL_LABELS["mud_model"])
    styles = {"granular_rft": ("#b9770e", "-"), "drft": ("#2471a3", "--"), "maxwell_only": ("#7d3c98", "-.")}
    for name, fits in baselines.items():
        tr = next(t for t in fits[0.25].trials if t.name == ref.name)
        colour, ls = styles.get(name, ("0.3", ":"))
        ax.plot(tr.time, tr.fitted, color=colour, ls=ls, lw=1.0, label=_MODEL_LABELS.get(name, name))
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("force on foot [N] (+ up)")
    ax.set_title(f"(a) fitted models, W = 25 %, {v * 1e3:g} mm/s", fontsize="medium")
    ax.legend(fontsize="small")
    ax = axes[0, 1]
    models = {"mud_model": table, **baselines}
    ws = list(table)
    width = 0.8 / len(models)
    x = np.arange(len(ws))
    for i, (name, fits) in enumerate(models.items()):
        colour = "k" if name == "mud_model" else styles.get(name, ("0.3", ":"))[0]
        ax.bar(x + (i - (len(models) - 1) / 2) * width, [fits[w].rmse for w in ws], width, color=colour,
               label=_MODEL_LABELS.get(name, name))
    ax.set_xticks(x, [f"{w:.0%}" for w in ws])
    ax.set_yscale("log")
    ax.set_xlabel("water content W")
    ax.set_ylabel("RMSE over all trials [N]")
    ax.set_title("(b) RMSE on the same mud data", fontsize="medium")
    ax.legend(fontsize="small")
    fig.suptitle("Mud model against granular baselines fitted to the same mud data (cf. paper Fig. 11 discussion)")
    return fig


_N_FIGURES = 9

_Spec = tuple[str, str, str, Callable[..., Any], tuple[Any, ...]]


def _sort_fits(fits: Mapping[_Job, ConditionFit]) -> tuple[
        dict[float, ConditionFit], dict[tuple[float, float], ConditionFit], dict[str, dict[float, ConditionFit]]]:
    """The fits by kind, each in ascending order of water content (then speed)."""
    table = dict(sorted((job[2], f) for job, f in fits.items() if job[0] == "table"))
    by_speed = dict(sorted(((job[2], job[3]), f) for job, f in fits.items() if job[0] == "velocity"))
    baselines = {name: dict(sorted((job[2], f) for job, f in fits.items()
                                   if job[0] == "baseline" and job[1] == name)) for name in BASELINE_NAMES}
    return table, by_speed, baselines


def _figure_specs(config: ReproduceConfig, dataset: Dataset, table: dict[float, ConditionFit],
                  by_speed: dict[tuple[float, float], ConditionFit],
                  baselines: dict[str, dict[float, ConditionFit]]) -> list[_Spec]:
    """(file, paper figure, caption, function, arguments) of every figure."""
    v = config.reference_velocity
    return [
        ("fig02_profile.png", "Paper Fig. 2a, 2b",
         f"Normalised resistive force at W = 25 %, {v * 1e3:g} mm/s, over normalised process time (a) and "
         f"normalised intrusion depth (b); band: ±1 standard deviation over {config.repeats} synthetic trials; "
         "dashed: the fitted model; inset: zoom on the suction and necking, where the repeats differ most. "
         "Force is normalised by the mean trace's maximum magnitude, time by the "
         "trial's duration, depth by the hold depth.",
         _fig02, (table, v,)),
        ("fig06_validation.png", "Paper Fig. 6a-c",
         f"W = 25 %, {v * 1e3:g} mm/s: (a) synthetic measured force of every repeat and the fitted model "
         "(dotted: necking instant); (b) intruder velocity from the measured depth (grey, differentiated "
         "numerically as in the paper) and from the fitted motion, and the model's mud velocity; (c) intruder "
         "and mud displacements. The mud lags the intruder, which compresses it.",
         _fig06, (table, dataset, v,)),
        ("fig07_error_profiles.png", "Paper Fig. 7",
         f"Error profiles (model minus measured force) of the fitted model at {v * 1e3:g} mm/s for every "
         "water content: mean and ±1 standard deviation over repeats, on normalised process time.",
         _fig07, (table, v,)),
        ("fig08_stiffness_damping_filter.png", "Paper Fig. 8",
         "Fitted k_m^i, b_m^i (top) and post-necking filter zeta, omega_0 (bottom) against water content, "
         "± 1 standard error, with the paper's Table I (grey squares). Open markers: not determined by the "
         "data (e.g. no trial necked).",
         _fig08, (table,)),
        ("fig09_alpha_beta_sigma.png", "Paper Fig. 9a-c",
         "Fitted stiffness alpha (a), exponent beta (b) and yield stress sigma_y (c) against water content, "
         "± 1 standard error, with the paper's Table I (grey squares). alpha and sigma_y fall steeply with W.",
         _fig09, (table,)),
        ("fig10_parameters_vs_velocity.png", "Paper Fig. 10a-c",
         "alpha (a), beta (b) and sigma_y (c) fitted separately for each speed and water content. The "
         "synthetic mud's parameters do not depend on speed, so flat lines are the expected result; the "
         "paper's measured sigma_y rose slightly with speed at W <= 25 %, which model-made data cannot show. "
         "Open markers: not determined (the suction never reached sigma_y at that speed).",
         _fig10, (by_speed,)),
        ("fig11_mud_vs_granular.png", "Paper Fig. 11a, 11b",
         f"Mud (W = 25 %, {v * 1e3:g} mm/s, synthetic mean and model) against granular media modelled by "
         "linear resistive force theory (force proportional to depth, no relaxation, no suction), each "
         "normalised by its maximum, over normalised time (a) and normalised depth (b). Dry and wet sand "
         "differ only in the RFT coefficient, so they coincide once normalised.",
         _fig11, (table, v, dataset.foot,)),
        ("critical_withdrawal_velocity.png", "Paper Table I and Section II-B (no figure in the paper)",
         "Critical withdrawal speed sigma_y / b_m^w against water content, fitted and from Table I. Withdrawals "
         "slower than it never neck (at W = 15 %, 10 mm/s the mud keeps clinging).",
         _fig_critical, (table, config,)),
        ("baselines.png", "Paper Fig. 11 discussion (no figure in the paper)",
         "Granular RFT, dynamic RFT and a Maxwell-only ablation fitted to the same synthetic mud data as the "
         f"mud model: (a) fitted forces at W = 25 %, {v * 1e3:g} mm/s; (b) RMSE per water content.",
         _fig_baselines, (table, baselines, v,)),
    ]

def _warm_up_matplotlib() -> None:
    """Import the renderer and load the fonts and mathtext parser once (forked workers inherit them)."""
    fig, axes = _figure(1, 1, 1.0, 1.0)
    axes[0, 0].set_title(r"$\sigma_y$ [-]")
    fig.canvas.draw()


def _render(make: Callable[..., Any], args: tuple[Any, ...]) -> bytes:
    from mudforce.plotting import figure_to_png

    return figure_to_png(make(*args))


def _write_figures(path: Path, specs: Sequence[_Spec], pool: Any, progress: Progress) -> list[tuple[str, str, str]]:
    """Render the figures (in ``pool`` if given) and write them atomically, in order."""
    from mudforce.io import atomic_open

    if pool is None:
        images = []
        for file, _, _, make, args in specs:
            images.append(_render(make, args))
            progress.update(1, file)
    else:
        futures = [pool.submit(_render, make, args) for _, _, _, make, args in specs]
        images = []
        for (file, *_), future in zip(specs, futures, strict=True):
            images.append(future.result())
            progress.update(1, file)
    for (file, *_), data in zip(specs, images, strict=True):
        with atomic_open(path / file, "wb") as handle:
            handle.write(data)
    return [(file, paper_fig, caption) for file, paper_fig, caption, _, _ in specs]


# ---------------------------------------------------------------------------- HTML
def _fmt(x: float | None, digits: int = 3) -> str:
    if x is None or not math.isfinite(x):
        return "&mdash;"
    return f"{x:.{digits}g}"


def _html(config: ReproduceConfig, summary: dict[str, Any], figures: list[tuple[str, str, str]]) -> str:
    e = html.escape
    mode = "--quick" if config.quick else "full"
    out = [
        "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
        "<title>mudforce reproduce: Chen, Yi &amp; Shan (2024)</title>",
        "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;line-height:1.45}"
        "table{border-collapse:collapse;margin:1em 0;font-size:0.9em}td,th{border:1px solid #bbb;padding:3px 7px;"
        "text-align:right}th{background:#eee}td:first-child,th:first-child{text-align:left}"
        "figure{margin:2em 0}img{max-width:100%}figcaption{font-size:0.92em;color:#333}"
        ".paper{color:#555}</style>",
        "</head>", "<body>",
        "<h1>The mud resistive-force model, reproduced</h1>",
        f"<p>Figures and tables of {e(CHEN2024)}, regenerated by <code>mudforce reproduce</code> "
        f"(mudforce {e(str(summary['mudforce_version']))}, {mode} run, seed {config.seed}).</p>",
        "<p>The paper's measurements are not public. The &ldquo;measured&rdquo; data here are synthetic "
        "experiments made from the model with the paper's Table I (interpolated) and the paper's protocol "
        f"(approach from 5 mm above the surface, intrude 20 mm, hold 6 s, withdraw to 20 mm above, 100 Hz): "
        f"{len(config.water_contents)} water contents &times; {len(config.velocities)} speeds "
        f"({', '.join(f'{v * 1e3:g}' for v in config.velocities)} mm/s) &times; {config.repeats} repeats, with "
        f"{config.force_noise:g} N force noise, {config.depth_noise * 1e3:g} mm depth noise, a {config.bias:g} N "
        f"sensor bias, and a {config.repeat_scatter:.0%} trial-to-trial scatter of "
        f"{', '.join(SCATTERED)} (fresh mud for every trial). The model is then fitted back to them with "
        "<code>mudforce.calibration</code>, as the paper calibrated its model, and granular baselines are fitted to "
        "the same data. What this shows is the model's behaviour and the calibration's ability to recover it, "
        "not the paper's experimental findings.</p>",
    ]
    # Table I
    out += ["<h2>Table I, as fitted and as published</h2>",
            "<p>Fitted on all speeds of each water content (value &plusmn; standard error; paper units). "
            "<span class=\"paper\">Grey rows: the paper's Table I.</span> RMSE: over all samples of all trials; "
            "the paper's RMSE is on its own data and cannot be reproduced, only cited.</p>",
            "<table><tr><th>W</th>" + "".join(
                f"<th>{e(n)} [{e(_PAPER_UNITS[n][1])}]</th>" for n in _NINE) + "<th>RMSE [N]</th></tr>"]
    for row in summary["table_i"]:
        cells = []
        for n in _NINE:
            scale = _PAPER_UNITS[n][0]
            se = row["stderr"].get(n)
            mark = "" if row["determined"][n] else "<sup>&dagger;</sup>"
            cells.append(f"<td>{_fmt(row['fitted'][n] * scale)}"
                         + (f" &plusmn; {_fmt(se * scale, 2)}" if se is not None else "") + f"{mark}</td>")
        out.append(f"<tr><td>{row['water_content']:.0%} fitted</td>{''.join(cells)}"
                   f"<td>{_fmt(row['rmse_N'])}</td></tr>")
        pcells = "".join(f"<td>{_fmt(row['paper'][n] * _PAPER_UNITS[n][0])}</td>" for n in _NINE)
        out.append(f"<tr class=\"paper\"><td>{row['water_content']:.0%} paper</td>{pcells}"
                   f"<td>{_fmt(row['paper_reported_rmse_N'])}</td></tr>")
    out.append("</table>")
    out.append("<p><sup>&dagger;</sup> Not determined by the data: no standard error, a relative standard error "
               f"above {POORLY_DETERMINED:.0%}, or at a bound of the fit (e.g. b<sub>m</sub><sup>w</sup> when the "
               "neck breaks long before the withdrawal relaxation time; &sigma;<sub>y</sub>, &zeta;, "
               "&omega;<sub>0</sub> when no trial necks).</p>")
    out.append("<p>RMSE of the paper's own Table I parameters on this synthetic data: " + ", ".join(
        f"{row['water_content']:.0%}: {_fmt(row['paper_parameters_rmse_N'])} N" for row in summary["table_i"])
        + " (the fit's floor is the force noise, " + f"{config.force_noise:g} N, plus the trial-to-trial scatter).</p>")
    warned = [(row["water_content"], w) for row in summary["table_i"] for w in row["warnings"]]
    if warned:
        out.append("<details><summary>Fit warnings</summary><ul>" + "".join(
            f"<li>W = {w:.0%}: {e(text)}</li>" for w, text in warned) + "</ul></details>")
    # critical velocity
    out += ["<h2>Critical withdrawal velocity for necking</h2>",
            "<p>While withdrawing, the Maxwell stress tends to <i>b<sub>m</sub><sup>w</sup> v</i>, so the neck can "
            "only break (suction reaching &sigma;<sub>y</sub>) above <i>v</i> = &sigma;<sub>y</sub> / "
            "<i>b<sub>m</sub><sup>w</sup></i>. Below it the mud keeps clinging.</p>",
            "<table><tr><th>W</th><th>fitted [mm/s]</th><th>paper [mm/s]</th>"
            + "".join(f"<th>necks at {float(v) * 1e3:g} mm/s (Table I)</th>" for v in config.velocities)
            + "</tr>"]
    for row in summary["critical_withdrawal_velocity"]:
        necks = "".join(f"<td>{'yes' if row['necks_at_m_s'][f'{v:g}'] else 'no'}</td>" for v in config.velocities)
        fitted = row["fitted_m_s"]
        mark = "" if row["fitted_determined"] else "<sup>&dagger;</sup>"
        out.append(f"<tr><td>{row['water_content']:.0%}</td><td>{_fmt(None if fitted is None else fitted * 1e3)}"
                   f"{mark}</td><td>{_fmt(row['paper_m_s'] * 1e3)}</td>{necks}</tr>")
    out.append("</table>")
    # baselines
    out += ["<h2>Baselines on the same mud data</h2>",
            "<p>Each model fitted per water content on all its trials (<code>mudforce fit --model NAME</code>); "
            "RMSE over all samples of all trials [N]. Granular RFT: force linear in depth, no relaxation, no "
            "suction (Li, Zhang &amp; Goldman 2013). Dynamic RFT: plus &lambda;&rho;v|v|. Maxwell only: the mud "
            "model without its nonlinear spring and without necking.</p>",
            "<table><tr><th>model</th><th>RMSE, all [N]</th>"
            + "".join(f"<th>W = {w:.0%}</th>" for w in config.water_contents) + "</tr>"]
    for name, entry in summary["baselines"].items():
        per = "".join(f"<td>{_fmt(entry['rmse_N_by_water_content'].get(f'{w:g}'))}</td>"
                      for w in config.water_contents)
        out.append(f"<tr><td>{e(_MODEL_LABELS.get(name, name))} (<code>{e(name)}</code>)</td>"
                   f"<td>{_fmt(entry['rmse_N'])}</td>{per}</tr>")
    out.append("</table>")
    # figures
    out.append("<h2>Figures</h2>")
    for file, paper_fig, caption in figures:
        out.append(f'<figure id="{e(Path(file).stem)}"><img src="{e(file)}" alt="{e(paper_fig)}">'
                   f"<figcaption><b>{e(paper_fig)}.</b> {e(caption)}</figcaption></figure>")
    out += ["<p>Data: <code>summary.json</code> beside this file (SI units).</p>", "</body>", "</html>"]
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------------------- the whole run
def reproduce(out: str | os.PathLike[str], config: ReproduceConfig | None = None, *, jobs: int = 1,
              quiet: bool = False, log: Callable[[str], None] | None = None) -> ReproduceResult:
    """Make the synthetic experiments, fit the model and the baselines, and write the report.

    Parameters
    ----------
    out : path-like
        Folder for ``report.html``, ``summary.json`` and the PNG figures (created).
    config : ReproduceConfig, optional
        :meth:`ReproduceConfig.full` by default.
    jobs : int
        Worker processes for the fits (1: in this process). The result does not depend on it.
    quiet : bool
        No progress on the terminal.
    log : callable, optional
        Receives one line per stage (e.g. ``print``), independent of the terminal.

    Returns
    -------
    ReproduceResult
    """
    from mudforce._optional import require

    require("matplotlib", "plot", "mudforce reproduce")
    _warm_up_matplotlib()  # before the workers fork, so that they do not each pay for it
    config = ReproduceConfig.full() if config is None else config
    positive_int(jobs, "jobs")
    path = check_output_dir(out)
    say = log if log is not None else (lambda _: None)
    dataset, truths = make_experiments(config)
    n_fits = _count_fits(config, dataset)
    pool = _executor(jobs)
    try:
        with Progress(n_fits + _N_FIGURES + 1, "reproduce", quiet=quiet) as progress:
            progress.update(1, "synthetic experiments")
            say(f"made {len(dataset.trials)} synthetic trials; fitting {n_fits} conditions")
            fits = _run_fits(config, dataset, pool, progress)
            table, by_speed, baselines = _sort_fits(fits)
            figures = _write_figures(path, _figure_specs(config, dataset, table, by_speed, baselines), pool,
                                     progress)
    finally:
        if pool is not None:
            pool.shutdown()

    summary = _summary(config, dataset, table, by_speed, baselines, figures)
    atomic_write_text(path / "summary.json", json.dumps(summary, indent=2, sort_keys=False) + "\n")
    atomic_write_text(path / "report.html", _html(config, summary, figures))
    say(f"wrote {path / 'report.html'}, {path / 'summary.json'} and {len(figures)} figures")
    return ReproduceResult(config=config, dataset=dataset, truths=truths, table_fits=table, velocity_fits=by_speed,
                           baseline_fits=baselines, summary=summary, figures=figures)
