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
   made ``max_attempts`` starts (:data:`~.search.MAX_ATTEMPTS`); then a last QP run from the best
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

import functools
import logging
import math
import threading
import time

import numpy as np
import numpy.typing as npt

from kin import KinError, RobotModel, as_joint_vector, load_robot
from kin.configuration import seed_inside

from ..analytic.idealised import Idealised, idealise
from ..exceptions import TargetError
from ..judge import POSITION_TOLERANCE, ROTATION_TOLERANCE, ToolJudge
from ..partial_pose import PartialPoseIK
from ..reach import Reach, arm_reach, reach_bound
from ..result import IKResult
from ..target import AxisTarget, PoseTarget, PositionTarget, is_partial, kind_error
from .damped_newton import COMPILED as COMPILED_STEP
from .damped_newton import load_linalg
from .differential_ik import DifferentialIK
from .free_joint import METHOD as FREE_JOINT
from .free_joint import (
    FreeJointClosedForm,
    SeededMany,
    compiled_seeded,
    compiled_seeded_many,
    free_joint_closed_form,
    solve_free_joint,
)
from .numeric_target import NumericTarget
from .restarts import MINK_QP, RANDOM_RESTART, polish_best, solve_with_restarts
from .search import MAX_ATTEMPTS, PIPELINE, Search, Stage, run_stages
from .seed_table import SeedTable, build_seed_table, seed_table_for
from .starts import SEED_TABLE, solve_from_starts

logger = logging.getLogger(__name__)

#: NumPy's (interned) float64 dtype: an identity check is the fast path's cheapest test.
_FLOAT64 = np.dtype(np.float64)

#: Default cap on the time of one solve [s], the partial poses' too: the work
#: (:data:`~.search.MAX_ATTEMPTS` starts, about 0.1 s when nothing is found, plus the seed table
#: and the MuJoCo model loaded once) decides the answer; a call the cap stops first says
#: ``timeout``. Found answers return as soon as found (tens of microseconds to a few ms).
DEFAULT_TIMEOUT = 2.0

#: Default free-joint scan steps of the closed form [rad], coarse to fine (with or without the
#: compiled twins: the same answers either way).
DEFAULT_CLOSED_FORM_STEPS = (0.05, 0.01)

#: The numeric pipeline, in order (see the module): each stage gets the solver as its context
#: (:class:`~.context.NumericContext`) and the shared :class:`~.search.Search`.
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
        table_size: Number of sampled poses in the seed table.
        qp_solver: QP solver of the mink fallback (``"daqp"`` or ``"osqp"``).
        nearest: Number of seed-table starts tried before the fallback.
        newton_iterations: Damped Newton steps per start.
        qp_iterations: mink QP steps per fallback run.
        patience: A nearest start is abandoned after this many damped Newton steps in a row
            that do not halve its error (None: always ``newton_iterations`` steps).
        random_starts: Random starts tried after the nearest ones and before the first mink
            QP run (a QP run costs as much as dozens of damped Newton starts).
        max_attempts: The work of one solve: damped Newton starts in all (seeded draws), after
            which a search without an answer says ``not_found``; a solve's own ``max_attempts``
            overrides it.
        random_between: Random starts between two mink QP runs (a QP run of ``qp_iterations``
            steps costs as much as about 20 random starts and finds as many answers near the
            limits).
        random_patience: ``patience`` of the random starts (a mink QP run is always followed
            by ``newton_iterations`` damped Newton steps).
        seed_radius: For a redundant target (more joints than it constrains), a caller's seed
            whose tool is within this of the target [m] (rotations weighed as in the seed
            table's pose embedding) is the first start of damped Newton, with the whole
            ``newton_iterations`` budget: the answer is the solution near the seed. A farther
            seed goes first only when its tool is at least as near as the nearest sample's.
        seed_reach: For a redundant target, a caller's seed whose tool is farther than
            ``seed_radius`` but within this [m] (and turned at most ``seed_turn``) is the first
            start of damped Newton too, on a ``seed_leash``; so is it in the closed-form stage
            when the closed form's answer from it is farther than ``seed_near`` from it (or there
            is none).
        seed_turn: The largest rotation angle between the seed's tool and a full-pose target for
            ``seed_reach`` [rad] (a seed turned farther has no solution near it).
        seed_leash: A damped Newton run from a seed beyond ``seed_radius`` gives up as soon as it
            has moved farther than this from the seed (largest joint change [rad]), or stalls
            (``patience``): the answer near the seed is not where it goes, and samples' starts
            are cheaper.
        seed_near: The closed form's answer from a seed near the target (within ``seed_reach``)
            is taken when no joint is farther than this from the seed's [rad]; else damped Newton
            from the seed runs first, and the nearer of the two answers is returned.
        near_seed: Whether the closed-form stage checks that its answer from the caller's seed
            is near the seed when the seed's tool is near the target (``seed_reach``,
            ``seed_near``). It costs one forward kinematics of the seed per seeded solve (about
            1.3 us, 10-20 % of a closed-form answer's time), hence off by default: without it,
            the closed form keeps the seed's free joint and its branch may be far.
        closed_form: Try the free-joint closed form first when the arm has one
            (:func:`~.free_joint.free_joint_closed_form`; False: damped Newton and mink only).
        closed_form_starts: Seed-table samples tried by the closed form before damped Newton.
        closed_form_steps: Free-joint scan steps of the first closed-form starts [rad], coarse
            to fine: when a start's free joint gives no branch inside the limits, it is scanned
            outward from there, on the coarse grid first.
        compiled: Run the free-joint closed form's compiled twin (``_closed7`` for humanoid7's
            structure, ``_shoulder7`` for the spherical shoulder) when it is built (False: the
            Python module). Both return the same joint vectors; the twin is faster. Damped
            Newton's steps take their compiled twin too (``_damped_step``; False: NumPy's, the
            same joint vectors to rounding).
        prepare: Build (or load) the seed table now (False: on the first solve that needs it,
            before its search, whatever its timeout: see :meth:`solve`).
    """

    #: Pipeline name reported in :attr:`IKResult.solver` (the :class:`~kin.ik.Solver` protocol).
    name = PIPELINE

    def __init__(
        self,
        robot: RobotModel,
        table_size: int = 20000,
        qp_solver: str = "daqp",
        nearest: int = 8,
        newton_iterations: int = 20,
        qp_iterations: int = 25,
        patience: int | None = 3,
        random_starts: int = 10,
        max_attempts: int = MAX_ATTEMPTS,
        random_between: int = 19,
        random_patience: int | None = 3,
        seed_radius: float = 0.1,
        seed_reach: float = 0.45,
        seed_turn: float = 1.2,
        seed_leash: float = 0.75,
        seed_near: float = 0.4,
        near_seed: bool = False,
        closed_form: bool = True,
        closed_form_starts: int = 32,
        closed_form_steps: tuple[float, ...] = DEFAULT_CLOSED_FORM_STEPS,
        compiled: bool = True,
        prepare: bool = True,
    ):
        self.robot = robot
        self.model = robot.model
        self.data = robot.model.createData()
        self.frame_id = robot.model.getFrameId(robot.tool_frame)
        #: Number of joints.
        self.nq: int = robot.model.nq
        #: The judge of every answer (Pinocchio's FK of the tool, the limits), in :attr:`data`.
        self.judge = ToolJudge(robot, self.data)
        self.table_size = table_size
        self.qp_solver = qp_solver
        self.nearest = nearest
        self.newton_iterations = newton_iterations
        self.qp_iterations = qp_iterations
        self.patience = patience
        self.random_starts = random_starts
        self.max_attempts = max_attempts
        self.random_between = random_between
        self.random_patience = random_patience
        self.seed_radius = seed_radius
        self.seed_reach = seed_reach
        self.seed_turn = seed_turn
        self.seed_leash = seed_leash
        self.seed_near = seed_near
        self.near_seed = near_seed
        self.lower = robot.model.lowerPositionLimit.copy()
        self.upper = robot.model.upperPositionLimit.copy()
        #: Joints without limits (``continuous`` rows): damped Newton moves them freely (a model
        #: with limits of +-3 pi for them, :attr:`search_model`) and answers are wrapped back
        #: into [-pi, pi], so that a solution across pi is found, not clamped away.
        self.continuous = tuple(i for i, row in enumerate(robot.table.rows) if row.continuous)
        self.search_model = robot.model
        if self.continuous:
            self.search_model = robot.model.copy()
            for i in self.continuous:
                self.search_model.lowerPositionLimit[i] = -3.0 * math.pi
                self.search_model.upperPositionLimit[i] = 3.0 * math.pi
        #: The limits as lists of floats (the stages' checks run on Python floats).
        self.lows, self.highs = self.lower.tolist(), self.upper.tolist()
        self._lows, self._highs = self.lows, self.highs
        #: The pipeline, in order (:class:`~.context.Stage`): each gets the shared search and
        #: returns a verified result, or hands the search on.
        self.stages: tuple[Stage, ...] = STAGES
        #: Upper bound of the tool's distance from the base origin [m] (triangle inequality): a
        #: target beyond it is answered ``out_of_reach`` before any search.
        self.reach = reach_bound(robot)
        self._base_origin = np.asarray(robot.table.T_world_base, dtype=float)[:3, 3].tolist()
        self._shape = (robot.model.nq,)
        # A pose on an arm of fewer than six joints, a masked pose and an axis target go to
        # :mod:`kin.ik.partial_pose` (weighted least squares on the constrained components).
        self._kinds: tuple[type, ...] = (NumericTarget, PoseTarget, PositionTarget, AxisTarget)
        self._partial: PartialPoseIK | None = None
        self._table: SeedTable | None = None
        self._differential: DifferentialIK | None = None
        #: The free-joint closed form of this arm, or None (no structure fits, or not asked).
        self.closed_form: FreeJointClosedForm | None = None
        #: The idealised table the free-joint closed form fits when the true one misses it by
        #: rounding (its answers are polished on the true chain), else None.
        self.idealised: Idealised | None = None
        if closed_form:
            # The special forms, on the true table, then on the idealised one (a rounded URDF);
            # only then the general 7R form on the true table (slower, no compiled twin).
            lower, upper = self.lower, self.upper
            self.closed_form = free_joint_closed_form(robot.table, lower, upper, general=False)
            ideal = idealise(robot.table) if self.closed_form is None else None
            if ideal is not None:
                self.closed_form = free_joint_closed_form(ideal.table, lower, upper, general=False)
                self.idealised = ideal if self.closed_form is not None else None
            if self.closed_form is None:
                self.closed_form = free_joint_closed_form(robot.table, lower, upper)
        if getattr(self.closed_form, "costly", False):  # a general 7R: after the seed table
            self.stages = (STAGES[1], STAGES[0], *STAGES[2:])
        self.closed_form_starts = closed_form_starts
        self.closed_form_steps = tuple(closed_form_steps)
        #: Whether the closed form runs its compiled twin (asked for and built).
        self.compiled = compiled and self.closed_form is not None and self.closed_form.compiled_twin
        #: Whether damped Newton's steps run their compiled twin (asked for and built).
        self.compiled_step = compiled and COMPILED_STEP
        #: Stage 0 from the caller's seed in one compiled call (:func:`.free_joint.compiled_seeded`)
        #: for a PoseTarget or PositionTarget, or None (the stages in Python).
        self._seeded = None
        if self.compiled and self.idealised is None and self.stages is STAGES:
            self._seeded = compiled_seeded(
                self.closed_form,
                robot.table,
                self._base_origin,
                self.reach,
                self.closed_form_steps,
                PIPELINE,
            )
        #: The batch's closed-form stage in compiled code (:func:`.free_joint.compiled_seeded_many`:
        #: :func:`kin.ik.solve_batch`, ``kin ik --stdin``), or None where ``_seeded`` is.
        self.seeded_many: SeededMany | None = None
        if self._seeded is not None:
            self.seeded_many = compiled_seeded_many(
                self.closed_form,
                robot.table,
                self.lower,
                self.upper,
                self._base_origin,
                self.reach,
            )
        # One solve at a time per solver: the stages share :attr:`data` and the caches (threads
        # that share a solver get the answers one thread would).
        self._lock = threading.Lock()
        self._table_lock = threading.Lock()
        # The seed table (tens of milliseconds to build, a few to load) and, for an arm without
        # a free-joint closed form (whose targets all go to damped Newton), SciPy's LAPACK for
        # the steps (imported once per process) come with the solver, not inside a solve's
        # cap. Without ``prepare`` the first solve that needs them loads them (the cap counts
        # it); with the steps' compiled twin (COMPILED_STEP) SciPy is not needed at all.
        if prepare:
            _ = self.table
            if self.closed_form is None and not self.compiled_step:
                load_linalg()

    @property
    def arm_reach(self) -> Reach:
        """The tool's largest distance from the base (:func:`kin.ik.reach.arm_reach`)."""
        return arm_reach(self.robot)

    @property
    def table(self) -> SeedTable:
        """The seed table (built on first use; cached on disk per table, in memory per shipped robot)."""
        if self._table is None:
            with self._table_lock:  # one build, whichever thread asks first
                if self._table is None:
                    if _is_shipped(self.robot):
                        self._table = seed_table_for(self.robot.name, self.table_size)
                    else:  # a robot loaded from a table file: its own table
                        self._table = build_seed_table(self.robot, self.table_size)
        return self._table

    @property
    def differential_loaded(self) -> bool:
        """Whether the mink differential IK is loaded (a QP run costs no model load)."""
        return self._differential is not None

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

        Nearest in the table's pose embedding (position [m], rotation weighed); none when the
        target's cell is empty. The table is built or loaded now if need be, whatever ``end``
        (the caller's cap, a ``time.perf_counter()`` value, which it checks itself after): the
        samples depend on the target alone.
        """
        del end  # the work, not the time left, decides what is returned
        table = self.table
        found = table.ranked(position, rotation)
        if found is None or not found[0].size:
            return np.empty((0, self.nq))
        candidates, distances = found
        order = np.argsort(distances, kind="stable")[: self.nearest]
        return table.q[candidates[order]]

    @property
    def differential(self) -> DifferentialIK:
        """The mink differential IK (MuJoCo model loaded on first use)."""
        if self._differential is None:
            self._differential = DifferentialIK(self.robot, solver=self.qp_solver)
        return self._differential

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """Target types :meth:`solve` accepts: a position; a full pose with six joints or more."""
        return self._kinds

    def solve(
        self,
        target: object,
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
                :data:`~.search.MAX_ATTEMPTS` by default).
            all_branches: On an arm with a free-joint closed form (7R) and a full pose, every
                verified branch at a grid of free-joint values, the seed's and the answer's,
                nearest the seed first (:mod:`.all_branches`); else the usual answer.

        Returns:
            ``IKResult(solver="numeric")`` with ``method`` the stage that answered; on failure
            ``rejected`` holds the best configuration. A target farther from the base than
            the links laid end to end (:attr:`reach`) is ``out_of_reach`` at once.

        Raises:
            TargetError: A target of a kind the arm cannot take (a pitch target; a full pose on
                an arm of fewer than six joints), a malformed one, or a seed of the wrong size.
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
        cls = target.__class__
        if cls is PoseTarget or cls is PositionTarget:
            # Checked when built, read-only since: the numeric stages read it as it is.
            if cls is PoseTarget and (target.mask is not None or self.nq < 6):  # type: ignore[attr-defined]
                return self.partial.solve(target, seed, timeout=timeout)  # type: ignore[arg-type]
            if not target.finite:  # type: ignore[attr-defined]  # an array made writeable again
                return IKResult(
                    False, PIPELINE, "invalid_target", f"target is not finite: {target}"
                )
            return self._solve(
                target,  # type: ignore[arg-type]  # read as a NumericTarget (same attributes)
                seed,
                start,
                timeout,
                random_seed,
                position_tol,
                rotation_tol,
                max_attempts,
            )
        if is_partial(target, self.nq):
            return self.partial.solve(target, seed, timeout=timeout)  # type: ignore[arg-type]
        if not isinstance(target, self._kinds):
            raise kind_error(self.robot.name, self._kinds, target)
        if not getattr(target, "finite", True):  # a target's arrays changed after it was built
            return IKResult(False, PIPELINE, "invalid_target", f"target is not finite: {target}")
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
            and not self.near_seed
            and (timeout is None or timeout >= 0.0)
        ):  # stage 0 from the seed, compiled: the usual answer, without the stages' set-up
            answer = seeded(target, seed, position_tol, rotation_tol, start, np.empty(7))
            if answer.__class__ is IKResult:
                return answer  # type: ignore[no-any-return]
            scanned = answer is False  # tried from the seed: stage 0 goes on from the samples
        if posture is not None and posture.shape != self._shape:
            raise TargetError(
                f"posture of '{self.robot.name}' must have {self.nq} values, got {posture.size}"
            )
        if posture is not None and not (
            np.all(posture >= self.lower) and np.all(posture <= self.upper)
        ):  # a preference outside the limits pulls toward the nearest joint vector inside
            clipped = np.minimum(np.maximum(posture, self.lower), self.upper)
            target = NumericTarget(target.position, target.rotation, clipped)
        budget = DEFAULT_TIMEOUT if timeout is None else timeout
        if not budget >= 0.0:
            raise TargetError(f"timeout must be a number of seconds >= 0, got {timeout!r}")
        with self._lock:
            distance = self.distance_from_base(target.position)
            if distance > self.reach:  # surely unreachable: no search
                return self._beyond_reach(target, distance, start)
            seed_vector = None if seed is None else self.seed_vector(seed)  # checked once
            table = self.table  # before the search, whatever the cap: work decides
            search = Search(
                self,
                target,
                position_tol,
                rotation_tol,
                budget,
                start,
                table,
                seed_vector,
                random_seed,
                self.max_attempts if max_attempts is None else max_attempts,
            )
            search.seed_scanned = scanned
            return run_stages(self.stages, self, search)

    def _beyond_reach(self, target: NumericTarget, distance: float, start: float) -> IKResult:
        """``out_of_reach`` for a target farther than :attr:`reach` from the base (no search)."""
        reach = self.arm_reach.maximum
        return IKResult(
            False,
            PIPELINE,
            "out_of_reach",
            f"target is {distance - reach:.4g} m beyond the arm's reach ({reach:.4g} m from its "
            "base); no search",
            distance_to_workspace=distance - reach,
            time=time.perf_counter() - start,
        )

    def distance_from_base(self, position: np.ndarray) -> float:
        """Distance of a world point from the base origin [m]."""
        x, y, z = position.tolist() if position.__class__ is np.ndarray else position
        bx, by, bz = self._base_origin
        return math.hypot(x - bx, y - by, z - bz)  # no overflow for 1e308

    def seed_vector(self, seed_q: npt.ArrayLike) -> np.ndarray:
        """The caller's seed as a finite joint vector (the solver never writes into it)."""
        if (
            type(seed_q) is np.ndarray
            and seed_q.shape == self._shape
            and seed_q.dtype is _FLOAT64
            and math.isfinite(sum(seed_q.tolist()))
        ):
            return seed_q  # already valid: no copy, no validation
        try:
            return as_joint_vector(self.robot, seed_q)
        except KinError as err:
            raise TargetError(f"seed of '{self.robot.name}': {err}") from err


def _is_shipped(robot: RobotModel) -> bool:
    """Whether ``robot`` is the registry's (cached) model of its name."""
    try:
        return load_robot(robot.name) is robot
    except Exception:  # noqa: BLE001 - any name the registry does not know
        return False


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
