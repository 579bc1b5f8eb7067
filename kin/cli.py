"""Command-line edges shared by the scripts: one-line errors, typed converters, units.

Scripts exit with code 2 and print exactly one line on stderr for bad input (argparse errors and
the project's exceptions alike), never a traceback.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from typing import NoReturn

from dh2urdf.exceptions import Dh2UrdfError
from dh2urdf.units import ANGLE_UNITS, LENGTH_UNITS

from .exceptions import KinError

#: Exit code for bad input.
EXIT_BAD_INPUT = 2


class ArgumentParser(argparse.ArgumentParser):
    """An argparse parser whose errors are one line on stderr and exit code 2."""

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


def run_guarded(
    prog: str, body: Callable[[], int], extra: tuple[type[BaseException], ...] = ()
) -> int:
    """Run ``body`` and turn the project's exceptions (and ``extra``) into a one-line exit 2."""
    try:
        return body()
    except (Dh2UrdfError, KinError, *extra) as err:
        return report_error(prog, err)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
