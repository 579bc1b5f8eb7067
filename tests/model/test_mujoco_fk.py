"""MuJoCo's FK of the same generated URDF equals Pinocchio's (``kin``) for every frame."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from support.dh_reference import rotation_angle

from dh2urdf import robot_names
from kin import load_robot
from kin.mujoco_model import load_mujoco_model

#: Position tolerance [m] and rotation tolerance [rad].
POS_TOL = 1e-9
ROT_TOL = 1e-9


def mujoco_poses(robot: str, q_all: np.ndarray, bodies: tuple[str, ...]) -> np.ndarray:
    """World poses of MuJoCo bodies at each q (mj_kinematics), shape (N, len(bodies), 4, 4)."""
    robot_model = load_robot(robot)
    model = load_mujoco_model(robot_model)
    data = mujoco.MjData(model)
    addresses = [model.jnt_qposadr[model.joint(name).id] for name in robot_model.joint_names]
    body_ids = [model.body(name).id for name in bodies]
    out = np.zeros((len(q_all), len(bodies), 4, 4))
    out[..., 3, 3] = 1.0
    for k, q in enumerate(q_all):
        data.qpos[addresses] = q
        mujoco.mj_kinematics(model, data)
        out[k, :, :3, :3] = data.xmat[body_ids].reshape(-1, 3, 3)
        out[k, :, :3, 3] = data.xpos[body_ids]
    return out


@pytest.mark.parametrize("robot", robot_names())
def test_mujoco_keeps_every_urdf_link_and_joint(robot):
    """MuJoCo has one body per URDF link (frame{i}, tool) and the same hinge/slide joints."""
    robot_model = load_robot(robot)
    model = load_mujoco_model(robot_model)
    bodies = {model.body(i).name for i in range(model.nbody)}
    frames = {f"frame{i}" for i in range(robot_model.nq + 1)} | {"base_link", "tool"}
    assert frames <= bodies, f"{robot=} missing bodies {sorted(frames - bodies)}"
    joints = tuple(model.joint(i).name for i in range(model.njnt))
    assert joints == robot_model.joint_names, f"{robot=}"
    assert model.nq == robot_model.nq, f"{robot=}"


@pytest.mark.parametrize("robot", robot_names())
def test_mujoco_fk_matches_pinocchio_at_random_configurations(robot, fk_q, kin_poses):
    """At 1000 random q within limits, MuJoCo puts frame0..frame{n} and tool where kin does."""
    frames, expected = kin_poses(robot)
    got = mujoco_poses(robot, fk_q(robot), frames)
    position = np.linalg.norm(got[..., :3, 3] - expected[..., :3, 3], axis=-1).max(axis=0)
    rotation = rotation_angle(got[..., :3, :3], expected[..., :3, :3]).max(axis=0)
    for j, frame in enumerate(frames):
        assert position[j] < POS_TOL, f"{robot=} {frame=} position error {position[j]:.3e} m"
        assert rotation[j] < ROT_TOL, f"{robot=} {frame=} rotation error {rotation[j]:.3e} rad"


@pytest.mark.parametrize("robot", robot_names())
def test_shipped_urdf_keeps_the_tool_in_raw_mujoco(robot):
    """The committed URDF, loaded by MuJoCo as is (no added compiler options), keeps every frame."""
    from dh2urdf import get_robot

    text = get_robot(robot).urdf_path.read_text(encoding="utf-8")
    model = mujoco.MjModel.from_xml_string(text)
    bodies = {model.body(i).name for i in range(model.nbody)}
    dof = get_robot(robot).load_table().dof
    frames = {f"frame{i}" for i in range(dof + 1)} | {"base_link", "tool"}
    assert frames <= bodies, f"{robot=} missing bodies {sorted(frames - bodies)}"
