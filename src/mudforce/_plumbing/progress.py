"""Progress on a terminal for long work (fits, sweeps, reports); silent otherwise or with --quiet."""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["Progress"]


class Progress:
    """A one-line progress indicator on stderr.

    Shown only when ``stream`` is a terminal and ``quiet`` is false, so that
    logs, pipes and CI stay clean and outputs stay byte-for-byte identical.

    Parameters
    ----------
    total : int
        Number of units of work.
    label : str
        What is being done.
    quiet : bool
        Suppress all output.
    """

    def __init__(self, total: int, label: str, *, quiet: bool = False, stream: TextIO | None = None) -> None:
        self.total = max(int(total), 1)
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        self.enabled = not quiet and bool(getattr(self.stream, "isatty", lambda: False)())
        self.done = 0
        self.start = time.monotonic()
        self._last = 0.0

    def update(self, n: int = 1, note: str = "") -> None:
        """Count ``n`` more units done and redraw (at most 10 times a second)."""
        self.done += n
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self._last < 0.1 and self.done < self.total:
            return
        self._last = now
        frac = min(self.done / self.total, 1.0)
        bar = "#" * int(frac * 24)
        elapsed = now - self.start
        self.stream.write(f"\r{self.label} [{bar:<24}] {self.done}/{self.total} {elapsed:5.1f}s {note[:40]:<40}")
        self.stream.flush()

    def close(self) -> None:
        """Finish the line."""
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
