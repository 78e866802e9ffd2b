"""The ``mudforce`` command line.

Each subcommand lives in its own module under :mod:`mudforce.cli` and
provides ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.

Exit status: 0 on success, 2 for bad input (one line on stderr, no
traceback, no output file touched), 1 when the system fails mid-way (an
``OSError``: one line too), 130 when interrupted (Ctrl-C, SIGINT: one line,
``mudforce: interrupted``, even when the interrupt came inside a callback
where Python cannot raise it; see :mod:`mudforce._plumbing.interrupt`). Bad input is refused at
its root (units, bounds, strict readers: :mod:`mudforce.io.units`,
:mod:`mudforce.io.tables`, :mod:`mudforce.io`); an ``OverflowError``,
``RecursionError`` or ``ValueError`` that still escapes a command is
reported the same way (one line, status 2), as a last line of defence.

Writing follows one rule in every command (:mod:`mudforce.io`'s writers): a
write refused because of the path given (a folder that does not exist or is
not writable, a name too long, a path that is a directory, permission
denied) is bad input, status 2; a failure of the system while writing (no
space left, an I/O error, a quota exceeded) is status 1. Either is one line
naming the output (``mudforce simulate: error: cannot write out.csv: No
space left on device``) and leaves every output as it was (nothing
half-written); a folder written whole (``synth``, ``reproduce``, ``fit
--report``) names the file in it that failed, by its full path.
"""

from __future__ import annotations

import argparse
import importlib
import math
import re
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

from mudforce._plumbing import interrupt as _interrupt
from mudforce._plumbing.writes import WriteFailure
from mudforce.errors import InputError

__all__ = ["COMMANDS", "main"]

#: Subcommand modules, in the order ``mudforce --help`` lists them.
COMMANDS: tuple[str, ...] = (
    "mudforce.cli.simulate",
    "mudforce.cli.params",
    "mudforce.cli.synth",
    "mudforce.cli.fit",
    "mudforce.cli.fit_drag",
    "mudforce.cli.identify",
    "mudforce.cli.drop",
    "mudforce.cli.track",
    "mudforce.cli.reproduce",
)


#: A word that is a value, not an option, though it starts with "-": a signed number with or without
#: its unit (``-0.5N``, ``-5mm``, ``-1e-3``, ``-.5``), or a signed infinity or NaN (which the value's own
#: check then refuses with its message). No option of any command starts with "-<digit>", "-inf" or "-nan".
_NEGATIVE_VALUE = re.compile(r"^-(?:\.?\d|inf|nan)", re.IGNORECASE)


#: Most digits :func:`plain_int` reads, leading zeros aside [-]: Python's default limit on ``int()`` of a string
#: (``sys.int_info.default_max_str_digits``), far past any count or seed.
MAX_INT_DIGITS = 4300


def plain_int(text: str) -> int:
    """An argparse ``type`` for a count or seed: a plain ASCII decimal integer (``12``, ``-3``), else ValueError,
    which argparse reports as ``invalid int value``. ``int`` itself also took ``1_0`` as 10 and other scripts'
    digits, where every other number the command line reads is plain ASCII. An integer of more than
    :data:`MAX_INT_DIGITS` digits is refused by its size (argparse.ArgumentTypeError), not echoed digit by digit."""
    text = str(text).strip()
    if re.fullmatch(r"[+-]?[0-9]+", text) is None:
        raise ValueError(text)
    sign, digits = ("-" if text[0] == "-" else ""), text.lstrip("+-").lstrip("0") or "0"
    if len(digits) > MAX_INT_DIGITS:  # int() raised ValueError, and argparse then printed every digit
        raise argparse.ArgumentTypeError(f"an integer of {len(digits)} digits is too large (at most "
                                         f"{MAX_INT_DIGITS} digits are read)")
    return int(sign + digits)


plain_int.__name__ = "int"  # argparse's message names the type: "argument --repeats: invalid int value: '1_0'"


def plain_float(text: str) -> float:
    """A plain ASCII decimal number (``20``, ``-1.5e-3``; ``nan`` and ``inf`` too, which each caller refuses in its
    own words), else ValueError: ``float`` itself also took ``1_0`` as 10 and other scripts' digits."""
    from mudforce.io.tables import NUMBER

    text = str(text).strip()
    if NUMBER.fullmatch(text) is None and text.lower().lstrip("+-") not in ("nan", "inf", "infinity"):
        raise ValueError(text)
    return float(text)


plain_float.__name__ = "float"  # as plain_int's: "argument --jitter: invalid float value: '0_1'"


def refuse_not_finite(value: float, text: object, option: str, expected: str, *, literal: str | None = None) -> None:
    """Refuse ``value``, read by :func:`plain_float`, if it is a NaN or an infinity written as one (``nan``,
    ``-inf``), in one line: ``{option}: {text!r} is not a finite number; expected {expected}``. A NaN is no value out
    of range (``--tilt nan`` was "outside -180 to 180 degrees"). A literal past the float range (``1e400``) is read as
    infinite too, but it is a number: it is left to the caller's range check. ``literal`` is the number's own text
    (default ``text``: ``"inf"`` of ``"inf%"``); ``""`` where it is lost (an argparse type's float): then only a
    NaN is refused."""
    word = str(text if literal is None else literal).strip().lstrip("+-").lower()
    if math.isnan(value) or (math.isinf(value) and word in ("inf", "infinity")):
        raise InputError(f"{option}: {text!r} is not a finite number; expected {expected}")


def refuse_empty_inputs(*inputs: tuple[str, str | None, str]) -> None:
    """Refuse an input given as an empty name (``''``, spaces: an unset shell variable), naming its option: each
    ``(option, name or None when not given, what is expected)``. ``Path('')`` is ``.``, the current folder, which
    the readers refused as "is a directory" or searched for a dataset.json."""
    for option, name, what in inputs:
        if name is not None and not str(name).strip():
            raise InputError(f"{option}: empty name {name!r}; expected {what}")


#: What each estimator's force lag is, as its summary says it: identify fits one first-order low-pass; the tracker
#: reads the mean delay of its hypotheses, each one first-order stage or two (:class:`~mudforce.TrackEstimate`).
LAG_READINGS = {"identify": "a first-order low-pass", "track": "the mean delay of one or two low-pass stages"}


def nuisance_text(offset: float, offset_stderr: float, lag: float, lag_stderr: float, reader: str) -> str:
    """The surface offset [m] and the force lag [s], each with its standard error, as ``identify``'s and ``track``'s
    summaries say them (millimetres and milliseconds); ``reader`` (a key of :data:`LAG_READINGS`) says what the lag
    is."""
    return (f"surface offset {offset * 1e3:+.2f} +- {offset_stderr * 1e3:.2f} mm (the model follows the depth plus "
            f"it), force lag {lag * 1e3:.1f} +- {lag_stderr * 1e3:.1f} ms ({LAG_READINGS[reader]})")


class _StoreOnce(argparse.Action):
    """argparse's ``store``, but an option given twice with different values (``--mass 5kg --mass 6kg``) is refused
    in one line naming both, where argparse kept the last without a word; the same value twice means one thing."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any,
                 option_string: str | None = None) -> None:
        given: dict[str, Any] = vars(namespace).setdefault("_given", {})
        if self.dest in given and given[self.dest] != values:
            first, then = (repr(v) if len(repr(v)) <= 40 else repr(v)[:37] + "..." for v in (given[self.dest], values))
            raise argparse.ArgumentError(self, f"given twice ({first}, then {then}); give it once")
        given[self.dest] = values
        setattr(namespace, self.dest, values)


class _Parser(argparse.ArgumentParser):
    """An argparse parser whose errors are one line and exit status 2, and which reads ``--bias -0.5N`` as
    an option and its value (argparse's own rule only takes plain numbers like ``-1`` for values, so it
    reported "expected one argument"); a value that must not be negative is refused by its own check. An
    option given twice with different values is refused (:class:`_StoreOnce`)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_VALUE
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser with every available subcommand."""
    from mudforce import __version__

    parser = _Parser(prog="mudforce", description="The mud resistive-force model of Chen, Yi & Shan (2024).")
    parser.add_argument("--version", action="version", version=f"mudforce {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:  # a command not written yet
                continue
            raise
        cmd = sub.add_parser(module.NAME, help=module.HELP, description=module.__doc__)
        module.add_arguments(cmd)
        cmd.set_defaults(_run=module.run, _parser=cmd)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # refused by the parser they were meant for: `mudforce params --bogus` names `mudforce params`
        getattr(args, "_parser", parser).error(f"unrecognized arguments: {' '.join(extra)}")
    if getattr(args, "_run", None) is None:
        names = [c.rsplit(".", 1)[-1].replace("_", "-") for c in COMMANDS]
        parser.error(f"a command is required, one of {', '.join(names)}")
    try:
        with _interrupt.watch():  # Ctrl-C always stops the command, even where Python would lose it
            status = int(args._run(args) or 0)
            _interrupt.check()  # an interrupt lost along the way: not a success
        return status
    except InputError as exc:
        print(f"mudforce {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        _interrupt.settle(exc)  # what the interrupt cut short is freed now, its finalisers' errors unprinted
        print("mudforce: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader went away (`mudforce params | head`): not an error of ours
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except (OverflowError, RecursionError, ValueError, ZeroDivisionError, MemoryError) as exc:
        # the last line of defence, after the checks at the roots (units, bounds, strict readers):
        # input of a kind no check foresaw still gets one line and status 2, not a traceback
        text = " ".join(str(exc).split())[:200] or exc.__class__.__name__
        print(f"mudforce {args.command}: error: the input could not be processed "
              f"({exc.__class__.__name__}: {text})", file=sys.stderr)
        return 2
    except OSError as exc:
        # the system failed us mid-way (a full disk, a vanished folder): one line, not a traceback;
        # status 1, since the input itself was fine (paths are checked before any work). A write's failure
        # names its output ("cannot write g5.csv: No space left on device")
        if isinstance(exc, WriteFailure):
            text = str(exc)
        else:
            text = (f"{exc.filename}: " if exc.filename else "") + str(exc.strerror or exc)
        print(f"mudforce {args.command}: error: {text}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
