"""Errors of the DH table audit: bad sample files and reference URDFs, as one project exception."""

from __future__ import annotations

from ..exceptions import KinError


class AuditError(KinError, ValueError):
    """A sample file, reference URDF or audit request cannot be used.

    Attributes:
        path: File the problem was found in (samples CSV, URDF or table), or None.
        line: 1-based line of the sample file, or None.
    """

    def __init__(self, message: str, path: str | None = None, line: int | None = None):
        self.path = path
        self.line = line
        where = path or ""
        if line is not None:
            where += f" line {line}"
        super().__init__(f"{where}: {message}" if where else message)
