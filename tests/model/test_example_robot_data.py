"""Our URDFs of real arms (ur3, ur5, ur10, panda) have the FK of example-robot-data's URDFs of them.

example-robot-data ships no Python module (only files under ``cmeel.prefix/share``); its URDFs are
found through the package's file list. Fixed base transform between the two URDF roots, measured
at q = 0 and checked at random q (``T_erd_world_flange = T_erd_world_our_world @ T_world_tool``):

- ur3, ur5, ur10: identity: each table's ``[base]`` turns the controller's DH base frame by pi
  about z from the ROS ``base_link``, as the URDF's ``base_link -> base`` joint does (up to 0.3.0
  the tables had no ``[base]`` and ``T_erd_world_our_world`` was ``Rz(pi)``); ``tool`` equals
  ``tool0``;
- panda: identity; ``tool`` equals ``panda_link8`` (fingers at 0).

Measured largest errors over 1000 random q: ur3 3.4e-12 m, ur5 5.2e-12 m, ur10 7.2e-12 m, each
1.5e-11 rad (ERD writes pi/2 as 1.57079632679, 4.9e-12 rad short, and the errors add up over the
joints), panda exactly 0 (the same floating-point operations). Hence the rotation tolerance 1e-10
rad.
"""

from __future__ import annotations

import importlib.metadata
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.dh_reference import random_configurations, rotation_angle

from kin import Configuration, load_robot

#: Position tolerance [m] and rotation tolerance [rad] against example-robot-data.
POS_TOL = 1e-9
ROT_TOL = 1e-10
#: Random configurations per arm.
SAMPLES = 1000

#: robot -> (ERD URDF path inside the package's robots folder, ERD flange frame, T_erd_our).
CASES = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_link8", np.eye(4)),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "tool0", np.eye(4)),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", "tool0", np.eye(4)),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0", np.eye(4)),
}

#: UR arm -> its flange at q = 0 in base_link [m], summed by hand from the maker's DH lengths:
#: (-(a2 + a3), d4 + d6, d1 - d5), the DH base frame turned by pi about z (a2, a3 < 0).
UR_HOME_FLANGE = {
    "ur10": (0.612 + 0.5723, 0.163941 + 0.0922, 0.1273 - 0.1157),
    "ur3": (0.24365 + 0.21325, 0.11235 + 0.0819, 0.1519 - 0.08535),
    "ur5": (0.425 + 0.39225, 0.10915 + 0.0823, 0.089159 - 0.09465),
}


def erd_urdf(relative: str) -> Path:
    """Absolute path of an example-robot-data URDF (``robots/<relative>``)."""
    suffix = f"example-robot-data/robots/{relative}"
    for file in importlib.metadata.files("example-robot-data") or ():
        if str(file).endswith(suffix):
            return Path(str(file.locate()))
    raise FileNotFoundError(suffix)


class ErdArm:
    """Pinocchio model of an ERD URDF, driven by our joint vector (other joints at 0)."""

    def __init__(self, robot: str):
        relative, self.frame, self.T_erd_our = CASES[robot]
        self.ours = load_robot(robot)
        self.model = pin.buildModelFromUrdf(str(erd_urdf(relative)))
        self.data = self.model.createData()
        assert self.model.existFrame(self.frame), f"{robot=} ERD has no frame {self.frame!r}"
        self.frame_id = self.model.getFrameId(self.frame)
        ids = [self.model.getJointId(name) for name in self.ours.joint_names]
        assert max(ids) < self.model.njoints, f"{robot=} ERD lacks a joint of ours"
        self.index = [self.model.idx_qs[i] for i in ids]
        self.lower = np.maximum(self.ours.lower, self.model.lowerPositionLimit[self.index])
        self.upper = np.minimum(self.ours.upper, self.model.upperPositionLimit[self.index])

    def T_world_flange(self, q: np.ndarray) -> np.ndarray:
        """Pose of the ERD flange frame in the ERD root frame at our joint vector q."""
        q_erd = np.zeros(self.model.nq)  # the other joints (panda fingers) at 0
        q_erd[self.index] = q
        pin.framesForwardKinematics(self.model, self.data, q_erd)
        return self.data.oMf[self.frame_id].homogeneous


@pytest.mark.parametrize("robot", sorted(CASES))
def test_fixed_base_transform_is_the_stated_one(robot):
    """At q = 0, T_erd_flange @ inv(T_our_tool) is the identity: the same world frame."""
    arm = ErdArm(robot)
    q = np.zeros(arm.ours.nq)
    T_our = Configuration(arm.ours, q).transform_frame_to_world("tool").homogeneous
    measured = arm.T_world_flange(q) @ np.linalg.inv(T_our)
    position = float(np.linalg.norm(measured[:3, 3] - arm.T_erd_our[:3, 3]))
    rotation = float(rotation_angle(measured[:3, :3], arm.T_erd_our[:3, :3]))
    assert position < POS_TOL, f"{robot=} {position=:.3e} m"
    assert rotation < ROT_TOL, f"{robot=} {rotation=:.3e} rad"


@pytest.mark.parametrize("robot", sorted(UR_HOME_FLANGE))
def test_ur_flange_at_zero_is_ahead_of_base_link(robot):
    """At q = 0 a shipped UR's flange is at +x in base_link, as in the maker's URDF (issue 43).

    The expected points are summed by hand from the maker's lengths (``UR_HOME_FLANGE``): x is the
    upper arm and forearm along base_link's +x (ur5 +0.81725 m, ur3 +0.4569 m, ur10 +1.1843 m).
    Up to 0.3.0 the tables gave x and y negated.
    """
    position = Configuration(load_robot(robot), np.zeros(6)).transform_frame_to_world("tool")
    expected = np.array(UR_HOME_FLANGE[robot])
    assert np.allclose(position.translation, expected, rtol=0.0, atol=1e-12), f"{robot=} {position}"


@pytest.mark.parametrize("robot", sorted(CASES))
def test_flange_pose_matches_example_robot_data(robot):
    """At 1000 random q in both URDFs' limits, our tool is ERD's flange after the base offset."""
    arm = ErdArm(robot)
    q_all = random_configurations(arm.lower, arm.upper, SAMPLES, seed=2024)
    configuration = Configuration(arm.ours)
    ours = np.empty((len(q_all), 4, 4))
    theirs = np.empty_like(ours)
    for k, q in enumerate(q_all):
        ours[k] = arm.T_erd_our @ configuration.fk(q, "tool").homogeneous
        theirs[k] = arm.T_world_flange(q)
    position = float(np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=-1).max())
    rotation = float(rotation_angle(ours[:, :3, :3], theirs[:, :3, :3]).max())
    assert position < POS_TOL, f"{robot=} {position=:.3e} m"
    assert rotation < ROT_TOL, f"{robot=} {rotation=:.3e} rad"


@pytest.mark.parametrize("robot", sorted(CASES))
def test_joint_limits_agree_with_example_robot_data(robot):
    """Our table's joint limits, velocities and efforts equal ERD's (2 pi written to 1e-11)."""
    arm = ErdArm(robot)
    for field, bound, erd in (
        ("lower", arm.ours.lower, arm.model.lowerPositionLimit),
        ("upper", arm.ours.upper, arm.model.upperPositionLimit),
        ("velocity", arm.ours.model.velocityLimit, arm.model.velocityLimit),
        ("effort", arm.ours.model.effortLimit, arm.model.effortLimit),
    ):
        assert np.allclose(bound, erd[arm.index], rtol=0.0, atol=1e-10), (
            f"{robot=} {field}: {bound=} {erd[arm.index]=}"
        )
