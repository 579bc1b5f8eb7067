"""Default seeds inside the limits, and the three failure statuses that say what is known."""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin
import pytest
from support.arm_tables import make_table
from support.solver_caps import NO_CAP

from kin import load_robot, robot_from_table
from kin.commands import ik
from kin.configuration import default_seed, seed_inside
from kin.ik import AxisTarget, PoseTarget, PositionTarget, get_solver
from kin.ik.analytic.branch_verification import how_far
from kin.ik.numeric.solver import NumericIK
from kin.ik.partial_pose import RANDOM_STARTS


def _tool(robot, q: np.ndarray) -> pin.SE3:
    """The tool pose of ``q`` by Pinocchio's forward kinematics on the model."""
    model, data = robot.model, robot.model.createData()
    pin.forwardKinematics(model, data, q)
    return pin.updateFramePlacement(model, data, model.getFrameId(robot.tool_frame)).copy()


def _four_joint_arm():
    """A general 4R arm (skewed twists: no closed form)."""
    table = make_table(
        [0.1, 0.3, 0.25, 0.05],
        [math.pi / 2, 0.3, -1.1, 0.7],
        [0.3, 0.05, 0.02, 0.1],
        [0, 0.2, 0, 0],
    )
    return robot_from_table(table)


def test_panda_default_seed_is_inside_its_limits_and_nearest_zero():
    """Panda's zero lies outside joint 4's range: its default seed is the box's point nearest 0."""
    robot = load_robot("panda")
    seed = default_seed(robot)
    assert np.all(seed >= robot.lower) and np.all(seed <= robot.upper), f"{seed=}"
    assert seed.tolist() == np.clip(np.zeros(7), robot.lower, robot.upper).tolist()
    assert seed[3] == robot.upper[3] < 0.0


@pytest.mark.parametrize("name", ["ur5", "puma560", "humanoid7"])
def test_an_arm_whose_zero_is_inside_keeps_zero(name):
    """Zero inside the limits: the default seed is zero, and a seed inside is kept as given."""
    robot = load_robot(name)
    assert not default_seed(robot).any(), f"{name=}"
    q = 0.5 * (robot.lower + robot.upper)
    assert seed_inside(robot, q) is q


def test_a_seed_outside_the_limits_gives_the_clipped_seeds_answer():
    """Panda from q = 0 (outside) answers as from q = 0 clipped into the limits."""
    robot = load_robot("panda")
    solver = get_solver(robot)
    clipped = np.clip(np.zeros(7), robot.lower, robot.upper)
    targets = [
        AxisTarget(np.array([0.5, 0.1, 0.4]), np.array([0.0, 0.0, -1.0])),
        PoseTarget(
            _tool(robot, np.array([0.3, -0.4, 0.2, -1.8, 0.1, 1.5, 0.4])).translation, np.eye(3)
        ),
    ]
    for target in targets:
        outside = solver.solve(target, np.zeros(7), timeout=NO_CAP)
        inside = solver.solve(target, clipped, timeout=NO_CAP)
        assert (outside.status, outside.method) == (inside.status, inside.method), f"{target=}"
        assert outside.success, f"{outside.message}"
        assert np.array_equal(outside.best.q, inside.best.q), f"{target=}"


def test_kin_ik_panda_axis_target_is_solved_on_target_inside_the_limits(capsys):
    """The issue's command: now solved, the tool at the point and its z axis along -z."""
    robot = load_robot("panda")
    argv = ["--robot", "panda", "--target", "0.5", "0.1", "0.4", "--axis", "0", "0", "-1"]
    assert ik.main([*argv, "--json"]) == 0, capsys.readouterr().err
    record = json.loads(capsys.readouterr().out)
    assert record["status"] == "ok"
    q = np.array(record["solutions"][0]["q"])
    assert np.all(q >= robot.lower) and np.all(q <= robot.upper), f"{q=}"
    pose = _tool(robot, q)
    assert np.linalg.norm(pose.translation - (0.5, 0.1, 0.4)) < 1e-5
    assert np.dot(pose.rotation[:, 2], (0.0, 0.0, -1.0)) > math.cos(1e-4)


def test_a_target_beyond_reach_is_out_of_reach():
    """Beyond the links laid end to end: proved unreachable, no search."""
    result = get_solver(_four_joint_arm()).solve(PoseTarget(np.array([5.0, 0, 0]), np.eye(3)))
    assert (result.success, result.status) == (False, "out_of_reach")
    assert result.distance_to_workspace > 3.0


@pytest.mark.parametrize("kind", ["position", "pose"])
def test_out_of_reach_within_the_reach_names_the_orientation_only_for_a_pose(kind):
    """A closed form's "no" within the reach: "not with this orientation" only when one was given."""
    solver = get_solver(load_robot("ur5"))
    point = np.array([0.0, 0.0, 0.05])  # 0.05 m from the base, within UR5's 1 m reach
    target = PositionTarget(point) if kind == "position" else PoseTarget(point, np.eye(3))
    message, gap = how_far(solver.robot, "no branch reaches the target", target, None)
    assert "within the arm's reach" in message and gap is None
    assert ("not with this orientation" in message) == (kind == "pose"), message


def test_an_orientation_a_four_joint_arm_lacks_is_not_found_after_every_start():
    """A reached point with its tool turned 1.2 rad: not_found, the starts named, no 'cannot'."""
    robot = _four_joint_arm()
    pose = _tool(robot, np.array([0.3, 0.5, -0.4, 0.8]))
    turned = pin.exp3(np.array([0.0, 1.2, 0.0])) @ pose.rotation
    result = get_solver(robot).solve(PoseTarget(pose.translation, turned), None, timeout=NO_CAP)
    assert (result.success, result.status) == (False, "not_found"), result.message
    assert f"({RANDOM_STARTS} of them random)" in result.message
    assert "reach" not in result.message.split(";")[0]
    assert result.rejected and result.rejected[0].rotation_error > 0.1


def test_a_partial_search_stopped_by_its_cap_says_timeout():
    """Panda's axis target (no closed form for it) at a 1 us cap: timeout, with the hint."""
    solver = get_solver(load_robot("panda"))
    target = AxisTarget(np.array([0.5, 0.1, 0.4]), np.array([0.0, 0.0, -1.0]))
    result = solver.solve(target, None, timeout=1e-6)
    assert (result.success, result.status) == (False, "timeout"), result.message
    assert "--timeout" in result.message


def test_the_numeric_pipeline_says_timeout_or_not_found_as_its_stop():
    """A pose under Panda's base: the deadline stops it (timeout); counted starts (not_found)."""
    solver = NumericIK(load_robot("panda"))
    target = PoseTarget(np.array([0.0, 0.0, -0.3]), np.eye(3))
    capped = solver.solve(target, None, timeout=0.02)
    assert (capped.success, capped.status) == (False, "timeout"), capped.message
    assert "--timeout" in capped.message
    counted = solver.solve(target, None, timeout=NO_CAP, max_attempts=3)
    assert (counted.success, counted.status) == (False, "not_found"), counted.message


def test_twenty_panda_axis_targets_give_the_same_answers_twice():
    """The partial-pose search is bounded by its starts: two runs give identical answers."""
    robot = load_robot("panda")
    rng = np.random.default_rng(7)
    targets = []
    for q in rng.uniform(robot.lower, robot.upper, size=(20, 7)):
        pose = _tool(robot, q)
        targets.append(AxisTarget(pose.translation, pose.rotation[:, 2]))
    runs = []
    for _ in range(2):
        solver = NumericIK(robot)  # a fresh solver each run
        runs.append([solver.solve(target, None) for target in targets])
    for first, second in zip(*runs):
        assert first.status == second.status != "timeout", first.message
        assert (first.best is None) == (second.best is None)
        if first.best is not None:
            assert np.array_equal(first.best.q, second.best.q)
    assert sum(result.success for result in runs[0]) >= 18
