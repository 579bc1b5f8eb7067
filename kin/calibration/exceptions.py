"""Errors of kinematic calibration: bad measurement files and requests, one project exception."""

from __future__ import annotations

from dh2urdf.quoted_input import quoted

from ..exceptions import KinError


class CalibrationError(KinError, ValueError):
    """A measurement file, robot or calibration request cannot be used.

    Attributes:
        path: File the problem was found in (measurements, output), or None.
        row: 1-based line of the measurement file, or None.
        column: Column name of the measurement file, or None.
    """

    def __init__(
        self,
        message: str,
        path: str | None = None,
        row: int | None = None,
        column: str | None = None,
    ):
        self.path = path
        self.row = row
        self.column = column
        where = path or ""
        if row is not None:
            where += f" line {row}"
        if column is not None:  # a header cell of the user's file: quoted short
            where += f" column {quoted(column)}"
        super().__init__(f"{where.strip()}: {message}" if where else message)
