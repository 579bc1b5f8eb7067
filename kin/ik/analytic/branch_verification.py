"""The branches of a closed form moved into the joint limits and measured by the judge.

For each branch of a closed-form arm (:class:`BranchVerifier`, which
:class:`~.closed_form.ClosedFormSolver` holds; the arm's values in a
:class:`~.closed_form_branches.ClosedFormArm`):

1. each angle goes to the ``2 pi`` copy inside the joint limits closest to the seed
   (:func:`kin.ik.limit_rule.wrap_into`, the rule of :mod:`kin.ik.limit_rule`);
2. the judge (:mod:`kin.ik.judge`: Pinocchio) measures the tool pose of the joint vector:
   position error [m], rotation error [rad] (the angle of ``R_fk^T R_target`` for pose targets,
   between the approach axes for pitch targets, None for position targets);
3. the branch is valid (inside the limits, on target), rejected (on target, outside) or dropped
   (off target: never returned, logged).

An idealised arm's branch (:mod:`.idealised`) far outside the limits is judged as it is, not
polished onto the true chain (:meth:`BranchVerifier.verify_far`): with a joint farther
than :data:`OUTSIDE_MARGIN` outside its limits in every copy ``+ 2 pi k`` and a miss ``e`` of at
most the idealisation's bounds (:func:`.idealised.snap_bounds`) plus :data:`UNPOLISHED_MISS`, it
is rejected, without the miss warning (off target by more than the tolerances, its ``reason``
names the joint). The rule: the polish (Gauss-Newton from ``e``) moves a joint by about
``|J^+ e| <= |e| / sigma_min(J)``, less than the margin wherever ``sigma_min(J) > |e| / 0.1``
[m/rad]: everywhere but within 2.4e-8 of a singular Jacobian on the corpus AL5D (``e`` at most
2.4e-9), within 3e-4 for a PUMA 560 whose twists read 1.5708 (``e`` up to 3e-5; its polish moves
a joint by up to 0.045 rad where the wrist nears ``q5 = 0``). A solve with no valid branch
polishes them all and judges them again (:mod:`.idealised_fallback`), so a "no" never rests on
this rule; a "yes" could miss a second valid branch only that near a singularity.

A structure with a compiled twin that verifies (the 6R closed forms, :mod:`.six_r.six_r_twin`)
does the three steps for a pose in one C call, which also makes the solutions and, when one
is valid and none off target, the result (:meth:`.six_r.six_r_twin.TwinVerifier.solutions`;
else :meth:`.closed_form.ClosedFormSolver._twin_answer`). Valid solutions are ordered by
Euclidean distance to the seed (:meth:`BranchVerifier.result`).
"""

from __future__ import annotations

import logging
import math
import operator
import time
from typing import Any

import numpy as np

from kin import RobotModel

from ..judge import ToolJudge, axis_error, rotation_error
from ..limit_rule import FAST_COPY, FAST_SEED, LIMIT_TOL, TWO_PI, wrap_into
from ..result import IKResult, IKSolution, Status
from ..targets.target import PitchTarget, PositionTarget, Target
from .branches import Branches, BranchStatus
from .closed_form_branches import ClosedFormArm
from .closed_form_structure import PitchStructure

logger = logging.getLogger("kin.ik.analytic.closed_form")

#: Sort key of the (distance to the seed, solution) pairs.
_DISTANCE = operator.itemgetter(0)

#: An idealised arm's branch with a joint farther than this [rad] outside its limits (in every
#: copy ``+ 2 pi k``) is judged without its polish (see the module): 98 % of the corpus AL5D's
#: branches outside its limits.
OUTSIDE_MARGIN = 0.1
#: Slack [m], [rad] over the idealisation's bounds on an unpolished branch's miss: a pose's
#: projection on a 4-joint arm misses by up to 2.5e-7 rad on the corpus AL5D where the polish
#: reaches the pose.
UNPOLISHED_MISS = 1e-6


def far_spans(
    offsets: list[float], lower: list[float], upper: list[float]
) -> tuple[tuple[int, float, float], ...]:
    """Per joint whose limits span less than a turn: (index, start, span) [rad].

    A DH angle ``theta`` has no copy ``+ 2 pi k`` within :data:`OUTSIDE_MARGIN` (and
    :data:`~kin.ik.limit_rule.LIMIT_TOL`) of the joint's limits when
    ``(theta - start) % 2 pi > span`` (``start``: the offset plus the lower limit, widened).
    """
    tolerance = LIMIT_TOL + OUTSIDE_MARGIN
    return tuple(
        (i, offset + low - tolerance, high - low + 2.0 * tolerance)
        for i, (offset, low, high) in enumerate(zip(offsets, lower, upper))
        if high - low + 2.0 * tolerance < TWO_PI
    )


def log_miss(robot: str, label: str, position_error: float, angle: float | None) -> None:
    """Log a branch dropped off target, with its errors [m], [rad]."""
    logger.warning(
        "%s: branch '%s' misses the target by %.3g m, %.3g rad; dropped",
        robot,
        label,
        position_error,
        angle or 0.0,
    )


def free_intervals(
    seed: list[float], lower: list[float], upper: list[float]
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Per joint, the open interval of angles that need no wrapping (lower ends, upper ends).

    Inside it an angle [rad] is within the limits ``lower``, ``upper`` and is already the copy
    nearest the ``seed``; NaN ends where the seed is too far out for the short way.
    """
    lows, highs = [], []
    for s, low, high in zip(seed, lower, upper):
        if abs(s) < FAST_SEED:
            lows.append(max(low, s - FAST_COPY))
            highs.append(min(high, s + FAST_COPY))
        else:  # every angle takes the exact path
            lows.append(math.nan)
            highs.append(math.nan)
    return tuple(lows), tuple(highs)


def how_far(
    robot: RobotModel, message: str, target: Target, gap: float | None
) -> tuple[str, float | None]:
    """``message`` with the target's distance from the base against the arm's reach, and the gap [m]."""
    from ..reach import arm_reach

    reach = arm_reach(robot)
    distance = reach.distance(target.position)
    if distance > reach.maximum:
        beyond = distance - reach.maximum
        text = f"{beyond:.4g} m beyond the arm's reach ({reach.maximum:.4g} m from its base)"
        return f"{message}: the target is {text}", beyond
    text = f"{distance:.4g} m from the base, within the arm's reach of {reach.maximum:.4g} m"
    if isinstance(target, PositionTarget):  # the reach's hollows, the structure's plane
        return f"{message} (the target is {text})", gap
    return f"{message} (the target is {text}: not with this orientation)", gap


class BranchVerifier:
    """Moves a closed form's branches into the limits and has the judge measure them (see the module).

    Args:
        arm: The arm as its structure sees it (offsets, directions, limits of ``q'``).
        name: The solver's name (:attr:`IKResult.solver`, ``closed_form:<structure>``).
        judge: The judge of the arm (Pinocchio's FK at the tool frame).
        tolerance_position: Largest position error of a valid branch [m].
        tolerance_rotation: Largest rotation error of a valid branch [rad].

    Attributes:
        nearest_miss: The smallest error [m] or [rad] of the branches the last :meth:`verify`
            dropped (inf: none); read by the idealised polish (:mod:`.idealised_fallback`)
            under the solver's lock.
        miss_bound: An idealised arm's bounds on an unpolished branch's miss ([m], [rad]): the
            idealisation's bounds plus :data:`UNPOLISHED_MISS`; None: an exact arm.
    """

    def __init__(
        self,
        arm: ClosedFormArm,
        name: str,
        judge: ToolJudge,
        tolerance_position: float,
        tolerance_rotation: float,
    ) -> None:
        self.arm = arm
        self.name = name
        self.judge = judge
        self.tolerance_position = tolerance_position
        self.tolerance_rotation = tolerance_rotation
        self.nearest_miss = math.inf
        ideal = arm.idealised
        self.miss_bound = (
            None
            if ideal is None
            else (ideal.position_bound + UNPOLISHED_MISS, ideal.rotation_bound + UNPOLISHED_MISS)
        )
        self.far_spans = far_spans(arm.offsets, arm.lower, arm.upper)
        self._robot_name = arm.robot.name
        self._joint_names = arm.robot.joint_names
        # The hot path's values, read as attributes of this object (no property calls).
        self._offsets, self._lower, self._upper = arm.offsets, arm.lower, arm.upper
        self._has_offsets, self._directions = arm.has_offsets, arm.directions
        self._zero_seed = arm.zero_seed
        self._joints_zero_seed = free_intervals(arm.zero_seed, arm.lower, arm.upper)

    def result(
        self,
        valid: list[tuple[float, IKSolution]],
        rejected: list[IKSolution],
        branch_status: BranchStatus,
        branch_message: str,
        start: float,
        method: str = "closed_form",
    ) -> IKResult:
        """The result of verified branches: valid ones ordered by distance to the seed."""
        if len(valid) > 1:
            valid.sort(key=_DISTANCE)
        solutions = tuple([solution for _, solution in valid])
        rejected_solutions = tuple(rejected)
        status: Status
        if solutions:
            status = branch_status
            message = branch_message or f"{len(solutions)} valid solution(s)"
        elif rejected_solutions:
            status = "outside_limits"
            message = (
                f"reachable only outside the joint limits ({len(rejected_solutions)} branch(es))"
            )
        else:
            status, message = "singular", branch_message or "no branch verified on target"
        return IKResult(
            success=bool(solutions),
            solver=self.name,
            status=status,
            message=message,
            solutions=solutions,
            rejected=rejected_solutions,
            time=time.perf_counter() - start,
            method=method if solutions else "",
        )

    def failure(
        self, status: str, message: str, start: float, gap: float | None = None, target: Any = None
    ) -> IKResult:
        """A result without solutions; ``out_of_reach`` of a ``target`` says how far it is."""
        if status == "out_of_reach" and target is not None and gap is None:
            message, gap = how_far(self.arm.robot, message, target, gap)
        return IKResult(
            success=False,
            solver=self.name,
            status=status,  # type: ignore[arg-type]
            message=message,
            distance_to_workspace=gap,
            time=time.perf_counter() - start,
        )

    def verify(
        self,
        target: Target,
        branches: Branches,
        seed: list[float],
        p: list[float],
        r: list[list[float]] | None,
        quiet: bool = False,
    ) -> tuple[list[tuple[float, IKSolution]], list[IKSolution]]:
        """Per branch: the joint vector, the judge's errors, and where it goes (valid, rejected, dropped).

        ``quiet``: a branch off target is dropped without a warning (the caller asks another
        solver then). The smallest error of those dropped ([m] or [rad], inf: none) is kept in
        :attr:`nearest_miss`.
        """
        tool, tool_position = self.judge.tool, self.judge.tool_position
        zero = seed is self._zero_seed or seed == self._zero_seed  # a zero seed's, computed once
        offsets, lower, upper = self._offsets, self._lower, self._upper
        lows, highs = self._joints_zero_seed if zero else free_intervals(seed, lower, upper)
        sub, lt, dist, array = operator.sub, operator.lt, math.dist, np.array
        tol_p, tol_r = self.tolerance_position, self.tolerance_rotation
        position_only = isinstance(target, PositionTarget)
        if r is not None:
            r_target = r[0] + r[1] + r[2]
        elif not position_only:
            structure = self.arm.structure
            assert isinstance(structure, PitchStructure) and isinstance(target, PitchTarget)
            approach = structure.approach(target, seed)
            tx, ty, tz = structure.approach_in_tool
        valid: list[tuple[float, IKSolution]] = []
        rejected: list[IKSolution] = []
        nearest_miss = math.inf
        has_offsets = self._has_offsets
        directions = self._directions
        for thetas, label in branches.thetas:
            q_list = list(map(sub, thetas, offsets)) if has_offsets else list(thetas)
            inside = True
            if not (all(map(lt, lows, q_list)) and all(map(lt, q_list, highs))):
                i = 0
                for value in q_list:
                    if (
                        not lows[i] < value < highs[i]
                    ):  # else: inside the limits, the copy nearest the seed
                        q_list[i], ok = wrap_into(value, seed[i], lower[i], upper[i])
                        if not ok:
                            inside = False
                    i += 1
            q = array(q_list)
            if directions is not None:  # the structure's q' to the arm's q, for the judge
                q = q * directions
            angle: float | None
            if position_only:  # the translation alone; the orientation is not constrained
                position_error = dist(tool_position(q), p)
                angle = None
            else:
                p_fk, r_fk = tool(q)
                position_error = dist(p_fk, p)
                if r is not None:
                    angle = rotation_error(r_fk, r_target)
                else:
                    m00, m01, m02, m10, m11, m12, m20, m21, m22 = r_fk
                    u = (
                        m00 * tx + m01 * ty + m02 * tz,
                        m10 * tx + m11 * ty + m12 * tz,
                        m20 * tx + m21 * ty + m22 * tz,
                    )
                    angle = axis_error(u, approach)
            if position_error > tol_p or (angle is not None and angle > tol_r):
                if not quiet:
                    log_miss(self._robot_name, label, position_error, angle)
                nearest_miss = min(nearest_miss, max(position_error, angle or 0.0))
                continue
            solution = IKSolution(q, label, inside, position_error, angle)
            if inside:
                valid.append((dist(q_list, seed), solution))
            else:
                rejected.append(solution)
        self.nearest_miss = nearest_miss
        return valid, rejected

    def far_outside(self, thetas: tuple[float, ...] | list[float]) -> bool:
        """Whether a joint of ``thetas`` (DH angles [rad]) is far outside its limits.

        Farther than :data:`OUTSIDE_MARGIN` (and :data:`~kin.ik.limit_rule.LIMIT_TOL`) in every
        copy ``+ 2 pi k`` (:func:`far_spans`).
        """
        for i, start, span in self.far_spans:
            if (thetas[i] - start) % TWO_PI > span:
                return True
        return False

    def verify_far(
        self,
        branches: list[tuple[tuple[float, ...], str]],
        seed: list[float],
        p: list[float],
        r: list[list[float]] | None,
        quiet: bool = False,
    ) -> list[IKSolution]:
        """An idealised arm's branches far outside the limits, judged unpolished: the rejected.

        Each (DH angles [rad]) is measured as it is (a position or pose target: ``p`` [m], ``r``):
        one off target by at most :attr:`miss_bound` ([m], [rad]) is rejected, moved to the
        copies of :func:`wrap_into` (the least outside, nearest the seed), with a reason when off
        by more than the tolerances; farther ones are dropped (logged unless ``quiet``).
        """
        judge, directions, offsets = self.judge, self._directions, self._offsets
        limits = list(zip(seed, self._lower, self._upper))
        assert self.miss_bound is not None
        bound_p, bound_r = self.miss_bound
        tol_p, tol_r = self.tolerance_position, self.tolerance_rotation
        r_target = None if r is None else r[0] + r[1] + r[2]
        rejected = []
        for thetas, label in branches:
            q_list = [theta - offset for theta, offset in zip(thetas, offsets)]
            q = np.array(q_list) if directions is None else np.array(q_list) * directions
            angle: float | None = None
            if r_target is None:
                position_error = math.dist(judge.tool_position(q), p)
            else:
                p_fk, r_fk = judge.tool(q)
                position_error, angle = math.dist(p_fk, p), rotation_error(r_fk, r_target)
            if position_error > bound_p or (angle or 0.0) > bound_r:
                if not quiet:
                    log_miss(self._robot_name, label, position_error, angle)
                continue
            # Each angle's copy of wrap_into (the tool's pose is the same to round-off): an angle
            # inside its limits and within FAST_COPY of the seed is its own.
            wrapped = [
                v
                if low <= v <= high and -FAST_COPY < v - s < FAST_COPY
                else wrap_into(v, s, low, high)[0]
                for v, (s, low, high) in zip(q_list, limits)
            ]
            if wrapped != q_list:
                q_list = wrapped
                q = np.array(q_list) if directions is None else np.array(q_list) * directions
            on_target = position_error <= tol_p and (angle or 0.0) <= tol_r
            reason = "" if on_target else self.far_reason(q_list)
            rejected.append(IKSolution(q, label, False, position_error, angle, reason))
        return rejected

    def far_reason(self, q_list: list[float]) -> str:
        """Why an unpolished branch off target is rejected: the joint farthest outside its limits.

        ``q_list``: the structure's ``q'`` moved toward the limits [rad], [m] (the arm's ``q``
        has the same joint farthest outside; its value is the solution's).
        """
        beyond = [max(low - v, v - high) for v, low, high in zip(q_list, self._lower, self._upper)]
        name = self._joint_names[beyond.index(max(beyond))]
        return f"outside the joint limits (joint '{name}'), not polished onto the true chain"
