"""solve_batch keeps each robot's vectorized closed form (recognising a general 6R arm takes up
to 0.5 s): built once, rebuilt when the joint limits change, shared by threads. Answers are
checked by Pinocchio's FK here, not by the code under test."""

from __future__ import annotations

import threading

import numpy as np
import pinocchio as pin

from kin import Configuration, load_robot
from kin.ik import solve_batch, solver_table
from kin.ik.targets.target import PoseTarget, PositionTarget


def _poses(robot, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    configuration = Configuration(robot)
    qs = np.random.default_rng(seed).uniform(robot.lower, robot.upper, size=(n, robot.nq))
    poses = [configuration.fk(q) for q in qs]
    return np.array([p.translation for p in poses]), np.array([p.rotation for p in poses])


def test_the_vectorized_closed_form_is_built_once_per_robot():
    """Two batches, and both target kinds, share one BatchSolver; another robot has its own."""
    robot = load_robot("ur5")
    points, frames = _poses(robot, 20, 1)
    solve_batch(robot, points, frames)
    first = solver_table._BATCH_SOLVERS[robot][2]
    solve_batch(robot, points, frames)
    assert solver_table._BATCH_SOLVERS[robot][2] is first
    assert solver_table.vectorized_solver(robot, PoseTarget) is first
    other = solver_table.vectorized_solver(load_robot("ur10"), PoseTarget)
    assert other is not None and other is not first


def test_an_arm_without_closed_form_is_remembered_as_none():
    """A robot no structure fits is not recognised again at every batch (None kept)."""
    robot = load_robot("panda")
    assert solver_table.vectorized_solver(robot, PoseTarget) is None
    assert robot in solver_table._BATCH_SOLVERS and solver_table._BATCH_SOLVERS[robot][2] is None
    assert solver_table.vectorized_solver(robot, PositionTarget) is None


def test_new_joint_limits_rebuild_it_and_the_answers_keep_to_them():
    """Narrowing a joint's limits after a batch: the next batch's answers are inside them."""
    robot = load_robot("ur5")
    points, frames = _poses(robot, 60, 2)
    wide = solve_batch(robot, points, frames)
    first = solver_table._BATCH_SOLVERS[robot][2]
    model = robot.model
    saved = model.upperPositionLimit.copy()
    try:
        upper = saved.copy()
        upper[0] = 0.0
        model.upperPositionLimit = upper
        narrow = solve_batch(robot, points, frames)
        assert solver_table._BATCH_SOLVERS[robot][2] is not first
        assert np.all(narrow.q[narrow.success, 0] <= 1e-12)
        assert np.any(wide.q[wide.success, 0] > 0.1)  # the old solver's answers would break them
    finally:
        model.upperPositionLimit = saved


def test_threads_sharing_a_robot_get_the_serial_answers():
    """Four threads batching one robot at once: one solver built, each answer the serial one and
    on target by Pinocchio's FK."""
    robot = load_robot("ur5")
    points, frames = _poses(robot, 100, 3)
    serial = solve_batch(robot, points, frames)
    solver_table._BATCH_SOLVERS.pop(robot)  # the threads find no solver: one of them builds it
    answers: list = [None] * 4

    def run(k: int) -> None:
        answers[k] = solve_batch(robot, points, frames)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert solver_table._BATCH_SOLVERS[robot][2] is not None
    configuration = Configuration(robot)
    for result in answers:
        np.testing.assert_array_equal(result.success, serial.success)
        np.testing.assert_allclose(result.q, serial.q, atol=1e-12, equal_nan=True)
    for i in np.flatnonzero(serial.success):
        reached = configuration.fk(serial.q[i])
        assert np.linalg.norm(reached.translation - points[i]) < 1e-9
        assert np.linalg.norm(pin.log3(reached.rotation.T @ frames[i])) < 1e-9
