"""Four-joint arms: a base yaw, then three parallel pitch joints (AL5D, Orion5, many hobby arms).

Joint 1's axis ``n1`` is normal to the three parallel axes of joints 2-4 (direction ``n2`` at
``q1 = 0``). The base yaw turns the plane of the pitch chain about ``n1``; the chain itself is a
planar 3R (:class:`~.parallel_axes.ParallelAxes` of three joints). The tool point keeps its
offset ``h`` along ``n2`` from joint 1's axis, so:

1. the yaw ``phi = q1`` puts the target on the chain's plane: ``n2(phi) . (p - o1) = h`` with
   ``n2(phi) = cos(phi) n2 + sin(phi) (n1 x n2)``, two solutions (the arm reaching in front or
   over its back);
2. the target turned back by ``-phi`` about ``n1`` is a pose of the planar 3R: its yaw about
   ``n2`` (the approach pitch) and its wrist point give the two elbow branches.

Four branches. A pose whose approach leaves the arm's plane is projected: the candidates are
the nearest poses the arm reaches there, which the partial-pose solver
(:mod:`kin.ik.partial_pose`) measures and, when they miss, reports as the nearest pose.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
import pinocchio as pin

from dh2urdf import DHTable

from ...exceptions import StructureError
from ...target import PoseTarget
from .parallel_axes import PARALLEL_TOL, ParallelAxes, _axes


class YawPlanar:
    """Base yaw and three parallel pitch joints (see the module).

    Attributes:
        n1: Joint 1's axis in the world frame.
        o1: A point on it [m].
        n2: The pitch axes' direction at ``q1 = 0``.
        h: The tool point's offset along ``n2`` from joint 1's axis [m] (constant).
        chain: The planar 3R of joints 2-4 at ``q1 = 0``.
    """

    name: ClassVar[str] = "yaw_planar"
    dof: ClassVar[int] = 4
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    branch_labels: tuple[str, ...] = (
        "yaw 1, elbow left",
        "yaw 1, elbow right",
        "yaw 2, elbow left",
        "yaw 2, elbow right",
    )
    #: The candidates are the projection of a pose (see :class:`~.parallel_axes.ParallelAxes`).
    projects: ClassVar[bool] = True

    def __init__(self, table: DHTable):
        if table.dof != self.dof or any(row.joint_type != "revolute" for row in table.rows):
            raise StructureError(table.name, self.name, "not four revolute joints")
        directions, points, tool = _axes(table)
        n1 = directions[0] / np.linalg.norm(directions[0])
        n2 = directions[1] / np.linalg.norm(directions[1])
        if abs(float(n1 @ n2)) > PARALLEL_TOL:
            raise StructureError(
                table.name, self.name, "joint 2's axis is not normal to joint 1's (no base yaw)"
            )
        self.chain = ParallelAxes.from_axes(
            table.name, directions[1:], points[1:], tool, ["revolute"] * 3
        )  # raises when joints 2-4 are not parallel
        self.n1, self.o1, self.n2 = n1, points[0], n2
        self.side = np.cross(n1, n2)
        self.h = float((tool[:3, 3] - self.o1) @ n2)

    @classmethod
    def recognise(cls, table: DHTable) -> YawPlanar:
        """This structure when the table is a base yaw and three parallel pitch joints.

        Raises:
            StructureError: What does not fit.
        """
        return cls(table)

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The four branches (4, 4) ``q`` [rad] of the target's projection (NaN: none)."""
        out = np.full((4, 4), np.nan)
        if rotation is None:
            return out
        p = np.asarray(position, dtype=float) - self.o1
        if not float(np.abs(p).max()) < 1e150:
            return out
        a, b = float(self.n2 @ p), float(self.side @ p)
        rho = math.hypot(a, b)
        if rho < abs(self.h) - 1e-12 or rho < 1e-15:
            return out
        spread = math.acos(max(-1.0, min(1.0, self.h / rho)))
        centre = math.atan2(b, a)
        for k, phi in enumerate((centre - spread, centre + spread)):
            back = pin.exp3(self.n1 * -phi)
            branches = self.chain.solve(self.o1 + back @ p, back @ np.asarray(rotation))
            out[2 * k : 2 * k + 2, 0] = math.remainder(phi, 2.0 * math.pi)
            out[2 * k : 2 * k + 2, 1:] = branches
        return out

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets: (N, 4, 4)."""
        if rotations is None:
            return np.full((len(positions), 4, 4), np.nan)
        return np.array([self.solve(p, r) for p, r in zip(positions, rotations)])
