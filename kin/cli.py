"""Command-line edges of ``kin``: those of :mod:`dh2urdf.command_line`, with kin's errors.

Scripts and commands exit with code 2 and print exactly one line on stderr for bad input
(argparse errors and the project's exceptions alike), never a traceback.
"""

from __future__ import annotations

from collections.abc import Callable

from dh2urdf.command_line import (
    EXIT_BAD_INPUT,
    EXIT_FAULT,
    EXIT_INTERRUPTED,
    EXIT_TERMINATED,
    ArgumentParser,
    angle_scale,
    finite_float,
    length_scale,
    positive_float,
    positive_int,
    report_error,
)
from dh2urdf.command_line import run_guarded as _run_guarded
from dh2urdf.exceptions import Dh2UrdfError

from .exceptions import KinError, RunFaultError

__all__ = [
    "EXIT_BAD_INPUT",
    "EXIT_FAULT",
    "EXIT_INTERRUPTED",
    "EXIT_TERMINATED",
    "ArgumentParser",
    "angle_scale",
    "finite_float",
    "length_scale",
    "positive_float",
    "positive_int",
    "report_error",
    "run_guarded",
]


def run_guarded(
    prog: str, body: Callable[[], int], extra: tuple[type[BaseException], ...] = ()
) -> int:
    """Run ``body``; the project's exceptions (and ``extra``) become a one-line exit 2.

    A :class:`~kin.exceptions.RunFaultError` (a fault during the run, not bad input) is one line
    too, ``prog: error: ...``, with exit :data:`EXIT_FAULT`.
    """

    def faults_exit_1() -> int:
        try:
            return body()
        except RunFaultError as err:
            report_error(prog, err)
            return EXIT_FAULT

    return _run_guarded(prog, faults_exit_1, (Dh2UrdfError, KinError, *extra))
