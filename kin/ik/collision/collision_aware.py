"""IK that avoids collisions: every answer of a solver judged by a collision checker.

:class:`CollisionAwareSolver` wraps any solver of the table (:mod:`.solver_table`) and a
:class:`~kin.collision.CollisionChecker`. Each valid answer of the wrapped solver is checked at
its joint vector; a colliding one moves to :attr:`~kin.ik.IKResult.rejected` with its reason
(``"self: forearm/base"``, ``"scene: table"``; every pair in contact, deepest first), never into
:attr:`~kin.ik.IKResult.solutions`. When the free answers that remain are none, the search goes
on where the arm has freedom left, bounded by work (the timeout only a cap):

- a target that leaves components free (an axis target, a masked pose: the route
  :data:`~kin.ik.routing.PARTIAL`): every roll of the partial-pose sweep
  (:meth:`~kin.ik.partial_pose.PartialPoseIK.solve` with ``every_roll=True``);
- a full pose on a 7R arm with a free-joint closed form: every branch of the all-branches grid
  (:mod:`kin.ik.numeric.all_branches`);
- any target the numeric solver answers: the distance-bounded solve
  (:mod:`kin.ik.collision.collision_bound`: each step a QP that keeps every checked pair apart) from
  the seed, the colliding answers and a few seeded random starts (from the seed alone where the
  free-joint grid swept the self-motion); then :data:`EXTRA_STARTS` more plain solves, each from a start drawn
  uniformly inside the limits (a fixed random seed: reproducible).

A closed-form 6R pose has every branch in its first answer: the nearest free branch is the
answer, with no search. The first free answers found win, nearest the caller's seed first.

The answers are judged nearest the seed first, and by default the judging stops at the first
free one: ``solutions`` holds that answer alone (the farther ones are not checked, so not
returned); ``every=True`` (or ``all_branches=True`` of a call, ``kin ik --all``) judges every
answer and keeps all the free ones. Only the answers judged colliding get a reason (a second,
full query of the checker).

Statuses: the wrapped solver's (``out_of_reach``, ``not_found``, ...) pass through unchanged;
``in_collision`` when answers were found but every one collides (after the extra search);
``timeout`` when the cap stopped the extra search first.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import numpy.typing as npt

from dh2urdf.output_text import shown_name

from ..numeric.sampling_box import sampling_limits
from ..result import IKResult, IKSolution
from ..routing import PARTIAL
from ..solver import IKSolver, PartialSolver
from ..targets.target import PoseTarget

__all__ = ["EXTRA_STARTS", "CollisionAwareSolver", "collision_reason"]

#: Numeric solves from random starts after every answer of the usual solve collided.
EXTRA_STARTS = 16
#: Default time cap of the whole collision-aware solve [s] (the numeric solver's default).
DEFAULT_TIMEOUT = 2.0


def collision_reason(checker: Any, q: np.ndarray) -> str:
    """Why ``q`` collides: ``"self: a/b"`` per link pair, ``"scene: name"`` per scene object.

    Pairs deepest first, joined by ``"; "``; ``""`` when nothing is in contact.
    """
    scene = set(checker.model.scene_objects)
    parts: list[str] = []
    for contact in checker.collisions(q):
        a, b = shown_name(contact.a), shown_name(contact.b)  # one line, whatever the names
        if contact.b in scene:
            part = f"scene: {b}"
        elif contact.a in scene:
            part = f"scene: {a}"
        else:
            part = f"self: {b}/{a}"
        if part not in parts:
            parts.append(part)
    return "; ".join(parts)


def _rejected(solution: IKSolution, reason: str) -> IKSolution:
    return IKSolution(
        solution.q,
        solution.branch,
        solution.within_limits,
        solution.position_error,
        solution.rotation_error,
        reason,
    )


class CollisionAwareSolver:
    """A solver whose answers are all collision-free at their joint vectors (see the module).

    Args:
        solver: A solver of the table (:func:`kin.ik.get_solver`), or any with its protocol.
        checker: The collision checker of the same robot
            (:class:`~kin.collision.CollisionChecker`).
        every: Judge every answer and keep all the free ones (default: stop at the first free
            one, nearest the seed).

    Attributes:
        name: The wrapped solver's name (:attr:`IKResult.solver`).
    """

    def __init__(self, solver: IKSolver, checker: Any, *, every: bool = False):
        if checker.model.robot.nq != solver.robot.nq:
            from ..exceptions import IKError

            raise IKError(
                f"collision model of {checker.model.robot.name!r} ({checker.model.robot.nq} "
                f"joints) does not fit robot {solver.robot.name!r} ({solver.robot.nq} joints)"
            )
        self.solver = solver
        self.checker = checker
        self.every = every
        self.robot = solver.robot
        self.name = solver.name
        #: ``route(target)``: the wrapped solver's (its answers judged, not routed again).
        self.route = solver.route
        # imported here, not in the first capped call that needs it (10-15 ms cold)
        from .collision_bound import solve_clear

        self._solve_clear = solve_clear

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """The target classes :meth:`solve` accepts (the wrapped solver's)."""
        return tuple(self.solver.target_kinds)

    def batch_route(self) -> None:
        """None: every target of a batch is solved and judged one by one."""
        return None

    @property
    def closed_form_kinds(self) -> tuple[type, ...]:
        """The wrapped solver's (its answers are judged, not searched again)."""
        return tuple(self.solver.closed_form_kinds)

    @property
    def numeric(self) -> IKSolver | None:
        """The wrapped solver's numeric solver (its answers not judged: the search's part)."""
        return self.solver.numeric

    @property
    def partial(self) -> PartialSolver | None:
        """The wrapped solver's partial-pose solver (its answers not judged)."""
        return self.solver.partial

    def solve(
        self,
        target: Any,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        all_branches: bool = False,
    ) -> IKResult:
        """Solve ``target`` from ``seed`` [rad / m]; only collision-free answers are solutions.

        Args:
            target: Any target the wrapped solver takes.
            seed: Start joint vector [rad] (or [m]), or None.
            timeout: Cap on the whole call [s], extra search included (None:
                :data:`DEFAULT_TIMEOUT` for the extra search; the first solve the wrapped
                solver's default).
            all_branches: Passed to the wrapped solver's first solve; every answer is judged
                and every free one kept (as ``every``).

        Returns:
            The wrapped solver's result with the colliding answers moved to ``rejected``; status
            ``in_collision`` or ``timeout`` when no free answer is left (see the module).
        """
        start = time.perf_counter()
        first = self.solver.solve(target, seed, timeout=timeout, all_branches=all_branches)
        if not first.solutions:
            return first
        every = self.every or all_branches
        free, colliding = self._judge(first.solutions, every)
        if free:
            if not colliding and len(free) == len(first.solutions):
                return first
            unchecked = len(first.solutions) - len(free) - len(colliding)
            return self._result(first, free, colliding, start, unchecked=unchecked)
        cap = start + (DEFAULT_TIMEOUT if timeout is None else timeout)
        found, more, stopped = self._search(target, seed, first, cap)
        colliding += [c for c in more if not _known(c, colliding)]
        if found:
            return self._result(found, found.solutions, colliding, start, found.method)
        return self._failure(first, colliding, start, stopped)

    # -- judging ---------------------------------------------------------------------------------

    def _judge(
        self, solutions: tuple[IKSolution, ...], every: bool
    ) -> tuple[tuple[IKSolution, ...], list[IKSolution]]:
        """(free answers in order, colliding ones with their reasons).

        Up to the first free answer, unless ``every``.
        """
        checker = self.checker
        free: list[IKSolution] = []
        colliding: list[IKSolution] = []
        for solution in solutions:
            q = solution.q  # in_collision takes a float64 vector as it is, converts the rest
            if checker.in_collision(q):
                colliding.append(_rejected(solution, collision_reason(checker, q)))
            else:
                free.append(solution)
                if not every:
                    break
        return tuple(free), colliding

    def _result(
        self,
        base: IKResult,
        free: tuple[IKSolution, ...],
        colliding: list[IKSolution],
        start: float,
        method: str | None = None,
        unchecked: int = 0,
    ) -> IKResult:
        """The result of free answers; ``unchecked``: answers after the first free one, not judged."""
        skipped = f"; {unchecked} farther answer(s) not checked" if unchecked else ""
        return IKResult(
            True,
            base.solver,
            "ok",
            f"{len(free)} collision-free solution(s) (nearest first); {len(colliding)} colliding "
            f"rejected{skipped}",
            free,
            tuple(colliding) + tuple(base.rejected),
            base.distance_to_workspace,
            base.iterations,
            time.perf_counter() - start,
            base.method if method is None else method,
            base.free,
        )

    def _failure(
        self, first: IKResult, colliding: list[IKSolution], start: float, stopped: bool
    ) -> IKResult:
        count = len(colliding)
        nearest = colliding[0].reason or "a checked pair"
        if stopped:
            status = "timeout"
            message = (
                f"the time cap stopped the search for a collision-free answer; the {count} "
                f"answers found all collide (nearest: {nearest})"
            )
        else:
            status = "in_collision"
            message = (
                f"target is reachable, but all {count} answers found collide (nearest: {nearest})"
            )
        return IKResult(
            False,
            first.solver,
            status,  # type: ignore[arg-type]
            message,
            (),
            tuple(colliding) + tuple(first.rejected),
            None,
            first.iterations,
            time.perf_counter() - start,
            "",
            first.free,
        )

    # -- the search where the arm has freedom left -----------------------------------------------

    def _search(
        self, target: Any, seed: npt.ArrayLike | None, first: IKResult, cap: float
    ) -> tuple[IKResult | None, list[IKSolution], bool]:
        """(a result with free answers or None, the colliding answers met, stopped by the cap)."""
        colliding: list[IKSolution] = []
        for solve in self._searches(target, seed, first.solutions):
            left = cap - time.perf_counter()
            if left <= 0.0:
                return None, colliding, True
            result = solve(left)
            if result is None:
                continue
            free, bad = self._judge(result.solutions, self.every)
            colliding += bad
            if free:
                return _with(result, free), colliding, False
            if result.status == "timeout":
                return None, colliding, True
        return None, colliding, False

    def _searches(self, target: Any, seed: npt.ArrayLike | None, first: Any = ()) -> Any:
        """The extra solves for ``target``, each ``solve(time_left) -> IKResult | None``.

        ``first``: the first solve's colliding answers (starts of the distance-bounded solve).
        """
        solver = self.solver
        cls = target.__class__
        partial = solver.route(target) is PARTIAL  # leaves components free: every roll
        numeric = _numeric_of(solver, partial, target)
        swept = False  # the free-joint grid swept the self-motion: the bound from the seed alone
        if partial:
            sweeper = solver.partial
            if sweeper is not None:
                yield lambda left: sweeper.solve(target, seed, timeout=left, every_roll=True)
        elif cls is PoseTarget and numeric is not None and self.robot.nq == 7:
            swept = numeric.context.closed_form is not None
            yield lambda left: numeric.solve(target, seed, timeout=left, all_branches=True)
        if numeric is None:
            return
        solve_clear = self._solve_clear
        yield lambda left: solve_clear(
            self.robot, self.checker, target, seed, first, left, numeric.name, swept=swept
        )
        rng = np.random.default_rng(0)
        lower, upper = _limits(self.robot)
        for _ in range(EXTRA_STARTS):
            start_q = rng.uniform(lower, upper)
            yield lambda left, q=start_q: numeric.solve(target, q, timeout=left)


def _numeric_of(solver: IKSolver, partial: bool, target: Any) -> Any:
    """The numeric solver that answers ``target`` for ``solver``, or None.

    None when a closed form gave every branch (a full pose or position its structure takes) or
    the solver has no numeric one (Newton-Raphson).
    """
    if target.__class__ in solver.closed_form_kinds and not partial:
        return None
    return solver.numeric


def _limits(robot: Any) -> tuple[np.ndarray, np.ndarray]:
    lower = np.asarray(robot.lower, dtype=float)
    upper = np.asarray(robot.upper, dtype=float)
    lower, upper = sampling_limits(robot.table, lower, upper)  # a long rail within the arm's size
    lower = np.where(np.isfinite(lower), lower, -math.pi)
    upper = np.where(np.isfinite(upper), upper, math.pi)
    return lower, upper


def _with(result: IKResult, free: tuple[IKSolution, ...]) -> IKResult:
    return IKResult(
        True,
        result.solver,
        "ok",
        result.message,
        free,
        result.rejected,
        result.distance_to_workspace,
        result.iterations,
        result.time,
        result.method,
        result.free,
    )


def _known(solution: IKSolution, known: list[IKSolution]) -> bool:
    return any(np.allclose(solution.q, k.q, atol=1e-9) for k in known)
