"""The results of a partial-pose search: the solutions found, or a failure that says what is known."""

from __future__ import annotations

import time

import numpy as np

from ..result import IKResult, IKSolution, Status
from ..targets.target import PoseTarget
from .context import PartialCall, PartialContext
from .progress import Progress
from .settings import RANDOM_STARTS
from .task import PartialTask

__all__ = ["failure", "solved", "unreached"]


def solved(
    ctx: PartialContext, task: PartialTask, call: PartialCall, progress: Progress
) -> IKResult:
    """The success: the solutions found, nearest the seed first (sum of joint differences)."""
    found = sorted(progress.found, key=lambda s: float(np.abs(s.q - call.seed).sum()))
    return IKResult(
        True,
        ctx.name,
        "ok",
        f"{len(found)} solution(s)",
        tuple(found),
        tuple(progress.outside),
        time=time.perf_counter() - call.start,
        method=progress.method,
        free=task.free,
    )


def unreached(
    ctx: PartialContext,
    task: PartialTask,
    best: tuple[float, np.ndarray] | None,
    outside: list[IKSolution],
    start: float,
    tried: int,
    capped: bool = False,
) -> IKResult:
    """The failure, saying what is known.

    ``timeout`` when the time cap stopped the search before its starts were done;
    ``outside_limits`` when it found the target only outside the limits; ``out_of_reach``
    when the closed form projected the target on the arm's poses (``tried`` 0: nothing to
    search); else ``not_found``, with the nearest pose the starts found (``best``: its weighted
    cost and joint vector).
    """
    nearest: tuple[IKSolution, ...] = ()
    what = "no pose found"
    if best is not None:
        solution, position_error, rotation_error = ctx.measured(task, best[1], "nearest")
        nearest = (solution,)
        what = f"the nearest pose found is {position_error:.4g} m" + (
            f" and {rotation_error:.4g} rad" if task.rotation_rows else ""
        )
        what += " away (position, rotation)"
    if capped:
        return failure(
            ctx,
            task,
            "timeout",
            f"the time cap stopped the search after {tried} start(s) (before its "
            f"{RANDOM_STARTS} random ones were done); {what}: raise the timeout (--timeout)",
            tuple(outside) + nearest,
            start,
        )
    if outside:
        return failure(
            ctx,
            task,
            "outside_limits",
            f"reachable only outside the joint limits ({len(outside)} joint vector(s))",
            tuple(outside),
            start,
        )
    hint = ""
    if ctx.nq < 6 and task.target.__class__ is PoseTarget and task.target.mask is None:  # type: ignore[attr-defined]
        hint = (
            f"; an arm of {ctx.nq} joints reaches only some orientations at a point: "
            "free the others with a mask (--mask)"
        )
    if not tried and nearest:  # the closed form's projection: the nearest pose the arm has
        return failure(
            ctx,
            task,
            "out_of_reach",
            f"no joint vector inside the limits reaches the target (the closed form's "
            f"branches): {what}{hint}",
            nearest,
            start,
        )
    return failure(
        ctx,
        task,
        "not_found",
        f"no joint vector inside the limits found on the target in {tried} start(s) "
        f"({RANDOM_STARTS} of them random); {what}{hint}",
        nearest,
        start,
    )


def failure(
    ctx: PartialContext,
    task: PartialTask,
    status: Status,
    message: str,
    rejected: tuple[IKSolution, ...],
    start: float,
    gap: float | None = None,
) -> IKResult:
    """A failed result with its status, message, rejected solutions and time since ``start`` [s].

    ``gap``: how far the target is beyond the reach [m], for ``out_of_reach`` by the reach bound.
    """
    elapsed = time.perf_counter() - start
    return IKResult(
        False, ctx.name, status, message, (), rejected, gap, time=elapsed, free=task.free
    )
