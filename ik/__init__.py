"""Inverse kinematics: closed form for the small arms, numeric (QP, Newton-Raphson) for 7 DOF."""

from .exceptions import IKError, StructureError, TargetError
from .result import IKResult, IKSolution

__version__ = "0.1.0"

__all__ = ["IKError", "IKResult", "IKSolution", "StructureError", "TargetError"]
