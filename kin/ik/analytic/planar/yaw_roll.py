"""Four-joint arms: a base yaw, two parallel pitch joints, a roll about the forearm (Kinova's 4-DOF).

Kinova's Mico and Jaco 4-DOF arms (``m1n4s200``, ``j2n4s300``): joint 1's axis ``n1`` is normal
to the two parallel axes of joints 2 and 3 (direction ``n2`` at ``q1 = 0``), joint 4 turns the
tool about an axis through the tool point. The tool point is set by joints 1-3 alone:

1. the base yaw ``q1`` puts the point on the pitch chain's plane
   (:func:`~.yaw_planar.plane_yaws`, two yaws: in front or over the back);
2. the planar 2R of joints 2 and 3 (:class:`~.parallel_axes.ParallelAxes`) gives the two elbow
   branches of each;
3. the roll ``q4``: a position leaves it free (the seed's value, stated in the labels); a pose
   gives it as the angle about joint 4's axis of ``(R1 R2 R3)^T R_target R0^T`` (product of
   exponentials at ``q = 0``), the nearest roll when the pose asks for an approach axis the
   branch does not have.

Four branches. A pose fixes four of the arm's values and asks six: the candidates are its
projection on what the arm reaches, measured on the whole pose by the solver
(``projects``, as :class:`~.yaw_planar.YawPlanar`'s); on a reachable pose usually one branch
has the target's approach axis.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
import pinocchio as pin

from dh2urdf import DHTable

from ...exceptions import StructureError
from ...target import PoseTarget, PositionTarget, Target
from ..branches import Branches
from ..closed_form_structure import BatchBranches, candidate_branches
from .parallel_axes import PARALLEL_TOL, ParallelAxes, _axes
from .yaw_planar import plane_yaws

#: Largest distance [m] of the tool point from joint 4's axis.
ON_AXIS_TOL = 1e-9


class YawPlanarRoll:
    """Base yaw, two parallel pitch joints, a roll through the tool point (see the module).

    Attributes:
        n1: Joint 1's axis in the world frame; ``o1`` a point on it [m].
        n2: The pitch axes' direction at ``q1 = 0``; ``side = n1 x n2``.
        h: The tool point's offset along ``n2`` from joint 1's axis [m] (constant).
        chain: The planar 2R of joints 2 and 3 to the tool point, at ``q1 = 0``.
        axes: The four joint axes' directions in the world at ``q = 0``.
        roll_basis: Two unit vectors normal to joint 4's axis (for the roll's angle).
        tool_rotation: ``R_world_tool`` at ``q = 0``.
        offsets: DH angle offsets ``theta`` [rad].
    """

    name: ClassVar[str] = "yaw_planar_roll"
    dof: ClassVar[int] = 4
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget, PoseTarget)
    branch_labels: tuple[str, ...] = (
        "yaw 1, elbow left",
        "yaw 1, elbow right",
        "yaw 2, elbow left",
        "yaw 2, elbow right",
    )
    #: The candidates are the projection of a pose on what the arm reaches.
    projects: ClassVar[bool] = True

    def __init__(self, table: DHTable):
        if table.dof != self.dof or any(row.joint_type != "revolute" for row in table.rows):
            raise StructureError(table.name, self.name, "not four revolute joints")
        directions, points, tool = _axes(table)
        axes = [u / np.linalg.norm(u) for u in directions]
        n1, n2 = axes[0], axes[1]
        if abs(float(n1 @ n2)) > PARALLEL_TOL:
            raise StructureError(
                table.name, self.name, "joint 2's axis is not normal to joint 1's (no base yaw)"
            )
        tool_point = tool[:3, 3]
        off_axis = np.linalg.norm(np.cross(tool_point - points[3], axes[3]))
        if off_axis > ON_AXIS_TOL:
            raise StructureError(
                table.name,
                self.name,
                f"the tool point is {off_axis:.3g} m off joint 4's axis (expected on it: a roll)",
            )
        self.chain = ParallelAxes.from_axes(
            table.name, directions[1:3], points[1:3], tool, ["revolute"] * 2
        )  # raises when joints 2 and 3 are not parallel
        self.n1, self.o1, self.n2 = n1, points[0], n2
        self.side = np.cross(n1, n2)
        self.h = float((tool_point - self.o1) @ n2)
        self.axes = axes
        helper = np.array([1.0, 0.0, 0.0]) if abs(axes[3][0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = np.cross(axes[3], helper)
        e1 /= np.linalg.norm(e1)
        self.roll_basis = (e1, np.cross(axes[3], e1))
        self.tool_rotation = tool[:3, :3]
        self.offsets = tuple(row.theta for row in table.rows)

    @classmethod
    def recognise(cls, table: DHTable) -> YawPlanarRoll:
        """This structure when the table is a base yaw, two pitch joints and a roll.

        Raises:
            StructureError: What does not fit.
        """
        return cls(table)

    def roll(self, q: np.ndarray, rotation: np.ndarray) -> float:
        """The roll ``q4`` [rad] of a branch ``q[:3]`` nearest the rotation ``R_world_tool``."""
        r123 = np.eye(3)
        for axis, angle in zip(self.axes[:3], q[:3]):
            r123 = r123 @ pin.exp3(axis * angle)
        m = r123.T @ rotation @ self.tool_rotation.T
        e1, e2 = self.roll_basis
        return math.atan2(e2 @ m @ e1 - e1 @ m @ e2, e1 @ m @ e1 + e2 @ m @ e2)

    def solve_roll(
        self, position: np.ndarray, rotation: np.ndarray | None, roll: float = 0.0
    ) -> np.ndarray:
        """The four branches (4, 4) ``q`` [rad]: ``q4`` from ``rotation``, else ``roll``."""
        out = np.full((4, 4), np.nan)
        p = np.asarray(position, dtype=float) - self.o1
        for k, phi in enumerate(plane_yaws(p, self.n2, self.side, self.h)):
            back = pin.exp3(self.n1 * -phi)
            rows = out[2 * k : 2 * k + 2]
            rows[:, 0] = math.remainder(phi, 2.0 * math.pi)
            rows[:, 1:3] = self.chain.solve(self.o1 + back @ p, None)
            for row in rows:
                if not np.isnan(row[1]):
                    row[3] = roll if rotation is None else self.roll(row, rotation)
        return out

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The four branches (4, 4) ``q`` [rad] of a pose's projection, or a position (``q4 = 0``)."""
        rotation = None if rotation is None else np.asarray(rotation, dtype=float)
        return self.solve_roll(position, rotation)

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """The branches (DH angles) of a pose's projection, or a position with the seed's roll."""
        if isinstance(target, PoseTarget):
            return candidate_branches(
                self, self.solve(target.position, target.rotation), self.offsets
            )
        q = self.solve_roll(target.position, None, float(seed[3]))
        branches = candidate_branches(self, q, self.offsets)
        branches.thetas = [
            (t, f"{label}, joint 4 free: the seed's value") for t, label in branches.thetas
        ]
        return branches

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """:meth:`solve_batch`; no elbow side (all False)."""
        q = self.solve_batch(positions, rotations)
        return BatchBranches(q, np.zeros(q.shape[:2], dtype=bool))

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets: (N, 4, 4)."""
        if rotations is None:
            return np.array([self.solve(p, None) for p in positions]).reshape(-1, 4, 4)
        return np.array([self.solve(p, r) for p, r in zip(positions, rotations)]).reshape(-1, 4, 4)
