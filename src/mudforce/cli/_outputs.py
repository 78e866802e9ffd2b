"""The suffix of ``--out FILE``, for the commands that write one file: any name, but not another format's.

A name may end in anything (``forces.txt``, ``run1``), but not in the suffix
of another format: ``mudforce simulate --out o.png`` wrote CSV under that
name (the plot is ``--plot``), ``mudforce fit --out f.csv`` JSON. Checked
after :func:`mudforce.io.check_output_path` and the check that an output
overwrites no input, which say the graver thing first.
"""

from __future__ import annotations

from pathlib import Path

from mudforce.errors import InputError

__all__ = ["OTHER_FORMATS", "check_suffix"]

#: Suffixes (lower case) that name a format, with its name: figures, tables and the package's text formats.
OTHER_FORMATS: dict[str, str] = {
    ".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG", ".svg": "SVG", ".pdf": "PDF", ".eps": "EPS", ".gif": "GIF",
    ".tif": "TIFF", ".tiff": "TIFF", ".webp": "WebP", ".csv": "CSV", ".tsv": "TSV", ".json": "JSON",
    ".html": "HTML", ".md": "Markdown", ".xlsx": "Excel", ".xls": "Excel", ".npy": "NumPy", ".npz": "NumPy",
}


def check_suffix(path: Path, option: str, written: str, suffix: str, plot: str = "") -> None:
    """Refuse an output ``path`` whose suffix names another format than the one ``written``: one line naming the
    expected ``suffix`` and what writes a plot instead.

    Parameters
    ----------
    path : Path
        The output file, as :func:`mudforce.io.check_output_path` returned it.
    option : str
        The option, for the message (``"--out"``).
    written : str
        The format written, as :data:`OTHER_FORMATS` names it (``"CSV"``).
    suffix : str
        Its suffix (``".csv"``).
    plot : str
        What writes a plot instead (``"--plot FILE.png writes a plot"``), or "" for none.
    """
    named = OTHER_FORMATS.get(path.suffix.lower())
    if named is not None and named != written:
        where = f" ({plot})" if plot else ""
        raise InputError(f"{option}: {str(path)[:80]!r} ends in {path.suffix} ({named}), but {option} writes "
                         f"{written}; expected a name ending in {suffix}{where}")
