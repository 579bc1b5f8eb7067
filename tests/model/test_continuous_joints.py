"""Continuous joints (URDF `continuous`, table `continuous = true`): limits [-pi, pi], and the
numeric solver moves across pi instead of stopping at it; the table format keeps the flag."""

from __future__ import annotations

import dataclasses
import math
import sys

import numpy as np
import pinocchio as pin
import pytest
from support.solver_caps import NO_CAP

from dh2urdf import get_robot, load_table, parse_table
from dh2urdf.table_writer import table_text
from kin import Configuration
from kin.ik import PoseTarget
from kin.ik.numeric.solver import NumericIK
from kin.robot_model import robot_from_table

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib


def _puma(continuous: bool):
    """PUMA 560 with joint 1 limited to [-pi, pi], continuous or not."""
    table = load_table(get_robot("puma560").table_path)
    first = dataclasses.replace(table.rows[0], lower=-math.pi, upper=math.pi, continuous=continuous)
    return robot_from_table(dataclasses.replace(table, rows=(first, *table.rows[1:])))


@pytest.mark.parametrize("continuous", [True, False])
def test_numeric_solver_crosses_pi_on_a_continuous_joint(continuous):
    """Targets at q1 = +-3.1 rad, seeds just across pi: on a continuous joint damped Newton goes
    through pi to the answer next to the seed (wrapped into [-pi, pi]); on a limited one it stops
    at pi and the answer comes from elsewhere (the contrast that makes the test able to fail)."""
    robot = _puma(continuous)
    solver = NumericIK(robot, closed_form=False)
    configuration = Configuration(robot)
    rng = np.random.default_rng(5)
    solved = near = 0
    for k in range(40):
        q = rng.uniform(robot.lower, robot.upper)
        q[0] = 3.1 if k % 2 else -3.1
        seed = q.copy()
        seed[0] = -q[0] + 0.02 * np.sign(q[0])  # just across pi
        seed[1:] += rng.uniform(-0.05, 0.05, size=robot.nq - 1)
        pose = configuration.fk(q)
        result = solver.solve(
            PoseTarget(pose.translation, pose.rotation), seed, timeout=NO_CAP, max_attempts=2
        )
        if result.success:
            answer = result.solutions[0].q
            assert -math.pi <= answer[0] <= math.pi
            reached = configuration.fk(answer)
            assert np.linalg.norm(reached.translation - pose.translation) < 1e-5
            assert np.linalg.norm(pin.log3(reached.rotation.T @ pose.rotation)) < 1e-4
            solved += 1
            gap = np.abs(np.remainder(answer - q + math.pi, 2 * math.pi) - math.pi).max()
            near += gap < 1e-4  # the answer next to the seed: the pose's own q
    if continuous:
        assert solved == 40 and near >= 38, (solved, near)
    else:
        assert near < 30, (solved, near)  # clamped at pi: mostly other answers


def test_table_file_keeps_the_continuous_flag():
    """continuous = true is written and read back; a prismatic continuous joint is refused."""
    robot = _puma(True)
    text = table_text(robot.table)
    assert "continuous = true" in text
    again = parse_table(tomllib.loads(text))
    assert [row.continuous for row in again.rows] == [True] + [False] * 5
    broken = text.replace('type = "revolute"', 'type = "prismatic"', 1)
    with pytest.raises(Exception, match="only a revolute joint can be continuous"):
        parse_table(tomllib.loads(broken))


def _ur5_wrist(continuous: bool):
    """UR5 with joint 6 limited to [-pi, pi], continuous or not."""
    table = load_table(get_robot("ur5").table_path)
    last = dataclasses.replace(table.rows[5], lower=-math.pi, upper=math.pi, continuous=continuous)
    return robot_from_table(dataclasses.replace(table, rows=(*table.rows[:5], last)))


@pytest.mark.parametrize("method", ["closed_form", "differential"])
@pytest.mark.parametrize("continuous", [True, False])
def test_path_crosses_pi_on_a_continuous_joint(continuous, method):
    """The tool turning about its z from q6 = 3.0 to 3.3 rad: on a continuous joint the path is
    followed, q6 going past pi without a jump; on a limited one it stops at the limit."""
    from kin.path import follow_path, line

    robot = _ur5_wrist(continuous)
    configuration = Configuration(robot)
    q0 = np.array([0.3, -1.2, 1.4, -0.5, 1.1, 3.0])
    q1 = q0.copy()
    q1[5] = 3.3 - 2.0 * math.pi  # the same pose as 3.3 rad
    start, end = configuration.fk(q0), configuration.fk(q1)
    path = line(
        PoseTarget(start.translation, start.rotation),
        PoseTarget(end.translation, end.rotation),
        12,
    )
    result = follow_path(robot, path, q0, method=method)
    if continuous:
        assert result.success, result.message
        assert result.max_joint_step < 0.1
        assert abs(result.q[-1, 5] - 3.3) < 1e-3  # past pi, not wrapped to -2.98
        for q, k in zip(result.q, range(len(result.q))):
            reached = configuration.fk(q)  # the same joint positions once wrapped
            assert np.linalg.norm(reached.translation - path.positions[k]) < 1e-5
    else:
        assert not result.success and result.stopped_at is not None


def test_mjcf_and_mujoco_model_leave_a_continuous_joint_unlimited():
    """The MJCF writer and the MuJoCo model of the robot: no limits on a continuous joint only."""
    mujoco = pytest.importorskip("mujoco")
    from dh2urdf.mjcf_writer import mjcf_string
    from kin.mujoco_model import load_mujoco_model

    robot = _ur5_wrist(True)
    for model in (
        mujoco.MjModel.from_xml_string(mjcf_string(robot.table)),
        load_mujoco_model(robot),
    ):
        limited = [bool(model.jnt_limited[model.joint(name).id]) for name in robot.joint_names]
        assert limited == [True] * 5 + [False]
