"""Audit a DH table against printed samples or a reference URDF: the ``dh2urdf audit`` command.

Options: ``python scripts/audit_dh.py --help`` (the same as ``dh2urdf audit --help``).
"""

from __future__ import annotations

from kin.commands import audit as command


def get_argument_parser() -> command.ArgumentParser:
    """Command-line arguments (those of ``dh2urdf audit``)."""
    return command.get_argument_parser("audit_dh.py")


def main(argv: list[str] | None = None) -> int:
    """Run ``dh2urdf audit`` with this script's name in messages."""
    return command.main(argv, prog="audit_dh.py")


if __name__ == "__main__":
    raise SystemExit(main())
