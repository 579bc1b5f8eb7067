"""Which IK solver ``kin ik`` runs: the robot's own (``kin.ik.get_solver``) or a forced one.

``--solver mink`` forces the numeric pipeline (:class:`kin.ik.numeric.solver.NumericIK`),
``--solver nr`` the paper's Newton-Raphson (position only, no limits). Every choice is seen
through one interface: ``name``, ``target_kinds`` and
``solve(target, seed=None, *, timeout=None) -> IKResult``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable

import numpy as np

from ..ik.exceptions import TargetError
from ..ik.result import IKResult
from ..ik.target import PositionTarget, Target
from ..robot_model import RobotModel


class NewtonRaphsonSolver:
    """The paper's Newton-Raphson IK behind the common solver interface.

    Args:
        robot: The robot.
    """

    name = "nr"
    target_kinds: tuple[type, ...] = (PositionTarget,)

    def __init__(self, robot: RobotModel):
        self.robot = robot

    def solve(
        self, target: Target, seed: np.ndarray | None = None, *, timeout: float | None = None
    ) -> IKResult:
        """Solve a position target from ``seed`` [rad] (q = 0 if None); ``timeout`` is unused.

        Raises:
            TargetError: Not a position target.
        """
        from ..ik.numeric.newton_raphson import newton_raphson

        if not isinstance(target, PositionTarget):
            raise TargetError(
                "--solver nr is the paper's position-only method: drop --rpy/--quat/--pitch"
            )
        return newton_raphson(self.robot, target.position, seed)


def choose_solver(robot: RobotModel, forced: str | None = None) -> object:
    """The solver for ``robot``: ``forced`` (``"mink"`` or ``"nr"``), else the robot's own.

    Raises:
        kin.ik.StructureError: No solver fits the robot.
    """
    if forced == "nr":
        return NewtonRaphsonSolver(robot)
    # A user who gives --seed-q expects the answer nearest it (NumericIK.near_seed).
    if forced == "mink":
        from ..ik.numeric.solver import NumericIK

        return NumericIK(robot, near_seed=True)
    from ..ik import get_solver

    return get_solver(robot, near_seed=True)


def target_kinds(solver: object) -> tuple[type, ...] | None:
    """The target classes ``solver`` accepts, or None when it does not say."""
    kinds = getattr(solver, "target_kinds", None)
    return tuple(kinds) if kinds is not None else None


def solve_function(
    solver: object, timeout: float | None
) -> Callable[[Target, np.ndarray | None], IKResult]:
    """``solve(target, seed)`` with the time budget ``timeout`` [s] bound.

    A solver whose ``solve`` takes no ``timeout`` (a closed form, which needs none) is called
    without it.
    """
    solve = solver.solve  # type: ignore[attr-defined]
    try:
        takes_timeout = "timeout" in inspect.signature(solve).parameters
    except (TypeError, ValueError):  # a compiled solve: assume the common interface
        takes_timeout = True
    if takes_timeout:
        return lambda target, seed: solve(target, seed, timeout=timeout)
    return lambda target, seed: solve(target, seed)
