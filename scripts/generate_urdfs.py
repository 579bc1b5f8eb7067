"""Regenerate urdf/<robot>.urdf from every shipped DH table; --check only compares (exit 1 if stale)."""

from __future__ import annotations

import sys

from dh2urdf import ROBOTS, Dh2UrdfError
from dh2urdf.command_line import ArgumentParser, run_guarded


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="generate_urdfs.py", description=__doc__)
    parser.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 when a committed URDF differs"
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Generate (or check) all URDFs; exit 0, 1 when --check finds a stale file, 2 for errors."""
    args = get_argument_parser().parse_args(argv)

    def body() -> int:
        from dh2urdf.urdf_writer import urdf_string, write_urdf

        stale = []
        for name, robot in ROBOTS.items():
            table = robot.load_table()
            path = robot.urdf_path
            if args.check:
                current = path.read_text(encoding="utf-8") if path.exists() else None
                if current != urdf_string(table, path.resolve().parent):
                    stale.append(str(path))
            else:
                write_urdf(table, path)
                print(f"wrote {path}")
        if stale:
            print(
                f"generate_urdfs.py: stale: {', '.join(stale)}; run: python scripts/generate_urdfs.py",
                file=sys.stderr,
            )
            return 1
        if args.check:
            print(f"{len(ROBOTS)} URDFs up to date")
        return 0

    return run_guarded("generate_urdfs.py", body, (Dh2UrdfError, OSError))


if __name__ == "__main__":
    raise SystemExit(main())
