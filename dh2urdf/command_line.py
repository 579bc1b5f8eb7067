"""Command-line edges shared by every command and script: one-line errors, typed converters.

Commands exit with code 2 and print exactly one line on stderr for bad input (argparse errors and
the project's exceptions alike), never a traceback; a closed output pipe (``kin fk ... | head``)
ends the command quietly; Ctrl-C prints one line and exits 130.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
from collections.abc import Callable
from typing import NoReturn

from .exceptions import Dh2UrdfError
from .units import ANGLE_UNITS, LENGTH_UNITS

#: Exit code for bad input.
EXIT_BAD_INPUT = 2

#: Exit code after Ctrl-C (128 + SIGINT).
EXIT_INTERRUPTED = 130

# argparse takes "-1.2e-16" for an option because its own pattern knows no exponent.
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


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


def finite_float(text: str) -> float:
    """Argparse type: a finite float (rejects nan, inf and non-numbers)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def positive_int(text: str) -> int:
    """Argparse type: a whole number >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def positive_float(text: str) -> float:
    """Argparse type: a finite number > 0."""
    value = finite_float(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {text!r}")
    return value


def length_scale(unit: str) -> float:
    """Meters per ``unit`` (m, cm, mm)."""
    return LENGTH_UNITS[unit]


def angle_scale(degrees: bool) -> float:
    """Radians per input angle unit."""
    return ANGLE_UNITS["deg" if degrees else "rad"]


def report_error(prog: str, err: BaseException) -> int:
    """Print one line ``prog: error: ...`` on stderr and return the bad-input exit code."""
    text = " ".join(str(err).split())
    print(f"{prog}: error: {text}", file=sys.stderr)
    return EXIT_BAD_INPUT


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail again."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout without a file descriptor (captured in tests)
        pass
    finally:
        os.close(devnull)


def run_guarded(
    prog: str,
    body: Callable[[], int],
    errors: tuple[type[BaseException], ...] = (Dh2UrdfError,),
) -> int:
    """Run ``body`` and turn ``errors`` into a one-line exit 2.

    A closed output pipe returns 0 without a word (the reader has what it wanted); Ctrl-C
    prints ``prog: interrupted`` and returns 130.
    """
    try:
        code = body()
        sys.stdout.flush()
        return code
    except BrokenPipeError:
        _silence_stdout()
        return 0
    except errors as err:
        return report_error(prog, err)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
