"""Batched closed-form IK: N targets at once, every branch, vectorized with NumPy over N.

The registered structure's batched solve (:mod:`.closed_form_structure`: the solver knows no
structure by name) gives the candidates; each angle goes to its ``2 pi`` copy inside the limits
nearest the target's seed (zero without one), the rule of the single call
(:func:`kin.ik.limit_rule.nearest_copies`); the batched judge (:func:`kin.ik.judge.batch_pose_errors`
on :func:`kin.batch_forward_kinematics`, not Pinocchio) measures them. The per-call API
(:class:`~.closed_form.ClosedFormSolver`) verifies with Pinocchio, and the tests check that the
two agree.

Branches come in a fixed order, :attr:`BatchResult.branch_names` (the structure's
``branch_labels``). A free joint at a singularity is set to 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from kin import RobotModel, batch_forward_kinematics

from ..exceptions import TargetError
from ..judge import batch_axis_errors, batch_pose_errors
from ..limit_rule import nearest_copies
from ..targets.target import PitchTarget, PoseTarget, PositionTarget
from .closed_form_structure import BatchBranches, DetailedStructure, PitchStructure
from .joint_directions import forward_table, mirrored_limits, reversed_joints, to_joint
from .registry import recognise_turned


@dataclass(frozen=True, eq=False)
class BatchResult:
    """All branches of N targets.

    Attributes:
        branch_names: Meaning of each of the B branch columns.
        q: Joint vectors (N, B, nq) [rad]; NaN where a branch does not exist.
        reached: (N, B) the branch exists and FK reproduces the target within the tolerances.
        within_limits: (N, B) the joint vector is inside the limits.
        elbow_up: (N, B) the elbow is above the line from shoulder to wrist (world z); for the
            planar arm, on the counter-clockwise side of the line from base to target.
        position_error: (N, B) [m], NumPy FK.
        rotation_error: (N, B) [rad] (pose: angle of ``R_fk^T R``; pitch: between approach axes).
    """

    branch_names: tuple[str, ...]
    q: np.ndarray
    reached: np.ndarray
    within_limits: np.ndarray
    elbow_up: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """(N, B) reached and within limits."""
        return self.reached & self.within_limits


#: Targets per vectorized chunk (arrays stay in cache).
CHUNK = 8192


def _chunked(solve, n: int, *arrays: np.ndarray) -> BatchResult:  # noqa: ANN001
    """Run ``solve`` on slices of at most :data:`CHUNK` targets and join the results."""
    if n <= CHUNK:
        return solve(*arrays)
    parts = [solve(*(a[i : i + CHUNK] for a in arrays)) for i in range(0, n, CHUNK)]
    first = parts[0]
    return BatchResult(
        first.branch_names,
        *(
            np.concatenate([getattr(r, f) for r in parts])
            for f in (
                "q",
                "reached",
                "within_limits",
                "elbow_up",
                "position_error",
                "rotation_error",
            )
        ),
    )


class BatchSolver:
    """Vectorized closed-form IK of one arm whose table fits a registered structure.

    Args:
        robot: The loaded robot.
        tolerance_position: Largest position error of a reached branch [m].
        tolerance_rotation: Largest rotation error of a reached branch [rad].

    Raises:
        StructureError: The table fits no closed form.
    """

    def __init__(
        self, robot: RobotModel, tolerance_position: float = 1e-9, tolerance_rotation: float = 1e-9
    ):
        self.robot = robot
        self.table = robot.table
        # A reversed joint (direction = -1): the structure solves the forward table in
        # q' = direction * q, wrapped into its mirrored limits; q goes to the judge.
        # Antiparallel axes turned over where that fits a structure (registry.recognise_turned):
        # q' = -q on those joints too.
        self._directions = reversed_joints(robot.table)
        self.structure, _, flips = recognise_turned(forward_table(robot.table))
        if flips is not None:
            self._directions = flips if self._directions is None else self._directions * flips
        self.tolerance_position = tolerance_position
        self.tolerance_rotation = tolerance_rotation
        self._lower, self._upper = robot.lower, robot.upper
        if self._directions is not None:
            self._lower, self._upper = mirrored_limits(self._lower, self._upper, self._directions)

    def _seeds(self, seeds: npt.ArrayLike | None, n: int) -> np.ndarray:
        """The seeds as (n, nq) [rad] (None: zero).

        Raises:
            TargetError: The seeds are neither (n, nq) nor (nq,), or not finite.
        """
        nq = len(self._lower)
        if seeds is None:
            return np.zeros((n, nq))
        values = np.asarray(seeds, dtype=float)
        if values.shape == (nq,):
            values = np.broadcast_to(values, (n, nq))
        if values.shape != (n, nq) or not np.isfinite(values).all():
            raise TargetError(
                f"the seeds of '{self.robot.name}' must be finite, ({n}, {nq}) or ({nq},); "
                f"got shape {values.shape}"
            )
        return values

    def _wrap(self, q: np.ndarray, seeds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each angle of ``q'`` (N, B, nq) into the limits nearest its target's seed (N, nq).

        ``q'`` and the limits are the structure's (``q' = direction * q``), the seeds the arm's.
        """
        if self._directions is not None:
            seeds = seeds * self._directions
        q, inside = nearest_copies(q, seeds[:, None, :], self._lower, self._upper)
        return q, np.asarray(inside.all(axis=-1))

    def _require(self, kind: type, instead: str) -> None:
        if kind not in self.structure.target_kinds:
            raise TargetError(
                f"'{self.robot.name}' ({self.structure.name}) does not take "
                f"{kind.__name__}s in closed form: use {instead}"
            )

    def _instead(self) -> str:
        kinds = self.structure.target_kinds
        methods = {PositionTarget: "solve_positions", PoseTarget: "solve_poses"}
        methods[PitchTarget] = "solve_pitch"
        return " or ".join(methods[k] for k in kinds if k in methods)

    def _candidates(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        structure = self.structure
        if isinstance(structure, DetailedStructure):
            return structure.batch_branches(positions, rotations)
        q = structure.solve_batch(positions, rotations)
        return BatchBranches(q, np.zeros(q.shape[:2], dtype=bool))

    def solve_positions(
        self, positions: npt.ArrayLike, seeds: npt.ArrayLike | None = None
    ) -> BatchResult:
        """All branches for N tool points (N, 3) [m] (a structure that takes positions).

        ``seeds`` (N, nq) or (nq,) [rad]: each angle goes to its copy inside the limits nearest
        its target's seed (None: zero), as :class:`~.closed_form.ClosedFormSolver` moves it.
        """
        self._require(PositionTarget, self._instead())
        p = np.asarray(positions, dtype=float).reshape(-1, 3)
        start = self._seeds(seeds, p.shape[0])
        if p.shape[0] > CHUNK:
            return _chunked(self.solve_positions, p.shape[0], p, start)
        return self._finish(self._candidates(p, None), p, None, start)

    def solve_poses(self, poses: npt.ArrayLike, seeds: npt.ArrayLike | None = None) -> BatchResult:
        """All branches for N tool poses ``T_world_tool`` (N, 4, 4) (a structure that takes poses).

        ``seeds``: as in :meth:`solve_positions`.
        """
        self._require(PoseTarget, self._instead())
        T = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
        start = self._seeds(seeds, T.shape[0])
        if T.shape[0] > CHUNK:
            return _chunked(self.solve_poses, T.shape[0], T, start)
        p, rotation = T[:, :3, 3], T[:, :3, :3]
        return self._finish(self._candidates(p, rotation), p, rotation, start)

    def solve_pitch(
        self, positions: npt.ArrayLike, pitch: npt.ArrayLike, roll: npt.ArrayLike = 0.0
    ) -> BatchResult:
        """All branches for N tool points (N, 3) with approach pitch [rad] and wrist roll q5 [rad]."""
        self._require(PitchTarget, self._instead())
        structure = self.structure
        assert isinstance(structure, PitchStructure)
        p = np.asarray(positions, dtype=float).reshape(-1, 3)
        n = p.shape[0]
        pitch = np.broadcast_to(np.asarray(pitch, dtype=float), (n,))
        roll = np.broadcast_to(np.asarray(roll, dtype=float), (n,))
        if n > CHUNK:
            return _chunked(self.solve_pitch, n, p, pitch, roll)
        start = self._seeds(None, n)
        return self._finish(structure.pitch_batch_branches(p, pitch, roll), p, None, start)

    def _finish(
        self,
        candidates: BatchBranches,
        p: np.ndarray,
        rotation: np.ndarray | None,
        seeds: np.ndarray,
    ) -> BatchResult:
        n, b, nq = candidates.q.shape
        exists = ~np.isnan(candidates.q).any(-1)
        q, inside = self._wrap(candidates.q, seeds)
        if self._directions is not None:
            q = to_joint(q, self._directions)
        poses = batch_forward_kinematics(self.table, q.reshape(-1, nq))
        positions = np.repeat(p, b, axis=0)
        rotations = None if rotation is None else np.repeat(rotation, b, axis=0)
        position_error, rotation_error = batch_pose_errors(poses, positions, rotations)
        if candidates.approach is not None:
            structure = self.structure
            assert isinstance(structure, PitchStructure)  # a pitch target
            axes = poses[:, :3, :3] @ np.asarray(structure.approach_in_tool)
            rotation_error = batch_axis_errors(axes, np.repeat(candidates.approach, b, axis=0))
        position_error = position_error.reshape(n, b)
        if rotation_error is None:
            rotation_error = np.zeros((n, b))
        else:
            rotation_error = rotation_error.reshape(n, b)
        with np.errstate(invalid="ignore"):
            reached = (
                exists
                & (position_error <= self.tolerance_position)
                & (rotation_error <= self.tolerance_rotation)
            )
        return BatchResult(
            tuple(self.structure.branch_labels),
            q,
            reached,
            inside & exists,
            candidates.elbow_up,
            position_error,
            rotation_error,
        )
