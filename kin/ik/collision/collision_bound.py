"""A distance bound inside the numeric solve: damped least-squares steps as QPs that keep apart.

Each step solves one small QP (``daqp``, :mod:`.dense_qp`; mink's ``solve_ik`` the same)::

    min  |W (A dq - e)|^2 / 2 + lam |dq|^2 / 2
    s.t. d_i + n_i^T (J_b - J_a) dq >= d_i - gain (d_i - tol - margin)  (pairs within influence)
         lower - q <= dq <= upper - q,  |dq| <= max_step

``e`` and ``A`` are the task's error and rows (:class:`~kin.ik.partial_pose.PartialTask`: a full
or masked pose, an axis target, a position), ``W`` its weights, ``lam`` Levenberg-Marquardt's
damping. The inequalities are the velocity damper of mink's ``CollisionAvoidanceLimit`` (and of
pink's barriers): a pair at distance ``d`` (coal's signed distance on the checker's own shapes,
padding taken off) may close at most the fraction ``gain`` of its gap to ``tol + margin`` per
step (``tol`` the contact tolerance below), and a pair already inside must open by that fraction.
``n`` is the unit normal from shape a to shape b, ``J_a`` and ``J_b`` the world-frame Jacobians
of the two witness points (the joint Jacobians of the shapes' joints moved to the points).
Pinocchio and coal compute it all on the checker's :class:`~kin.collision.CollisionModel` (its
geometry model and pairs, the hulls or primitives its queries use), so the bound and the
checker's verdict measure the same shapes, with the checker's requests
(:func:`~kin.collision.requests.prepare_requests`: GJK to 1e-8 m from its default guess,
signed). One verdict: a run is clear when every pair is farther than
:data:`~kin.collision.requests.CONTACT_TOLERANCE` (below it the checker counts contact), and an
answer is given only where ``in_collision`` also says free.

Work, not time, decides the answer: fixed steps per start, fixed starts (the given ones, then
a seeded generator's). The cap, checked before each start and step (an overrun of one step),
stops a run with no answer: a busy machine gives an idle one's answer, or ``timeout``. Pinocchio
judges: a solution is on target within the tolerances, inside the limits, and checked free.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from ...collision.distance_jacobian import pair_rows
from ...collision.requests import CONTACT_TOLERANCE, prepare_requests
from ..exceptions import TargetError
from ..judge import POSITION_TOLERANCE, ROTATION_TOLERANCE, _tool_frame_id
from ..numeric.dense_qp import solve_dense_qp
from ..numeric.numeric_target import NumericTarget
from ..numeric.sampling_box import sampling_limits
from ..partial_pose import PartialTask
from ..result import IKResult, IKSolution
from ..targets.target import AxisTarget, PoseTarget, PositionTarget
from .distance_bound import DistanceBound

__all__ = [
    "METHOD",
    "BoundOutcome",
    "DistanceBound",
    "DistanceBoundedIK",
    "held_in_scene",
    "solve_clear",
]

#: :attr:`IKResult.method` and the branch label of an answer of the bounded solve.
METHOD = "collision_bound"

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_POSITION_MASK = (True, True, True, False, False, False)


@dataclass(frozen=True)
class BoundOutcome:
    """One bounded run.

    Attributes:
        q: Final joint vector [rad] (or [m]), inside the limits.
        converged: On target within the tolerances and every pair farther than the padding
            plus :data:`~kin.collision.requests.CONTACT_TOLERANCE`.
        iterations: Steps taken.
        position_error: Of the constrained components [m].
        rotation_error: Of the constrained components [rad].
        distance: Smallest distance of a checked pair at ``q``, padding taken off [m].
        stopped: The time cap stopped the run before its work was done.
    """

    q: np.ndarray
    converged: bool
    iterations: int
    position_error: float
    rotation_error: float
    distance: float
    stopped: bool = False


def _task(target: Any) -> PartialTask | None:
    """The task of ``target``: a pose (masked or not), an axis, a position; None for another kind."""
    if isinstance(target, (PoseTarget, AxisTarget)):
        return PartialTask(target)
    if isinstance(target, (PositionTarget, NumericTarget)):  # a posture preference is not kept
        if target.rotation is None:
            return PartialTask(PoseTarget(target.position, np.eye(3), _POSITION_MASK))
        return PartialTask(PoseTarget(target.position, target.rotation))
    return None


def _task_of(target: Any) -> PartialTask:
    task = _task(target)
    if task is None:
        raise TargetError(
            f"the distance-bounded solve takes a pose, position or axis target, not {target!r}"
        )
    return task


class DistanceBoundedIK:
    """IK whose steps keep every checked pair of a collision checker apart (see the module).

    Args:
        robot: The robot (its Pinocchio model and tool frame).
        checker: The robot's :class:`~kin.collision.CollisionChecker` (shapes, pairs, padding).
        bound: The settings (:class:`DistanceBound`).
    """

    def __init__(self, robot: Any, checker: Any, bound: DistanceBound | None = None):
        self.robot = robot
        self.checker = checker
        self.bound = bound or DistanceBound()
        self.model: pin.Model = robot.model
        self.frame_id = _tool_frame_id(robot)
        self.lower = np.asarray(self.model.lowerPositionLimit, dtype=float).copy()
        self.upper = np.asarray(self.model.upperPositionLimit, dtype=float).copy()

    def run(
        self,
        target: Any,
        q0: npt.ArrayLike,
        position_tol: float = 1e-7,
        rotation_tol: float = 1e-6,
        end: float = math.inf,
    ) -> BoundOutcome:
        """Bounded steps from ``q0`` [rad] toward ``target``, :attr:`DistanceBound.iterations` at most.

        ``end``: the cap, a ``time.perf_counter()`` value checked before each step; a run it
        stops says ``stopped`` (``math.inf``: never).

        Raises:
            TargetError: A target kind the bound does not take (a pitch target).
        """
        bound, model = self.bound, self.model
        geometry_model = self.checker.model.geometry_model
        padding = self.checker.model.padding
        data, geometry_data = model.createData(), pin.GeometryData(geometry_model)
        prepare_requests(geometry_data, padding)  # the checker's distance queries
        task = _task_of(target)
        weights = task.weights
        q = np.clip(np.asarray(q0, dtype=float), self.lower, self.upper)
        identity = np.eye(model.nv)
        errors, smallest, steps = (math.inf, math.inf), -math.inf, 0
        best_error, best_clearance, progress = math.inf, -math.inf, 0
        stopped = False
        while True:
            pin.computeJointJacobians(model, data, q)
            pose = pin.updateFramePlacement(model, data, self.frame_id)
            pin.updateGeometryPlacements(model, data, geometry_model, geometry_data)
            pin.computeDistances(geometry_model, geometry_data)
            e = task.error(pose.translation, pose.rotation)
            errors = task.errors(e)
            d, rows, smallest = pair_rows(
                model, data, geometry_model, geometry_data, padding, bound.influence
            )
            on_target = errors[0] < position_tol and errors[1] < rotation_tol
            squared = errors[0] ** 2 + errors[1] ** 2
            if squared < 0.25 * best_error or min(smallest, 0.0) > best_clearance + 1e-3:
                best_error, best_clearance = min(best_error, squared), min(smallest, 0.0)
                progress = steps
            if (
                (on_target and smallest > CONTACT_TOLERANCE)
                or steps >= bound.iterations
                or steps - progress > bound.patience
            ):
                break
            if time.perf_counter() >= end:
                stopped = True
                break
            steps += 1
            frame_jacobian = pin.getFrameJacobian(model, data, self.frame_id, _LWA)
            a = task.jacobian(e, pose.rotation, frame_jacobian)[task.rows] * weights[:, None]
            r = e[task.rows] * weights
            lam = bound.damping + bound.error_damping * float(r @ r)
            lb = np.maximum(self.lower - q, -bound.max_step)
            ub = np.minimum(self.upper - q, bound.max_step)
            kept = CONTACT_TOLERANCE + bound.margin  # the margin beyond contact
            h = np.maximum(bound.gain * (d - kept), -bound.opening)
            args = (a.T @ a + lam * identity, -(a.T @ r))
            dq = None
            if not len(h):  # no pair close: the damped step itself when the bounds keep it
                dq = np.linalg.solve(args[0], -args[1])
                if not (np.all(dq >= lb) and np.all(dq <= ub)):
                    dq = None
            if dq is None:
                dq = solve_dense_qp(*args, -rows, h, lb, ub, bound.qp_solver)
            if dq is None and len(h):  # too far inside to open at that rate: do not close
                dq = solve_dense_qp(*args, -rows, np.maximum(h, 0.0), lb, ub, bound.qp_solver)
            if dq is None:
                break
            q = np.clip(q + dq, self.lower, self.upper)
        clear = on_target and smallest > CONTACT_TOLERANCE
        return BoundOutcome(q, clear, steps, *errors, smallest, stopped)

    def solve(
        self,
        target: Any,
        starts: Iterable[npt.ArrayLike],
        *,
        timeout: float | None = None,
        position_tol: float = POSITION_TOLERANCE,
        rotation_tol: float = ROTATION_TOLERANCE,
        solver: str = "numeric",
    ) -> IKResult:
        """Bounded runs from each of ``starts`` [rad], then from the random starts, until one is free.

        Args:
            target: A pose (masked or not), position or axis target, world frame.
            starts: Start joint vectors, tried in order (e.g. the colliding answers, the seed).
            timeout: Cap [s], checked before each start and each step (None: no cap).
            position_tol: Success tolerance on the position [m].
            rotation_tol: Success tolerance on the rotation [rad].
            solver: :attr:`IKResult.solver` of the result.

        Returns:
            ``ok`` with the first answer on target, inside the limits and free by the checker;
            else ``not_found`` (the work done) or ``timeout`` (the cap first), with the run that
            came nearest in ``rejected``.
        """
        begin = time.perf_counter()
        end = math.inf if timeout is None else begin + timeout
        best: BoundOutcome | None = None
        iterations = 0
        for q0 in self._starts(starts):
            if time.perf_counter() >= end:
                return self._failure(target, best, iterations, begin, solver, timeout=True)
            outcome = self.run(target, q0, end=end)
            iterations += outcome.iterations
            if outcome.stopped:  # unfinished work gives no answer: the cap's answer is timeout
                best = outcome if best is None or _worse(best, outcome) else best
                return self._failure(target, best, iterations, begin, solver, timeout=True)
            within = outcome.position_error < position_tol and outcome.rotation_error < rotation_tol
            clear = outcome.distance > CONTACT_TOLERANCE
            if within and clear and not self.checker.in_collision(outcome.q):
                found = IKSolution(
                    outcome.q, METHOD, True, outcome.position_error, _rotation(target, outcome)
                )
                return IKResult(
                    True,
                    solver,
                    "ok",
                    f"collision-free answer of the distance-bounded solve (clearance "
                    f"{outcome.distance:.4g} m)",
                    (found,),
                    (),
                    None,
                    iterations,
                    time.perf_counter() - begin,
                    METHOD,
                )
            if best is None or _worse(best, outcome):
                best = outcome
        return self._failure(target, best, iterations, begin, solver, timeout=False)

    def _starts(self, given: Iterable[npt.ArrayLike]) -> Iterable[np.ndarray]:
        yield from (np.asarray(q, dtype=float) for q in given)
        rng = np.random.default_rng(self.bound.random_seed)
        box = np.array(sampling_limits(self.robot.table, self.lower, self.upper))  # a rail cut
        lower, upper = np.where(np.isfinite(box), box, [[-math.pi], [math.pi]])
        for _ in range(self.bound.random_starts):
            yield rng.uniform(lower, upper)

    def _failure(
        self,
        target: Any,
        best: BoundOutcome | None,
        iterations: int,
        begin: float,
        solver: str,
        timeout: bool,
    ) -> IKResult:
        rejected: tuple[IKSolution, ...] = ()
        if best is not None:
            rejected = (
                IKSolution(best.q, METHOD, True, best.position_error, _rotation(target, best)),
            )
        if timeout:
            status, message = "timeout", "the time cap stopped the distance-bounded solve"
        else:
            status = "not_found"
            message = "the distance-bounded solve found no collision-free answer on target"
            if best is not None:
                message += (
                    f" (nearest: {best.position_error:.3g} m, {best.rotation_error:.3g} rad off, "
                    f"clearance {best.distance:.3g} m)"
                )
        return IKResult(
            False,
            solver,
            status,  # type: ignore[arg-type]
            message,
            (),
            rejected,
            None,
            iterations,
            time.perf_counter() - begin,
            "",
        )


def _rotation(target: Any, outcome: BoundOutcome) -> float | None:
    return None if isinstance(target, PositionTarget) else outcome.rotation_error


def _worse(best: BoundOutcome, outcome: BoundOutcome) -> bool:
    """Whether ``outcome`` beats ``best``: free before colliding, then nearer the target."""
    key_best = (_in_contact(best), best.position_error + best.rotation_error)
    key = (_in_contact(outcome), outcome.position_error + outcome.rotation_error)
    return key < key_best


def _in_contact(outcome: BoundOutcome) -> bool:
    """Whether a pair of ``outcome`` is within the checker's contact tolerance (one verdict)."""
    return outcome.distance < CONTACT_TOLERANCE


def solve_clear(
    robot: Any,
    checker: Any,
    target: Any,
    seed: npt.ArrayLike | None,
    colliding: Iterable[IKSolution],
    timeout: float | None,
    solver: str = "numeric",
    swept: bool = False,
) -> IKResult | None:
    """The distance-bounded solve after answers collided: from the seed, each of them, random starts.

    None for a target kind the bound does not take (the caller's search goes on without it).

    Args:
        robot: The robot.
        checker: Its collision checker.
        target: The target that was solved.
        seed: The caller's start joint vector [rad] (often free: the arm's present posture), or
            None.
        colliding: The answers found colliding, nearest the seed first.
        timeout: Cap [s], checked before each start and each step.
        solver: :attr:`IKResult.solver` of the result.
        swept: The first search swept the self-motion (a 7R arm's free-joint grid: every
            branch at every grid value): the bounded solve then runs from the seed alone. The
            colliding answers are points of that sweep, from which a bounded walk retraces it,
            and the random starts rarely find what it missed (1 free answer in 53 on Panda, at
            3x the work). On Panda (scripts/bench_collision_bound.py, 208 cases, 84 calls)
            the seed found the one free answer the grid missed, at its 8th step; the colliding
            answers none.
    """
    if _task(target) is None:  # a kind the bound does not take (a 5-joint arm's pitch target)
        return None
    colliding = list(colliding)
    if target.__class__ is PoseTarget and target.mask is None and colliding:
        pair = held_in_scene(robot, checker, colliding[0].q)
        # An answer is on target: the links the tool carries sit where the target puts them.
        if pair:
            return IKResult(
                False,
                solver,
                "not_found",
                f"the links the tool carries collide at the target pose itself ({pair}): no "
                "joint vector reaching it is free",
            )
    starts = [] if seed is None else [np.asarray(seed, dtype=float)]  # checked by the first solve
    if not swept:
        starts += [np.asarray(s.q, dtype=float) for s in colliding]
    bound = DistanceBound(random_starts=0) if swept else DistanceBound()
    return DistanceBoundedIK(robot, checker, bound).solve(
        target, starts, timeout=timeout, solver=solver
    )


def held_in_scene(robot: Any, checker: Any, q: npt.ArrayLike) -> str:
    """A scene contact of the links on the tool frame's joint at ``q`` [rad], ``"link/object"``.

    Those links are placed by the tool pose alone: at a full pose target their contact with the
    scene is the same at every joint vector that reaches it. ``""`` when they touch nothing.
    """
    model = checker.model
    joint = robot.model.frames[_tool_frame_id(robot)].parentJoint
    objects = model.geometry_model.geometryObjects
    held = {model.owners[i] for i, shape in enumerate(objects) if shape.parentJoint == joint}
    scene = set(model.scene_objects)
    for contact in checker.collisions(q):
        if (contact.a in held and contact.b in scene) or (contact.b in held and contact.a in scene):
            return f"{contact.a}/{contact.b}"
    return ""
