"""``mudforce fit --out FIT.json --report DIR`` stopped partway: the old pair or the new one (issue 20, items 2, 8).

The fit and its report are staged beside their targets and swapped in
together; Ctrl-C ends the command with one line and status 130, even when
Python would lose the interrupt in a weak-reference callback (as matplotlib
frees its caches while the report is drawn); what a killed run leaves is
removed by the next run of the same command.

Each run is stopped at a chosen point, not after a guessed delay: once its
staged folders exist (SIGINT, SIGKILL), or inside the report, after its
second figure, where a ``sitecustomize`` put before the package on the
path (``MUDFORCE_TEST_STOP=lose``) loses an interrupt in a callback. Linux only (the
staged folders' ``flock`` and the signals). The dataset is one trial, so a
whole run costs a few seconds.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from mudforce.estimation.calibration.synth import synthesize
from mudforce_cli_harness import run_cli, snapshot, start_cli

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux (flock, signals)")

OLD_FIT = b"old fit\n"
OLD_REPORT = {"report.md": b"old report\n", "W25_force_time.png": b"old png"}

#: Stops ``mudforce fit --report`` inside the report: after its second figure, ``lose`` sends itself SIGINT
#: inside a weak-reference callback, where Python cannot raise it, and notes in ``lost.txt`` that it got lost
#: there; ``wait`` sleeps there instead (to be signalled from outside, when debugging by hand).
HOOK = '''
import os
STOP = os.environ.get("MUDFORCE_TEST_STOP")
if STOP:
    import signal, time, weakref
    import mudforce.io.plotting as plotting

    real, calls = plotting.save_png, []

    class Thing:
        pass

    def callback(_):
        try:
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(10**6):  # Python acts on the signal here at the latest, inside the callback
                pass
        except KeyboardInterrupt:
            with open("lost.txt", "w") as f:
                f.write("raised inside the callback\\n")
            raise

    def save_png(fig, path, **kw):
        real(fig, path, **kw)
        calls.append(path)
        if len(calls) == 2:
            if STOP == "wait":
                time.sleep(120)
            else:
                thing = Thing()
                ref = weakref.ref(thing, callback)
                del thing  # the callback runs now; the interrupt it raises is lost ("Exception ignored")

    plotting.save_png = save_png
'''


def _wait_for(condition: Callable[[], bool], timeout: float) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.02)
    return False


def _setup(root: Path, fit: str = "fit.json", report: str = "rep") -> tuple[Path, Path]:
    """A one-trial dataset, an old fit and an old report, and the hook, in ``root``."""
    synthesize(root / "ds", velocities=(0.02,), repeats=1, seed=1)
    (root / fit).write_bytes(OLD_FIT)
    (root / report).mkdir()
    for name, data in OLD_REPORT.items():
        (root / report / name).write_bytes(data)
    (root / "hook").mkdir()
    (root / "hook" / "sitecustomize.py").write_text(HOOK)
    return root / fit, root / report


def _start(root: Path, stop: str | None, fit: str = "fit.json", report: str = "rep") -> subprocess.Popen[str]:
    return start_cli(["fit", "ds", "--out", fit, "--report", report, "--quiet"], root, path_first=[root / "hook"],
                     env={"MUDFORCE_TEST_STOP": stop} if stop else None)


def _staged(target: Path) -> list[Path]:
    """The hidden siblings ``.NAME.mudforce-fit-*`` of a target (exact names: ``[`` in NAME is no pattern)."""
    prefix = f".{target.name}.mudforce-fit-"
    return sorted(p for p in target.parent.iterdir() if p.name.startswith(prefix))


def _old_pair(fit: Path, report: Path) -> bool:
    return fit.read_bytes() == OLD_FIT and snapshot(report) == OLD_REPORT


def _new_pair(fit: Path, report: Path) -> None:
    """A complete new fit and report: fit.json parses, report.md links exactly the PNGs the folder holds."""
    assert json.loads(fit.read_text())["model"] == "chen2024"
    text = (report / "report.md").read_text()
    pngs = {p.name for p in report.iterdir()} - {"report.md"}
    assert pngs and all(name.endswith(".png") and f"]({name})" in text for name in pngs)
    assert "W25_force_time.png" in pngs and (report / "W25_force_time.png").read_bytes() != b"old png"


def _interrupted(proc: subprocess.Popen[str]) -> None:
    """Status 130 and the one line of an interrupt: no traceback, no ``Exception ignored``."""
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert err == "mudforce: interrupted\n" and out == ""


def test_sigint_during_the_fit_leaves_the_old_pair(tmp_path: Path) -> None:
    fit, report = _setup(tmp_path)
    proc = _start(tmp_path, None)
    try:
        # staged beside both targets before the fit starts (the report's folder, the fit's folder)
        assert _wait_for(lambda: (len(_staged(fit)) == 1 and len(_staged(report)) == 1) or proc.poll() is not None,
                         60.0)
        proc.send_signal(signal.SIGINT)
        _interrupted(proc)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert _old_pair(fit, report)
    assert _staged(fit) == [] and _staged(report) == []


def test_an_interrupt_lost_in_a_callback_still_stops_the_report(tmp_path: Path) -> None:
    """Python drops a KeyboardInterrupt raised in a weakref callback; the command stops anyway, with one line."""
    fit, report = _setup(tmp_path)
    proc = _start(tmp_path, "lose")
    try:
        _interrupted(proc)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert (tmp_path / "lost.txt").read_text() == "raised inside the callback\n"  # it was lost there
    assert _old_pair(fit, report)  # the report was half-drawn and the fit written, both aside
    assert _staged(fit) == [] and _staged(report) == []


def test_sigkill_then_the_next_run_cleans_up(tmp_path: Path) -> None:
    """Names with glob characters, whose staged folders a pattern would miss; the next run removes them."""
    fit, report = _setup(tmp_path, "fit[1].json", "rep*[1]")
    proc = _start(tmp_path, None, fit.name, report.name)
    try:
        assert _wait_for(lambda: (len(_staged(fit)) == 1 and len(_staged(report)) == 1) or proc.poll() is not None,
                         60.0)
        proc.kill()
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert _old_pair(fit, report)
    assert len(_staged(fit)) == 1 and len(_staged(report)) == 1  # left behind, no longer locked
    proc = run_cli(["fit", "ds", "--out", fit.name, "--report", report.name, "--quiet"], tmp_path, timeout=120)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    _new_pair(fit, report)
    assert _staged(fit) == [] and _staged(report) == []
    assert sorted(os.listdir(tmp_path)) == sorted(["ds", "hook", fit.name, report.name])


#: ``mudforce params`` interrupted inside code run from a string (as the libraries' generated functions are): the
#: KeyboardInterrupt is caught by the command line like any other.
STRING_HOOK = '''
import mudforce.cli.params as params

def run(args):
    exec("raise KeyboardInterrupt", {})

params.run = run
'''


def test_an_interrupt_inside_code_run_from_a_string_still_exits_130(tmp_path: Path) -> None:
    """CPython remembers a KeyboardInterrupt that ended a string's evaluation even once it is caught, and under
    ``python -m`` ends the process by SIGINT (-2) instead of the status returned; ``mudforce/__main__.py`` clears
    that note after the command returns. Seen as a -2 once in about 20 interrupted fits before it did."""
    (tmp_path / "hook").mkdir()
    (tmp_path / "hook" / "sitecustomize.py").write_text(STRING_HOOK)
    proc = start_cli(["params", "--water-content", "25%"], tmp_path, path_first=[tmp_path / "hook"])
    _interrupted(proc)
