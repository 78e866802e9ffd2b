"""Test configuration: reproducible Hypothesis runs on CI, a wider search on request."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import matplotlib
import pytest
from hypothesis import settings

matplotlib.use("Agg")

# tests/ on the import path, so that any test folder can `from mudforce_cli_harness import run_cli`
# (the one subprocess harness; there are no __init__.py files, and pytest only inserts each test's own folder)
_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

# CI (and anyone who sets CI=true) runs the same examples every time; a
# developer's run explores new ones (MUDFORCE_EXAMPLES sets how many).
settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


#: Seconds each of the slowest modules takes on one of two cores (measured 2026-11-25 from a clean clone; a module
#: not listed counts 0.02 s a test). Only their order matters: see :func:`pytest_collection_modifyitems`.
SLOW_MODULES: dict[str, float] = {
    "api/test_typing.py": 16,  # mypy, cold on a clean clone (measured 2026-11-29, eighth session)
    "reproduce/test_reproduce.py": 39,
    "steppers/test_properties.py": 15,
    "engines/test_mjx_drop.py": 5,
    "reproduce/test_reproduce_interrupt.py": 19,
    "engines/test_mjx3d.py": 18,
    "cli/test_fit_report_interrupt.py": 18,
    "estimation/test_calibration_fit.py": 16,
    "jax/test_jax_contact3d.py": 15,
    "engines/test_drops3d.py": 15,
    "cli/test_cli.py": 15,
    "api/test_conformance.py": 14,
    "engines/test_quadruped_mjx_env.py": 24,
    "cli/test_drop3d_cli.py": 17,
    "references/test_reference3d.py": 10,
    "jax/test_jax_grad.py": 9,
    "references/test_reference.py": 8,
    "cli/test_cli_bad_values.py": 8,
    "cli/test_cli_outputs_together.py": 5,  # measured 2026-11-29
    "api/test_readme_tour.py": 9,  # measured 2026-11-29 (alone, one core)
    "engines/test_leg_examples.py": 7,  # measured 2026-11-29 (alone, one core)
    "engines/test_mjx_rest.py": 6,
    "api/test_layout.py": 6,
    "estimation/test_identify_misfit.py": 5,
    "engines/test_dynamics.py": 5,
    "jax/test_jax_stepper.py": 4,
    "engines/test_mujoco.py": 4,
    "api/test_deprecated.py": 4,
    "steppers/test_simulation.py": 3,
    "steppers/test_contact3d.py": 3,
    "model/test_equations.py": 3,
    "io/test_readers.py": 3,
    "estimation/test_identify_nuisances.py": 3,
    "estimation/test_calibration.py": 3,
    "cli/test_harness.py": 3,
    "api/test_refused_unchanged.py": 3,
    "model/test_shapes.py": 2,
    "kernel/test_pow.py": 2,
    "kernel/test_kernel_transitions.py": 2,
    "estimation/test_tracker.py": 2,
    "engines/test_adapter3d_fast.py": 2,
    "cli/test_fit_cli.py": 2,
    "cli/test_estimation_nuisances_cli.py": 2,
    "api/test_one_api.py": 2,
}


def _module_cost(path: str, tests: int) -> float:
    key = path.split("tests/", 1)[-1]
    return SLOW_MODULES.get(key, 0.02 * tests)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The slowest modules first, so that the workers end together.

    pytest-xdist's ``--dist loadscope`` hands each worker a module at a time, in the order
    of the collection (:func:`pytest_configure` turns off its own reordering, which puts
    the modules with the most tests first: the report's six tests and the MJX environment's
    one, the longest, then came last, and one worker ran them while the other had finished).
    Longest first is the classic rule for keeping the last one short. The order of the
    tests within a module is kept; a plain run is ordered the same way.
    """
    modules: dict[str, list[pytest.Item]] = {}
    for item in items:
        modules.setdefault(item.nodeid.split("::", 1)[0], []).append(item)
    order = sorted(modules, key=lambda path: -_module_cost(path, len(modules[path])))  # stable: ties keep their order
    items[:] = [item for path in order for item in modules[path]]


def _distributed(config: pytest.Config) -> bool:
    """Whether this is pytest-xdist's controller of two or more workers (not a worker, not a plain run)."""
    if hasattr(config, "workerinput"):
        return False
    workers = getattr(config.option, "numprocesses", None)
    if workers in ("auto", "logical"):
        return (os.cpu_count() or 1) > 1
    return isinstance(workers, int) and workers > 1


def pytest_configure(config: pytest.Config) -> None:
    """Before the workers start, compile the numba kernels once into the on-disk cache (tests/numba_warmup.py).

    Each worker would otherwise compile the same kernels itself on a clean
    clone (about 100 s of CPU each). The two halves run at once, one per
    core; with a warm cache they only load it. ``MUDFORCE_NO_WARMUP=1`` skips it.
    """
    if not _distributed(config):
        return
    config.option.loadscopereorder = False  # keep pytest_collection_modifyitems' order (longest first)
    if os.environ.get("MUDFORCE_NO_WARMUP"):
        return
    script = Path(__file__).resolve().parent / "numba_warmup.py"
    from mudforce_cli_harness import cli_env  # the package under test first on the path, as every subprocess

    env = cli_env()
    halves = [subprocess.Popen([sys.executable, str(script), part], env=env, stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True) for part in ("a", "b")]
    for proc in halves:
        _, err = proc.communicate()
        lines = [line for line in err.splitlines() if line.startswith("numba warm-up") and "failed" in line]
        for line in lines:
            print(line, file=sys.stderr)
