"""IK of a URDF chain with mimic joints behind the solvers' common interface.

``kin ik`` sees every solver through ``name``, ``target_kinds`` and
``solve(target, seed=None, *, timeout=None) -> IKResult`` (:mod:`kin.commands.solver_choice`).
:class:`MimicSolver` gives that interface to :meth:`kin.mimic.arm.MimicArm.search`: damped least
squares over the independent joints, every answer judged by Pinocchio's mimic model of the
original URDF inside every joint's limits, mimic ones included.

A search that ends without an answer proves nothing about the target: its status is
``"not_found"`` (``"timeout"`` when the time cap stopped it first), never ``"out_of_reach"``,
with the best attempt as the rejected solution.

Work, not time, decides the answer: the seed, then :data:`RESTARTS` starts, the first
:data:`NEAR_STARTS` of them sampled poses nearest the target (:mod:`.starts`), the rest random
(seeded), each of at most :data:`MAX_ITERATIONS` steps. The timeout (:data:`DEFAULT_TIMEOUT`) is
only a cap, checked before each start after the seed's: a call that reaches it says
``"timeout"``, else its answer is the one an idle machine gives.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..ik.exceptions import TargetError
from ..ik.result import IKResult
from ..ik.routing import REFUSED, own_search_routes
from ..ik.targets.target import PoseTarget, PositionTarget
from .starts import sample_table

if TYPE_CHECKING:
    from ..ik.numeric.seed_table import SeedTable
    from ..ik.targets.target import Target
    from .arm import MimicArm

__all__ = ["MimicSolver"]

#: The pipeline name in results.
PIPELINE = "mimic_dls"

#: Starts after the seed (near ones, then random): the work of one search (about 0.15 s when
#: nothing is found).
RESTARTS = 40

#: Starts from the samples whose poses are nearest the target (:mod:`.starts`), after the
#: seed and before the random ones (within :data:`RESTARTS`).
NEAR_STARTS = 8

#: Damped least-squares steps per start at most (a start also stops when stuck).
MAX_ITERATIONS = 200

#: Default cap on the time of one solve [s] (the partial poses' and the numeric pipeline's too).
DEFAULT_TIMEOUT = 2.0


class MimicSolver:
    """Damped least squares on a :class:`~kin.mimic.arm.MimicArm`'s coupled Jacobian.

    Args:
        arm: The arm (its joint vector holds the independent joints only).
        restarts: Random starts after the seed (the work; :data:`RESTARTS`).
        max_iter: Damped least-squares steps per start at most (:data:`MAX_ITERATIONS`).
    """

    name = PIPELINE
    #: A whole pose or a position, by its descent (:func:`kin.ik.routing.own_search_routes`); a
    #: masked pose or another kind refused.
    routes = own_search_routes((PoseTarget, PositionTarget))
    target_kinds: tuple[type, ...] = routes.kinds
    #: ``route(target)``: its descent, or none (:meth:`kin.ik.routing.Routes.of`).
    route = routes.of
    #: No closed form, no numeric or partial-pose solver behind it: its own descent.
    closed_form_kinds: tuple[type, ...] = ()
    numeric = None
    partial = None

    def __init__(self, arm: MimicArm, restarts: int = RESTARTS, max_iter: int = MAX_ITERATIONS):
        self.arm = arm
        self.robot = arm  # what it solves, under the solver interface's name
        self.restarts = restarts
        self.max_iter = max_iter
        self._table: SeedTable | None = None  # the samples of the starts, made on first solve

    def batch_route(self) -> None:
        """None: a batch solves target by target (:class:`kin.ik.solver.IKSolver`)."""
        return None

    def solve(
        self,
        target: Target,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        all_branches: bool = False,
    ) -> IKResult:
        """Solve a whole pose or a position of the tip in the chain's base link.

        Args:
            target: A :class:`~kin.ik.targets.target.PoseTarget` (no mask) or a
                :class:`~kin.ik.targets.target.PositionTarget`, in the base link [m].
            seed: First start [rad] or [m] of the independent joints, clipped into the limits
                (default: zero, clipped so: ``kin ik``'s seed without ``--seed-q``, as
                :func:`kin.configuration.default_seed` is every other arm's).
            timeout: Cap on the time [s] (None: :data:`DEFAULT_TIMEOUT`): no new start after
                it (the seed's always runs); a start once begun runs to its end, so a call the
                cap does not stop gives the answer of an idle machine.
            all_branches: Ignored (one answer: the search's).

        Returns:
            ``"ok"`` with the answer, else ``"not_found"`` (every start done) or ``"timeout"``
            with the best attempt rejected.

        Raises:
            TargetError: Another kind of target, or a pose with a mask.
            kin.exceptions.JointVectorError: ``seed`` is not one value per independent joint.
        """
        started = time.perf_counter()
        cap = DEFAULT_TIMEOUT if timeout is None else timeout
        if not cap >= 0.0:
            raise TargetError(f"timeout must be a number of seconds >= 0, got {timeout!r}")
        if self.routes.of(target) is REFUSED:
            raise TargetError(
                f"'{self.arm.name}' (a chain with mimic joints) takes a whole pose (--rpy or "
                "--quat, no --mask) or a position"
            )
        rotation = None if isinstance(target, PositionTarget) else np.asarray(target.rotation)  # type: ignore[union-attr]
        position = np.asarray(target.position)

        def near() -> np.ndarray:
            table = self._table
            if table is None:  # two threads may both build it: the same samples (seeded)
                table = self._table = sample_table(self.arm)
            return table.nearest_rows(position, rotation, NEAR_STARTS)

        found = self.arm.search(
            position,
            rotation,
            np.zeros(self.arm.nq) if seed is None else seed,
            restarts=self.restarts,
            max_iter=self.max_iter,
            timeout=cap,
            near=near,
        )
        elapsed = time.perf_counter() - started
        if found.answer is not None:
            method = (
                "damped_least_squares"
                if found.starts == 1
                else "seed_table"
                if found.starts <= 1 + NEAR_STARTS
                else "random_restart"
            )
            return IKResult(
                True,
                PIPELINE,
                "ok",
                "on target inside every joint's limits, mimic joints included (judged by "
                "Pinocchio's mimic model of the URDF)",
                (found.answer,),
                iterations=found.iterations,
                time=elapsed,
                method=method,
            )
        if found.starts < self.restarts + 1:  # the timeout stopped the starts
            return IKResult(
                False,
                PIPELINE,
                "timeout",
                f"the time cap ({cap * 1e3:.4g} ms) stopped the search after {found.starts} of "
                f"{self.restarts + 1} starts; best position error "
                f"{found.best.position_error:.4g} m: raise the timeout (--timeout)",
                (),
                (found.best,),
                iterations=found.iterations,
                time=elapsed,
            )
        return IKResult(
            False,
            PIPELINE,
            "not_found",
            f"no solution inside the joint limits found in {found.starts} starts; the search "
            "does not prove the target out of reach",
            (),
            (found.best,),
            iterations=found.iterations,
            time=elapsed,
        )
