"""A position on a 6R arm whose closed form takes poses: the answer nearest the seed.

For a position the arm has three joints to spare: its answers form a three-dimensional set, and
a person (or a path's next sample) expects the one nearest the arm's posture, not a seed-table
sample's far branch. :class:`PositionNearSeed` finds it from two kinds of start, each on target:

1. the damped least-squares step sequence from the seed: ``dq = J^T (J J^T + lambda^2 I)^-1 e``
   with the position rows of the ``LOCAL_WORLD_ALIGNED`` tool Jacobian, ``lambda`` =
   :data:`DAMPING` [m], each step cut to :data:`STEP` [rad] and clipped into the limits, until
   the error is below :data:`ON_TARGET` [m];
2. the closed form's branches at the target position with the seed's own tool rotation, and with
   that rotation turned about the first joint's axis by the target's azimuth from the seed's
   tool (the arm pans), each angle moved to its ``2 pi`` copy nearest the seed
   (:func:`~kin.ik.limit_rule.nearest_copies`); those inside the limits, nearest first.

From each start, a descent along the target's answers toward the seed: the seed's pull projected
on the null space of the position Jacobian, then Gauss-Newton steps back onto the target, a step
kept only when it brings the answer nearer the seed (the step rate halved otherwise), until the
projected pull is below :data:`SETTLED` [rad]. So the answer is never farther from the seed than
the end of the step sequence of start 1. The nearest answer the judge finds on target inside the
limits is returned; None when no start reaches the target (the numeric pipeline answers then),
at once for a target farther from the base than the links laid end to end
(:func:`~kin.ik.reach.reach_bound`: no step taken, which would only overflow for a far one).
Angles in [rad], lengths in [m], world frame.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from kin import RobotModel

from ..judge import ToolJudge
from ..limit_rule import nearest_copies
from ..reach import reach_bound

#: Damping of the least-squares steps from the seed [m].
DAMPING = 0.05
#: Largest joint step of a least-squares or a return step [rad] (Euclidean norm).
STEP = 0.1
#: Steps of the least-squares sequence from the seed before it gives up.
WALK_STEPS = 2000
#: Position error below which a joint vector is on target [m].
ON_TARGET = 1e-10
#: Gauss-Newton steps back onto the target after a descent step.
RETURN_STEPS = 30
#: Damping of the return steps [m] (a guard at singularities only).
RETURN_DAMPING = 1e-4
#: Descent steps along the target's answers toward the seed.
DESCENT_STEPS = 40
#: The descent stops when the seed's pull projected on the answers is below this [rad].
SETTLED = 1e-6
#: Closed-form branches descended after the least-squares answer (nearest the seed first).
BRANCH_STARTS = 2

#: The closed form's branches of full poses: ``(position (3,), rotations (K, 3, 3), seed)`` ->
#: ``[(q, label), ...]`` (:meth:`~.closed_form_routes.ClosedFormRoutes.pose_candidates`).
PoseCandidates = Callable[[np.ndarray, np.ndarray, np.ndarray], list[tuple[np.ndarray, str]]]

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@dataclass(frozen=True)
class NearSeedAnswer:
    """The answer of :meth:`PositionNearSeed.solve`.

    Attributes:
        q: Joint vector [rad], on target and inside the limits.
        position_error: ``|p_fk(q) - p_target|`` [m], the judge's.
        start: Where its descent began: ``"damped least squares from the seed"`` or
            ``"branch '<closed form's label>'"`` (at the seed's tool rotation, or panned).
        steps: Least-squares, descent and return steps taken over every start.
    """

    q: np.ndarray
    position_error: float
    start: str
    steps: int


class PositionNearSeed:
    """The answer nearest the seed of a position target (module docstring).

    Args:
        robot: The robot (six revolute joints).
        candidates: The closed form's branches of full poses (:data:`PoseCandidates`).
    """

    def __init__(self, robot: RobotModel, candidates: PoseCandidates):
        self.robot = robot
        self.candidates = candidates
        self.lower = np.asarray(robot.lower, dtype=float)
        self.upper = np.asarray(robot.upper, dtype=float)
        base = np.asarray(robot.table.T_world_base, dtype=float)
        #: The first joint's axis and a point on it, world frame.
        self.axis, self.origin = base[:3, 2].copy(), base[:3, 3].copy()
        #: Sure upper bound of the tool's distance from the base origin [m].
        self.bound = reach_bound(robot)

    def solve(self, position: np.ndarray, seed: np.ndarray) -> NearSeedAnswer | None:
        """The answer nearest ``seed`` reaching ``position`` [m], or None when no start does.

        Args:
            position: Tool position (3,) [m], world frame, finite.
            seed: Joint vector (6,) [rad] inside the limits.
        """
        position = np.asarray(position, dtype=float)
        if math.hypot(*(position - self.origin).tolist()) > self.bound:
            return None  # surely beyond reach: no start gets there
        run = _Run(self, position, np.asarray(seed, dtype=float))
        best: tuple[float, np.ndarray, str] | None = None
        walked = run.walk()
        starts: list[tuple[np.ndarray, str]] = []
        if walked is not None:
            starts.append((walked, "damped least squares from the seed"))
        starts += self._branches(run)[:BRANCH_STARTS]
        for q0, label in starts:
            if best is not None and float(np.linalg.norm(q0 - run.seed)) > best[0] + math.pi:
                continue  # a branch far beyond the best answer: its descent will not win
            q = run.descend(q0)
            if q is None:
                continue
            distance = float(np.linalg.norm(q - run.seed))
            if best is None or distance < best[0]:
                best = (distance, q, label)
        if best is None:
            return None
        q = best[1]
        error, _ = run.judge.errors(q, run.position.tolist(), None)
        if not run.judge.within_limits(q.tolist()) or error > 1e3 * ON_TARGET:
            return None
        return NearSeedAnswer(q, error, best[2], run.steps)

    def _branches(self, run: _Run) -> list[tuple[np.ndarray, str]]:
        """The closed form's branches at the seed's tool rotation (and panned), nearest first."""
        pose = run.tool(run.seed)
        rotation = pose.rotation
        turn = _azimuth(self.axis, self.origin, pose.translation, run.position)
        rotations = np.stack([rotation, _about(self.axis, turn) @ rotation])
        found = []
        for q, label in self.candidates(run.position, rotations, run.seed):
            copy, inside = nearest_copies(q, run.seed, self.lower, self.upper)
            if bool(inside.all()):
                found.append((float(np.linalg.norm(copy - run.seed)), copy, f"branch '{label}'"))
        found.sort(key=lambda item: item[0])
        return [(q, label) for _, q, label in found]


class _Run:
    """One solve's Pinocchio data, target, seed and step count."""

    def __init__(self, near: PositionNearSeed, position: np.ndarray, seed: np.ndarray):
        self.judge = ToolJudge(near.robot)
        self.model, self.data, self.frame = self.judge.model, self.judge.data, self.judge.frame_id
        self.lower, self.upper = near.lower, near.upper
        self.position, self.seed = position, seed
        self.steps = 0

    def tool(self, q: np.ndarray) -> pin.SE3:
        """The tool pose at ``q`` (world frame)."""
        return self.judge.tool_pose(q)

    def error_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``p_target - p(q)`` [m] and the position rows (3, 6) of the tool Jacobian."""
        jacobian = pin.computeFrameJacobian(self.model, self.data, q, self.frame, _LWA)[:3]
        self.steps += 1
        return self.position - self.data.oMf[self.frame].translation, jacobian

    def _step(self, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        norm = float(np.linalg.norm(dq))
        if norm > STEP:
            dq = dq * (STEP / norm)
        return np.clip(q + dq, self.lower, self.upper)

    def walk(self) -> np.ndarray | None:
        """The damped least-squares step sequence from the seed; its end on target, or None."""
        return self._steps(self.seed.copy(), DAMPING, WALK_STEPS)

    def back_on_target(self, q: np.ndarray) -> np.ndarray | None:
        """Gauss-Newton steps from ``q`` onto the target; None when they do not get there."""
        return self._steps(q, RETURN_DAMPING, RETURN_STEPS)

    def _steps(self, q: np.ndarray, damping: float, count: int) -> np.ndarray | None:
        """Up to ``count`` damped least-squares steps (``damping`` [m]); the end on target or None."""
        regulariser = damping * damping * np.eye(3)
        for _ in range(count):
            error, jacobian = self.error_and_jacobian(q)
            if float(error @ error) < ON_TARGET * ON_TARGET:
                return q
            gram = jacobian @ jacobian.T + regulariser
            q = self._step(q, jacobian.T @ np.linalg.solve(gram, error))
        return None

    def descend(self, q: np.ndarray) -> np.ndarray | None:
        """From ``q`` along the target's answers toward the seed (module docstring)."""
        current = self.back_on_target(q)
        if current is None:
            return None
        distance = float(np.linalg.norm(current - self.seed))
        rate = 0.5
        for _ in range(DESCENT_STEPS):
            _, jacobian = self.error_and_jacobian(current)
            # A joint at a limit that the pull pushes outward stays there.
            pull = self.seed - current
            held = ((current <= self.lower) & (pull < 0)) | ((current >= self.upper) & (pull > 0))
            jacobian = jacobian * ~held
            pull = pull * ~held
            gram = jacobian @ jacobian.T + RETURN_DAMPING * RETURN_DAMPING * np.eye(3)
            along = pull - jacobian.T @ np.linalg.solve(gram, jacobian @ pull)
            if float(np.linalg.norm(along)) < SETTLED:
                break
            while rate > 1e-4:
                trial = self.back_on_target(np.clip(current + rate * along, self.lower, self.upper))
                if trial is not None and float(np.linalg.norm(trial - self.seed)) < distance:
                    current, rate = trial, min(1.0, 1.5 * rate)
                    distance = float(np.linalg.norm(trial - self.seed))
                    break
                rate *= 0.5
            else:
                break
        return current


def _azimuth(axis: np.ndarray, origin: np.ndarray, start: np.ndarray, end: np.ndarray) -> float:
    """The angle [rad] about ``axis`` (through ``origin``) from point ``start`` to ``end``."""
    a = start - origin
    b = end - origin
    a = a - axis * float(axis @ a)
    b = b - axis * float(axis @ b)
    return math.atan2(float(axis @ np.cross(a, b)), float(a @ b))


def _about(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation (3, 3) by ``angle`` [rad] about the unit ``axis``."""
    return np.asarray(pin.AngleAxis(angle, axis).toRotationMatrix())
