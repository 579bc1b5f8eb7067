"""One partial-pose search: the closed form's branches, then damped Newton, then least squares.

1. **Closed-form candidates** where the arm has a closed form (:mod:`.candidates`), judged on
   the constrained components; the grid of rolls only when the seed's roll gives none (or every
   roll is asked).
2. A closed form that *projects* (a SCARA's tool cannot tilt): its nearest branch inside the
   limits is the nearest pose; no search.
3. **Damped Newton** on a full pose from the seed and the seed-table samples
   (:func:`.starts.newton_starts`).
4. **Weighted least squares** from the remaining starts (:func:`.starts.least_squares_starts`).
"""

from __future__ import annotations

import numpy as np

from ..result import IKResult
from ..targets.target import PoseTarget
from .candidates import candidates
from .context import PartialCall, PartialContext
from .outcome import solved, unreached
from .progress import Progress
from .starts import least_squares_starts, newton_starts
from .task import PartialTask, sweeps

__all__ = ["search"]


def search(ctx: PartialContext, task: PartialTask, call: PartialCall) -> IKResult:
    """The solutions of ``task`` inside the limits, or the failure that says what is known."""
    progress = Progress()
    closed_form_stage(ctx, task, call, progress)
    samples: np.ndarray | None = None
    if progress.found:
        progress.method = "closed_form"
    else:
        progress.attempts.sort(key=lambda item: item[0])
        if getattr(ctx.structure, "projects", False):
            inside = [attempt for attempt in progress.attempts if ctx.inside(attempt[1])]
            if inside:
                # The closed form projected the target on the arm's poses: its nearest branch
                # inside the limits is the nearest pose (a SCARA's tool cannot tilt).
                return unreached(ctx, task, inside[0], progress.outside, call.start, 0)
        target = task.target
        full = ctx.samples is not None and isinstance(target, PoseTarget) and target.mask is None
        if full:
            hit, samples = newton_starts(ctx, task, call)
            if hit is not None:
                progress.found.append(hit)
                progress.method = "damped_newton"
    if not progress.found:
        best, tried, capped = least_squares_starts(ctx, task, call, progress, samples)
        if not progress.found:
            return unreached(ctx, task, best, progress.outside, call.start, tried, capped)
    return solved(ctx, task, call, progress)


def closed_form_stage(
    ctx: PartialContext, task: PartialTask, call: PartialCall, progress: Progress
) -> None:
    """Judge the closed form's branches: the seed's roll first, the grid when that gives none.

    On target inside the limits: ``progress.found``; outside: ``progress.outside``; off target:
    ``progress.attempts`` (the least-squares starts). Stops at the first group with a solution
    unless ``call.every_roll``.
    """
    for grid in (False, True) if sweeps(task) else (False,):
        for group in candidates(ctx, task, call.seed, grid):
            for q, label in group:
                verdict = ctx.judged(task, q, label, call.position_tol, call.rotation_tol)
                if verdict is None:
                    progress.attempts.append((ctx.cost(task, q), q))
                elif verdict.within_limits:
                    progress.add(verdict)
                else:
                    progress.outside.append(verdict)
            if progress.found and not call.every_roll:
                return
