"""The goal configurations of a plan: a joint vector, or every collision-free IK answer of a target.

A target (pose, position, axis, masked pose) becomes every answer the collision-aware IK gives
with ``all_branches=True`` (:class:`kin.ik.collision.collision_aware.CollisionAwareSolver`: the closed
forms' every branch, a 7R arm's free-joint grid, the numeric solver's answers), each one free and
within the limits, so a pose goal never fails for want of goal samples. A revolute joint whose
range spans more than a turn gets each answer's value moved by whole turns to the one nearest the
start within its limits (the same place of the arm, a shorter motion); both are offered when
they differ.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..configuration import as_joint_vector, limit_violations

if TYPE_CHECKING:  # pragma: no cover
    from ..collision import CollisionChecker

__all__ = ["GoalSet", "goal_configurations", "joint_goal"]


class GoalSet:
    """Goal configurations, or why there are none.

    Attributes:
        q: Goal joint vectors, shape (G, nq) [rad] / [m] (G = 0 when none).
        status: ``"ok"``, or the plan status when there is no goal (``"goal_in_collision"``,
            ``"out_of_reach"``, ``"timeout"``, ``"not_found"``).
        message: One sentence for a person ("" when ``ok``).
    """

    def __init__(self, q: np.ndarray, status: str = "ok", message: str = ""):
        self.q = q
        self.status = status
        self.message = message


def joint_goal(robot: Any, goal: Any, checker: CollisionChecker) -> GoalSet:
    """A joint vector as the goal: checked for size, limits and collisions.

    Raises:
        kin.JointVectorError: Wrong size or a non-finite value.
        kin.NotWithinLimitsError: Outside the joint limits (the first joint out).
    """
    from ..ik.collision.collision_aware import collision_reason

    q = as_joint_vector(robot, goal)
    outside = limit_violations(robot, q)
    if outside:
        raise outside[0]
    if checker.in_collision(q):
        reason = collision_reason(checker, q)
        return GoalSet(
            np.zeros((0, robot.nq)), "goal_in_collision", f"the goal is in collision ({reason})"
        )
    return GoalSet(q[None, :])


def goal_configurations(
    robot: Any, target: Any, start: np.ndarray, checker: CollisionChecker, timeout: float
) -> GoalSet:
    """Every collision-free IK answer of ``target`` (and its nearer whole-turn twins).

    Args:
        robot: The robot.
        target: A :mod:`kin.ik` target in the world frame.
        start: The plan's start [rad] / [m] (the IK seed; twins are moved towards it).
        checker: The collision checker every answer must pass.
        timeout: Cap of the IK search [s].
    """
    from ..ik import get_solver
    from ..ik.collision.collision_aware import CollisionAwareSolver

    solver = CollisionAwareSolver(get_solver(robot), checker, every=True)
    result = solver.solve(target, start, timeout=timeout)
    if not result.solutions:
        status = {"in_collision": "goal_in_collision", "out_of_reach": "out_of_reach"}.get(
            result.status, "timeout" if result.status == "timeout" else "not_found"
        )
        return GoalSet(np.zeros((0, robot.nq)), status, f"the target: {result.message}")
    goals: list[np.ndarray] = []
    for solution in result.solutions:  # free; a twin is the same place of the arm, so free too
        for q in (solution.q, _nearest_turn(robot, solution.q, start)):
            if not any(np.array_equal(q, known) for known in goals):
                goals.append(np.asarray(q, dtype=float))
    return GoalSet(np.array(goals))


def _nearest_turn(robot: Any, q: np.ndarray, start: np.ndarray) -> np.ndarray:
    """``q`` with each revolute joint at its copy nearest ``start`` within the limits.

    The IK's limit rule (:func:`kin.ik.limit_rule.nearest_inside`); a joint with no copy inside
    stays where it was.
    """
    from ..ik.limit_rule import nearest_inside

    moved = np.array(q, dtype=float)
    for i, row in enumerate(robot.table.rows):
        if row.joint_type == "revolute":
            copy = nearest_inside(moved[i], start[i], float(robot.lower[i]), float(robot.upper[i]))
            moved[i] = moved[i] if copy is None else copy
    return moved
