"""Closed-form IK solver of a small arm: every branch, limits, Pinocchio verification, ordering.

:class:`ClosedFormSolver` asks the registered structures (:mod:`.registry`) which one fits the
arm's DH table, computes every branch with it (:mod:`.closed_form_structure`: the solver knows
no structure by name), then moves each branch into the joint limits and has the judge measure
it (:mod:`.branch_verification`: valid, rejected or dropped; valid ones ordered by distance to
the seed). A structure with a compiled twin that verifies (the 6R closed forms,
:mod:`.six_r.six_r_twin`) does that for a pose target in one C call: the same wrapping, and the
table's plain DH product in C as the judge instead of Pinocchio (``tests/test_six_r_twins.py``
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

import numpy.typing as npt

from kin import RobotModel
from kin.configuration import default_seed, seed_inside

from ..exceptions import StructureError
from ..judge import ToolJudge
from ..result import IKResult
from ..target import (
    AxisTarget,
    PitchTarget,
    PoseTarget,
    PositionTarget,
    Target,
    is_partial,
    kind_error,
)
from .branch_verification import UNPOLISHED_MISS, far_spans
from .closed_form_routes import ClosedFormRoutes
from .closed_form_structure import (
    ClosedFormStructure,
    DetailedStructure,
)
from .idealised import Idealised, idealise
from .idealised_fallback import UnprovedCall
from .joint_directions import forward_table, mirrored_limits, reversed_joints
from .registry import recognise_turned

logger = logging.getLogger(__name__)


class ClosedFormSolver(ClosedFormRoutes):
    """Every closed-form IK branch of one small arm, verified with Pinocchio.

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
        directions = reversed_joints(robot.table)
        table = forward_table(robot.table)
        #: The idealised table the structure fits when the true one misses it by rounding
        #: (:mod:`.idealised`: answers polished on the true chain), else None.
        self.idealised: Idealised | None = None
        try:
            self.structure: ClosedFormStructure
            self.structure, table, flips = recognise_turned(table)
        except StructureError as exact:
            ideal = idealise(table)
            if ideal is None:
                raise
            try:
                self.structure, table, flips = recognise_turned(ideal.table)
            except StructureError:
                raise exact from None
            self.idealised = ideal
            compiled = False  # the twins measure with the table they solve: the ideal one
        self._miss_bound = (
            None
            if self.idealised is None
            else (
                self.idealised.position_bound + UNPOLISHED_MISS,
                self.idealised.rotation_bound + UNPOLISHED_MISS,
            )
        )
        if flips is not None:
            directions = flips if directions is None else directions * flips
        #: Per joint 1 or -1 when the table reverses a joint or the structure fits it with
        #: antiparallel axes turned over (:func:`.registry.recognise_turned`), else None: the
        #: structure solves its table (:mod:`.joint_directions`) in ``q' = direction * q``;
        #: seeds are mapped in, answers out before the judge measures them on the true arm.
        self._directions = directions
        self.name = f"closed_form:{self.structure.name}"
        self._detailed = isinstance(self.structure, DetailedStructure)
        self.tolerance_position = tolerance_position
        self.tolerance_rotation = tolerance_rotation
        self._judge = ToolJudge(robot)
        # One solve at a time: the judge's Pinocchio data is shared (threads get the answers
        # one thread would).
        self._lock = threading.Lock()
        self._joint_names = robot.joint_names
        #: Per joint, revolute (compared modulo a turn by IKResult.without_repeats); None: all.
        revolute = tuple(row.joint_type == "revolute" for row in robot.table.rows)
        self._revolute = None if all(revolute) else revolute
        self._lower = robot.model.lowerPositionLimit.tolist()
        self._upper = robot.model.upperPositionLimit.tolist()
        if self._directions is not None:  # the limits of q' (those of the forward table)
            lower, upper = mirrored_limits(self._lower, self._upper, self._directions)
            self._lower, self._upper = lower.tolist(), upper.tolist()
        self._offsets = [row.theta for row in table.rows]
        self._has_offsets = any(self._offsets)
        self._far_spans = far_spans(self._offsets, self._lower, self._upper)
        # Everything below depends only on the table: computed once, as floats and tuples, so that
        # a solve runs on the math module rather than on small NumPy arrays.
        self._kinds = self.closed_form_kinds
        self._numeric: Any = None
        self._partial: Any = None
        # A full pose goes to the partial-pose solver on an arm of fewer than six joints whose
        # closed form does not take it whole (a five-joint arm's does, with its own reasons).
        # So does one whose closed form projects the pose on what the arm reaches (a SCARA's).
        whole = PoseTarget in self._kinds and not getattr(self.structure, "projects", False)
        self._partial_below = 6 if whole else len(self._lower)
        #: A full pose on an arm of fewer than six joints whose closed form solves positions only
        #: (a planar 2R, a 3R arm) or projects poses on the arm's (a SCARA, any arm of parallel
        #: axes): the closed form's branches are its only candidates, measured on the whole pose
        #: (:meth:`_pose_from_branches`) before the partial-pose solver is asked.
        self._pose_by_branches = (
            PositionTarget in self._kinds and PoseTarget not in self._kinds
        ) or bool(getattr(self.structure, "projects", False))
        self._zero_seed = [0.0] * len(self._lower)
        #: The seed of a call given none (:func:`kin.configuration.default_seed`); None when it
        #: is zero (the readers' own default).
        start_q = default_seed(robot)
        self._default_seed = None if not start_q.any() else start_q
        self._joints_zero_seed = self._joints([0.0] * len(self._lower))
        # A structure with a compiled twin that also verifies (the 6R closed forms): pose targets
        # are solved, moved into the limits and measured in one call (:mod:`.six_r_twin`).
        verifier = getattr(self.structure, "verifier", None)
        self._twin = (
            None
            if verifier is None or not compiled
            else verifier(table, self._lower, self._upper, tolerance_position, tolerance_rotation)
        )
        #: The twin's whole answer of a pose (:meth:`.six_r_twin.TwinVerifier.solutions`), or
        #: None: no twin.
        self._solutions = (
            None
            if self._twin is None
            else self._twin.solutions(self._directions, self.structure.branch_labels, self.name)
        )

    @property
    def closed_form_kinds(self) -> tuple[type, ...]:
        """The target classes the closed form itself solves (the structure's)."""
        return tuple(self.structure.target_kinds)

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """The target classes this solver accepts.

        The closed form's, and a position when the closed form does not take one (answered by
        the numeric solver, see :meth:`solve`).
        """
        kinds = self.closed_form_kinds
        kinds = kinds if PositionTarget in kinds else (*kinds, PositionTarget)
        extra = tuple(kind for kind in (PoseTarget, AxisTarget) if kind not in kinds)
        return (*kinds, *extra)

    def _failure(
        self, status: str, message: str, start: float, gap: float | None = None, target: Any = None
    ) -> IKResult:
        if status == "out_of_reach" and target is not None and gap is None:
            message, gap = self._how_far(message, target, gap)
        return IKResult(
            success=False,
            solver=self.name,
            status=status,  # type: ignore[arg-type]
            message=message,
            distance_to_workspace=gap,
            time=time.perf_counter() - start,
        )

    def _how_far(self, message: str, target: Target, gap: float | None) -> tuple[str, float | None]:
        """``message`` with the target's distance from the base against the arm's reach, and the gap [m]."""
        from ..reach import arm_reach

        reach = arm_reach(self.robot)
        distance = reach.distance(target.position)
        if distance > reach.maximum:
            beyond = distance - reach.maximum
            text = f"{beyond:.4g} m beyond the arm's reach ({reach.maximum:.4g} m from its base)"
            return f"{message}: the target is {text}", beyond
        text = f"{distance:.4g} m from the base, within the arm's reach of {reach.maximum:.4g} m"
        if isinstance(target, PositionTarget):  # the reach's hollows, the structure's plane
            return f"{message} (the target is {text})", gap
        return f"{message} (the target is {text}: not with this orientation)", gap

    def solve(
        self, target: Target, seed: npt.ArrayLike | None = None, *, timeout: float | None = None
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

        Returns:
            The result; never raises for unreachable, singular or non-finite targets.

        Raises:
            TargetError: The target kind does not fit the arm, or the seed has the wrong size.
        """
        start = time.perf_counter()
        seed = self._default_seed if seed is None else seed_inside(self.robot, seed)
        if target.__class__ is PoseTarget and self._solutions is not None:
            if target.mask is None:  # type: ignore[attr-defined]
                # One C call (no lock: the twin shares no state between calls), which makes the
                # result when a branch is valid, none is off target and none repeats another.
                answer = self._solutions(target, seed, start)
                if answer.__class__ is IKResult:
                    return answer  # type: ignore[no-any-return]
                twin = self._twin_answer(answer, target, seed, start)  # type: ignore[arg-type]
                return twin.without_repeats(self._revolute)
        if not isinstance(target, self._kinds) or target.__class__ is PoseTarget:
            if is_partial(target, self._partial_below):
                if (
                    self._pose_by_branches
                    and isinstance(target, PoseTarget)
                    and target.mask is None
                ):
                    with self._lock:
                        done = self._pose_from_branches(target, seed, start)
                    if done is not None:
                        return done
                return self.partial.solve(target, seed, timeout=timeout)  # type: ignore[arg-type]
        if not isinstance(target, self._kinds):
            if isinstance(target, self.target_kinds):
                return self._solve_numeric(target, seed, timeout)
            raise kind_error(self.robot.name, self.target_kinds, target)
        with self._lock:
            return self._solve_closed(target, seed, start, timeout).without_repeats(self._revolute)

    def _solve_closed(
        self, target: Target, seed: npt.ArrayLike | None, start: float, timeout: float | None
    ) -> IKResult:
        """:meth:`solve` of a target the closed form takes (under the solver's lock).

        A rounded arm's target none of whose polished branches is valid is answered by
        :meth:`~.idealised_fallback.IdealisedFallback._unproved` (``timeout``: its numeric
        search's cap [s]).
        """
        arm_seed = seed
        if self._directions is not None and seed is not None:
            seed = self._forward_seed(seed)
        seed_list = self._seed_list(seed)
        if not target.finite:
            return self._failure("invalid_target", "the target has a NaN or infinite value", start)
        p = target.position.tolist()
        r = target.rotation.tolist() if isinstance(target, PoseTarget) else None
        branches = self._branches(target, seed_list)
        rounded = self.idealised is not None and not isinstance(target, PitchTarget)
        if branches.status == "out_of_reach" and not rounded:
            return self._failure("out_of_reach", branches.message, start, branches.gap, target)
        if rounded:
            found = bool(branches.thetas)  # before the polish takes those far outside away
            valid, rejected = self._verify_polished(target, branches, seed_list, p, r)
            if not valid:
                call = UnprovedCall(seed_list, arm_seed, start, timeout)
                return self._unproved(target, branches, found, rejected, call)
            method = "closed_form_polished"
        else:
            valid, rejected = self._verify(target, branches, seed_list, p, r)
            method = "closed_form"
        return self._result(valid, rejected, branches.status, branches.message, start, method)
