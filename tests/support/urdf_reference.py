"""Example-robot-data's serial arms and Pinocchio's FK of an original URDF between two links:
the reference the URDF tests compare the extracted tables, the solvers and the preview against."""

from __future__ import annotations

import importlib.metadata
import math
from pathlib import Path

import numpy as np
import pinocchio as pin


def erd(relative: str) -> Path:
    """Absolute path of an example-robot-data URDF (``robots/<relative>``)."""
    suffix = f"example-robot-data/robots/{relative}"
    for file in importlib.metadata.files("example-robot-data") or ():
        if str(file).endswith(suffix):
            return Path(str(file.locate()))
    raise FileNotFoundError(suffix)


#: arm -> (URDF inside example-robot-data's robots folder, base link or None, tip link or None).
ARMS = {
    "ur3": ("ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", None, "tool0"),
    "ur5_limited": ("ur_description/urdf/ur5_joint_limited_robot.urdf", None, "tool0"),
    "panda": ("panda_description/urdf/panda.urdf", None, "panda_link8"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, None),
    "kinova": ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    "z1": ("z1_description/urdf/z1.urdf", None, "link06"),
    "so100": ("so_arm_description/urdf/so100.urdf", None, "gripper"),
    "so101": ("so_arm_description/urdf/so101.urdf", None, "gripper_link"),
    "baxter_left": ("baxter_description/urdf/baxter.urdf", "torso", "left_gripper"),
    "baxter_right": ("baxter_description/urdf/baxter.urdf", "torso", "right_gripper"),
    "tiago": ("tiago_description/robots/tiago.urdf", "torso_lift_link", "arm_tool_link"),
    "double_pendulum": (
        "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
        None,
        None,
    ),
    "asr_twodof": ("asr_twodof_description/urdf/TwoDofs.urdf", None, None),
}


def place_frames(model: pin.Model, data: pin.Data, joints: list, q: np.ndarray) -> None:
    """Pinocchio's FK into ``data.oMf``: ``joints`` at ``q`` [rad / m] (a continuous joint as
    its cos and sin), every other joint of ``model`` at its neutral value."""
    full = pin.neutral(model)
    for joint, value in zip(joints, q, strict=True):
        if joint.nq == 2:  # continuous: (cos, sin)
            full[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
        else:
            full[joint.idx_q] = value
    pin.forwardKinematics(model, data, full)
    pin.updateFramePlacements(model, data)


class UrdfReference:
    """Pinocchio's FK of the original URDF: the chain's joints at q, every other one at 0."""

    def __init__(self, path: Path, base: str, tip: str, joint_names: tuple[str, ...]):
        self.model = pin.buildModelFromUrdf(str(path))
        self.data = self.model.createData()
        self.base = self.model.getFrameId(base, pin.FrameType.BODY)
        self.tip = self.model.getFrameId(tip, pin.FrameType.BODY)
        self.joints = [self.model.joints[self.model.getJointId(name)] for name in joint_names]

    def pose(self, q: np.ndarray) -> np.ndarray:
        place_frames(self.model, self.data, self.joints, q)
        return (self.data.oMf[self.base].inverse() * self.data.oMf[self.tip]).homogeneous
