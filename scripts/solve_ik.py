"""Solve the inverse kinematics of a robot: the ``kin ik`` command as a script.

Options: ``python scripts/solve_ik.py --help`` (the same as ``kin ik --help``).
"""

from __future__ import annotations

from kin.commands import ik


def get_argument_parser() -> ik.ArgumentParser:
    """Command-line arguments (those of ``kin ik``)."""
    return ik.get_argument_parser("solve_ik.py")


def main(argv: list[str] | None = None) -> int:
    """Run ``kin ik`` with this script's name in messages."""
    return ik.main(argv, prog="solve_ik.py")


if __name__ == "__main__":
    raise SystemExit(main())
