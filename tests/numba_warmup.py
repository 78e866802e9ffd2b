"""Compile mudforce's numba functions once, into numba's on-disk cache, before the test workers start.

A clean clone has no cache, and every pytest-xdist worker (and every
command-line test's subprocess started before a cache file exists) would
otherwise compile the same kernels again: about 100 s of CPU for the
paths below, paid once per process. ``tests/conftest.py`` runs this file's
two halves in two processes at once, in the controller, when the run is
distributed (``-n 2`` or more); a warm cache makes it a few seconds of loading.

Nothing here is asserted: a step that fails only prints a line (the tests
that cover it will fail on their own, with a proper report). Run it by hand
with ``python tests/numba_warmup.py a`` (or ``b``).
"""

from __future__ import annotations

import contextlib
import io
import sys
import tempfile
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any


def _cli(*argv: str) -> None:
    from mudforce.cli import main

    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        main(list(argv))


def _one_d(tmp: Path) -> list[tuple[str, Callable[[], None]]]:
    import numpy as np

    import mudforce as mf

    params = mf.MudParameters.from_water_content(0.25)
    time_, depth = mf.Protocol.paper(depth=0.02, velocity=0.01).sample()

    def steppers() -> None:
        res = mf.simulate(time_, depth, params)
        mf.simulate(time_, depth + 1e-4 * np.sin(np.arange(depth.size)), params)  # noisy: the filtered rule
        res.to_csv(tmp / "run.csv")
        contact = mf.MudContact(params)
        contact.step(0.0, 0.0)
        contact.step(1e-3, 0.01)

    def trackers() -> None:
        tracker = mf.MudTracker()
        tracker.update(0.0, 0.0, 0.0)
        tracker.update(1e-3, 1.0, 0.01)
        many = mf.MudTrackers(2)
        many.update(np.zeros(2), np.zeros(2), 0.0)
        many.update(np.full(2, 1e-3), np.ones(2), 0.01)

    def engines() -> None:  # the MuJoCo adapter's drop is in the 3-D half: the two halves then take about as long
        _cli("drop", "--engine", "builtin", "--mass", "5kg", "--water-content", "25%", "--duration", "0.2s",
             "--out", str(tmp / "b.csv"))
        from mudforce.engines.dynamics import naive_drop

        naive_drop(5.0, params, duration=0.05)

    return [("1-D steppers", steppers), ("trackers", trackers), ("1-D engines", engines),
            *_commands(tmp), ("1-D feet", lambda: _feet(params))]


def _feet(params: Any) -> None:
    """Four 1-D feet stepped twice on one thread and on two, last in the 1-D half: the 3-D half's numpy reference
    step (``law3d``) compiles the same serial loop (``run_feet``, which a threaded ``MudContacts`` also compiles
    first) about halfway into the 1-D half, and a process finds a cache entry written while it ran, so the loop
    is compiled once, not in both halves at once (2-6 s of CPU, measured on a clean clone)."""
    import numpy as np

    import mudforce as mf

    for threads in (1, 2):
        feet = mf.MudContacts(params, n=4, threads=threads)
        feet.step(np.full(4, 0.0), 0.0)
        feet.step(np.full(4, 0.01), 1e-3)


def _commands(tmp: Path) -> list[tuple[str, Callable[[], None]]]:
    """The estimation commands and the baselines: last in the 1-D half, which has put the stepper and the
    tracker they call in the cache by then (the two halves then take about as long)."""

    def commands() -> None:
        _cli("synth", "--out", str(tmp / "d"), "--water-content", "25%", "--velocities", "10mm/s",
             "--repeats", "1", "--seed", "1", "--quiet")
        _cli("synth", "--motion", "gait", "--out", str(tmp / "g"), "--water-content", "22%", "--repeats", "1",
             "--seed", "1", "--duration", "4s", "--quiet")
        for trial in sorted((tmp / "g").glob("*.csv"))[:1]:
            _cli("identify", str(trial), "--json")
            _cli("track", str(trial), "--out", str(tmp / "track.csv"))
        _cli("fit", str(tmp / "d"), "--out", str(tmp / "fit.json"), "--quiet")

    def baselines() -> None:
        import mudforce as mf
        from mudforce.model import baselines

        time_, depth = mf.Protocol.paper(depth=0.02, velocity=0.01).sample()
        baselines.maxwell_only_force(time_, depth, 1e6, 1e4, 1e6, 1e4)

    return [("commands", commands), ("baselines", baselines)]


def _feet3d(threads: int) -> None:
    """Two 3-D feet stepped twice on ``threads`` threads (the threaded loop is a compile of its own)."""
    import numpy as np

    import mudforce as mf
    from mudforce.model import shapes

    upright = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    feet = mf.MudContacts3D(mf.MudParameters.from_water_content(0.25), shapes.sphere(0.04), 2, threads=threads)
    feet.step(np.zeros((2, 3)), upright, 0.0)
    feet.step(np.full((2, 3), -1e-3), upright, 0.01)


def _kernel_step() -> None:
    """The compiled single step, called directly by the kernel's tests (last in the 3-D half: the halves then
    take about as long)."""
    import mudforce as mf
    from mudforce import _kernel as K
    from mudforce.model.velocity import VelocityFilter

    params = mf.MudParameters.from_water_content(0.25)
    for window in (1, 4):
        row = K.params_row(params, mf.Foot.paper(), VelocityFilter(window, 0.0))[None, :]
        states, out = K.new_states(1), K.new_out(1)
        K.step(states, K.new_ring(1, window), 0, row, 0.01, 0.01, out, 0)


def _three_d_and_engines(tmp: Path) -> list[tuple[str, Callable[[], None]]]:
    import mudforce as mf
    from mudforce.model import shapes

    params = mf.MudParameters.from_water_content(0.25)
    upright = [1.0, 0.0, 0.0, 0.0]

    def law3d() -> None:
        toe = mf.MudContact3D(params, shapes.sphere(0.04))
        toe.step([0.0, 0.0, 0.01], upright, 0.0)
        toe.step([0.0, 0.0, -0.001], upright, 0.01)
        toe._step_numpy([0.0, 0.0, -0.002], upright, 0.01)  # the numpy reference step's compiled element forces
        _feet3d(1)

    def threads3d() -> None:  # (right after the step it shares, in this half: the halves then take about as long)
        _feet3d(2)

    def engine() -> None:
        _cli("drop", "--engine", "mujoco", "--shape", "sphere:40mm", "--mass", "2kg", "--water-content", "25%",
             "--duration", "0.2s", "--out", str(tmp / "s.csv"))

    def mujoco_1d() -> None:  # the 1-D adapter, here (after the 3-D one) so that the two halves take about as long
        _cli("drop", "--engine", "mujoco", "--mass", "5kg", "--water-content", "25%", "--duration", "0.2s",
             "--out", str(tmp / "m.csv"))

    return [("3-D law", law3d), ("3-D feet on threads", threads3d), ("3-D MuJoCo adapter", engine),
            ("1-D MuJoCo adapter", mujoco_1d), ("kernel", _kernel_step)]


PARTS = {"a": _one_d, "b": _three_d_and_engines}


def main(part: str) -> int:
    from numba_typing_memo import install  # tests/ is this script's folder

    install()
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mudforce-warmup-") as folder:
        for name, step in PARTS[part](Path(folder)):
            began = time.perf_counter()
            try:
                step()
            except Exception:  # a warm-up never fails the run; the tests report it properly
                print(f"numba warm-up {part}: {name} failed:\n{traceback.format_exc()}", file=sys.stderr)
            print(f"numba warm-up {part}: {name} {time.perf_counter() - began:.1f} s", file=sys.stderr)
    print(f"numba warm-up {part}: {time.perf_counter() - start:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "a"))
