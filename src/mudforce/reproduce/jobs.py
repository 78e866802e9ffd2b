"""The fits of :mod:`mudforce.reproduce`, as jobs, and the worker processes that run them.

The paper's model is fitted per water content on all its speeds ("Table I
as fitted"), the baselines of :mod:`mudforce.model.baselines` per water content on
the same trials, and, once a water content's fit is known, the paper's
model per (water content, speed) with only :data:`VELOCITY_FREE` free
(Fig. 10). Every fit has its own seed, so the result does not depend on
the order the jobs finish in, nor on the number of workers.

Process plumbing (no physics): :func:`executor` makes the worker pool.
Its workers die with the process that made them, even when that process
is killed with SIGKILL (which it cannot catch): on Linux the kernel is
asked to kill them (``prctl(PR_SET_PDEATHSIG)``), and everywhere a watchdog
thread in each worker exits when its parent is gone. :func:`terminate`
stops a pool at once, for an interrupted run.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from mudforce._plumbing.progress import Progress
from mudforce.errors import InputError, positive_int, shown
from mudforce.estimation.calibration.dataset import Dataset, Trial
from mudforce.estimation.calibration.fit import ConditionFit, FitOptions, fit_condition
from mudforce.model.baselines import BASELINE_NAMES
from mudforce.model.foot import Foot
from mudforce.reproduce.experiments import ReproduceConfig

__all__ = ["GAIN_UNCERTAINTY", "THREADED_RUNTIMES", "VELOCITY_FREE", "Job", "count_fits", "executor", "run_fits",
           "sort_fits", "start_method", "terminate"]

#: A fit job: (kind "table" | "velocity" | "baseline", model, water content [-], speed [m/s]; 0 for all speeds).
Job = tuple[str, str, float, float]

#: Parameters fitted per speed (Fig. 10); the others are held at the water content's fit.
VELOCITY_FREE: tuple[str, ...] = ("alpha", "beta", "sigma_y")


@dataclass(frozen=True, eq=False)
class _Work:
    job: Job
    trials: tuple[Trial, ...]
    seed: int
    options: FitOptions
    fixed: Mapping[str, float] | None = None
    start: Mapping[str, float] | None = None


#: The force sensor's gain uncertainty of the report's fits: none. The experiments are synthetic
#: (:mod:`mudforce.reproduce.experiments`: force noise, depth noise and a bias, and an exact gain), as a lab's
#: calibrated load cell is; ``mudforce fit``'s default of 5 % is for a robot's force estimate.
GAIN_UNCERTAINTY = 0.0


def _fit_job(work: _Work, foot: Foot) -> ConditionFit:
    if work.fixed is None:
        return fit_condition(work.trials, foot, model=work.job[1], seed=work.seed, options=work.options,
                             force_gain_uncertainty=GAIN_UNCERTAINTY)
    return fit_condition(work.trials, foot, model=work.job[1], free=VELOCITY_FREE, fixed=work.fixed,
                         start=work.start, seed=work.seed, options=work.options,
                         force_gain_uncertainty=GAIN_UNCERTAINTY)


def _first_jobs(config: ReproduceConfig, dataset: Dataset) -> list[_Work]:
    """The paper's model per water content (all speeds), then the baselines, longest first."""
    out: list[_Work] = []
    conditions = dataset.conditions()
    for i, (w, trials) in enumerate(conditions.items()):
        out.append(_Work(("table", "chen2024", w, 0.0), trials, config.seed + 104729 * i, config.fit_options))
    for name in BASELINE_NAMES:
        for i, (w, trials) in enumerate(conditions.items()):
            out.append(_Work(("baseline", name, w, 0.0), trials, config.seed + 104729 * i, config.fit_options))
    return out


def _velocity_jobs(config: ReproduceConfig, dataset: Dataset, w: float, table_fit: ConditionFit) -> list[_Work]:
    """Each speed of water content ``w`` on its own, from (and around) the water content's fit."""
    conditions = dataset.conditions()
    i = list(conditions).index(w)
    fixed = {n: v for n, v in table_fit.parameters.items() if n not in VELOCITY_FREE}
    start = {**fixed, **{n: table_fit.parameters[n] for n in VELOCITY_FREE}}
    out = []
    for j, v in enumerate(config.velocities):
        group = tuple(t for t in conditions[w] if t.velocity == v)
        out.append(_Work(("velocity", "chen2024", w, v), group, config.seed + 15485863 * (10 * i + j + 1),
                         config.velocity_fit_options, fixed, start))
    return out


def count_fits(config: ReproduceConfig, dataset: Dataset) -> int:
    n_w = len(dataset.conditions())
    return n_w * (1 + len(BASELINE_NAMES) + len(config.velocities))


def _note(job: Job) -> str:
    kind, model, w, v = job
    return f"{model} W={w:.0%}" + (f" {v * 1e3:g}mm/s" if kind == "velocity" else "")


def run_fits(config: ReproduceConfig, dataset: Dataset, pool: Any, progress: Progress) -> dict[Job, ConditionFit]:
    """Every fit; in ``pool`` (an executor) if given, else here. Per-speed fits follow their water content's."""
    results: dict[Job, ConditionFit] = {}
    foot = dataset.foot
    if pool is None:
        queue = _first_jobs(config, dataset)
        while queue:
            work = queue.pop(0)
            results[work.job] = fit = _fit_job(work, foot)
            if work.job[0] == "table":
                queue = _velocity_jobs(config, dataset, work.job[2], fit) + queue
            progress.update(1, _note(work.job))
        return results
    from concurrent.futures import FIRST_COMPLETED, wait

    pending = {pool.submit(_fit_job, work, foot): work for work in _first_jobs(config, dataset)}
    while pending:
        done, _ = wait(pending, return_when=FIRST_COMPLETED)
        for future in done:
            work = pending.pop(future)
            results[work.job] = fit = future.result()
            if work.job[0] == "table":
                for extra in _velocity_jobs(config, dataset, work.job[2], fit):
                    pending[pool.submit(_fit_job, extra, foot)] = extra
            progress.update(1, _note(work.job))
    return results


def sort_fits(fits: Mapping[Job, ConditionFit]) -> tuple[
        dict[float, ConditionFit], dict[tuple[float, float], ConditionFit], dict[str, dict[float, ConditionFit]]]:
    """The fits by kind, each in ascending order of water content (then speed)."""
    table = dict(sorted((job[2], f) for job, f in fits.items() if job[0] == "table"))
    by_speed = dict(sorted(((job[2], job[3]), f) for job, f in fits.items() if job[0] == "velocity"))
    baselines = {name: dict(sorted((job[2], f) for job, f in fits.items()
                                   if job[0] == "baseline" and job[1] == name)) for name in BASELINE_NAMES}
    return table, by_speed, baselines


# ---------------------------------------------------------------------------- worker processes (plumbing)
#: prctl(2) option: the signal the kernel sends a process when the thread that made it ends.
_PR_SET_PDEATHSIG = 1
#: How often a worker's watchdog looks for its parent [s].
WATCHDOG_PERIOD = 0.5


def _ask_kernel_to_kill_on_parent_death() -> bool:
    """Linux only: SIGKILL this process when its parent ends. False where that is not available."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return int(libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)) == 0
    except (OSError, AttributeError):  # pragma: no cover - no libc prctl
        return False


def _watchdog(parent: int, period: float) -> None:
    """Exit this process as soon as ``parent`` is no longer its parent (it died; we were re-parented)."""
    while True:
        if os.getppid() != parent:
            os._exit(1)
        time.sleep(period)


def _worker_init(parent: int) -> None:
    """Initializer of every worker: die with ``parent`` (kernel request, plus a watchdog thread)."""
    # workers leave SIGTERM and SIGINT to their defaults: the parent's handlers are not theirs
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _ask_kernel_to_kill_on_parent_death()
    if os.getppid() != parent:  # the parent died before the request took effect
        os._exit(1)
    threading.Thread(target=_watchdog, args=(parent, WATCHDOG_PERIOD), name="mudforce-watchdog",
                     daemon=True).start()


#: Libraries that run threads of their own once imported: a process that has one loaded is not forked (a fork
#: copies a lock one of those threads may hold, and the child can hang on it; JAX warns of exactly this).
THREADED_RUNTIMES = ("jax", "jaxlib", "torch")


def start_method() -> str | None:
    """How the workers start: ``"fork"`` (instant, nothing to import again) where the platform has it and no
    threaded runtime (:data:`THREADED_RUNTIMES`) is loaded in this process, else ``"spawn"`` where the
    platform has it (a fresh interpreter per worker, a second or two to import), else the default (None)."""
    import multiprocessing

    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and not any(name in sys.modules for name in THREADED_RUNTIMES):
        return "fork"
    return "spawn" if "spawn" in methods else None


#: The most worker processes :func:`mudforce.reproduce.reproduce` starts (``mudforce reproduce --jobs``'s bound too):
#: with ``fork`` a pool starts all its workers at its first job, so that jobs=10**6 asked for a million processes.
MAX_JOBS = 64


def job_count(jobs: Any) -> int:
    """``jobs`` as an int in [1, :data:`MAX_JOBS`], else a one-line InputError."""
    if positive_int(jobs, "jobs") > MAX_JOBS:
        raise InputError(f"jobs must be at most {MAX_JOBS} (worker processes), got {shown(jobs)}")
    return int(jobs)


def executor(jobs: int) -> Any:
    """A process pool of ``jobs`` workers (:func:`start_method`), or None for ``jobs == 1``.

    Its workers die with this process (see the module's docstring): each is a child of this process, with
    either start method.
    """
    if jobs <= 1:
        return None
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    context = multiprocessing.get_context(start_method())
    return ProcessPoolExecutor(max_workers=jobs, mp_context=context, initializer=_worker_init,
                               initargs=(os.getpid(),))


def terminate(pool: Any) -> None:
    """Stop ``pool`` now: cancel what has not started, kill the workers, reap them.

    The pool's parts are taken before ``shutdown``, which drops its references to them (it set
    ``_processes`` to None, so that the workers were never killed: they ran their fits to the end, and the
    command took 14-22 s to exit after SIGTERM).
    """
    # ProcessPoolExecutor has no public terminate(); its workers are in _processes, its queue in _call_queue
    processes = list((getattr(pool, "_processes", None) or {}).values())
    call_queue = getattr(pool, "_call_queue", None)
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(timeout=5.0)
            if process.is_alive():  # pragma: no cover - ignored SIGTERM
                process.kill()
                process.join(timeout=5.0)
    # the feeder thread may be blocked writing jobs into a pipe only the dead workers read: close its read
    # end here (the write then fails and the feeder ends, as the pool does itself when a worker dies), then
    # let the manager thread see the dead workers and finish (Python's exit joins it)
    with contextlib.suppress(Exception):
        call_queue._reader.close()  # type: ignore[union-attr]
    if manager is not None:
        with contextlib.suppress(Exception):
            manager.join(timeout=5.0)
