"""The goal configurations of a plan: a joint vector, or every collision-free IK answer of a target.

A target (pose, position, axis, masked pose) becomes every answer the collision-aware IK gives
with ``all_branches=True`` (:class:`kin.ik.collision.collision_aware.CollisionAwareSolver`: the closed
forms' every branch, a 7R arm's free-joint grid, the numeric solver's answers), each one free and
within the limits, so a pose goal never fails for want of goal samples. A revolute joint whose
range spans more than a turn gets each answer's value moved by whole turns to the one nearest the
start within its limits (the same place of the arm, a shorter motion); both are offered when
they differ.

A joint vector is the goal as given; with ``any_turn`` its whole-turn copies are goals too: the
combinations of ``q_j + 2 pi k`` within the limits on its revolute joints (per joint ``q_j`` and
its two copies nearest the start's value; the same place of the arm, so as free as ``q``), the
:data:`MOST_TURNS` nearest the start. The path then ends at the
copy it reaches (``PlanResult.goal_index``), which may be a turn away from the values given.
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING, Any

import numpy as np

from ..configuration import as_joint_vector, limit_violations

if TYPE_CHECKING:  # pragma: no cover
    from ..collision import CollisionChecker

__all__ = ["MOST_TURNS", "GoalSet", "goal_configurations", "joint_goal"]

#: Most whole-turn copies of a joint goal offered with ``any_turn`` (the nearest the start).
MOST_TURNS = 64


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


def joint_goal(
    robot: Any,
    goal: Any,
    checker: CollisionChecker,
    start: np.ndarray | None = None,
    any_turn: bool = False,
) -> GoalSet:
    """A joint vector as the goal: checked for size, limits and collisions.

    Args:
        robot: The robot.
        goal: The goal joint vector [rad] / [m].
        checker: The collision checker the goal must pass.
        start: The plan's start [rad] / [m] (with ``any_turn``: the copies nearest it are kept).
        any_turn: Offer the goal's whole-turn copies within the limits too (the module).

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
    if not any_turn:
        return GoalSet(q[None, :])
    return GoalSet(_turns(robot, q, q if start is None else start))


def _turns(robot: Any, q: np.ndarray, start: np.ndarray) -> np.ndarray:
    """``q`` and its whole-turn copies within the limits, nearest ``start`` first.

    At most :data:`MOST_TURNS` of them, ``q`` always among them.
    """
    from ..ik.limit_rule import turn_copies

    values = [  # per joint, the value and its two copies nearest the start (5 joints: 243)
        turn_copies(float(v), float(lo), float(hi), float(s))
        if row.joint_type == "revolute"
        else [float(v)]
        for v, lo, hi, s, row in zip(q, robot.lower, robot.upper, start, robot.table.rows)
    ]
    copies = np.array(list(itertools.product(*values)), dtype=float)
    order = np.argsort(np.linalg.norm(copies - start, axis=1), kind="stable")
    kept = copies[order[:MOST_TURNS]]
    if not (kept == q).all(axis=1).any():
        kept = np.vstack([q[None, :], kept[: MOST_TURNS - 1]])
    return kept


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
    from ..ik.solver_table import choose

    # get_solver's choice, wrapped by the table's one wrapper (every free answer kept)
    solver = choose(robot, "auto", collisions=checker, every=True)
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
