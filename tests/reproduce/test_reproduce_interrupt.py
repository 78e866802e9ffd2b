"""``mudforce reproduce`` stopped partway: no worker survives it, and the folder holds the old report or the new.

Linux only (processes are found through /proc). Each test runs one quick
report in a subprocess (of two water contents rather than five, one for the
figures: a ``sitecustomize`` put before the package on the path) and kills it as soon
as it reaches the stage under test, so they cost a few seconds each.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

from mudforce_cli_harness import start_cli

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")

OLD = {"report.html": "old report\n", "summary.json": "{}\n", "fig02_profile.png": "old png"}


def _stat(pid: int) -> list[str] | None:
    """Fields of /proc/PID/stat after the command name (state first), or None if gone."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text[text.rindex(")") + 2:].split()


def _children(pid: int) -> dict[int, str]:
    """Child pid -> its start time (to tell it from a later process given the same pid)."""
    out = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            fields = _stat(int(entry.name))
            if fields is not None and int(fields[1]) == pid:
                out[int(entry.name)] = fields[19]
    return out


def _alive(pid: int, start: str) -> bool:
    """Whether process ``pid`` (started at ``start``) has a thread that has not finished exiting.

    Every thread counts, not only the first: a killed process's first thread
    can show ``Z`` while the others still hold its open files (and so the
    staged folder's lock) for a moment longer.
    """
    fields = _stat(pid)
    if fields is None or fields[19] != start:
        return False
    try:
        tasks = [int(t.name) for t in Path(f"/proc/{pid}/task").iterdir()]
    except OSError:
        return False
    states = [Path(f"/proc/{pid}/task/{t}/stat") for t in tasks]
    return any(_thread_running(s) for s in states)


def _thread_running(stat: Path) -> bool:
    try:
        text = stat.read_text()
    except OSError:
        return False
    return text[text.rindex(")") + 2:].split()[0] not in ("Z", "X")


def _wait_for(condition, timeout: float) -> bool:  # type: ignore[no-untyped-def]
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.05)
    return False


#: Makes ``--quick`` smaller still: two water contents instead of five (the fits, under SIGTERM); with
#: ``MUDFORCE_TEST_FIGURES=1`` only 0.25, so that the figures (under SIGKILL) start after half as many
#: fits. Put before the package on the path by a ``sitecustomize``.
HOOK = '''
import dataclasses
import os

from mudforce.reproduce import experiments

_quick = experiments.ReproduceConfig.quick_config.__func__


def _smaller(cls, seed=0):
    if os.environ.get("MUDFORCE_TEST_FIGURES"):
        return dataclasses.replace(_quick(cls, seed), water_contents=(0.25,))
    return dataclasses.replace(_quick(cls, seed), water_contents=(0.2, 0.25))


experiments.ReproduceConfig.quick_config = classmethod(_smaller)
'''


@pytest.fixture(scope="module")
def hook(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("hook")
    (folder / "sitecustomize.py").write_text(HOOK)
    return folder


def _start(out: Path, hook: Path, *, figures: bool = False) -> subprocess.Popen[str]:
    out.mkdir()
    for name, text in OLD.items():
        (out / name).write_text(text)
    return start_cli(["reproduce", "--quick", "--jobs", "2", "--quiet", "--out", str(out)], path_first=[hook],
                     env={"MUDFORCE_TEST_FIGURES": "1"} if figures else None)


def _old_or_complete_new(out: Path) -> str:
    names = {p.name for p in out.iterdir()}
    if names == set(OLD) and all((out / n).read_text() == t for n, t in OLD.items()):
        return "old"
    summary = json.loads((out / "summary.json").read_text())
    assert names == {"report.html", "summary.json"} | {f["file"] for f in summary["figures"]}
    assert (out / "report.html").read_text().endswith("</html>\n")
    return "new"


def _staged(out: Path) -> list[Path]:
    prefix = f".{out.name}.mudforce-reproduce-new-"  # compared, not a glob pattern: names may hold [ or *
    return sorted(p for p in out.parent.iterdir() if p.name.startswith(prefix))


def _no_worker_survives(workers: dict[int, str]) -> None:
    assert workers, "no worker process was seen"
    assert _wait_for(lambda: not any(_alive(p, s) for p, s in workers.items()), 10.0), \
        f"workers still running: {[p for p, s in workers.items() if _alive(p, s)]}"


def test_sigterm_during_the_fits(tmp_path: Path, hook: Path) -> None:
    out = tmp_path / "out"
    proc = _start(out, hook)
    try:
        assert _wait_for(lambda: len(_children(proc.pid)) >= 2 or proc.poll() is not None, 120.0)
        workers = _children(proc.pid)
        proc.send_signal(signal.SIGTERM)
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 128 + signal.SIGTERM, stderr
    assert "Traceback" not in stderr
    _no_worker_survives(workers)
    assert _old_or_complete_new(out) == "old"
    assert _staged(out) == []  # its unfinished folder removed


def test_sigkill_during_the_figures(tmp_path: Path, hook: Path) -> None:
    out = tmp_path / "out[1]"  # a name a glob pattern would not match (its staged folder was never removed)
    proc = _start(out, hook, figures=True)
    try:
        # the figures are being written once the staged folder holds a PNG
        assert _wait_for(lambda: any(any(p.glob("*.png")) for p in _staged(out)) or proc.poll() is not None, 240.0)
        workers = _children(proc.pid)
        proc.kill()
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    _no_worker_survives(workers)
    assert _old_or_complete_new(out) == "old"
    # the next run's clean-up removes the killed run's folder (nobody holds its lock any more)
    from mudforce.reproduce.output import clean_stale

    left = _staged(out)
    assert len(left) == 1
    # the kernel drops the lock as the last of the killed processes' threads ends; allow it a moment
    removed: list[Path] = []
    assert _wait_for(lambda: bool(removed.extend(clean_stale(out)) or removed), 10.0), "the staged folder stays locked"
    assert removed == left and _staged(out) == []
    assert _old_or_complete_new(out) == "old"
    assert os.listdir(tmp_path) == ["out[1]"]


def test_terminate_kills_the_workers_it_does_not_wait_for_their_jobs() -> None:
    """``jobs.terminate`` once let the workers run their fits to the end (shutdown had dropped its list of them)."""
    import time as _time

    from mudforce.reproduce.jobs import executor, terminate

    pool = executor(2)
    futures = [pool.submit(_time.sleep, 60.0) for _ in range(4)]
    assert _wait_for(lambda: len(pool._processes or {}) == 2 and any(f.running() for f in futures), 30.0)
    workers = list(pool._processes.values())
    terminate(pool)
    assert [w.exitcode for w in workers] == [-signal.SIGTERM, -signal.SIGTERM]  # killed, not finished


def test_a_process_with_jax_loaded_starts_its_workers_fresh(monkeypatch: pytest.MonkeyPatch) -> None:
    """Forked workers of a process running JAX's threads can hang on a lock copied mid-use (JAX warns of it):
    such a process spawns them instead, and they still run its jobs and die with it (each is its child)."""
    import sys
    import types

    from mudforce.reproduce.jobs import executor, start_method, terminate

    monkeypatch.delitem(sys.modules, "jax", raising=False)
    monkeypatch.delitem(sys.modules, "jaxlib", raising=False)
    monkeypatch.delitem(sys.modules, "torch", raising=False)
    assert start_method() == "fork"
    monkeypatch.setitem(sys.modules, "jax", types.ModuleType("jax"))
    assert start_method() == "spawn"
    pool = executor(2)
    try:
        pids = {pool.submit(os.getpid).result(timeout=60) for _ in range(4)}
        workers = _children(os.getpid())
        assert pids and os.getpid() not in pids and pids <= set(workers)  # this process's children
    finally:
        terminate(pool)
    _no_worker_survives({p: workers[p] for p in pids})
