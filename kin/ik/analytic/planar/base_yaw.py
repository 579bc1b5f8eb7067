"""A base yaw over a chain of parallel pitch axes: the two yaws that put a point on its plane.

Joint 1's axis ``n1`` is normal to the pitch axes (direction ``n2`` at ``q1 = 0``). The base yaw
``phi = q1`` turns the plane of the pitch chain about ``n1``; the tool point keeps its offset
``h`` along ``n2`` from joint 1's axis, so ``n2(phi) . (p - o1) = h`` with
``n2(phi) = cos(phi) n2 + sin(phi) (n1 x n2)``: two yaws (the arm reaching in front or over its
back). Turned back by ``-phi`` about ``n1``, the point is one the pitch chain reaches at
``q1 = 0``. :class:`BaseYaw` holds that geometry for the ``yaw_planar`` arms
(:mod:`.yaw_planar`, :mod:`.yaw_roll`), in plain floats for one target.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable

from ...exceptions import StructureError
from ..closed_form_structure import BatchBranches
from ..per_target_batch import branches_of_each, solve_each
from .plane_chain import PARALLEL_TOL, joint_axes

#: A 3-vector as an array or plain floats.
Vector = Sequence[float] | np.ndarray
#: A 3-vector in plain floats.
Point = tuple[float, float, float]


def plane_yaws(p: Vector, n2: Vector, side: Vector, h: float) -> tuple[float, ...]:
    """The base yaws ``phi`` [rad] putting a point in the pitch chain's plane.

    Solves ``n2(phi) . p = h`` with ``n2(phi) = cos(phi) n2 + sin(phi) side``: two yaws (in
    front, over the back), none when the point is nearer the base axis than ``|h|``.

    Args:
        p: The point from a point of the base axis [m] (world).
        n2: The pitch axes' direction at ``phi = 0`` (normal to the base axis).
        side: ``n1 x n2``.
        h: The chain's offset along its pitch axes from the base axis [m].
    """
    x, y, z = (float(v) for v in p)
    if not (abs(x) < 1e150 and abs(y) < 1e150 and abs(z) < 1e150):
        return ()
    a = float(n2[0]) * x + float(n2[1]) * y + float(n2[2]) * z
    b = float(side[0]) * x + float(side[1]) * y + float(side[2]) * z
    rho = math.hypot(a, b)
    if rho < abs(h) - 1e-12 or rho < 1e-15:
        return ()
    spread = math.acos(max(-1.0, min(1.0, h / rho)))
    centre = math.atan2(b, a)
    return centre - spread, centre + spread


def turn(axis: Point, c: float, s: float, v: Point) -> Point:
    """``v`` turned about the unit ``axis`` by the angle of cosine ``c`` and sine ``s`` (Rodrigues)."""
    ax, ay, az = axis
    vx, vy, vz = v
    dot = (ax * vx + ay * vy + az * vz) * (1.0 - c)
    return (
        c * vx + s * (ay * vz - az * vy) + dot * ax,
        c * vy + s * (az * vx - ax * vz) + dot * ay,
        c * vz + s * (ax * vy - ay * vx) + dot * az,
    )


def dot(u: Sequence[float], v: Sequence[float]) -> float:
    """``u . v`` of two 3-vectors in plain floats."""
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def apply_rows(rows: Sequence[Sequence[float]], v: Sequence[float]) -> Point:
    """``R v`` of a rotation given as rows of plain floats."""
    return (dot(rows[0], v), dot(rows[1], v), dot(rows[2], v))


class BaseYaw:
    """A base yaw normal to the parallel pitch axes that follow it (see the module).

    Attributes:
        n1: Joint 1's axis in the world frame; ``o1`` a point on it [m].
        n2: The pitch axes' direction at ``q1 = 0``; ``side = n1 x n2``.
        h: The tool point's offset along ``n2`` from joint 1's axis [m] (constant).
        lower, upper: Joint limits [rad].
        offsets: DH angle offsets ``theta`` [rad].
    """

    name: ClassVar[str]
    dof: ClassVar[int] = 4
    branch_labels: tuple[str, ...] = (
        "yaw 1, elbow left",
        "yaw 1, elbow right",
        "yaw 2, elbow left",
        "yaw 2, elbow right",
    )
    #: The candidates are the projection of a pose on what the arm reaches.
    projects: ClassVar[bool] = True

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """Candidate joint vectors (B, 4) [rad] of one world target (the subclass's form)."""
        raise NotImplementedError

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets (N, 3) [m], rotations (N, 3, 3) or None: (N, B, dof)."""
        return solve_each(self, positions, rotations)

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """:meth:`solve_batch`; no elbow side (all False)."""
        return branches_of_each(self, positions, rotations)

    def _base_yaw(self, table: DHTable) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
        """Read the base yaw of a table of four revolute joints: its joint axes and tool.

        Raises:
            StructureError: Not four revolute joints, or joint 2's axis not normal to joint 1's.
        """
        if table.dof != self.dof or any(row.joint_type != "revolute" for row in table.rows):
            raise StructureError(table.name, self.name, "not four revolute joints")
        directions, points, tool = joint_axes(table)
        n1 = directions[0] / np.linalg.norm(directions[0])
        n2 = directions[1] / np.linalg.norm(directions[1])
        if abs(float(n1 @ n2)) > PARALLEL_TOL:
            raise StructureError(
                table.name, self.name, "joint 2's axis is not normal to joint 1's (no base yaw)"
            )
        self.n1, self.o1, self.n2 = n1, points[0], n2
        self.side = np.cross(n1, n2)
        self.h = float((tool[:3, 3] - self.o1) @ n2)
        self.lower = np.array([row.lower for row in table.rows])
        self.upper = np.array([row.upper for row in table.rows])
        self.offsets = tuple(row.theta for row in table.rows)
        # plain floats of the single-target path (:meth:`plane_points`)
        self._yaw_axes = tuple(tuple(v.tolist()) for v in (self.n1, self.o1, self.n2, self.side))
        return directions, points, tool

    def plane_points(self, position: Vector) -> list[tuple[float, Point, float, float]]:
        """Per base yaw, the point [m] turned back onto the chain's plane.

        Two tuples (in front, over the back; none when the point is too near the base axis):
        the yaw ``q1`` [rad] (wrapped), the turned point, and the cosine and sine of the turn
        back (``-q1``: :func:`turn` them onto a vector to bring it onto the plane too).
        """
        n1, o1, n2, side = self._yaw_axes
        p = (float(position[0]) - o1[0], float(position[1]) - o1[1], float(position[2]) - o1[2])
        out = []
        for phi in plane_yaws(p, n2, side, self.h):
            c, s = math.cos(phi), -math.sin(phi)
            tx, ty, tz = turn(n1, c, s, p)
            yaw = math.remainder(phi, 2.0 * math.pi)
            out.append((yaw, (o1[0] + tx, o1[1] + ty, o1[2] + tz), c, s))
        return out

    def turned_back(self, rotation: np.ndarray, c: float, s: float) -> list[list[float]]:
        """``R_world_tool`` turned back by a base yaw (:meth:`plane_points`' ``c, s``), as rows."""
        n1 = self._yaw_axes[0]
        columns = [turn(n1, c, s, column) for column in np.asarray(rotation).T.tolist()]
        return [[column[i] for column in columns] for i in range(3)]
