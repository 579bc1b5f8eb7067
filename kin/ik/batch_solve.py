"""IK of many poses in one call: :func:`solve_batch`, vectorized where a closed form fits.

For an arm whose table fits a closed-form structure that takes the targets (poses, or positions),
every pose is solved at once in NumPy (:class:`~kin.ik.analytic.batch.BatchSolver`: every branch,
moved into the limits by the single call's rule (:mod:`kin.ik.limit_rule`: the copy nearest the
target's seed), each measured by the table's NumPy DH product); the answer of a pose is
its valid branch nearest its seed. A 7R arm with a free-joint closed form (humanoid7, Panda,
xArm7) has its stage 0 batched: every target's scan from its seed, in compiled code and in
threads (:func:`~.free_joint_batch.free_joint_answers`). For the others, and the targets that stage leaves (a
numeric arm, a position on a six-joint arm, a rounded table solved on its idealised geometry),
the robot's own solver answers pose by pose, Pinocchio judging each answer. Either way every
success is on target (1e-9 m and rad for the closed forms, 1e-5 m and 1e-4 rad for the numeric
stages) and inside the limits, and the stage that answered is named per pose.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from kin import RobotModel
from kin.configuration import default_seed, seed_inside

from .analytic.batch import BatchResult, BatchSolver
from .free_joint_batch import FREE_JOINT_STAGE, free_joint_answers, start_free_joint_answers
from .solver_table import Kept, front_end_solver, kept_for, vectorized_solver
from .targets.batch import checked_array
from .targets.batch import checked_rotations as _rotations
from .targets.target import PoseTarget, PositionTarget

# The free-joint stage lives in .free_joint_batch; its names stay importable from here.
__all__ = [
    "FREE_JOINT_STAGE",
    "BatchIKResult",
    "free_joint_answers",
    "solve_batch",
    "start_free_joint_answers",
]


@dataclass(frozen=True, eq=False)
class BatchIKResult:
    """The answers of N targets.

    Attributes:
        q: One joint vector per target (N, nq) [rad, m]: the valid answer nearest its seed; NaN
            where there is none.
        success: (N,) a valid answer exists.
        position_error: (N,) its position error [m] (NaN without one).
        rotation_error: (N,) its rotation error [rad] (NaN without one, or for positions).
        stage: Per target, the stage that answered (``"closed_form"``, or a numeric stage as
            :attr:`IKResult.method` names it; ``""`` when none did).
        branches: With ``all_branches`` and a vectorized closed form, every branch (the
            :class:`~kin.ik.analytic.batch.BatchResult`, (N, B, nq)); else None.
    """

    q: np.ndarray
    success: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    stage: tuple[str, ...]
    branches: BatchResult | None = None


def solve_batch(
    robot: RobotModel,
    positions: npt.ArrayLike,
    rotations: npt.ArrayLike | None = None,
    seeds: npt.ArrayLike | None = None,
    *,
    all_branches: bool = False,
    timeout: float | None = None,
    collisions: Any = None,
) -> BatchIKResult:
    """Solve N targets: tool positions (N, 3) [m], with rotations (N, 3, 3) for full poses.

    A vectorized closed form answers every target at once; a 7R arm's free-joint closed form
    scans each target's free joint from its seed and judges its branch in compiled code, 256
    targets or more cut into blocks that one thread per processor takes in turn
    (:func:`.analytic.seven_r.subproblems.call_first_many`); the targets left go to the
    numeric solver one by one.

    Args:
        robot: The robot.
        positions: Tool points in the world frame (N, 3) [m].
        rotations: Tool rotations ``R_world_tool`` (N, 3, 3), or None for positions only.
        seeds: Start joint vectors (N, nq) or one (nq,) for all [rad, m], moved into the limits
            (:func:`kin.configuration.seed_inside`); None: zero, or the nearest joint vector to
            it inside the limits. The answer of a target is the valid one nearest its seed.
        all_branches: Keep every branch of a vectorized closed form in :attr:`BatchIKResult.branches`.
        timeout: Time budget of each numeric solve [s] (None: the solver's default).
        collisions: A :class:`~kin.collision.CollisionChecker` of ``robot``: every target is
            solved by the collision-aware solver (``get_solver(robot, collisions=...)``, one by
            one, the compiled routes bypassed): its answer is the nearest collision-free one;
            ``all_branches`` is then ignored.

    Raises:
        TargetError: A non-finite value, a wrong shape or a matrix that is no rotation; the
            message names the array and the row.
    """
    points = checked_array(positions, (-1, 3), "positions")
    n, nq = points.shape[0], robot.nq
    frames = None if rotations is None else _rotations(rotations, n)
    if seeds is None:
        start = np.broadcast_to(default_seed(robot), (n, nq)).copy()
    else:
        start = np.array(seeds, dtype=float)
        start = np.broadcast_to(start, (n, nq)).copy() if start.shape == (nq,) else start
        start = seed_inside(robot, checked_array(start, (n, nq), "seeds"))
    if collisions is not None:
        aware = front_end_solver(robot, "batch", collisions=collisions)
        return _one_by_one(robot, points, frames, start, timeout, aware)
    vectorized = _closed_form(robot, frames is not None)
    if vectorized is not None and n:
        return _vectorized(vectorized, points, frames, start, all_branches)
    return _free_joint_first(robot, points, frames, start, timeout)


def _closed_form(robot: RobotModel, poses: bool) -> BatchSolver | None:
    """The batch closed form of ``robot`` when it takes these targets, else None (the table)."""
    return vectorized_solver(robot, PoseTarget if poses else PositionTarget)


def _vectorized(
    solver: BatchSolver,
    points: np.ndarray,
    frames: np.ndarray | None,
    seeds: np.ndarray,
    all_branches: bool,
) -> BatchIKResult:
    n = points.shape[0]
    if frames is None:
        result = solver.solve_positions(points, seeds)
    else:
        poses = np.zeros((n, 4, 4))
        poses[:, :3, :3], poses[:, :3, 3], poses[:, 3, 3] = frames, points, 1.0
        result = _compiled_poses(solver, poses, seeds) or solver.solve_poses(poses, seeds)
    valid = result.valid
    # The valid branch nearest the seed (Euclidean joint distance), as the per-call solver orders.
    distance = np.where(valid, np.linalg.norm(result.q - seeds[:, None, :], axis=2), math.inf)
    choice = distance.argmin(axis=1)
    rows = np.arange(n)
    success = valid[rows, choice]
    q = np.where(success[:, None], result.q[rows, choice], np.nan)
    position_error = np.where(success, result.position_error[rows, choice], np.nan)
    rotation = result.rotation_error[rows, choice] if frames is not None else np.full(n, np.nan)
    rotation_error = np.where(success, rotation, np.nan)
    stage = tuple("closed_form" if ok else "" for ok in success.tolist())
    return BatchIKResult(
        q, success, position_error, rotation_error, stage, result if all_branches else None
    )


#: The compiled verifier's ``check`` block of each batch solver that has one (None: none).
_CHECKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _compiled_poses(
    solver: BatchSolver, poses: np.ndarray, seeds: np.ndarray
) -> BatchResult | None:
    """``solver.solve_poses(poses, seeds)`` verified in the structure's compiled twin, or None.

    A general 6R arm whose twin is built (:mod:`.analytic.six_r._general_6r_verify`: the same
    limit rule and judge, in C); None for the others.
    """
    from .analytic.six_r._general_6r_verify import check_block, verified_batch

    if solver not in _CHECKS:
        _CHECKS[solver] = check_block(solver)
    check = _CHECKS[solver]
    return None if check is None else verified_batch(solver, check, poses, seeds)


def _free_joint_first(
    robot: RobotModel,
    points: np.ndarray,
    frames: np.ndarray | None,
    seeds: np.ndarray,
    timeout: float | None,
) -> BatchIKResult:
    """Stage 0 of the numeric pipeline for every target, then the whole solver for the rest.

    For an arm with a free-joint closed form (:func:`free_joint_answers`), the targets it
    answers; the others go through the robot's solver one by one (:func:`_one_by_one`), every
    stage of it.
    """
    solver = _solver(robot)
    answers = free_joint_answers(solver, robot, points, frames, seeds) if len(points) else None
    if answers is None:
        return _one_by_one(robot, points, frames, seeds, timeout, solver)
    q, position_error, rotation_error = answers
    found = ~np.isnan(q).any(axis=1)
    stage = [FREE_JOINT_STAGE if ok else "" for ok in found.tolist()]
    rest = np.flatnonzero(~found)
    if rest.size:
        others = _one_by_one(
            robot,
            points[rest],
            None if frames is None else frames[rest],
            seeds[rest],
            timeout,
            solver,
        )
        q[rest] = others.q
        position_error[rest] = others.position_error
        rotation_error[rest] = others.rotation_error
        for k, i in enumerate(rest.tolist()):
            stage[i] = others.stage[k]
    success = ~np.isnan(q).any(axis=1)
    return BatchIKResult(q, success, position_error, rotation_error, tuple(stage))


#: The solver of each robot :func:`solve_batch` was given (building one takes about 0.7 ms),
#: with the joint limits [rad, m] it was built with.
_SOLVERS: Kept = weakref.WeakKeyDictionary()


def _solver(robot: RobotModel) -> Any:
    """The solver table's ``batch`` solver of ``robot``, kept while the robot lives.

    Built on the robot's first batch; rebuilt when the model's joint limits are no longer those
    it was built with (:func:`~.solver_table.kept_for`). A solver serializes its solves (a
    lock), so threads that share a robot share it safely.
    """
    return kept_for(_SOLVERS, robot, lambda robot: front_end_solver(robot, "batch"))


def _one_by_one(
    robot: RobotModel,
    points: np.ndarray,
    frames: np.ndarray | None,
    seeds: np.ndarray,
    timeout: float | None,
    solver: object | None = None,
) -> BatchIKResult:
    """The robot's solver, target by target (every stage of it)."""
    chosen = front_end_solver(robot, "batch") if solver is None else solver
    solve = chosen.solve  # type: ignore[attr-defined]
    n, nq = points.shape[0], robot.nq
    q = np.full((n, nq), np.nan)
    position_error = np.full(n, np.nan)
    rotation_error = np.full(n, np.nan)
    stage = []
    for i in range(n):
        target = PositionTarget(points[i]) if frames is None else PoseTarget(points[i], frames[i])
        result = solve(target, seeds[i], timeout=timeout)
        if result.success:
            best = result.solutions[0]
            q[i] = best.q
            position_error[i] = best.position_error
            if best.rotation_error is not None:
                rotation_error[i] = best.rotation_error
        stage.append(result.method if result.success else "")
    success = ~np.isnan(q).any(axis=1)
    return BatchIKResult(q, success, position_error, rotation_error, tuple(stage))
