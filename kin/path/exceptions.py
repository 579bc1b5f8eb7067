"""Exceptions of ``kin.path``: a :class:`kin.KinError` subclass for malformed paths."""

from __future__ import annotations

from ..exceptions import KinError


class PathError(KinError, ValueError):
    """A Cartesian path or its timing is malformed (mixed waypoint kinds, too few steps, bad limits).

    Attributes:
        what: The argument or field at fault (e.g. ``"steps"``, ``"waypoint 2"``, ``"vmax"``).
    """

    def __init__(self, message: str, what: str = ""):
        self.what = what
        super().__init__(message)
