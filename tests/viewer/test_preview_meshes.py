"""A robot loaded from a URDF is previewed with the maker's meshes, driven by the DH model's q;
a missing mesh falls back to the DH cylinders with one warning."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
from support.urdf_reference import ARMS, erd

from kin import Configuration, load_robot
from kin.viewer import RobotViewer


@pytest.mark.parametrize("arm", ["ur5", "panda", "tiago"])
def test_maker_meshes_follow_the_dh_model(arm):
    """The maker's tip link, placed by full_q and the base transform, is the DH model's tool."""
    relative, base, tip = ARMS[arm]
    robot = load_robot(erd(relative), base, tip)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        viewer = RobotViewer(robot)
    meshes = viewer.meshes
    assert meshes is not None and len(meshes.visual_model.geometryObjects) > robot.nq
    assert any(
        g.meshPath.endswith((".dae", ".stl", ".obj")) for g in meshes.visual_model.geometryObjects
    )
    data = meshes.model.createData()
    tip_id = meshes.model.getFrameId(robot.urdf_source[2], pin.FrameType.BODY)
    configuration = Configuration(robot)
    rng = np.random.default_rng(2)
    for q in rng.uniform(
        np.maximum(robot.lower, -3), np.minimum(robot.upper, 3), size=(20, robot.nq)
    ):
        pin.framesForwardKinematics(meshes.model, data, meshes.full_q(q))
        drawn = np.linalg.inv(meshes.base_in_root) @ data.oMf[tip_id].homogeneous
        np.testing.assert_allclose(drawn, configuration.fk(q).homogeneous, atol=1e-9)


def test_missing_mesh_falls_back_to_the_dh_cylinders(tmp_path):
    """A URDF whose mesh file is missing: one warning naming it, the DH cylinders drawn."""
    text = erd(ARMS["ur5"][0]).read_text(encoding="utf-8")
    text = text.replace(
        "package://example-robot-data/robots/ur_description/meshes/ur5/visual/", "meshes/"
    )
    path = tmp_path / "ur5_no_meshes.urdf"
    path.write_text(text, encoding="utf-8")
    robot = load_robot(path, tip="tool0")
    with pytest.warns(UserWarning, match="drawing the DH cylinders instead"):
        viewer = RobotViewer(robot)
    assert viewer.meshes is None
    assert all("axis" in name or name for name in viewer.geometry_nodes)
