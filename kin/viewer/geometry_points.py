"""Points of what a viewer draws: a mesh's vertices, a primitive's box corners, the arm's at q.

The camera frames the arm by these points (:func:`~kin.viewer.arm_camera.framed_view`), and a
scene object's box tells it what the object hides (:class:`~kin.viewer.camera_view.Obstacle`).
Lengths in meters; Pinocchio loads a mesh with the URDF's scale applied to its vertices, so the
points are those of the geometry drawn.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..robot_model import RobotModel
from .maker_meshes import MakerMeshes

__all__ = ["local_box", "mesh_vertices", "visual_points"]


def visual_points(
    robot: RobotModel,
    meshes: MakerMeshes | None,
    visual_model: pin.GeometryModel,
    q: np.ndarray,
) -> list[np.ndarray]:
    """The vertices of each mesh of the arm drawn at ``q``, the corners of each primitive's box.

    Args:
        robot: The robot (its DH model places the drawing when ``meshes`` is None).
        meshes: The maker's meshes the arm is drawn with, or None (the URDF's DH visuals).
        visual_model: The visual geometry drawn (``meshes.visual_model`` or the DH URDF's).
        q: Joint values of the DH model [rad] or [m].

    Returns:
        Points (3,) in the world frame [m].
    """
    if meshes is not None:
        model, full = meshes.model, meshes.full_q(q)
        root_to_world = np.linalg.inv(meshes.base_in_root)
    else:
        model, full, root_to_world = robot.model, q, np.eye(4)
    data = model.createData()
    geometry_data = pin.GeometryData(visual_model)
    pin.updateGeometryPlacements(model, data, visual_model, geometry_data, full)
    points = []
    for obj, placement in zip(visual_model.geometryObjects, geometry_data.oMg):
        local = mesh_vertices(obj)
        if local is None:
            local = local_box(obj)
        if local is None:
            continue
        T = root_to_world @ placement.homogeneous
        points.extend((T[:3, :3] @ local.T).T + T[:3, 3])
    return points


def mesh_vertices(obj: pin.GeometryObject) -> np.ndarray | None:
    """A mesh geometry's vertices (N, 3) in its own frame [m], or None for a primitive."""
    vertices = getattr(obj.geometry, "vertices", None)
    if vertices is None:
        return None
    try:
        array = np.asarray(vertices(), dtype=float).reshape(-1, 3)
    except (TypeError, ValueError, RuntimeError):
        return None
    if len(array) == 0 or not np.all(np.isfinite(array)):
        return None
    return array


def local_box(obj: pin.GeometryObject) -> np.ndarray | None:
    """The 8 corners (8, 3) of a geometry's bounding box in its own frame [m], or None.

    Pinocchio loads a mesh with the URDF's scale applied to its vertices: the box is the drawn one.
    """
    geometry = obj.geometry
    try:
        geometry.computeLocalAABB()
        low = np.asarray(geometry.aabb_local.min_, dtype=float)
        high = np.asarray(geometry.aabb_local.max_, dtype=float)
    except (AttributeError, RuntimeError):
        return None
    if not (np.all(np.isfinite(low)) and np.all(np.isfinite(high))):
        return None
    pick = np.array([[i >> 2 & 1, i >> 1 & 1, i & 1] for i in range(8)], dtype=float)
    return low + pick * (high - low)
