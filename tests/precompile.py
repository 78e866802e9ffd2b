"""Byte-compile ``src/`` and the installed packages the tests import, on every core (the test command's second step).

pip byte-compiles every file it installs on one core, about half of its install's time on a clean clone; the
test command installs with uv (or pip ``--no-compile``), neither byte-compiling, and runs this instead. It
writes the same ``.pyc`` files that pip would, in parallel, and skips what the tests never import: the packages'
own test suites, and a few dependencies of dependencies that nothing here loads (PyOpenGL, pulled in by MuJoCo
for rendering, 2,900 files; pip and setuptools; fontTools, which Matplotlib loads only for PDF and PostScript;
mypy and mypyc, which run as compiled extension modules; Pygments' lexers; and a few subpackages, such as
scipy.signal and numba.cuda, that nothing here imports). A file that is skipped, or does not
compile, is compiled on import as usual, so this only moves time, never changes a result. ``python
tests/precompile.py``.

Then it writes pytest's own cached form of the modules that pytest rewrites (its assertions made to explain
themselves): the test modules and ``conftest.py``, and the modules of the pytest plugins installed (Hypothesis,
pytest-xdist, pytest-timeout), which pytest rewrites as they are imported. Every pytest-xdist worker collects
every module, and on a clean clone each rewrote all of them itself, at the same time (about 4 s of CPU each, with
``PYTHONDONTWRITEBYTECODE`` set in every run); the workers now read what pytest's own functions wrote here
(:func:`rewritten`), the same code. Where those functions are not what this pytest has, nothing is written and
each worker rewrites as before.
"""

from __future__ import annotations

import compileall
import importlib.metadata
import os
import re
import sys
import sysconfig
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

#: Folders whose files the test run does not import (matched anywhere in a path).
SKIP = re.compile(r"[/\\](tests?|OpenGL|pip|setuptools|pkg_resources|_distutils_hack|fontTools|websockets|fsspec"
                  r"|mypy|mypyc|lexers"
                  # subpackages of the test run's dependencies that no process of the run imports (found from the
                  # .pyc files a whole run read, 2026-11-29: 6.5 MB of source, a tenth of what is compiled)
                  r"|jax[/\\]_src[/\\]internal_test_util|jax[/\\]experimental[/\\](mosaic|pallas|sparse)"
                  r"|scipy[/\\]signal|scipy[/\\]_lib[/\\](cobyqa|pyprima)|numpy[/\\]distutils|numba[/\\]cuda"
                  r"|pandas[/\\]plotting[/\\]_matplotlib"
                  # the same count again (2026-11-30: 25 of 84 MB of .pyc files compiled here were never read): the
                  # pytest plugins, whose modules pytest rewrites and reads in that form (written below), never
                  # these; JAX's kernel languages for accelerators (Pallas, Triton) and MLIR's dialects for them;
                  # MuJoCo's GPU back end, studio and system identification; SciPy's and Matplotlib's unused parts
                  r"|hypothesis|xdist|jax[/\\]_src[/\\]pallas[/\\](mosaic|mosaic_gpu|fuser|triton)"
                  r"|jax[/\\]_src[/\\]scipy[/\\]stats|jaxlib[/\\]triton|mujoco[/\\](studio|sysid|mjx[/\\]third_party[/\\]warp)"
                  r"|scipy[/\\](cluster|io)|absl[/\\](flags|testing)|mpl_toolkits[/\\](axisartist|axes_grid1))[/\\]"
                  # single files of the same kinds: the libraries' own tests, MLIR's accelerator dialects, docstrings
                  r"|(mujoco[/\\](mjx[/\\]_src[/\\])?\w+_test|mujoco_warp[/\\]_src[/\\](?!forward\.|__init__\.)\w+"
                  r"|jax[/\\]_src[/\\]test_util|scipy[/\\]special[/\\]_add_newdocs"
                  r"|pandas[/\\]io[/\\]formats[/\\]style(_render)?|matplotlib[/\\]backends[/\\]backend_(?!agg)\w+"
                  r"|jaxlib[/\\]mlir[/\\]dialects[/\\]_(llvm|nvvm|gpu|vector|arith|sparse_tensor|memref|math|nvgpu|scf|cf)"
                  r"_(ops|enum)_gen)\.py$")


def rewritten(files: list[str]) -> int:
    """Write pytest's cached rewritten form of each of ``files`` (absolute paths); returns how many were written.

    pytest's own functions (``_pytest.assertion.rewrite``): the code it would compile on import, in the file it
    would write itself, where it looks first (a source changed since is rewritten again on import, as usual).
    """
    try:
        from _pytest.assertion.rewrite import PYC_TAIL, _rewrite_test, _write_pyc_fp, get_cache_dir
    except ImportError:  # another pytest: the workers rewrite, as they did
        return 0
    done = 0
    for name in files:
        path = Path(name)
        try:
            source_hash, code = _rewrite_test(path, None)  # type: ignore[arg-type]  # (no ini options read)
            folder = get_cache_dir(path)
            folder.mkdir(exist_ok=True)
            partial = folder / f"{path.name[:-3]}{PYC_TAIL}.{os.getpid()}"
            with open(partial, "wb") as handle:
                _write_pyc_fp(handle, source_hash, code)
            os.replace(partial, folder / (path.name[:-3] + PYC_TAIL))
            done += 1
        except Exception:  # a file not written is rewritten on import, as without this step
            continue
    return done


def _rewritten_by_pytest(tests: Path, packages: Path) -> list[str]:
    """The modules pytest rewrites on import: the tests' and ``conftest.py``, and the installed plugins' modules."""
    files = sorted(str(p) for pattern in ("test_*.py", "conftest.py") for p in tests.rglob(pattern))
    try:
        from _pytest.config import _iter_rewritable_modules
    except ImportError:
        return files
    names: set[str] = set()
    for dist in importlib.metadata.distributions():
        if any(entry.group == "pytest11" for entry in dist.entry_points):
            names.update(_iter_rewritable_modules(str(f) for f in dist.files or []))
    for name in sorted(names):
        module = packages / f"{name}.py"
        found = [module] if module.is_file() else sorted((packages / name).rglob("*.py"))
        files.extend(str(p) for p in found if not SKIP.search(str(p)))
    return files


def main() -> int:
    root = Path(__file__).resolve().parents[1]
    packages = sysconfig.get_path("purelib")
    for folder in (str(root / "src"), packages):
        compileall.compile_dir(folder, quiet=2, workers=0, rx=SKIP)  # a file that does not compile is skipped
    files = _rewritten_by_pytest(root / "tests", Path(packages))
    workers = max(1, min(os.cpu_count() or 1, 8))
    with ProcessPoolExecutor(workers) as pool:
        sum(pool.map(rewritten, [files[i::workers] for i in range(workers)]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
