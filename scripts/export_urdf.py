"""Write the URDF (or MJCF) of a shipped robot (--robot NAME) or of any DH table (TABLE.toml).

A thin shim over the ``dh2urdf`` command: ``dh2urdf TABLE.toml -o FILE`` does the same.
"""

from __future__ import annotations

from dh2urdf.command import get_argument_parser, main

__all__ = ["get_argument_parser", "main"]

if __name__ == "__main__":
    raise SystemExit(main())
