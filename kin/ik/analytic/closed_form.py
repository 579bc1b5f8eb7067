"""Closed-form IK solver of a small arm: every branch, limits, Pinocchio verification, ordering.

:class:`ClosedFormSolver` asks the registered structures (:mod:`.registry`) which one fits the
arm's DH table, computes every branch with it (:mod:`.closed_form_structure`: the solver knows
no structure by name), then moves each branch into the joint limits and has the judge measure
it (:mod:`.branch_verification`: valid, rejected or dropped; valid ones ordered by distance to
the seed). A structure with a compiled twin that verifies (the 6R closed forms,
:mod:`.six_r.six_r_twin`) does that for a pose target in one C call: the same wrapping, and the
table's plain DH product in C as the judge instead of Pinocchio (``tests/native/test_six_r_twins.py``
checks that both paths return the same solutions and errors). A rounded table is solved on its
idealised geometry and every branch polished on the true chain (:mod:`.idealised`), but those far
outside the limits, judged as they are (:mod:`.branch_verification`); when none is valid,
:mod:`.idealised_fallback` looks further before it says "no" (``out_of_reach`` only when proved).
A target kind the closed form does not take goes to the numeric or the partial-pose solver.
"""

from __future__ import annotations

import logging
import threading
import time
from typing import Any

import numpy as np
import numpy.typing as npt

from kin import RobotModel
from kin.configuration import default_seed, seed_inside

from ..judge import ToolJudge
from ..result import IKResult
from ..routing import BRANCHES, CLOSED, NUMERIC, REFUSED, TWIN, closed_form_routes
from ..targets.target import PitchTarget, PoseTarget, Target, kind_error
from .branch_verification import BranchVerifier, log_miss
from .closed_form_branches import ClosedFormArm, recognise_arm
from .closed_form_routes import ClosedFormRoutes, OnFirstUse
from .idealised import Idealised
from .idealised_fallback import IdealisedPolish, UnprovedCall

logger = logging.getLogger(__name__)


class ClosedFormSolver:
    """Every closed-form IK branch of one small arm, verified with Pinocchio.

    A router over objects it holds: the arm as its structure sees it
    (:class:`~.closed_form_branches.ClosedFormArm`), the branch verifier
    (:class:`~.branch_verification.BranchVerifier`), a rounded arm's polish
    (:class:`~.idealised_fallback.IdealisedPolish`, None for an exact arm) and the routes of the
    target kinds its closed form does not take (``handlers``:
    :class:`~.closed_form_routes.ClosedFormRoutes`); which of them answers a target is its
    ``routes`` (:func:`kin.ik.routing.closed_form_routes`).

    Args:
        robot: The loaded robot (its table must fit a registered structure, :mod:`.registry`).
        tolerance_position: Largest position error of a returned solution [m].
        tolerance_rotation: Largest rotation error of a returned solution [rad].
        compiled: Solve and verify pose targets in the structure's compiled twin when it has one
            and it is built (the 6R closed forms, :mod:`.six_r_twin`: the table's DH product in
            C measures the branches instead of Pinocchio); False: always the Python steps.

    Raises:
        StructureError: The table does not fit a closed-form solver.
    """

    def __init__(
        self,
        robot: RobotModel,
        tolerance_position: float = 1e-9,
        tolerance_rotation: float = 1e-9,
        *,
        compiled: bool = True,
    ):
        self.robot = robot
        self.arm: ClosedFormArm = recognise_arm(robot)
        arm = self.arm
        self.structure = arm.structure
        #: The idealised table the structure fits when the true one misses it by rounding
        #: (:mod:`.idealised`: answers polished on the true chain), else None.
        self.idealised: Idealised | None = arm.idealised
        compiled = compiled and arm.idealised is None  # a twin measures the table it solves
        self.name = f"closed_form:{arm.structure.name}"
        self.tolerance_position = tolerance_position
        self.tolerance_rotation = tolerance_rotation
        self.verifier = BranchVerifier(
            arm, self.name, ToolJudge(robot), tolerance_position, tolerance_rotation
        )
        numeric = OnFirstUse(self._numeric_solver)
        self.polish = (
            None if arm.idealised is None else IdealisedPolish(arm, self.verifier, numeric)
        )
        # One solve at a time: the judge's Pinocchio data is shared (threads get the answers
        # one thread would).
        self._lock = threading.Lock()
        self.handlers = ClosedFormRoutes(
            arm, self.verifier, self.polish, numeric, self.name, self._lock
        )
        #: Per joint, revolute (compared modulo a turn by IKResult.without_repeats); None: all.
        revolute = tuple(row.joint_type == "revolute" for row in robot.table.rows)
        self._revolute = None if all(revolute) else revolute
        #: The seed of a call given none (:func:`kin.configuration.default_seed`); None when it
        #: is zero (the readers' own default).
        start_q = default_seed(robot)
        self._default_seed = None if not start_q.any() else start_q
        # A structure with a compiled twin that also verifies (the 6R closed forms): pose targets
        # are solved, moved into the limits and measured in one call (:mod:`.six_r_twin`).
        twin_verifier = getattr(arm.structure, "verifier", None)
        self._twin = (
            None
            if twin_verifier is None or not compiled
            else twin_verifier(
                arm.table,
                arm.lower,
                arm.upper,
                tolerance_position,
                tolerance_rotation,
            )
        )
        #: The twin's whole answer of a pose (:meth:`.six_r_twin.TwinVerifier.solutions`), or
        #: None: no twin.
        self._solutions: Any = (
            None
            if self._twin is None
            else self._twin.solutions(arm.directions, arm.structure.branch_labels, self.name)
        )
        #: Which part answers each target kind (:func:`kin.ik.routing.closed_form_routes`).
        self.routes = closed_form_routes(
            self.closed_form_kinds,
            len(arm.lower),
            projects=bool(getattr(arm.structure, "projects", False)),
            twin=self._solutions is not None,
        )
        self._by_class = self.routes.by_class
        #: ``route(target)``: the part that answers it (:meth:`kin.ik.routing.Routes.of`).
        self.route = self.routes.of

    def _numeric_solver(self) -> Any:
        """The numeric solver of the same robot, for the target kinds the closed form lacks."""
        from ..numeric.solver import NumericIK

        # Built inside a solve: its seed table within that call's budget, or in the
        # background for the next calls (NumericIK.solve).
        return NumericIK(self.robot, closed_form=False, prepare=False)

    @property
    def numeric(self) -> Any:
        """The numeric solver of the same robot (built on first use)."""
        return self.handlers.numeric()

    @property
    def partial(self) -> Any:
        """The solver of partial poses (:mod:`kin.ik.partial_pose`), built on first use.

        This closed form's branches are its candidates, then weighted least squares.
        """
        return self.handlers.partial()

    def pose_candidates(
        self, position: np.ndarray, rotations: np.ndarray, seed: npt.ArrayLike
    ) -> list[tuple[np.ndarray, str]]:
        """The closed form's branches of full poses (:meth:`.ClosedFormRoutes.pose_candidates`)."""
        return self.handlers.pose_candidates(position, rotations, seed)

    @property
    def closed_form_kinds(self) -> tuple[type, ...]:
        """The target classes the closed form itself solves (the structure's)."""
        return tuple(self.structure.target_kinds)

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """The target classes this solver accepts (:func:`kin.ik.routing.closed_form_routes`).

        The closed form's, a position and a whole pose (the numeric or the partial-pose solver
        answers those the closed form does not take) and an axis target (the partial-pose solver).
        """
        return self.routes.kinds

    def batch_route(self) -> None:
        """None: a batch takes the vectorized closed form (:func:`kin.ik.solver_table.vectorized_solver`)."""
        return None

    def solve(
        self,
        target: Target,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        all_branches: bool = False,
    ) -> IKResult:
        """Every branch reaching ``target``, valid ones ordered by distance to ``seed``.

        Args:
            target: A :class:`PositionTarget` (planar 2R, offset 3R), :class:`PoseTarget` or
                :class:`PitchTarget` (five-joint arms), in the world frame.
            seed: Current joint vector [rad], moved into the limits first
                (:func:`kin.configuration.seed_inside`; None: zero, or the nearest vector to it
                inside the limits): the order of the solutions and the ``2 pi`` copy of each
                angle; also the value of a free joint at a singularity.

            timeout: Time budget [s] of the numeric solver, which answers the target kinds the
                closed form does not take (a position on a five-joint arm); the closed form
                itself ignores it.
            all_branches: Ignored: every branch is in the answer anyway (the interface's,
                :class:`kin.ik.solver.IKSolver`).

        Returns:
            The result; never raises for unreachable, singular or non-finite targets.

        Raises:
            TargetError: The target kind does not fit the arm, or the seed has the wrong size.
        """
        start = time.perf_counter()
        seed = self._default_seed if seed is None else seed_inside(self.robot, seed)
        route = self._by_class[target.__class__]
        if route is TWIN and target.mask is None:  # type: ignore[union-attr]
            # One C call (no lock: the twin shares no state between calls), which makes the
            # result when a branch is valid, none is off target and none repeats another.
            answer = self._solutions(target, seed, start)
            if answer.__class__ is IKResult:
                return answer  # type: ignore[no-any-return]
            twin = twin_answer(self.verifier, self._solutions, answer, target, seed, start)  # type: ignore[arg-type]
            return twin.without_repeats(self._revolute)
        route = self.route(target)
        if route is CLOSED:
            with self._lock:
                closed = self._solve_closed(target, seed, start, timeout)
            return closed.without_repeats(self._revolute)
        if route is BRANCHES:
            with self._lock:
                done = self.handlers.pose_from_branches(target, seed, start)  # type: ignore[arg-type]
            if done is not None:
                return done
        if route is NUMERIC:
            return self.handlers.solve_numeric(target, seed, timeout)
        if route is REFUSED:
            raise kind_error(self.robot.name, self.target_kinds, target)
        return self.partial.solve(target, seed, timeout=timeout)  # type: ignore[arg-type]

    def _solve_closed(
        self, target: Target, seed: npt.ArrayLike | None, start: float, timeout: float | None
    ) -> IKResult:
        """:meth:`solve` of a target the closed form takes (under the solver's lock).

        A rounded arm's target none of whose polished branches is valid is answered by
        :meth:`.IdealisedPolish.unproved` (``timeout``: its numeric
        search's cap [s]).
        """
        arm, verifier, polish = self.arm, self.verifier, self.polish
        arm_seed = seed
        if arm.directions is not None and seed is not None:
            seed = arm.forward_seed(seed)
        seed_list = arm.seed_list(seed)
        if not target.finite:
            return verifier.failure(
                "invalid_target", "the target has a NaN or infinite value", start
            )
        p = target.position.tolist()
        r = target.rotation.tolist() if isinstance(target, PoseTarget) else None
        branches = arm.branches(target, seed_list)
        rounded = polish is not None and not isinstance(target, PitchTarget)
        if branches.status == "out_of_reach" and not rounded:
            return verifier.failure("out_of_reach", branches.message, start, branches.gap, target)
        if rounded:
            assert polish is not None
            found = bool(branches.thetas)  # before the polish takes those far outside away
            valid, rejected = polish.verify_polished(target, branches, seed_list, p, r)
            if not valid:
                call = UnprovedCall(seed_list, arm_seed, start, timeout)
                return polish.unproved(target, branches, found, rejected, call)
            method = "closed_form_polished"
        else:
            valid, rejected = verifier.verify(target, branches, seed_list, p, r)
            method = "closed_form"
        return verifier.result(valid, rejected, branches.status, branches.message, start, method)


def twin_answer(
    verifier: BranchVerifier,
    solutions: Any,
    answer: Any,
    target: PoseTarget,
    seed: npt.ArrayLike | None,
    start: float,
) -> IKResult:
    """The result of a pose from the compiled twin's answer when it is not the result itself.

    ``answer`` is what ``solutions``, the twin's :meth:`.six_r_twin.TwinVerifier.solutions`, returned: the branches
    (moved into the limits as :func:`~kin.ik.limit_rule.wrap_into` does, measured by the
    table's DH product in C instead of Pinocchio; the tests compare the two paths) when
    some are off target or none
    is valid, else a code: no branch, a target that is not finite, a seed to check here.
    """
    if answer.__class__ is int and answer == -2:  # checked here: a TargetError names it
        checked = np.array(verifier.arm.seed_list(seed), dtype=float)
        answer = solutions(target, checked, start)
        if answer.__class__ is IKResult:
            return answer  # type: ignore[no-any-return]
    if answer.__class__ is tuple:
        valid, rejected, off = answer
        for label, position_error, angle in off:
            log_miss(verifier.arm.robot.name, label, position_error, angle)
        if valid:
            return IKResult(
                True,
                verifier.name,
                "ok",
                f"{len(valid)} valid solution(s)",
                valid,
                rejected,
                None,
                0,
                time.perf_counter() - start,
                "closed_form",
            )
        return verifier.result([], list(rejected), "ok", "", start)
    if answer < 0:
        return verifier.failure("invalid_target", "the target has a NaN or infinite value", start)
    return verifier.failure(
        "out_of_reach",
        f"no {verifier.arm.structure.name} branch reaches the target",
        start,
        target=target,
    )
