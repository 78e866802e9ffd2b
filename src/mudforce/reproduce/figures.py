"""The figures of :mod:`mudforce.reproduce`: the paper's Figs. 2, 6-11, the critical withdrawal velocity, the baselines.

Each figure is drawn by one function from the fits, on a figure of
:func:`mudforce.io.plotting.new_figure`, and saved by
:func:`mudforce.io.plotting.save_png` (reproducible bytes: no version or
timestamp in the PNG). :func:`figure_specs` lists them with the paper's
figure each corresponds to and its caption (shown in ``report.html``).
Depths and speeds are drawn in mm and mm/s, parameters in the paper's
units (:data:`mudforce.reproduce.summary.PAPER_UNITS`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mudforce._plumbing.progress import Progress
from mudforce.estimation.calibration.dataset import Dataset
from mudforce.estimation.calibration.fit import ConditionFit, TrialFit
from mudforce.estimation.calibration.report import error_profile
from mudforce.io.plotting import new_figure, save_png
from mudforce.model.baselines import granular_rft_force
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.reproduce.experiments import ReproduceConfig, _is_reference
from mudforce.reproduce.summary import MODEL_LABELS, PAPER_UNITS, determined, in_paper_units
from mudforce.steppers.simulation import simulate

__all__ = ["N_FIGURES", "Spec", "figure_specs", "warm_up_matplotlib", "write_figures"]

_W_COLOURS = {0.15: "#1b4f72", 0.20: "#2e86c1", 0.25: "#28b463", 0.30: "#f39c12", 0.35: "#c0392b"}


def _figure(nrows: int, ncols: int, width: float, height: float) -> tuple[Any, np.ndarray]:
    """A figure of ``width`` x ``height`` inches at 100 dpi and its ``nrows`` x ``ncols`` axes (2-D array)."""
    fig = new_figure(width, height)
    axes = np.asarray(fig.subplots(nrows, ncols, squeeze=False))
    return fig, axes


def _norm_time(t: np.ndarray) -> np.ndarray:
    out: np.ndarray = (t - t[0]) / (t[-1] - t[0])
    return out


def _at_reference(fits: dict[float, ConditionFit]) -> ConditionFit:
    """The fit at the reference water content 0.25, whose key may be 0.25 to float rounding only (as
    :class:`ReproduceConfig` takes it: ``table[0.25]`` was a KeyError after every fit of the run)."""
    return next(f for w, f in fits.items() if _is_reference(w))


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
    trials = _reference_trials(_at_reference(table), v)
    fig, axes = _figure(1, 2, 10.0, 3.8)
    s = _norm_time(trials[0].time)
    forces = np.array([t.force for t in trials])
    scale = float(np.max(np.abs(forces.mean(axis=0))))
    mean = forces.mean(axis=0) / scale
    # the repeats' scatter (none with one repeat: no band, rather than numpy's NaN and its warning)
    std = forces.std(axis=0, ddof=1) / scale if len(trials) > 1 else np.zeros_like(mean)
    model = trials[0].fitted / scale
    zn = trials[0].depth / float(np.max(trials[0].depth))
    ax = axes[0, 0]
    ax.fill_between(s, mean - std, mean + std, color="#85c1e9", lw=0, label="±1 sd" if len(trials) > 1 else None)
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
    fit = _at_reference(table)
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
    unit = PAPER_UNITS[name][1]
    ws = np.array(list(table))
    vals = in_paper_units(name, np.array([table[w].parameters[name] for w in ws]))
    ses = in_paper_units(name, np.array([np.nan if table[w].stderr.get(name) is None else table[w].stderr[name]
                                         for w in ws], dtype=np.float64))
    paper = in_paper_units(name, np.array([getattr(MudParameters.from_water_content(w), name) for w in ws]))
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
        unit = PAPER_UNITS[name][1]
        for w in ws:
            keys = sorted(k for k in by_speed if k[0] == w)
            vs = np.array([k[1] for k in keys]) * 1e3
            vals = in_paper_units(name, np.array([by_speed[k].parameters[name] for k in keys]))
            ses = in_paper_units(name, np.array([np.nan if by_speed[k].stderr.get(name) is None
                                                 else by_speed[k].stderr[name] for k in keys], dtype=np.float64))
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
    trials = _reference_trials(_at_reference(table), v)
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
    ref = _reference_trials(_at_reference(table), v)[0]
    ax.plot(ref.time, ref.force, ".", ms=1.2, color="0.6", label="measured (synthetic)")
    ax.plot(ref.time, ref.fitted, color="k", lw=1.1, label=MODEL_LABELS["mud_model"])
    styles = {"granular_rft": ("#b9770e", "-"), "drft": ("#2471a3", "--"), "maxwell_only": ("#7d3c98", "-.")}
    for name, fits in baselines.items():
        tr = next(t for t in _at_reference(fits).trials if t.name == ref.name)
        colour, ls = styles.get(name, ("0.3", ":"))
        ax.plot(tr.time, tr.fitted, color=colour, ls=ls, lw=1.0, label=MODEL_LABELS.get(name, name))
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
               label=MODEL_LABELS.get(name, name))
    ax.set_xticks(x, [f"{w:.0%}" for w in ws])
    ax.set_yscale("log")
    ax.set_xlabel("water content W")
    ax.set_ylabel("RMSE over all trials [N]")
    ax.set_title("(b) RMSE on the same mud data", fontsize="medium")
    ax.legend(fontsize="small")
    fig.suptitle("Mud model against granular baselines fitted to the same mud data (cf. paper Fig. 11 discussion)")
    return fig


#: How many figures the report has.
N_FIGURES = 10

#: A figure: (file, paper figure, caption, function that draws it, its arguments).
Spec = tuple[str, str, str, Callable[..., Any], tuple[Any, ...]]


def figure_specs(config: ReproduceConfig, dataset: Dataset, table: dict[float, ConditionFit],
                  by_speed: dict[tuple[float, float], ConditionFit],
                  baselines: dict[str, dict[float, ConditionFit]]) -> list[Spec]:
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
        ("tracking.png", "Paper Sec. I, telling mud conditions apart, online (no figure in the paper)",
         "A simulated robot foot walks on mud whose water content changes from 20 % to 30 % at the first swing "
         "after 20 s (gait: touchdowns, stances with sway, re-pushes, lift-offs; 0.3 N force noise, 0.03 mm depth "
         "noise, 0.5 N sensor offset). Top: measured force and the tracker's prediction; bottom: the tracker's "
         "water-content estimate with its 95 % interval against the truth, updated sample by sample without "
         "being told of the change. See docs/tracking.md.",
         _fig_tracking, (config.seed,)),
    ]


def _fig_tracking(seed: int) -> Any:
    from mudforce.estimation.tracking_plots import tracking_figure

    return tracking_figure(seed=seed)

def warm_up_matplotlib() -> None:
    """Import the renderer and load the fonts and mathtext parser once (forked workers inherit them)."""
    fig, axes = _figure(1, 1, 1.0, 1.0)
    axes[0, 0].set_title(r"$\sigma_y$ [-]")
    fig.canvas.draw()


def _draw(make: Callable[..., Any], args: tuple[Any, ...], path: Path) -> None:
    save_png(make(*args), path)


def write_figures(path: Path, specs: Sequence[Spec], pool: Any, progress: Progress) -> list[tuple[str, str, str]]:
    """Draw the figures into folder ``path`` (in ``pool`` if given), each saved with :func:`save_png`.

    Returns
    -------
    list of (file, paper figure, caption)
    """
    if pool is None:
        for file, _, _, make, args in specs:
            _draw(make, args, path / file)
            progress.update(1, file)
    else:
        futures = [pool.submit(_draw, make, args, path / file) for file, _, _, make, args in specs]
        for (file, *_), future in zip(specs, futures, strict=True):
            future.result()
            progress.update(1, file)
    return [(file, paper_fig, caption) for file, paper_fig, caption, _, _ in specs]
