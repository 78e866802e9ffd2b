"""Figures of a simulation result (needs matplotlib: ``pip install 'mudforce[plot]'``).

:func:`plot_result` draws three panels:

* force [N] over time [s], with the contact states FREE / CONTACT / NECKED
  shaded and every necking instant (Eq. (9)) marked;
* force [N] over foot depth [mm] (the hysteresis loop of intrusion and
  withdrawal);
* foot depth ``z_i`` and mud displacement ``z_m`` (Eq. (3)) [mm] over time [s].

:func:`plot_foot_result` draws a simulated foot (:mod:`mudforce.dynamics`):
depth, velocity and mud force over time, with its phases shaded.

Values are SI inside; the depth axes are drawn in millimetres because that
is the scale of the experiment. The figure is built without :mod:`pyplot`
(no global figure registry, no GUI backend) on an Agg canvas, and saved as
PNG atomically and byte-for-byte reproducibly: no software version or
timestamp in the file's metadata.
"""

from __future__ import annotations

import io
import os
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mudforce._optional import require

if TYPE_CHECKING:
    from mudforce.dynamics.result import FootResult
    from mudforce.simulation import SimulationResult

__all__ = [
    "PHASE_COLOURS",
    "STATE_COLOURS",
    "figure_to_png",
    "new_figure",
    "plot_foot_result",
    "plot_result",
    "save_png",
]

#: Shading per contact state (FREE is left unshaded).
STATE_COLOURS: dict[str, str | None] = {"FREE": None, "CONTACT": "#cfe3f7", "NECKED": "#fbd9b5"}

#: Shading per phase of a simulated foot (FREE is left unshaded).
PHASE_COLOURS: dict[str, str] = {"INTRUSION": "#cfe3f7", "WITHDRAWAL": "#fbd9b5", "STUCK": "#d5efd0",
                                 "NECKED": "#f3c6c6"}

_NECK_COLOUR = "#c0392b"
_FIGSIZE = (9.0, 7.0)  # [in]
_DPI = 100
#: PNG metadata keys set to ``None`` are left out of the file (matplotlib writes "Software" by default).
_PNG_METADATA: dict[str, Any] = {"Software": None}


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

    from mudforce.simulation import STATE_NAMES

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
        Also save the figure there as PNG [100 dpi], atomically (a temporary
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
    mudforce._optional.MissingDependencyError
        If matplotlib is not installed.
    """
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


def new_figure(width: float, height: float, *, dpi: float = _DPI,
               layout: Literal["constrained", "compressed", "tight"] | None = "constrained") -> Any:
    """A matplotlib figure on its own Agg canvas, outside :mod:`matplotlib.pyplot`.

    The one figure constructor of mudforce's plots: no global figure
    registry, no GUI backend, so it works in worker processes and on
    headless machines, and nothing is kept alive after the caller drops it.

    Parameters
    ----------
    width, height : float
        Figure size [in].
    dpi : float
        Resolution [dots per inch] of the figure and of its PNG (100 by default).
    layout : str or None
        matplotlib layout engine ("constrained" by default).

    Returns
    -------
    matplotlib.figure.Figure
        Add axes with ``fig.subplots(...)`` or ``fig.add_gridspec(...)``.

    Raises
    ------
    mudforce._optional.MissingDependencyError
        If matplotlib is not installed.
    """
    require("matplotlib", "plot", "plotting")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi, layout=layout)
    FigureCanvasAgg(fig)
    return fig


def figure_to_png(fig: Any, *, dpi: float | None = None) -> bytes:
    """Render a matplotlib figure to PNG bytes with the Agg renderer, without metadata that varies.

    The one way mudforce turns a figure into PNG bytes: the same figure
    gives the same bytes (no software version, no timestamp).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (its size is kept).
    dpi : float, optional
        Resolution of the PNG [dots per inch]; the figure's own by default.

    Returns
    -------
    bytes
        The PNG file's content; identical for identical figures.
    """
    require("matplotlib", "plot", "plotting")
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    buffer = io.BytesIO()
    if dpi is None:
        fig.savefig(buffer, format="png", metadata=dict(_PNG_METADATA))
    else:
        fig.savefig(buffer, format="png", dpi=dpi, metadata=dict(_PNG_METADATA))
    return buffer.getvalue()


def save_png(fig: Any, path: str | os.PathLike[str], *, dpi: float | None = None) -> None:
    """Save a figure as PNG at ``path`` atomically (temporary file, then rename), reproducibly.

    The one way mudforce saves a PNG. The figure is rendered in memory
    first (:func:`figure_to_png`), so a rendering error leaves an existing
    file at ``path`` untouched.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : path-like
        The PNG file to write (replaced whole or not at all).
    dpi : float, optional
        Resolution [dots per inch]; the figure's own by default.
    """
    from mudforce.io import atomic_open

    data = figure_to_png(fig, dpi=dpi)
    with atomic_open(path, "wb") as handle:
        handle.write(data)


def plot_foot_result(result: FootResult, path: str | os.PathLike[str] | None = None, *,
                     title: str | None = None) -> Any:
    """Depth [mm], velocity [mm/s] and mud force [N] of a simulated foot over time [s], phases shaded.

    Parameters
    ----------
    result : FootResult
        From :func:`mudforce.dynamics.simulate_foot` or :func:`mudforce.mujoco.simulate_drop`.
    path : str or PathLike, optional
        Where to save the figure as PNG (atomically, without metadata that varies).
    title : str, optional
        Figure title; by default the mass and the engine.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from mudforce.dynamics.result import PHASE_NAMES, FootResult, check_path

    if not isinstance(result, FootResult):
        from mudforce.errors import InputError

        raise InputError(f"result must be a FootResult, got {type(result).__name__}")
    if path is not None:
        check_path(path, "path")
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
