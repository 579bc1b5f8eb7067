"""Inverse kinematics of any DH table: closed form where a structure fits, else numeric."""

from .analytic.batch import BatchResult, BatchSolver
from .analytic.closed_form import ClosedFormSolver
from .analytic.closed_form_structure import ClosedFormStructure
from .analytic.five_joint.five_dof import FiveDof
from .analytic.planar.offset3r import Offset3R
from .analytic.planar.planar2r import Planar2R
from .analytic.registry import recognise, register
from .analytic.seven_r.seven_dof import SevenDofIK
from .analytic.structure import SevenDof
from .batch_solve import BatchIKResult, solve_batch
from .dispatch import Solver, get_solver, solve_ik
from .exceptions import IKError, StructureError, TargetError
from .numeric.differential_ik import DifferentialIK
from .numeric.newton_raphson import newton_raphson
from .numeric.numeric_target import NumericTarget
from .numeric.solver import NumericIK, solve_numeric
from .partial_pose import PartialPoseIK
from .result import IKResult, IKSolution
from .targets.target import AxisTarget, PitchTarget, PoseTarget, PositionTarget

__all__ = [
    "AxisTarget",
    "BatchIKResult",
    "BatchResult",
    "BatchSolver",
    "ClosedFormSolver",
    "ClosedFormStructure",
    "DifferentialIK",
    "FiveDof",
    "IKError",
    "IKResult",
    "IKSolution",
    "NumericIK",
    "NumericTarget",
    "Offset3R",
    "PartialPoseIK",
    "PitchTarget",
    "Planar2R",
    "PoseTarget",
    "PositionTarget",
    "SevenDof",
    "SevenDofIK",
    "Solver",
    "StructureError",
    "TargetError",
    "get_solver",
    "newton_raphson",
    "recognise",
    "register",
    "solve_batch",
    "solve_ik",
    "solve_numeric",
]
