"""The state one numeric solve shares between its stages: the target, the budget, the best attempt.

Each stage of :class:`~kin.ik.numeric.solver.NumericIK` (closed form with a free joint, seed-table
starts, random restarts, mink QP) runs damped Newton from its starts through :meth:`Search.newton`
and hands every outcome to :meth:`Search.accept`, which returns the verified result or keeps the
best failed attempt for :meth:`Search.failure`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from operator import le
from typing import TYPE_CHECKING

import numpy as np

from ..reach import REACH_COST, known_reach
from ..result import IKResult, IKSolution
from .damped_newton import LINALG_COST, NewtonOutcome, damped_newton, linalg_within
from .numeric_target import NumericTarget

if TYPE_CHECKING:
    from .context import NumericContext
    from .seed_table import SeedTable

#: Weight of the rotation error when ranking failed attempts [m/rad].
RANK_WEIGHT = 0.1

#: Pipeline name reported in :attr:`IKResult.solver`.
PIPELINE = "numeric"

#: The shortest hard end of a call [s] (see :func:`allowance`).
MIN_ALLOWANCE = 0.02


def allowance(timeout: float) -> float:
    """How long a call with time budget ``timeout`` [s] may take at most, cold caches included.

    ``max(2 timeout, 20 ms)``: the search stops at ``timeout``; loading a cache or a model that a
    stage needs (the seed table, the MuJoCo model of the QP runs) counts too, and is done only
    when its expected cost ends before this.
    """
    return max(2.0 * timeout, MIN_ALLOWANCE)


class Search:
    """One solve in progress.

    Args:
        ik: The solver as its stages see it (:class:`~.context.NumericContext`).
        target: The target (``position`` [m], ``rotation`` or None, ``posture`` or None).
        position_tol: Success tolerance on the position [m].
        rotation_tol: Success tolerance on the rotation [rad].
        timeout: Time budget [s], counted from ``start``.
        start: ``time.perf_counter()`` when the call began (default: now).
        table: The seed table, or None when this call could not afford to build it (the stages
            that start from its samples are skipped).
        seed: The caller's seed as a checked joint vector [rad], or None: prepared once, read by
            every stage.
        random_seed: Seed of the random restarts.
        max_attempts: Stop after this many starts even before the deadline, or None.
    """

    __slots__ = (
        "ik",
        "target",
        "position_tol",
        "rotation_tol",
        "start",
        "deadline",
        "best",
        "best_from_qp",
        "iterations",
        "attempts",
        "inner_position_tol",
        "inner_rotation_tol",
        "seed_distance",
        "seed_bound",
        "seed_tried",
        "seed_scanned",
        "allowance",
        "table",
        "linalg",
        "seed",
        "random_seed",
        "max_attempts",
    )

    def __init__(
        self,
        ik: NumericContext,
        target: NumericTarget,
        position_tol: float,
        rotation_tol: float,
        timeout: float,
        start: float | None = None,
        table: SeedTable | None = None,
        seed: np.ndarray | None = None,
        random_seed: int = 0,
        max_attempts: int | None = None,
    ):
        self.ik = ik
        self.seed = seed
        self.random_seed = random_seed
        self.max_attempts = max_attempts
        self.target = target
        self.position_tol = position_tol
        self.rotation_tol = rotation_tol
        self.start = time.perf_counter() if start is None else start
        self.deadline = self.start + timeout
        #: The hard end of the call: a cold resource (the MuJoCo model) is loaded only when its
        #: cost fits before it (:func:`allowance`).
        self.allowance = self.start + allowance(timeout)
        self.table = table
        #: The damped Newton steps' linear algebra: SciPy's LAPACK when loaded or affordable;
        #: chosen at the first step (most calls end in the closed form without one).
        self.linalg: tuple | None = None
        self.best: NewtonOutcome | None = None
        self.best_from_qp = False
        self.iterations = 0
        self.attempts = 0
        #: Tolerances of damped Newton and mink QP runs: ten times tighter than the judge's.
        self.inner_position_tol = 0.1 * position_tol
        self.inner_rotation_tol = 0.1 * rotation_tol
        #: Squared distance of the caller's seed's tool to the target in the seed table's
        #: embedding (:func:`.starts.seed_distance`), once measured.
        self.seed_distance: float | None = None
        #: A lower bound of :attr:`seed_distance` when only that is known, else None.
        self.seed_bound: float | None = None
        #: Whether damped Newton already ran from the caller's seed (a stage skips it then).
        self.seed_tried = False
        #: Whether the free-joint closed form already ran from the caller's seed, every scan step
        #: (its compiled path, :func:`.free_joint.compiled_seeded`): stage 0 goes on from the
        #: seed-table samples.
        self.seed_scanned = False

    def expired(self) -> bool:
        """Whether the time budget is spent."""
        return time.perf_counter() > self.deadline

    def newton(
        self, q0: np.ndarray, patience: int | None, leash: float | None = None
    ) -> NewtonOutcome:
        """Damped Newton from ``q0`` (``patience``, ``leash``: see :func:`damped_newton`), counted."""
        ik, target = self.ik, self.target
        if self.linalg is None:  # SciPy's import pays off only for steps the twin does not take
            twin = ik.compiled_step and target.rotation is not None
            self.linalg = linalg_within(not twin and self.affords(LINALG_COST))
        outcome = damped_newton(
            ik.search_model,
            ik.data,
            ik.frame_id,
            q0,
            target.position,
            target.rotation,
            max_iterations=ik.newton_iterations,
            position_tol=self.inner_position_tol,
            rotation_tol=self.inner_rotation_tol,
            posture=target.posture,
            patience=patience,
            leash=leash,
            linalg=self.linalg,
            compiled=ik.compiled_step,
        )
        self.iterations += outcome.iterations
        self.attempts += 1
        if ik.continuous:  # back into [-pi, pi]: the same pose
            q = outcome.q
            for i in ik.continuous:
                q[i] = math.remainder(q[i], 2.0 * math.pi)
        return outcome

    def accept(
        self, outcome: NewtonOutcome, method: str, message: str, from_qp: bool = False
    ) -> IKResult | None:
        """The result when ``outcome`` is verified; else None (kept if the best so far).

        The last damped Newton evaluation ran Pinocchio's forward kinematics at ``outcome.q``
        itself: its errors are the judge's measurement (:mod:`kin.ik.judge` would recompute them,
        equal to rounding); the limits are checked on the returned values.
        """
        q = outcome.q
        values = q.tolist()
        if (
            outcome.converged
            and outcome.position_error < self.position_tol
            and outcome.rotation_error < self.rotation_tol
            and all(map(le, self.ik.lows, values))
            and all(map(le, values, self.ik.highs))
        ):
            rotation_error = None if self.target.rotation is None else outcome.rotation_error
            solution = IKSolution(q.copy(), "", True, outcome.position_error, rotation_error)
            return self.success(solution, method, message)
        best = self.best
        if best is None or (
            outcome.position_error + RANK_WEIGHT * outcome.rotation_error
            < best.position_error + RANK_WEIGHT * best.rotation_error
        ):
            self.best = outcome
            self.best_from_qp = from_qp
        return None

    def success(
        self, solution: IKSolution, method: str, message: str, iterations: int | None = None
    ) -> IKResult:
        """The successful result with one verified solution, answered by stage ``method``.

        ``iterations``: reported instead of the damped Newton steps so far (a closed form's
        answer reports 0).
        """
        return IKResult(
            True,
            PIPELINE,
            "ok",
            message,
            (solution,),
            iterations=self.iterations if iterations is None else iterations,
            time=time.perf_counter() - self.start,
            method=method,
        )

    def affords(self, cost: float) -> bool:
        """Whether a load expected to take ``cost`` [s] ends before the call's hard end."""
        return time.perf_counter() + cost <= self.allowance

    @property
    def out_of_reach(self) -> bool:
        """Whether the target is beyond the arm's reach (the largest distance found from its base).

        When that distance is not known yet and the call cannot afford finding it
        (:data:`~kin.ik.reach.REACH_COST`), the sure bound (links laid end to end) decides.
        """
        ik = self.ik
        reach = known_reach(ik.robot)
        if reach is None and self.affords(REACH_COST):
            reach = ik.arm_reach
        limit = ik.reach if reach is None else reach.maximum
        return ik.distance_from_base(self.target.position) > limit

    def failure(self) -> IKResult:
        """The failed result: the best configuration found, measured by the judge.

        ``out_of_reach`` beyond the arm's reach; ``timeout`` when the deadline ended the starts;
        ``not_found`` when they were all done (``max_attempts``).
        """
        ik, target, best = self.ik, self.target, self.best
        elapsed = time.perf_counter() - self.start
        rejected: tuple[IKSolution, ...] = ()
        detail = "no configuration"
        if best is not None:
            verdict = ik.judge.measure(best.q, target)
            rotation_error = None if target.position_only else verdict.rotation_error
            rejected = (
                IKSolution(
                    best.q.copy(),
                    "",
                    verdict.within_limits,
                    verdict.position_error,
                    rotation_error,
                ),
            )
            detail = f"best configuration misses by {verdict.position_error:.3g} m" + (
                "" if target.position_only else f" and {verdict.rotation_error:.3g} rad"
            )
        if self.out_of_reach:
            found = known_reach(ik.robot)
            reach = ik.reach if found is None else found.maximum
            distance = ik.distance_from_base(target.position) - reach
            return IKResult(
                False,
                PIPELINE,
                "out_of_reach",
                f"target is {distance:.4g} m beyond the arm's reach ({reach:.4g} m from its "
                f"base); {detail}",
                (),
                rejected,
                distance_to_workspace=distance,
                iterations=self.iterations,
                time=elapsed,
            )
        worked = self.max_attempts is not None and self.attempts >= self.max_attempts
        if self.expired() and not worked:  # the deadline stopped the starts, not their count
            return IKResult(
                False,
                PIPELINE,
                "timeout",
                f"the time budget ({(self.deadline - self.start) * 1e3:.4g} ms) ended the search "
                f"after {self.attempts} starts; {detail}: raise the timeout (--timeout)",
                (),
                rejected,
                iterations=self.iterations,
                time=elapsed,
            )
        return IKResult(
            False,
            PIPELINE,
            "not_found",
            f"no solution inside the joint limits found in {self.attempts} starts; {detail}",
            (),
            rejected,
            iterations=self.iterations,
            time=elapsed,
        )


@dataclass(frozen=True)
class Stage:
    """One stage of the numeric pipeline: its name and what it runs.

    Attributes:
        name: The stage, as :attr:`IKResult.method` names its answers (``"seed_table"``, ...).
        run: ``run(ik, search)``: a verified result, or None to hand the search to the next
            stage.
    """

    name: str
    run: Callable[[NumericContext, Search], IKResult | None]


def run_stages(stages: Sequence[Stage], ik: NumericContext, search: Search) -> IKResult:
    """The first verified result of ``stages`` in order, else the search's failure."""
    for stage in stages:
        done = stage.run(ik, search)
        if done is not None:
            return done
    return search.failure()
