"""Cartesian paths: samples on the line, IK along them on one branch, honest stops."""

from __future__ import annotations

import functools
import importlib

import numpy as np
import pinocchio as pin
import pytest

from kin import Configuration, load_robot
from kin.ik import PitchTarget, PoseTarget, PositionTarget, get_solver
from kin.path import PathError, follow_path, line, polyline

#: Start configurations well inside the workspace, away from singularities.
STARTS = {
    "humanoid7": [0.2, 0.3, 0.1, 1.0, 0.1, 0.4, 0.1],
    "lab5": [0.3, 0.4, -0.6, 0.2, 0.1],
    "pickplace3": [0.3, 0.4, -0.6],
    "scorbot": [0.3, 0.4, -0.6, 0.2, 0.1],
    "ur5": [0.2, -1.0, 1.5, -0.5, 1.2, 0.3],
}
#: Tool displacement of the test lines [m] (|d| = 0.054 m).
DISPLACEMENT = np.array([-0.04, 0.02, 0.03])
STEPS = 30


@functools.cache
def tool_pose(name: str) -> pin.SE3:
    robot = load_robot(name)
    return Configuration(robot, np.array(STARTS[name])).transform_frame_to_world("tool")


def start_and_end(name: str) -> tuple:
    """Waypoints of the kind the robot's solver takes (pitch for five-joint arms)."""
    T = tool_pose(name)
    p = T.translation
    if name == "pickplace3":
        return PositionTarget(p), PositionTarget(p + DISPLACEMENT)
    if name in ("lab5", "scorbot"):
        return PitchTarget(p, 0.3), PitchTarget(p + DISPLACEMENT, 0.3)
    turned = T.rotation @ pin.exp3(np.array([0.0, 0.0, 0.2]))
    return PoseTarget(p, T.rotation), PoseTarget(p + DISPLACEMENT, turned)


def test_line_samples_are_on_the_segment_with_slerped_orientation():
    """Positions move linearly, the orientation turns at a constant rate about one axis."""
    a = PoseTarget.from_rpy([0.1, 0.2, 0.3], [0.0, 0.0, 0.0])
    b = PoseTarget.from_rpy([0.5, 0.2, 0.1], [0.0, 0.0, 1.0])
    path = line(a, b, 10)
    assert len(path) == 11 and path.waypoint_indices == (0, 10)
    np.testing.assert_allclose(path.positions[5], [0.3, 0.2, 0.2], atol=1e-15)
    angles = [np.linalg.norm(pin.log3(a.rotation.T @ R)) for R in path.rotations]
    np.testing.assert_allclose(angles, np.linspace(0.0, 1.0, 11), atol=1e-12)
    assert path.length == pytest.approx(np.hypot(0.4, 0.2), abs=1e-12)


def test_polyline_passes_through_every_waypoint_with_steps_by_length():
    """Each waypoint is a sample; steps are shared in proportion to the segment lengths."""
    points = [[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.3, 0.1, 0.0]]
    path = polyline([PositionTarget(p) for p in points], 10)
    assert path.waypoint_indices == (0, 7, 10)
    for index, point in zip(path.waypoint_indices, points):
        np.testing.assert_allclose(path.positions[index], point, atol=1e-15)
    assert np.allclose(np.diff(path.positions[:8, 0]), 0.3 / 7)


def test_bad_paths_raise_path_error():
    """Mixed waypoint kinds and fewer steps than segments are refused with a PathError."""
    p = PositionTarget([0.0, 0.0, 0.0])
    with pytest.raises(PathError, match="waypoint 2"):
        polyline([p, PoseTarget.from_rpy([1.0, 0.0, 0.0], [0.0, 0.0, 0.0])], 4)
    with pytest.raises(PathError, match="at least 2"):
        polyline([p, p, p], 1)


@pytest.mark.parametrize("name", ["scorbot", "lab5", "pickplace3", "ur5", "humanoid7"])
def test_line_inside_the_workspace_is_followed_closely_on_one_branch(name):
    """Deviation < 1e-4 m (samples and midpoints), joint steps < 20 rad/m x step, no branch change."""
    robot = load_robot(name)
    result = follow_path(robot, line(*start_and_end(name), STEPS), STARTS[name])
    step_length = np.linalg.norm(DISPLACEMENT) / STEPS
    assert result.success and result.stopped_at is None, f"{name=} {result.message}"
    assert result.q.shape == (STEPS + 1, robot.nq)
    assert result.max_deviation < 1e-4, f"{name=} {result.max_deviation=}"
    assert result.max_joint_step < 20.0 * step_length, f"{name=} {result.max_joint_step=}"
    assert result.branch_changes == ()
    assert len(set(result.branches)) == 1
    assert (result.q >= robot.lower).all() and (result.q <= robot.upper).all()
    if result.max_rotation_error is not None:
        assert result.max_rotation_error < 1e-4, f"{name=}"
    expected = "differential" if name == "humanoid7" else "closed_form"
    assert result.method == expected


def test_closed_form_path_is_exact_at_the_samples():
    """scorbot in closed form: the tool is on each sample to 1e-9 m."""
    from kin.batch_fk import batch_tool_positions

    robot = load_robot("scorbot")
    path = line(*start_and_end("scorbot"), STEPS)
    result = follow_path(robot, path, STARTS["scorbot"])
    error = np.linalg.norm(batch_tool_positions(robot.table, result.q) - path.positions, axis=1)
    assert error.max() < 1e-9


def test_humanoid7_consecutive_solutions_stay_close():
    """humanoid7's joints move < 0.01 rad per 1.8 mm step (a numeric solve per sample: 0.45)."""
    robot = load_robot("humanoid7")
    result = follow_path(robot, line(*start_and_end("humanoid7"), STEPS), STARTS["humanoid7"])
    assert result.success, result.message
    assert result.max_joint_step < 0.01, result.max_joint_step
    np.testing.assert_allclose(result.q[0], STARTS["humanoid7"], atol=1e-9)


def test_line_past_a_joint_limit_stops_there_without_a_jump():
    """scorbot's base (+-155 deg) stops a line that runs behind the arm: joint limit, small steps."""
    robot = load_robot("scorbot")
    path = line(PitchTarget([-0.35, 0.35, 0.3], 0.3), PitchTarget([-0.35, -0.35, 0.3], 0.3), 40)
    result = follow_path(robot, path)
    assert not result.success and result.stopped_at == 11
    assert "joint limit" in result.message and "'base'" in result.message
    assert len(result.q) == result.stopped_at
    assert result.max_joint_step < 0.1


@pytest.mark.parametrize("name", ["scorbot", "humanoid7", "ur5"])
def test_line_leaving_the_workspace_reports_stopped_at(name):
    """A line out of reach stops at a sample, every step before it below the jump bound."""
    robot = load_robot(name)
    T = tool_pose(name)
    if name == "scorbot":
        a, b = PitchTarget(T.translation, 0.3), PitchTarget(T.translation * 3.0, 0.3)
    else:
        a, b = PositionTarget(T.translation), PositionTarget(T.translation * 3.0)
    result = follow_path(robot, line(a, b, 40), STARTS[name])
    assert not result.success and result.stopped_at is not None, f"{name=}"
    assert 0 < result.stopped_at < 40 and len(result.q) == result.stopped_at
    assert result.max_joint_step <= 0.35, f"{name=}"
    assert result.message.startswith(f"stopped at sample {result.stopped_at}: ")


class RelabelledSolver:
    """scorbot's closed form with the branch labels renamed from sample ``switch`` on."""

    def __init__(self, robot, switch_x: float):
        self.solver = get_solver(robot)
        self.switch_x = switch_x
        self.target_kinds = self.solver.target_kinds
        # the interface's parts: a closed form's (a path asks them, not the class)
        self.closed_form_kinds = self.solver.closed_form_kinds
        self.numeric = self.solver.numeric
        self.partial = self.solver.partial
        self.route = self.solver.route

    def solve(self, target, seed=None, *, timeout=None, all_branches=False):
        result = self.solver.solve(target, seed, timeout=timeout)
        if target.position[0] < self.switch_x:
            return result
        result_type = importlib.import_module("kin.ik.result")
        renamed = tuple(
            result_type.IKSolution(
                s.q, s.branch + " (renamed)", s.within_limits, s.position_error, s.rotation_error
            )
            for s in result.solutions
        )
        return result_type.IKResult(
            result.success, result.solver, result.status, result.message, renamed
        )


def test_unstable_labels_are_followed_by_nearest_and_recorded():
    """When a branch label changes under a continuous motion, the change index is recorded."""
    robot = load_robot("scorbot")
    path = line(PitchTarget([0.45, 0.0, 0.3], 0.3), PitchTarget([0.55, 0.0, 0.3], 0.3), 10)
    solver = RelabelledSolver(robot, switch_x=0.5 - 1e-9)
    result = follow_path(robot, path, solver=solver)
    assert result.success, result.message
    assert result.branch_changes == (5,)
    assert result.branches[5].endswith("(renamed)") and not result.branches[4].endswith("ed)")
    assert result.max_joint_step < 0.1


def test_unknown_start_branch_names_the_branches():
    """--branch that the first sample does not have: PathError listing its branches."""
    robot = load_robot("scorbot")
    with pytest.raises(PathError, match="shoulder front, elbow up"):
        follow_path(robot, line(*start_and_end("scorbot"), 4), branch="no such branch")


def test_start_branch_is_kept():
    """The chosen start branch is the branch of every sample."""
    robot = load_robot("lab5")
    result = follow_path(robot, line(*start_and_end("lab5"), 6), branch="shoulder back, elbow down")
    assert result.success, result.message
    assert set(result.branches) == {"shoulder back, elbow down"}


def test_continuation_a_turn_past_a_limit_is_a_joint_limit_stop():
    """lab5 shoulder back, elbow up: the shoulder would pass -180 deg; the stop names the joint."""
    robot = load_robot("lab5")
    path = line(*start_and_end("lab5"), 6)
    result = follow_path(robot, path, branch="shoulder back, elbow up")
    assert result.stopped_at == 1 and len(result.q) == 1
    assert "joint limit: joint 'shoulder'" in result.message
