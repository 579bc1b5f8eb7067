"""Pinocchio FK of the generated URDFs (``kin``) equals a plain NumPy DH product of the tables."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, random_configurations, rotation_angle

from dh2urdf import get_robot, robot_names
from kin import Configuration, load_robot

#: Position tolerance [m] and rotation tolerance [rad] of the FK comparisons.
POS_TOL = 1e-9
ROT_TOL = 1e-9


def pose_errors(T1: np.ndarray, T2: np.ndarray) -> tuple[float, float]:
    """Largest position error [m] and rotation angle of R1^T R2 [rad] over batches of poses."""
    position = float(np.linalg.norm(T1[..., :3, 3] - T2[..., :3, 3], axis=-1).max())
    rotation = float(rotation_angle(T1[..., :3, :3], T2[..., :3, :3]).max())
    return position, rotation


@pytest.mark.parametrize("robot", robot_names())
def test_tool_pose_matches_numpy_dh_product(robot, fk_q, kin_poses):
    """At 1000 random q within limits, kin's T_world_tool equals the NumPy DH product."""
    frames, poses = kin_poses(robot)
    ref = load_reference(get_robot(robot).table_path)
    q = fk_q(robot)
    assert q.shape == (1000, ref.dof), f"{robot=}"
    assert np.all((q >= ref.lower) & (q <= ref.upper)), f"{robot=}"
    expected = fk_frames(ref, q)
    position, rotation = pose_errors(poses[:, -1], expected[:, -1])
    assert frames[-1] == "tool", f"{robot=}"
    assert position < POS_TOL, f"{robot=} tool position error {position:.3e} m"
    assert rotation < ROT_TOL, f"{robot=} tool rotation error {rotation:.3e} rad"


@pytest.mark.parametrize("robot", robot_names())
def test_intermediate_dh_frames_match_numpy_dh_product(robot, fk_q, kin_poses):
    """Every DH frame frame0..frame{n} of the URDF sits where the NumPy DH product puts it."""
    frames, poses = kin_poses(robot)
    expected = fk_frames(load_reference(get_robot(robot).table_path), fk_q(robot))
    for j, frame in enumerate(frames[:-1]):
        position, rotation = pose_errors(poses[:, j], expected[:, j])
        assert position < POS_TOL, f"{robot=} {frame=} position error {position:.3e} m"
        assert rotation < ROT_TOL, f"{robot=} {frame=} rotation error {rotation:.3e} rad"


@pytest.mark.parametrize("robot", robot_names())
def test_fast_fk_path_matches_update(robot, fk_q):
    """Configuration.fk(q) gives the same tool pose as update(q) and leaves self.q unchanged."""
    robot_model = load_robot(robot)
    configuration = Configuration(robot_model)
    for q in fk_q(robot)[:50]:
        fast = configuration.fk(np.array(q), "tool").homogeneous
        assert np.array_equal(configuration.q, np.zeros(robot_model.nq)), f"{robot=}"
        slow = Configuration(robot_model, q).transform_frame_to_world("tool").homogeneous
        assert np.abs(fast - slow).max() < 1e-15, f"{robot=}"


@pytest.mark.parametrize("robot", robot_names())
def test_fast_fk_path_leaves_current_poses_alone(robot, fk_q):
    """After fk(q2), transform_frame_to_world still gives the poses at the current q."""
    robot_model = load_robot(robot)
    q1, q2 = fk_q(robot)[:2]
    configuration = Configuration(robot_model, q1)
    before = configuration.transform_frame_to_world("tool").homogeneous
    moved = configuration.fk(np.array(q2), "tool").homogeneous
    after = configuration.transform_frame_to_world("tool").homogeneous
    assert np.abs(moved - before).max() > 1e-6, f"{robot=}: q1 and q2 must differ"
    assert np.array_equal(after, before), f"{robot=}: fk(q2) changed the pose at q = q1"
    assert np.array_equal(configuration.q, q1), f"{robot=}"


# Home (q = 0) tool positions stated in the table comments, papers or makers' data, [m].
HOME_TOOL_POSITIONS = {
    "humanoid7": (0.0965 + 0.28774 + 0.2804 + 0.1994, 0.0, 0.0),  # stretched along x
    "lab5": (0.105 + 0.100, 0.0, 0.105 - 0.150),  # stretched along x, tool pointing down
    "ned5": (0.438, 0.0, 0.01),  # (a2 + a3 + a4 + d5, 0, d1)
    "panda": (0.088, 0.0, 0.333 + 0.316 + 0.384 - 0.107),  # flange pointing down
    "pickplace3": (0.197 + 0.258, 0.010, 0.170),  # eqs. (8)-(10) at q = 0
    "planar2": (0.5, 0.0, 0.0),  # a1 + a2
    "scorbot": (0.603, 0.0, 0.349),  # the paper's 0T5 at q = 0
    "ur10": (
        0.612 + 0.5723,
        0.163941 + 0.0922,
        0.1273 - 0.1157,
    ),  # (-(a2 + a3), d4 + d6, d1 - d5): ROS base_link, the DH base frame turned by pi
    "ur3": (
        0.24365 + 0.21325,
        0.11235 + 0.0819,
        0.1519 - 0.08535,
    ),  # (-(a2 + a3), d4 + d6, d1 - d5): ROS base_link, the DH base frame turned by pi
    "ur5": (
        0.425 + 0.39225,
        0.10915 + 0.0823,
        0.089159 - 0.09465,
    ),  # (-(a2 + a3), d4 + d6, d1 - d5): ROS base_link, the DH base frame turned by pi
}


@pytest.mark.parametrize("robot", sorted(HOME_TOOL_POSITIONS))
def test_home_tool_position_is_the_documented_one(robot):
    """At q = 0 the tool is where the table's source says (e.g. SCORBOT (603, 0, 349) mm)."""
    configuration = Configuration(load_robot(robot))
    position = configuration.transform_frame_to_world("tool").translation
    assert np.allclose(position, HOME_TOOL_POSITIONS[robot], atol=1e-12), f"{robot=} {position=}"


# Tiny inline tables exercising what the shipped robots do not: prismatic joints, [base] and
# [tool] in both forms, cm / deg units, the modified convention with offsets.
INLINE_TABLES = {
    "standard_prismatic_base_rpy": """
        convention = "standard"
        length_unit = "cm"
        angle_unit = "deg"
        [[joints]]
        type = "revolute"
        a = 12.0
        alpha = 90.0
        d = 30.0
        theta = 15.0
        limits = [-170.0, 170.0]
        [[joints]]
        type = "prismatic"
        a = 0.0
        alpha = -90.0
        d = 5.0
        theta = 90.0
        limits = [0.0, 40.0]
        [[joints]]
        type = "revolute"
        a = 7.0
        alpha = 30.0
        d = -3.0
        theta = -45.0
        limits = [-120.0, 120.0]
        [base]
        xyz = [10.0, -20.0, 5.0]
        rpy = [30.0, -60.0, 135.0]
        [tool]
        xyz = [1.0, 2.0, 3.0]
        rpy = [-10.0, 20.0, 170.0]
    """,
    "modified_prismatic_dh_base_tool": """
        convention = "modified"
        length_unit = "mm"
        angle_unit = "rad"
        [[joints]]
        type = "prismatic"
        a = 0.0
        alpha = 0.0
        d = 100.0
        theta = 0.5
        limits = [-50.0, 250.0]
        [[joints]]
        type = "revolute"
        a = 80.0
        alpha = -1.2
        d = 20.0
        theta = 0.3
        limits = [-3.0, 3.0]
        [[joints]]
        type = "revolute"
        a = 150.0
        alpha = 1.5707963267948966
        d = 0.0
        theta = -0.7
        limits = [-2.0, 2.5]
        [base]
        a = 40.0
        alpha = 0.4
        d = 60.0
        theta = -1.1
        [tool]
        a = 0.0
        alpha = 3.0
        d = 55.0
        theta = 0.2
    """,
}


@pytest.mark.parametrize("name", sorted(INLINE_TABLES))
def test_inline_table_with_prismatic_base_and_tool_matches_numpy(name, tmp_path):
    """Tables with prismatic joints, base/tool transforms and cm/mm/deg units match NumPy too."""
    path = tmp_path / f"{name}.toml"
    path.write_text(textwrap.dedent(INLINE_TABLES[name]), encoding="utf-8")
    robot_model = load_robot(path)
    ref = load_reference(path)
    assert np.allclose(robot_model.lower, ref.lower) and np.allclose(
        robot_model.upper, ref.upper
    ), f"{name=}"
    frames = (*(f"frame{i}" for i in range(ref.dof + 1)), "tool")
    q_all = random_configurations(ref.lower, ref.upper, 200, seed=7)
    expected = fk_frames(ref, q_all)
    configuration = Configuration(robot_model)
    got = np.empty_like(expected)
    for k, q in enumerate(q_all):
        configuration.update(q)
        for j, frame in enumerate(frames):
            got[k, j] = configuration.transform_frame_to_world(frame).homogeneous
    position, rotation = pose_errors(got, expected)
    assert position < POS_TOL, f"{name=} position error {position:.3e} m"
    assert rotation < ROT_TOL, f"{name=} rotation error {rotation:.3e} rad"
