"""The whole run of :mod:`mudforce.reproduce`: synthetic experiments, fits, figures, ``report.html``, ``summary.json``.

No experimental data from Chen, Yi & Shan (arXiv:2403.02617) is public, so
:func:`reproduce` works the way the paper did, on data the project can make:

1. **Synthetic experiments** (:mod:`mudforce.reproduce.experiments`): for
   each water content, speed and repeat, one trial of the paper's protocol
   from Table I, with sensor noise and trial-to-trial scatter of the mud.
2. **Calibration** (:mod:`mudforce.reproduce.jobs`): the paper's model is
   fitted per water content (all speeds: "Table I as fitted") and per
   (water content, speed) (Fig. 10) with
   :func:`mudforce.estimation.calibration.fit_condition`; the baselines of
   :mod:`mudforce.model.baselines` are fitted on the same trials.
3. **Report**: ``summary.json`` (:mod:`mudforce.reproduce.summary`), the PNG
   figures, each captioned with the paper's figure it corresponds to
   (:mod:`mudforce.reproduce.figures`), and ``report.html``
   (:mod:`mudforce.reproduce.html`), all built in a hidden sibling folder
   and swapped in whole at the end (:mod:`mudforce.reproduce.output`).

Everything is deterministic for a given seed: the fits are seeded, the
figures are rendered without timestamps or version metadata, and the
numbers in ``summary.json`` are rounded to 6 significant digits. Parallel
fits (``jobs > 1``) give the same result as serial ones.

A run stopped at any point leaves the old report or the new one, never a
mix; its worker processes end with it, even on SIGKILL; on SIGTERM it
stops its workers, removes its unfinished folder and exits with status 143.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from mudforce._plumbing.progress import Progress
from mudforce.errors import InputError, true_or_false
from mudforce.estimation.calibration.dataset import Dataset
from mudforce.estimation.calibration.fit import ConditionFit
from mudforce.io import atomic_write_text
from mudforce.model.parameters import MudParameters
from mudforce.reproduce.experiments import ReproduceConfig, make_experiments
from mudforce.reproduce.figures import N_FIGURES, figure_specs, warm_up_matplotlib, write_figures
from mudforce.reproduce.html import render_html
from mudforce.reproduce.jobs import count_fits, executor, job_count, run_fits, sort_fits, terminate
from mudforce.reproduce.output import StagedFolder, check_report_dir
from mudforce.reproduce.summary import make_summary, summary_json

__all__ = ["ReproduceResult", "Terminated", "reproduce"]


class Terminated(SystemExit):
    """Raised in :func:`reproduce` when the process receives SIGTERM (exit status 128 + 15)."""


@contextlib.contextmanager
def _sigterm_raises() -> Iterator[None]:
    """While inside, SIGTERM raises :class:`Terminated` (main thread only), so that cleanups run."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        raise Terminated(128 + signum)

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


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


def reproduce(out: str | os.PathLike[str], config: ReproduceConfig | None = None, *, jobs: int = 1,
              quiet: bool = False, log: Callable[[str], None] | None = None) -> ReproduceResult:
    """Make the synthetic experiments, fit the model and the baselines, and write the report.

    Parameters
    ----------
    out : path-like
        Folder for ``report.html``, ``summary.json`` and the PNG figures:
        new, empty, or an earlier report's (it is replaced whole, at the end).
    config : ReproduceConfig, optional
        :meth:`ReproduceConfig.full` by default.
    jobs : int
        Worker processes for the fits (1: in this process), at most 64. The result does not depend on it.
    quiet : bool
        No progress on the terminal.
    log : callable, optional
        Receives one line per stage (e.g. ``print``), independent of the terminal.

    Returns
    -------
    ReproduceResult

    Raises
    ------
    InputError
        If ``out`` cannot hold the report (see
        :func:`mudforce.reproduce.output.check_report_dir`), ``config`` is no
        :class:`ReproduceConfig`, ``log`` is not callable, or ``jobs`` is not
        in [1, :data:`mudforce.reproduce.jobs.MAX_JOBS`] (64).
    Terminated
        On SIGTERM (in the main thread): the workers are stopped and ``out`` is left as it was.
    """
    from mudforce._plumbing.optional import require

    require("matplotlib", "plot", "mudforce reproduce")
    config = ReproduceConfig.full() if config is None else config
    if not isinstance(config, ReproduceConfig):  # was an AttributeError ('str' object has no attribute 'seed')
        raise InputError(f"config must be a ReproduceConfig or None, got {type(config).__name__}")
    jobs = job_count(jobs)
    quiet = true_or_false(quiet, "quiet")
    if log is not None and not callable(log):  # was a TypeError once the experiments were made
        raise InputError(f"log must be a callable (e.g. print) or None, got {type(log).__name__}")
    path = check_report_dir(out)
    warm_up_matplotlib()  # before the workers fork, so that they do not each pay for it
    say = log if log is not None else (lambda _: None)
    with _sigterm_raises(), StagedFolder(path) as staged:
        dataset, truths = make_experiments(config)
        n_fits = count_fits(config, dataset)
        pool = executor(jobs)
        try:
            with Progress(n_fits + N_FIGURES + 1, "reproduce", quiet=quiet) as progress:
                progress.update(1, "synthetic experiments")
                say(f"made {len(dataset.trials)} synthetic trials; fitting {n_fits} conditions")
                fits = run_fits(config, dataset, pool, progress)
                table, by_speed, baselines = sort_fits(fits)
                specs = figure_specs(config, dataset, table, by_speed, baselines)
                figures = write_figures(staged.staged, specs, pool, progress)
        except BaseException:
            if pool is not None:
                terminate(pool)
            raise
        if pool is not None:
            pool.shutdown()
        summary = make_summary(config, dataset, table, by_speed, baselines, figures)
        atomic_write_text(staged.staged / "summary.json", summary_json(summary))
        atomic_write_text(staged.staged / "report.html", render_html(config, summary, figures))
        staged.commit()
    say(f"wrote {path / 'report.html'}, {path / 'summary.json'} and {len(figures)} figures")
    return ReproduceResult(config=config, dataset=dataset, truths=truths, table_fits=table, velocity_fits=by_speed,
                           baseline_fits=baselines, summary=summary, figures=figures)
