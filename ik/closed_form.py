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


#: Below this distance from the seed [rad] the copy of an angle nearest the seed is the one
#: :func:`_nearest_copy` picks when it is inside the limits (the others are ``2 pi`` further).
_FAST_COPY = math.pi - 1e-9


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


def _rows(matrix: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(row) for row in matrix.tolist())


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
        # Everything below depends only on the table: computed once, as floats and tuples, so that
        # a solve runs on the math module rather than on small NumPy arrays.
        self._kinds = self.target_kinds
        self._zero_seed = [0.0] * len(self._lower)
        # per joint: DH offset, lower bound with its slack, upper bound, raw limits (slow path)
        self._joints = tuple(
            (offset, lower - LIMIT_TOL, upper, lower, upper)
            for offset, lower, upper in zip(self._offsets, self._lower, self._upper)
        )
        # frame 0 from the world (3 x 4 rows), and the world from frame 0 (3 x 3 rows)
        self._base_rows = None if self._base is None else _rows(self._base[:3, :])
        self._world_rows = None if self._base is None else _rows(base[:3, :3])
        if isinstance(self.structure, FiveDof):
            self._approach_in_tool = tuple(self.structure.R_roll_tool[2, :].tolist())

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

    def _point_in_frame0(self, p: list[float]) -> list[float]:
        rows = self._base_rows
        if rows is None:
            return p
        x, y, z = p
        return [r[0] * x + r[1] * y + r[2] * z + r[3] for r in rows]

    def _rotation_in_frame0(self, r: list[list[float]]) -> list[list[float]]:
        rows = self._base_rows
        if rows is None:
            return r
        return [[b[0] * r[0][j] + b[1] * r[1][j] + b[2] * r[2][j] for j in range(3)] for b in rows]

    def _branches(self, target: Target, seed: list[float], p: list[float], r: list[list[float]] | None) -> Branches:
        """Branches for the target whose position (and rotation) in the world are ``p`` (``r``)."""
        structure, offsets = self.structure, self._offsets
        free_t1 = seed[0] + offsets[0]
        x, y, z = self._point_in_frame0(p)
        if isinstance(structure, Planar2R):
            return solve_planar2r(structure, x, y, z, free_t1=free_t1)
        if isinstance(structure, Offset3R):
            return solve_offset3r(structure, x, y, z, free_t1=free_t1)
        if r is not None:
            return solve_pose(structure, (x, y, z), self._rotation_in_frame0(r), free_t1=free_t1)
        roll = seed[4] if target.roll is None else target.roll  # type: ignore[union-attr]
        return solve_pitch(structure, (x, y, z), target.pitch, roll + offsets[4], free_t1=free_t1)  # type: ignore[union-attr]

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
        if not isinstance(target, self._kinds):
            kinds = " or ".join(kind.__name__ for kind in self._kinds)
            raise TargetError(
                f"'{self.robot.name}' ({self.name}) takes a {kinds}, got a {type(target).__name__}"
            )
        nq = len(self._lower)
        if seed is None:
            seed_list = self._zero_seed
        else:
            seed_list = np.asarray(seed, dtype=float).reshape(-1).tolist()
            if len(seed_list) != nq:
                raise TargetError(f"the seed of '{self.robot.name}' must have {nq} values, got {len(seed_list)}")
            if not all(math.isfinite(v) for v in seed_list):
                raise TargetError(f"the seed must be finite, got {seed_list}")
        if not target.finite:
            return self._failure("invalid_target", "the target has a NaN or infinite value", start)
        p = target.position.tolist()
        r = target.rotation.tolist() if isinstance(target, PoseTarget) else None
        branches = self._branches(target, seed_list, p, r)
        if branches.status == "out_of_reach":
            return self._failure("out_of_reach", branches.message, start, branches.gap)
        valid, rejected = self._verify(target, branches, seed_list, p, r)
        if len(valid) > 1:
            valid.sort(key=_first)
        solutions = tuple([solution for _, solution in valid])
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

    def _approach(self, target: PitchTarget, seed: list[float], p: list[float]) -> tuple[float, float, float]:
        """The target's approach axis in the world frame."""
        p0 = self._point_in_frame0(p)
        rho = math.hypot(p0[0], p0[1])
        angle = math.atan2(p0[1], p0[0]) if rho > 0.0 else seed[0] + self._offsets[0]
        cp = math.cos(target.pitch)
        a = (cp * math.cos(angle), cp * math.sin(angle), -math.sin(target.pitch))
        rows = self._world_rows
        if rows is None:
            return a
        return tuple(row[0] * a[0] + row[1] * a[1] + row[2] * a[2] for row in rows)  # type: ignore[return-value]

    def _verify(
        self, target: Target, branches: Branches, seed: list[float], p: list[float], r: list[list[float]] | None
    ) -> tuple[list[tuple[float, IKSolution]], list[IKSolution]]:
        """Per branch: the joint vector, its Pinocchio FK errors, and where it goes (valid, rejected, dropped)."""
        model, data, frame = self._model, self._data, self._frame
        joints = self._joints
        forward, update, array = pin.forwardKinematics, pin.updateFramePlacement, np.array
        sqrt, asin, fast = math.sqrt, math.asin, _FAST_COPY
        tol_p, tol_r = self.tolerance_position, self.tolerance_rotation
        px, py, pz = p
        pitch = isinstance(target, PitchTarget)
        if r is not None:
            (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = r
        elif pitch:
            ax, ay, az = self._approach(target, seed, p)  # type: ignore[arg-type]
            tx, ty, tz = self._approach_in_tool
        valid: list[tuple[float, IKSolution]] = []
        rejected: list[IKSolution] = []
        for thetas, label in branches.thetas:
            q_list = []
            inside = True
            distance = 0.0
            for theta, s, (offset, lower_tol, upper, lower, upper_raw) in zip(thetas, seed, joints):
                value = theta - offset
                # the copy nearest the seed, if inside the limits; else search (see _nearest_copy)
                base = value - TWO_PI * round((value - s) / TWO_PI)
                d = base - s
                if -fast < d < fast and lower_tol - base <= 0.0 and base - upper - LIMIT_TOL <= 0.0:
                    value = base
                else:
                    value, ok = _nearest_copy(value, s, lower, upper_raw)
                    inside = inside and ok
                    d = value - s
                q_list.append(value)
                distance += d * d
            q = array(q_list)
            forward(model, data, q)
            h0, h1, h2, _ = update(model, data, frame).homogeneous.tolist()
            ex, ey, ez = h0[3] - px, h1[3] - py, h2[3] - pz
            position_error = sqrt(ex * ex + ey * ey + ez * ez)
            if r is not None:
                # |R_fk - R_target|_F = 2 sqrt(2) sin(angle / 2): accurate for small angles
                d0, d1, d2 = h0[0] - r00, h0[1] - r01, h0[2] - r02
                d3, d4, d5 = h1[0] - r10, h1[1] - r11, h1[2] - r12
                d6, d7, d8 = h2[0] - r20, h2[1] - r21, h2[2] - r22
                squares = d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3 + d4 * d4 + d5 * d5 + d6 * d6 + d7 * d7 + d8 * d8
                rotation_error = 2.0 * asin(min(1.0, sqrt(squares / 8.0)))
            elif pitch:
                ux = h0[0] * tx + h0[1] * ty + h0[2] * tz
                uy = h1[0] * tx + h1[1] * ty + h1[2] * tz
                uz = h2[0] * tx + h2[1] * ty + h2[2] * tz
                cx, cy, cz = uy * az - uz * ay, uz * ax - ux * az, ux * ay - uy * ax
                rotation_error = math.atan2(sqrt(cx * cx + cy * cy + cz * cz), ux * ax + uy * ay + uz * az)
            else:
                rotation_error = 0.0
            solution = IKSolution(q, label, inside, position_error, rotation_error)
            if position_error > tol_p or rotation_error > tol_r:
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


def _first(pair: tuple[float, IKSolution]) -> float:
    return pair[0]
