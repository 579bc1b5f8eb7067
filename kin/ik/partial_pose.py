"""Partial poses: a masked pose, a free tool axis, a full pose on an arm of fewer than six joints.

The targets real tasks give constrain fewer than six components of the tool pose: a SCARA's
position and yaw, a drill's position and axis (the roll about it free), any pose with a mask. An
arm of fewer than six joints asked for a full pose reaches it only when the pose lies in its
(lower-dimensional) set of poses. All of these are solved here, for any arm, by one method:

1. **Closed-form candidates** where the arm has a closed form (:mod:`.analytic.registry`): its
   branches for the pose (a mask keeps the given values of the free components); for an
   :class:`~kin.ik.AxisTarget`, the branches of the seed's roll (the seed's tool turned onto the
   axis by the smallest rotation: the answer nearest the seed), and of a grid of
   :data:`ROLL_GRID` rolls over a turn when those give none or when every roll is asked. An
   arm whose structure takes positions only (planar 2R, offset 3R) gives the branches of the
   position.
2. **Weighted least squares** (Levenberg-Marquardt, clamped to the joint limits) on the
   constrained components: from each off-target candidate, then from the seed, then from
   :data:`RANDOM_STARTS` random joint vectors inside the limits (a seeded draw: the same call gives
   the same answer on any machine; the timeout is only a cap, reported as ``timeout``). The
   residual is
   ``e = (p_target - p, w log3(R_target R^T))`` in world axes ([m], and [rad] weighted by
   :data:`ROTATION_WEIGHT` [m/rad]), the rows the mask keeps; for an axis target the rotation
   rows are ``w theta n`` with ``theta`` the angle from the tool axis to the target axis and
   ``n`` the unit vector of their cross product (the roll about the axis takes no part). Where
   the pose is not reachable this converges to the nearest pose the arm reaches (in that
   weighted sense), which the failure reports: ``not_found`` (the starts searched; no claim that
   the pose is unreachable) or ``timeout`` (the cap came first).

Every returned solution is measured by Pinocchio's forward kinematics on the constrained
components only (:class:`PartialTask`): position error ``|e_p|`` [m] and rotation error
``|e_r|`` [rad] of the kept components (the angle between the axes for an axis target), below
the judge's tolerances (:data:`~kin.ik.judge.POSITION_TOLERANCE`,
:data:`~kin.ik.judge.ROTATION_TOLERANCE`), and inside the joint limits. The result names the
free components (:attr:`IKResult.free`).
"""

from __future__ import annotations

import math
import threading
import time
from typing import Any

import numpy.typing as npt

from kin import RobotModel

from .exceptions import TargetError
from .judge import POSITION_TOLERANCE, ROTATION_TOLERANCE
from .partial.context import PartialCall, PoseCandidates, Samples, partial_context
from .partial.outcome import failure
from .partial.search import search
from .partial.settings import (
    DEFAULT_TIMEOUT,
    MAX_ITERATIONS,
    MAX_STEP,
    NEWTON_ITERATIONS,
    NEWTON_PATIENCE,
    RANDOM_STARTS,
    ROLL_GRID,
    ROTATION_WEIGHT,
    SAME_SOLUTION,
)
from .partial.task import PartialTask, sweeps
from .result import IKResult
from .targets.target import AxisTarget, PoseTarget, is_partial

# The settings and the task live in kin.ik.partial (the stages); their names stay importable here.
__all__ = [
    "DEFAULT_TIMEOUT",
    "MAX_ITERATIONS",
    "MAX_STEP",
    "NEWTON_ITERATIONS",
    "NEWTON_PATIENCE",
    "RANDOM_STARTS",
    "ROLL_GRID",
    "ROTATION_WEIGHT",
    "SAME_SOLUTION",
    "PartialPoseIK",
    "PartialTask",
    "is_partial",
    "sweeps",
]


class PartialPoseIK:
    """IK of partial poses of one robot: closed-form candidates, then weighted least squares.

    Args:
        robot: The robot.
        structure: Its closed-form structure (:func:`kin.ik.analytic.registry.recognise` of its
            forward table, :func:`~kin.ik.analytic.joint_directions.forward_table`), or None:
            looked up (the idealised table's when the true one misses a structure by
            rounding), none if no structure fits.
        name: The pipeline reported in :attr:`IKResult.solver`.
        samples: ``samples(position, rotation, end)``: joint vectors of the seed-table samples
            nearest a pose (``rotation`` None: nearest the position alone), tried after the seed
            and before the random starts; or None. ``end`` is the call's cap (a
            ``time.perf_counter()`` value); the samples depend on the target alone. A five-joint
            arm's poses are a thin set: a start in the right basin matters more there than
            many random ones.
        pose_candidates: ``pose_candidates(position, rotations, seed)``: the closed form's
            branches of full poses as the arm's joint vectors
            (:meth:`~kin.ik.analytic.closed_form.ClosedFormSolver.pose_candidates`: its
            idealisation, offsets and joint directions applied), or None: ``structure``'s own
            branches are used.

    Attributes:
        context: The model handles and hooks the stages read
            (:class:`~kin.ik.partial.context.PartialContext`).
    """

    def __init__(
        self,
        robot: RobotModel,
        structure: Any = None,
        name: str = "numeric",
        samples: Samples | None = None,
        pose_candidates: PoseCandidates | None = None,
    ):
        self.robot = robot
        self.name = name
        self.context = partial_context(robot, structure, name, samples, pose_candidates)
        self.structure = self.context.structure
        self._lock = threading.Lock()

    def solve(
        self,
        target: PoseTarget | AxisTarget,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        random_seed: int = 0,
        position_tol: float = POSITION_TOLERANCE,
        rotation_tol: float = ROTATION_TOLERANCE,
        every_roll: bool = False,
    ) -> IKResult:
        """The joint vectors inside the limits that put the tool on ``target``'s constrained components.

        Args:
            target: A pose (masked, or full on an arm of fewer than six joints) or an axis target.
            seed: Start joint vector [rad] (or [m] for prismatic joints); the solutions are
                ordered by distance to it; moved into the limits first (None: zero, or the
                nearest joint vector to it inside the limits).
            timeout: Cap on the time [s] (None: :data:`DEFAULT_TIMEOUT`); the search stops at the
                first solution after the closed-form candidates, after its starts
                (:data:`RANDOM_STARTS` random ones; ``not_found``), or at the cap (``timeout``).
            random_seed: Seed of the random starts (results are reproducible).
            position_tol: Success tolerance on the constrained position components [m].
            rotation_tol: Success tolerance on the constrained rotation components [rad].
            every_roll: For an axis target on a closed-form arm: the branches of every roll of
                the grid (:data:`ROLL_GRID` rolls over a turn) too, not only of the seed's roll
                (when that gives a solution).

        Raises:
            TargetError: A seed of the wrong size or with a value that is not finite.
        """
        start = time.perf_counter()
        budget = DEFAULT_TIMEOUT if timeout is None else timeout
        if not budget >= 0.0:
            raise TargetError(f"timeout must be a number of seconds >= 0, got {timeout!r}")
        ctx = self.context
        seed_q = ctx.seed(seed)
        if not target.finite:
            return IKResult(False, self.name, "invalid_target", f"target is not finite: {target}")
        task = PartialTask(target)
        if task.position_rows:  # the kept position components alone may be out of reach
            offset = (target.position - ctx.base).tolist()
            distance = math.hypot(*[offset[i] for i in task.position_rows])
            if distance > ctx.reach:
                return failure(
                    ctx,
                    task,
                    "out_of_reach",
                    f"target is {distance - ctx.reach:.4g} m beyond the arm's reach "
                    f"({ctx.reach:.4g} m from its base); no search",
                    (),
                    start,
                    distance - ctx.reach,
                )
        call = PartialCall(
            seed_q, start, start + budget, random_seed, position_tol, rotation_tol, every_roll
        )
        with self._lock:
            return search(ctx, task, call)
