"""Stage 0 of a 7R batch: the free-joint closed form's answer of every target from its seed.

For an arm with a free-joint closed form (:mod:`.numeric.free_joint`: humanoid7's, Panda's,
xArm7's), :func:`free_joint_answers` gives each target's branch with its seed's free joint
(scanned outward, coarse to fine, when that gives none inside the limits), as the first step of a
call of the solver from that seed, measured by the table's DH product and kept within
:data:`CLOSED_TOLERANCE` and inside the limits; compiled and in threads where the twin is built.
:func:`kin.ik.solve_batch` (:mod:`.batch_solve`) and ``kin ik --stdin`` use it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from kin import RobotModel, batch_forward_kinematics
from kin.configuration import seed_inside

from .judge import batch_pose_errors
from .solver import FreeJointRoute, IKSolver

if TYPE_CHECKING:
    from .analytic.twin_support import ScanJob

__all__ = [
    "CLOSED_TOLERANCE",
    "FREE_JOINT_STAGE",
    "FreeJointAnswers",
    "free_joint_answers",
    "start_free_joint_answers",
]

#: Largest position [m] and rotation [rad] error of a closed-form candidate in a batch.
CLOSED_TOLERANCE = 1e-9

#: :attr:`BatchIKResult.stage` of an answer of the free-joint closed form (as the per-call
#: solver's :attr:`~kin.ik.IKResult.method`).
FREE_JOINT_STAGE = "closed_form_free_joint"


def free_joint_answers(
    solver: IKSolver,
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
    solver: IKSolver,
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
    route = solver.batch_route()
    if route is None:
        return None
    closed = route.closed
    if getattr(closed, "costly", False):  # a general 7R: the solver's stages, seed table first
        return None
    n, nq = points.shape[0], robot.nq
    seeds = seed_inside(robot, seeds)  # as the solver's call moves each
    near_rows, skipped = _near_seeds(route, robot, points, frames, seeds)
    candidates = np.full((n, nq), np.nan)
    jobs: list[tuple[np.ndarray, ScanJob]] = []
    first_each = getattr(closed, "first_each", None)
    many = route.seeded_many
    if many is not None:
        # Compiled end to end: each row's scan and its judge (the table's DH product, the
        # limits) in the threads; the answer rows carry their errors.
        for index, row_steps in _row_groups(route, near_rows, skipped):
            frame_rows = None if frames is None else frames[index]
            job = many.start(points[index], frame_rows, seeds[index], row_steps, CLOSED_TOLERANCE)
            jobs.append((index, job))
    elif first_each is not None and frames is not None:
        # A form whose solve is batched itself (General7RIK): one solve of every target at its
        # seed's free joint, no scan (the targets it leaves go to the solver one by one).
        targets = np.zeros((n, 4, 4))
        targets[:, :3, :3], targets[:, :3, 3], targets[:, 3, 3] = frames, points, 1.0
        candidates = first_each(targets, seeds)
        candidates[skipped] = np.nan
    else:
        jobs = _branches_from_seeds(route, points, frames, seeds, near_rows, skipped, candidates)
    judged = many is not None
    return FreeJointAnswers(
        route, robot, points, frames, seeds, near_rows, candidates, jobs, judged
    )


@dataclass(frozen=True)
class FreeJointAnswers:
    """:func:`start_free_joint_answers` under way.

    Attributes: the solver's batch route, the robot, targets and seeds it was given; ``near_rows`` as
    :func:`_near_seeds` says; ``candidates`` (N, nq) so far; ``jobs`` the scans still running
    (the rows each fills); ``judged``: the jobs' rows are the solver's ``seeded_many`` answers,
    q and errors, judged in compiled code already (else ``result`` judges the candidates).
    """

    route: FreeJointRoute
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
            limit = self.route.seed_near
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
            ok = p_err < CLOSED_TOLERANCE
            if r_err is not None:
                ok &= r_err < CLOSED_TOLERANCE
            ok &= np.all((chosen >= robot.lower) & (chosen <= robot.upper), axis=1)
            candidates[rows[~ok]] = np.nan
            position_error[rows[ok]] = p_err[ok]
            if r_err is not None:
                rotation_error[rows[ok]] = r_err[ok]
        return candidates, position_error, rotation_error


def _branches_from_seeds(
    route: FreeJointRoute,
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
    closed, compiled, steps = route.closed, route.compiled, route.steps
    first_many = getattr(closed, "first_many", None) if compiled else None
    if first_many is not None:
        jobs = []
        for index, row_steps in _row_groups(route, near_rows, skipped):
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


def _row_groups(
    route: FreeJointRoute, near_rows: np.ndarray, skipped: np.ndarray
) -> list[tuple[np.ndarray, tuple[float, ...]]]:
    """The rows to scan and their steps [rad], no group empty and no skipped row in any.

    The rows far from their seeds take the solver's steps; the near ones their seed's free
    joint only (``0.0``).
    """
    groups = ((~near_rows & ~skipped, route.steps), (near_rows & ~skipped, (0.0,)))
    return [(np.flatnonzero(rows), steps) for rows, steps in groups if rows.any()]


def _near_seeds(
    route: FreeJointRoute,
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
    if not route.near_seed:
        return near, near
    reach = max(route.seed_reach, route.seed_radius)
    if n > 1 and seeds.strides[0] == 0:  # one seed for all (a broadcast view): one FK
        tools = np.broadcast_to(batch_forward_kinematics(robot.table, seeds[:1]), (n, 4, 4))
    else:
        tools = batch_forward_kinematics(robot.table, seeds)
    with np.errstate(all="ignore"):  # a target 1e200 m away is far (inf), no warning
        offset = tools[:, :3, 3] - points
        near = np.hypot(np.hypot(offset[:, 0], offset[:, 1]), offset[:, 2]) <= reach
    if frames is not None:
        inner = np.einsum("nij,nij->n", tools[:, :3, :3], frames)
        near &= inner >= 1.0 + 2.0 * math.cos(route.seed_turn)
    inside = np.all((seeds >= robot.lower) & (seeds <= robot.upper), axis=1)
    return near, near & ~inside
