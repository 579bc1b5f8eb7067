"""Exceptions of ``kin.ik``: one base class (a :class:`kin.KinError`), specific subclasses."""

from __future__ import annotations

from ..exceptions import KinError


class IKError(KinError):
    """Base class of every error raised by ``kin.ik``."""


class StructureError(IKError, ValueError):
    """A robot's DH table does not have the structure a closed-form solver needs.

    Attributes:
        robot: Robot name.
        solver: Solver name.
        mismatch: What does not fit (row, parameter, expected and actual value).
    """

    def __init__(self, robot: str, solver: str, mismatch: str):
        self.robot = robot
        self.solver = solver
        self.mismatch = mismatch
        super().__init__(f"'{robot}' does not fit the {solver} solver: {mismatch}")


class TargetError(IKError, ValueError):
    """A target is malformed (wrong size, wrong kind for the solver)."""
