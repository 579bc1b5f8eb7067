"""Print the tool pose of a robot at a joint vector: the ``kin fk`` command as a script.

Options: ``python scripts/fk.py --help`` (the same as ``kin fk --help``).
"""

from __future__ import annotations

from kin.commands import fk


def get_argument_parser() -> fk.ArgumentParser:
    """Command-line arguments (those of ``kin fk``)."""
    return fk.get_argument_parser("fk.py")


def main(argv: list[str] | None = None) -> int:
    """Run ``kin fk`` with this script's name in messages."""
    return fk.main(argv, prog="fk.py")


if __name__ == "__main__":
    raise SystemExit(main())
