"""The IK judge against an independent NumPy DH product, and its batched twin against it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle

from dh2urdf import get_robot
from kin import batch_forward_kinematics, load_robot
from kin.ik.judge import (
    Measurement,
    ToolJudge,
    axis_error,
    batch_axis_errors,
    batch_pose_errors,
    measure,
    rotation_error,
)
from kin.ik.numeric.numeric_target import NumericTarget

ROBOTS = ["planar2", "pickplace3", "scorbot", "ur5", "humanoid7"]


def random_rotations(rng, n: int) -> np.ndarray:
    """Random rotations (n, 3, 3) from random quaternions."""
    w, x, y, z = rng.normal(size=(4, n))
    norm = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


@pytest.mark.parametrize("name", ROBOTS)
def test_scalar_and_batched_judge_match_a_numpy_dh_product(name):
    """Errors of random q against nearby targets: the judge (Pinocchio), its batched twin (kin's
    batched FK) and a plain NumPy DH product with the trace formula agree to 1e-9."""
    robot = load_robot(name)
    rng = np.random.default_rng(7)
    q = rng.uniform(robot.lower, robot.upper, size=(50, robot.nq))
    reference = fk_frames(load_reference(get_robot(name).table_path), q)[:, -1]
    # Targets near and far: small and large rotations, small and large offsets.
    scale = np.where(np.arange(50) < 25, 1e-3, 1.0)[:, None]
    positions = reference[:, :3, 3] + rng.normal(size=(50, 3)) * scale
    rotations = random_rotations(rng, 50)
    rotations[:25] = reference[:25, :3, :3] @ np.array(
        [[math.cos(1e-4), -math.sin(1e-4), 0], [math.sin(1e-4), math.cos(1e-4), 0], [0, 0, 1]]
    )
    expected_p = np.linalg.norm(reference[:, :3, 3] - positions, axis=-1)
    expected_r = rotation_angle(reference[:, :3, :3], rotations)

    judge = ToolJudge(robot)
    for i in range(50):
        p_err, r_err = judge.errors(q[i], positions[i].tolist(), rotations[i].ravel().tolist())
        assert p_err == pytest.approx(expected_p[i], abs=1e-9), f"{name=} {i=}"
        assert r_err == pytest.approx(expected_r[i], abs=1e-9), f"{name=} {i=}"
        assert judge.errors(q[i], positions[i].tolist(), None)[1] is None
    p_batch, r_batch = batch_pose_errors(
        batch_forward_kinematics(robot.table, q), positions, rotations
    )
    assert np.abs(p_batch - expected_p).max() < 1e-9, name
    assert np.abs(r_batch - expected_r).max() < 1e-9, name
    # Near targets: the small angle is measured, not rounded to 0.
    assert np.abs(r_batch[:25] - 1e-4).max() < 1e-9


def test_measure_reports_limits_and_zero_rotation_for_a_position():
    """``measure``: 0 rad for a position target; a joint past its limit is reported."""
    robot = load_robot("scorbot")
    q = 0.5 * (robot.lower + robot.upper)
    pose = ToolJudge(robot).tool_pose(q)
    target = NumericTarget.from_se3(pose, position_only=True)
    verdict = measure(robot, robot.model.createData(), q, target)
    assert verdict == Measurement(0.0, 0.0, True)
    q_out = q.copy()
    q_out[2] = robot.upper[2] + 1e-6
    verdict = measure(robot, robot.model.createData(), q_out, target)
    assert not verdict.within_limits and verdict.position_error > 0.0
    assert ToolJudge(robot).within_limits(robot.upper.tolist())


def test_angle_formulas_match_arccos():
    """``rotation_error`` and ``axis_error`` (scalar and batched) against arccos formulas."""
    rng = np.random.default_rng(3)
    a, b = random_rotations(rng, 200), random_rotations(rng, 200)
    by_trace = np.arccos(np.clip((np.trace(a.swapaxes(1, 2) @ b, axis1=1, axis2=2) - 1) / 2, -1, 1))
    for i in range(200):
        assert rotation_error(a[i].ravel().tolist(), b[i].ravel().tolist()) == pytest.approx(
            by_trace[i], abs=1e-7
        )
    u, v = rng.normal(size=(200, 3)), rng.normal(size=(200, 3))
    cosine = (u * v).sum(-1) / np.linalg.norm(u, axis=-1) / np.linalg.norm(v, axis=-1)
    expected = np.arccos(np.clip(cosine, -1, 1))
    assert np.abs(batch_axis_errors(u, v) - expected).max() < 1e-9
    for i in range(200):
        assert axis_error(u[i].tolist(), v[i].tolist()) == pytest.approx(expected[i], abs=1e-9)
