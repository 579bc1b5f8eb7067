"""The work of one IK call on a redundant arm on a mobile base (9 joints), counted, not timed.

The arm is the Robotics Toolbox's Frankie as its URDF declares it: a revolute and a prismatic base
joint with +-999,999 limits, then Panda's seven joints (the maker's joint origins and limits, no
meshes). Drawn over the rail's whole travel, every seed-table sample and random start was
kilometres from any target and every call fell through to the mink QP runs (83 steps a call,
15 of 200 reachable targets not found); :mod:`kin.ik.numeric.sampling_box` draws the rail within
the arm's size. The targets and the answers are checked by Pinocchio's FK of the URDF text.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from support.long_rail_arm import PANDA, frankie_urdf

from kin import load_robot
from kin.ik import PoseTarget, get_solver
from kin.ik.numeric.sampling_box import LONG_RAIL, arm_size, sampling_limits

#: Damped Newton and QP steps of one call, at most (a call that reaches the QP runs takes 60+).
STEP_BUDGET = 60


@pytest.fixture(scope="module")
def frankie(tmp_path_factory: pytest.TempPathFactory):
    path = tmp_path_factory.mktemp("frankie") / "frankie.urdf"
    path.write_text(frankie_urdf())
    return path


def test_rail_drawn_within_the_arm_and_other_joints_kept(frankie):
    robot = load_robot(frankie, "base0", "flange")
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    low, high = sampling_limits(robot.table, lower, upper)
    size = sum(abs(x) for xyz, *_ in PANDA for x in xyz) + 0.15 + 0.38 + 0.107
    assert arm_size(robot.table) == pytest.approx(size, abs=1e-9)
    rail = robot.joint_names.index("base_rail")
    assert (low[rail], high[rail]) == pytest.approx((-arm_size(robot.table), arm_size(robot.table)))
    others = [i for i in range(robot.nq) if i != rail]
    assert np.array_equal(low[others], lower[others])
    assert np.array_equal(high[others], upper[others])
    assert upper[rail] - lower[rail] > LONG_RAIL * arm_size(robot.table)


def test_an_arm_without_a_long_rail_keeps_its_limits():
    robot = load_robot("ur5")
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    low, high = sampling_limits(robot.table, lower, upper)
    assert low is lower and high is upper


def test_one_call_on_the_mobile_panda_is_a_few_damped_newton_steps(frankie):
    """30 reachable targets: each answered, on target by Pinocchio, in at most STEP_BUDGET steps."""
    robot = load_robot(frankie, "base0", "flange")
    solver = get_solver(robot)
    reference = pin.buildModelFromXML(frankie_urdf())
    data = reference.createData()
    tool = reference.getFrameId("flange")
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    rng = np.random.default_rng(7)
    seed = np.clip(np.zeros(robot.nq), lower, upper)
    steps = []
    for _ in range(30):
        q = rng.uniform(np.maximum(lower, -math.pi), np.minimum(upper, math.pi))
        pin.framesForwardKinematics(reference, data, q)
        target = data.oMf[tool].copy()
        result = solver.solve(PoseTarget(target.translation, target.rotation), seed)
        assert result.success, result.message
        assert result.method != "mink_qp"
        steps.append(result.iterations)
        answer = result.solutions[0].q
        assert np.all(answer >= lower - 1e-12) and np.all(answer <= upper + 1e-12)
        pin.framesForwardKinematics(reference, data, answer)
        reached = data.oMf[tool]
        assert np.linalg.norm(reached.translation - target.translation) < 1e-5
        assert np.linalg.norm(pin.log3(reached.rotation.T @ target.rotation)) < 1e-4
    assert max(steps) <= STEP_BUDGET, steps
