"""The parts of the planning scripts' problems (issue 44, items 3-5): arms and scene boxes.

Plain values, read by :mod:`plan_problems` (which draws the problems and builds kin's checker)
and by :mod:`plan_reference` (the independent check), so that neither imports the other's
module for them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["ARMS", "Arm", "Box"]


@dataclass(frozen=True)
class Arm:
    """An arm of the scripts: where its model comes from.

    Attributes:
        name: Row name.
        robot: example-robot-data URDF (relative to ``robots/``) or a shipped table's name.
        tip: The chain's tip link (URDF), or None for a table.
        srdf: example-robot-data SRDF, or None.
        reach: Rough reach from the base [m], the scenes' scale.
        span: Start and goal joints are drawn within +-span [rad] (and the limits).
    """

    name: str
    robot: str
    tip: str | None
    srdf: str | None
    reach: float
    span: float = math.pi


ARMS = {
    "panda": Arm(
        "panda", "panda_description/urdf/panda.urdf", "panda_hand",
        "panda_description/srdf/panda.srdf", 0.85,
    ),
    "ur5": Arm(
        "ur5", "ur_description/urdf/ur5_robot.urdf", "tool0", "ur_description/srdf/ur5.srdf", 0.85
    ),
    "ur10-dh": Arm("ur10-dh", "ur10", None, None, 1.3),
}  # fmt: skip


@dataclass(frozen=True)
class Box:
    """A box of a scene: size [m] and pose in the arm's base frame (xyz [m], yaw [rad])."""

    name: str
    size: tuple[float, float, float]
    xyz: tuple[float, float, float]
    yaw: float = 0.0

    def as_json(self) -> dict:
        """The box as a JSON object (``rpy`` [rad])."""
        return {"name": self.name, "size": self.size, "xyz": self.xyz, "rpy": [0, 0, self.yaw]}
