"""The camera of a robot's meshcat scene: aimed from a point at a point, or framed on the arm.

meshcat's camera orbits the origin of its world: to centre a view, :func:`aim_camera` shifts
``scene`` (and the grid) by ``-target``, the robot's world frame moving with it, and sets the
camera's offset from the target and its zoom. :func:`framed_view` chooses the view that frames
the arm's drawing (:func:`~kin.viewer.camera_view.choose_view`). Both work on a
:class:`ShownArm` (a :class:`~kin.viewer.RobotViewer`). World frame, lengths in meters.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import meshcat
import meshcat.transformations as tf
import numpy as np
import numpy.typing as npt
import pinocchio as pin

from ..configuration import as_joint_vector
from ..robot_model import RobotModel
from .camera_view import CameraView, Obstacle, choose_view
from .exceptions import ViewerInputError
from .finite_array import finite_array
from .geometry_points import visual_points
from .maker_meshes import MakerMeshes
from .riders import Rider, rider_points

__all__ = ["ShownArm", "aim_camera", "framed_view"]


class ShownArm(Protocol):
    """What the camera needs of a robot's scene (:class:`~kin.viewer.RobotViewer` has it)."""

    @property
    def robot(self) -> RobotModel:
        """The robot shown."""

    @property
    def q(self) -> np.ndarray:
        """The joint values shown [rad] or [m]."""

    @property
    def meshes(self) -> MakerMeshes | None:
        """The maker's meshes drawn, or None (the DH visuals)."""

    @property
    def visual_model(self) -> pin.GeometryModel:
        """The visual geometry drawn."""

    @property
    def riders(self) -> dict[str, Rider]:
        """Nodes riding on a joint (attached objects): in view with the arm."""

    @property
    def obstacles(self) -> list[Obstacle]:
        """Boxes of the scene objects drawn: the camera looks past them."""

    @property
    def arm_length(self) -> float:
        """Length of the chain of frame origins [m]."""

    @property
    def viewer(self) -> meshcat.Visualizer:
        """The meshcat visualizer (server or recorder)."""

    @property
    def scene(self) -> meshcat.Visualizer:
        """Its ``scene`` node, where the robot and the markers are."""

    @property
    def grid_scale(self) -> float:
        """Scale of meshcat's grid (1: 20 m in 0.5 m cells)."""


def aim_camera(
    arm: ShownArm, target: npt.ArrayLike, position: npt.ArrayLike, zoom: float = 1.0
) -> None:
    """Aim the camera from ``position`` at ``target`` (world frame [m]); the mouse orbits it.

    Args:
        arm: The scene.
        target: The point looked at [m], shape (3,).
        position: The camera [m], shape (3,), not at ``target``.
        zoom: Magnification (three.js's camera zoom: 2 shows things twice as large), > 0.

    Raises:
        ViewerInputError: Not finite points of shape (3,), the same point twice, or a zoom
            that is not a positive number.
    """
    target = finite_array(target, (3,), "camera target")
    offset = finite_array(position, (3,), "camera position") - target
    if not np.linalg.norm(offset) > 0.0:
        raise ViewerInputError("the camera position and its target are the same point")
    if not (np.isfinite(zoom) and zoom > 0.0):
        raise ViewerInputError(f"the camera zoom must be a positive number, got {zoom!r}")
    shift = tf.translation_matrix(-target)  # meshcat's camera looks at its world origin
    arm.scene.set_transform(shift)
    arm.viewer["/Grid"].set_transform(shift @ tf.scale_matrix(arm.grid_scale))
    # the camera sits in meshcat's y-up frame "rotated": world (x, y, z) is (x, -z, y) there
    camera = arm.viewer["/Cameras/default/rotated/<object>"]
    camera.set_property("position", [offset[0], offset[2], -offset[1]])
    camera.set_property("zoom", float(zoom))


def framed_view(
    arm: ShownArm,
    extra_points: npt.ArrayLike | None = None,
    configurations: Sequence[npt.ArrayLike] | None = None,
) -> CameraView:
    """The camera that frames the arm and ``extra_points`` (:func:`~.camera_view.choose_view`).

    Every visual geometry of the arm (the maker's meshes included) enters by its vertices
    (a mesh) or the corners of its bounding box (a primitive) at each configuration, the
    objects riding on it (``arm.riders``) by their corners; the
    scene's objects do not (the arm is what the picture is about) but the camera looks past
    them (``arm.obstacles``) at the arm's frame origins.

    Args:
        arm: The scene.
        extra_points: More points to keep in view, shape (M, 3), world frame [m].
        configurations: Joint vectors whose arm must be in view (default: the current q).
    """
    robot = arm.robot
    data = robot.model.createData()
    points: list[np.ndarray] = []
    sights: list[np.ndarray] = []
    for q in [arm.q] if configurations is None else configurations:
        q = as_joint_vector(robot, q)
        pin.framesForwardKinematics(robot.model, data, q)
        origins = [frame.translation.copy() for frame in data.oMf]
        points.extend(origins)
        sights.extend(origins)
        points.extend(visual_points(robot, arm.meshes, arm.visual_model, q))
        points.extend(rider_points(robot.model, arm.riders.values(), q))
    if extra_points is not None:
        points.extend(np.asarray(extra_points, dtype=float).reshape(-1, 3))
    return choose_view(np.array(points), np.array(sights), arm.obstacles, 0.2 * arm.arm_length)
