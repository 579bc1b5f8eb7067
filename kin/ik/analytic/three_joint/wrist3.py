"""Three revolute joints whose axes meet at one point: a wrist alone (Valkyrie's forearm model).

The axes ``u1, u2, u3`` (world, at ``q = 0``) pass through one centre ``o``; the tool turns about
it: ``R(q) = Rot(u1, q1) Rot(u2, q2) Rot(u3, q3) R0`` and the tool point is
``o + R(q) R0^T (t0 - o)`` (``t0``, ``R0``: the tool at ``q = 0``, product of exponentials).

A pose: ``M = R_target R0^T``. Joint 3 keeps ``u3``, so ``Rot(u1, q1) Rot(u2, q2) u3 = M u3``: two
rotations about two crossing axes taking one vector onto another (Paden-Kahan sub-problem 2,
:func:`rotation_pair`), two pairs ``(q1, q2)`` (the wrist's two sides); ``q3`` then turns a
vector normal to ``u3`` onto its image (sub-problem 1, :func:`turn_angle`). Two branches; a pose
whose position the wrist does not reach with that rotation is measured by the solver
(``projects``: the candidates are its rotation's).

A position: with the tool point on the centre every joint vector reaches it (the seed's, stated:
all three joints free); off the centre, joint 3 keeps the seed's value and the pair
``(q1, q2)`` turns the tool point's offset onto the target's (two branches).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable

from ...exceptions import StructureError
from ...targets.target import PoseTarget, PositionTarget, Target
from ..branches import REACH_TOL, Branches
from ..closed_form_structure import BatchBranches, candidate_branches
from ..per_target_batch import branches_of_each, solve_each
from ..planar.base_yaw import Point, apply_rows, dot, turn
from ..planar.plane_chain import PARALLEL_TOL, joint_axes

#: Largest distance [m] of an axis from the common centre.
MEET_TOL = 1e-9


def _cross(u: Point, v: Point) -> Point:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def turn_angle(axis: Point, p: Point, d: Point) -> float | None:
    """The angle [rad] about the unit ``axis`` turning ``p`` onto ``d`` (sub-problem 1).

    None when either is along the axis (any angle does it).
    """
    a = dot(axis, p)
    b = dot(axis, d)
    pp = (p[0] - a * axis[0], p[1] - a * axis[1], p[2] - a * axis[2])
    dd = (d[0] - b * axis[0], d[1] - b * axis[1], d[2] - b * axis[2])
    if dot(pp, pp) < 1e-24 or dot(dd, dd) < 1e-24:
        return None
    return math.atan2(dot(axis, _cross(pp, dd)), dot(pp, dd))


def rotation_pair(u1: Point, u2: Point, p: Point, d: Point) -> list[tuple[float, float]]:
    """The pairs ``(q1, q2)`` [rad] with ``Rot(u1, q1) Rot(u2, q2) p = d`` (sub-problem 2).

    ``u1, u2``: unit axes through one point, not parallel; ``|p| = |d|``. The common vector
    ``c = Rot(u2, q2) p = Rot(u1, -q1) d`` has ``u1 . c = u1 . d``, ``u2 . c = u2 . p`` and
    ``|c| = |p|``: two (one at a tangency, none when the cones miss each other).
    """
    k = dot(u1, u2)
    w = _cross(u1, u2)
    ww = dot(w, w)
    a1, a2 = dot(u1, d), dot(u2, p)
    alpha = (a1 - k * a2) / ww
    beta = (a2 - k * a1) / ww
    square = (dot(p, p) - alpha * alpha - beta * beta - 2.0 * alpha * beta * k) / ww
    if square < -1e-12:
        return []
    gammas = (0.0,) if square <= 0.0 else (math.sqrt(square), -math.sqrt(square))
    pairs = []
    for gamma in gammas:
        c = tuple(alpha * u1[i] + beta * u2[i] + gamma * w[i] for i in range(3))
        q2 = turn_angle(u2, p, c)  # type: ignore[arg-type]
        q1 = turn_angle(u1, c, d)  # type: ignore[arg-type]
        pairs.append((0.0 if q1 is None else q1, 0.0 if q2 is None else q2))
    return pairs


class Wrist3:
    """Three revolute joints whose axes meet at one point (see the module).

    Attributes:
        axes: The joints' axis directions (world, ``q = 0``) as plain floats.
        centre: The point [m] where they meet.
        offset: The tool point from the centre at ``q = 0`` [m].
        tool_rotation: ``R_world_tool`` at ``q = 0``.
        offsets: DH angle offsets ``theta`` [rad].
    """

    name: ClassVar[str] = "wrist3"
    dof: ClassVar[int] = 3
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget, PoseTarget)
    branch_labels: tuple[str, ...] = ("wrist side 1", "wrist side 2")
    #: The candidates are the rotation's; the position is measured by the solver.
    projects: ClassVar[bool] = True

    def __init__(self, table: DHTable):
        if table.dof != self.dof or any(row.joint_type != "revolute" for row in table.rows):
            raise StructureError(table.name, self.name, "not three revolute joints")
        directions, points, tool = joint_axes(table)
        units = [u / np.linalg.norm(u) for u in directions]
        for i in (0, 1):
            if np.linalg.norm(np.cross(units[i], units[i + 1])) < PARALLEL_TOL:
                raise StructureError(
                    table.name, self.name, f"joints {i + 1} and {i + 2} have parallel axes"
                )
        # The point nearest the three axis lines (least squares), then each line's distance.
        normal = [np.eye(3) - np.outer(u, u) for u in units]
        centre = np.linalg.solve(sum(normal), sum(n @ p for n, p in zip(normal, points)))
        miss = max(float(np.linalg.norm(n @ (centre - p))) for n, p in zip(normal, points))
        if miss > MEET_TOL:
            raise StructureError(
                table.name, self.name, f"the three axes do not meet ({miss:.3g} m apart)"
            )
        self.axes = tuple(tuple(u.tolist()) for u in units)
        self.centre = tuple(centre.tolist())
        self.offset = tuple((tool[:3, 3] - centre).tolist())
        self.tool_rotation = tool[:3, :3]
        self.offsets = tuple(row.theta for row in table.rows)
        helper = np.array([1.0, 0.0, 0.0]) if abs(units[2][0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        normal3 = np.cross(units[2], helper)
        self._normal3 = tuple((normal3 / np.linalg.norm(normal3)).tolist())
        self._tool_normal3 = tuple((self.tool_rotation.T @ np.array(self._normal3)).tolist())
        self._tool_u3 = tuple((self.tool_rotation.T @ units[2]).tolist())

    @classmethod
    def recognise(cls, table: DHTable) -> Wrist3:
        """This structure when the table's three revolute axes meet at one point.

        Raises:
            StructureError: What does not fit.
        """
        return cls(table)

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets (N, 3) [m], rotations (N, 3, 3) or None: (N, B, dof)."""
        return solve_each(self, positions, rotations)

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """:meth:`solve_batch`; no elbow side (all False)."""
        return branches_of_each(self, positions, rotations)

    def pose_rows(self, rotation: np.ndarray) -> list[tuple[float, ...]]:
        """The two branches ``q`` [rad] of a tool rotation ``R_world_tool`` (NaN rows: none)."""
        r = np.asarray(rotation, dtype=float).tolist()
        u1, u2, u3 = self.axes
        m_u3 = apply_rows(r, self._tool_u3)  # M u3 = R R0^T u3
        m_v = apply_rows(r, self._tool_normal3)  # M v, v normal to u3
        rows: list[tuple[float, ...]] = []
        for q1, q2 in rotation_pair(u1, u2, u3, m_u3):
            back = turn(u1, math.cos(q1), -math.sin(q1), m_v)
            back = turn(u2, math.cos(q2), -math.sin(q2), back)
            q3 = turn_angle(u3, self._normal3, back)
            rows.append((q1, q2, 0.0 if q3 is None else q3))
        rows.extend([(math.nan,) * 3] * (2 - len(rows)))
        return rows

    def position_rows(self, position: np.ndarray, q3: float) -> list[tuple[float, ...]]:
        """The branches ``q`` [rad] of a tool point with joint 3 at ``q3`` (NaN rows: none)."""
        u1, u2, u3 = self.axes
        target = tuple(float(position[i]) - self.centre[i] for i in range(3))
        offset = turn(u3, math.cos(q3), math.sin(q3), self.offset)  # type: ignore[arg-type]
        rows: list[tuple[float, ...]] = [
            (q1, q2, q3) for q1, q2 in rotation_pair(u1, u2, offset, target)
        ]  # type: ignore[arg-type]
        return rows + [(math.nan,) * 3] * (2 - len(rows))

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The two branches (2, 3) ``q`` [rad] of a pose's rotation, or a point (``q3 = 0``)."""
        if rotation is not None:
            return np.array(self.pose_rows(rotation), dtype=float)
        return np.array(self._position(position, (0.0, 0.0, 0.0))[0], dtype=float)

    def _position(
        self, position: np.ndarray, seed: Sequence[float]
    ) -> tuple[list[tuple[float, ...]], str]:
        """The branches of a point and what is free (the tool on the centre: the seed itself)."""
        distance = math.dist(self.centre, [float(v) for v in position])
        reach = math.hypot(*self.offset)
        if abs(distance - reach) > REACH_TOL + 1e-12 * reach:
            return [(math.nan,) * 3] * 2, ""
        if reach < 1e-12:
            return [
                tuple(float(v) for v in seed[:3]),
                (math.nan,) * 3,
            ], "every joint free: the seed's"
        return self.position_rows(position, float(seed[2])), "joint 3 free: the seed's value"

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """The branches (DH angles) of a pose's rotation, or of a point (joint 3 the seed's)."""
        if isinstance(target, PoseTarget):
            return candidate_branches(
                self, self.solve(target.position, target.rotation), self.offsets
            )
        rows, free = self._position(target.position, seed)
        branches = candidate_branches(self, np.array(rows, dtype=float), self.offsets)
        branches.thetas = [(t, f"{label}, {free}") for t, label in branches.thetas]
        return branches
