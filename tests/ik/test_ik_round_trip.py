"""Closed-form IK by round trip: FK(q) -> IK -> every branch reproduces the pose, q is among them."""

import math

import numpy as np
import pytest

import kin
from kin.ik import (
    BatchSolver,
    ClosedFormSolver,
    PitchTarget,
    PoseTarget,
    PositionTarget,
)

SMALL_ROBOTS = ["lab5", "ned5", "pickplace3", "planar2", "scorbot"]
SAMPLES = 10_000
#: Configurations closer than this to a singularity (|sin q3| or distance of the wrist to the base
#: axis, or to the shoulder-offset cylinder [m]) are counted, not required to come back exactly.
SINGULAR_MARGIN = 1e-6


def _angle_gap(a, b):
    return np.abs(np.remainder(np.asarray(a) - np.asarray(b) + np.pi, 2 * np.pi) - np.pi)


def _near_singular(robot, q):
    elbow = q[1] if robot.nq == 2 else q[2]
    return (
        abs(math.sin(elbow + robot.table.rows[1 if robot.nq == 2 else 2].theta)) < SINGULAR_MARGIN
    )


@pytest.mark.parametrize("name", SMALL_ROBOTS)
def test_round_trip_every_branch_on_target_and_q_among_them(name):
    """10,000 seeded q within limits: every solution within 1e-9 m / 1e-9 rad, q among them."""
    robot = kin.load_robot(name)
    solver = ClosedFormSolver(robot)
    configuration = kin.Configuration(robot)
    rng = np.random.default_rng(3)
    missing, near_singular = 0, 0
    for _ in range(SAMPLES):
        q = rng.uniform(robot.lower, robot.upper)
        pose = configuration.fk(q)
        target = PositionTarget(pose.translation) if robot.nq < 5 else PoseTarget.from_matrix(pose)
        result = solver.solve(target)
        solutions = result.solutions + result.rejected
        assert result.success or result.status == "outside_limits", f"{name=} {q=} {result.message}"
        for solution in solutions:
            assert solution.position_error <= 1e-9, f"{name=} {q=}"
            if isinstance(target, PositionTarget):  # the orientation is free: not measured
                assert solution.rotation_error is None, f"{name=} {q=}"
            else:
                assert solution.rotation_error <= 1e-9, f"{name=} {q=}"
        if not any(_angle_gap(s.q, q).max() < 1e-6 for s in solutions):
            if _near_singular(robot, q):
                near_singular += 1
            else:
                missing += 1
    assert missing == 0, f"{name=}: {missing} q not found"
    assert near_singular <= SAMPLES // 1000, f"{name=}: {near_singular} near-singular samples"


@pytest.mark.parametrize("name", SMALL_ROBOTS)
def test_seed_picks_the_original_configuration_first(name):
    """With the original q as seed, the first solution is q itself (2 pi copies included)."""
    robot = kin.load_robot(name)
    solver = ClosedFormSolver(robot)
    configuration = kin.Configuration(robot)
    rng = np.random.default_rng(7)
    for _ in range(200):
        q = rng.uniform(robot.lower, robot.upper)
        pose = configuration.fk(q)
        target = PositionTarget(pose.translation) if robot.nq < 5 else PoseTarget.from_matrix(pose)
        result = solver.solve(target, seed=q)
        assert result.success, f"{name=} {q=}"
        np.testing.assert_allclose(result.solutions[0].q, q, atol=1e-6, err_msg=f"{name=}")


@pytest.mark.parametrize("name", ["lab5", "ned5", "scorbot"])
def test_pitch_targets_round_trip(name):
    """Position + pitch + roll targets made from FK come back on target with q among the branches."""
    robot = kin.load_robot(name)
    solver = ClosedFormSolver(robot)
    configuration = kin.Configuration(robot)
    rng = np.random.default_rng(11)
    axis_in_tool = solver.structure.R_roll_tool[2, :]
    for _ in range(1000):
        q = rng.uniform(robot.lower, robot.upper)
        pose = configuration.fk(q)
        p, a = pose.translation, pose.rotation @ axis_in_tool
        if math.hypot(p[0], p[1]) < 1e-6:
            continue
        h = p[:2] / math.hypot(p[0], p[1])
        pitch = math.atan2(-a[2], a[:2] @ h)
        result = solver.solve(PitchTarget(p, pitch, roll=q[4]))
        solutions = result.solutions + result.rejected
        assert all(s.position_error <= 1e-9 and s.rotation_error <= 1e-9 for s in solutions), (
            f"{name=}"
        )
        assert any(_angle_gap(s.q, q).max() < 1e-6 for s in solutions), f"{name=} {q=}"


def test_lab5_pitch_is_ninety_minus_theta234_with_shoulder_in_front():
    """002 eq. (9): for lab5, shoulder front, pitch = 90 deg - (q2 + q3 + q4)."""
    solver = ClosedFormSolver(kin.load_robot("lab5"))
    result = solver.solve(
        PitchTarget([0.22, 0.161, 0.22], math.radians(11.0), roll=math.radians(90))
    )
    for solution in result.solutions:
        if solution.branch.startswith("shoulder front"):
            assert math.degrees(solution.q[1:4].sum()) == pytest.approx(79.0, abs=1e-9)


@pytest.mark.parametrize("name", SMALL_ROBOTS)
def test_batch_agrees_with_scalar_and_pinocchio(name):
    """The batched solver finds q, kin's batched FK matches Pinocchio, same valid count as scalar."""
    robot = kin.load_robot(name)
    configuration = kin.Configuration(robot)
    rng = np.random.default_rng(5)
    q = rng.uniform(robot.lower, robot.upper, size=(500, robot.nq))
    poses = kin.batch_forward_kinematics(robot.table, q)
    for i in range(0, 500, 50):
        np.testing.assert_allclose(poses[i], configuration.fk(q[i]).homogeneous, atol=1e-12)
    batch = BatchSolver(robot)
    result = batch.solve_positions(poses[:, :3, 3]) if robot.nq < 5 else batch.solve_poses(poses)
    found = (np.nan_to_num(_angle_gap(result.q, q[:, None, :]).max(-1), nan=9.0) < 1e-6).any(1)
    assert found.all(), f"{name=}"
    scalar = ClosedFormSolver(robot)
    for i in range(0, 500, 25):
        target = (
            PositionTarget(poses[i, :3, 3]) if robot.nq < 5 else PoseTarget.from_matrix(poses[i])
        )
        assert len(scalar.solve(target).solutions) == int(result.valid[i].sum()), f"{name=} {i=}"
