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
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ik.exceptions import TargetError
from ..ik.numeric.newton_raphson_solver import NewtonRaphsonSolver
from ..ik.result import IKResult
from ..ik.solver import IKSolver
from ..ik.solver_table import CHOICES, FrontEnd, bind_timeout, front_end_solver
from ..ik.targets.target import Target
from ..robot_model import RobotModel

if TYPE_CHECKING:
    from ..mimic.arm import MimicArm
    from ..mimic.solver import MimicSolver

__all__ = [
    "COMMAND",
    "CommandSolver",
    "NewtonRaphsonSolver",
    "checks_own_kinds",
    "choose_solver",
    "command_solver",
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


#: ``solve(target, seed)`` with the options of the command bound.
Solve = Callable[[Target, np.ndarray | None], IKResult]


@dataclass(frozen=True)
class CommandSolver:
    """The solver ``kin ik`` runs, with its time budget bound: what the command asks of it.

    Attributes:
        solver: The solver.
        solve: ``solve(target, seed)``: every branch with ``--all``, else the answer.
        solve_all: ``solve(target, seed)`` of every branch (the stream's ``"all"`` lines).
        kinds: The target classes it takes, or None when it refuses other kinds in its own
            words (:func:`checks_own_kinds`).
    """

    solver: IKSolver
    solve: Solve
    solve_all: Solve
    kinds: tuple[type, ...] | None


def command_solver(
    robot: RobotModel | MimicArm,
    forced: str | None,
    *,
    collisions: Any = None,
    collision_files: str | None = None,
    timeout: float | None = None,
    all_branches: bool = False,
) -> CommandSolver:
    """The solver of ``kin ik``: :func:`choose_solver`'s, or a mimic chain's own, bound.

    Args:
        robot: The robot, or a URDF chain with mimic joints (:func:`kin.load_arm`).
        forced: ``--solver``'s value, or None.
        collisions: The collision checker of ``--scene``/``--srdf`` (a robot's), or None.
        collision_files: ``--scene`` or ``--srdf`` as given (refused for a mimic chain), or None.
        timeout: The time budget of one solve [s], or None.
        all_branches: ``--all``: :attr:`CommandSolver.solve` answers every branch.

    Raises:
        TargetError: ``--solver`` or ``--scene``/``--srdf`` given for a chain with mimic joints.
        kin.ik.IKError: ``forced`` is not a choice of the command (the message lists them).
    """
    solver: IKSolver
    if not isinstance(robot, RobotModel):  # a chain with mimic joints
        solver = _mimic_solver(robot, forced, collision_files)
    else:  # every answer judged: the counts of free and rejected ones do not depend on --all
        solver = front_end_solver(robot, COMMAND, forced, collisions=collisions, every=True)
    solve_all = bind_timeout(solver, timeout, all_branches=True)
    solve = solve_all if all_branches else bind_timeout(solver, timeout)
    kinds = None if checks_own_kinds(forced) else target_kinds(solver)
    return CommandSolver(solver, solve, solve_all, kinds)


def _mimic_solver(arm: MimicArm, forced: str | None, collisions: str | None) -> MimicSolver:
    """The solver of a URDF chain with mimic joints; ``--solver`` cannot choose another.

    Raises:
        TargetError: ``--solver`` given (mink and nr read one joint per DH row), or
            ``--scene``/``--srdf`` (``collisions``: no collision model of such a chain yet).
    """
    if collisions is not None:
        raise TargetError(
            f"--scene/--srdf: '{arm.name}' is a chain with mimic joints, which has no collision "
            "model yet; drop --scene and --srdf"
        )
    if forced is not None:
        raise TargetError(
            f"--solver {forced}: '{arm.name}' is a chain with mimic joints, solved by damped "
            "least squares over its independent joints; drop --solver"
        )
    from ..mimic.solver import MimicSolver  # only a mimic chain needs it

    return MimicSolver(arm)
