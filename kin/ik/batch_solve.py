"""IK of many poses in one call: :func:`solve_batch`, vectorized where a closed form fits.

For an arm whose table fits a closed-form structure that takes the targets (poses, or positions),
every pose is solved at once in NumPy (:class:`~kin.ik.analytic.batch.BatchSolver`: every branch,
moved into the limits by the single call's rule (:mod:`kin.ik.limit_rule`: the copy nearest the
target's seed), each measured by the table's NumPy DH product); the answer of a pose is
its valid branch nearest its seed. A 7R arm with a free-joint closed form (humanoid7, Panda,
xArm7) has its stage 0 batched: every target's scan from its seed, in compiled code and in
threads (:func:`free_joint_answers`). For the others, and the targets that stage leaves (a
numeric arm, a position on a six-joint arm, a rounded table solved on its idealised geometry),
the robot's own solver answers pose by pose, Pinocchio judging each answer. Either way every
success is on target (1e-9 m and rad for the closed forms, 1e-5 m and 1e-4 rad for the numeric
stages) and inside the limits, and the stage that answered is named per pose.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from kin import RobotModel, batch_forward_kinematics
from kin.configuration import default_seed, seed_inside

from .analytic.batch import BatchResult, BatchSolver
from .exceptions import TargetError
from .judge import batch_pose_errors
from .solver_table import front_end_solver, vectorized_solver
from .target import ROTATION_SNAP, PoseTarget, PositionTarget

if TYPE_CHECKING:
    from .analytic.seven_r.subproblems import ScanJob

__all__ = ["FREE_JOINT_STAGE", "BatchIKResult", "free_joint_answers", "solve_batch"]


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


def _array(values: npt.ArrayLike, shape: tuple[int, ...], what: str) -> np.ndarray:
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError, OverflowError) as err:
        raise TargetError(f"{what} must be numbers of shape {shape}, got {values!r}") from err
    if array.shape[1:] != shape[1:] or (shape[0] >= 0 and array.shape[0] != shape[0]):
        raise TargetError(f"{what} must have shape {shape}, got {array.shape}")
    bad = ~np.isfinite(array.reshape(array.shape[0], -1)).all(axis=1)
    if bad.any():
        raise TargetError(f"{what}[{int(np.flatnonzero(bad)[0])}] is not finite")
    return array


def _rotations(values: npt.ArrayLike, n: int) -> np.ndarray:
    """N rotation matrices, each within :data:`ROTATION_SNAP` of one (snapped), else refused."""
    rotations = _array(values, (n, 3, 3), "rotations")
    r = rotations.reshape(n, 9).T  # (9, N): row-major entries, each over the N matrices
    columns = (r[0::3], r[1::3], r[2::3])
    deviation = np.zeros(n)
    with np.errstate(all="ignore"):
        # max |R^T R - I| from the six distinct dot products of the columns, and det R as
        # the expansion along the first row (elementwise: a tenth of einsum's and det's time)
        for i in range(3):
            for j in range(i, 3):
                a, b = columns[i], columns[j]
                gram = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] - (1.0 if i == j else 0.0)
                np.maximum(deviation, np.abs(gram), out=deviation)
        r0, r1, r2, r3, r4, r5, r6, r7, r8 = r
        determinant = r0 * (r4 * r8 - r5 * r7) - r1 * (r3 * r8 - r5 * r6) + r2 * (r3 * r7 - r4 * r6)
    bad = ~((deviation <= ROTATION_SNAP) & (determinant > 0.0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise TargetError(
            f"rotations[{i}] is not a rotation matrix (max |R^T R - I| = {deviation[i]:.3g}, "
            f"det = {determinant[i]:.3g})"
        )
    snap = deviation > 1e-12
    if snap.any():
        u, _, vt = np.linalg.svd(rotations[snap])
        rotations[snap] = u @ vt
    return rotations


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
    points = _array(positions, (-1, 3), "positions")
    n, nq = points.shape[0], robot.nq
    frames = None if rotations is None else _rotations(rotations, n)
    if seeds is None:
        start = np.broadcast_to(default_seed(robot), (n, nq)).copy()
    else:
        start = np.array(seeds, dtype=float)
        start = np.broadcast_to(start, (n, nq)).copy() if start.shape == (nq,) else start
        start = seed_inside(robot, _array(start, (n, nq), "seeds"))
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
        result = solver.solve_poses(poses, seeds)
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
_SOLVERS: weakref.WeakKeyDictionary[RobotModel, tuple[np.ndarray, np.ndarray, Any]] = (
    weakref.WeakKeyDictionary()
)


def _solver(robot: RobotModel) -> Any:
    """The solver table's ``batch`` solver of ``robot``, kept while the robot lives.

    Built on the robot's first batch; rebuilt when the model's joint limits are no longer those
    it was built with. A solver serializes its solves (a lock), so threads that share a robot
    share it safely.
    """
    kept = _SOLVERS.get(robot)
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    if kept is None or not (np.array_equal(kept[0], lower) and np.array_equal(kept[1], upper)):
        kept = _SOLVERS[robot] = (lower.copy(), upper.copy(), front_end_solver(robot, "batch"))
    return kept[2]


#: :attr:`BatchIKResult.stage` of an answer of the free-joint closed form (as the per-call
#: solver's :attr:`~kin.ik.IKResult.method`).
FREE_JOINT_STAGE = "closed_form_free_joint"


def free_joint_answers(
    solver: object,
    robot: RobotModel,
    points: np.ndarray,
    frames: np.ndarray | None,
    seeds: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The free-joint closed form's answers of N targets, or None when the solver has none.

    For an arm with a free-joint closed form (:mod:`.numeric.free_joint`: humanoid7's, Panda's,
    xArm7's; not on an idealised table), each target's branch with its seed's free joint
    (scanned outward, coarse to fine, when that gives none inside the limits), as the first step
    of a call of the solver from that seed, each candidate measured by the table's DH product
    and kept within 1e-9 m and rad and inside the limits. Where the solver has ``seeded_many``
    (:func:`.numeric.free_joint.compiled_seeded_many`: the two special 7R forms with their twin
    built), all of it is compiled and runs in threads, blocks of rows at a time; else the
    twin's ``first_many`` (or ``first`` per target) gives the candidates and the batched judge
    (:func:`kin.batch_forward_kinematics`, :func:`~kin.ik.judge.batch_pose_errors`) measures them
    in NumPy.

    A solver with ``near_seed`` (the ``kin`` commands') answers a target whose seed's tool is
    near it (:func:`_near_seeds`) with the branch of the seed's own free joint (no scan), and
    only when no joint moved farther than its ``seed_near``, as its call does first; else (and
    for such a seed outside the limits) no answer here.

    Args:
        solver: The robot's solver (:func:`~kin.ik.get_solver`).
        robot: The robot.
        points: Target positions (N, 3) [m], world frame.
        frames: Target rotations (N, 3, 3), or None for positions.
        seeds: Start joint vectors (N, nq) [rad], moved into the limits
            (:func:`kin.configuration.seed_inside`).

    Returns:
        ``(q, position_error, rotation_error)``: (N, nq) with NaN rows where the closed form
        gave no verified answer, and the errors (N,) [m], [rad] (NaN there, and for positions).
    """
    started = start_free_joint_answers(solver, robot, points, frames, seeds)
    return None if started is None else started.result()


def start_free_joint_answers(
    solver: object,
    robot: RobotModel,
    points: np.ndarray,
    frames: np.ndarray | None,
    seeds: np.ndarray,
) -> FreeJointAnswers | None:
    """:func:`free_joint_answers` started, or None when the solver has no such closed form.

    Its compiled scans run in threads while the caller goes on (``kin ik --stdin`` answers the
    lines it read before meanwhile); :meth:`FreeJointAnswers.result` waits for them and judges
    the candidates.
    """
    closed = getattr(solver, "closed_form", None)
    if closed is None or getattr(solver, "idealised", None) is not None:
        return None
    if getattr(closed, "costly", False):  # a general 7R: the solver's stages, seed table first
        return None
    n, nq = points.shape[0], robot.nq
    seeds = seed_inside(robot, seeds)  # as the solver's call moves each
    near_rows, skipped = _near_seeds(solver, robot, points, frames, seeds)
    candidates = np.full((n, nq), np.nan)
    jobs: list[tuple[np.ndarray, ScanJob]] = []
    first_each = getattr(closed, "first_each", None)
    many = getattr(solver, "seeded_many", None)
    if many is not None:
        # Compiled end to end: each row's scan and its judge (the table's DH product, the
        # limits) in the threads; the answer rows carry their errors.
        for index, row_steps in _row_groups(solver, near_rows, skipped):
            frame_rows = None if frames is None else frames[index]
            job = many.start(points[index], frame_rows, seeds[index], row_steps, _CLOSED_TOLERANCE)
            jobs.append((index, job))
    elif first_each is not None and frames is not None:
        # A form whose solve is batched itself (General7RIK): one solve of every target at its
        # seed's free joint, no scan (the targets it leaves go to the solver one by one).
        targets = np.zeros((n, 4, 4))
        targets[:, :3, :3], targets[:, :3, 3], targets[:, 3, 3] = frames, points, 1.0
        candidates = first_each(targets, seeds)
        candidates[skipped] = np.nan
    else:
        jobs = _branches_from_seeds(
            closed, solver, points, frames, seeds, near_rows, skipped, candidates
        )
    judged = many is not None
    return FreeJointAnswers(
        solver, robot, points, frames, seeds, near_rows, candidates, jobs, judged
    )


@dataclass(frozen=True)
class FreeJointAnswers:
    """:func:`start_free_joint_answers` under way.

    Attributes: the solver, robot, targets and seeds it was given; ``near_rows`` as
    :func:`_near_seeds` says; ``candidates`` (N, nq) so far; ``jobs`` the scans still running
    (the rows each fills); ``judged``: the jobs' rows are the solver's ``seeded_many`` answers,
    q and errors, judged in compiled code already (else ``result`` judges the candidates).
    """

    solver: object
    robot: RobotModel
    points: np.ndarray
    frames: np.ndarray | None
    seeds: np.ndarray
    near_rows: np.ndarray
    candidates: np.ndarray
    jobs: list[tuple[np.ndarray, ScanJob]]
    judged: bool = False

    def result(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:func:`free_joint_answers`' answer, once the scans are done (call it once)."""
        robot, points, frames, candidates = self.robot, self.points, self.frames, self.candidates
        n = points.shape[0]
        position_error = np.full(n, np.nan)
        rotation_error = np.full(n, np.nan)
        for index, job in self.jobs:
            rows = job.result()
            candidates[index] = rows[:, :7]
            if self.judged:
                position_error[index], rotation_error[index] = rows[:, 7], rows[:, 8]
        if self.near_rows.any():  # kept only within seed_near of the seed (else damped Newton)
            moved = np.abs(candidates - self.seeds).max(axis=1)
            limit = getattr(self.solver, "seed_near", 0.0)
            far = self.near_rows & ~(moved <= limit)
            candidates[far] = position_error[far] = rotation_error[far] = np.nan
        if self.judged:
            return candidates, position_error, rotation_error
        found = ~np.isnan(candidates).any(axis=1)
        if found.any():
            rows = np.flatnonzero(found)
            chosen = candidates[rows]
            poses = batch_forward_kinematics(robot.table, chosen)
            with np.errstate(all="ignore"):  # a target far away is just off target
                p_err, r_err = batch_pose_errors(
                    poses, points[rows], None if frames is None else frames[rows]
                )
            ok = p_err < _CLOSED_TOLERANCE
            if r_err is not None:
                ok &= r_err < _CLOSED_TOLERANCE
            ok &= np.all((chosen >= robot.lower) & (chosen <= robot.upper), axis=1)
            candidates[rows[~ok]] = np.nan
            position_error[rows[ok]] = p_err[ok]
            if r_err is not None:
                rotation_error[rows[ok]] = r_err[ok]
        return candidates, position_error, rotation_error


def _branches_from_seeds(
    closed: Any,
    solver: object,
    points: np.ndarray,
    frames: np.ndarray | None,
    seeds: np.ndarray,
    near_rows: np.ndarray,
    skipped: np.ndarray,
    candidates: np.ndarray,
) -> list[tuple[np.ndarray, ScanJob]]:
    """Each target's branch from its seed into ``candidates``, or the scans that will give them.

    The compiled twin's ``first_many`` started in threads (``later``), one call for the seeds far
    from their targets (the scan steps in turn) and one for the near ones (no scan): the rows
    each fills and its job. Else ``first`` target by target, at once (no job).
    """
    out = np.empty(candidates.shape[1])
    compiled = bool(getattr(solver, "compiled", False))
    steps = _steps(solver)
    first_many = getattr(closed, "first_many", None) if compiled else None
    if first_many is not None:
        jobs = []
        for index, row_steps in _row_groups(solver, near_rows, skipped):
            frame_rows = None if frames is None else frames[index]
            job = first_many(points[index], frame_rows, seeds[index], row_steps, later=True)
            if job is None:
                break
            jobs.append((index, job))
        else:
            return jobs
        for _, job in jobs:  # none started after all (not built): no half-done scan left
            job.result()
    prepare, first = closed.prepare, closed.first
    for i in range(len(points)):
        if skipped[i]:
            continue
        prepared = prepare(points[i], None if frames is None else frames[i])
        if prepared is None:
            continue
        start = seeds[i : i + 1]
        for step in (0.0,) if near_rows[i] else steps:
            if first(prepared, start, out, step, compiled) == 0:
                candidates[i] = out
                break
    return []


def _steps(solver: object) -> tuple[float, ...]:
    """The solver's scan steps of the free joint [rad], coarse to fine."""
    return tuple(getattr(solver, "closed_form_steps", (0.05, 0.01)))


def _row_groups(
    solver: object, near_rows: np.ndarray, skipped: np.ndarray
) -> list[tuple[np.ndarray, tuple[float, ...]]]:
    """The rows to scan and their steps [rad], no group empty and no skipped row in any.

    The rows far from their seeds take the solver's steps; the near ones their seed's free
    joint only (``0.0``).
    """
    groups = ((~near_rows & ~skipped, _steps(solver)), (near_rows & ~skipped, (0.0,)))
    return [(np.flatnonzero(rows), steps) for rows, steps in groups if rows.any()]


def _near_seeds(
    solver: object,
    robot: RobotModel,
    points: np.ndarray,
    frames: np.ndarray | None,
    seeds: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Per target, whether its seed is near it for a ``near_seed`` solver, and whether to skip it.

    Near, as :func:`kin.ik.numeric.starts.seed_leash` decides: the seed's tool within the
    solver's ``max(seed_reach, seed_radius)`` [m] of the target and, for a pose, turned less
    than its ``seed_turn`` [rad]. A near seed outside the limits is skipped (the call clips it).
    """
    n = len(points)
    near = np.zeros(n, dtype=bool)
    if not getattr(solver, "near_seed", False):
        return near, near
    reach = max(solver.seed_reach, solver.seed_radius)  # type: ignore[attr-defined]
    if n > 1 and seeds.strides[0] == 0:  # one seed for all (a broadcast view): one FK
        tools = np.broadcast_to(batch_forward_kinematics(robot.table, seeds[:1]), (n, 4, 4))
    else:
        tools = batch_forward_kinematics(robot.table, seeds)
    with np.errstate(all="ignore"):  # a target 1e200 m away is far (inf), no warning
        offset = tools[:, :3, 3] - points
        near = np.hypot(np.hypot(offset[:, 0], offset[:, 1]), offset[:, 2]) <= reach
    if frames is not None:
        inner = np.einsum("nij,nij->n", tools[:, :3, :3], frames)
        near &= inner >= 1.0 + 2.0 * math.cos(solver.seed_turn)  # type: ignore[attr-defined]
    inside = np.all((seeds >= robot.lower) & (seeds <= robot.upper), axis=1)
    return near, near & ~inside


#: Largest position [m] and rotation [rad] error of a closed-form candidate in a batch.
_CLOSED_TOLERANCE = 1e-9


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
