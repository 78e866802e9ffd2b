"""Byte-compile ``src/`` and the installed packages the tests import, on every core (the test command's second step).

pip byte-compiles every file it installs on one core, about half of its install's time on a clean clone; the
test command installs with uv (or pip ``--no-compile``), neither byte-compiling, and runs this instead. It
writes the same ``.pyc`` files that pip would, in parallel, and skips what the tests never import: the packages'
own test suites, and a few dependencies of dependencies that nothing here loads (PyOpenGL, pulled in by MuJoCo
for rendering, 2,900 files; pip and setuptools; fontTools, which Matplotlib loads only for PDF and PostScript;
mypy and mypyc, which run as compiled extension modules; Pygments' lexers). A file that is skipped, or does not
compile, is compiled on import as usual, so this only moves time, never changes a result. ``python
tests/precompile.py``.
"""

from __future__ import annotations

import compileall
import re
import sys
import sysconfig
from pathlib import Path

#: Folders whose files the test run does not import (matched anywhere in a path).
SKIP = re.compile(r"[/\\](tests?|OpenGL|pip|setuptools|pkg_resources|_distutils_hack|fontTools|websockets|fsspec"
                  r"|mypy|mypyc|lexers)[/\\]")


def main() -> int:
    root = Path(__file__).resolve().parents[1]
    folders = [str(root / "src"), sysconfig.get_path("purelib")]
    for folder in folders:
        compileall.compile_dir(folder, quiet=2, workers=0, rx=SKIP)  # a file that does not compile is skipped
    return 0


if __name__ == "__main__":
    sys.exit(main())
