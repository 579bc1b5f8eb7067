"""A tool target for the numeric solvers, and Pinocchio's verdict on a joint vector against it.

Frames: the target is ``T_world_tool`` (position [m] in the world frame, rotation matrix of the
tool axes in the world frame). Pinocchio's forward kinematics is the judge of every numeric
solver: :func:`measure` is what decides ``success``.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import RobotModel

from ..exceptions import TargetError

#: Default tolerances of a numeric solution, measured by Pinocchio.
POSITION_TOLERANCE = 1e-5  # [m]
ROTATION_TOLERANCE = 1e-4  # [rad]


@dataclass(frozen=True, eq=False)
class NumericTarget:
    """What the tool must reach.

    Attributes:
        position: Tool position in the world frame [m], shape (3,).
        rotation: Tool rotation ``R_world_tool`` (3 x 3), or None for a position-only target.
        posture: Preferred joint vector [rad] for the redundancy (the solver stays close to it
            when it can), or None.
    """

    position: np.ndarray
    rotation: np.ndarray | None = None
    posture: np.ndarray | None = None

    @property
    def position_only(self) -> bool:
        """Whether only the position is constrained."""
        return self.rotation is None

    @classmethod
    def from_arrays(
        cls,
        position: npt.ArrayLike,
        rotation: npt.ArrayLike | None = None,
        posture: npt.ArrayLike | None = None,
    ) -> NumericTarget:
        """Validated target from array-likes (position [m], rotation matrix, posture [rad]).

        Raises:
            TargetError: Wrong shapes, non-finite values, or a rotation that is not orthonormal.
        """
        p = _finite(position, (3,), "target position")
        rot = None
        if rotation is not None:
            rot = _finite(rotation, (3, 3), "target rotation")
            if np.abs(rot.T @ rot - np.eye(3)).max() > 1e-6 or np.linalg.det(rot) < 0.0:
                raise TargetError(f"target rotation is not a rotation matrix: {rot.tolist()}")
        pose = None if posture is None else _finite(posture, (-1,), "posture")
        return cls(position=p, rotation=rot, posture=pose)

    @classmethod
    def from_target(cls, target: object) -> NumericTarget:
        """From ``ik.target``'s ``PositionTarget`` / ``PoseTarget`` (or a ``NumericTarget``).

        Raises:
            TargetError: Another kind of target (e.g. a ``PitchTarget``).
        """
        if isinstance(target, NumericTarget):
            return target
        from ..target import PoseTarget, PositionTarget

        if isinstance(target, PoseTarget):
            return cls.from_arrays(target.position, target.rotation)
        if isinstance(target, PositionTarget):
            return cls.from_arrays(target.position)
        raise TargetError(
            f"the numeric solver takes a PositionTarget, PoseTarget or NumericTarget, "
            f"got {type(target).__name__}"
        )

    @classmethod
    def from_se3(cls, pose: pin.SE3, position_only: bool = False) -> NumericTarget:
        """Target from a Pinocchio ``T_world_tool`` (meters)."""
        return cls(
            position=np.array(pose.translation, dtype=float),
            rotation=None if position_only else np.array(pose.rotation, dtype=float),
        )


def _finite(value: npt.ArrayLike, shape: tuple[int, ...], what: str) -> np.ndarray:
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError) as err:
        raise TargetError(f"{what} must be numbers, got {value!r}") from err
    if shape == (-1,):
        array = array.reshape(-1)
    elif array.shape != shape:
        raise TargetError(f"{what} must have shape {shape}, got {array.shape}")
    if not np.isfinite(array).all():
        raise TargetError(f"{what} must be finite, got {array.tolist()}")
    return array


@dataclass(frozen=True)
class Measurement:
    """Pinocchio's measurement of a joint vector against a target.

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


def measure(robot: RobotModel, data: pin.Data, q: np.ndarray, target: NumericTarget) -> Measurement:
    """Measure ``q`` against ``target`` with Pinocchio's forward kinematics of ``robot.tool_frame``.

    Args:
        robot: The robot (its Pinocchio model is the judge).
        data: A Pinocchio data of ``robot.model`` (overwritten).
        q: Joint vector [rad].
        target: The target.
    """
    model = robot.model
    pin.forwardKinematics(model, data, q)
    pose = pin.updateFramePlacement(model, data, _tool_frame_id(robot))
    d = pose.translation - target.position
    position_error = math.sqrt(float(d @ d))
    rotation_error = 0.0
    if target.rotation is not None:
        w = pin.log3(pose.rotation.T @ target.rotation)
        rotation_error = math.sqrt(float(w @ w))
    within = not bool(((q < model.lowerPositionLimit) | (q > model.upperPositionLimit)).any())
    return Measurement(position_error, rotation_error, within)


def _tool_frame_id(robot: RobotModel) -> int:
    fid = _FRAME_IDS.get(robot)
    if fid is None:
        fid = _FRAME_IDS[robot] = robot.model.getFrameId(robot.tool_frame)
    return fid


_FRAME_IDS: weakref.WeakKeyDictionary[RobotModel, int] = weakref.WeakKeyDictionary()
