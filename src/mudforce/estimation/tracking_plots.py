"""Figures of online tracking (needs matplotlib: ``pip install 'mudforce[plot]'``).

:func:`plot_track` draws a tracked recording in two panels sharing the time
axis: the measured and predicted force [N], and the water-content estimate
with its 95 % band [%] (and the truth, when known), with the samples where
a change of mud was flagged marked. :func:`tracking_figure` simulates a walk
whose mud changes partway (:func:`mudforce.motions.gait.walk`), tracks it, and draws
it: deterministic from its seed, for ``mudforce reproduce``.

Built without :mod:`pyplot` on an Agg canvas; PNGs are saved atomically and
byte-for-byte reproducibly (:func:`mudforce.io.plotting.save_png`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from mudforce._plumbing.optional import require
from mudforce.errors import InputError, real_array
from mudforce.io import check_output_path
from mudforce.io.plotting import check_title

if TYPE_CHECKING:
    from mudforce.estimation.tracker import TrackResult

__all__ = ["plot_track", "tracking_figure"]

_FIGSIZE = (9.0, 6.5)  # [in]
_DPI = 100
_FLAG_COLOUR = "#c0392b"
_BAND_COLOUR = "#aed6f1"
_EST_COLOUR = "#1f618d"


def plot_track(result: TrackResult, path: str | os.PathLike[str] | None = None, *,
               truth: np.ndarray | None = None, title: str | None = None) -> Any:
    """Plot a tracked recording: force measured and predicted, and the water content with its band.

    Parameters
    ----------
    result : TrackResult
        From :func:`mudforce.estimation.tracker.track` (time [s], force [N], estimates [-]).
    path : path-like, optional
        Also save the figure there as PNG (a name ending in ``.png``), atomically and reproducibly.
    truth : array_like, optional
        The true water content at each sample [-], drawn dashed when given.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from mudforce.estimation.tracker import TrackResult

    if not isinstance(result, TrackResult):  # was an AttributeError (no attribute 'changed')
        raise InputError(f"result must be a TrackResult (from mudforce.estimation.tracker.track), got "
                         f"{type(result).__name__}")
    check_title(title)
    if isinstance(path, (str, os.PathLike)):  # a.pdf was written with PNG bytes in it
        check_output_path(path, "path", suffix=".png")
    t = np.asarray(result.time, dtype=np.float64)
    if truth is not None:  # was matplotlib's ValueError, not naming truth ('x and y must have same first dimension')
        truth = real_array(truth, "truth", "-")
        if truth.shape != t.shape:
            raise InputError(f"truth must hold one water content per sample [-], shape {t.shape}, got shape "
                             f"{truth.shape}")
    require("matplotlib", "plot", "plotting")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=_FIGSIZE, dpi=_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    ax_f, ax_w = fig.subplots(2, 1, sharex=True, height_ratios=(1.0, 1.0))
    flags = t[np.asarray(result.changed, dtype=bool)]

    ax_f.plot(t, result.force, color="0.55", lw=0.8, label="measured")
    ax_f.plot(t, result.force_predicted, color="k", lw=1.0, label="predicted (one step ahead)")
    ax_f.axhline(0.0, color="0.5", lw=0.6, zorder=1)
    ax_f.set_ylabel("force on foot [N] (+ up)")
    ax_f.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), fontsize="small", ncols=2, frameon=False)

    ax_w.fill_between(t, 100.0 * np.asarray(result.low), 100.0 * np.asarray(result.high), color=_BAND_COLOUR,
                      lw=0.0, label="95 % interval")
    ax_w.plot(t, 100.0 * np.asarray(result.water_content), color=_EST_COLOUR, lw=1.2, label="estimate")
    if truth is not None:
        ax_w.plot(t, 100.0 * truth, color="k", lw=1.0, ls="--", label="truth")
    for ax in (ax_f, ax_w):
        for tf in flags:
            ax.axvline(tf, color=_FLAG_COLOUR, ls=":", lw=1.0)
    if flags.size:
        from matplotlib.lines import Line2D

        handles, _ = ax_w.get_legend_handles_labels()
        handles.append(Line2D([], [], color=_FLAG_COLOUR, ls=":", lw=1.0, label="change flagged"))
        ax_w.legend(handles=handles, loc="best", fontsize="small")
    else:
        ax_w.legend(loc="best", fontsize="small")
    ax_w.set_ylim(14.0, 36.0)
    ax_w.set_xlabel("time [s]")
    ax_w.set_ylabel("water content W [%]")
    if title:
        fig.suptitle(title)
    if path is not None:
        from mudforce.io.plotting import save_png

        save_png(fig, path)
    return fig


def tracking_figure(path: str | os.PathLike[str] | None = None, *, seed: int = 0,
                    water_content: Sequence[float] = (0.20, 0.30), change_time: float = 20.0,
                    duration: float = 45.0, force_noise: float = 0.3, depth_noise: float = 3e-5,
                    bias: float = 0.5) -> Any:
    """Track a simulated walk across a change of mud and plot it (deterministic from ``seed``).

    Parameters
    ----------
    path : path-like, optional
        Save the figure there as PNG (a name ending in ``.png``; atomically, the same bytes for the same
        arguments).
    seed : int
        Seed of the gait and the sensor noise (>= 0).
    water_content : sequence of two float
        Water content before and after the change [-] (default 20 % then 30 %).
    change_time : float
        The mud changes at the first swing at or after this time [s].
    duration : float
        Length of the walk [s].
    force_noise, depth_noise, bias : float
        Sensor noise std [N], [m] and force offset [N].

    Returns
    -------
    matplotlib.figure.Figure
    """
    if isinstance(path, (str, os.PathLike)):  # refused before the walk is simulated and tracked
        check_output_path(path, "path", suffix=".png")
    require("matplotlib", "plot", "the tracking figure")
    from mudforce.estimation.tracker import track
    from mudforce.motions.gait import walk

    values = real_array(water_content, "water_content", "-")  # 0.25 was a TypeError, "ab" a ValueError
    if values.ndim != 1:
        raise InputError(f"water_content must be a sequence of water contents [-] (before and after the change), "
                         f"got shape {values.shape}")
    contents = tuple(values.tolist())
    changes = [change_time] * (len(contents) - 1) if len(contents) <= 2 else [
        change_time * (k + 1) for k in range(len(contents) - 1)]
    w = walk(contents, change_times=changes, seed=seed, duration=duration, force_noise=force_noise,
             depth_noise=depth_noise, bias=bias)
    result = track(w.time, w.depth, w.force)
    title = (f"Tracking across a change of mud: W {' -> '.join(f'{100 * c:g} %' for c in contents)} "
             f"(seed {seed}, force noise {force_noise:g} N, offset {bias:g} N)")
    return plot_track(result, path, truth=w.water_content, title=title)
