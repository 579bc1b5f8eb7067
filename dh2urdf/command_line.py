"""Command-line edges shared by every command and script: one-line errors, typed converters.

Commands exit with code 2 and print exactly one line on stderr for bad input (argparse errors and
the project's exceptions alike), never a traceback; a closed output pipe (``kin fk ... | head``)
or a closed stdout (``>&-``) is ignored quietly and the command keeps its own exit code (1 stays 1
under ``set -o pipefail``); stdout on a full device (``> /dev/full``, ENOSPC, EIO...) and an output
file that cannot be written to the end are one line and exit 1; Ctrl-C prints one line and exits
130, SIGTERM the same with 143 (:mod:`dh2urdf.stop_signals`).
"""

from __future__ import annotations

import argparse
import errno
import math
import os
import re
import sys
import warnings
from collections.abc import Callable
from typing import Any, NoReturn, TextIO

from .exceptions import Dh2UrdfError, OutputWriteError
from .quoted_input import quoted
from .units import ANGLE_UNITS, LENGTH_UNITS

#: Exit code for bad input.
EXIT_BAD_INPUT = 2

#: Exit code after Ctrl-C (128 + SIGINT).
EXIT_INTERRUPTED = 130

#: Exit code after SIGTERM (128 + SIGTERM), which stops a command as Ctrl-C does.
EXIT_TERMINATED = 143

#: Most characters of an error message on the one error line (then "...").
ERROR_LINE_LIMIT = 2000

#: Exit code of a run that failed part-way for a reason outside its input (a full disk).
EXIT_FAULT = 1

#: Errors of a standard output that takes no more output: the reader left (quiet, the command's
#: own exit code) or the device is full or failing (one line, :data:`EXIT_FAULT`).
_STDOUT_GONE = (errno.EPIPE, errno.EBADF)
_STDOUT_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EIO)

# argparse takes "-1.2e-16" for an option because its own pattern knows no exponent; "-inf" and
# "-nan" are values too (refused by the converters with a clear line, not "expected 3 arguments").
_NEGATIVE_NUMBER = re.compile(
    r"^-((\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|inf|infinity|nan)$", re.IGNORECASE
)


class ArgumentParser(argparse.ArgumentParser):
    """An argparse parser whose errors are one line on stderr and exit code 2.

    Negative numbers in any notation (``-3``, ``-.5``, ``-1.2e-16``) are values, not options.
    """

    def __init__(self, *args, **kwargs):  # noqa: ANN002, ANN003
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message: str) -> NoReturn:
        """Print ``prog: error: message`` on one line and exit 2."""
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def _plain_number(text: str) -> None:
    """Refuse what Python's ``float`` and ``int`` read but a number on a command line is not.

    ``1_000`` (Python's digit grouping, read as 1000: a typo of ``1.000`` or ``1,000`` as likely)
    and digits of other scripts (``float("\u0661")`` is 1.0) are refused with the fix.

    Raises:
        argparse.ArgumentTypeError: ``text`` holds ``_`` or a character outside ASCII.
    """
    if "_" in text or not text.isascii():
        raise argparse.ArgumentTypeError(
            f"not a number: {quoted(text)}; write it with the digits 0-9, without '_' (1000, not 1_000)"
        )


def finite_float(text: str) -> float:
    """Argparse type: a finite float (rejects nan, inf, non-numbers, ``1_000``)."""
    _plain_number(text)
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {quoted(text)}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {quoted(text)}")
    return value


def whole_number(text: str) -> int:
    """Argparse type: a whole number of any sign (rejects ``1_000`` and ``1.5``)."""
    _plain_number(text)
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {quoted(text)}") from None


def positive_int(text: str) -> int:
    """Argparse type: a whole number >= 1 (rejects ``1_000``)."""
    _plain_number(text)
    try:
        value = int(text)
    except ValueError:
        hint = ""
        try:
            number = float(text)
        except ValueError:
            number = math.nan
        if math.isfinite(number) and number == int(number):  # 1e6: write the digits out
            hint = f"; write it with digits only, e.g. {int(number)}"
        raise argparse.ArgumentTypeError(f"not a whole number: {quoted(text)}{hint}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def positive_float(text: str) -> float:
    """Argparse type: a finite number > 0."""
    value = finite_float(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {quoted(text)}")
    return value


def length_scale(unit: str) -> float:
    """Meters per ``unit`` (m, cm, mm)."""
    return LENGTH_UNITS[unit]


def angle_scale(degrees: bool) -> float:
    """Radians per input angle unit."""
    return ANGLE_UNITS["deg" if degrees else "rad"]


def report_error(prog: str, err: BaseException) -> int:
    """Print one line ``prog: error: ...`` on stderr and return the bad-input exit code.

    The line is cut at :data:`ERROR_LINE_LIMIT` characters: a message that lists names read
    from a hostile file (links of a megabyte each) stays a line a terminal can show.
    """
    text = " ".join(str(err).split())
    if len(text) > ERROR_LINE_LIMIT:
        text = text[:ERROR_LINE_LIMIT] + "..."
    print(f"{prog}: error: {text}", file=sys.stderr)
    return EXIT_BAD_INPUT


def _say(line: str) -> None:
    """Print ``line`` on stderr, unless stderr itself is gone (``2>/dev/full``)."""
    try:
        print(line, file=sys.stderr)
    except (OSError, ValueError, AttributeError):
        pass


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail again."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout without a file descriptor (captured in tests)
        pass
    finally:
        os.close(devnull)


class PipeGuard:
    """Standard output that survives its reader going away (``| head``) or a full device.

    The first write or flush that meets a closed pipe (or a full device: :attr:`fault`) points
    the file descriptor at ``/dev/null`` and sets :attr:`broken`; later output is dropped. The
    command goes on; a stream (``kin ik --stdin``) stops reading when it sees :attr:`broken`. A
    stdout closed at start (``>&-``, ``None``) is ``/dev/null`` from the start, broken.
    """

    def __init__(self, target: TextIO | None):
        self.broken = target is None
        if target is None:  # also keeps fd 1 from being reused by the next file opened
            target = open(os.devnull, "w", encoding="utf-8")  # noqa: SIM115
        self.target: TextIO = target
        #: What the operating system said when stdout was full or failing, else None.
        self.fault: str | None = None
        #: Warning lines not shown yet (see :func:`run_guarded`).
        self.pending: list[str] = []

    def show_warnings(self) -> None:
        """Print the pending warning lines on stderr."""
        for line in self.pending:
            print(line, file=sys.stderr)
        self.pending.clear()

    def write(self, text: str) -> int:
        """Write ``text`` (dropped once the pipe is broken), after any pending warning."""
        if self.pending:
            self.show_warnings()
        if not self.broken:
            try:
                return self.target.write(text)
            except OSError as err:
                self._break(err)
        return len(text)

    def flush(self) -> None:
        """Flush (nothing once the pipe is broken)."""
        if not self.broken:
            try:
                self.target.flush()
            except OSError as err:
                self._break(err)

    def _break(self, err: OSError) -> None:
        """Drop later output after a closed pipe or a full device; re-raise any other error."""
        if err.errno not in _STDOUT_GONE + _STDOUT_FULL:
            raise err
        if err.errno in _STDOUT_FULL:
            self.fault = err.strerror or str(err)
        self.broken = True
        _silence_stdout()

    def __getattr__(self, name: str) -> Any:
        return getattr(self.target, name)


def run_guarded(
    prog: str,
    body: Callable[[], int],
    errors: tuple[type[BaseException], ...] = (Dh2UrdfError,),
) -> int:
    """Run ``body`` and turn ``errors`` into a one-line exit 2.

    Standard output is a :class:`PipeGuard` meanwhile: a closed output pipe is ignored without a
    word and ``body``'s own exit code is returned; a full stdout (``> /dev/full``) and an
    :class:`~dh2urdf.exceptions.OutputWriteError` are one line and :data:`EXIT_FAULT`. Ctrl-C
    prints ``prog: interrupted`` and returns 130; SIGTERM stops it the same way (workers ended,
    what is done kept: :mod:`dh2urdf.stop_signals`), ``prog: terminated`` and 143.
    """
    from .stop_signals import hold_stops, listen_to_stops, terminated

    restore_sigterm = listen_to_stops()
    previous = sys.stdout
    guard = PipeGuard(previous) if not isinstance(previous, PipeGuard) else previous
    sys.stdout = guard  # type: ignore[assignment]
    show = warnings.showwarning

    def one_line(message: Warning | str, *_: object, **__: object) -> None:
        guard.pending.append(f"{prog}: warning: {' '.join(str(message).split())}")

    # A library warning is one line on stderr, no source line; held until the command writes
    # its first output or ends, so that bad input stays exactly one line (the error).
    warnings.showwarning = one_line
    try:
        code = body()
        guard.show_warnings()
        guard.flush()
        if guard.fault is not None:
            _say(f"{prog}: error: cannot write to standard output: {guard.fault}")
            return EXIT_FAULT
        return code
    except BrokenPipeError:  # output written around the guard
        _silence_stdout()
        return 0
    except OutputWriteError as err:  # a full disk under -o: a fault, not bad input
        report_error(prog, err)
        return EXIT_FAULT
    except errors as err:
        return report_error(prog, err)
    except KeyboardInterrupt:
        hold_stops()  # a second Ctrl-C while the process ends is not a traceback
        if terminated():
            _say(f"{prog}: terminated")
            return EXIT_TERMINATED
        _say(f"{prog}: interrupted")
        return EXIT_INTERRUPTED
    finally:
        sys.stdout = previous
        warnings.showwarning = show
        restore_sigterm()
