"""``kin preview``'s camera frames every drawn shape, the maker's meshes included.

The reference is built apart from the viewer: each <visual> mesh of Panda's URDF read with coal's
own loader from the file the URDF names (ElementTree, package:// resolved by the collision
reference), placed by Pinocchio's forward kinematics of the original URDF. The camera must aim at
the centre of the box around all their vertices and stand far enough to frame all of it (the
frame origins alone gave a box 15 % smaller: the base and hand meshes were cut off).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest
from collision_reference import resolve_mesh
from urdf_reference import erd

from kin import load_robot

viewer_module = pytest.importorskip("kin.viewer")


def reference_box(urdf: Path, base: str, q: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """Lowest and highest corner of every <visual> mesh's vertices, in ``base``'s frame [m]."""
    text = urdf.read_text(encoding="utf-8")
    model = pin.buildModelFromXML(text)
    data = model.createData()
    full = pin.neutral(model)
    for name, value in q.items():
        full[model.joints[model.getJointId(name)].idx_q] = value
    pin.forwardKinematics(model, data, full)
    pin.updateFramePlacements(model, data)
    base_inv = data.oMf[model.getFrameId(base)].inverse()
    points = []
    for link in ET.fromstring(text).findall("link"):
        for visual in link.findall("visual"):
            mesh = visual.find("geometry/mesh")
            if mesh is None:
                continue
            origin = visual.find("origin")
            xyz = (
                [0.0] * 3
                if origin is None
                else [float(v) for v in origin.get("xyz", "0 0 0").split()]
            )
            rpy = (
                [0.0] * 3
                if origin is None
                else [float(v) for v in origin.get("rpy", "0 0 0").split()]
            )
            local = pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz))
            bvh = coal.MeshLoader().load(str(resolve_mesh(mesh.get("filename"), urdf)))
            vertices = np.asarray(bvh.vertices())
            T = (base_inv * data.oMf[model.getFrameId(link.get("name"))] * local).homogeneous
            points.append(vertices @ T[:3, :3].T + T[:3, 3])
    cloud = np.vstack(points)
    return cloud.min(axis=0), cloud.max(axis=0)


def test_panda_camera_aims_at_the_box_of_its_meshes():
    """Panda with the maker's meshes (to panda_hand): the camera aims at the meshes' box centre."""
    urdf = erd("panda_description/urdf/panda.urdf")
    robot = load_robot(urdf, None, "panda_hand")
    q = [0.3, -0.6, 0.2, -2.0, 0.1, 1.6, 0.7]
    viewer = viewer_module.RobotViewer(robot)
    assert viewer.meshes is not None
    viewer.display(q)
    aimed = []
    viewer.set_camera = lambda t, p: aimed.append((np.array(t), np.array(p)))  # type: ignore[method-assign]
    viewer.fit_camera()
    target, position = aimed[0]
    path, base, _ = robot.urdf_source
    low, high = reference_box(Path(path), base or "panda_link0", dict(zip(robot.joint_names, q)))
    # the fingers (beyond panda_hand) are drawn too: the box may only grow past the reference
    centre = 0.5 * (low + high)
    assert np.linalg.norm(target - centre) < 0.15 * np.linalg.norm(high - low), (target, centre)
    diagonal = float(np.linalg.norm(high - low))
    distance = float(np.linalg.norm(position - target))
    assert distance >= 0.99 * viewer_module.robot_viewer.CAMERA_DISTANCE * diagonal, (
        distance,
        diagonal,
    )
    assert low[0] < -0.15  # the base mesh reaches 0.15 m behind the base, no frame does
