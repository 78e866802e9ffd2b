"""Ctrl-C (SIGINT) that always stops a command: never swallowed where Python cannot raise it.

Python turns SIGINT into :class:`KeyboardInterrupt` at the next bytecode of
the main thread. When that bytecode belongs to a weak-reference callback or
a finaliser run by the garbage collector (matplotlib frees its figures'
caches that way while a report is drawn), the exception cannot propagate:
Python prints ``Exception ignored in: ...`` with a traceback, drops it, and
the command carries on to finish and exit 0.

:func:`watch`, around a command (:func:`mudforce.cli.main`), closes that gap:

* a SIGINT handler that records the interrupt before raising it, so that
  it is known even where the exception is lost;
* an ``unraisablehook`` that, for a lost :class:`KeyboardInterrupt`, prints
  nothing and raises the interrupt again a moment later (from a timer
  thread, once the main thread is out of the callback), where it can act;
* :func:`check`, which raises :class:`KeyboardInterrupt` if an interrupt
  came and was lost: a staged output is not swapped in after it
  (:meth:`mudforce.io.StagedOutputs.commit`), and the command line exits
  with status 130 after a command that ends normally despite it.

:func:`settle`, once the command line has caught the interrupt, releases
what the frames it cut short held, with what their finalisers raise
silenced: an interrupt inside a finaliser (numba's compiler frees LLVM
objects that way) can leave an object half-closed, whose next finaliser
call then fails, and Python printed that as ``Exception ignored in: ...``
with a traceback after the one line ``mudforce: interrupted``.

Where SIGINT is ignored (a background job of a non-interactive shell), it
stays ignored.

:func:`held` holds SIGINT and SIGTERM back over a few statements that must
run whole (staged outputs made, swapped in or removed), and delivers them on
leaving. Plumbing; no physics, no units.
"""

from __future__ import annotations

import _thread
import contextlib
import gc
import signal
import sys
import threading
import traceback
from collections.abc import Callable, Iterator
from typing import Any

__all__ = ["check", "held", "pending", "settle", "watch"]

#: Delay before an interrupt lost in a callback is raised again [s].
_RETRY_S = 0.01

_pending = False


def pending() -> bool:
    """Whether an interrupt came during the current :func:`watch` (raised or lost)."""
    return _pending


def check() -> None:
    """Raise :class:`KeyboardInterrupt` if an interrupt came during the current :func:`watch`."""
    if _pending:
        raise KeyboardInterrupt


def settle(exc: BaseException) -> None:
    """Release the frames the interrupt ``exc`` cut short (their locals, then a collection), with anything their
    finalisers raise dropped, not printed; ``sys.unraisablehook`` comes back on leaving. For the command line's
    handler of :class:`KeyboardInterrupt`: the command is over and exits with status 130."""
    previous_hook = sys.unraisablehook
    sys.unraisablehook = _drop
    try:
        if exc.__traceback__ is not None:
            traceback.clear_frames(exc.__traceback__)  # (the frame still running is skipped)
        gc.collect()
    except KeyboardInterrupt:
        pass  # a second Ctrl-C while freeing: the command is interrupted already
    finally:
        sys.unraisablehook = previous_hook


def _drop(unraisable: Any) -> None:
    """An unraisable exception, dropped (:func:`settle`)."""


def _handler(signum: int, frame: Any) -> None:
    global _pending
    _pending = True
    raise KeyboardInterrupt


def _deliver() -> None:
    """Nothing: a call, at whose start the interpreter delivers a pending interrupt."""


@contextlib.contextmanager
def watch() -> Iterator[None]:
    """Inside, SIGINT is recorded as well as raised, and one lost where Python cannot raise it is raised again.

    Only in the main thread and where SIGINT has Python's default handler;
    the previous handler and ``sys.unraisablehook`` come back on leaving,
    and what was recorded is forgotten (it belonged to this command).
    """
    global _pending
    _pending = False
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    previous_hook = sys.unraisablehook
    timers: list[threading.Timer] = []
    closing = False  # watch() is ending: a lost interrupt is no longer retried (see the finally clause)
    lost_while_closing = False

    def hook(unraisable: Any) -> None:
        nonlocal lost_while_closing
        if isinstance(unraisable.exc_value, KeyboardInterrupt) and closing:
            # a retry lost in a callback while the timers are joined: a timer started now would fire after the
            # handlers are restored, once the command has returned (exit by SIGINT, -2); the interrupt is acted
            # on below instead, as one delivered there
            lost_while_closing = True
        elif isinstance(unraisable.exc_value, KeyboardInterrupt):
            # lost in a callback or finaliser: raise it again once the main thread is out of it (not from
            # here: the main thread would act on it at once, inside this hook, and lose it again)
            # A retry of an earlier one may land in here (a loaded machine, matplotlib freeing caches one after
            # another): it is the same interrupt, already recorded; schedule again and let nothing escape the
            # hook (Python would print "Exception ignored in sys.unraisablehook" with a traceback).
            while True:
                try:
                    timer = threading.Timer(_RETRY_S, _thread.interrupt_main)
                    timer.daemon = True
                    timers.append(timer)
                    timer.start()
                    break
                except KeyboardInterrupt:
                    continue
        else:
            previous_hook(unraisable)

    late = False

    def absorb(signum: int, frame: Any) -> None:
        nonlocal late
        late = True

    signal.signal(signal.SIGINT, _handler)
    sys.unraisablehook = hook
    try:
        yield
    finally:
        # From here on an interrupt only records itself (``absorb``): a retry that fires now (a loaded machine runs
        # its timer late) or one already tripped. Raised in this clause, between two of its statements, it would
        # skip the rest: a timer left unjoined would interrupt the main thread after the command had reported
        # "interrupted" and returned 130, and Python would end the process by SIGINT instead (exit status -2). The
        # interrupt a retry repeats is already recorded (``_pending``) and acted on; a Ctrl-C that comes only now,
        # with the command done, is raised at the end, once the handlers are back. A retry that trips before
        # ``absorb`` is in place (at this clause's first call) raises here: recorded (``_handler``), it is taken as
        # a late one, and ``absorb`` is put in place again, so that the rest of the clause still runs.
        while True:
            try:
                signal.signal(signal.SIGINT, absorb)
                break
            except KeyboardInterrupt:
                late = True
        closing = True
        for timer in timers:
            timer.cancel()
        for timer in timers:
            if timer.ident is not None:  # started: wait until it has run or seen its cancellation
                timer.join()
        _deliver()  # a signal the last of them tripped is handled here, by ``absorb``
        sys.unraisablehook = previous_hook
        signal.signal(signal.SIGINT, signal.default_int_handler)
        _pending = False
        if (late or lost_while_closing) and sys.exc_info()[0] is None:
            raise KeyboardInterrupt


#: The signals :func:`held` holds back.
_HELD = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def held() -> Iterator[None]:
    """Inside, SIGINT and SIGTERM are recorded, not acted on; on leaving, each one that came is raised again.

    Python runs a signal's handler in the main thread, whichever thread the system delivered the signal to, so
    the handlers are swapped for one that records (a mask of the main thread alone, ``pthread_sigmask``, lets
    the system deliver a process's signal to another thread, and Python then acts on it at once). On leaving, the
    handlers come back and each signal recorded is raised again (:func:`signal.raise_signal`): a Ctrl-C raises
    :class:`KeyboardInterrupt` there, past the held statements; a SIGTERM with the system's default ends the
    process there. A signal that is ignored stays ignored, and one whose handler Python did not install (``None``)
    is left alone. Outside the main thread handlers cannot be changed; nothing is held there.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    came: list[signal.Signals] = []

    def record(signum: int, frame: Any) -> None:
        if signal.Signals(signum) not in came:
            came.append(signal.Signals(signum))

    previous: list[tuple[signal.Signals, Callable[[int, Any], Any] | int]] = []
    try:
        for signum in _HELD:
            handler = signal.getsignal(signum)
            if handler is None or handler == signal.SIG_IGN:
                continue
            signal.signal(signum, record)
            previous.append((signum, handler))
        yield
    finally:
        for signum, handler in reversed(previous):
            signal.signal(signum, handler)
        for signum in came:
            signal.raise_signal(signum)
