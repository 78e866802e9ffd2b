"""Figures of a simulated foot (needs matplotlib: ``pip install 'mudforce[plot]'``): depth, velocity and mud
force over time, with its phases shaded (:mod:`mudforce.engines.dynamics`). The figure and its PNG are made by
:mod:`mudforce.io.plotting`.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from mudforce._plumbing.optional import require
from mudforce.engines.dynamics.result import PHASE_NAMES, FootResult, check_path
from mudforce.io import check_output_path
from mudforce.io.plotting import check_title, new_figure, save_png

__all__ = ["PHASE_COLOURS", "plot_foot_result"]

#: Shading per phase of a simulated foot (FREE is left unshaded).
PHASE_COLOURS: dict[str, str] = {"INTRUSION": "#cfe3f7", "WITHDRAWAL": "#fbd9b5", "STUCK": "#d5efd0",
                                 "NECKED": "#f3c6c6"}


def plot_foot_result(result: FootResult, path: str | os.PathLike[str] | None = None, *,
                     title: str | None = None) -> Any:
    """Depth [mm], velocity [mm/s] and mud force [N] of a simulated foot over time [s], phases shaded.

    Parameters
    ----------
    result : FootResult
        From :func:`mudforce.engines.dynamics.simulate_foot` or :func:`mudforce.engines.mujoco.simulate_drop`.
    path : str or PathLike, optional
        Where to save the figure as PNG (atomically, without metadata that varies).
    title : str, optional
        Figure title; by default the mass and the engine.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not isinstance(result, FootResult):
        from mudforce.errors import InputError

        raise InputError(f"result must be a FootResult, got {type(result).__name__}")
    if path is not None:
        check_path(path, "path")
        check_output_path(path, "path", suffix=".png")  # 'foot.pdf' was written with PNG bytes
    check_title(title)
    require("matplotlib", "plot", "plotting")
    from matplotlib.patches import Patch

    fig = new_figure(8.0, 7.0, layout=None)
    axes = fig.subplots(3, 1, sharex=True)
    series = ((result.depth * 1e3, "depth [mm]"), (result.velocity * 1e3, "velocity [mm/s]"),
              (result.force, "mud force [N]"))
    change = np.flatnonzero(np.diff(result.phase.astype(np.int64))) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change, [result.phase.size - 1]))
    for ax, (data, label) in zip(axes, series, strict=True):
        for s, e in zip(starts, ends, strict=True):
            colour = PHASE_COLOURS.get(PHASE_NAMES[int(result.phase[s])])
            if colour is not None:
                ax.axvspan(result.time[s], result.time[e], color=colour, lw=0)
        ax.plot(result.time, data, color="k", lw=1.0)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    shown = {PHASE_NAMES[int(c)] for c in np.unique(result.phase)}
    handles = [Patch(color=c, label=name) for name, c in PHASE_COLOURS.items() if name in shown]
    if handles:
        axes[0].legend(handles=handles, loc="lower right", fontsize="small")
    axes[2].axhline(result.mass * result.gravity, color="#c0392b", lw=0.8, ls="--", label="m g")
    axes[2].legend(loc="lower right")
    axes[2].set_xlabel("time [s]")
    fig.suptitle(title or f"{result.mass:g} kg foot dropped in mud ({result.engine} engine)")
    if path is not None:
        save_png(fig, path, dpi=100)
    return fig
