"""The compiled ``all_branches`` and ``sift_rows`` (kin/_native/ik/analytic/seven_r/_branches7.h) against the Python path.

``solve(..., all_branches=True)`` on a 7R arm with a compiled free-joint form answers in one C
call; the NumPy path of :mod:`kin.ik.numeric.all_branches` (``branches_over``, ``distinct``,
``windings``, the batched judge) is the reference. Both must give the same branches in the same
order, with the same errors, and the same rejected ones; the branches themselves are checked
against the plain NumPy DH product of the table file (``dh_reference``).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle

import dh2urdf
from kin import load_robot
from kin.ik import PoseTarget, get_solver
from kin.ik.numeric import all_branches, branch_arm

TABLES = Path(dh2urdf.__file__).resolve().parent / "tables"  # the installed package's
#: The shipped 7R arms with a compiled free-joint form (spherical shoulder, SevenDof).
ARMS = ("panda", "xarm7", "humanoid7")
TARGETS = 12


def _solver(name: str):
    solver = get_solver(load_robot(name))
    if branch_arm.branch_arm(solver, solver.closed_form).compiled is None:
        pytest.skip(f"{name}: the compiled twin of its closed form is not built")
    return solver


def _python_path(solver, target, seed=None):
    """The answer of the NumPy path (the compiled call switched off for this form)."""
    saved = branch_arm.branch_arm(solver, solver.closed_form)
    branch_arm._remember(solver, dataclasses.replace(saved, compiled=None, sift=None))
    try:
        return solver.solve(target, seed, all_branches=True)
    finally:
        branch_arm._remember(solver, saved)


def _rows(solutions) -> np.ndarray:
    return np.array([s.q for s in solutions]).reshape(-1, 7)


@pytest.mark.parametrize("name", ARMS)
def test_the_twin_gives_the_python_paths_branches_in_its_order(name):
    """Same branches, order, errors, rejected ones; each on the pose by the NumPy DH product."""
    solver = _solver(name)
    robot = solver.robot
    reference = load_reference(TABLES / f"{name}.toml")
    rng = np.random.default_rng(7)
    q_all = rng.uniform(robot.lower, robot.upper, (TARGETS, robot.nq))
    poses = fk_frames(reference, q_all)[:, -1]
    seeds = rng.uniform(robot.lower, robot.upper, (TARGETS, robot.nq))
    rejected = 0
    for pose, seed in zip(poses, seeds):
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        fast = solver.solve(target, seed, all_branches=True)
        slow = _python_path(solver, target, seed)
        assert fast.message == slow.message, f"{name=}"
        assert fast.method == slow.method and fast.success == slow.success, f"{name=}"
        q_fast, q_slow = _rows(fast.solutions), _rows(slow.solutions)
        assert q_fast.shape == q_slow.shape and q_fast.shape[0] > 0, f"{name=}"
        np.testing.assert_allclose(q_fast, q_slow, rtol=0, atol=1e-10, err_msg=name)
        for a, b in zip(fast.solutions, slow.solutions):
            assert a.within_limits and b.within_limits
            assert abs(a.position_error - b.position_error) < 1e-13, f"{name=}"
            assert abs(a.rotation_error - b.rotation_error) < 1e-13, f"{name=}"
        np.testing.assert_allclose(
            _rows(fast.rejected), _rows(slow.rejected), rtol=0, atol=1e-10, err_msg=name
        )
        assert not any(s.within_limits for s in fast.rejected)
        rejected += len(fast.rejected)
        reached = fk_frames(reference, q_fast)[:, -1]
        assert np.linalg.norm(reached[:, :3, 3] - pose[:3, 3], axis=1).max() < 1e-9, f"{name=}"
        angles = rotation_angle(
            reached[:, :3, :3], np.broadcast_to(pose[:3, :3], reached[:, :3, :3].shape)
        )
        assert angles.max() < 1e-9, f"{name=}"
        distance = ((q_fast - solver.seed_vector(seed)) ** 2).sum(axis=1)
        assert (np.diff(distance) >= 0).all(), f"{name=} not nearest the seed first"
    assert rejected > 0, f"{name=}: no target had a branch outside the limits (nothing compared)"


def test_a_near_miss_hands_the_target_back_to_the_python_path():
    """Every branch a near miss (tolerances below rounding): the twin answers None."""
    solver = _solver("panda")
    call = branch_arm.branch_arm(solver, solver.closed_form).compiled
    q = np.array([0.3, -0.4, 0.2, -1.9, 0.1, 1.6, 0.5])
    pose = fk_frames(load_reference(TABLES / "panda.toml"), q[None])[0, -1]
    target = PoseTarget(pose[:3, 3], pose[:3, :3])
    grid = np.array([0.5])
    limits = (np.ascontiguousarray(solver.lower), np.ascontiguousarray(solver.upper))
    made = all_branches._MADE
    found = call(target, grid, *limits, q, 1e-9, 1e-9, 1e-3, *made)
    assert found is not None and len(found[0]) >= 1
    assert np.abs(_rows(found[0]) - q).max(axis=1).min() < 1e-9
    assert call(target, grid, *limits, q, 0.0, 0.0, 1e-3, *made) is None


def test_a_target_that_is_not_a_finite_pose_is_handed_back():
    """A NaN in the target: None (the Python path says what is wrong)."""
    solver = _solver("panda")
    call = branch_arm.branch_arm(solver, solver.closed_form).compiled

    class Pose:
        position = np.array([np.nan, 0.0, 0.5])
        rotation = np.eye(3)

    limits = (np.ascontiguousarray(solver.lower), np.ascontiguousarray(solver.upper))
    near = np.zeros(7)
    assert (
        call(Pose(), np.array([0.1]), *limits, near, 1e-9, 1e-9, 1e-3, *all_branches._MADE) is None
    )


def test_the_general_form_is_sifted_in_c_as_in_python():
    """A random 7R arm (the general form: no twin of its own): its branches sifted by
    ``sift_rows`` give the Python path's answer, each on the pose by the NumPy DH product."""
    from support.arm_tables import make_table, random_pose
    from support.dh_reference import ReferenceTable

    import kin
    from kin.ik.analytic.seven_r.general_7r import General7RIK

    rng = np.random.default_rng(3)
    a, d = rng.uniform(-0.4, 0.4, (2, 7))
    alpha, theta = rng.uniform(-np.pi, np.pi, (2, 7))
    base, tool = random_pose(rng), random_pose(rng)
    table = make_table(a, alpha, d, theta, "standard", base, tool, name="r7")
    solver = get_solver(kin.robot_from_table(table))
    assert isinstance(solver.closed_form, General7RIK)
    arm = branch_arm.branch_arm(solver, solver.closed_form)
    if arm.sift is None:
        pytest.skip("the compiled twins are not built")
    ones = np.ones(7)
    reference = ReferenceTable(
        "standard", tuple(f"j{i}" for i in range(1, 8)), np.zeros(7, dtype=bool), a, alpha, d,
        theta, -2 * np.pi * ones, 2 * np.pi * ones, base, tool,
    )  # fmt: skip
    poses = fk_frames(reference, rng.uniform(-np.pi, np.pi, (3, 7)))[:, -1]
    for pose in poses:
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        fast = solver.solve(target, all_branches=True)
        slow = _python_path(solver, target)
        q_fast = _rows(fast.solutions)
        assert q_fast.shape[0] > 0 and q_fast.shape == _rows(slow.solutions).shape
        np.testing.assert_allclose(q_fast, _rows(slow.solutions), rtol=0, atol=1e-10)
        np.testing.assert_allclose(_rows(fast.rejected), _rows(slow.rejected), rtol=0, atol=1e-10)
        reached = fk_frames(reference, q_fast)[:, -1]
        assert np.linalg.norm(reached[:, :3, 3] - pose[:3, 3], axis=1).max() < 1e-9
