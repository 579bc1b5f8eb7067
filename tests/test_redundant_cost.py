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

from kin import load_robot
from kin.ik import PoseTarget, get_solver
from kin.ik.numeric.sampling_box import LONG_RAIL, arm_size, sampling_limits

HALF_PI = math.pi / 2
#: Panda's joints: (origin xyz [m], origin roll [rad], lower, upper [rad]), franka_description's.
PANDA = (
    ((0.0, 0.0, 0.333), 0.0, -2.8973, 2.8973),
    ((0.0, 0.0, 0.0), -HALF_PI, -1.7628, 1.7628),
    ((0.0, -0.316, 0.0), HALF_PI, -2.8973, 2.8973),
    ((0.0825, 0.0, 0.0), HALF_PI, -3.0718, -0.0698),
    ((-0.0825, 0.384, 0.0), -HALF_PI, -2.8973, 2.8973),
    ((0.0, 0.0, 0.0), HALF_PI, -0.0175, 3.7525),
    ((0.088, 0.0, 0.0), HALF_PI, -2.8973, 2.8973),
)

#: Damped Newton and QP steps of one call, at most (a call that reaches the QP runs takes 60+).
STEP_BUDGET = 60


def _joint(name: str, kind: str, parent: str, child: str, xyz: str, roll: float, limits: str):
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{roll!r} 0 0"/><axis xyz="{"1 0 0" if kind == "prismatic" else "0 0 1"}"/>'
        f'<limit lower="{limits.split()[0]}" upper="{limits.split()[1]}" effort="1" velocity="1"/>'
        "</joint>"
    )


def frankie_urdf() -> str:
    """Panda on a revolute and a prismatic base joint of +-999,999 (rad, m), tool at flange."""
    links = ["base0", "base1", "rail", *(f"link{i}" for i in range(1, 8)), "flange"]
    joints = [
        _joint("base_turn", "revolute", "base0", "base1", "0 0 0", 0.0, "-999999 999999"),
        _joint("base_rail", "prismatic", "base1", "rail", "0 0 0", 0.0, "-999999 999999"),
        '<joint name="mount" type="fixed"><parent link="rail"/><child link="link0"/>'
        '<origin xyz="0.15 0 0.38"/></joint>',
    ]
    for i, (xyz, roll, lower, upper) in enumerate(PANDA, start=1):
        parent = f"link{i - 1}"
        joints.append(
            _joint(
                f"joint{i}",
                "revolute",
                parent,
                f"link{i}",
                " ".join(map(str, xyz)),
                roll,
                f"{lower} {upper}",
            )
        )
    joints.append(
        '<joint name="flange_joint" type="fixed"><parent link="link7"/><child link="flange"/>'
        '<origin xyz="0 0 0.107"/></joint>'
    )
    body = "".join(f'<link name="{name}"/>' for name in [*links, "link0"]) + "".join(joints)
    return f'<?xml version="1.0"?><robot name="frankie_kinematics">{body}</robot>'


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
