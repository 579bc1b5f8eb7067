"""Collision-free motion planning with OMPL: from a joint vector to a joint vector or an IK target.

:func:`plan` checks the start and the goals, tries the straight joint motion to each goal first
(most plans in an open cell need nothing else), then runs an OMPL planner on
:class:`~kin.plan.ompl_problem.CertifiedSpace` (the project's collision checker and its motion
rule, so every edge is certified), shortens the path with OMPL's simplifier (whose shortcuts go
through the same motion rule), and checks the whole result once more with
:func:`kin.path.collision_check.check_path_collisions` before it is returned.

Same input, same path: OMPL's random numbers are seeded from ``seed`` before each plan
(``ompl.util.RNG.setSeed``, process-wide: one plan at a time per process) and the search is
bounded by ``max_checks``; ``time_limit`` is a cap, reported as ``timeout`` when it ends the search.
"""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..configuration import as_joint_vector, limit_violations
from ..exceptions import KinError
from .goals import GoalSet, goal_configurations, joint_goal
from .ompl_problem import RESOLUTION, Budget, CertifiedSpace, joint_bounds, silence_ompl
from .result import PlanResult

if TYPE_CHECKING:  # pragma: no cover
    from ..collision import CollisionChecker
    from .sphere_motion import SphereMotion

__all__ = ["DEFAULT_CHECKS", "DEFAULT_PLANNER", "PLANNERS", "PlanError", "plan"]

#: OMPL's geometric planners in the ``ompl`` wheel that :func:`plan` offers, by OMPL's names.
#: PRM and PRMstar are left out: they grow their roadmap in a thread of their own, whose calls
#: into the Python checks wait for the interpreter lock that ``solve`` holds (a deadlock).
PLANNERS: tuple[str, ...] = (
    "RRTConnect",
    "RRT",
    "RRTstar",
    "InformedRRTstar",
    "SORRTstar",
    "AORRTC",
    "BITstar",
    "FMT",
    "BFMT",
    "KPIECE1",
    "BKPIECE1",
    "LBKPIECE1",
)
#: The planner used when none is named.
DEFAULT_PLANNER = "RRTConnect"
#: Configurations a plan may check before it stops with ``not_found`` [count].
DEFAULT_CHECKS = 200_000
#: Configurations the search may check on the spheres alone before the exact rule joins [count].
SPHERE_CHECKS = 50_000
#: Configurations the simplifier may check after the search [count].
SIMPLIFY_CHECKS = 20_000
#: Default wall-clock cap of a plan [s].
DEFAULT_TIME_LIMIT = 10.0
#: One plan at a time: OMPL's random seed is process-wide.
_LOCK = threading.Lock()


class PlanError(KinError, ValueError):
    """A plan request that cannot be run as written (an unknown planner, a bad budget)."""


def plan(
    robot: Any,
    start: npt.ArrayLike,
    goal: Any,
    *,
    collisions: CollisionChecker | None = None,
    planner: str = DEFAULT_PLANNER,
    time_limit: float = DEFAULT_TIME_LIMIT,
    max_checks: int = DEFAULT_CHECKS,
    seed: int = 0,
    simplify: bool = True,
) -> PlanResult:
    """Plan a collision-free joint path from ``start`` to ``goal``.

    Args:
        robot: The robot (:class:`kin.RobotModel`).
        start: Start joint vector [rad] (or [m] for prismatic joints), within the limits.
        goal: A goal joint vector, or a :mod:`kin.ik` target (``PoseTarget``,
            ``PositionTarget``, ``AxisTarget``, a masked pose) in the base frame: every
            collision-free IK answer is then a goal (:mod:`kin.plan.goals`).
        collisions: The collision checker (scene, SRDF, padding); None: the arm against itself
            (``load_collision_model(robot)``).
        planner: An OMPL planner's name (:data:`PLANNERS`).
        time_limit: Wall-clock cap of the whole plan [s] (IK of a target included).
        max_checks: Configurations checked before the search gives up [count]: the bound that
            makes the answer the same on a busy machine.
        seed: Random seed of OMPL's sampling (0 to 2**31 - 1).
        simplify: Shorten the path with OMPL's simplifier (rope shortcuts, then vertex
            reduction), each shortcut certified.

    Returns:
        The path and how it was found, or the status saying why there is none.

    Raises:
        kin.JointVectorError: ``start`` or a joint goal of the wrong size or not finite.
        kin.NotWithinLimitsError: ``start`` or a joint goal outside the limits.
        PlanError: An unknown planner, a budget or cap that is not positive, a bad seed.
    """
    if planner not in PLANNERS:
        raise PlanError(f"unknown planner {planner!r}; choose one of: {', '.join(PLANNERS)}")
    if not (time_limit > 0.0):
        raise PlanError(f"time_limit must be a positive number of seconds, got {time_limit!r}")
    if isinstance(max_checks, bool) or not isinstance(max_checks, int) or max_checks < 1:
        raise PlanError(f"max_checks must be a positive integer, got {max_checks!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**31:
        raise PlanError(f"seed must be an integer from 0 to 2**31 - 1, got {seed!r}")
    q0 = as_joint_vector(robot, start)
    outside = limit_violations(robot, q0)
    if outside:
        raise outside[0]
    checker = collisions if collisions is not None else _self_checker(robot)
    began = time.perf_counter()
    empty = np.zeros((0, robot.nq))

    def answer(status: str, message: str, **fields: Any) -> PlanResult:
        fields.setdefault("path", empty)
        return PlanResult(
            status,  # type: ignore[arg-type]
            planner,
            message,
            plan_time=time.perf_counter() - began,
            seed=seed,
            **fields,
        )

    if checker.in_collision(q0):
        from ..ik.collision_aware import collision_reason

        reason = collision_reason(checker, q0)
        return answer("start_in_collision", f"the start is in collision ({reason})")
    if isinstance(goal, (list, tuple, np.ndarray)):
        goals = joint_goal(robot, goal, checker)
    else:
        goals = goal_configurations(robot, goal, q0, checker, time_limit)
    if goals.status != "ok":
        return answer(goals.status, goals.message)
    with _LOCK:
        return _search(
            robot,
            checker,
            q0,
            goals,
            planner,
            time_limit,
            max_checks,
            seed,
            simplify,
            began,
            answer,
        )


def _self_checker(robot: Any) -> CollisionChecker:
    from ..collision import CollisionChecker, load_collision_model

    return CollisionChecker(load_collision_model(robot))


def _search(
    robot: Any,
    checker: CollisionChecker,
    q0: np.ndarray,
    goals: GoalSet,
    planner: str,
    time_limit: float,
    max_checks: int,
    seed: int,
    simplify: bool,
    began: float,
    answer: Any,
) -> PlanResult:
    """The OMPL search on the certified space (the start and goals already checked free)."""
    ob, og, ou = silence_ompl()
    budget = Budget(max_checks, time_limit - (time.perf_counter() - began))
    lower, upper = joint_bounds(robot, np.vstack([q0[None, :], goals.q]))
    ends = [q0, *goals.q]
    # first the spheres alone (exact only at the start and goals), then the exact rule
    first = CertifiedSpace(checker, lower, upper, budget, exact=False, exact_at=ends)
    spaces: list[CertifiedSpace | None] = [first, None] if first.spheres is not None else [None]
    order = np.argsort(np.linalg.norm(goals.q - q0, axis=1), kind="stable")
    path: list[np.ndarray] | None = None
    found: Any = None
    space = first
    for phase, given in enumerate(spaces):
        if given is None:
            budget.max_checks = max_checks
            space = CertifiedSpace(checker, lower, upper, budget)
        else:
            space = given
            budget.max_checks = min(max_checks, SPHERE_CHECKS)
        for index in order:  # the straight motion, nearest goal first
            if space.motion_free(q0, goals.q[index]):
                path = [q0, goals.q[index]]
                break
            budget.reraise()
        if path is not None:
            break
        ou.RNG.setSeed(seed + 1)  # OMPL's seed 0 means "random"; every plan reseeds it
        setup = og.SimpleSetup(space.si)
        setup.setStartState(space.state(q0))
        goal_states = ob.GoalStates(space.si)
        for q in goals.q:
            goal_states.addState(space.state(q))
        setup.setGoal(goal_states)
        setup.setPlanner(getattr(og, planner)(space.si))
        solved = setup.solve(ob.PlannerTerminationCondition(budget.spent))
        budget.reraise()
        if solved and setup.haveExactSolutionPath():
            found = setup.getSolutionPath()
            break
        if budget.timed_out or phase + 1 == len(spaces):
            if budget.timed_out:
                return answer(
                    "timeout",
                    f"no path within the {time_limit:g} s cap ({budget.checks} checks)",
                    goals=goals.q,
                    checks=budget.checks,
                )
            return answer(
                "not_found",
                f"no path found within {max_checks} checks",
                goals=goals.q,
                checks=budget.checks,
            )
    if path is None:
        if simplify:
            simplifier = og.PathSimplifier(space.si)
            # its own work budget: once spent, every shortcut is refused and the path kept
            budget.max_checks = budget.checks + SIMPLIFY_CHECKS
            simplifier.ropeShortcutPath(found)
            simplifier.reduceVertices(found)
            budget.reraise()
        path = _without_collinear(
            [space.q(found.getState(i)) for i in range(found.getStateCount())]
        )
    return _certified(robot, checker, np.array(path), goals, budget, answer, space.spheres)


def _without_collinear(path: list[np.ndarray]) -> list[np.ndarray]:
    """The path without interior vertices on the straight line between their neighbours.

    The motion through such a vertex (to 1e-9 of the steps' lengths) is the straight motion that
    skips it, so the path does not change; only the rows are fewer (the final check judges the
    path returned).
    """
    kept = [path[0]]
    for middle, after in zip(path[1:-1], path[2:]):
        a, b = middle - kept[-1], after - middle
        scale = float(np.linalg.norm(a) * np.linalg.norm(b))
        if a @ b <= 0.0 or _sine(a, b) > 1e-9 * scale:  # a turn (the final check sees the rest)
            kept.append(middle)
    kept.append(path[-1])
    return kept


def _sine(a: np.ndarray, b: np.ndarray) -> float:
    """|a| |b| sin(angle between a and b), in any dimension (the area of their parallelogram)."""
    return float(np.sqrt(max((a @ a) * (b @ b) - (a @ b) ** 2, 0.0)))


def _certified(
    robot: Any,
    checker: CollisionChecker,
    path: np.ndarray,
    goals: GoalSet,
    budget: Budget,
    answer: Any,
    spheres: SphereMotion | None,
) -> PlanResult:
    """The path after its final check of every sample and every motion, from scratch.

    Each motion is judged by the spheres' rule (:mod:`kin.plan.sphere_motion`), and where they
    do not show it free, by :func:`kin.path.collision_check.check_path_collisions` (the exact
    rule, coal's distances).
    """
    from ..path.collision_check import check_path_collisions

    for i in range(len(path) - 1):
        if spheres is not None:
            a, b = path[i], path[i + 1]
            if spheres.state_free(a) and spheres.state_free(b):
                if spheres.motion_free(a, b, RESOLUTION, SIMPLIFY_CHECKS)[0]:
                    continue
        verdict = check_path_collisions(checker, path[i : i + 2])
        if not verdict.free:  # never expected: every edge passed the same rule
            return answer(
                "not_found",
                f"the path failed its final check ({verdict.first.describe()})",  # type: ignore[union-attr]
                goals=goals.q,
                checks=budget.checks,
            )
    reached = int(np.argmin(np.linalg.norm(goals.q - path[-1], axis=1)))
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    clearance = min(checker.distance(q).distance for q in path) if checker.model.pairs else None
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
