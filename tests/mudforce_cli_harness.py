"""The one subprocess harness for every command-line test (any folder): ``from mudforce_cli_harness import run_cli``.

``run_cli`` runs ``python -m mudforce`` in a folder (the real thing: exit
status, stderr, no traceback); ``start_cli`` starts one without waiting (to
interrupt it). ``run_batch`` runs many command lines in ONE subprocess
(importing numba costs ~0.5 s a process): each case calls
:func:`mudforce.cli.main` in its own folder, with stdout and stderr captured
and any exception that escapes ``main`` recorded as a traceback, so a batch
checks what a process would show at a fraction of the cost.

Every subprocess gets the package under test first on ``PYTHONPATH`` as an
absolute path (tests run from temporary folders, where a relative ``src``
would not resolve and another installed copy would run instead). The
top-level ``tests/conftest.py`` puts ``tests/`` on ``sys.path`` so this module
imports from any test folder (there are no ``__init__.py`` files).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from tree_snapshot import snapshot  # noqa: F401  (re-exported: the CLI tests take it from the harness)

PYTHON_M = [sys.executable, "-m", "mudforce"]

_DRIVER = r"""
import contextlib, io, json, os, sys, traceback
from mudforce.cli import main
cases = json.load(sys.stdin)
results = []
for case in cases:
    os.chdir(case["cwd"])
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(case["argv"])
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else 1
        except BaseException:
            rc = -1
            err.write(traceback.format_exc())
    results.append({"rc": rc, "stdout": out.getvalue(), "stderr": err.getvalue()})
json.dump(results, sys.stdout)
"""


@dataclass
class Run:
    """What one command line did."""

    returncode: int
    stdout: str
    stderr: str


def cli_env(path_first: Sequence[Path | str] = (), extra: Mapping[str, str] | None = None) -> dict[str, str]:
    """The environment for a run: the package under test first on the path (after ``path_first``, for a
    test that shadows a module), ``MPLBACKEND`` unset, and ``extra`` variables set."""
    import mudforce

    env = dict(os.environ)
    env.pop("MPLBACKEND", None)
    here = str(Path(mudforce.__file__).resolve().parents[1])
    rest = [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    env["PYTHONPATH"] = os.pathsep.join([*(str(Path(p).resolve()) for p in path_first), here, *rest])
    env.update(extra or {})
    return env



def run_cli(args: Sequence[str], cwd: Path | None = None, timeout: float = 180, *,
            command: Sequence[str] = PYTHON_M, path_first: Sequence[Path | str] = (),
            env: Mapping[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``python -m mudforce ARGS`` (or ``command ARGS``) in ``cwd`` with no stdin; returns the finished
    process. ``env`` adds variables; ``path_first`` goes before the package on ``PYTHONPATH``."""
    return subprocess.run([*command, *args], cwd=cwd, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                          timeout=timeout, env=cli_env(path_first, env))


def start_cli(args: Sequence[str], cwd: Path | None = None, *, path_first: Sequence[Path | str] = (),
              env: Mapping[str, str] | None = None) -> subprocess.Popen[str]:
    """Start ``python -m mudforce ARGS`` in ``cwd`` without waiting, stdout and stderr piped, no stdin, and
    SIGINT at its default (a test run in the background of a shell would otherwise pass it on ignored).
    ``path_first`` goes before the package on ``PYTHONPATH`` (a ``sitecustomize`` that stops at a chosen point)."""
    return subprocess.Popen([*PYTHON_M, *args], cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=cli_env(path_first, env),
                            preexec_fn=_default_sigint if os.name == "posix" else None)


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def run_batch(cases: Sequence[tuple[Sequence[str], Path]], timeout: float = 300) -> list[Run]:
    """Run each ``(argv, cwd)`` through ``mudforce.cli.main`` in one subprocess; one :class:`Run` per case."""
    payload = json.dumps([{"argv": list(argv), "cwd": str(cwd)} for argv, cwd in cases])
    proc = subprocess.run([sys.executable, "-c", _DRIVER], input=payload, capture_output=True, text=True,
                          timeout=timeout, env=cli_env())
    assert proc.returncode == 0, proc.stderr[-3000:]
    return [Run(r["rc"], r["stdout"], r["stderr"]) for r in json.loads(proc.stdout)]


def assert_refused(run: Run, *words: str) -> None:
    """Exit 2, one short line on stderr naming the problem, nothing on stdout, no traceback."""
    err = run.stderr
    assert run.returncode == 2, (run.returncode, err)
    assert "Traceback" not in err, err
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert len(err) < 400, err
    assert err.startswith("mudforce") and ": error: " in err, err
    for word in words:
        assert word in err, (word, err)
    assert run.stdout == ""
