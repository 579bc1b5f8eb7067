"""kin.plan.plan: certified collision-free paths, judged by a coal check built apart from kin.

The reference (tests/support/collision_reference.py) places the URDF's shapes by Pinocchio's FK of the
robot's URDF text and asks coal pair by pair; a returned path is resampled at 0.005 rad (the
largest joint step between two checked configurations) and every configuration must be apart.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.collision_reference import CollisionReference
from support.plan_support import _resampled

from kin import JointVectorError, NotWithinLimitsError, load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.requests import CONTACT_TOLERANCE
from kin.ik import PoseTarget, PositionTarget
from kin.plan import PLANNERS, PlanError, plan

#: The README's example cell (a table, a wall in front, a ball to the side).
CELL = Path(__file__).resolve().parents[2] / "examples" / "cell.toml"
#: A ball just inside planar2's reach on its x axis (the straight swing from -90 to +90 deg of
#: the first joint, elbow straight, passes through it; folding the elbow passes it by).
BALL = "[[sphere]]\nname = 'ball'\nradius = 0.04\nxyz = [0.45, 0.0, 0.0]\n"


@pytest.fixture(scope="module")
def planar(tmp_path_factory):
    """planar2 with the ball: robot, checker, reference, the pairs the reference judges."""
    scene = tmp_path_factory.mktemp("plan") / "ball.toml"
    scene.write_text(BALL, encoding="utf-8")
    robot = load_robot("planar2")
    model = load_collision_model(robot, scene=scene)
    reference = CollisionReference(robot.urdf, None, robot.joint_names, None, scene)
    pairs = [(link, "ball") for link in reference.links]
    pairs += [p for p in model.pairs if p[1] != "ball"]
    return robot, CollisionChecker(model), reference, pairs


def _assert_free(reference: CollisionReference, pairs, path: np.ndarray) -> None:
    for q in _resampled(path):
        closest = min(d for d, _ in reference.signed_distances(q, pairs).values())
        assert closest > -CONTACT_TOLERANCE, (q, closest)


def test_the_straight_swing_collides_and_the_plan_goes_around(planar):
    robot, checker, reference, pairs = planar
    start, goal = np.radians([-90.0, 0.0]), np.radians([90.0, 0.0])
    straight = np.array([start, goal])
    worst = min(
        min(d for d, _ in reference.signed_distances(q, pairs).values())
        for q in _resampled(straight)
    )
    assert worst < -0.01  # the ball is in the way of the straight swing (reference's verdict)
    result = plan(robot, start, goal, collisions=checker, seed=3)
    assert result.status == "ok", result.message
    assert np.array_equal(result.path[0], start) and np.allclose(result.path[-1], goal)
    assert (result.path >= robot.lower).all() and (result.path <= robot.upper).all()
    assert len(result.path) > 2 and result.length > result.straight_length
    assert result.clearance is not None and result.clearance > 0.0
    _assert_free(reference, pairs, result.path)


def test_the_same_seed_gives_the_same_path_and_every_planner_a_free_one(planar):
    robot, checker, reference, pairs = planar
    start, goal = np.radians([-90.0, 0.0]), np.radians([90.0, 0.0])
    first = plan(robot, start, goal, collisions=checker, seed=7, time_limit=math.inf)
    again = plan(robot, start, goal, collisions=checker, seed=7, time_limit=math.inf)
    assert np.array_equal(first.path, again.path) and first.checks == again.checks
    for name in ("RRT", "KPIECE1", "BKPIECE1", "BITstar"):
        result = plan(robot, start, goal, collisions=checker, planner=name, seed=1)
        assert result.status == "ok" and result.planner == name, result.message
        _assert_free(reference, pairs, result.path)


def test_an_open_straight_motion_is_the_path(planar):
    robot, checker, reference, pairs = planar
    start, goal = np.radians([100.0, 10.0]), np.radians([170.0, -30.0])
    result = plan(robot, start, goal, collisions=checker)
    assert result.status == "ok" and len(result.path) == 2
    assert result.length == pytest.approx(float(np.linalg.norm(goal - start)))
    _assert_free(reference, pairs, result.path)


def test_a_pose_target_ends_on_target_at_a_free_branch(planar):
    """The target's IK branches are the goals; the path's end is on target (Pinocchio FK)."""
    robot, checker, reference, pairs = planar
    q_goal = np.radians([60.0, -70.0])
    model = pin.buildModelFromXML(robot.urdf)
    data = model.createData()
    frame = model.getFrameId(robot.tool_frame)
    pin.framesForwardKinematics(model, data, q_goal)
    target = PositionTarget(np.array(data.oMf[frame].translation))
    result = plan(robot, np.radians([-90.0, 0.0]), target, collisions=checker, seed=2)
    assert result.status == "ok", result.message
    assert len(result.goals) >= 2  # elbow up and elbow down
    pin.framesForwardKinematics(model, data, result.path[-1])
    assert np.linalg.norm(data.oMf[frame].translation - target.position) < 1e-6
    _assert_free(reference, pairs, result.path)


def test_statuses_say_why_there_is_no_path(planar):
    robot, checker, _, _ = planar
    inside = np.radians([0.0, 0.0])  # the forearm through the ball
    free = np.radians([-90.0, 0.0])
    assert checker.in_collision(inside)
    result = plan(robot, inside, free, collisions=checker)
    assert result.status == "start_in_collision" and "ball" in result.message
    assert len(result.path) == 0 and not result.success
    result = plan(robot, free, inside, collisions=checker)
    assert result.status == "goal_in_collision" and "ball" in result.message
    far = PositionTarget(np.array([2.0, 0.0, 0.0]))
    assert plan(robot, free, far, collisions=checker).status == "out_of_reach"
    tight = plan(robot, free, np.radians([90.0, 0.0]), collisions=checker, max_checks=5)
    assert tight.status == "not_found" and "5 checks" in tight.message
    capped = plan(robot, free, np.radians([90.0, 0.0]), collisions=checker, time_limit=1e-9)
    assert capped.status == "timeout"


def test_bad_requests_are_one_error_each(planar):
    robot, checker, _, _ = planar
    free = np.radians([-90.0, 0.0])
    with pytest.raises(PlanError, match="unknown planner 'RRTx'; choose one of: RRTConnect"):
        plan(robot, free, free, collisions=checker, planner="RRTx")
    with pytest.raises(JointVectorError):
        plan(robot, [math.nan, 0.0], free, collisions=checker)
    with pytest.raises(JointVectorError):
        plan(robot, free, [0.0, 0.0, 0.0], collisions=checker)
    with pytest.raises(NotWithinLimitsError):
        plan(robot, free, [4.0, 0.0], collisions=checker)
    for options in ({"time_limit": 0.0}, {"max_checks": 0}, {"seed": -1}, {"seed": 1.5}):
        with pytest.raises(PlanError):
            plan(robot, free, free, collisions=checker, **options)
    assert "RRTConnect" in PLANNERS and "PRM" not in PLANNERS  # PRM's own thread: a deadlock


@pytest.mark.parametrize("where", ["checker", "spheres"])
def test_a_ctrl_c_inside_a_check_is_raised_once_ompl_has_returned(planar, monkeypatch, where):
    """The KeyboardInterrupt of a callback stops the search and comes out of plan().

    Raised by the collision checker (the spheres' checks left out, so that every check is the
    checker's) or by the spheres' motion check (the search on the spheres alone).
    """
    import kin.plan.ompl_problem as ompl_problem
    from kin.plan.sphere_motion import SphereMotion

    robot, checker, _, _ = planar
    calls = [0]
    most = 40 if where == "checker" else 3  # the spheres: past the straight motion's check

    def counted() -> None:
        calls[0] += 1
        if calls[0] > most:
            raise KeyboardInterrupt

    class Interrupted(CollisionChecker):
        def in_collision(self, q):
            counted()
            return super().in_collision(q)

    if where == "checker":
        monkeypatch.setattr(ompl_problem, "sphere_motion", lambda model: None)
        collisions = Interrupted(checker.model)
    else:
        motion_free = SphereMotion.motion_free

        def interrupted(self, *args):
            counted()
            return motion_free(self, *args)

        monkeypatch.setattr(SphereMotion, "motion_free", interrupted)
        collisions = CollisionChecker(checker.model)
    with pytest.raises(KeyboardInterrupt):
        plan(robot, np.radians([-90.0, 0.0]), np.radians([90.0, 0.0]), collisions=collisions)


def test_a_ur5_pose_in_the_example_cell():
    """Every branch of a UR5 pose is offered; the path reaches one, free by the reference."""
    robot = load_robot("ur5")
    model = load_collision_model(robot, scene=CELL)
    checker = CollisionChecker(model)
    reference = CollisionReference(robot.urdf, None, robot.joint_names, None, Path(CELL))
    pairs = [(link, obj) for link in reference.links for obj in reference.scene_names]
    pairs += [p for p in model.pairs if p[1] not in reference.scene_names]
    q_goal = np.array([2.0, -1.2, 1.2, -1.6, -1.5, 0.3])  # the straight pan crosses the wall
    assert not checker.in_collision(q_goal)
    pin_model = pin.buildModelFromXML(robot.urdf)
    data = pin_model.createData()
    frame = pin_model.getFrameId(robot.tool_frame)
    pin.framesForwardKinematics(pin_model, data, q_goal)
    pose = data.oMf[frame]
    target = PoseTarget(np.array(pose.translation), np.array(pose.rotation))
    start = np.array([-1.2, -1.3, 1.4, -1.6, -1.5, 0.0])
    result = plan(robot, start, target, collisions=checker, seed=0)
    assert result.status == "ok", result.message
    assert len(result.goals) >= 2
    pin.framesForwardKinematics(pin_model, data, result.path[-1])
    assert np.linalg.norm(data.oMf[frame].translation - pose.translation) < 1e-6
    _assert_free(reference, pairs, result.path)
