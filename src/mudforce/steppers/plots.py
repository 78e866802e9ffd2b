"""Figures of a simulation result (needs matplotlib: ``pip install 'mudforce[plot]'``).

:func:`plot_result` draws three panels:

* force [N] over time [s], with the contact states FREE / CONTACT / NECKED
  shaded and every necking instant (Eq. (9)) marked;
* force [N] over foot depth [mm] (the hysteresis loop of intrusion and
  withdrawal);
* foot depth ``z_i`` and mud displacement ``z_m`` (Eq. (3)) [mm] over time [s].

Values are SI inside; the depth axes are drawn in millimetres because that
is the scale of the experiment. The figure and its PNG are made by :mod:`mudforce.io.plotting`.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

import numpy as np

from mudforce._kernel.layout import STATE_NAMES
from mudforce._plumbing.optional import require
from mudforce.errors import InputError
from mudforce.io import check_output_path
from mudforce.io.plotting import check_title, new_figure, save_png

if TYPE_CHECKING:
    from mudforce.steppers.simulation import SimulationResult

__all__ = ["STATE_COLOURS", "plot_result"]

#: Shading per contact state (FREE is left unshaded).
STATE_COLOURS: dict[str, str | None] = {"FREE": None, "CONTACT": "#cfe3f7", "NECKED": "#fbd9b5"}

_NECK_COLOUR = "#c0392b"
#: What plot_result reads of its result.
_DRAWN = ("time", "depth", "force", "mud_displacement", "necking_times", "state")
_FIGSIZE = (9.0, 7.0)  # [in]


def _state_runs(state: np.ndarray) -> list[tuple[int, int, int]]:
    """Runs of equal state as ``(code, first, last)`` sample indices (inclusive)."""
    if state.size == 0:
        return []
    change = np.flatnonzero(np.diff(state.astype(np.int64))) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change - 1, [state.size - 1]))
    return [(int(state[s]), int(s), int(e)) for s, e in zip(starts, ends, strict=True)]


def _shade_states(ax: Any, result: SimulationResult) -> list[Any]:
    """Shade each run of CONTACT or NECKED samples; returns legend handles."""
    from matplotlib.patches import Patch


    t = result.time
    used: set[str] = set()
    for code, first, last in _state_runs(result.state):
        name = STATE_NAMES[code]
        colour = STATE_COLOURS.get(name)
        if colour is None:
            continue
        # sample k's state holds over the step (t[k-1], t[k]] that ends at it
        left = t[first - 1] if first > 0 else t[first]
        right = t[last]
        ax.axvspan(left, right, color=colour, lw=0, zorder=0)
        used.add(name)
    handles = [Patch(facecolor="white", edgecolor="0.6", label="FREE")]
    handles += [Patch(facecolor=STATE_COLOURS[n], label=n) for n in ("CONTACT", "NECKED") if n in used]
    return handles


def plot_result(result: SimulationResult, path: str | os.PathLike[str] | None = None, *,
                title: str | None = None) -> Any:
    """Plot a simulation result: force over time and depth, and the displacements.

    Parameters
    ----------
    result : SimulationResult
        From :func:`mudforce.simulate` (time [s], depth [m], force [N], ...).
    path : path-like, optional
        Also save the figure there as PNG [100 dpi] (a name ending in ``.png``), atomically (a temporary
        file beside ``path``, then a rename: an existing file is replaced
        whole or not at all) and reproducibly (no version or timestamp in
        the metadata).
    title : str, optional
        Figure title; none by default.

    Returns
    -------
    matplotlib.figure.Figure
        Not registered with :mod:`matplotlib.pyplot`; display it in a
        notebook as is, or save it with :func:`save_png`.

    Raises
    ------
    InputError
        If ``result`` is no :class:`SimulationResult`, ``title`` no str, or ``path`` does not end in
        ``.png`` or cannot be written.
    mudforce._plumbing.optional.MissingDependencyError
        If matplotlib is not installed.
    """
    # by what is drawn, not by class (steppers.simulation, a front end, is not imported here): was an AttributeError
    if not all(hasattr(result, name) for name in _DRAWN):  # ('dict' object has no attribute 'time')
        raise InputError(f"result must be a SimulationResult (from mudforce.simulate), got {type(result).__name__}")
    check_title(title)
    if isinstance(path, (str, os.PathLike)):  # a.pdf was written with PNG bytes in it
        check_output_path(path, "path", suffix=".png")
    require("matplotlib", "plot", "plotting")
    from matplotlib.lines import Line2D

    t = np.asarray(result.time, dtype=np.float64)
    z_mm = np.asarray(result.depth, dtype=np.float64) * 1e3
    zm_mm = np.asarray(result.mud_displacement, dtype=np.float64) * 1e3
    force = np.asarray(result.force, dtype=np.float64)
    necks = np.asarray(result.necking_times, dtype=np.float64)

    fig = new_figure(*_FIGSIZE)
    grid = fig.add_gridspec(2, 2, height_ratios=(1.1, 1.0))
    ax_ft = fig.add_subplot(grid[0, :])
    ax_fz = fig.add_subplot(grid[1, 0])
    ax_zt = fig.add_subplot(grid[1, 1], sharex=ax_ft)

    # force over time, with contact states and necking instants
    handles = _shade_states(ax_ft, result)
    (line,) = ax_ft.plot(t, force, color="k", lw=1.2, label="force")
    ax_ft.axhline(0.0, color="0.5", lw=0.6, zorder=1)
    for tn in necks:
        ax_ft.axvline(tn, color=_NECK_COLOUR, ls="--", lw=1.0)
    legend = [line, *handles]
    if necks.size:
        legend.append(Line2D([], [], color=_NECK_COLOUR, ls="--", lw=1.0, label="necking"))
    # above the axes, so that it never hides the curve
    ax_ft.legend(handles=legend, loc="lower center", bbox_to_anchor=(0.5, 1.0), fontsize="small",
                 ncols=len(legend), frameon=False)
    ax_ft.set_xlabel("time [s]")
    ax_ft.set_ylabel("force on foot [N] (+ up)")

    # force over depth
    ax_fz.plot(z_mm, force, color="k", lw=1.0)
    ax_fz.axhline(0.0, color="0.5", lw=0.6)
    ax_fz.axvline(0.0, color="0.5", lw=0.6)
    if necks.size and t.size > 1:
        zn = np.interp(necks, t, z_mm)
        fn = np.interp(necks, t, force)
        ax_fz.plot(zn, fn, ls="none", marker="x", color=_NECK_COLOUR, label="necking")
        ax_fz.legend(loc="best", fontsize="small")
    ax_fz.set_xlabel("foot depth $z_i$ [mm] (+ down)")
    ax_fz.set_ylabel("force on foot [N] (+ up)")
    ax_fz.set_title("Force over depth", fontsize="medium")

    # depth and mud displacement over time
    ax_zt.plot(t, z_mm, color="k", lw=1.2, label="foot depth $z_i$")
    ax_zt.plot(t, zm_mm, color="#2471a3", lw=1.0, ls="-.", label="mud displacement $z_m$")
    ax_zt.axhline(0.0, color="0.5", lw=0.6)
    for tn in necks:
        ax_zt.axvline(tn, color=_NECK_COLOUR, ls="--", lw=1.0)
    ax_zt.invert_yaxis()  # down is down
    ax_zt.legend(loc="best", fontsize="small")
    ax_zt.set_xlabel("time [s]")
    ax_zt.set_ylabel("displacement [mm] (+ down)")
    ax_zt.set_title("Foot and mud displacement", fontsize="medium")

    if title:
        fig.suptitle(title)
    if path is not None:
        save_png(fig, path)
    return fig
