"""Inverse kinematics: closed form for the small arms, numeric (QP, Newton-Raphson) for 7 DOF."""

from .batch import BatchResult, BatchSolver, dh_forward_kinematics
from .closed_form import ClosedFormSolver
from .differential_ik import DifferentialIK
from .dispatch import NUMERIC_SOLVERS, Solver, get_solver
from .exceptions import IKError, StructureError, TargetError
from .newton_raphson import newton_raphson
from .numeric import NumericIK, solve_numeric
from .numeric_target import NumericTarget
from .result import IKResult, IKSolution
from .seven_dof import SevenDofIK
from .structure import FiveDof, Offset3R, Planar2R, SevenDof, recognise
from .target import PitchTarget, PoseTarget, PositionTarget

__version__ = "0.1.0"

__all__ = [
    "BatchResult",
    "BatchSolver",
    "ClosedFormSolver",
    "DifferentialIK",
    "FiveDof",
    "IKError",
    "IKResult",
    "IKSolution",
    "NUMERIC_SOLVERS",
    "NumericIK",
    "NumericTarget",
    "Offset3R",
    "PitchTarget",
    "Planar2R",
    "PoseTarget",
    "PositionTarget",
    "SevenDof",
    "SevenDofIK",
    "Solver",
    "StructureError",
    "TargetError",
    "dh_forward_kinematics",
    "get_solver",
    "newton_raphson",
    "recognise",
    "solve_numeric",
]
