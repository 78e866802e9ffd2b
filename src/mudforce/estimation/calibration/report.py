"""A calibration report: markdown and PNG figures for a :class:`~mudforce.estimation.calibration.fit.FitResult`.

For each condition (water content): measured against fitted force over
time and over depth, the residuals, the error profile (mean and one
standard deviation over repeats, as in Fig. 7 of [1]) and a parameter
table with standard errors; across conditions, the parameters against
water content (Figs. 8-9 of [1]) and, when per-speed fits are given,
against speed (Fig. 10 of [1]).

Needs matplotlib (``pip install 'mudforce[plot]'``). The output is
deterministic: the same fit gives the same files, byte for byte (no
timestamps, no software version in the PNGs).

.. [1] X. Chen, J. Yi, J. Shan, arXiv:2403.02617 (2024).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mudforce._plumbing.optional import require
from mudforce.estimation.calibration.fit import ConditionFit, FitResult, TrialFit, speed_key
from mudforce.estimation.calibration.models import get_model
from mudforce.io import atomic_write_text
from mudforce.io.plotting import new_figure, save_png
from mudforce.model.parameters import PAPER_UNITS

__all__ = ["ERROR_PROFILE_POINTS", "error_profile", "write_report"]

#: Points of normalised process time in an error profile [-].
ERROR_PROFILE_POINTS = 200

# shown in the paper's units where Table I has one other than SI (MPa, kPa); the rest in SI
_SCALE = {name: (1.0 / si, unit) for name, (si, unit) in PAPER_UNITS.items() if si != 1.0}


def error_profile(trials: Sequence[TrialFit], points: int = ERROR_PROFILE_POINTS) -> tuple[np.ndarray, ...]:
    """Mean and standard deviation of the force error over trials, on normalised process time.

    Each trial's time runs from its first sample (0) to its last (1); its
    error ``fitted - measured`` [N] is interpolated onto ``points`` equally
    spaced instants, then averaged over the trials (Fig. 7 of [1]).

    Returns
    -------
    s : ndarray
        Normalised time [-].
    mean, std : ndarray
        Mean and standard deviation of the error [N] (std 0 for one trial).
    """
    s = np.linspace(0.0, 1.0, points)
    rows = []
    for t in trials:
        u = (t.time - t.time[0]) / (t.time[-1] - t.time[0])
        rows.append(np.interp(s, u, t.residual))
    block = np.array(rows)
    std = block.std(axis=0, ddof=1) if len(rows) > 1 else np.zeros(points)
    return s, block.mean(axis=0), std


def _figure(ncols: int, nrows: int = 1, width: float = 4.0, height: float = 3.0) -> tuple[Any, np.ndarray]:
    fig = new_figure(width * ncols, height * nrows)
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False)).ravel()
    return fig, axes


def _save(fig: Any, path: Path) -> None:
    save_png(fig, path, dpi=90)


def _groups(cond: ConditionFit) -> dict[float, list[TrialFit]]:
    groups: dict[float, list[TrialFit]] = {}
    for t in cond.trials:
        groups.setdefault(speed_key(t.nominal_velocity, t.velocity), []).append(t)
    return dict(sorted(groups.items()))


def _condition_figures(cond: ConditionFit, out: Path, stem: str) -> list[str]:
    groups = _groups(cond)
    files = []
    for kind, xlabel in (("time", "time [s]"), ("depth", "depth [mm]")):
        fig, axes = _figure(len(groups))
        for ax, (v, trials) in zip(axes, groups.items(), strict=True):
            for i, t in enumerate(trials):
                x = t.time if kind == "time" else t.depth * 1e3
                ax.plot(x, t.force, ".", ms=1.5, color="0.6", label="measured" if i == 0 else None)
                ax.plot(x, t.fitted, "-", lw=1.0, color=f"C{i}", label=f"fit, {t.name}")
            ax.set_title(f"W = {cond.water_content:.0%}, {v * 1e3:g} mm/s")
            ax.set_xlabel(xlabel)
            ax.set_ylabel("force [N]")
            ax.legend(fontsize=6)
        name = f"{stem}_force_{kind}.png"
        _save(fig, out / name)
        files.append(name)
    fig, axes = _figure(len(groups))
    for ax, (v, trials) in zip(axes, groups.items(), strict=True):
        for i, t in enumerate(trials):
            ax.plot(t.time, t.residual, "-", lw=0.6, color=f"C{i}", label=t.name)
        ax.set_title(f"residual, {v * 1e3:g} mm/s")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("fitted - measured [N]")
        ax.legend(fontsize=6)
    files.append(f"{stem}_residuals.png")
    _save(fig, out / files[-1])
    fig, axes = _figure(1, width=6.0)
    ax = axes[0]
    for i, (v, trials) in enumerate(groups.items()):
        s, mean, std = error_profile(trials)
        ax.fill_between(s, mean - std, mean + std, color=f"C{i}", alpha=0.25, lw=0)
        ax.plot(s, mean, color=f"C{i}", lw=1.0, label=f"{v * 1e3:g} mm/s ({len(trials)} trials)")
    ax.set_title(f"error profile, W = {cond.water_content:.0%} (mean ± 1 sd over repeats)")
    ax.set_xlabel("normalised process time [-]")
    ax.set_ylabel("fitted - measured [N]")
    ax.legend(fontsize=7)
    files.append(f"{stem}_error_profile.png")
    _save(fig, out / files[-1])
    return files


def _fmt(value: float | None, name: str) -> str:
    if value is None or not math.isfinite(value):
        return "—"
    scale, _ = _SCALE.get(name, (1.0, ""))
    return f"{value * scale:.4g}"


def _unit(name: str, units: Mapping[str, str]) -> str:
    return _SCALE[name][1] if name in _SCALE else units.get(name, "")


def _parameter_table(cond: ConditionFit, units: Mapping[str, str]) -> list[str]:
    lines = ["| parameter | value | standard error | unit |", "|---|---|---|---|"]
    for name, value in cond.parameters.items():
        se = cond.stderr.get(name)
        fixed = name not in cond.free
        lines.append(f"| {name} | {_fmt(value, name)} | {'fixed' if fixed else _fmt(se, name)} "
                     f"| {_unit(name, units)} |")
    return lines


def _trend_figure(points: Mapping[str, list[tuple[float, float, float | None, str]]], names: Sequence[str],
                  xlabel: str, title: str, units: Mapping[str, str], path: Path) -> None:
    ncols = 3
    nrows = max(1, math.ceil(len(names) / ncols))
    fig, axes = _figure(ncols, nrows, width=3.3, height=2.6)
    for ax, name in zip(axes, names, strict=False):
        series: dict[str, list[tuple[float, float, float]]] = {}
        for x, value, se, label in points[name]:
            scale = _SCALE.get(name, (1.0, ""))[0]
            series.setdefault(label, []).append((x, value * scale, (se or 0.0) * scale))
        for i, (label, rows) in enumerate(sorted(series.items())):
            arr = np.array(sorted(rows))
            ax.errorbar(arr[:, 0], arr[:, 1], yerr=arr[:, 2], fmt="o-", ms=3, lw=1, capsize=2, color=f"C{i}",
                        label=label or None)
        ax.set_title(f"{name} [{_unit(name, units)}]", fontsize=9)
        ax.set_xlabel(xlabel, fontsize=8)
        if any(label for label in series):
            ax.legend(fontsize=6)
    for ax in axes[len(names):]:
        ax.set_visible(False)
    fig.suptitle(title)
    _save(fig, path)


def write_report(fit: FitResult, directory: str | os.PathLike[str], *,
                 velocity_fits: Sequence[tuple[float, ConditionFit]] = ()) -> Path:
    """Write ``report.md`` and its PNG figures into ``directory``.

    Parameters
    ----------
    fit : FitResult
        The dataset's fit.
    directory : path-like
        Output folder (created).
    velocity_fits : sequence of (speed [m/s], ConditionFit)
        Optional fits of each (water content, speed) on its own, for the
        parameters-against-speed figure (Fig. 10 of [1]).

    Returns
    -------
    Path
        The ``report.md`` written.
    """
    require("matplotlib", "plot", "the calibration report (--report)")
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    units = get_model(fit.model).units
    lines = [f"# Calibration report ({fit.model})", ""]
    lines += [f"Foot: area {fit.foot.area * 1e4:.4g} cm², width {fit.foot.width * 1e3:.4g} mm. Seed {fit.seed}."]
    if fit.shared:
        lines += [f"Shared across water contents: {', '.join(fit.shared)}."]
    lines += ["", "| W | RMSE [N] | force noise [N] | trials | warnings |", "|---|---|---|---|---|"]
    for c in fit.conditions:
        lines.append(f"| {c.water_content:.1%} | {c.rmse:.3f} | {c.force_noise:.3f} | {len(c.trials)} "
                     f"| {len(c.warnings)} |")
    for c in fit.conditions:
        stem = f"W{c.water_content * 100:g}".replace(".", "p")
        files = _condition_figures(c, out, stem)
        lines += ["", f"## W = {c.water_content:.1%}", ""]
        lines += [f"RMSE {c.rmse:.3f} N against a force noise of {c.force_noise:.3f} N.", ""]
        lines += _parameter_table(c, units)
        lines += ["", "| trial | speed [mm/s] | RMSE [N] | bias [N] | reversal [s] |", "|---|---|---|---|---|"]
        lines += [f"| {t.name} | {t.velocity * 1e3:.3g} | {t.rmse:.3f} | {t.bias:.3f} | {t.reversal_time:.4f} |"
                  for t in c.trials]
        if c.warnings:
            lines += ["", "Warnings:", ""] + [f"- {w}" for w in c.warnings]
        lines += [""] + [f"![{f}]({f})" for f in files]
    free = [n for n in get_model(fit.model).parameter_names if any(n in c.free for c in fit.conditions)]
    by_w: dict[str, list[tuple[float, float, float | None, str]]] = {n: [] for n in free}
    for c in fit.conditions:
        for n in free:
            by_w[n].append((c.water_content * 100, c.parameters[n], c.stderr.get(n), ""))
    _trend_figure(by_w, free, "water content W [%]", "parameters against water content (Figs. 8-9)", units,
                  out / "parameters_vs_water_content.png")
    lines += ["", "## Parameters against water content", "", "![parameters](parameters_vs_water_content.png)"]
    if velocity_fits:
        by_v: dict[str, list[tuple[float, float, float | None, str]]] = {n: [] for n in free}
        for v, c in velocity_fits:
            for n in free:
                by_v[n].append((v * 1e3, c.parameters[n], c.stderr.get(n), f"W = {c.water_content:.0%}"))
        _trend_figure(by_v, free, "speed [mm/s]", "parameters fitted per speed (Fig. 10)", units,
                      out / "parameters_vs_velocity.png")
        lines += ["", "## Parameters against speed", "",
                  "Each (water content, speed) fitted on its own trials.", "",
                  "![parameters](parameters_vs_velocity.png)"]
    path = out / "report.md"
    atomic_write_text(path, "\n".join(lines) + "\n")
    return path
