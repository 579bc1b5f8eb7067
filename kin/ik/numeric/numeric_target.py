"""A tool target for the numeric solvers.

Frames: the target is ``T_world_tool`` (position [m] in the world frame, rotation matrix of the
tool axes in the world frame). The judge (:func:`kin.ik.judge.measure`, re-exported here with its
tolerances) decides ``success``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from ..exceptions import TargetError
from ..judge import POSITION_TOLERANCE, ROTATION_TOLERANCE, Measurement, measure

__all__ = [
    "POSITION_TOLERANCE",
    "ROTATION_TOLERANCE",
    "Measurement",
    "NumericTarget",
    "measure",
]


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
    #: No packed values: the compiled solvers read the arrays (see :class:`~kin.ik.PoseTarget`).
    _packed: ClassVar[None] = None

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
        from ..targets.target import PoseTarget, PositionTarget

        # Checked when they were built (finite, a rotation matrix): no second check.
        if isinstance(target, PoseTarget):
            return cls(target.position, target.rotation)
        if isinstance(target, PositionTarget):
            return cls(target.position)
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
