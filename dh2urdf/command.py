"""The ``dh2urdf`` command: write the URDF or MJCF of a DH table (meters, radians).

Usage::

    dh2urdf TABLE.toml -o arm.urdf
    dh2urdf --robot ur5 -o ur5.xml          # MJCF, from the .xml suffix
    dh2urdf --robot ur5 --format mjcf -o -  # to stdout
    dh2urdf from-urdf arm.urdf --tip tool0 -o arm.toml   # a URDF's chain as a DH table

Bad input (missing file, bad table, unknown robot, unwritable output folder) exits 2 with one line
on stderr and leaves no file behind. A first argument naming a subcommand (``from-urdf``) is set
apart before the table parser runs, so subcommands live beside the form ``dh2urdf TABLE.toml -o
...`` without changing it.

This package never imports ``kin`` (the upper layer). The installed ``dh2urdf`` program is
composed above both (:mod:`kin.commands.dh2urdf_program`): it passes :func:`main` this package's
:data:`SUBCOMMANDS` with ``kin``'s ``audit`` and ``calibrate``. ``python -m dh2urdf`` runs this
package's forms alone and says in one line where those two are.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

from . import __version__
from .command_line import EXIT_BAD_INPUT, ArgumentParser, run_guarded
from .exceptions import Dh2UrdfError
from .output_text import counted, shown_name
from .robots import get_robot, robot_names
from .table_file import load_table

PROG = "dh2urdf"
#: Output formats and the file suffixes that choose them when --format is not given.
FORMATS = ("mjcf", "urdf")
MJCF_SUFFIXES = (".mjcf", ".xml")
#: A subcommand's ``main(argv, prog=...)``: its exit status.
SubcommandMain = Callable[..., int]


@dataclass(frozen=True)
class Subcommand:
    """A form ``dh2urdf NAME ...``: one line of help and its ``main``, imported only when used.

    Attributes:
        help: One line for ``dh2urdf --help``.
        load: Imports the subcommand's module and returns its ``main(argv, prog=...)``.
    """

    help: str
    load: Callable[[], SubcommandMain]


def _from_urdf() -> SubcommandMain:
    from .from_urdf_command import main

    return main


#: This package's subcommands (first argument -> subcommand).
SUBCOMMANDS: dict[str, Subcommand] = {
    "from-urdf": Subcommand(
        "the DH table (.toml) of a URDF's chain from --base to --tip", _from_urdf
    ),
}
#: Subcommands that the installed program adds from ``kin`` (named here only to say where they are).
INSTALLED_ONLY = ("audit", "calibrate")
#: The module that composes the installed program (``python -m`` runs it too).
INSTALLED_PROGRAM = "kin.commands.dh2urdf_program"


def get_argument_parser(subcommands: Mapping[str, Subcommand] = SUBCOMMANDS) -> ArgumentParser:
    """Arguments of the export form ``dh2urdf (TABLE.toml | --robot NAME) -o FILE``.

    Args:
        subcommands: The program's subcommands, listed in the help's epilog.
    """
    parser = ArgumentParser(
        prog=PROG,
        description=__doc__.splitlines()[0],
        epilog="subcommands:\n"
        + "\n".join(f"  {PROG} {name:<10} {sub.help}" for name, sub in subcommands.items())
        + f"\n\n{PROG} SUBCOMMAND --help shows its options.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("table", nargs="?", type=Path, help="DH table file (.toml)")
    source.add_argument("--robot", choices=robot_names(), help="a shipped robot")
    parser.add_argument("-o", "--output", required=True, help="file to write, '-' for stdout")
    parser.add_argument(
        "--format",
        choices=FORMATS,
        help="output format (default: mjcf for a .xml/.mjcf output, else urdf)",
    )
    return parser


def output_format(output: str, chosen: str | None) -> str:
    """The format to write: ``chosen``, else from the suffix of ``output``."""
    if chosen is not None:
        return chosen
    return "mjcf" if Path(output).suffix.lower() in MJCF_SUFFIXES else "urdf"


def _export(args: argparse.Namespace) -> int:
    """Load the table, render it and write it (atomically) or print it."""
    output: str = args.output
    if output != "-":
        from .output_file import checked_output

        # a regular file or a new path, before any work; never the table itself
        read = get_robot(args.robot).table_path if args.robot else args.table
        checked_output(output, "-o", inputs=[("--robot" if args.robot else "the table", read)])
    table = get_robot(args.robot).load_table() if args.robot else load_table(args.table)
    kind = output_format(output, args.format)
    if kind == "mjcf":
        from .mjcf_writer import mjcf_string

        text = mjcf_string(table)
    else:
        from .urdf_writer import urdf_string

        # a file names the table's meshes relative to its own folder, as write_urdf does
        text = urdf_string(table, None if output == "-" else Path(output).resolve().parent)
    if output == "-":
        sys.stdout.write(text)
        return 0
    from .urdf_writer import write_text_atomic

    write_text_atomic(text, output)
    print(
        f"wrote {output} ({kind.upper()}, {shown_name(table.name)}, {counted(table.dof, 'joint')}, "
        "meters/radians)"
    )
    return 0


def main(argv: list[str] | None = None, subcommands: Mapping[str, Subcommand] = SUBCOMMANDS) -> int:
    """Run ``dh2urdf``; exit 0, or 2 with one line on stderr for bad input.

    Args:
        argv: The arguments (``sys.argv[1:]`` when None).
        subcommands: The program's subcommands: this package's own (``python -m dh2urdf``), or
            those of the installed program (:mod:`kin.commands.dh2urdf_program`).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in subcommands:
        name = argv[0]
        try:
            run = subcommands[name].load()
        except ImportError as err:
            print(f"{PROG}: error: '{name}' is not available: {err}", file=sys.stderr)
            return EXIT_BAD_INPUT
        return int(run(argv[1:], prog=f"{PROG} {name}"))
    if argv and argv[0] in INSTALLED_ONLY:
        print(
            f"{PROG}: error: '{argv[0]}' comes with kin: run the installed program "
            f"(dh2urdf {argv[0]} ...) or python -m {INSTALLED_PROGRAM} {argv[0]} ...",
            file=sys.stderr,
        )
        return EXIT_BAD_INPUT
    args = get_argument_parser(subcommands).parse_args(argv)
    return run_guarded(PROG, lambda: _export(args), (Dh2UrdfError, OSError))


def console() -> int:
    """``python -m dh2urdf``: :func:`main` with this package's subcommands, for life.

    A stop signal after the command has stopped or returned is ignored, not a traceback while
    the interpreter ends (:func:`dh2urdf.stop_signals.run_process`).
    """
    from .stop_signals import run_process

    return run_process(main)
