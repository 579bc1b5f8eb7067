"""Which IK solver ``kin ik`` and ``kin preview --ik`` run: the solver table's ``command`` row.

The choices and options are :data:`kin.ik.solver_table.FRONT_ENDS` ``["command"]``: the robot's
own solver by default (``auto``), ``--solver mink`` the numeric pipeline
(:class:`kin.ik.numeric.solver.NumericIK`), ``--solver nr`` the paper's Newton-Raphson
(position only, no limits), each with ``near_seed`` (a user who gives ``--seed-q`` expects the
answer nearest it). Every choice is seen through one interface: ``name``, ``target_kinds`` and
``solve(target, seed=None, *, timeout=None) -> IKResult``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..ik.numeric.newton_raphson_solver import NewtonRaphsonSolver
from ..ik.result import IKResult
from ..ik.solver_table import bind_timeout, front_end_solver
from ..ik.target import Target
from ..robot_model import RobotModel

__all__ = ["NewtonRaphsonSolver", "choose_solver", "solve_function", "target_kinds"]


def choose_solver(robot: RobotModel, forced: str | None = None) -> object:
    """The solver for ``robot``: ``forced`` (``"mink"`` or ``"nr"``), else the robot's own.

    Raises:
        kin.ik.IKError: ``forced`` is not a choice of the command (the message lists them).
    """
    return front_end_solver(robot, "command", forced)


def target_kinds(solver: object) -> tuple[type, ...] | None:
    """The target classes ``solver`` accepts, or None when it does not say."""
    kinds = getattr(solver, "target_kinds", None)
    return tuple(kinds) if kinds is not None else None


def solve_function(
    solver: object, timeout: float | None
) -> Callable[[Target, np.ndarray | None], IKResult]:
    """``solve(target, seed)`` with the time budget ``timeout`` [s] bound.

    A solver whose ``solve`` takes no ``timeout`` is called without it
    (:func:`kin.ik.solver_table.bind_timeout`).
    """
    return bind_timeout(solver, timeout)
