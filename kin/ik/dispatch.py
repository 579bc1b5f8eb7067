"""Which IK solver a robot uses: one small mapping, shared by the scripts.

Robots listed in :data:`NUMERIC_SOLVERS` (the redundant ``humanoid7``) use the numeric solver
registered there; every other robot gets a :class:`ClosedFormSolver`
if its DH table fits one of the closed-form structures, else a :class:`StructureError`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy.typing as npt

from kin import RobotModel

from .analytic.closed_form import ClosedFormSolver
from .numeric.solver import NumericIK
from .result import IKResult


class Solver(Protocol):
    """What the scripts need from a solver."""

    name: str
    target_kinds: tuple[type, ...]

    def solve(self, target: object, seed: npt.ArrayLike | None = None) -> IKResult:
        """Solve one target from a seed."""
        ...


#: Robot name -> factory of its numeric solver (sorted by name).
NUMERIC_SOLVERS: dict[str, Callable[[RobotModel], Solver]] = {"humanoid7": NumericIK}


def get_solver(robot: RobotModel) -> Solver:
    """The solver of ``robot``: its registered numeric solver, else the closed-form one.

    Raises:
        StructureError: No numeric solver is registered and the table fits no closed form.
    """
    factory = NUMERIC_SOLVERS.get(robot.name)
    if factory is not None:
        return factory(robot)
    return ClosedFormSolver(robot)
