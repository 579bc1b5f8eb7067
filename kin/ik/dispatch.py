"""Which IK solver a robot uses, for any DH table, behind one :class:`Solver` protocol.

:func:`get_solver` reads the solver table (:mod:`kin.ik.solver_table`, choice ``auto``): the
closed form when a registered structure fits the table (:mod:`kin.ik.analytic.registry`, asked
by precedence) gives a :class:`ClosedFormSolver`, which hands the numeric solver the target
kinds its closed form does not take (a position on a five- or six-joint arm). When none fits,
the numeric solver (:class:`NumericIK`), which itself starts with a closed form with a free
joint where the arm has one (seven-joint arms: humanoid7's joint 1, Panda's and xArm7's joint
7). :func:`solve_ik` is the one-call form.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy.typing as npt

from kin import RobotModel

from .exceptions import TargetError
from .result import IKResult
from .solver_table import Solver, choose

if TYPE_CHECKING:
    from ..mimic.arm import MimicArm

__all__ = ["Solver", "get_solver", "solve_ik"]


def get_solver(
    robot: RobotModel | MimicArm, *, near_seed: bool = False, collisions: Any = None
) -> Solver:
    """The solver of ``robot``: the closed form when a registered structure fits, else numeric.

    Never raises for a table: an arm no closed form fits (any number of joints, revolute or
    prismatic) gets the numeric solver. A chain with mimic joints (:func:`kin.load_arm`) gets
    ``kin ik``'s :class:`~kin.mimic.solver.MimicSolver`.

    Args:
        robot: The robot, or a chain with mimic joints.
        near_seed: The numeric solver's :attr:`NumericIK.near_seed`: a seeded answer of the
            free-joint closed form far from the seed is checked against damped Newton from the
            seed (about 1.3 us more per seeded solve; the ``kin`` commands and the paths use it).
        collisions: A :class:`~kin.collision.CollisionChecker` of ``robot``: every answer is
            also judged by it (:class:`~kin.ik.collision.collision_aware.CollisionAwareSolver`: colliding
            ones rejected with their reason, status ``in_collision`` when all collide).

    Raises:
        TargetError: ``collisions`` given for a chain with mimic joints (no collision model).
    """
    if not isinstance(robot, RobotModel):
        return _mimic_solver(robot, collisions)
    return choose(robot, "auto", near_seed=near_seed, collisions=collisions)


def _mimic_solver(arm: MimicArm, collisions: Any) -> Solver:
    """``kin ik``'s solver of a chain with mimic joints (no collision model of it yet)."""
    from ..mimic.solver import MimicSolver

    if collisions is not None:
        raise TargetError(
            f"'{arm.name}' is a chain with mimic joints, which has no collision model yet: "
            "solve it without collisions="
        )
    return MimicSolver(arm)


def solve_ik(
    robot: RobotModel | MimicArm, target: Any, seed: npt.ArrayLike | None = None, **options: Any
) -> IKResult:
    """Solve ``target`` with the robot's own solver (:func:`get_solver`).

    Args:
        robot: The robot, or a chain with mimic joints (:func:`kin.load_arm`).
        target: A :class:`~kin.ik.PositionTarget`, :class:`~kin.ik.PoseTarget` or
            :class:`~kin.ik.PitchTarget` in the world frame.
        seed: Start joint vector [rad] (or [m] for prismatic joints), or None.
        **options: Passed to the solver's ``solve`` (e.g. ``timeout`` [s]); ``collisions``, a
            collision checker, to :func:`get_solver`.

    Raises:
        TargetError: The arm cannot take this kind of target; the message names those it takes.
    """
    collisions = options.pop("collisions", None)
    return get_solver(robot, collisions=collisions).solve(target, seed, **options)
