"""Values returned by every IK solver: one solution, and the result of one solve."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields
from operator import mul
from typing import Any, Literal

import numpy as np

from .angles import wrap

Status = Literal[
    "ok",
    "out_of_reach",
    "outside_limits",
    "singular",
    "invalid_target",
    "not_found",
    "timeout",
    "in_collision",
]


@dataclass(frozen=True, eq=False, slots=True)
class IKSolution:
    """One joint vector that the solver returns, verified by forward kinematics.

    The FK is Pinocchio's, except on the compiled paths, which measure with the table's DH product
    in C: the 6R closed forms' (:mod:`kin.ik.analytic.six_r.six_r_twin`) and the 7R free-joint
    forms' answer from the caller's seed (:func:`kin.ik.numeric.free_joint.compiled_seeded`).

    Attributes:
        q: Joint vector [rad] (or [m] for prismatic joints).
        branch: Branch label, e.g. ``"shoulder front, elbow up"``; ``""`` for numeric solvers.
        within_limits: Whether ``q`` is inside the joint limits.
        position_error: ``|p_fk(q) - p_target|`` [m].
        rotation_error: Angle of ``R_fk(q)^T R_target`` [rad]; None when the target does not
            constrain the orientation (a position target).
        reason: Why it is rejected, where more than the limits and errors say: a collision-aware
            solve's (:mod:`kin.ik.collision.collision_aware`) ``"self: forearm/base"`` or
            ``"scene: table"``; a rounded arm's branch far outside the limits, judged without
            its polish (:mod:`kin.ik.analytic.branch_verification`), names the joint farthest
            out; ``""`` otherwise.
    """

    q: np.ndarray
    branch: str
    within_limits: bool
    position_error: float
    rotation_error: float | None
    reason: str = ""

    def __init__(
        self,
        q: np.ndarray,
        branch: str,
        within_limits: bool,
        position_error: float,
        rotation_error: float | None,
        reason: str = "",
    ):
        # Slots, set through their descriptors (the generated frozen __init__ looks each one up
        # through object.__setattr__). The closed forms' compiled twins fill the same slots
        # directly (kin/_native/ik/analytic/six_r/_six_r_module.h), a few of them per call.
        _SET_Q(self, q)
        _SET_BRANCH(self, branch)
        _SET_WITHIN_LIMITS(self, within_limits)
        _SET_POSITION_ERROR(self, position_error)
        _SET_ROTATION_ERROR(self, rotation_error)
        _SET_REASON(self, reason)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict, SI: ``q`` in rad (revolute) / m (prismatic), errors in m and rad.

        ``"reason"`` is there only when it is not empty (a collision-aware rejection).
        """
        q = self.q
        out = {
            "q": q.tolist() if q.__class__ is np.ndarray else [float(v) for v in q],
            "branch": self.branch,
            "within_limits": bool(self.within_limits),
            "position_error_m": float(self.position_error),
            "rotation_error_rad": (
                None if self.rotation_error is None else float(self.rotation_error)
            ),
        }
        reason = self.reason
        if reason:
            out["reason"] = reason
        return out


def _slot_setters(cls: type) -> list[Callable[[object, object], None]]:
    """The ``__set__`` of each field's slot descriptor, in field order.

    They set a slot past the class's frozen ``__setattr__`` (as the generated ``__init__`` of a
    frozen dataclass does, for a fraction of its cost).
    """
    return [cls.__dict__[item.name].__set__ for item in fields(cls)]


_SET_Q, _SET_BRANCH, _SET_WITHIN_LIMITS, _SET_POSITION_ERROR, _SET_ROTATION_ERROR, _SET_REASON = (
    _slot_setters(IKSolution)
)


@dataclass(frozen=True, eq=False, slots=True)
class IKResult:
    """Outcome of one IK solve.

    Attributes:
        success: At least one solution is on target and within limits.
        solver: The pipeline that was asked (e.g. ``"closed_form:pickplace3"``, ``"numeric"``,
            ``"nr"``).
        method: The stage of that pipeline that answered: ``"closed_form"``,
            ``"closed_form_free_joint"``, ``"closed_form_polished"``, ``"seed_table"``,
            ``"damped_newton"`` (from the caller's seed), ``"random_restart"``, ``"mink_qp"``,
            ``"newton_raphson"``; for a partial pose (:mod:`kin.ik.partial_pose`) also
            ``"weighted_newton"`` (least squares from the seed or a random start) and
            ``"closed_form_refined"`` (least squares from a closed-form branch of the sweep,
            where the free rotation is no symmetry of the arm: a five-joint arm's world-axis
            mask); ``""`` when none did.
        status: ``"ok"`` or why there is no valid solution: ``"out_of_reach"`` only when
            proved (beyond the reach bound, or no closed-form branch); ``"not_found"`` when a
            search did its bounded work without an answer (no claim of unreachability);
            ``"timeout"`` when the time cap stopped a search first; ``"in_collision"`` when the
            target is reachable but every answer found collides (a collision-aware solve,
            :mod:`kin.ik.collision.collision_aware`; the colliding answers are ``rejected``).
        message: One sentence for a person (e.g. how far out of reach the target is).
        solutions: Valid solutions (on target, within limits), closest to the seed first.
        rejected: Solutions on target but outside the limits (a rounded arm's branch far outside
            them judged unpolished, its ``reason`` set when it misses the target), colliding ones
            with their ``reason``, or the best off-target attempt of a numeric solver.
        distance_to_workspace: For ``"out_of_reach"``, how far the target is from the reachable
            set [m]; else None.
        iterations: Iterations used (numeric solvers), 0 for closed form.
        time: Wall time of the solve [s].
        free: The pose components the target left free (``"rx"``, ``"ry"``, ...; the roll
            about the tool axis of an axis target), ``()`` when it constrains all it names.
    """

    success: bool
    solver: str
    status: Status
    message: str
    solutions: tuple[IKSolution, ...] = field(default_factory=tuple)
    rejected: tuple[IKSolution, ...] = field(default_factory=tuple)
    distance_to_workspace: float | None = None
    iterations: int = 0
    time: float = 0.0
    method: str = ""
    free: tuple[str, ...] = ()

    def __init__(
        self,
        success: bool,
        solver: str,
        status: Status,
        message: str,
        solutions: tuple[IKSolution, ...] = (),
        rejected: tuple[IKSolution, ...] = (),
        distance_to_workspace: float | None = None,
        iterations: int = 0,
        time: float = 0.0,
        method: str = "",
        free: tuple[str, ...] = (),
    ):
        # Same fields and defaults as the generated frozen __init__, set through the slots'
        # descriptors (past the frozen __setattr__, as IKSolution's): a numeric solve makes one
        # per call. The compiled twins fill the same slots directly (kin/_native/include/_results.h).
        _SET_SUCCESS(self, success)
        _SET_SOLVER(self, solver)
        _SET_STATUS(self, status)
        _SET_MESSAGE(self, message)
        _SET_SOLUTIONS(self, solutions)
        _SET_REJECTED(self, rejected)
        _SET_DISTANCE(self, distance_to_workspace)
        _SET_ITERATIONS(self, iterations)
        _SET_TIME(self, time)
        _SET_METHOD(self, method)
        _SET_FREE(self, free)

    def without_repeats(self, revolute: Sequence[bool] | None = None) -> IKResult:
        """This result with each joint vector once (:func:`distinct_solutions`), self if none repeats.

        At a singularity two branches can be one joint vector (a wrist flip with the wrist
        straight, an elbow stretched): the first keeps its place and label, the message counts
        the answers left and says how many repeats were merged.

        Args:
            revolute: Per joint, whether it is revolute (its difference taken modulo a turn);
                None: every joint.
        """
        solutions = distinct_solutions(self.solutions, revolute)
        rejected = distinct_solutions(self.rejected, revolute)
        if solutions is self.solutions and rejected is self.rejected:
            return self
        merged = len(self.solutions) + len(self.rejected) - len(solutions) - len(rejected)
        message = self.message
        valid = f"{len(self.solutions)} valid solution(s)"  # the closed forms' counts
        outside = f"({len(self.rejected)} branch(es))"
        if message.startswith(valid):
            message = f"{len(solutions)} valid solution(s)" + message[len(valid) :]
        elif message.endswith(outside):
            message = message[: -len(outside)] + f"({len(rejected)} branch(es))"
        message += f"; {merged} repeated branch(es) merged (the same joint vector)"
        return IKResult(
            self.success,
            self.solver,
            self.status,
            message,
            solutions,
            rejected,
            self.distance_to_workspace,
            self.iterations,
            self.time,
            self.method,
            self.free,
        )

    @property
    def best(self) -> IKSolution | None:
        """The first valid solution, else the first rejected one, else None."""
        if self.solutions:
            return self.solutions[0]
        return self.rejected[0] if self.rejected else None

    def to_dict(self, rejected: bool = True) -> dict[str, Any]:
        """JSON-ready dict of the result, SI (see ``kin ik --json``).

        Args:
            rejected: Include the rejected solutions even when there are valid ones (False:
                ``"rejected"`` is filled only when ``solutions`` is empty, with the best attempts).
        """
        keep = rejected or not self.solutions
        listed = len(self.rejected) if keep else 0
        return {
            "success": bool(self.success),
            "solver": self.solver,
            "status": self.status,
            "message": self.message,
            "solutions": [s.to_dict() for s in self.solutions],
            "rejected": [s.to_dict() for s in self.rejected] if keep else [],
            "method": self.method,
            "distance_to_workspace_m": self.distance_to_workspace,
            "iterations": int(self.iterations),
            "time_s": float(self.time),
            "free": list(self.free),
            "counts": counts_record(len(self.solutions), len(self.rejected), listed),
        }


def counts_record(solutions: int, rejected: int, rejected_listed: int) -> dict[str, int]:
    """The ``"counts"`` of an answer's record: what it holds, and what it leaves out.

    Every valid solution is listed; the rejected ones only with ``--all`` (``"all": true``) or
    when there is no valid one.
    """
    return {"solutions": solutions, "rejected": rejected, "rejected_listed": rejected_listed}


#: Two answers are one branch when every joint differs by at most this [rad] / [m], a revolute
#: joint's difference taken modulo a turn (:func:`kin.ik.angles.wrap`).
SAME_BRANCH = 1e-6
_TWO_PI = 2.0 * math.pi
remainder = math.remainder


def distinct_solutions(
    solutions: tuple[IKSolution, ...],
    revolute: Sequence[bool] | None = None,
    tolerance: float = SAME_BRANCH,
) -> tuple[IKSolution, ...]:
    """``solutions`` without the ones whose joint vector repeats an earlier one's, in order.

    Args:
        solutions: Answers of one solve.
        revolute: Per joint, whether it is revolute; None: every joint.
        tolerance: Largest joint difference of one joint vector [rad] / [m] (:data:`SAME_BRANCH`).

    Returns:
        ``solutions`` itself when no joint vector repeats, else a new tuple. The usual case costs
        one key per answer, ``sum_j j q_j`` modulo a turn (not the plain sum: parallel joints
        keep theirs on every branch), which two equal vectors share to
        ``nq (nq + 1) / 2 * tolerance``: no two keys that close (sorted, round the circle), no
        pair compared.
    """
    count = len(solutions)
    if count < 2:
        return solutions
    rows = [s.q.tolist() if s.q.__class__ is np.ndarray else list(s.q) for s in solutions]
    weights = range(1, len(rows[0]) + 1)  # whole numbers: a turn of a joint turns the key
    keys = sorted([remainder(sum(map(mul, row, weights)), _TWO_PI) for row in rows])
    span = sum(weights) * tolerance
    if keys[0] + _TWO_PI - keys[-1] > span and all(b - a > span for a, b in zip(keys, keys[1:])):
        return solutions
    repeats: set[int] = set()
    for i in range(1, count):
        for j in range(i):
            if j not in repeats and _same(rows[i], rows[j], revolute, tolerance):
                repeats.add(i)
                break
    if not repeats:
        return solutions
    return tuple(s for i, s in enumerate(solutions) if i not in repeats)


def _same(
    a: list[float], b: list[float], revolute: Sequence[bool] | None, tolerance: float
) -> bool:
    """Whether the joint vectors ``a`` and ``b`` are one (:func:`distinct_solutions`)."""
    for index, (u, v) in enumerate(zip(a, b)):
        gap = wrap(u - v) if revolute is None or revolute[index] else u - v
        if abs(gap) > tolerance:
            return False
    return True


# IKResult's, in field order (success, solver, status, message, solutions, rejected,
# distance_to_workspace, iterations, time, method, free).
_RESULT_SETTERS = _slot_setters(IKResult)
_SET_SUCCESS, _SET_SOLVER, _SET_STATUS, _SET_MESSAGE, _SET_SOLUTIONS = _RESULT_SETTERS[:5]
_SET_REJECTED, _SET_DISTANCE, _SET_ITERATIONS, _SET_TIME, _SET_METHOD = _RESULT_SETTERS[5:10]
(_SET_FREE,) = _RESULT_SETTERS[10:]
