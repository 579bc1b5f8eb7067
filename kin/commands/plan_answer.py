"""What ``kin plan`` and each ``kin plan --stdin`` line share: the inputs checked, the answer.

:func:`joints_within_limits` reads a start or goal in the command's units, :func:`plan_checker`
builds the collision model once (the arm alone without a file), :func:`timed_plan` times a path
(toppra) and :func:`plan_record` makes the JSON answer (SI).
"""

from __future__ import annotations

import argparse
from typing import Any

from .collision_options import collision_checker

__all__ = ["joints_within_limits", "plan_checker", "plan_record", "timed_plan"]


def joints_within_limits(robot: Any, units: Any, values: Any, name: str, srdf: Any = None) -> Any:
    """Joint values in the command's units, or a named state, in SI [rad, m], within limits.

    Args:
        robot: The robot.
        units: The command's joint units.
        values: One value per joint, or one name of the robot's named states (its table's
            ``[states]``, ``srdf``'s group states: :mod:`kin.commands.named_states`).
        name: The option or key, for messages.
        srdf: The command's ``--srdf`` file, or None.

    Raises:
        kin.JointVectorError: Not one finite value per joint (the message names ``name``).
        kin.NamedStateError: An unknown state name (the message lists the names there are).
        kin.plan.PlanError: A value outside its joint's limits (named with ``name``).
    """
    from ..configuration import limit_violations
    from ..plan import PlanError
    from .named_states import joint_vector

    q = joint_vector(robot, list(values), units, name, srdf)
    assert q is not None  # values were given
    outside = limit_violations(robot, q)
    if outside:
        raise PlanError(f"{name}: {outside[0]}")
    return q


def plan_checker(robot: Any, args: argparse.Namespace, length: float) -> Any:
    """The collision checker of --scene/--srdf/--padding/--hold; the arm alone without files.

    Built here also without a file, so that --padding and --hold hold for the arm's own pairs
    (and a stream builds it once).

    Args:
        robot: The robot.
        args: Options with ``scene``, ``srdf``, ``padding`` [``length``] and ``hold``.
        length: Meters per unit of ``--padding``.

    Raises:
        kin.exceptions.CollisionModelError: A file cannot be read or does not fit the robot.
    """
    checker = collision_checker(args, robot, length)
    if checker is not None:
        return checker
    from ..collision import CollisionChecker, load_collision_model
    from .collision_options import held_joints

    padding = 0.0 if args.padding is None else args.padding * length
    return CollisionChecker(load_collision_model(robot, padding=padding, hold=held_joints(args)))


def timed_plan(robot: Any, result: Any) -> Any:
    """The path of ``result`` timed by toppra within the table's velocity and acceleration limits."""
    from ..path import table_limits, time_optimal

    vmax, amax = table_limits(robot.table)
    return time_optimal(result.path, vmax, amax)


def plan_record(robot: Any, units: Any, result: Any, timed: Any) -> dict[str, Any]:
    """The JSON answer (``--json``, a ``--stdin`` line's), SI.

    Args:
        robot: The robot.
        units: Its joint units (the names and SI labels are used).
        result: The :class:`kin.plan.PlanResult`.
        timed: :func:`timed_plan` of its path, or None.
    """
    record: dict[str, Any] = {
        "robot": robot.name,
        "status": result.status,
        "message": result.message,
        "planner": result.planner,
        "seed": result.seed,
        "plan_time": result.plan_time,
        "checks": result.checks,
        "joint_names": list(units.joint_names),
        "q_units": list(units.si_labels),
        "length": result.length,
        "straight_length": result.straight_length,
        "clearance_m": result.clearance,
        "goal_index": result.goal_index,
        "goals": result.goals.tolist(),
        "path": result.path.tolist(),
        "q": result.path.tolist(),
    }
    if timed is not None:
        record["duration_s"] = timed.duration
        record["t"] = timed.waypoint_times.tolist()
        record["t_s"] = record["t"]
        record["qd"] = timed.waypoint_qd.tolist()
        record["qd_units"] = [f"{u}/s" for u in units.si_labels]
    return record
