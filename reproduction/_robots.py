"""Robots for the reproduction: shipped ones, and variants of their tables built in memory.

Every position of the report goes through Pinocchio (``kin``): a variant table (another length,
another sign, the other DH convention) is turned into a URDF by ``dh2urdf`` and loaded like a
shipped robot, never evaluated by a hand-written formula.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import pinocchio as pin

from dh2urdf import DHTable
from kin.configuration import Configuration
from kin.robot_model import RobotModel, robot_from_table


def variant(
    table: DHTable, name: str, convention: str | None = None, **rows: dict[str, Any]
) -> RobotModel:
    """A robot from ``table`` with some row fields replaced (SI units).

    Args:
        table: The table to start from.
        name: Name of the variant (for messages).
        convention: ``"standard"`` or ``"modified"`` to change the convention, or None.
        rows: ``row<i>={field: value}`` for the 1-based row ``i``, e.g. ``row3={"d": 0.287}``.
    """
    new_rows = list(table.rows)
    for key, changes in rows.items():
        index = int(key.removeprefix("row")) - 1
        new_rows[index] = dataclasses.replace(new_rows[index], **changes)
    changed = dataclasses.replace(table, name=name, rows=tuple(new_rows))
    if convention is not None:
        changed = dataclasses.replace(changed, convention=convention)
    return robot_from_table(changed)


def tool_pose_deg(robot: RobotModel, q_deg: Sequence[float]) -> pin.SE3:
    """Pose ``T_world_tool`` [m] at joint values given in degrees (all joints revolute)."""
    q = np.array([math.radians(v) for v in q_deg])
    return Configuration(robot, q).transform_frame_to_world(robot.tool_frame)


def tool_position_deg(robot: RobotModel, q_deg: Sequence[float], unit: float) -> np.ndarray:
    """Tool position in ``unit`` (meters per unit, e.g. 0.01 for cm) at ``q_deg`` [deg]."""
    return tool_pose_deg(robot, q_deg).translation / unit


def dh_angles_to_q(robot: RobotModel, dh_angles_deg: Sequence[float]) -> list[float]:
    """Joint values [deg] giving the DH angles ``dh_angles_deg`` [deg]: ``q = angle - offset``."""
    return [
        a - math.degrees(row.theta) for a, row in zip(dh_angles_deg, robot.table.rows, strict=True)
    ]
