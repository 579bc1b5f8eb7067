"""Write the URDF of a shipped robot (--robot NAME) or of any DH table file (TABLE.toml)."""

from __future__ import annotations

import sys
from pathlib import Path

from dh2urdf import get_robot, load_table, robot_names
from kin.cli import ArgumentParser, run_guarded


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="export_urdf.py", description=__doc__)
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("table", nargs="?", type=Path, help="DH table file (.toml)")
    source.add_argument("--robot", choices=robot_names(), help="a shipped robot")
    parser.add_argument(
        "-o", "--output", type=Path, required=True, help="URDF file to write ('-' for stdout)"
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Export one URDF; exit 0, or 2 with one line on stderr for bad input."""
    args = get_argument_parser().parse_args(argv)

    def body() -> int:
        from dh2urdf.urdf_writer import urdf_string, write_urdf

        table = get_robot(args.robot).load_table() if args.robot else load_table(args.table)
        if str(args.output) == "-":
            sys.stdout.write(urdf_string(table))
            return 0
        if not args.output.parent.is_dir():
            raise OSError(f"{args.output}: folder {args.output.parent} does not exist")
        write_urdf(table, args.output)
        print(f"wrote {args.output} ({table.name}, {table.dof} joints, meters/radians)")
        return 0

    return run_guarded("export_urdf.py", body, extra=(OSError,))


if __name__ == "__main__":
    raise SystemExit(main())
