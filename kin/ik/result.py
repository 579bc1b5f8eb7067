"""Values returned by every IK solver: one solution, and the result of one solve."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any, Literal

import numpy as np

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
            solve's (:mod:`kin.ik.collision_aware`) ``"self: forearm/base"`` or
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
        # directly (kin/_native/_six_r_module.h), a few of them per call.
        _SET_Q(self, q)
        _SET_BRANCH(self, branch)
        _SET_WITHIN_LIMITS(self, within_limits)
        _SET_POSITION_ERROR(self, position_error)
        _SET_ROTATION_ERROR(self, rotation_error)
        _SET_REASON(self, reason)

    def __getattr__(self, name: str) -> Any:
        # Only reached when a slot is unset: the compiled twins fill the first five fields alone.
        if name == "reason":
            return ""
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

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
            :mod:`kin.ik.collision_aware`; the colliding answers are ``rejected``).
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
        # per call. The compiled twins fill the same slots directly (kin/_native/_results.h).
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
        }


# IKResult's, in field order (success, solver, status, message, solutions, rejected,
# distance_to_workspace, iterations, time, method, free).
_RESULT_SETTERS = _slot_setters(IKResult)
_SET_SUCCESS, _SET_SOLVER, _SET_STATUS, _SET_MESSAGE, _SET_SOLUTIONS = _RESULT_SETTERS[:5]
_SET_REJECTED, _SET_DISTANCE, _SET_ITERATIONS, _SET_TIME, _SET_METHOD = _RESULT_SETTERS[5:10]
(_SET_FREE,) = _RESULT_SETTERS[10:]
