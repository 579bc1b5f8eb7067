"""The installed ``dh2urdf`` program: dh2urdf's export and ``from-urdf``, kin's audit and calibrate.

``dh2urdf`` is the lower package and never imports ``kin``; this module, above both, gives
:func:`dh2urdf.command.main` the subcommands of the two: ``dh2urdf audit`` (:mod:`kin.audit`)
and ``dh2urdf calibrate`` (:mod:`kin.calibration`), their commands :mod:`.audit` and
:mod:`.calibrate`, beside dh2urdf's own (``from-urdf``). Each
subcommand's module is imported only when it is chosen. The console script ``dh2urdf`` runs
:func:`console`, as ``python -m kin.commands.dh2urdf_program`` does; ``python -m dh2urdf`` runs
dh2urdf's own forms alone.
"""

from __future__ import annotations

from dh2urdf import command
from dh2urdf.command import Subcommand, SubcommandMain

__all__ = ["SUBCOMMANDS", "console", "main"]


def _audit() -> SubcommandMain:
    from .audit import main

    return main


def _calibrate() -> SubcommandMain:
    from .calibrate import main

    return main


#: The program's subcommands: kin's, then dh2urdf's own (``dh2urdf --help`` lists them so).
SUBCOMMANDS: dict[str, Subcommand] = {
    "audit": Subcommand(
        "which reading of a paper's DH table reproduces its printed poses or a URDF", _audit
    ),
    "calibrate": Subcommand(
        "the DH table and URDF of the arm you have, from measured positions or poses", _calibrate
    ),
    **command.SUBCOMMANDS,
}


def main(argv: list[str] | None = None) -> int:
    """Run ``dh2urdf`` with every subcommand; exit 0, or 2 with one line on stderr."""
    return command.main(argv, SUBCOMMANDS)


def console() -> int:
    """The ``dh2urdf`` console script: :func:`main` for the process's life.

    A stop signal after the command has stopped or returned is ignored, not a traceback while
    the interpreter ends (:func:`dh2urdf.stop_signals.run_process`).
    """
    from dh2urdf.stop_signals import run_process

    return run_process(main)


if __name__ == "__main__":
    raise SystemExit(console())
