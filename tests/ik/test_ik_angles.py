"""kin.ik.angles and the judge's rotation error, against Pinocchio and plain formulas."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from kin.ik.angles import (
    SLACK,
    clip_cosines,
    clip_unit,
    quaternion_matrix,
    rpy_matrices,
    rpy_matrix,
    wrap,
    wrap_array,
)
from kin.ik.judge import rotation_angles, rotation_error


def test_wrap_gives_the_angle_in_minus_pi_to_pi_with_the_same_sine_and_cosine():
    """Random angles up to +-50 rad: in (-pi, pi], same sin and cos; -pi goes to pi."""
    angles = np.random.default_rng(2).uniform(-50.0, 50.0, 500)
    wrapped = wrap_array(angles)
    for angle, value in zip(angles, wrapped):
        assert -math.pi < wrap(angle) <= math.pi and wrap(angle) == value
        assert abs(math.sin(value) - math.sin(angle)) < 1e-12
        assert abs(math.cos(value) - math.cos(angle)) < 1e-12
    assert wrap(-math.pi) == math.pi and wrap_array(np.array([-math.pi]))[0] == math.pi
    assert math.isnan(wrap_array(np.array([math.nan]))[0])


def test_clip_unit_rounds_within_the_slack_and_rejects_beyond():
    """+-1 within SLACK beyond; None farther; inside unchanged; NaN stays NaN; arrays alike."""
    assert clip_unit(0.25) == 0.25 and clip_unit(-1.0) == -1.0
    assert clip_unit(1.0 + SLACK / 2) == 1.0 and clip_unit(-1.0 - SLACK / 2) == -1.0
    assert clip_unit(1.0 + 2 * SLACK) is None and clip_unit(-1.0 - 2 * SLACK) is None
    assert clip_unit(1.5, slack=1.0) == 1.0
    assert math.isnan(clip_unit(math.nan))  # type: ignore[arg-type]
    values = np.array([0.25, 1.0 + SLACK / 2, -1.0 - 2 * SLACK])
    out = clip_cosines(values)
    assert out[0] == 0.25 and out[1] == 1.0 and math.isnan(out[2])


def test_rpy_and_quaternion_matrices_are_pinocchios():
    """Random roll-pitch-yaw and quaternions: the same rotations as Pinocchio's."""
    rng = np.random.default_rng(5)
    rpy = rng.uniform(-math.pi, math.pi, (50, 3))
    batched = rpy_matrices(rpy)
    for row, matrix in zip(rpy, batched):
        expected = pin.rpy.rpyToMatrix(*row)
        assert np.abs(np.array(rpy_matrix(*row)) - expected).max() < 1e-15
        assert np.abs(matrix - expected).max() < 1e-15
    for w, x, y, z in rng.normal(size=(50, 4)):
        expected = pin.Quaternion(w, x, y, z).normalized().toRotationMatrix()
        assert np.abs(np.array(quaternion_matrix(w, x, y, z)) - expected).max() < 1e-14


def test_the_judges_rotation_error_is_the_angle_of_log3():
    """Scalar and batched: the angle of R_fk^T R_target, as |log3| gives it."""
    rng = np.random.default_rng(9)
    a = np.array([pin.rpy.rpyToMatrix(*v) for v in rng.uniform(-3, 3, (40, 3))])
    b = np.array([pin.rpy.rpyToMatrix(*v) for v in rng.uniform(-3, 3, (40, 3))])
    b[:10] = a[:10] @ np.array([pin.exp3(v) for v in rng.normal(scale=1e-6, size=(10, 3))])
    batched = rotation_angles(a, b)
    for i in range(40):
        expected = np.linalg.norm(pin.log3(a[i].T @ b[i]))
        assert abs(batched[i] - expected) < 1e-9
        assert abs(rotation_error(a[i].ravel().tolist(), b[i].ravel().tolist()) - expected) < 1e-9
