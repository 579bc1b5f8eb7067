"""Monte Carlo workspace of a robot (reach, box, volume, PNG): ``kin workspace`` as a script.

Options: ``python scripts/workspace.py --help`` (the same as ``kin workspace --help``).
"""

from __future__ import annotations

from kin.commands import workspace


def get_argument_parser() -> workspace.ArgumentParser:
    """Command-line arguments (those of ``kin workspace``)."""
    return workspace.get_argument_parser("workspace.py")


def main(argv: list[str] | None = None) -> int:
    """Run ``kin workspace`` with this script's name in messages."""
    return workspace.main(argv, prog="workspace.py")


if __name__ == "__main__":
    raise SystemExit(main())
