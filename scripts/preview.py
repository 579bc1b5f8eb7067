"""Show a robot in the browser (meshcat): the ``kin preview`` command as a script.

Options: ``python scripts/preview.py --help`` (the same as ``kin preview --help``).
"""

from __future__ import annotations

from kin.commands import preview


def get_argument_parser() -> preview.ArgumentParser:
    """Command-line arguments (those of ``kin preview``)."""
    return preview.get_argument_parser("preview.py")


def main(argv: list[str] | None = None) -> int:
    """Run ``kin preview`` with this script's name in messages."""
    return preview.main(argv, prog="preview.py")


if __name__ == "__main__":
    raise SystemExit(main())
