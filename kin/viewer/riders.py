"""Things drawn on the arm besides its own geometry that ride on one of its joints.

A :class:`Rider` is a meshcat node that a :class:`~kin.viewer.RobotViewer` moves with a joint of
the robot's DH model (``robot.model``): at every configuration it displays or animates, the node's
transform is ``T_world_joint(q) @ placement``. The objects attached to a link of a collision
model (:func:`kin.viewer.collision_view.show_attached`) are drawn so. World frame = the arm's
base; lengths in meters.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

__all__ = ["Rider", "rider_points", "rider_pose"]


@dataclass(frozen=True, eq=False)
class Rider:
    """A meshcat node carried by a joint.

    Attributes:
        node: Its meshcat path (``scene/attached/<name>``).
        joint: The joint of ``robot.model`` that carries it (0: the world, fixed).
        placement: ``T_joint_node`` (4, 4) [m].
        corners: Corners (N, 3) of what it draws, in the node's frame [m] (the camera keeps
            them in view), or None.
    """

    node: str
    joint: int
    placement: np.ndarray
    corners: np.ndarray | None = None


def rider_pose(data: pin.Data, rider: Rider) -> np.ndarray:
    """``T_world_node`` (4, 4) [m] from ``data.oMi`` (after ``pin.forwardKinematics``)."""
    return np.asarray(data.oMi[rider.joint].homogeneous @ rider.placement)


def rider_points(model: pin.Model, riders: Iterable[Rider], q: np.ndarray) -> list[np.ndarray]:
    """The corners of every rider at joint values ``q`` [rad, m], in the world frame [m]."""
    data = model.createData()
    pin.forwardKinematics(model, data, q)
    points: list[np.ndarray] = []
    for rider in riders:
        if rider.corners is not None:
            T = rider_pose(data, rider)
            points.extend(rider.corners @ T[:3, :3].T + T[:3, 3])
    return points
