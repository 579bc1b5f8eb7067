"""Exceptions of the ``ik`` package: one base class, specific subclasses carrying data."""

from __future__ import annotations


class IKError(Exception):
    """Base class of every error raised by ``ik``."""


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
