"""The ``kin`` command: one entry point, a thin subcommand per task.

``kin robots`` lists the shipped robots, ``kin fk`` prints a frame pose, ``kin ik`` solves the
inverse kinematics (one target, or a stream of JSON targets with ``--stdin``). Each subcommand
is a module with ``main(argv, prog)``, imported only when chosen, so that ``kin fk`` never loads
the IK solvers.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from dh2urdf.command_line import EXIT_BAD_INPUT, ArgumentParser

__all__ = ["COMMANDS", "console", "get_argument_parser", "main"]

#: Subcommand -> one-line summary (the module is ``kin.commands.<name>``).
COMMANDS: dict[str, str] = {
    "cache": "the numeric solver's seed-table cache: folder, files, size; --clear empties it",
    "check": "collisions of a joint vector: self, with a scene (--scene, --srdf); exit 1 if any",
    "collisions": "SRDF of the link pairs a collision check may skip (as MoveIt's assistant)",
    "drives": "stepper pulses of a joint vector, the angles reached and the tool error",
    "fk": "pose of a robot frame at a joint vector",
    "ik": "inverse kinematics of a tool target (or JSON targets on stdin)",
    "path": "joint path along a Cartesian line or polyline, optionally time-optimal (toppra)",
    "plan": "collision-free joint motion to joints or any IK target (OMPL), certified between samples",
    "preview": "browser view (meshcat) of the arm, its frames, a target and the IK motion",
    "reach": "reachability map: fraction of tool orientations reached per voxel (.npz, PNG)",
    "robots": "the shipped robots: joints and source of each DH table",
    "workspace": "Monte Carlo workspace: reach, bounding box, volume, PNG of the views",
}


def get_argument_parser() -> ArgumentParser:
    """The top-level parser: ``kin [--version] COMMAND ...``."""
    from .. import __version__

    width = max(map(len, COMMANDS)) + 2
    epilog = "commands:\n" + "\n".join(
        f"  {name:<{width}}{text}" for name, text in COMMANDS.items()
    )
    parser = ArgumentParser(
        prog="kin",
        description="kin: forward and inverse kinematics of DH robots, one subcommand per task.",
        epilog=epilog + "\n\nkin COMMAND --help shows the options of a command.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"kin {__version__}")
    parser.add_argument("command", choices=tuple(COMMANDS), metavar="COMMAND", help="see below")
    parser.add_argument("args", nargs="...", help=argparse.SUPPRESS)  # the command's own options
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run ``kin COMMAND ...``; with no command print the usage and return 2."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] in COMMANDS:
        module = importlib.import_module(f"{__name__}.{argv[0]}")
        return module.main(argv[1:], prog=f"kin {argv[0]}")
    parser = get_argument_parser()
    if not argv:
        parser.print_usage(sys.stderr)
        return EXIT_BAD_INPUT
    parser.parse_args(argv)  # --help, --version, or a one-line error (exit 2)
    return EXIT_BAD_INPUT  # not reached: argv[0] was not a command


def console() -> int:
    """The ``kin`` program (console script, ``python -m kin``): :func:`main` as the process's life.

    A stop signal after the command has stopped or returned is ignored, not a traceback while the
    interpreter ends (:func:`dh2urdf.stop_signals.run_process`).
    """
    from dh2urdf.stop_signals import run_process

    return run_process(main)
