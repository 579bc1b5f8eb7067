"""The compiled twin of damped Newton's step (kin/_native/ik/numeric/_damped_step.c) against NumPy.

The twin solves ``J^T (J J^T + lam I)^-1 e`` by Cholesky in one call (NumPy's LU solve of the
same normal equations is the reference), measures the pose error with its own rotation vector
(Pinocchio's ``log3`` and the exact rotation vector ``exp3`` was given are the references) and
takes the bounded step (the Python arithmetic it replaces is the reference). A whole damped
Newton run with and without the twin reaches the same joint vector (to rounding) in the same
number of steps.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from kin import load_robot
from kin.ik.numeric import damped_newton as dn

needs_twin = pytest.mark.skipif(not dn.COMPILED, reason="kin/ik/numeric/_damped_step not built")


def numpy_step(jacobian: np.ndarray, error: np.ndarray, lam: float) -> np.ndarray:
    m = jacobian.shape[0]
    return jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + lam * np.eye(m), error)


@needs_twin
@pytest.mark.parametrize("shape", [(6, 7), (6, 6), (6, 12), (3, 7), (1, 1), (5, 3)])
def test_step_equals_numpys_solve(shape):
    from kin.ik.numeric._damped_step import damped_step

    rng = np.random.default_rng(sum(shape))
    for _ in range(200):
        jacobian = rng.normal(size=shape) * rng.uniform(0.01, 2.0)
        error = rng.normal(size=shape[0])
        lam = float(rng.choice([1e-9, 1e-3, 0.5]))
        out = np.full(shape[1], np.nan)
        assert damped_step(jacobian, error, lam, out) == 0
        expected = numpy_step(jacobian, error, lam)
        # Both solves lose digits with the normal matrix's condition number (J J^T squares J's).
        normal = jacobian @ jacobian.T + lam * np.eye(shape[0])
        tolerance = 1e-14 * np.linalg.cond(normal) * (np.abs(expected).max() + 1.0)
        np.testing.assert_allclose(out, expected, rtol=0, atol=tolerance)


@needs_twin
def test_step_declines_what_it_cannot_take_and_leaves_out_alone():
    from kin.ik.numeric._damped_step import damped_step

    rng = np.random.default_rng(1)
    good = rng.normal(size=(6, 7))
    cases = [
        (np.zeros((6, 7)), np.ones(6), 0.0, np.zeros(7), 1),  # singular, no damping
        (np.full((6, 7), np.nan), np.ones(6), 1e-3, np.zeros(7), 1),  # NaN
        (np.asfortranarray(good), np.ones(6), 1e-3, np.zeros(7), -1),  # not C order
        (good, np.ones(6), 1e-3, np.zeros(6), -1),  # out of the wrong size
        (good, np.ones(5), 1e-3, np.zeros(7), -1),  # error of the wrong size
        (good.astype(np.float32), np.ones(6), 1e-3, np.zeros(7), -1),  # not float64
        (np.ones((7, 7)), np.ones(7), 1e-3, np.zeros(7), -1),  # more than six rows
        (good, np.ones(6), -1.0, np.zeros(7), -1),  # negative damping
        ([[1.0]], [1.0], 0.0, np.zeros(1), -1),  # not arrays
    ]
    for jacobian, error, lam, out, code in cases:
        before = out.copy()
        assert damped_step(jacobian, error, lam, out) == code
        np.testing.assert_array_equal(out, before)
    read_only = np.zeros(7)
    read_only.flags.writeable = False
    assert damped_step(good, np.ones(6), 1e-3, read_only) == -1
    with pytest.raises(TypeError):
        damped_step(good, np.ones(6), 1e-3)
    with pytest.raises(TypeError):
        damped_step(good, np.ones(6), "lam", np.zeros(7))


@needs_twin
@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-6, 0.3, 2.0, 2.7, 3.0, np.pi - 1e-6, np.pi])
def test_pose_error_is_the_rotation_vector(angle):
    from kin.ik.numeric._damped_step import pose_error

    rng = np.random.default_rng(int(angle * 1000))
    for _ in range(200):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        orientation = pin.SE3.Random().rotation  # Pinocchio's view: column-major, any strides
        rotation = pin.exp3(axis * angle) @ orientation
        position, translation = rng.normal(size=3), rng.normal(size=3)
        e = np.full(6, np.nan)
        squared = pose_error(position, translation, rotation, orientation, e)
        np.testing.assert_array_equal(e[:3], position - translation)
        exact = axis * angle
        if angle > np.pi - 1e-5 and e[3:] @ exact < 0:  # a half turn: either direction
            exact = -exact
        np.testing.assert_allclose(e[3:], exact, rtol=0, atol=1e-14)
        reference = pin.log3(rotation @ orientation.T)
        assert abs(np.linalg.norm(e[3:]) - np.linalg.norm(reference)) < 1e-12
        assert squared[0] == pytest.approx(e[:3] @ e[:3], rel=1e-15, abs=0.0)
        assert squared[1] == pytest.approx(e[3:] @ e[3:], rel=1e-15, abs=0.0)
    assert pose_error(np.zeros(2), np.zeros(3), np.eye(3), np.eye(3), np.empty(6)) is None
    assert pose_error(np.zeros(3), np.zeros(3), np.eye(3), np.eye(3), np.empty(5)) is None


@needs_twin
def test_advance_is_the_python_arithmetic():
    from kin.ik.numeric._damped_step import advance

    rng = np.random.default_rng(5)
    lower, upper = -np.ones(7), np.ones(7)
    for _ in range(500):
        q = rng.uniform(-1.0, 1.0, 7)
        dq = rng.normal(scale=rng.choice([0.01, 0.3, 2.0]), size=7)
        bound = float(rng.choice([0.0, 0.5]))
        expected = dq.copy()
        if bound and np.abs(expected).max() > bound:
            expected *= bound / np.abs(expected).max()
        stepped = np.full(7, np.nan)
        inside = advance(dq, bound, q, lower, upper, stepped)
        np.testing.assert_array_equal(dq, expected)
        np.testing.assert_array_equal(stepped, q + expected)
        assert inside == int(np.all((q + expected >= lower) & (q + expected <= upper)))
    assert advance(np.zeros(6), 0.0, np.zeros(7), lower, upper, np.zeros(7)) == -1
    assert advance(np.zeros(7, np.float32), 0.0, np.zeros(7), lower, upper, np.zeros(7)) == -1


@needs_twin
@pytest.mark.parametrize("posture", [False, True])
@pytest.mark.parametrize("name", ["humanoid7", "panda", "ur5"])
def test_damped_newton_with_and_without_the_twin(name, posture):
    robot = load_robot(name)
    model = robot.model
    data = model.createData()
    frame = model.getFrameId("tool")
    rng = np.random.default_rng(2)
    converged = 0
    for _ in range(60):
        q = rng.uniform(robot.lower, robot.upper)
        pin.framesForwardKinematics(model, data, q)
        pose = data.oMf[frame]
        position, rotation = pose.translation.copy(), pose.rotation.copy()
        start = np.clip(q + rng.normal(scale=0.3, size=robot.nq), robot.lower, robot.upper)
        preferred = rng.uniform(robot.lower, robot.upper) if posture else None
        runs = [
            dn.damped_newton(
                model, data, frame, start, position, rotation, posture=preferred, compiled=twin
            )
            for twin in (True, False)
        ]
        alone = [  # a position target: the same steps with and without the twin, bit for bit
            dn.damped_newton(model, data, frame, start, position, None, compiled=twin)
            for twin in (True, False)
        ]
        np.testing.assert_array_equal(alone[0].q, alone[1].q)
        assert alone[0].iterations == alone[1].iterations
        assert runs[0].converged == runs[1].converged
        assert runs[0].iterations == runs[1].iterations
        np.testing.assert_allclose(runs[0].q, runs[1].q, rtol=0, atol=1e-9)
        if runs[0].converged:  # verified against Pinocchio's FK, not the run's own numbers
            converged += 1
            pin.framesForwardKinematics(model, data, runs[0].q)
            assert np.linalg.norm(data.oMf[frame].translation - position) < 1e-6
        assert np.all(runs[0].q >= robot.lower) and np.all(runs[0].q <= robot.upper)
    assert converged >= 40
