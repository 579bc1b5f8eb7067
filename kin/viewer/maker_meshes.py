"""The maker's meshes of a robot loaded from a URDF, driven by the DH model's joint vector.

A robot loaded from a URDF (:func:`kin.load_robot`) is a DH table; the preview draws it with the
visual geometry of the original URDF instead of the DH cylinders: Pinocchio builds the original
model and its visuals (``package://`` and relative mesh paths resolved from the URDF's folder and
its parents; when they are COLLADA files, which meshcat draws with pieces missing, the collision
meshes in grey), the chain's joints take the DH model's values (by name; the others stay at 0), and
the drawing is placed in the chain's base frame (the DH model's world). A mesh that cannot be
found gives a :class:`~kin.viewer.exceptions.ViewerError`: the viewer then warns in one line and
draws the DH cylinders.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..robot_model import RobotModel
from .exceptions import ViewerError

__all__ = ["MakerMeshes", "maker_meshes"]

#: Folders above the URDF searched for ``package://NAME/...`` (NAME is a folder there).
PACKAGE_LEVELS = 6

#: Color of meshes drawn without the URDF's materials (the collision meshes), RGBA in [0, 1].
MESH_RGBA = (0.72, 0.74, 0.78, 1.0)
#: Their emission (a share of that color that needs no light) [0, 1].
MESH_EMISSION = (0.35, 0.36, 0.38, 1.0)


@dataclass(frozen=True, eq=False)
class MakerMeshes:
    """The original URDF's model and visuals, and how the DH model's q drives them.

    Attributes:
        model: Pinocchio model of the whole original URDF.
        visual_model: Its visual geometry (the maker's meshes).
        base_in_root: ``T_root_base`` (4x4, [m]): the chain's base link in the URDF root.
        joints: Per joint of the DH model, ``(idx_q, nq)`` of the original model's joint.
    """

    model: pin.Model
    visual_model: pin.GeometryModel
    base_in_root: np.ndarray
    joints: tuple[tuple[int, int], ...]

    def full_q(self, q: np.ndarray) -> np.ndarray:
        """The original model's configuration for the DH model's ``q`` [rad, m]."""
        full = pin.neutral(self.model)
        for (index, size), value in zip(
            self.joints, np.asarray(q, dtype=float).tolist(), strict=True
        ):
            if size == 2:  # continuous: (cos, sin)
                full[index], full[index + 1] = math.cos(value), math.sin(value)
            else:
                full[index] = value
        return full


def maker_meshes(robot: RobotModel) -> MakerMeshes:
    """The :class:`MakerMeshes` of a robot loaded from a URDF.

    Raises:
        ViewerError: The robot was not loaded from a URDF, a joint of its table is not in the
            URDF, or Pinocchio cannot load a mesh (the message names it).
    """
    if robot.urdf_source is None:
        raise ViewerError(f"'{robot.name}' was not loaded from a URDF")
    path, base, _ = robot.urdf_source
    folder = Path(path).resolve().parent
    package_dirs = [str(p) for p in [folder, *folder.parents][:PACKAGE_LEVELS]]
    try:
        model = pin.buildModelFromUrdf(path)
        visual = pin.buildGeomFromUrdf(
            model, path, pin.GeometryType.VISUAL, package_dirs=package_dirs
        )
        if any(g.meshPath.lower().endswith(".dae") for g in visual.geometryObjects):
            # meshcat draws COLLADA meshes incompletely (pieces missing): the collision
            # meshes (STL), when there are any, give the whole arm
            collision = pin.buildGeomFromUrdf(
                model, path, pin.GeometryType.COLLISION, package_dirs=package_dirs
            )
            if collision.geometryObjects and not any(
                g.meshPath.lower().endswith(".dae") for g in collision.geometryObjects
            ):
                for geometry in collision.geometryObjects:
                    geometry.meshColor = np.array(MESH_RGBA)
                    # STL meshes come without normals: an emissive share keeps them visible
                    geometry.meshMaterial = pin.GeometryPhongMaterial(
                        np.array(MESH_EMISSION), np.array((0.2, 0.2, 0.2, 1.0)), 0.3
                    )
                    geometry.overrideMaterial = True
                visual = collision
    except (RuntimeError, ValueError, OSError) as err:
        raise ViewerError(
            f"{path}: cannot load its meshes ({' '.join(str(err).split())[:160]})"
        ) from err
    for geometry in visual.geometryObjects:
        mesh = getattr(geometry, "meshPath", "")
        if mesh and not mesh.startswith(("BOX", "SPHERE", "CYLINDER")) and not Path(mesh).is_file():
            raise ViewerError(f"{path}: mesh not found: {mesh}")
    joints = []
    for name in robot.joint_names:
        if not model.existJointName(name):
            raise ViewerError(f"{path}: no joint {name!r} (the table's joint names changed?)")
        joint = model.joints[model.getJointId(name)]
        joints.append((joint.idx_q, joint.nq))
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    base_in_root = data.oMf[model.getFrameId(base, pin.FrameType.BODY)].homogeneous.copy()
    return MakerMeshes(model, visual, base_in_root, tuple(joints))
