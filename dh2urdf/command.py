"""The ``dh2urdf`` command: write the URDF or MJCF of a DH table (meters, radians).

Usage::

    dh2urdf TABLE.toml -o arm.urdf
    dh2urdf --robot ur5 -o ur5.xml          # MJCF, from the .xml suffix
    dh2urdf --robot ur5 --format mjcf -o -  # to stdout
    dh2urdf from-urdf arm.urdf --tip tool0 -o arm.toml   # a URDF's chain as a DH table

Bad input (missing file, bad table, unknown robot, unwritable output folder) exits 2 with one line
on stderr and leaves no file behind. A first argument naming a subcommand (``audit``) is set apart
before the table parser runs, so subcommands live beside the form ``dh2urdf TABLE.toml -o ...``
without changing it. Exporting never imports ``kin`` (the upper layer); ``dh2urdf audit`` is
implemented there (``kin.audit.command``) and its module is loaded by name only when asked for.
"""

from __future__ import annotations

import argparse
import importlib
import sys
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
#: Subcommands: first argument -> module with ``main(argv, prog)``, loaded only when used.
SUBCOMMANDS: dict[str, str] = {
    "audit": "kin.audit.command",
    "calibrate": "kin.calibration.command",
    "from-urdf": "dh2urdf.from_urdf_command",
}
#: One line per subcommand, for ``dh2urdf --help``.
SUBCOMMAND_HELP: dict[str, str] = {
    "audit": "which reading of a paper's DH table reproduces its printed poses or a URDF",
    "calibrate": "the DH table and URDF of the arm you have, from measured positions or poses",
    "from-urdf": "the DH table (.toml) of a URDF's chain from --base to --tip",
}


def get_argument_parser() -> ArgumentParser:
    """Arguments of the export form ``dh2urdf (TABLE.toml | --robot NAME) -o FILE``."""
    parser = ArgumentParser(
        prog=PROG,
        description=__doc__.splitlines()[0],
        epilog="subcommands:\n"
        + "\n".join(f"  {PROG} {name:<10} {SUBCOMMAND_HELP[name]}" for name in SUBCOMMANDS)
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


def _subcommand(name: str, argv: list[str]) -> int:
    """Run subcommand ``name`` from its module (imported here, by name, on demand)."""
    try:
        module = importlib.import_module(SUBCOMMANDS[name])
    except ImportError as err:
        print(f"{PROG}: error: '{name}' is not available: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    return int(module.main(argv, prog=f"{PROG} {name}"))


def main(argv: list[str] | None = None) -> int:
    """Run ``dh2urdf``; exit 0, or 2 with one line on stderr for bad input."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in SUBCOMMANDS:
        return _subcommand(argv[0], argv[1:])
    args = get_argument_parser().parse_args(argv)
    return run_guarded(PROG, lambda: _export(args), (Dh2UrdfError, OSError))


def console() -> int:
    """The ``dh2urdf`` program (console script, ``python -m dh2urdf``): :func:`main` for life.

    A stop signal after the command has stopped or returned is ignored, not a traceback while
    the interpreter ends (:func:`dh2urdf.stop_signals.run_process`).
    """
    from .stop_signals import run_process

    return run_process(main)
