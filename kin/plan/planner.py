"""Collision-free motion planning with OMPL: from a joint vector to a joint vector or an IK target.

:func:`plan` checks the start and the goals, tries the straight joint motion to each goal first
(most plans in an open cell need nothing else), then runs an OMPL planner on
:class:`~kin.plan.ompl_problem.CertifiedSpace` (the project's collision checker and its motion
rule, so every edge is certified), shortens the path with OMPL's simplifier (whose shortcuts go
through the same motion rule), and checks the whole result once more
(:func:`kin.plan.final_check.certified`) before it is returned.

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
from .final_check import certified
from .goals import GoalSet, goal_configurations, joint_goal
from .ompl_problem import (
    Budget,
    CertifiedSpace,
    joint_bounds,
    prepare,
    silence_ompl,
)
from .result import PlanResult

if TYPE_CHECKING:  # pragma: no cover
    from ..collision import CollisionChecker

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
#: Configurations the exact rule may check on a straight motion to a goal [count].
STRAIGHT_CHECKS = 64
#: Configurations the exact rule may check on the motion to an escape (:func:`_escape`) [count].
ESCAPE_CHECKS = 64
#: Joint-space distances [rad] at which a state near a start or goal is looked for (:func:`_escape`).
ESCAPE_STEPS = (0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7)
#: Random directions tried at each of :data:`ESCAPE_STEPS` [count].
ESCAPE_TRIES = 16
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
    any_turn: bool = False,
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
        time_limit: Wall-clock cap of the whole plan [s] (IK of a target included; the
            checker's one-off setup, :func:`kin.plan.prepare`, made before the clock starts).
        max_checks: Configurations checked before the search gives up [count]: the bound that
            makes the answer the same on a busy machine.
        seed: Random seed of OMPL's sampling (0 to 2**31 - 1).
        simplify: Shorten the path with OMPL's simplifier (rope shortcuts, then vertex
            reduction), each shortcut certified.
        any_turn: A joint goal's whole-turn copies within the limits are goals too (the same
            place of the arm; :func:`kin.plan.goals.joint_goal`): the path may end a turn away
            from the values given, at ``goals[goal_index]``. A target's goals have theirs anyway.

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
    prepare(checker)  # once per checker: the spheres' tests, the exact rule (not in plan_time)
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
        from ..ik.collision.collision_aware import collision_reason

        reason = collision_reason(checker, q0)
        return answer("start_in_collision", f"the start is in collision ({reason})")
    if isinstance(goal, (list, tuple, np.ndarray)):
        goals = joint_goal(robot, goal, checker, q0, any_turn)
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
    """The OMPL search on the certified space (the start and goals already checked free).

    Three steps, each bounded by work: the straight motion to each goal (nearest first); the
    search on the spheres alone (:mod:`kin.plan.sphere_motion`: no coal), from and to states
    near the start and goals that the spheres show free, reached from them by a short motion the
    exact rule certifies (:func:`_escape`), for up to :data:`SPHERE_CHECKS` checks; then, if
    that found nothing, the search on the exact rule (spheres first, coal where they cannot
    tell) with the whole budget.
    """
    ob, og, ou = silence_ompl()
    budget = Budget(max_checks, time_limit - (time.perf_counter() - began))
    lower, upper = joint_bounds(robot, np.vstack([q0[None, :], goals.q]))
    exact = CertifiedSpace(checker, lower, upper, budget)
    order = np.argsort(np.linalg.norm(goals.q - q0, axis=1), kind="stable")
    for index in order:  # the straight motion, nearest goal first
        if exact.motion_free(q0, goals.q[index], STRAIGHT_CHECKS):
            return certified(checker, np.array([q0, goals.q[index]]), goals, budget, answer, exact)
        budget.reraise()
    path = None
    spheres = exact.spheres
    if spheres is not None:
        budget.max_checks = min(max_checks, SPHERE_CHECKS)
        rng = np.random.default_rng(seed)
        start = _escape(q0, exact, rng, lower, upper)
        near = [_escape(q, exact, rng, lower, upper) for q in goals.q]
        kept = [i for i, q in enumerate(near) if q is not None]
        targets = [q for q in near if q is not None]
        if start is not None and kept:
            space = CertifiedSpace(checker, lower, upper, budget, exact=False, shown=exact.shown)
            found = _ompl(space, start, targets, planner, seed, simplify, ob, og, ou)
            budget.reraise()
            if found is not None:
                ends = [np.linalg.norm(found[-1] - q) for q in targets]
                reached = kept[int(np.argmin(ends))]
                path = _without_collinear(_joined(q0, found, goals.q[reached]))
    if path is None:
        budget.max_checks = max_checks
        found = _ompl(exact, q0, list(goals.q), planner, seed, simplify, ob, og, ou)
        budget.reraise()
        if found is None:
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
        path = _without_collinear(found)
    return certified(checker, np.array(path), goals, budget, answer, exact)


def _joined(q0: np.ndarray, found: list[np.ndarray], goal: np.ndarray) -> list[np.ndarray]:
    """The start, the path found between the escapes, the goal (an escape that is its end kept once)."""
    head = [] if np.array_equal(found[0], q0) else [q0]
    tail = [] if np.array_equal(found[-1], goal) else [goal]
    return head + found + tail


def _escape(
    q: np.ndarray,
    exact: CertifiedSpace,
    rng: np.random.Generator,
    lower: np.ndarray,
    upper: np.ndarray,
) -> np.ndarray | None:
    """``q`` when the spheres show it free, else a state near it that they do, or None.

    The state is reached from ``q`` by a straight motion the exact rule certifies: random
    directions (``rng``: the plan's seed) at joint-space distances of :data:`ESCAPE_STEPS` [rad],
    :data:`ESCAPE_TRIES` each, the first that works.
    """
    spheres = exact.spheres
    assert spheres is not None
    if spheres.state_free(q):
        return q
    for step in ESCAPE_STEPS:
        for _ in range(ESCAPE_TRIES):
            if exact.budget.spent():
                return None
            direction = rng.normal(size=len(q))
            candidate = np.clip(q + step * direction / np.linalg.norm(direction), lower, upper)
            exact.budget.checks += 1
            if spheres.state_free(candidate) and exact.motion_free(q, candidate, ESCAPE_CHECKS):
                return candidate
    return None


def _ompl(
    space: CertifiedSpace,
    start: np.ndarray,
    goals: list[np.ndarray],
    planner: str,
    seed: int,
    simplify: bool,
    ob: Any,
    og: Any,
    ou: Any,
) -> list[np.ndarray] | None:
    """OMPL's ``planner`` on ``space`` from ``start`` to any of ``goals``, simplified; or None."""
    ou.RNG.setSeed(seed + 1)  # OMPL's seed 0 means "random"; every plan reseeds it
    setup = og.SimpleSetup(space.si)
    setup.setStartState(space.state(start))
    goal_states = ob.GoalStates(space.si)
    for q in goals:
        goal_states.addState(space.state(q))
    setup.setGoal(goal_states)
    setup.setPlanner(getattr(og, planner)(space.si))
    budget = space.budget
    solved = setup.solve(ob.PlannerTerminationCondition(budget.spent))
    if budget.raised is not None or not (solved and setup.haveExactSolutionPath()):
        return None
    found = setup.getSolutionPath()
    if simplify:
        simplifier = og.PathSimplifier(space.si)
        # its own work budget: once spent, every shortcut is refused and the path kept
        budget.max_checks = budget.checks + SIMPLIFY_CHECKS
        simplifier.ropeShortcutPath(found)
        simplifier.reduceVertices(found)
    return [space.q(found.getState(i)) for i in range(found.getStateCount())]


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
