"""solve_batch: N targets in one call, the same poses reached as one call per target, every
success verified by Pinocchio here (not by the code under test)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from support.solver_caps import NO_CAP

from kin import Configuration, load_robot
from kin.ik import PoseTarget, PositionTarget, TargetError, get_solver, solve_batch
from kin.ik.analytic.seven_r.seven_dof import COMPILED as CLOSED7
from kin.ik.analytic.seven_r.spherical_shoulder7 import COMPILED as SHOULDER7

# The free-joint scan in threads is the 7R twins' (the NumPy form answers one row at a time).
needs_7r_twins = pytest.mark.skipif(not (CLOSED7 and SHOULDER7), reason="7R twins not built")


def _poses(name: str, n: int, seed: int):
    robot = load_robot(name)
    configuration = Configuration(robot)
    qs = np.random.default_rng(seed).uniform(robot.lower, robot.upper, size=(n, robot.nq))
    poses = [configuration.fk(q) for q in qs]
    return robot, np.array([p.translation for p in poses]), np.array([p.rotation for p in poses])


def _check(robot, result, points, frames) -> None:
    configuration = Configuration(robot)
    for i in np.flatnonzero(result.success):
        q = result.q[i]
        assert np.all(q >= robot.lower - 1e-12) and np.all(q <= robot.upper + 1e-12)
        reached = configuration.fk(q)
        assert np.linalg.norm(reached.translation - points[i]) < 1e-5
        if frames is not None:
            assert np.linalg.norm(pin.log3(reached.rotation.T @ frames[i])) < 1e-4


@pytest.mark.parametrize(
    ("name", "full", "stage"),
    [
        ("ur5", True, "closed_form"),
        ("puma560", True, "closed_form"),
        ("pickplace3", False, "closed_form"),
        ("humanoid7", True, None),
        ("panda", False, None),
    ],
)
def test_batch_reaches_every_pose_as_single_calls_do(name, full, stage):
    """200 poses from FK: all solved, verified by Pinocchio; success as the per-call solver's."""
    robot, points, frames = _poses(name, 200, seed=3)
    frames_or_none = frames if full else None
    result = solve_batch(robot, points, frames_or_none, timeout=NO_CAP)
    assert result.q.shape == (200, robot.nq) and result.success.shape == (200,)
    assert result.success.mean() >= 0.99
    _check(robot, result, points, frames_or_none)
    if stage is not None:
        assert set(result.stage) == {stage}
    solver = get_solver(robot)
    for i in range(0, 200, 20):
        target = PoseTarget(points[i], frames[i]) if full else PositionTarget(points[i])
        single = solver.solve(target, np.zeros(robot.nq), timeout=NO_CAP)
        assert single.success == bool(result.success[i])


def test_closed_form_batch_picks_the_branch_nearest_the_seed():
    """ur5: the batch answer is the valid branch nearest each seed, as the per-call order."""
    robot, points, frames = _poses("ur5", 50, seed=8)
    seeds = np.random.default_rng(1).uniform(-1, 1, size=(50, 6))
    result = solve_batch(robot, points, frames, seeds, all_branches=True)
    assert result.branches is not None and result.branches.q.shape[:2] == (50, 8)
    for i in range(50):
        valid = result.branches.q[i][result.branches.valid[i]]
        nearest = valid[np.argmin(np.linalg.norm(valid - seeds[i], axis=1))]
        np.testing.assert_array_equal(result.q[i], nearest)


def test_bad_arrays_name_the_row():
    """A NaN position, a sheared rotation, a wrong shape: TargetError naming the array and row."""
    robot, points, frames = _poses("ur5", 5, seed=2)
    points[3, 1] = np.nan
    with pytest.raises(TargetError, match=r"positions\[3\] is not finite"):
        solve_batch(robot, points, frames)
    points[3, 1] = 0.1
    frames[2] = frames[2] + 0.2
    with pytest.raises(TargetError, match=r"rotations\[2\] is not a rotation matrix"):
        solve_batch(robot, points, frames)
    with pytest.raises(TargetError, match="shape"):
        solve_batch(robot, points[:, :2])


@pytest.mark.parametrize("name", ["humanoid7", "panda", "xarm7"])
def test_free_joint_stage_in_a_batch_gives_the_per_call_answers(name):
    """The batched stage 0 (each seed's free joint, compiled closed form, batched judge) answers
    what one call per pose answers from the same seed; every answer verified by Pinocchio."""
    robot, points, frames = _poses(name, 300, seed=8)
    rng = np.random.default_rng(2)
    seeds = rng.uniform(robot.lower, robot.upper, size=(300, robot.nq))
    result = solve_batch(robot, points, frames, seeds)
    _check(robot, result, points, frames)
    assert result.success.mean() >= 0.999
    assert result.stage.count("closed_form_free_joint") >= 290
    solver = get_solver(robot)
    for i in range(0, 300, 15):
        single = solver.solve(PoseTarget(points[i], frames[i]), seeds[i])
        if result.stage[i] == "closed_form_free_joint" and single.method == result.stage[i]:
            np.testing.assert_allclose(result.q[i], single.best.q, atol=1e-9)


@needs_7r_twins
@pytest.mark.parametrize("name", ["humanoid7", "panda"])
def test_threaded_scan_gives_the_single_thread_answers(name, monkeypatch):
    """The free-joint scan cut into blocks solved in threads: the same rows, bit for bit."""
    from kin.ik.analytic import twin_support
    from kin.ik.numeric.solver import NumericIK

    robot, points, frames = _poses(name, 700, 11)
    closed = NumericIK(robot, prepare=False).closed_form
    seeds = np.random.default_rng(12).uniform(robot.lower, robot.upper, (700, robot.nq))
    monkeypatch.setattr(twin_support, "batch_threads", lambda: 3)
    threaded = closed.first_many(points, frames, seeds, (0.05, 0.01))
    monkeypatch.setattr(twin_support, "PARALLEL_ROWS", 10**9)
    single = closed.first_many(points, frames, seeds, (0.05, 0.01))
    assert threaded is not None and np.isfinite(threaded).all(axis=1).mean() > 0.95
    np.testing.assert_array_equal(threaded, single)


@needs_7r_twins
@pytest.mark.parametrize("name", ["humanoid7", "panda"])
@pytest.mark.parametrize("rows", [40, 700])
def test_a_scan_started_for_later_gives_the_answers_of_one_call(name, rows):
    """``later``: the scan runs in the threads (one block below PARALLEL_ROWS) while the caller
    goes on; its result, and the batch stage started the same way, are bit for bit the answers
    of the call that waits (kin ik --stdin reads its next lines meanwhile)."""
    from kin.ik.analytic.seven_r.subproblems import ScanJob
    from kin.ik.batch_solve import free_joint_answers, start_free_joint_answers
    from kin.ik.numeric.solver import NumericIK

    robot, points, frames = _poses(name, rows, 17)
    solver = NumericIK(robot, prepare=False, near_seed=True)
    seeds = np.random.default_rng(18).uniform(robot.lower, robot.upper, (rows, robot.nq))
    seeds[::5] = 0.0  # some near their targets' tools (the scan without steps)
    job = solver.closed_form.first_many(points, frames, seeds, (0.05, 0.01), later=True)
    assert isinstance(job, ScanJob)
    now = solver.closed_form.first_many(points, frames, seeds, (0.05, 0.01))
    np.testing.assert_array_equal(job.result(), now)
    started = start_free_joint_answers(solver, robot, points, frames, seeds)
    waited = free_joint_answers(solver, robot, points, frames, seeds)
    assert started is not None and waited is not None
    for a, b in zip(started.result(), waited, strict=True):
        np.testing.assert_array_equal(a, b)
    assert np.isfinite(waited[0]).all(axis=1).mean() > 0.8


def test_a_forked_child_solves_batches_with_its_own_threads():
    """A process forked after the parent's threaded batch makes its own pool (the parent's
    threads do not exist in the child) and gives the parent's answers."""
    import multiprocessing

    robot, points, frames = _poses("humanoid7", 300, 13)
    parent = solve_batch(robot, points, frames)
    context = multiprocessing.get_context("fork")
    with context.Pool(1) as pool:
        child = pool.apply_async(solve_batch, (robot, points, frames)).get(timeout=120)
    np.testing.assert_array_equal(child.q, parent.q)
    assert child.success.all()


def test_rotation_check_agrees_with_numpy_gram_and_det():
    """The batch's rotation check (elementwise |R^T R - I| and det) takes and refuses what
    einsum's Gram matrix and numpy.linalg.det say, and snaps what is near a rotation."""
    from kin.ik import batch_solve
    from kin.ik.targets.target import ROTATION_SNAP

    robot, points, frames = _poses("humanoid7", 200, 21)
    rng = np.random.default_rng(22)
    scale = rng.choice([0.0, 0.3 * ROTATION_SNAP, 3.0 * ROTATION_SNAP, 0.1], 200)
    noisy = frames + scale[:, None, None] * rng.standard_normal((200, 3, 3))
    noisy[5] = -noisy[5]  # a reflection
    gram = np.einsum("nji,njk->nik", noisy, noisy) - np.eye(3)
    expected = (np.abs(gram).reshape(200, 9).max(axis=1) <= ROTATION_SNAP) & (
        np.linalg.det(noisy) > 0.0
    )
    for i in range(200):
        if expected[i]:
            snapped = batch_solve._rotations(noisy[i : i + 1], 1)[0]
            np.testing.assert_allclose(snapped.T @ snapped, np.eye(3), atol=1e-12)
            assert np.linalg.det(snapped) > 0.0
        else:
            with pytest.raises(TargetError, match=r"rotations\[0\] is not a rotation matrix"):
                batch_solve._rotations(noisy[i : i + 1], 1)
    assert 20 < expected.sum() < 180
    if expected.all():
        return
    first_bad = int(np.flatnonzero(~expected)[0])
    with pytest.raises(TargetError, match=rf"rotations\[{first_bad}\]"):
        solve_batch(robot, points, noisy)


def test_a_robot_keeps_its_batch_solver_until_its_limits_change():
    """The solver solve_batch builds for a robot is built once; new joint limits rebuild it (and
    the answers keep to them)."""
    from kin.ik import batch_solve

    robot, points, frames = _poses("panda", 50, 23)
    solve_batch(robot, points, frames)
    first = batch_solve._SOLVERS[robot][2]
    solve_batch(robot, points, frames)
    assert batch_solve._SOLVERS[robot][2] is first
    model = robot.model
    saved = model.upperPositionLimit.copy()
    try:
        upper = saved.copy()
        upper[3] = -1.5
        model.upperPositionLimit = upper
        narrowed = solve_batch(robot, points, frames)
        assert batch_solve._SOLVERS[robot][2] is not first
        assert np.all(narrowed.q[narrowed.success, 3] <= -1.5)
    finally:
        model.upperPositionLimit = saved
