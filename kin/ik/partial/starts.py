"""The starts of a partial-pose search after the closed form: damped Newton, then least squares.

Work, not time, decides the answer: the closed form's branches off target, the seed, the
seed-table samples and :data:`~.settings.RANDOM_STARTS` random joint vectors inside the limits (a
seeded draw: the same call gives the same answer on any machine). The time cap only stops the
starts early (the search then says ``timeout``).
"""

from __future__ import annotations

import time

import numpy as np

from ..numeric.damped_newton import damped_newton
from ..numeric.sampling_box import sampling_limits
from ..result import IKSolution
from ..targets.target import PoseTarget
from .context import PartialCall, PartialContext
from .least_squares import least_squares
from .progress import Progress
from .settings import NEWTON_ITERATIONS, NEWTON_PATIENCE, NEWTON_RANDOM_STARTS, RANDOM_STARTS
from .task import PartialTask, sweep

__all__ = ["least_squares_starts", "newton_starts"]


def newton_starts(
    ctx: PartialContext, task: PartialTask, call: PartialCall
) -> tuple[IKSolution | None, np.ndarray | None]:
    """Damped Newton on a full pose from the seed, the samples nearest it, then random starts.

    The first answer the judge finds on the pose inside the limits, else None; and the
    samples when they were looked up (the least-squares starts take them next). The random
    starts are the first :data:`~.settings.NEWTON_RANDOM_STARTS` of the least squares' draw: a
    pose whose samples lie on another branch (Fetch's head camera beyond its sampled rail) is
    found there at the cost of a few damped Newton runs, not of every least-squares start. Damped
    Newton's steps (its compiled twin) are several times cheaper than the least-squares
    ones, and a reachable full pose needs no weighing of components.
    """
    target = task.target
    assert isinstance(target, PoseTarget) and ctx.samples is not None
    starts: list[np.ndarray] = [call.seed]
    samples: np.ndarray | None = None
    randoms = False
    while starts or not randoms:
        if not starts:  # the seed and the samples failed: the first random starts
            randoms = True
            starts.extend(random_starts(ctx, call)[:NEWTON_RANDOM_STARTS])
            continue
        outcome = damped_newton(
            ctx.model,
            ctx.data,
            ctx.frame_id,
            starts.pop(0),
            target.position,
            target.rotation,
            max_iterations=NEWTON_ITERATIONS,
            position_tol=0.1 * call.position_tol,
            rotation_tol=0.1 * call.rotation_tol,
            patience=NEWTON_PATIENCE,
        )
        if outcome.converged:
            verdict = ctx.judged(task, outcome.q, "", call.position_tol, call.rotation_tol)
            if verdict is not None and verdict.within_limits:
                return verdict, samples
        if samples is None:
            samples = ctx.samples(target.position, target.rotation, call.deadline)
            starts.extend(samples)
        if time.perf_counter() > call.deadline:
            break
    return None, samples


def random_starts(ctx: PartialContext, call: PartialCall) -> list[np.ndarray]:
    """The search's random starts, drawn from ``call.random_seed``.

    :data:`~.settings.RANDOM_STARTS` joint vectors inside the limits (a long rail within the
    arm's size).
    """
    rng = np.random.default_rng(call.random_seed)
    low, high = sampling_limits(ctx.robot.table, ctx.search_lower, ctx.search_upper)
    return list(rng.uniform(low, high, (RANDOM_STARTS, ctx.nq)))


def least_squares_starts(
    ctx: PartialContext,
    task: PartialTask,
    call: PartialCall,
    progress: Progress,
    samples: np.ndarray | None,
) -> tuple[tuple[float, np.ndarray] | None, int, bool]:
    """Weighted least squares from each start in turn until one lands on the target.

    The starts: the closed-form branches off target (``progress.attempts``, best first), the
    seed, the seed-table ``samples`` (looked up here, after the seed, when None and the solver
    has a table), then the random ones. An answer inside the limits goes into ``progress``
    (method ``closed_form_refined`` from a branch, else ``weighted_newton``), one outside the
    limits into ``progress.outside``.

    Returns:
        The lowest weighted cost and its joint vector (None: no start ran), the starts run,
        and whether the time cap stopped them.
    """
    starts = [q for _, q in progress.attempts]
    refined = len(starts)  # the first starts: the closed form's branches off target
    starts.append(call.seed)
    # The samples nearest the pose (a full one; a masked one's given rotation; an axis
    # target at the seed's roll), after the seed: looked up only when it is needed.
    lazy = ctx.samples is not None and samples is None
    if samples is not None:
        starts.extend(samples)
    randoms = random_starts(ctx, call)
    best: tuple[float, np.ndarray] | None = None
    tried = 0
    while True:
        if not starts:
            if lazy:
                lazy = False
                # A mask that frees a rotation on an arm of fewer than six joints: the
                # samples nearest the position alone (the given rotation is one of many
                # the target allows, and most of them are off the arm's thin set).
                at_seed, turned = ctx.fk(call.seed)
                rotation = (
                    None
                    if ctx.nq < 6 and len(task.rotation_rows) < 3 and task.axis_column is None
                    else sweep(task, turned, False)[0][0]
                )
                starts.extend(ctx.samples(task.near(at_seed), rotation, call.deadline))  # type: ignore[misc]
                continue
            if not randoms:
                return best, tried, False  # the work is done
            starts.append(randoms.pop(0))
        if time.perf_counter() > call.deadline:
            return best, tried, True
        q, cost = least_squares(
            ctx, task, starts.pop(0), 0.1 * call.position_tol, 0.1 * call.rotation_tol
        )
        tried += 1
        verdict = ctx.judged(task, q, "", call.position_tol, call.rotation_tol)
        if verdict is not None and verdict.within_limits:
            progress.add(verdict)
            progress.method = "closed_form_refined" if tried <= refined else "weighted_newton"
            return best, tried, False
        if verdict is not None:
            progress.outside.append(verdict)
        if best is None or cost < best[0]:
            best = (cost, q)
