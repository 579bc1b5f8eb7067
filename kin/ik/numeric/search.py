"""The state one numeric solve shares between its stages: the target, the cap, the best attempt.

Each stage of :class:`~kin.ik.numeric.solver.NumericIK` (closed form with a free joint, seed-table
starts, random restarts, mink QP) runs damped Newton from its starts through :meth:`Search.newton`
and hands every outcome to :meth:`Search.accept`, which returns the verified result or keeps the
best failed attempt for :func:`failure`.

Work, not time, decides the answer: the stages run a fixed number of starts
(:data:`MAX_ATTEMPTS`, the solver's ``max_attempts``) of a fixed number of steps, from seeded
draws, and load what they need (the seed table, the arm's reach, the MuJoCo model of the QP runs)
whenever they need it. The time budget is only a cap, checked before each start and each load
(:meth:`Search.expired`): a call that reaches it stops there with status ``timeout``. So the
same call answers the same on a busy or an idle machine, or says ``timeout``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from operator import le
from typing import TYPE_CHECKING

import numpy as np

from ..result import IKResult, IKSolution
from .damped_newton import NUMPY_LINALG, NewtonOutcome, damped_newton, linalg_within
from .numeric_target import NumericTarget
from .settings import MAX_ATTEMPTS

if TYPE_CHECKING:
    from .context import NumericContext
    from .seed_table import SeedTable

#: Weight of the rotation error when ranking failed attempts [m/rad].
RANK_WEIGHT = 0.1

#: Pipeline name reported in :attr:`IKResult.solver`.
PIPELINE = "numeric"


class Search:
    """One solve in progress.

    Args:
        ik: The solver's settings and model handles (:class:`~.context.NumericContext`).
        target: The target (``position`` [m], ``rotation`` or None, ``posture`` or None).
        position_tol: Success tolerance on the position [m].
        rotation_tol: Success tolerance on the rotation [rad].
        timeout: Cap on the time [s], counted from ``start``: checked before each start and each
            load, it stops the search (status ``timeout``); it never shortens the work.
        start: ``time.perf_counter()`` when the call began (default: now).
        table: The seed table, or None (the stages that start from its samples are skipped; the
            solver always hands its table, built or loaded before the search).
        seed: The caller's seed as a checked joint vector [rad], or None: prepared once, read by
            every stage.
        random_seed: Seed of the random restarts.
        max_attempts: The work: damped Newton starts of the search (None: :data:`MAX_ATTEMPTS`).
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
        "capped",
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
        self.max_attempts = MAX_ATTEMPTS if max_attempts is None else max_attempts
        self.target = target
        self.position_tol = position_tol
        self.rotation_tol = rotation_tol
        self.start = time.perf_counter() if start is None else start
        self.deadline = self.start + timeout
        #: Whether the cap stopped the search (:meth:`expired` found it reached).
        self.capped = False
        self.table = table
        #: The damped Newton steps' linear algebra, chosen at the first step by the target alone
        #: (most calls end in the closed form without one).
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
        """Whether the cap is reached; then the search is stopped (:attr:`capped`: ``timeout``).

        The stages ask before each start and each load, never inside one: a search the cap does
        not stop does the same work, and gives the same answer, on any machine.
        """
        if time.perf_counter() > self.deadline:
            self.capped = True
        return self.capped

    def newton(
        self, q0: np.ndarray, patience: int | None, leash: float | None = None
    ) -> NewtonOutcome:
        """Damped Newton from ``q0`` (``patience``, ``leash``: see :func:`damped_newton`), counted."""
        ik, target = self.ik, self.target
        if self.linalg is None:
            # By the target, never the clock: a full pose the compiled twin does not step takes
            # SciPy's LAPACK (imported now if need be: a load); positions (3 x 3 steps in Python)
            # and the twin's rare declines NumPy's, the same in every call.
            full = target.rotation is not None
            twin = ik.compiled_step and full
            self.linalg = linalg_within(True) if full and not twin else NUMPY_LINALG
        outcome = damped_newton(
            ik.search_model,
            ik.data,
            ik.frame_id,
            q0,
            target.position,
            target.rotation,
            max_iterations=ik.settings.newton_iterations,
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

    @property
    def out_of_reach(self) -> bool:
        """Whether the target is beyond the arm's reach (the largest distance found from its base).

        The reach is found on first use (:func:`kin.ik.reach.arm_reach`, a few milliseconds once
        per robot), whatever the time left: the verdict depends on the target alone.
        """
        ik = self.ik
        return ik.arm_reach.distance(self.target.position) > ik.arm_reach.maximum


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


def failure(search: Search) -> IKResult:
    """The failed result of ``search``: the best configuration found, measured by the judge.

    ``timeout`` when the cap stopped the search (:attr:`Search.capped`), whatever the target;
    else ``out_of_reach`` beyond the arm's reach, ``not_found`` when the work was done.
    """
    ik, target, best = search.ik, search.target, search.best
    elapsed = time.perf_counter() - search.start
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
    if search.capped:  # the cap stopped the starts, not their count
        return IKResult(
            False,
            PIPELINE,
            "timeout",
            f"the time cap ({(search.deadline - search.start) * 1e3:.4g} ms) stopped the search "
            f"after {search.attempts} of its {search.max_attempts} starts; {detail}: raise the "
            "timeout (--timeout)",
            (),
            rejected,
            iterations=search.iterations,
            time=elapsed,
        )
    if search.out_of_reach:
        reach = ik.arm_reach.maximum
        distance = ik.arm_reach.distance(target.position) - reach
        return IKResult(
            False,
            PIPELINE,
            "out_of_reach",
            f"target is {distance:.4g} m beyond the arm's reach ({reach:.4g} m from its "
            f"base); {detail}",
            (),
            rejected,
            distance_to_workspace=distance,
            iterations=search.iterations,
            time=elapsed,
        )
    return IKResult(
        False,
        PIPELINE,
        "not_found",
        f"no solution inside the joint limits found in {search.attempts} starts; {detail}",
        (),
        rejected,
        iterations=search.iterations,
        time=elapsed,
    )


def run_stages(stages: Sequence[Stage], ik: NumericContext, search: Search) -> IKResult:
    """The first verified result of ``stages`` in order, else the search's failure.

    The cap is checked before each stage (:meth:`Search.expired`): a capped search runs no more.
    """
    for stage in stages:
        if search.expired():
            break
        done = stage.run(ik, search)
        if done is not None:
            return done
    return failure(search)
