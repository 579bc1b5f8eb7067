"""Frame Jacobians (LOCAL, LOCAL_WORLD_ALIGNED) equal central finite differences on SE(3)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from support.dh_reference import random_configurations

from dh2urdf import robot_names
from kin import Configuration, load_robot

#: Finite-difference step [rad] or [m], configurations per robot, and tolerance [m or rad per unit].
STEP = 1e-6
SAMPLES = 20
TOL = 1e-8


def all_frames(robot_model) -> tuple[str, ...]:
    """DH frames frame0..frame{n} and the tool."""
    return (*(f"frame{i}" for i in range(robot_model.nq + 1)), robot_model.tool_frame)


def frame_poses(
    model: pin.Model, data: pin.Data, q: np.ndarray, frames: tuple[str, ...]
) -> list[pin.SE3]:
    """``T_world_frame`` of each frame at q."""
    pin.framesForwardKinematics(model, data, q)
    return [data.oMf[model.getFrameId(f)].copy() for f in frames]


def finite_difference_jacobians(robot_model, q: np.ndarray, frames: tuple[str, ...]):
    """Central differences of each frame's pose along each joint, integrated with pin.integrate.

    Returns:
        Two lists (LOCAL, LOCAL_WORLD_ALIGNED) of 6 x nq arrays, rows (v, omega).
    """
    model = robot_model.model
    data = model.createData()
    T0 = frame_poses(model, data, q, frames)
    local = [np.zeros((6, model.nv)) for _ in frames]
    aligned = [np.zeros((6, model.nv)) for _ in frames]
    for k in range(model.nv):
        dq = np.zeros(model.nv)
        dq[k] = STEP
        plus = frame_poses(model, data, pin.integrate(model, q, dq), frames)
        minus = frame_poses(model, data, pin.integrate(model, q, -dq), frames)
        for j, (T, Tp, Tm) in enumerate(zip(T0, plus, minus, strict=True)):
            local[j][:, k] = (pin.log6(T.actInv(Tp)).vector - pin.log6(T.actInv(Tm)).vector) / (
                2 * STEP
            )
            aligned[j][:3, k] = (Tp.translation - Tm.translation) / (2 * STEP)
            aligned[j][3:, k] = (
                pin.log3(Tp.rotation @ T.rotation.T) - pin.log3(Tm.rotation @ T.rotation.T)
            ) / (2 * STEP)
    return local, aligned


@pytest.mark.parametrize("robot", robot_names())
def test_jacobians_match_finite_differences(robot):
    """At 20 seeded random q, every frame's LOCAL and LOCAL_WORLD_ALIGNED Jacobian is the FD one."""
    robot_model = load_robot(robot)
    frames = all_frames(robot_model)
    configuration = Configuration(robot_model)
    worst = {"local": 0.0, "local_world_aligned": 0.0}
    for q in random_configurations(robot_model.lower, robot_model.upper, SAMPLES, seed=11):
        configuration.update(q)
        local, aligned = finite_difference_jacobians(robot_model, q, frames)
        for j, frame in enumerate(frames):
            for reference, expected in (("local", local[j]), ("local_world_aligned", aligned[j])):
                J = configuration.frame_jacobian(frame, reference=reference)
                assert J.shape == (6, robot_model.nq), f"{robot=} {frame=} {reference=}"
                error = float(np.abs(J - expected).max())
                worst[reference] = max(worst[reference], error)
                assert error < TOL, f"{robot=} {frame=} {reference=} {error=:.3e} q={q.tolist()}"
    assert max(worst.values()) > 0.0, f"{robot=}: finite differences cannot be exact"


@pytest.mark.parametrize("robot", robot_names())
def test_frame_jacobian_ignores_joints_beyond_the_frame(robot):
    """Joints i+1..n do not move DH frame i: those Jacobian columns are exactly zero."""
    robot_model = load_robot(robot)
    q = random_configurations(robot_model.lower, robot_model.upper, 1, seed=3)[0]
    configuration = Configuration(robot_model, q)
    for i in range(robot_model.nq + 1):
        J = configuration.frame_jacobian(f"frame{i}", reference="local_world_aligned")
        assert np.all(J[:, i:] == 0.0), f"{robot=} frame{i}"
        if i > 0:
            assert np.linalg.norm(J[:, i - 1]) > 0.5, f"{robot=} joint {i} must move frame{i}"


@pytest.mark.parametrize("robot", robot_names())
def test_local_world_aligned_is_local_rotated_to_world(robot):
    """J_LOCAL_WORLD_ALIGNED = diag(R_world_tool, R_world_tool) @ J_LOCAL at the tool."""
    robot_model = load_robot(robot)
    q = random_configurations(robot_model.lower, robot_model.upper, 1, seed=5)[0]
    configuration = Configuration(robot_model, q)
    R = configuration.transform_frame_to_world("tool").rotation
    J_local = configuration.frame_jacobian("tool", reference="local")
    J_aligned = configuration.frame_jacobian("tool", reference="local_world_aligned")
    rotated = np.vstack([R @ J_local[:3], R @ J_local[3:]])
    assert np.abs(rotated - J_aligned).max() < 1e-12, f"{robot=}"


def test_unknown_jacobian_reference_raises_value_error():
    """An unknown reference name is refused, naming the valid ones."""
    configuration = Configuration(load_robot("planar2"))
    with pytest.raises(ValueError, match="local_world_aligned"):
        configuration.frame_jacobian("tool", reference="global")
