"""Every serial arm of example-robot-data loaded from its URDF: the solver it gets, and IK round
trips judged by Pinocchio's FK of the original URDF (not of the extracted table)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from support.solver_caps import NO_CAP
from support.urdf_reference import ARMS, UrdfReference, erd

from dh2urdf.urdf_chain import read_chain
from kin import load_robot
from kin.ik import PoseTarget, PositionTarget, get_solver
from kin.ik.numeric.solver import NumericIK

#: arm -> (solver name, its free-joint closed form or None): the README's table.
SOLVERS = {
    "ur3": ("closed_form:ur_wrist", None),
    "ur5": ("closed_form:ur_wrist", None),
    "ur10": ("closed_form:ur_wrist", None),
    "ur5_limited": ("closed_form:ur_wrist", None),
    "panda": ("numeric", "SphericalShoulder7RIK"),
    "xarm7": ("numeric", "SphericalShoulder7RIK"),
    "kinova": ("closed_form:spherical_wrist", None),
    "z1": ("closed_form:ur_wrist", None),
    "so100": ("closed_form:fivedof", None),
    "so101": ("numeric", None),
    "baxter_left": ("numeric", "General7RIK"),
    "baxter_right": ("numeric", "General7RIK"),
    "tiago": ("numeric", "SevenDofIK"),
    "double_pendulum": ("closed_form:parallel_axes", None),
    "asr_twodof": ("closed_form:planar2r", None),
}
POSES = 1000


def original(arm: str) -> UrdfReference:
    """Pinocchio's FK of the arm's original URDF between the chain's base and tip."""
    relative, base, tip = ARMS[arm]
    chain = read_chain(erd(relative), base, tip)
    names = tuple(joint.name for joint in chain.joints)
    return UrdfReference(erd(relative), chain.base, chain.tip, names)


@pytest.mark.parametrize("arm", list(SOLVERS))
def test_urdf_arm_gets_its_solver(arm):
    """The solver of each arm read from its URDF (the README lists them)."""
    relative, base, tip = ARMS[arm]
    solver = get_solver(load_robot(erd(relative), base, tip))
    name, free_joint = SOLVERS[arm]
    assert solver.name == name, f"{arm=}"
    closed = getattr(solver, "closed_form", None)
    assert (closed.__class__.__name__ if closed is not None else None) == free_joint, f"{arm=}"


@pytest.mark.parametrize("arm", list(SOLVERS))
def test_urdf_arm_round_trips_judged_on_the_original_urdf(arm):
    """1000 poses from the original URDF's FK: >= 99.9 % solved, no false success."""
    relative, base, tip = ARMS[arm]
    robot = load_robot(erd(relative), base, tip)
    solver = get_solver(robot)
    reference = original(arm)
    full = PoseTarget in solver.target_kinds and robot.nq >= 6
    rng = np.random.default_rng(len(arm))
    solved = false = 0
    for q in rng.uniform(robot.lower, robot.upper, size=(POSES, robot.nq)):
        pose = pin.SE3(reference.pose(q))
        target = (
            PoseTarget(pose.translation, pose.rotation)
            if full
            else PositionTarget(pose.translation)
        )
        result = solver.solve(target, timeout=NO_CAP)
        solved += result.success
        for solution in result.solutions:
            reached = pin.SE3(reference.pose(solution.q))
            position = np.linalg.norm(reached.translation - pose.translation)
            angle = np.linalg.norm(pin.log3(reached.rotation.T @ pose.rotation)) if full else 0.0
            inside = np.all(solution.q >= robot.lower) and np.all(solution.q <= robot.upper)
            false += not (position < 1e-5 and angle < 1e-4 and inside)
    assert false == 0, f"{arm=} {false=}"
    assert solved >= 0.999 * POSES, f"{arm=} {solved=}"


def test_rounded_seven_joint_arm_gets_its_closed_form_polished():
    """xArm7's URDF writes 1.5708 for pi/2: the idealised table's closed form, polished on the
    true chain to 1e-12 m (the judge's 1e-5 m would pass the unpolished 4.5e-6 m)."""
    relative, base, tip = ARMS["xarm7"]
    robot = load_robot(erd(relative), base, tip)
    solver = get_solver(robot)
    assert isinstance(solver, NumericIK) and solver.idealised is not None
    assert any("alpha 1.5708" in change for change in solver.idealised.changes)
    assert 1e-7 < solver.idealised.deviation < 1e-4  # micrometers: rounding, not structure
    reference = original("xarm7")
    rng = np.random.default_rng(3)
    for q in rng.uniform(robot.lower, robot.upper, size=(50, robot.nq)):
        pose = pin.SE3(reference.pose(q))
        result = solver.solve(PoseTarget(pose.translation, pose.rotation))
        assert result.method == "closed_form_free_joint"
        reached = pin.SE3(reference.pose(result.solutions[0].q))
        assert np.linalg.norm(reached.translation - pose.translation) < 1e-12


def test_polish_with_and_without_the_twin_and_its_fallback(monkeypatch):
    """The polish of xArm7's idealised answers: damped Newton's twin (minimum-norm Cholesky steps,
    its own rotation vector) and NumPy's least squares reach the same joint vector on the true
    chain; a twin whose steps go nowhere hands over to NumPy's, which still reaches it."""
    from kin.ik.analytic import idealised
    from kin.ik.numeric import damped_newton

    if not damped_newton.COMPILED:
        pytest.skip("kin/ik/numeric/_damped_step not built")
    relative, base, tip = ARMS["xarm7"]
    robot = load_robot(erd(relative), base, tip)
    ideal = idealised.idealise(robot.table)
    assert ideal is not None
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.tool_frame)
    rng = np.random.default_rng(5)
    starts, targets = [], []
    for q in rng.uniform(robot.lower, robot.upper, size=(60, robot.nq)):
        pin.forwardKinematics(model, data, q)
        pose = pin.updateFramePlacement(model, data, frame)
        targets.append((pose.translation.copy(), pose.rotation.copy()))
        starts.append(q + rng.normal(scale=1e-5, size=robot.nq))  # an idealised answer's offset

    def polished(compiled: bool) -> list[np.ndarray]:
        return [
            idealised.polish(model, data, frame, q, p, r, compiled)
            for q, (p, r) in zip(starts, targets)
        ]

    def miss(q: np.ndarray, p: np.ndarray, r: np.ndarray) -> float:
        pin.forwardKinematics(model, data, q)
        pose = pin.updateFramePlacement(model, data, frame)
        return max(np.abs(pose.translation - p).max(), np.abs(pin.log3(r @ pose.rotation.T)).max())

    twin, plain = polished(True), polished(False)
    for a, b, (p, r) in zip(twin, plain, targets):
        assert miss(a, p, r) < 1e-12 and miss(b, p, r) < 1e-12
        assert np.abs(a - b).max() < 1e-9

    def nowhere(jacobian, error, lam, out):  # noqa: ANN001, ANN202
        out[:] = 0.0
        return 0

    monkeypatch.setattr(idealised, "_damped_step", nowhere)
    for a, b in zip(polished(True), plain):
        np.testing.assert_array_equal(a, b)  # NumPy's steps from the start again


def test_five_joint_arm_without_closed_form_reaches_full_poses_from_samples():
    """SO-101 (5 joints, no closed form) given whole poses of its own: damped Newton from the
    seed, then from the seed-table samples nearest the pose, before the least-squares starts
    (95 of these 100 poses were solved by those alone); every answer judged on the original
    URDF."""
    relative, base, tip = ARMS["so101"]
    robot = load_robot(erd(relative), base, tip)
    solver = get_solver(robot)
    assert isinstance(solver, NumericIK)
    reference = original("so101")
    lower, upper = robot.lower, robot.upper
    rng = np.random.default_rng(7)
    seed = np.clip(np.zeros(robot.nq), lower, upper)
    solved = newton = 0
    for q in rng.uniform(np.maximum(lower, -np.pi), np.minimum(upper, np.pi), (100, robot.nq)):
        pose = pin.SE3(reference.pose(q))
        result = solver.solve(PoseTarget(pose.translation, pose.rotation), seed, timeout=NO_CAP)
        solved += result.success
        newton += result.method == "damped_newton"
        for solution in result.solutions:
            reached = pin.SE3(reference.pose(solution.q))
            assert np.linalg.norm(reached.translation - pose.translation) < 1e-5
            assert np.linalg.norm(pin.log3(reached.rotation.T @ pose.rotation)) < 1e-4
            assert np.all(solution.q >= lower) and np.all(solution.q <= upper)
    assert solved >= 99 and newton >= 90, f"{solved=} {newton=}"
    samples = solver.nearest_samples(pose.translation, pose.rotation, np.inf)
    assert samples.shape == (solver.nearest, robot.nq)


def test_tool_on_the_last_axis_full_poses_by_the_closed_form():
    """The double pendulum's tool sits on its second joint's axis (no second link in the plane):
    the parallel-axes closed form takes the first angle from the position, the second from the
    yaw; every pose of its own answered so (one branch), judged on the original URDF."""
    relative, base, tip = ARMS["double_pendulum"]
    robot = load_robot(erd(relative), base, tip)
    solver = get_solver(robot)
    assert solver.name == "closed_form:parallel_axes"
    reference = original("double_pendulum")
    rng = np.random.default_rng(11)
    for q in rng.uniform(robot.lower, robot.upper, size=(100, robot.nq)):
        pose = pin.SE3(reference.pose(q))
        result = solver.solve(PoseTarget(pose.translation, pose.rotation), np.zeros(robot.nq))
        assert result.method == "closed_form" and len(result.solutions) == 1, result.message
        got = result.solutions[0].q
        assert np.abs(np.remainder(got - q + np.pi, 2 * np.pi) - np.pi).max() < 1e-9
        reached = pin.SE3(reference.pose(got))
        assert np.linalg.norm(reached.translation - pose.translation) < 1e-9
        assert np.linalg.norm(pin.log3(reached.rotation.T @ pose.rotation)) < 1e-9
    tilted = pose.rotation @ pin.exp3(np.array([0.2, 0.3, 0.4]))  # off the arm's rotations
    result = solver.solve(PoseTarget(pose.translation, tilted))
    assert not result.success and result.method == ""
