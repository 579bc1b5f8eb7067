"""A plan's final check: every motion of the returned path, then its clearance.

:func:`certified` is the last step of :func:`kin.plan.plan`: a path whose every motion is shown
free becomes the ``ok`` answer (with its length, the goal it reaches and its smallest clearance);
one that is not (never expected: every edge passed the same rule during the search) becomes
``not_found`` naming the place.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .ompl_problem import RESOLUTION, exact_rule

if TYPE_CHECKING:  # pragma: no cover
    from ..collision import CollisionChecker
    from ..path.collision_check import MotionCheck
    from .goals import GoalSet
    from .ompl_problem import Budget, CertifiedSpace
    from .result import PlanResult

__all__ = ["MOTION_CHECKS", "certified"]

#: Most midpoints the spheres may take on one motion of the final check [count].
MOTION_CHECKS = 20_000


def _clearance(
    checker: CollisionChecker, path: np.ndarray, space: CertifiedSpace, exact: MotionCheck
) -> float | None:
    """The smallest distance of any checked pair at the path's joint vectors [m] (None: no pair).

    Coal's distances (:meth:`kin.collision.CollisionChecker.distance`'s values), asked in the
    order of the spheres' lower bounds where the plan has spheres, so that the pairs far apart
    are not measured (:meth:`kin.path.pair_distances.PairDistances.smallest`).
    """
    if not checker.model.pairs:
        return None
    if space.spheres is None or exact.helper is None:
        return min(checker.distance(q).distance for q in path)
    from ..collision.sphere_bound import sphere_bound

    below = sphere_bound(checker.model).lower_bounds(path)
    return min(exact.helper.measured.smallest(q, b) for q, b in zip(path, below))


def certified(
    checker: CollisionChecker,
    path: np.ndarray,
    goals: GoalSet,
    budget: Budget,
    answer: Any,
    space: CertifiedSpace,
) -> PlanResult:
    """The path after its final check of every joint vector and every motion.

    A motion the plan's rules showed free during the search (the same two ends, bit for bit:
    ``space.shown``) is known free, its ends with it. Any other (an edge the path's assembly
    made) is judged by the spheres' rule (:mod:`kin.plan.sphere_motion`), and where they do not
    show it free, by the exact rule (:class:`kin.path.collision_check.MotionCheck`, coal's
    distances, no budget but its own 100,000 checks a motion), its ends by the checker.
    """
    spheres = space.spheres
    exact = exact_rule(checker)
    for i in range(len(path) - 1):
        a, b = path[i], path[i + 1]
        if space.shown.holds(a, b):
            continue
        if spheres is not None and spheres.state_free(a) and spheres.state_free(b):
            if spheres.motion_free(a, b, RESOLUTION, MOTION_CHECKS)[0]:
                continue
        found = None
        if checker.in_collision(a) or checker.in_collision(b):
            found = "a joint vector in collision"
        else:
            place = exact.between(
                a, b, exact.distances(a), exact.distances(b), i, exact.checks + 100_000
            )
            found = None if place is None else place.describe()
        if found is not None:  # never expected: every edge passed the same rule
            return answer(
                "not_found",
                f"the path failed its final check ({found})",
                goals=goals.q,
                checks=budget.checks,
            )
    reached = int(np.argmin(np.linalg.norm(goals.q - path[-1], axis=1)))
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    clearance = _clearance(checker, path, space, exact)
    cut = " (the time cap cut its simplification short)" if budget.timed_out else ""
    return answer(
        "ok",
        f"a collision-free path of {len(path)} joint vectors{cut}",
        path=path,
        goal_index=reached,
        goals=goals.q,
        length=float(steps.sum()),
        straight_length=float(np.linalg.norm(path[-1] - path[0])),
        checks=budget.checks,
        clearance=clearance,
    )
