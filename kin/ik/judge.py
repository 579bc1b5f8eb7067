"""The judge of every IK solver: the tool's pose error at a joint vector, and the joint limits.

Frames: targets are ``T_world_tool`` (position [m] in the world frame, the tool axes' rotation
``R_world_tool`` in the world frame). The scalar judge (:class:`ToolJudge`, :func:`measure`) runs
Pinocchio's forward kinematics of the robot's model (:class:`kin.RobotModel`); the batched twin
(:func:`batch_pose_errors`) measures poses from :func:`kin.batch_forward_kinematics`, with the
same formulas:

- position error: ``|p_fk - p_target|`` [m];
- rotation error: the angle of ``R_fk^T R_target`` [rad], from
  ``|R_fk - R_target|_F = 2 sqrt(2) sin(angle / 2)`` (accurate for small angles, no ``log3``);
- axis error (a pitch target): the angle between the tool's approach axis and the target's [rad];
- limits: ``lower <= q <= upper``, no tolerance.

A numeric solution succeeds when both errors are below :data:`POSITION_TOLERANCE` and
:data:`ROTATION_TOLERANCE` and it is inside the limits; the closed forms drop branches above
their own (tighter) tolerances.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Sequence
from dataclasses import dataclass
from operator import le
from typing import Protocol

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import RobotModel

#: Default tolerances of a numeric solution, measured by the judge.
POSITION_TOLERANCE = 1e-5  # [m]
ROTATION_TOLERANCE = 1e-4  # [rad]

_SQRT8 = math.sqrt(8.0)


class ToolTarget(Protocol):
    """What :func:`measure` reads of a target: ``position`` [m] (3,), ``rotation`` (3, 3) or None."""

    @property
    def position(self) -> np.ndarray: ...  # noqa: D102

    @property
    def rotation(self) -> np.ndarray | None: ...  # noqa: D102


@dataclass(frozen=True)
class Measurement:
    """The judge's measurement of a joint vector against a target.

    Attributes:
        position_error: ``|p_fk - p_target|`` [m].
        rotation_error: Angle of ``R_fk^T R_target`` [rad]; 0 for position-only targets.
        within_limits: Whether ``q`` is inside the joint limits (no tolerance).
    """

    position_error: float
    rotation_error: float
    within_limits: bool

    def on_target(
        self, position_tol: float = POSITION_TOLERANCE, rotation_tol: float = ROTATION_TOLERANCE
    ) -> bool:
        """Whether both errors are below the tolerances ([m], [rad])."""
        return self.position_error < position_tol and self.rotation_error < rotation_tol


def rotation_error(r_fk: Sequence[float], r_target: Sequence[float]) -> float:
    """Angle of ``R_fk^T R_target`` [rad] from two rotations given row-major (9 values each)."""
    return 2.0 * math.asin(min(1.0, math.dist(r_fk, r_target) / _SQRT8))


def rotation_angles(r_fk: npt.ArrayLike, r_target: npt.ArrayLike) -> np.ndarray:
    """:func:`rotation_error` of rotations (..., 3, 3): angles of ``R_fk^T R_target`` [rad]."""
    difference = np.asarray(r_fk, dtype=float) - np.asarray(r_target, dtype=float)
    distance = np.sqrt((difference**2).sum((-2, -1)))
    return np.asarray(2.0 * np.arcsin(np.minimum(1.0, distance / _SQRT8)))


def axis_error(u: Sequence[float], a: Sequence[float]) -> float:
    """Angle between the vectors ``u`` and ``a`` (3 each) [rad], in ``[0, pi]``."""
    ux, uy, uz = u
    ax, ay, az = a
    cx, cy, cz = uy * az - uz * ay, uz * ax - ux * az, ux * ay - uy * ax
    return math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), ux * ax + uy * ay + uz * az)


class ToolJudge:
    """Pinocchio's forward kinematics of one robot's tool frame, and its joint limits.

    Args:
        robot: The robot (its Pinocchio model and tool frame).
        data: A Pinocchio data of ``robot.model`` to work in (overwritten), or None: its own.
    """

    def __init__(self, robot: RobotModel, data: pin.Data | None = None):
        self.robot = robot
        self.model = robot.model
        self.data = robot.model.createData() if data is None else data
        self.frame_id = _tool_frame_id(robot)
        self._lows = robot.model.lowerPositionLimit.tolist()
        self._highs = robot.model.upperPositionLimit.tolist()

    def tool_pose(self, q: np.ndarray) -> pin.SE3:
        """``T_world_tool`` at ``q`` [rad] (a reference into the judge's data: copy to keep)."""
        pin.forwardKinematics(self.model, self.data, q)
        return pin.updateFramePlacement(self.model, self.data, self.frame_id)

    def tool(self, q: np.ndarray) -> tuple[list[float], list[float]]:
        """The tool position [m] and ``R_world_tool`` row-major (9 values) at ``q`` [rad]."""
        (r0, r1, r2, x), (r3, r4, r5, y), (r6, r7, r8, z), _ = self.tool_pose(
            q
        ).homogeneous.tolist()
        return [x, y, z], [r0, r1, r2, r3, r4, r5, r6, r7, r8]

    def tool_position(self, q: np.ndarray) -> list[float]:
        """The tool position [m] in the world frame at ``q`` [rad]."""
        pin.forwardKinematics(self.model, self.data, q)
        return pin.updateFramePlacement(self.model, self.data, self.frame_id).translation.tolist()

    def errors(
        self, q: np.ndarray, position: Sequence[float], rotation: Sequence[float] | None
    ) -> tuple[float, float | None]:
        """Position error [m] and rotation error [rad] (None without a rotation) at ``q``.

        Args:
            q: Joint vector [rad].
            position: Target tool position in the world frame [m] (3).
            rotation: Target ``R_world_tool`` row-major (9), or None for a position target.
        """
        if rotation is None:  # the translation alone: no 4x4 matrix
            return math.dist(self.tool_position(q), position), None
        p_fk, r_fk = self.tool(q)
        return math.dist(p_fk, position), rotation_error(r_fk, rotation)

    def within_limits(self, q: Sequence[float]) -> bool:
        """Whether ``lower <= q <= upper`` joint by joint (no tolerance)."""
        return all(map(le, self._lows, q)) and all(map(le, q, self._highs))

    def measure(self, q: np.ndarray, target: ToolTarget) -> Measurement:
        """The errors of ``q`` against ``target`` (rotation error 0 without a rotation) and its limits."""
        rotation = None if target.rotation is None else target.rotation.ravel().tolist()
        position_error, angle = self.errors(q, target.position.tolist(), rotation)
        return Measurement(position_error, angle or 0.0, self.within_limits(q.tolist()))


def measure(robot: RobotModel, data: pin.Data, q: np.ndarray, target: ToolTarget) -> Measurement:
    """:meth:`ToolJudge.measure` with a Pinocchio data of the caller's (overwritten).

    Args:
        robot: The robot (its Pinocchio model is the judge).
        data: A Pinocchio data of ``robot.model`` (overwritten).
        q: Joint vector [rad].
        target: The target (``position`` [m], ``rotation`` or None).
    """
    return ToolJudge(robot, data).measure(np.asarray(q, dtype=float), target)


def batch_pose_errors(
    poses: np.ndarray, positions: np.ndarray, rotations: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray | None]:
    """The batched twin of :meth:`ToolJudge.errors`: M tool poses against M targets.

    Args:
        poses: ``T_world_tool`` (M, 4, 4) of the joint vectors (:func:`kin.batch_forward_kinematics`).
        positions: Target positions (M, 3) [m].
        rotations: Target rotations ``R_world_tool`` (M, 3, 3), or None.

    Returns:
        Position errors (M,) [m] and rotation errors (M,) [rad] (None without rotations).
    """
    position_error = np.sqrt(((poses[:, :3, 3] - positions) ** 2).sum(-1))
    if rotations is None:
        return position_error, None
    return position_error, rotation_angles(poses[:, :3, :3], rotations)


def batch_axis_errors(axes: np.ndarray, target_axes: np.ndarray) -> np.ndarray:
    """The batched twin of :func:`axis_error`: angles between M pairs of vectors (M, 3) [rad]."""
    cross = np.sqrt((np.cross(axes, target_axes) ** 2).sum(-1))
    return np.arctan2(cross, (axes * target_axes).sum(-1))


def _tool_frame_id(robot: RobotModel) -> int:
    fid = _FRAME_IDS.get(robot)
    if fid is None:
        fid = _FRAME_IDS[robot] = robot.model.getFrameId(robot.tool_frame)
    return fid


_FRAME_IDS: weakref.WeakKeyDictionary[RobotModel, int] = weakref.WeakKeyDictionary()
