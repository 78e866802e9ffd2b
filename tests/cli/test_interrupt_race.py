"""A retried interrupt that fires late is delivered inside ``watch``, never after the command has returned 130."""

from __future__ import annotations

import _thread
import sys
import threading
import time
from types import SimpleNamespace

import pytest

from mudforce._plumbing import interrupt


def test_a_retry_that_fired_late_is_absorbed_and_the_interrupt_still_stops_the_command(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The race a loaded machine showed: a lost interrupt's retry, already running when the command stopped,
    interrupted the main thread after ``main`` had returned 130, and Python ended the process by SIGINT (-2)."""
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("watch() acts in the main thread only")
    real = _thread.interrupt_main

    def slow_retry() -> None:  # the retry's timer thread, descheduled between its wait and its call
        time.sleep(0.1)
        real()

    monkeypatch.setattr(interrupt, "_RETRY_S", 0.0)
    monkeypatch.setattr(_thread, "interrupt_main", slow_retry)
    lost = SimpleNamespace(exc_type=KeyboardInterrupt, exc_value=KeyboardInterrupt(), exc_traceback=None,
                           err_msg=None, object=None)
    with pytest.raises(KeyboardInterrupt), interrupt.watch():
        sys.unraisablehook(lost)  # an interrupt lost in a callback: the retry is scheduled ...
        time.sleep(0.02)  # ... and its timer has fired (it is inside slow_retry) ...
        raise KeyboardInterrupt  # ... when the command stops on the recorded interrupt (check())
    time.sleep(0.3)  # the retry's interrupt was delivered inside watch(): none arrives here
    assert not interrupt.pending()


def test_a_ctrl_c_that_arrives_as_the_command_ends_is_not_swallowed() -> None:
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("watch() acts in the main thread only")
    with pytest.raises(KeyboardInterrupt), interrupt.watch():
        _thread.interrupt_main()  # pending at the end of the body
    time.sleep(0.05)
