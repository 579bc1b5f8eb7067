"""The outcome of following a Cartesian path, and its measurement by forward kinematics.

The deviation is measured, not assumed: the tool point at each joint sample is compared with its
Cartesian sample, and the tool point at ``between`` points of the straight joint-space segment
between consecutive samples with the Cartesian segment between their targets (world frame, [m]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from ..batch_fk import batch_forward_kinematics
from ..robot_model import RobotModel
from .cartesian import CartesianPath, segment_distance


@dataclass(frozen=True, eq=False)
class PathResult:
    """A joint path that follows a Cartesian path, as far as it could.

    Attributes:
        success: Every sample was reached (``stopped_at`` is None).
        q: Joint path, shape (M, nq) [rad] / [m]; the samples reached, so M is ``stopped_at``
            when the motion stopped.
        path: The Cartesian path that was followed.
        method: ``"closed_form"`` (one branch, chosen per sample), ``"partial"`` (partial poses
            on an arm without a closed form: each sample solved from the previous one) or
            ``"differential"``
            (velocity-limited QP steps, :class:`kin.ik.DifferentialIK`).
        branches: Branch label of each reached sample (``""`` for the differential method).
        branch_changes: Sample indices where the branch label changed (with a small joint step).
        stopped_at: Index of the first sample that could not be reached, or None.
        message: Why the motion stopped, or ``""``.
        max_deviation: Largest distance of the tool point from the Cartesian path, at the
            samples and between them [m].
        max_rotation_error: Largest tool rotation error at the samples of a pose path [rad],
            else None.
        max_joint_step: Largest change of one joint between consecutive samples [rad] / [m].
        max_step_joint: Index of the joint of ``max_joint_step`` (-1 for fewer than 2 samples).
    """

    success: bool
    q: np.ndarray
    path: CartesianPath
    method: str
    branches: tuple[str, ...]
    branch_changes: tuple[int, ...]
    stopped_at: int | None
    message: str
    max_deviation: float
    max_rotation_error: float | None
    max_joint_step: float
    max_step_joint: int

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict, SI: ``q`` in rad (revolute) / m (prismatic), deviations in m, rad."""
        return {
            "success": self.success,
            "method": self.method,
            "samples": len(self.path),
            "q": self.q.tolist(),
            "branches": list(self.branches),
            "branch_changes": list(self.branch_changes),
            "stopped_at": self.stopped_at,
            "message": self.message,
            "max_deviation_m": _json_float(self.max_deviation),
            "max_rotation_error_rad": (
                None if self.max_rotation_error is None else _json_float(self.max_rotation_error)
            ),
            "max_joint_step": _json_float(self.max_joint_step),
        }


def _json_float(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


@dataclass(frozen=True)
class PathMeasure:
    """Forward-kinematics measurement of a joint path against its Cartesian path.

    Attributes:
        max_deviation: [m], at the samples and at the points between them.
        max_rotation_error: [rad] at the samples of a pose path, else None.
        max_joint_step: [rad] / [m].
        max_step_joint: Joint index of ``max_joint_step`` (-1 for fewer than 2 samples).
    """

    max_deviation: float
    max_rotation_error: float | None
    max_joint_step: float
    max_step_joint: int


def measure_path(
    robot: RobotModel, path: CartesianPath, q: np.ndarray, between: int = 1
) -> PathMeasure:
    """Measure the joint path ``q`` (its first ``len(q)`` samples) against ``path``.

    Args:
        robot: The robot (FK of its DH table, which the tests check against Pinocchio).
        path: The Cartesian path.
        q: Joint path, shape (M, nq), M <= ``len(path)``.
        between: Points checked on each joint-space segment, evenly spaced (1: the midpoint).
    """
    m = len(q)
    if m == 0:
        return PathMeasure(math.nan, None, math.nan, -1)
    T = batch_forward_kinematics(robot.table, q)
    targets = path.positions[:m]
    deviation = float(np.linalg.norm(T[:, :3, 3] - targets, axis=1).max())
    rotation = None
    partial = path.axes is not None or path.mask is not None
    if partial:  # measured on the constrained components (kin.ik.partial_pose)
        from ..ik.partial_pose import PartialTask

        errors = [
            PartialTask(path.target(i)).errors(  # type: ignore[arg-type]
                PartialTask(path.target(i)).error(T[i, :3, 3], T[i, :3, :3])  # type: ignore[arg-type]
            )
            for i in range(m)
        ]
        deviation = max(position for position, _ in errors)
        rotation = max(turn for _, turn in errors)
    elif path.rotations is not None:
        rotation = max(
            float(np.linalg.norm(pin.log3(R.T @ R_target)))
            for R, R_target in zip(T[:, :3, :3], path.rotations[:m])
        )
    if m < 2:
        return PathMeasure(deviation, rotation, 0.0, -1)
    fractions = np.arange(1, between + 1) / (between + 1)
    inner = q[:-1, None, :] + fractions[None, :, None] * (q[1:] - q[:-1])[:, None, :]
    points = batch_forward_kinematics(robot.table, inner.reshape(-1, q.shape[1]))[:, :3, 3]
    a = np.repeat(targets[:-1], between, axis=0)
    b = np.repeat(targets[1:], between, axis=0)
    if path.mask is None or all(path.mask[:3]):  # the tool point is on the segments' line
        deviation = max(deviation, float(segment_distance(points, a, b).max()))
    steps = np.abs(np.diff(q, axis=0))
    joint = int(np.unravel_index(int(np.argmax(steps)), steps.shape)[1])
    return PathMeasure(deviation, rotation, float(steps.max()), joint)


@dataclass
class Trace:
    """What a follower collects, sample by sample (mutable; see :class:`PathResult`).

    Attributes:
        q: Joint vectors reached [rad] / [m].
        branches: Branch label per reached sample.
        branch_changes: Sample indices where the label changed.
        stopped_at: First sample not reached, or None.
        message: Why the motion stopped.
    """

    q: list[np.ndarray]
    branches: list[str]
    branch_changes: list[int]
    stopped_at: int | None = None
    message: str = ""

    def stop(self, index: int, message: str) -> Trace:
        """Record the stop at sample ``index`` and return self."""
        self.stopped_at = index
        self.message = f"stopped at sample {index}: {message}"
        return self
