"""The shipped tables of real arms have the FK of the makers' models.

xarm7 against example-robot-data's URDF of that arm (ur3, ur5, ur10 and panda, in the makers'
base frames, are in tests/model/test_example_robot_data.py), puma560 against the Robotics Toolbox's DH
model. Each at 1000 random q within both models' limits, on our tool frame through ``kin``.

- xarm7: identity base, ``tool`` equals ``link7`` (and ``link_eef``). The maker's URDF writes the
  six twists pi/2 as ``1.5708`` (3.7e-6 rad long); our table keeps the published exact twists.
  With those six literals set to pi/2 the two agree exactly (0 m, 0 rad measured); as shipped they
  differ by the rounding alone: 4.5e-6 m and 1.9e-5 rad measured, bounded here by the sum of the
  six roundings (rotation) and that sum times the arm's reach (position).
- puma560: a plain NumPy DH product of the parameters as the Robotics Toolbox writes them (in this
  file, not read from our table), and the toolbox's own ``fkine`` when ``roboticstoolbox`` is
  installed (measured 4.6e-16 m with roboticstoolbox 1.5.0).
"""

from __future__ import annotations

import importlib.metadata
import math
import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.dh_reference import dh_matrices, random_configurations, rotation_angle

from kin import Configuration, load_robot

#: Position tolerance [m] and rotation tolerance [rad] against the makers' models.
POS_TOL = 1e-9
ROT_TOL = 1e-10
#: Random configurations per arm.
SAMPLES = 1000

#: robot -> (ERD URDF inside the package's robots folder, ERD flange frame, T_erd_our).
CASES = {
    "xarm7": ("xarm_description/urdf/xarm7.urdf", "link7", np.eye(4)),
}

#: The xArm7 URDF's spelling of a quarter turn in its joint origins.
XARM_QUARTER = "1.5708"
#: Its joint origins that turn by +-1.5708 about x (joints 2 to 7).
XARM_TWISTS = 6
#: Upper bound of the xArm7's reach from its base frame [m] (0.267 + 0.293 + 0.3425 + ... < 1.2).
XARM_REACH = 1.2


def erd_urdf(relative: str) -> Path:
    """Absolute path of an example-robot-data URDF (``robots/<relative>``)."""
    suffix = f"example-robot-data/robots/{relative}"
    for file in importlib.metadata.files("example-robot-data") or ():
        if str(file).endswith(suffix):
            return Path(str(file.locate()))
    raise FileNotFoundError(suffix)


def exact_quarter_turns(urdf_text: str) -> tuple[str, int]:
    """The URDF with every ``rpy="+-1.5708 `` roll written as the exact pi/2, and the count."""
    return re.subn(
        rf'rpy="(-?){re.escape(XARM_QUARTER)} ',
        lambda match: f'rpy="{match.group(1)}{math.pi / 2!r} ',
        urdf_text,
    )


class ErdArm:
    """Pinocchio model of an ERD URDF (its text), driven by our joint vector."""

    def __init__(self, robot: str, urdf_text: str | None = None):
        relative, self.frame, self.T_erd_our = CASES[robot]
        self.ours = load_robot(robot)
        text = erd_urdf(relative).read_text(encoding="utf-8") if urdf_text is None else urdf_text
        self.model = pin.buildModelFromXML(text)
        self.data = self.model.createData()
        assert self.model.existFrame(self.frame), f"{robot=} ERD has no frame {self.frame!r}"
        self.frame_id = self.model.getFrameId(self.frame)
        ids = [self.model.getJointId(name) for name in self.ours.joint_names]
        assert max(ids) < self.model.njoints, f"{robot=} ERD lacks a joint of ours"
        assert self.model.nq == self.ours.nq, f"{robot=} ERD has other joints"
        self.index = [self.model.idx_qs[i] for i in ids]
        self.lower = np.maximum(self.ours.lower, self.model.lowerPositionLimit[self.index])
        self.upper = np.minimum(self.ours.upper, self.model.upperPositionLimit[self.index])

    def T_world_flange(self, q: np.ndarray) -> np.ndarray:
        """Pose of the ERD flange frame in the ERD root frame at our joint vector q."""
        q_erd = np.zeros(self.model.nq)
        q_erd[self.index] = q
        pin.framesForwardKinematics(self.model, self.data, q_erd)
        return self.data.oMf[self.frame_id].homogeneous


def xarm_exact_text() -> str:
    """The xArm7 URDF of example-robot-data with its quarter turns exact."""
    text, count = exact_quarter_turns(erd_urdf(CASES["xarm7"][0]).read_text(encoding="utf-8"))
    assert count == XARM_TWISTS, f"{count=} quarter turns rewritten"
    return text


def flange_errors(arm: ErdArm) -> tuple[float, float]:
    """Largest position [m] and rotation [rad] error of our tool against the ERD flange."""
    q_all = random_configurations(arm.lower, arm.upper, SAMPLES, seed=2024)
    configuration = Configuration(arm.ours)
    ours = np.empty((len(q_all), 4, 4))
    theirs = np.empty_like(ours)
    for k, q in enumerate(q_all):
        ours[k] = arm.T_erd_our @ configuration.fk(q, "tool").homogeneous
        theirs[k] = arm.T_world_flange(q)
    position = float(np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=-1).max())
    rotation = float(rotation_angle(ours[:, :3, :3], theirs[:, :3, :3]).max())
    return position, rotation


def exact_arm(robot: str) -> ErdArm:
    """The ERD arm, with the xArm7's rounded quarter turns made exact."""
    return ErdArm(robot, xarm_exact_text() if robot == "xarm7" else None)


@pytest.mark.parametrize("robot", sorted(CASES))
def test_fixed_base_transform_is_the_stated_one(robot):
    """At q = 0, T_erd_flange @ inv(T_our_tool) is the identity for xarm7."""
    arm = exact_arm(robot)
    q = np.zeros(arm.ours.nq)
    T_our = Configuration(arm.ours, q).transform_frame_to_world("tool").homogeneous
    measured = arm.T_world_flange(q) @ np.linalg.inv(T_our)
    position = float(np.linalg.norm(measured[:3, 3] - arm.T_erd_our[:3, 3]))
    rotation = float(rotation_angle(measured[:3, :3], arm.T_erd_our[:3, :3]))
    assert position < POS_TOL, f"{robot=} {position=:.3e} m"
    assert rotation < ROT_TOL, f"{robot=} {rotation=:.3e} rad"


@pytest.mark.parametrize("robot", sorted(CASES))
def test_flange_pose_matches_example_robot_data(robot):
    """At 1000 random q in both URDFs' limits, our tool is ERD's flange after the base offset."""
    position, rotation = flange_errors(exact_arm(robot))
    assert position < POS_TOL, f"{robot=} {position=:.3e} m"
    assert rotation < ROT_TOL, f"{robot=} {rotation=:.3e} rad"


def test_xarm7_differs_from_the_shipped_urdf_by_its_rounded_twists_only():
    """Against the xArm7 URDF as shipped, the error stays within what 1.5708 for pi/2 explains."""
    rounding = XARM_TWISTS * abs(float(XARM_QUARTER) - math.pi / 2)
    position, rotation = flange_errors(ErdArm("xarm7"))
    assert rotation < rounding + ROT_TOL, f"{position=:.3e} m {rotation=:.3e} rad {rounding=:.3e}"
    assert position < rounding * XARM_REACH + POS_TOL, f"{position=:.3e} m {rounding=:.3e}"
    assert position > POS_TOL, f"{position=:.3e} m: the rounding should show"


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


# --- puma560: the Robotics Toolbox's models.DH.Puma560 (standard DH, SI units) ---------------

#: Published rows (d, a, alpha) [m, m, rad] and qlim [deg], as roboticstoolbox writes them.
PUMA_D = np.array([26.45 * 0.0254, 0.0, 0.15005, 0.4318, 0.0, 0.0])
PUMA_A = np.array([0.0, 0.4318, 0.0203, 0.0, 0.0, 0.0])
PUMA_ALPHA = np.array([math.pi / 2, 0.0, -math.pi / 2, math.pi / 2, -math.pi / 2, 0.0])
PUMA_QLIM_DEG = np.array(
    [
        [-160.0, 160.0],
        [-45.0, 225.0],
        [-225.0, 45.0],
        [-110.0, 170.0],
        [-100.0, 100.0],
        [-266.0, 266.0],
    ]
)


def puma_samples() -> tuple[np.ndarray, np.ndarray]:
    """Random q within the published qlim and our tool poses there, shapes (N, 6), (N, 4, 4)."""
    robot = load_robot("puma560")
    deg = math.pi / 180
    q_all = random_configurations(PUMA_QLIM_DEG[:, 0] * deg, PUMA_QLIM_DEG[:, 1] * deg, SAMPLES, 11)
    configuration = Configuration(robot)
    ours = np.array([configuration.fk(q, "tool").homogeneous for q in q_all])
    return q_all, ours


def pose_errors(ours: np.ndarray, theirs: np.ndarray) -> tuple[float, float]:
    """Largest position [m] and rotation [rad] error between two batches of poses."""
    position = float(np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=-1).max())
    rotation = float(rotation_angle(ours[:, :3, :3], theirs[:, :3, :3]).max())
    return position, rotation


def test_puma560_matches_the_published_dh_product():
    """At 1000 random q, our tool is the product of the toolbox's published DH rows."""
    q_all, ours = puma_samples()
    links = dh_matrices("standard", PUMA_A, PUMA_ALPHA, PUMA_D, q_all)  # (N, 6, 4, 4)
    theirs = np.broadcast_to(np.eye(4), ours.shape).copy()
    for j in range(links.shape[1]):
        theirs = theirs @ links[:, j]
    position, rotation = pose_errors(ours, theirs)
    assert position < POS_TOL, f"{position=:.3e} m"
    assert rotation < ROT_TOL, f"{rotation=:.3e} rad"


def test_puma560_limits_are_the_published_qlim():
    """Our puma560 limits are the toolbox's qlim in degrees."""
    robot = load_robot("puma560")
    expected = np.radians(PUMA_QLIM_DEG)
    assert np.allclose(robot.lower, expected[:, 0], rtol=0.0, atol=1e-12), f"{robot.lower=}"
    assert np.allclose(robot.upper, expected[:, 1], rtol=0.0, atol=1e-12), f"{robot.upper=}"


@pytest.mark.peer
def test_puma560_matches_robotics_toolbox_fkine():
    """At 1000 random q, our tool is roboticstoolbox's Puma560().fkine(q), and qlim agrees."""
    rtb = pytest.importorskip(
        "roboticstoolbox", reason="roboticstoolbox-python is not installed (optional reference)"
    )
    puma = rtb.models.DH.Puma560()
    q_all, ours = puma_samples()
    theirs = np.array([np.asarray(puma.fkine(q).A) for q in q_all])
    position, rotation = pose_errors(ours, theirs)
    assert position < POS_TOL, f"{position=:.3e} m"
    assert rotation < ROT_TOL, f"{rotation=:.3e} rad"
    robot = load_robot("puma560")
    assert np.allclose(puma.qlim, [robot.lower, robot.upper], rtol=0.0, atol=1e-12), f"{puma.qlim=}"
