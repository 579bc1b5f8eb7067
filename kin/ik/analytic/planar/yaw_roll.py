"""Four-joint arms: a base yaw, two parallel pitch joints, a roll about the forearm (Kinova's 4-DOF).

Kinova's Mico and Jaco 4-DOF arms (``m1n4s200``, ``j2n4s300``): joint 1's axis ``n1`` is normal
to the two parallel axes of joints 2 and 3 (direction ``n2`` at ``q1 = 0``), joint 4 turns the
tool about an axis through the tool point. The tool point is set by joints 1-3 alone:

1. the base yaw ``q1`` puts the point on the pitch chain's plane
   (:meth:`~.base_yaw.BaseYaw.plane_points`, two yaws: in front or over the back);
2. the planar 2R of joints 2 and 3 (:class:`~.plane_chain.PlaneChain`) gives the two elbow
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

from dh2urdf import DHTable

from ...exceptions import StructureError
from ...targets.target import PoseTarget, PositionTarget, Target
from ..branches import Branches
from ..closed_form_structure import candidate_branches
from .base_yaw import BaseYaw, Point, apply_rows, dot, turn
from .plane_chain import PlaneChain

#: Largest distance [m] of the tool point from joint 4's axis.
ON_AXIS_TOL = 1e-9


class YawPlanarRoll(BaseYaw):
    """Base yaw, two parallel pitch joints, a roll through the tool point (see the module).

    Attributes:
        chain: The planar 2R of joints 2 and 3 to the tool point, at ``q1 = 0``.
        axes: The four joint axes' directions in the world at ``q = 0``.
        roll_basis: Two unit vectors normal to joint 4's axis (for the roll's angle).
        tool_rotation: ``R_world_tool`` at ``q = 0``.
        (the base yaw's: :class:`~.base_yaw.BaseYaw`)
    """

    name: ClassVar[str] = "yaw_planar_roll"
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget, PoseTarget)

    def __init__(self, table: DHTable):
        directions, points, tool = self._base_yaw(table)
        axes = [u / np.linalg.norm(u) for u in directions]
        tool_point = tool[:3, 3]
        off_axis = np.linalg.norm(np.cross(tool_point - points[3], axes[3]))
        if off_axis > ON_AXIS_TOL:
            raise StructureError(
                table.name,
                self.name,
                f"the tool point is {off_axis:.3g} m off joint 4's axis (expected on it: a roll)",
            )
        self.chain = PlaneChain(
            table.name, directions[1:3], points[1:3], tool, ["revolute"] * 2
        )  # raises when joints 2 and 3 are not parallel
        self.axes = axes
        helper = np.array([1.0, 0.0, 0.0]) if abs(axes[3][0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = np.cross(axes[3], helper)
        e1 /= np.linalg.norm(e1)
        self.roll_basis = (e1, np.cross(axes[3], e1))
        self.tool_rotation = tool[:3, :3]
        # Plain floats of :meth:`roll`: the axes of joints 2 and 3, the roll basis, and the
        # basis brought back through the tool's rotation at q = 0 (``R0^T e_j``).
        self._roll_axes = tuple(tuple(u.tolist()) for u in axes[1:3])
        self._basis = tuple(tuple(e.tolist()) for e in self.roll_basis)
        self._tool_basis = tuple(
            tuple((self.tool_rotation.T @ e).tolist()) for e in self.roll_basis
        )

    @classmethod
    def recognise(cls, table: DHTable) -> YawPlanarRoll:
        """This structure when the table is a base yaw, two pitch joints and a roll.

        Raises:
            StructureError: What does not fit.
        """
        return cls(table)

    def roll(self, q: np.ndarray | Sequence[float], rotation: np.ndarray) -> float:
        """The roll ``q4`` [rad] of a branch ``q[:3]`` nearest the rotation ``R_world_tool``.

        The angle about joint 4's axis of ``m = (R1 R2 R3)^T R R0^T``, from
        ``e_i . m e_j = (R3^T R2^T R1^T R R0^T e_j) . e_i`` in plain floats.
        """
        r = np.asarray(rotation, dtype=float).tolist()
        n1 = self._yaw_axes[0]
        c1, s1 = math.cos(q[0]), -math.sin(q[0])
        back = [self._back_turned(turn(n1, c1, s1, apply_rows(r, b)), q) for b in self._tool_basis]
        e1, e2 = self._basis
        return math.atan2(dot(e2, back[0]) - dot(e1, back[1]), dot(e1, back[0]) + dot(e2, back[1]))

    def _back_turned(self, v: Point, q: np.ndarray | Sequence[float]) -> Point:
        """``R3^T R2^T v`` at the branch's ``q2, q3`` [rad]."""
        (a2, a3) = self._roll_axes
        v = turn(a2, math.cos(q[1]), -math.sin(q[1]), v)
        return turn(a3, math.cos(q[2]), -math.sin(q[2]), v)

    def solve_roll(
        self, position: np.ndarray, rotation: np.ndarray | None, roll: float = 0.0
    ) -> np.ndarray:
        """The four branches (4, 4) ``q`` [rad]: ``q4`` from ``rotation``, else ``roll``."""
        out = np.full((4, 4), np.nan)
        for k, (yaw, point, _, _) in enumerate(self.plane_points(position)):
            for j, (q2, q3) in enumerate(self.chain.solve_chain(point, None)):
                if math.isnan(q2):
                    continue
                q4 = roll if rotation is None else self.roll((yaw, q2, q3), rotation)
                out[2 * k + j] = (yaw, q2, q3, q4)
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
