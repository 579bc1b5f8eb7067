"""Closed-form IK solver of a small arm: every branch, limits, Pinocchio verification, ordering.

:class:`ClosedFormSolver` recognises the arm's structure from its DH table
(:mod:`ik.structure`), computes every branch with the matching solver (:mod:`ik.planar2r`,
:mod:`ik.offset3r`, :mod:`ik.five_dof`), then, per branch:

1. brings each angle to the ``2 pi`` copy inside the joint limits closest to the seed (angles are
   compared modulo ``2 pi`` where the limits allow);
2. measures the tool pose of the joint vector with Pinocchio (position error [m], rotation error
   [rad]: the angle of ``R_fk^T R_target`` for pose targets, the angle between the approach axes
   for pitch targets, 0 for position targets);
3. keeps it as valid (within limits, on target), rejected (on target, outside limits) or drops it
   (off target: never returned, logged).

Valid solutions are ordered by Euclidean distance to the seed.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import RobotModel

from .branches import Branches
from .exceptions import TargetError
from .five_dof import solve_pitch, solve_pose
from .offset3r import solve_offset3r
from .planar2r import solve_planar2r
from .result import IKResult, IKSolution
from .structure import FiveDof, Offset3R, Planar2R, Structure, recognise
from .target import PitchTarget, PoseTarget, PositionTarget, Target

logger = logging.getLogger(__name__)

TWO_PI = 2.0 * math.pi
#: Slack on the joint limits [rad] for angles computed exactly at a limit.
LIMIT_TOL = 1e-10


def _nearest_copy(value: float, seed: float, lower: float, upper: float) -> tuple[float, bool]:
    """The ``value + 2 pi k`` inside ``[lower, upper]`` closest to ``seed``, else the least outside."""
    base = value - TWO_PI * round((value - seed) / TWO_PI)
    best, best_key = base, (math.inf, math.inf)
    for candidate in (base, base - TWO_PI, base + TWO_PI, base - 2 * TWO_PI, base + 2 * TWO_PI):
        violation = max(lower - LIMIT_TOL - candidate, candidate - upper - LIMIT_TOL, 0.0)
        key = (violation, abs(candidate - seed))
        if key < best_key:
            best, best_key = candidate, key
    return best, best_key[0] == 0.0


class ClosedFormSolver:
    """Every closed-form IK branch of one small arm, verified with Pinocchio.

    Args:
        robot: The loaded robot (its table must fit one of the structures of :mod:`ik.structure`).
        tolerance_position: Largest position error of a returned solution [m].
        tolerance_rotation: Largest rotation error of a returned solution [rad].

    Raises:
        StructureError: The table does not fit a closed-form solver.
    """

    def __init__(self, robot: RobotModel, tolerance_position: float = 1e-9, tolerance_rotation: float = 1e-9):
        self.robot = robot
        self.structure: Structure = recognise(robot.table)
        self.name = f"closed_form:{type(self.structure).__name__.lower()}"
        self.tolerance_position = tolerance_position
        self.tolerance_rotation = tolerance_rotation
        self._model = robot.model
        self._data = robot.model.createData()
        self._frame = robot.model.getFrameId(robot.tool_frame)
        self._lower = robot.model.lowerPositionLimit.tolist()
        self._upper = robot.model.upperPositionLimit.tolist()
        self._offsets = [row.theta for row in robot.table.rows]
        base = np.asarray(robot.table.T_world_base, dtype=float)
        self._base = None if np.allclose(base, np.eye(4), atol=0.0) else np.linalg.inv(base)
        if isinstance(self.structure, FiveDof):
            self._approach_in_tool = self.structure.R_roll_tool[2, :].tolist()

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """The target classes this solver accepts."""
        if isinstance(self.structure, FiveDof):
            return (PoseTarget, PitchTarget)
        return (PositionTarget,)

    def _failure(self, status: str, message: str, start: float, gap: float | None = None) -> IKResult:
        return IKResult(
            success=False,
            solver=self.name,
            status=status,  # type: ignore[arg-type]
            message=message,
            distance_to_workspace=gap,
            time=time.perf_counter() - start,
        )

    def _in_frame0(self, position: np.ndarray, rotation: np.ndarray | None) -> tuple[list[float], list[list[float]] | None]:
        if self._base is None:
            return position.tolist(), None if rotation is None else rotation.tolist()
        p = self._base[:3, :3] @ position + self._base[:3, 3]
        r = None if rotation is None else (self._base[:3, :3] @ rotation).tolist()
        return p.tolist(), r

    def _branches(self, target: Target, seed: list[float]) -> Branches:
        structure, offsets = self.structure, self._offsets
        free_t1 = seed[0] + offsets[0]
        if isinstance(structure, Planar2R):
            p, _ = self._in_frame0(target.position, None)
            return solve_planar2r(structure, *p, free_t1=free_t1)
        if isinstance(structure, Offset3R):
            p, _ = self._in_frame0(target.position, None)
            return solve_offset3r(structure, *p, free_t1=free_t1)
        if isinstance(target, PoseTarget):
            p, r = self._in_frame0(target.position, target.rotation)
            return solve_pose(structure, tuple(p), r, free_t1=free_t1)
        p, _ = self._in_frame0(target.position, None)
        roll = seed[4] if target.roll is None else target.roll
        return solve_pitch(structure, tuple(p), target.pitch, roll + offsets[4], free_t1=free_t1)

    def solve(self, target: Target, seed: npt.ArrayLike | None = None) -> IKResult:
        """Every branch reaching ``target``, valid ones ordered by distance to ``seed``.

        Args:
            target: A :class:`PositionTarget` (planar 2R, offset 3R), :class:`PoseTarget` or
                :class:`PitchTarget` (five-joint arms), in the world frame.
            seed: Current joint vector [rad] (zeros if None): the order of the solutions and the
                ``2 pi`` copy of each angle; also the value of a free joint at a singularity.

        Returns:
            The result; never raises for unreachable, singular or non-finite targets.

        Raises:
            TargetError: The target kind does not fit the arm, or the seed has the wrong size.
        """
        start = time.perf_counter()
        if not isinstance(target, self.target_kinds):
            kinds = " or ".join(kind.__name__ for kind in self.target_kinds)
            raise TargetError(
                f"'{self.robot.name}' ({self.name}) takes a {kinds}, got a {type(target).__name__}"
            )
        nq = len(self._lower)
        if seed is None:
            seed_list = [0.0] * nq
        else:
            seed_list = np.asarray(seed, dtype=float).reshape(-1).tolist()
            if len(seed_list) != nq:
                raise TargetError(f"the seed of '{self.robot.name}' must have {nq} values, got {len(seed_list)}")
            if not all(math.isfinite(v) for v in seed_list):
                raise TargetError(f"the seed must be finite, got {seed_list}")
        if not target.finite:
            return self._failure("invalid_target", "the target has a NaN or infinite value", start)
        branches = self._branches(target, seed_list)
        if branches.status == "out_of_reach":
            return self._failure("out_of_reach", branches.message, start, branches.gap)
        valid, rejected = self._verify(target, branches, seed_list)
        valid.sort(key=lambda pair: pair[0])
        solutions = tuple(solution for _, solution in valid)
        rejected_solutions = tuple(rejected)
        if solutions:
            status, message = branches.status, branches.message or f"{len(solutions)} valid solution(s)"
        elif rejected_solutions:
            status = "outside_limits"
            message = f"reachable only outside the joint limits ({len(rejected_solutions)} branch(es))"
        else:
            status, message = "singular", branches.message or "no branch verified on target"
        return IKResult(
            success=bool(solutions),
            solver=self.name,
            status=status,
            message=message,
            solutions=solutions,
            rejected=rejected_solutions,
            time=time.perf_counter() - start,
        )

    def _verify(
        self, target: Target, branches: Branches, seed: list[float]
    ) -> tuple[list[tuple[float, IKSolution]], list[IKSolution]]:
        model, data, frame = self._model, self._data, self._frame
        lower, upper, offsets = self._lower, self._upper, self._offsets
        px, py, pz = target.position.tolist()
        if isinstance(target, PoseTarget):
            r_target = target.rotation.ravel()
        elif isinstance(target, PitchTarget):
            p0, _ = self._in_frame0(target.position, None)
            rho = math.hypot(p0[0], p0[1])
            angle = math.atan2(p0[1], p0[0]) if rho > 0.0 else seed[0] + offsets[0]
            cp = math.cos(target.pitch)
            approach = np.array([cp * math.cos(angle), cp * math.sin(angle), -math.sin(target.pitch)])
            if self._base is not None:
                approach = np.linalg.solve(self._base[:3, :3], approach)
        valid: list[tuple[float, IKSolution]] = []
        rejected: list[IKSolution] = []
        for thetas, label in branches.thetas:
            q_list = []
            inside = True
            distance = 0.0
            for i, theta in enumerate(thetas):
                value, ok = _nearest_copy(theta - offsets[i], seed[i], lower[i], upper[i])
                q_list.append(value)
                inside = inside and ok
                distance += (value - seed[i]) ** 2
            q = np.array(q_list)
            pin.forwardKinematics(model, data, q)
            placement = pin.updateFramePlacement(model, data, frame)
            ex, ey, ez = (placement.translation - target.position).tolist()
            position_error = math.sqrt(ex * ex + ey * ey + ez * ez)
            if isinstance(target, PoseTarget):
                diff = placement.rotation.ravel() - r_target
                rotation_error = 2.0 * math.asin(min(1.0, math.sqrt(float(diff @ diff) / 8.0)))
            elif isinstance(target, PitchTarget):
                ux, uy, uz = (placement.rotation @ self._approach_in_tool).tolist()
                ax, ay, az = approach.tolist()
                cx, cy, cz = uy * az - uz * ay, uz * ax - ux * az, ux * ay - uy * ax
                rotation_error = math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), ux * ax + uy * ay + uz * az)
            else:
                rotation_error = 0.0
            solution = IKSolution(q, label, inside, position_error, rotation_error)
            if position_error > self.tolerance_position or rotation_error > self.tolerance_rotation:
                logger.warning(
                    "%s: branch '%s' misses the target by %.3g m, %.3g rad; dropped",
                    self.robot.name, label, position_error, rotation_error,
                )
                continue
            if inside:
                valid.append((distance, solution))
            else:
                rejected.append(solution)
        return valid, rejected
