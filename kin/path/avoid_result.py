"""The outcome of following a path collision-free (:func:`kin.path.follow_path_avoiding`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from .cartesian import CartesianPath
from .collision_check import PathCollision, PathCollisionCheck
from .result import PathResult


@dataclass(frozen=True, eq=False)
class AvoidFailure:
    """The sample where no collision-free, continuous path goes on.

    Attributes:
        sample: Index of the sample.
        arc_length: Length of the tool path from the start to the sample [m].
        position: Tool point of the sample, world frame [m].
        rpy: Its orientation as URDF roll-pitch-yaw [rad] (pose paths), else None.
        axis: Its tool-axis direction (axis paths), else None.
        reason: Why: every answer collides, the nearest free one would jump, or the motion to
            every free one within the step collides.
    """

    sample: int
    arc_length: float
    position: np.ndarray
    rpy: np.ndarray | None
    axis: np.ndarray | None
    reason: str

    def describe(self) -> str:
        """One line: the sample, where it is, and why."""
        pose = "xyz = ({:.4g}, {:.4g}, {:.4g}) m".format(*(self.position + 0.0))
        if self.rpy is not None:
            pose += ", rpy = ({:.4g}, {:.4g}, {:.4g}) rad".format(*(self.rpy + 0.0))
        if self.axis is not None:
            pose += ", axis = ({:.4g}, {:.4g}, {:.4g})".format(*self.axis)
        return (
            f"no collision-free path at sample {self.sample} (arc length "
            f"{self.arc_length:.4g} m, {pose}): {self.reason}"
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict, SI."""
        return {
            "sample": self.sample,
            "arc_length_m": self.arc_length,
            "xyz_m": self.position.tolist(),
            "rpy_rad": None if self.rpy is None else self.rpy.tolist(),
            "axis": None if self.axis is None else self.axis.tolist(),
            "reason": self.reason,
        }


def failure_at(path: CartesianPath, index: int, reason: str) -> AvoidFailure:
    """The :class:`AvoidFailure` of sample ``index`` of ``path``."""
    steps = np.linalg.norm(np.diff(path.positions[: index + 1], axis=0), axis=1)
    rpy = None if path.rotations is None else np.asarray(pin.rpy.matrixToRpy(path.rotations[index]))
    axis = None if path.axes is None else np.array(path.axes[index], dtype=float)
    return AvoidFailure(index, float(steps.sum()), path.positions[index].copy(), rpy, axis, reason)


@dataclass(frozen=True, eq=False)
class AvoidedPath:
    """A joint path whose samples and motions between them are collision-free, or why not.

    Attributes:
        success: A free path was found (``result`` and ``check`` set, ``failure`` None).
        result: The joint path, measured against the Cartesian path, or None.
        check: The collision check of ``result`` (free), or None.
        plain: The first collision of the plain path (:func:`kin.path.follow_path`), None when
            it was free (then ``result`` is the plain path).
        failure: Where no free, continuous path goes on, or None.
        searched: The plain path collided or stopped, so the answers were searched.
    """

    success: bool
    result: PathResult | None
    check: PathCollisionCheck | None
    plain: PathCollision | None
    failure: AvoidFailure | None = None
    searched: bool = True

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict, SI (the path's own record is :meth:`PathResult.to_dict`)."""
        plain = self.plain
        return {
            "success": self.success,
            "searched": self.searched,
            "plain_path_collision": None if plain is None else plain.describe(),
            "failure": None if self.failure is None else self.failure.to_dict(),
        }
