"""Numeric IK of any DH table: a pipeline of small stages, inside the limits, verified by Pinocchio.

The stages, in order, until one returns a verified solution or the work is done (or the cap):

0. :mod:`.free_joint`: the closed form with a free joint, for an arm that has one (humanoid7's
   :class:`~kin.ik.analytic.structure.SevenDof` structure; Panda's and xArm7's
   :class:`~kin.ik.analytic.seven_r.shoulder7_structure.SphericalShoulder7R`, full poses; any
   other 7R arm's, :mod:`~kin.ik.analytic.seven_r.general_7r`, full poses, asked after stage 1
   when its closed form takes the general 6R elimination, about 1 ms a solve) and a target
   without posture preference. Most of its targets end here, in tens of microseconds. With
   ``near_seed``, a seed near the target gets the answer near it (damped Newton from the seed
   when the closed form's branch with the seed's free joint is far from it).
1. :mod:`.starts`: damped Newton from the seed-table samples nearest the target, after the
   caller's posture and seed for a redundant target (the answer stays near them).
2. :mod:`.restarts`: random restarts and mink QP runs with hard limits, until the search has
   made ``max_attempts`` starts (:data:`~.settings.MAX_ATTEMPTS`); then a last QP run from the best
   configuration.

Work, not time, decides the answer (:mod:`.search`): a fixed number of starts of a fixed number
of steps from seeded draws, and the seed table built or loaded before the search. The timeout
(:data:`DEFAULT_TIMEOUT`) is only a cap: a call that reaches it says ``timeout``. So a busy machine
gives the answers of an idle one, or ``timeout``.

:class:`~.search.Search` carries the target, the cap and the best attempt between stages.
Pinocchio is the judge: a configuration is a solution only when Pinocchio's forward kinematics at
it finds it within ``1e-5 m`` and ``1e-4 rad`` of the target and inside the limits. Otherwise the
result says so (``success=False``) and carries the best configuration found and its errors. One
exception to the judge: stage 0 from the caller's seed of a :class:`~kin.ik.PoseTarget` or
:class:`~kin.ik.PositionTarget` runs in one compiled call where the arm's closed form has a twin
(:func:`.free_joint.compiled_seeded`), which measures its answer with the table's DH product in C
(the chain Pinocchio's model is built from; the tests compare the two to 1e-12).
:attr:`IKResult.method` names the stage that answered: ``"closed_form_free_joint"``,
``"seed_table"``, ``"damped_newton"`` (from the caller's seed), ``"random_restart"``,
``"mink_qp"``.
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import threading
import time
from typing import Any

import numpy as np
import numpy.typing as npt

from kin import RobotModel, load_robot
from kin.configuration import seed_inside

from ..exceptions import TargetError
from ..judge import POSITION_TOLERANCE, ROTATION_TOLERANCE
from ..partial_pose import PartialPoseIK
from ..result import IKResult
from ..routing import NUMERIC, REFUSED, numeric_routes
from ..solver import FreeJointRoute
from ..targets.target import AxisTarget, PoseTarget, PositionTarget, kind_error
from .build_context import build_context, compiled_stage0
from .damped_newton import load_linalg
from .free_joint import METHOD as FREE_JOINT
from .free_joint import (
    solve_free_joint,
)
from .numeric_target import NumericTarget
from .restarts import MINK_QP, RANDOM_RESTART, polish_best, solve_with_restarts
from .search import PIPELINE, Search, Stage, run_stages
from .seed_table import SeedTable, seed_table_of
from .settings import DEFAULT_CLOSED_FORM_STEPS as DEFAULT_CLOSED_FORM_STEPS
from .settings import NumericSettings
from .solver_fields import free_joint_route, read_only_fields
from .starts import SEED_TABLE, solve_from_starts

logger = logging.getLogger(__name__)

#: Default cap on the time of one solve [s], the partial poses' too: the work
#: (:data:`~.settings.MAX_ATTEMPTS` starts, about 0.1 s when nothing is found, plus the seed table
#: and the MuJoCo model loaded once) decides the answer; a call the cap stops first says
#: ``timeout``. Found answers return as soon as found (tens of microseconds to a few ms).
DEFAULT_TIMEOUT = 2.0

#: The numeric pipeline, in order (see the module): each stage gets the solver's frozen
#: :class:`~.context.NumericContext` and the shared :class:`~.search.Search`.
STAGES: tuple[Stage, ...] = (
    Stage(FREE_JOINT, solve_free_joint),
    Stage(SEED_TABLE, solve_from_starts),
    Stage(RANDOM_RESTART, solve_with_restarts),
    Stage(MINK_QP, polish_best),
)


class NumericIK:
    """Numeric IK of one robot: seed table, damped Newton fast path, mink QP fallback.

    Args:
        robot: The robot.
        settings: The settings (:class:`~.settings.NumericSettings`; None: its defaults).
        **options: Settings by name (``near_seed=True``, ``closed_form=False``, ...), over
            ``settings``: every field of :class:`~.settings.NumericSettings`, with its unit.

    Attributes:
        settings: The settings, frozen.
        context: What the stages read (:class:`~.context.NumericContext`): the settings and the
            model handles. Their fields read as the solver's too (``solver.nearest``,
            ``solver.judge``, ``solver.closed_form``), read-only properties
            (:func:`.solver_fields.read_only_fields`; no ``__getattr__``).
        stages: The pipeline, in order (:class:`~.search.Stage`): each gets the context and the
            shared search, and returns a verified result or hands the search on.
    """

    #: Pipeline name reported in :attr:`IKResult.solver` (the :class:`~kin.ik.Solver` protocol);
    #: no kind answered with every branch in one solve (a search: a 7R's grid only when asked).
    name = PIPELINE
    closed_form_kinds: tuple[type, ...] = ()

    def __init__(
        self, robot: RobotModel, settings: NumericSettings | None = None, **options: Any
    ) -> None:
        self.settings = settings = dataclasses.replace(settings or NumericSettings(), **options)
        self.context = context = build_context(robot, settings)
        self.robot = robot
        #: Number of joints, and the joint limits (arrays).
        self.nq: int = context.nq
        self.lower, self.upper = context.lower, context.upper
        self._shape = (self.nq,)
        #: Which part answers each target kind (:func:`kin.ik.routing.numeric_routes`): a pose
        #: on fewer than six joints, a masked pose, an axis target go to the partial-pose solver.
        self.routes = numeric_routes(
            self.nq, (NumericTarget, PoseTarget, PositionTarget, AxisTarget)
        )
        #: ``route(target)``: the part that answers it (:meth:`kin.ik.routing.Routes.of`).
        self.route = self.routes.of
        self._partial: PartialPoseIK | None = None
        self._table: SeedTable | None = None
        self.stages: tuple[Stage, ...] = STAGES
        if getattr(context.closed_form, "costly", False):  # a general 7R: after the seed table
            self.stages = (STAGES[1], STAGES[0], *STAGES[2:])
        #: Stage 0 from the caller's seed in one compiled call (:func:`.free_joint.compiled_seeded`)
        #: for a PoseTarget or PositionTarget, and the batch's (:func:`kin.ik.solve_batch`, ``kin
        #: ik --stdin``), or None (the stages in Python).
        self._seeded, self.seeded_many = None, None
        if context.compiled and context.idealised is None and self.stages is STAGES:
            self._seeded, self.seeded_many = compiled_stage0(context, PIPELINE)
        # One solve at a time per solver: the stages share the context's data and the caches.
        self._lock = threading.Lock()
        self._table_lock = threading.Lock()
        # The seed table and, for an arm without a free-joint closed form nor the steps' compiled
        # twin, SciPy's LAPACK come with the solver, not inside a solve's cap (without
        # ``prepare``: with the first solve that needs them, the cap counting them).
        if settings.prepare:
            _ = self.table
            if context.closed_form is None and not context.compiled_step:
                load_linalg()

    def batch_route(self) -> FreeJointRoute | None:
        """Stage 0 of a batch of poses (:func:`.solver_fields.free_joint_route`), or None."""
        return free_joint_route(self.context, self.settings, self.seeded_many)

    @property
    def table(self) -> SeedTable:
        """The seed table (built on first use; cached on disk per table, in memory per shipped robot)."""
        if self._table is None:
            with self._table_lock:  # one build, whichever thread asks first
                if self._table is None:
                    self._table = seed_table_of(self.robot, self.settings.table_size)
        return self._table

    @property
    def numeric(self) -> NumericIK:
        """Itself: the numeric solver answers every target kind it takes."""
        return self

    @property
    def partial(self) -> PartialPoseIK:
        """The solver of partial poses (:mod:`kin.ik.partial_pose`), built on first use."""
        if self._partial is None:
            self._partial = PartialPoseIK(self.robot, None, PIPELINE, self.nearest_samples)
        return self._partial

    def nearest_samples(
        self, position: np.ndarray, rotation: np.ndarray | None, end: float
    ) -> np.ndarray:
        """The joint vectors of the :attr:`nearest` seed-table samples nearest a pose, (k, nq).

        Nearest in the table's pose embedding (position [m], rotation weighed). The table is
        built or loaded now if need be, whatever ``end`` (the caller's cap, which it checks).
        """
        del end  # the work, not the time left, decides what is returned
        return self.table.nearest_rows(position, rotation, self.settings.nearest)

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """Target types :meth:`solve` accepts: a position, a pose, an axis, a numeric target."""
        return self.routes.kinds

    def solve(
        self,
        target: Any,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        random_seed: int = 0,
        position_tol: float = POSITION_TOLERANCE,
        rotation_tol: float = ROTATION_TOLERANCE,
        max_attempts: int | None = None,
        all_branches: bool = False,
    ) -> IKResult:
        """Find a joint vector inside the limits that puts the tool on ``target``.

        Args:
            target: Tool target: a position or a full pose (a :class:`NumericTarget` may add a
                posture preference); a masked pose, an axis target, or a pose on an arm of fewer
                than six joints is solved by :class:`~kin.ik.partial_pose.PartialPoseIK`.
            seed: Start joint vector [rad] (or [m] for prismatic joints), moved into the limits
                first (:func:`kin.configuration.seed_inside`). The free-joint closed
                form (when the arm has one) starts from it first: the answer keeps its free
                joint as nearly as the target allows. Damped Newton tries it first, with its whole
                iteration budget, for a redundant target when its tool is within
                ``seed_radius``; else first when its tool pose is at least as near to the target
                as the nearest seed-table sample's. A posture preference is always tried first.
            timeout: Cap on the time [s] (None: :data:`DEFAULT_TIMEOUT`), cold loads included
                (the seed table, the arm's reach, the MuJoCo model of the QP runs, SciPy's
                LAPACK: each loaded when first needed, whatever the time left). Checked before
                each stage, start and load, never inside one: a call that reaches it returns
                ``timeout`` with the best configuration found (a call overruns it by at most one
                start or load); else the answer is the one the work gives on any machine.
            random_seed: Seed of the random restarts (results are reproducible).
            position_tol: Success tolerance on the position [m].
            rotation_tol: Success tolerance on the rotation [rad].
            max_attempts: The work: damped Newton starts in all, after which a search without
                an answer says ``not_found`` (None: the solver's ``max_attempts``,
                :data:`~.settings.MAX_ATTEMPTS` by default).
            all_branches: On an arm with a free-joint closed form (7R) and a full pose, every
                verified branch at a grid of free-joint values, the seed's and the answer's,
                nearest the seed first (:mod:`.all_branches`); else the usual answer.

        Returns:
            ``IKResult(solver="numeric")`` with ``method`` the stage that answered; on failure
            ``rejected`` holds the best configuration. A target farther from the base than
            the links laid end to end (:attr:`reach`) is ``out_of_reach`` at once.

        Raises:
            TargetError: A target of a kind it does not take (a pitch target: its routes,
                :func:`kin.ik.routing.numeric_routes`), or a seed of the wrong size.
        """
        if all_branches:
            from .all_branches import solve_all_branches

            return solve_all_branches(
                self,
                target,
                seed,
                timeout=timeout,
                random_seed=random_seed,
                position_tol=position_tol,
                rotation_tol=rotation_tol,
                max_attempts=max_attempts,
            )
        start = time.perf_counter()
        seed = seed_inside(self.robot, seed)
        route = self.route(target)
        if route is not NUMERIC:
            if route is REFUSED:
                raise kind_error(self.robot.name, self.routes.kinds, target)
            return self.partial.solve(target, seed, timeout=timeout)
        cls = target.__class__
        # Checked when built, read-only since: the numeric stages read a pose or a position as
        # it is (a NumericTarget's attributes); another kind is made a NumericTarget.
        plain = cls is PoseTarget or cls is PositionTarget
        if not (target.finite if plain else getattr(target, "finite", True)):  # writeable again
            return IKResult(False, PIPELINE, "invalid_target", f"target is not finite: {target}")
        if not plain:
            target = NumericTarget.from_target(target)
        return self._solve(
            target, seed, start, timeout, random_seed, position_tol, rotation_tol, max_attempts
        )

    def _solve(
        self,
        target: NumericTarget,
        seed: npt.ArrayLike | None,
        start: float,
        timeout: float | None,
        random_seed: int,
        position_tol: float,
        rotation_tol: float,
        max_attempts: int | None,
    ) -> IKResult:
        """:meth:`solve` of a checked target (``position``, ``rotation``, ``posture``)."""
        posture = target.posture
        seeded = self._seeded
        scanned = False
        if (
            seeded is not None
            and seed is not None
            and posture is None
            and not self.settings.near_seed
            and (timeout is None or timeout >= 0.0)
        ):  # stage 0 from the seed, compiled: the usual answer, without the stages' set-up
            answer = seeded(target, seed, position_tol, rotation_tol, start, np.empty(7))
            if answer.__class__ is IKResult:
                return answer  # type: ignore[no-any-return]
            scanned = answer is False  # tried from the seed: stage 0 goes on from the samples
        if posture is not None:
            target = self.context.posture_inside(target, posture)
        budget = DEFAULT_TIMEOUT if timeout is None else timeout
        if not budget >= 0.0:
            raise TargetError(f"timeout must be a number of seconds >= 0, got {timeout!r}")
        with self._lock:
            context = self.context
            distance = context.distance_from_base(target.position)
            if distance > context.reach:  # surely unreachable: no search
                return _beyond_reach(context.arm_reach.maximum, distance, start)
            seed_vector = None if seed is None else self.seed_vector(seed)  # checked once
            table = self.table  # before the search, whatever the cap: work decides
            search = Search(
                context,
                target,
                position_tol,
                rotation_tol,
                budget,
                start,
                table,
                seed_vector,
                random_seed,
                self.settings.max_attempts if max_attempts is None else max_attempts,
            )
            search.seed_scanned = scanned
            return run_stages(self.stages, context, search)

    def seed_vector(self, seed_q: npt.ArrayLike) -> np.ndarray:
        """The caller's seed as a finite joint vector (:meth:`.NumericContext.seed_vector`)."""
        return self.context.seed_vector(seed_q)


read_only_fields(NumericIK)


def _beyond_reach(reach: float, distance: float, start: float) -> IKResult:
    """``out_of_reach`` for a target ``distance`` [m] from the base, beyond the arm's ``reach`` [m].

    No search: the target is farther than the links laid end to end (``start``: the call's
    ``time.perf_counter()``).
    """
    return IKResult(
        False,
        PIPELINE,
        "out_of_reach",
        f"target is {distance - reach:.4g} m beyond the arm's reach ({reach:.4g} m from its "
        "base); no search",
        distance_to_workspace=distance - reach,
        time=time.perf_counter() - start,
    )


@functools.lru_cache(maxsize=8)
def numeric_ik_for(robot_name: str) -> NumericIK:
    """The (cached) numeric IK of a shipped robot."""
    return NumericIK(load_robot(robot_name))


def solve_numeric(
    robot: RobotModel | str,
    position: npt.ArrayLike,
    rotation: npt.ArrayLike | None = None,
    posture: npt.ArrayLike | None = None,
    seed_q: npt.ArrayLike | None = None,
    timeout: float = DEFAULT_TIMEOUT,
) -> IKResult:
    """Numeric IK in one call: position [m], optional rotation ``R_world_tool`` and posture.

    Args:
        robot: A loaded robot or a shipped robot's name.
        position: Tool position in the world frame [m].
        rotation: Tool rotation (3 x 3), or None for a position-only target.
        posture: Preferred joint vector [rad] for the redundancy, or None.
        seed_q: Start joint vector [rad], or None.
        timeout: Time budget [s].
    """
    solver = numeric_ik_for(robot) if isinstance(robot, str) else NumericIK(robot)
    target = NumericTarget.from_arrays(position, rotation, posture)
    return solver.solve(target, seed=seed_q, timeout=timeout)
