"""Follow a Cartesian line or polyline with the joints, optionally timed: ``kin path`` as a script.

Options: ``python scripts/path.py --help`` (the same as ``kin path --help``).
"""

from __future__ import annotations

from kin.commands import path


def get_argument_parser() -> path.ArgumentParser:
    """Command-line arguments (those of ``kin path``)."""
    return path.get_argument_parser("path.py")


def main(argv: list[str] | None = None) -> int:
    """Run ``kin path`` with this script's name in messages."""
    return path.main(argv, prog="path.py")


if __name__ == "__main__":
    raise SystemExit(main())
