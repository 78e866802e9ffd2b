"""``mudforce fit-drag`` through a subprocess: lambda back from a sliding run written in mm/s."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from numpy.testing import assert_allclose

from mudforce_cli_harness import run_cli


def test_fit_drag_cli(tmp_path: Path) -> None:
    v = np.linspace(-1.0, 1.0, 21)
    f = 0.02 * 1840 * 19.38e-4 * np.sign(v) * v**2
    path = tmp_path / "slide.csv"
    rows = "".join(f"{float(a) * 1e3!r},{float(b)!r}\n" for a, b in zip(v, f, strict=True))
    path.write_text("velocity_mm_s,force_N\n" + rows)
    proc = run_cli(["fit-drag", str(path), "--area", "19.38cm2", "--json"], timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert_allclose(json.loads(proc.stdout)["lambda"], 0.02, rtol=1e-9)
