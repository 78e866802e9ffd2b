"""The one subprocess harness for every command-line test (any folder): ``from mudforce_cli_harness import run_cli``.

``run_cli`` runs ``python -m mudforce`` in a folder (the real thing: exit
status, stderr, no traceback); ``start_cli`` starts one without waiting (to
interrupt it). ``run_batch`` runs many command lines in ONE subprocess: each
case calls :func:`mudforce.cli.main` in its own folder, with stdout and
stderr captured and any exception that escapes ``main`` recorded as a
traceback, so a batch checks what a process would show at a fraction of the
cost.

**Warm processes.** A fresh interpreter pays about 1.5 s of CPU before the
command starts (numpy, scipy, numba, and numba's first load of a cached
kernel); the suite runs some 50 of them. So each test process keeps one
*warm parent*: an interpreter started like any other run (the same
``PYTHONPATH``, no stdin) that imports the command line, scipy and matplotlib,
loads one kernel and runs synth, identify and track once on a short walk (in a
folder it then removes, its output discarded), then only forks (it never imports JAX or MuJoCo, whose
threads a fork would not carry). Each ``run_cli`` and ``run_batch`` is a child forked from it:
its own process, with its own folder, environment, stdin (``/dev/null``),
stdout and stderr (files), that runs ``python -m mudforce``'s ``__main__``
(``runpy``, as ``-m`` does) and exits with its status, or by its signal. What a
fork cannot give falls back to a fresh ``python -m mudforce``: another
``command``, a ``path_first`` (a module shadowed at start-up), and a variable
read at start-up (``PYTHON*``, ``NUMBA_*``, thread counts) that differs from the
warm parent's. ``start_cli`` (the interrupt tests) is always fresh, and
``MUDFORCE_TEST_FRESH=1`` makes every run fresh. Linux and macOS only (``fork``);
elsewhere every run is fresh.

Every subprocess gets the package under test first on ``PYTHONPATH`` as an
absolute path (tests run from temporary folders, where a relative ``src``
would not resolve and another installed copy would run instead). The
top-level ``tests/conftest.py`` puts ``tests/`` on ``sys.path`` so this module
imports from any test folder (there are no ``__init__.py`` files).
"""

from __future__ import annotations

import atexit
import json
import locale
import os
import select
import signal
import subprocess
import sys
import tempfile
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from tree_snapshot import snapshot  # noqa: F401  (re-exported: the CLI tests take it from the harness)

PYTHON_M = [sys.executable, "-m", "mudforce"]

_BATCH = r"""
def run_cases(cases):
    import contextlib, io, os, traceback
    from mudforce.cli import main
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
    return results
"""

#: a fresh batch: the cases on stdin, the results on stdout (JSON)
_DRIVER = _BATCH + r"""
import json, sys
json.dump(run_cases(json.load(sys.stdin)), sys.stdout)
"""

#: the warm parent: one request a line on stdin, one reply a line on stdout (JSON); each request is a forked child
_WARM = _BATCH + r"""
import atexit, io, json, locale, os, runpy, sys, time, traceback, warnings

def warm():
    with warnings.catch_warnings():  # leaves no warning marked as shown for the children
        warnings.simplefilter("ignore")
        import mudforce.cli  # noqa: F401
        import mudforce as mf
        import scipy.integrate, scipy.interpolate, scipy.optimize  # noqa: F401  (fit, identify, the drops)
        try:
            import matplotlib.backends.backend_agg, matplotlib.figure  # noqa: F401  (figures, without pyplot)
        except ImportError:
            pass
        t, z = mf.Protocol.paper(depth=0.02, velocity=0.01).sample()
        mf.simulate(t[:64], z[:64], mf.MudParameters.from_water_content(0.25))  # numba's first cached kernel
        # the estimation commands once, on a short walk: their modules and compiled functions then loaded
        import contextlib, io, pathlib, tempfile
        from mudforce.cli import main
        with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()), \
                contextlib.redirect_stderr(io.StringIO()):
            try:
                main(["synth", "--motion", "gait", "--out", tmp + "/g", "--water-content", "22%", "--repeats", "1",
                      "--seed", "1", "--duration", "2s", "--quiet"])
                trial = str(sorted(pathlib.Path(tmp, "g").glob("*.csv"))[0])
                main(["identify", trial, "--json"])
                main(["track", trial, "--out", tmp + "/t.csv", "--quiet"])
            except (Exception, SystemExit):
                pass  # a warm-up only: the tests that run these commands report any failure

def exit_code(exc):
    code = exc.code
    if code is None:
        return 0
    if isinstance(code, int):
        return code % 256
    print(code, file=sys.stderr)
    return 1

def child(req):
    code = 1
    try:
        enc = locale.getpreferredencoding(False)
        null = os.open(os.devnull, os.O_RDONLY)
        os.dup2(null, 0)
        os.close(null)
        for fd, path in ((1, req["stdout"]), (2, req["stderr"])):
            f = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
            os.dup2(f, fd)
            os.close(f)
        sys.stdin = sys.__stdin__ = io.TextIOWrapper(io.BufferedReader(io.FileIO(0, "r", closefd=False)),
                                                     encoding=enc)
        sys.stdout = sys.__stdout__ = io.TextIOWrapper(io.BufferedWriter(io.FileIO(1, "w", closefd=False)),
                                                       encoding=enc)
        sys.stderr = sys.__stderr__ = io.TextIOWrapper(io.BufferedWriter(io.FileIO(2, "w", closefd=False)),
                                                       encoding=enc, errors="backslashreplace",
                                                       line_buffering=True)
        os.environ.clear()
        os.environ.update(req["env"])
        os.chdir(req["cwd"])
        if req["cases"] is None:
            sys.argv = ["mudforce", *req["argv"]]
            if sys.path and sys.path[0] == "":
                sys.path[0] = os.getcwd()  # what -m puts first (-c, which started the parent, puts "")
            runpy.run_module("mudforce", run_name="__main__", alter_sys=True)  # as python -m mudforce
            code = 0
        else:
            json.dump(run_cases(req["cases"]), sys.stdout)
            code = 0
    except SystemExit as exc:
        code = exit_code(exc)
    except BaseException:
        traceback.print_exc()
        code = 1
    finally:
        try:
            atexit._run_exitfuncs()
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code)

def wait(pid, timeout):
    end = time.monotonic() + timeout
    pause = 0.0005
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            return os.waitstatus_to_exitcode(status), False
        if time.monotonic() > end:
            os.kill(pid, 9)
            os.waitpid(pid, 0)
            return -9, True
        time.sleep(pause)
        pause = min(2 * pause, 0.01)

warm()
reply = sys.stdout
reply.write("ready\n")
reply.flush()
for line in sys.stdin:
    req = json.loads(line)
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:
        child(req)
    rc, late = wait(pid, req["timeout"])
    reply.write(json.dumps({"rc": rc, "timed_out": late}) + "\n")
    reply.flush()
"""

#: variables a process reads when it starts (a forked child keeps its parent's): a difference means a fresh run
_AT_START = ("PYTHON", "NUMBA_", "OMP_", "MKL_", "OPENBLAS_", "LD_", "MALLOC_")


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
            env: Mapping[str, str] | None = None, fresh: bool = False) -> subprocess.CompletedProcess[str]:
    """Run ``python -m mudforce ARGS`` (or ``command ARGS``) in ``cwd`` with no stdin; returns the finished
    process. ``env`` adds variables; ``path_first`` goes before the package on ``PYTHONPATH``. A child of the
    warm parent where it can be (see the module's docstring), else (or with ``fresh``) a fresh interpreter."""
    full = cli_env(path_first, env)
    warm = _warm_parent(full) if list(command) == PYTHON_M and not path_first and not fresh else None
    if warm is None:
        return subprocess.run([*command, *args], cwd=cwd, stdin=subprocess.DEVNULL, capture_output=True,
                              text=True, timeout=timeout, env=full)
    rc, out, err = warm.run({"argv": list(args), "cases": None}, cwd, full, timeout, [*command, *args])
    return subprocess.CompletedProcess([*command, *args], rc, out, err)


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
    todo = [{"argv": list(argv), "cwd": str(cwd)} for argv, cwd in cases]
    env = cli_env()
    warm = _warm_parent(env)
    if warm is None:
        proc = subprocess.run([sys.executable, "-c", _DRIVER], input=json.dumps(todo), capture_output=True,
                              text=True, timeout=timeout, env=env)
        rc, out, err = proc.returncode, proc.stdout, proc.stderr
    else:
        rc, out, err = warm.run({"argv": None, "cases": todo}, None, env, timeout, ["run_batch"])
    assert rc == 0, err[-3000:]
    return [Run(r["rc"], r["stdout"], r["stderr"]) for r in json.loads(out)]


class _WarmParent:
    """The warm parent of this test process: started once, then asked for one forked child per run."""

    def __init__(self, env: dict[str, str]) -> None:
        self.pid = os.getpid()
        self.start_env = {k: v for k, v in env.items() if k.startswith(_AT_START)}
        self.log = tempfile.TemporaryFile(mode="w+")
        self.proc = subprocess.Popen([sys.executable, "-c", _WARM], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=self.log, text=True, env=env)
        self._reply(600.0, "start")
        atexit.register(self.close)

    def close(self) -> None:
        """End the warm parent (at this process's exit): no more requests, then wait for it."""
        if self.pid != os.getpid() or self.proc.poll() is not None:
            return
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        try:
            self.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()

    def fits(self, env: Mapping[str, str]) -> bool:
        """Whether a child of this parent starts as a fresh process with ``env`` would."""
        return {k: v for k, v in env.items() if k.startswith(_AT_START)} == self.start_env

    def _reply(self, timeout: float, what: str) -> str:
        assert self.proc.stdout is not None
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        line = self.proc.stdout.readline() if ready else ""
        if not line:
            self.proc.kill()
            self.log.seek(0)
            raise RuntimeError(f"the warm parent of the command-line tests gave no reply ({what}); its stderr:\n"
                               f"{self.log.read()[-3000:]}\n(MUDFORCE_TEST_FRESH=1 runs every command fresh)")
        return line

    def run(self, request: dict[str, object], cwd: Path | None, env: Mapping[str, str], timeout: float,
            cmd: list[str]) -> tuple[int, str, str]:
        """One forked child: its exit status (negative: the signal that ended it), stdout and stderr."""
        assert self.proc.stdin is not None
        with tempfile.TemporaryDirectory(prefix="mudforce-cli-") as folder:
            out, err = Path(folder) / "stdout", Path(folder) / "stderr"
            request = {**request, "cwd": str(Path(cwd) if cwd is not None else Path.cwd()), "env": dict(env),
                       "stdout": str(out), "stderr": str(err), "timeout": timeout}
            self.proc.stdin.write(json.dumps(request) + "\n")
            self.proc.stdin.flush()
            reply = json.loads(self._reply(timeout + 60.0, " ".join(cmd)))
            if reply["timed_out"]:
                raise subprocess.TimeoutExpired(cmd, timeout)
            encoding = locale.getpreferredencoding(False)
            return (reply["rc"], out.read_text(encoding=encoding, errors="replace"),
                    err.read_text(encoding=encoding, errors="replace"))


_WARM_PARENTS: list[_WarmParent] = []
_NO_WARM_PARENT: list[str] = []  # why a warm parent could not start in this process, once it has failed


def _warm_parent(env: Mapping[str, str]) -> _WarmParent | None:
    """This test process's warm parent for a run in ``env``, started if need be; None where a fresh run is needed."""
    if not hasattr(os, "fork") or os.environ.get("MUDFORCE_TEST_FRESH"):
        return None
    if _WARM_PARENTS and _WARM_PARENTS[0].pid == os.getpid() and _WARM_PARENTS[0].proc.poll() is None:
        parent = _WARM_PARENTS[0]  # this process's, alive: its child, unless the run's start-up differs (fresh)
        return parent if parent.fits(env) else None
    if _NO_WARM_PARENT:
        return None
    try:
        parent = _WarmParent(cli_env())
    except RuntimeError as err:  # no warm parent here: every run fresh, said once (pytest lists the warning)
        _NO_WARM_PARENT.append(str(err))
        warnings.warn(f"command-line tests run fresh: {err}", stacklevel=2)
        return None
    _WARM_PARENTS[:] = [parent]
    return parent if parent.fits(env) else None


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
