"""Which IK solver ``kin ik`` and ``kin preview --ik`` run: the commands' front end of the solver table.

The choices (:data:`COMMAND`): the robot's own solver by default (``auto``), ``--solver mink`` the
numeric pipeline (:class:`kin.ik.numeric.solver.NumericIK`), ``--solver nr`` the paper's
Newton-Raphson (position only, no limits), each with ``near_seed`` (a user who gives
``--seed-q`` expects the answer nearest it). These names are the command line's; the rows they
try are the library's table (:data:`kin.ik.solver_table.SOLVERS`), which also applies the
collision wrapper (``--scene``/``--srdf``). Every choice is seen through one interface
(:class:`kin.ik.solver.IKSolver`): ``name``, ``target_kinds``, ``solve(target, seed=None, *,
timeout=None, all_branches=False) -> IKResult`` and ``batch_route()``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..ik.numeric.newton_raphson_solver import NewtonRaphsonSolver
from ..ik.result import IKResult
from ..ik.solver import IKSolver
from ..ik.solver_table import CHOICES, FrontEnd, bind_timeout, front_end_solver
from ..ik.targets.target import Target
from ..robot_model import RobotModel

__all__ = [
    "COMMAND",
    "NewtonRaphsonSolver",
    "checks_own_kinds",
    "choose_solver",
    "solve_function",
    "target_kinds",
]

#: ``kin ik --solver`` and ``kin preview --ik``: the names the command line offers (default
#: first) and the library's rows each tries.
COMMAND = FrontEnd(
    "command",
    {"auto": CHOICES["auto"], "mink": CHOICES["numeric"], "nr": CHOICES["nr"]},
    near_seed=True,
)

#: Choices whose solver names the target kinds it refuses itself, in the command line's words
#: (``nr``: "drop --rpy/--quat/--pitch"), so the command does not check them first.
_OWN_KIND_CHECK = frozenset({"nr"})


def choose_solver(
    robot: RobotModel, forced: str | None = None, *, collisions: Any = None, every: bool = False
) -> IKSolver:
    """The solver for ``robot``: ``forced`` (``"mink"`` or ``"nr"``), else the robot's own.

    Args:
        robot: The robot.
        forced: ``--solver``'s value, or None.
        collisions: The collision checker of ``--scene``/``--srdf``, or None.
        every: With ``collisions``: every answer judged (the counts of free and rejected ones
            do not depend on ``--all``).

    Raises:
        kin.ik.IKError: ``forced`` is not a choice of the command (the message lists them).
    """
    return front_end_solver(robot, COMMAND, forced, collisions=collisions, every=every)


def checks_own_kinds(forced: str | None) -> bool:
    """Whether the solver ``--solver forced`` refuses other target kinds in its own words."""
    return forced in _OWN_KIND_CHECK


def target_kinds(solver: IKSolver) -> tuple[type, ...]:
    """The target classes ``solver`` accepts."""
    return tuple(solver.target_kinds)


def solve_function(
    solver: IKSolver, timeout: float | None, *, all_branches: bool = False
) -> Callable[[Target, np.ndarray | None], IKResult]:
    """``solve(target, seed)`` with the time budget ``timeout`` [s] (and ``all_branches``) bound."""
    return bind_timeout(solver, timeout, all_branches=all_branches)
