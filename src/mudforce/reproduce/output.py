"""The report's folder of :mod:`mudforce.reproduce`: checked first, built aside, swapped in whole.

``mudforce reproduce --out DIR`` replaces the folder ``DIR`` as a whole, so
that a run stopped at any point (Ctrl-C, SIGTERM, even SIGKILL or a power
cut) leaves either the old report or the new one in ``DIR``, never a mix.
The machinery is the package's one for outputs staged and swapped in
together (:mod:`mudforce.io`, steps 4-6), with the tag
``mudforce-reproduce``:

1. :func:`check_report_dir` refuses, before any work, a ``DIR`` that is a
   file, that holds anything but an earlier report (``report.html``,
   ``summary.json``, PNGs), or that overlaps the mudforce package (whose
   files are the report's inputs): what is in ``DIR`` is replaced.
2. :class:`StagedFolder` builds the report in a sibling folder
   ``.DIR.mudforce-reproduce-new-XXXXXXXX`` (hidden), locked with
   ``flock`` for as long as the run (and its workers) live.
3. :meth:`StagedFolder.commit` swaps it in: on Linux with one atomic
   ``renameat2(RENAME_EXCHANGE)``; elsewhere by renaming ``DIR`` aside
   (``.DIR.mudforce-reproduce-old-XXXXXXXX``), then the new folder in.
   The old report is then deleted.

Each run first removes the siblings that earlier killed runs left (those
whose lock nobody holds; :func:`clean_stale`); an old report left renamed
aside between the two renames of step 3 is put back if ``DIR`` is missing.

File-system plumbing (no physics).
"""

from __future__ import annotations

import os
from pathlib import Path

from mudforce import io

__all__ = ["REPORT_FILES", "StagedFolder", "check_report_dir", "clean_stale"]

#: What a report folder may hold besides its PNG figures.
REPORT_FILES = frozenset({"report.html", "summary.json"})

#: The tag in the names of this command's staged siblings.
_TAG = "mudforce-reproduce"


def check_report_dir(out: str | os.PathLike[str], option: str = "--out") -> Path:
    """The report folder ``out`` as an absolute path, after checking that it can be replaced whole.

    Parameters
    ----------
    out : path-like
        The folder (need not exist; its parent is created if needed).
    option : str
        The option's name, for the message.

    Returns
    -------
    Path
        ``out`` resolved (symbolic links followed).

    Raises
    ------
    InputError
        If ``out`` is a file or a mount point, holds anything but an earlier
        report, overlaps the mudforce package, or its parent folder cannot be
        created or written (see :func:`mudforce.io.check_replaceable_dir`).
    """
    return io.check_replaceable_dir(out, option, REPORT_FILES, _TAG)


def clean_stale(path: Path) -> list[Path]:
    """Remove what killed runs left beside report folder ``path``; put back an old report left aside.

    Only siblings named by this module and locked by nobody are touched
    (:func:`mudforce.io.clean_stale`).

    Returns
    -------
    list of Path
        The siblings removed or put back.
    """
    return io.clean_stale(path, _TAG)


class StagedFolder(io.StagedOutputs):
    """A hidden sibling folder where a report is built, then swapped in for ``path`` whole.

    Use as a context manager: leaving it with an exception removes the
    staged folder and leaves ``path`` as it was; :meth:`commit` swaps.

    Parameters
    ----------
    path : Path
        The report folder, as :func:`check_report_dir` returns it.

    Attributes
    ----------
    path : Path
        The report folder.
    staged : Path
        Where the report is built.
    """

    def __init__(self, path: Path) -> None:
        super().__init__(_TAG, folders=[path])
        self.path = path
        self.staged = self.staged_path(path)
