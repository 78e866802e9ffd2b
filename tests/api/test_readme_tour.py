"""README's short tour runs as written, and every figure its comments state is what it prints.

The tour is the first thing a new user copies. Its comments state the figures each ``print`` gives (``# 59.5 N,
-11.63 N, [8.66 s]``); they had drifted from the code (the tracker's interval read 0.316 where it prints 0.322).
The block runs in a scratch folder (it writes ``w25.csv`` and ``w25.png``); each commented ``print`` is recorded
instead of printed, and each number of its comment must equal the printed number at the comment's precision
(half a unit of its last digit: "0.109" holds 0.1092, "0" holds 8e-5).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _tour() -> str:
    text = README.read_text(encoding="utf-8")
    start = text.index("## A short tour")
    block = re.search(r"```python\n(.*?)```", text[start:], re.S)
    assert block is not None, "README's short tour has no ```python block"
    return block.group(1)


def _tolerance(stated: str) -> float:
    """Half a unit of the last digit written: 59.5 -> 0.05, 0.284 -> 0.0005, 0 -> 0.5, 1e-3 -> 5e-4."""
    mantissa, _, exponent = stated.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def _instrumented(source: str) -> tuple[str, dict[int, str]]:
    """The tour with each ``print(...)  # figures`` line calling ``_said(line, ...)``; the comments by line."""
    lines, stated = [], {}
    for k, line in enumerate(source.splitlines(), start=1):
        code, _, comment = line.partition("#")
        if code.lstrip().startswith("print(") and NUMBER.search(comment):
            stated[k] = comment
            line = code.replace("print(", f"_said({k}, ", 1)
        lines.append(line)
    return "\n".join(lines) + "\n", stated


def test_the_tour_runs_and_prints_the_figures_its_comments_state(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("jax")  # the tour's last part (extra "jax"; the test extra installs it)
    source, stated = _instrumented(_tour())
    assert len(stated) >= 3, "the tour's commented prints were not found"
    printed: dict[int, str] = {}

    def said(line: int, *args: Any) -> None:
        printed[line] = " ".join(str(a) for a in args)

    monkeypatch.chdir(tmp_path)
    exec(compile(source, "README.md (the short tour)", "exec"), {"_said": said, "__name__": "__readme__"})
    assert (tmp_path / "w25.csv").is_file() and (tmp_path / "w25.png").is_file()
    for line, comment in stated.items():
        want = NUMBER.findall(comment)
        got = [float(x) for x in NUMBER.findall(printed[line])]
        assert len(got) == len(want), f"tour line {line}: prints {printed[line]!r}, its comment says {comment!r}"
        for w, g in zip(want, got, strict=True):
            assert abs(g - float(w)) <= _tolerance(w) * (1 + 1e-9), (
                f"tour line {line}: prints {printed[line]!r}, its comment says {comment.strip()!r}")


@pytest.mark.parametrize(("stated", "half_unit"), [("59.5", 0.05), ("0.284", 5e-4), ("0", 0.5), ("-11.63", 5e-3),
                                                   ("1e-3", 5e-4), ("2.5e2", 5.0)])
def test_the_precision_of_a_stated_figure(stated: str, half_unit: float) -> None:
    assert _tolerance(stated) == pytest.approx(half_unit)
