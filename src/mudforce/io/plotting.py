"""Figures as files: a figure without :mod:`pyplot`, and PNG bytes or files made reproducibly (needs
matplotlib: ``pip install 'mudforce[plot]'``).

The figure is built without :mod:`pyplot` (no global figure registry, no GUI backend) on an Agg canvas, and
saved as PNG atomically and byte-for-byte reproducibly: no software version or timestamp in the file's
metadata. What each result draws lives with the result: :mod:`mudforce.steppers.plots` (a simulation),
:mod:`mudforce.engines.dynamics.plots` (a simulated foot), :mod:`mudforce.estimation.tracking_plots` (a
tracker's run).
"""

from __future__ import annotations

import io
import os
from typing import Any, Literal

from mudforce._plumbing.deprecation import module_getattr
from mudforce._plumbing.optional import require

__all__ = ["check_title", "figure_to_png", "new_figure", "save_png"]

_FIGSIZE = (9.0, 7.0)  # [in]
_DPI = 100
#: PNG metadata keys set to ``None`` are left out of the file (matplotlib writes "Software" by default).
_PNG_METADATA: dict[str, Any] = {"Software": None}


def check_title(title: Any) -> None:
    """Refuse a figure title that is not a str or None in one line: the plots' ``if title:`` raised numpy's
    ValueError (truth value ambiguous) for an array, and matplotlib's str() of 10**5000 raised ValueError."""
    if title is not None and not isinstance(title, str):
        from mudforce.errors import InputError

        raise InputError(f"title must be a str or None, got {type(title).__name__}")


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
    mudforce._plumbing.optional.MissingDependencyError
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

    if isinstance(path, (str, os.PathLike)) and os.fspath(path)[-4:].lower() != ".png":  # (callers check first)
        from mudforce.errors import InputError

        raise InputError(f"{os.fspath(path)!r} must end in .png (only PNG is written)")
    data = figure_to_png(fig, dpi=dpi)
    with atomic_open(path, "wb") as handle:
        handle.write(data)


# moved to the results they draw (docs/api.md, "Moved in 0.2")
__getattr__ = module_getattr("mudforce.io.plotting", {
    "plot_result": ("mudforce.steppers.plots.plot_result", "mudforce.steppers.plots:plot_result"),
    "STATE_COLOURS": ("mudforce.steppers.plots.STATE_COLOURS", "mudforce.steppers.plots:STATE_COLOURS"),
    "plot_foot_result": ("mudforce.engines.dynamics.plots.plot_foot_result",
                         "mudforce.engines.dynamics.plots:plot_foot_result"),
    "PHASE_COLOURS": ("mudforce.engines.dynamics.plots.PHASE_COLOURS",
                      "mudforce.engines.dynamics.plots:PHASE_COLOURS"),
})
