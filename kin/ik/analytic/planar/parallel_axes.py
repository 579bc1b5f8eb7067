"""Arms whose joint axes are all parallel: SCARA (RRPR, RRRP), planar 3R, planar 2R with a slide.

Every revolute axis and every prismatic direction is parallel to one unit vector ``n`` (the
first joint's axis). Then the tool moves in the plane normal to ``n`` by the revolute joints,
along ``n`` by the prismatic one, and turns about ``n`` only:

- in the plane (2D coordinates in a basis ``e1, e2`` normal to ``n``), with the revolute joints
  ``r1, r2, (r3)`` and the link vectors ``L_k`` between their axes (the last one to the tool
  point) read at ``q = 0``: ``P = c1 + Rot(phi1) L1 + Rot(phi2) L2 (+ Rot(phi3) L3)``, where
  ``phi_k = sum_{j <= k} s_j q_rj`` and ``s_j = +-1`` says whether axis ``rj`` points along
  ``n`` or against it;
- along ``n``: ``(p - c1) . n = h0 + s_p q_p`` for the prismatic joint;
- the tool rotation: ``R = Rot(n, phi_last) R0``.

Given a pose, the yaw ``psi`` is the angle of ``R_target R0^T`` about ``n`` (the nearest rotation
about ``n`` when the target is tilted: the arm cannot tilt its tool); with three revolute joints
``phi3 = psi`` and the wrist point ``W = P - Rot(psi) L3`` is a two-link problem, two branches
(the elbow's two sides); with two, the position alone gives the two branches. The candidates are
the projection of the target on what the arm reaches; the partial-pose solver
(:mod:`kin.ik.partial_pose`) measures them on the target's constrained components and reports
the nearest pose when they miss.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable
from dh2urdf.dh_table import dh_link_transform

from ...exceptions import StructureError
from ...target import PoseTarget

#: Largest ``|u_i x n|`` of an axis taken as parallel to ``n``.
PARALLEL_TOL = 1e-9


def _axes(table: DHTable) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Per joint its axis direction and a point on it (world, ``q = 0``), and ``T_world_tool``."""
    frame = np.asarray(table.T_world_base, dtype=float)
    directions, points = [], []
    for row in table.rows:
        if table.convention == "standard":
            axis_frame = frame
            frame = frame @ dh_link_transform("standard", row.a, row.alpha, row.d, row.theta)
        else:
            axis_frame = frame @ dh_link_transform("modified", row.a, row.alpha, 0.0, 0.0)
            frame = frame @ dh_link_transform("modified", row.a, row.alpha, row.d, row.theta)
        directions.append(axis_frame[:3, 2].copy())
        points.append(axis_frame[:3, 3].copy())
    return directions, points, frame @ np.asarray(table.T_last_tool, dtype=float)


class ParallelAxes:
    """The closed form of an arm with every joint axis parallel (see the module).

    Attributes:
        n: The common axis direction in the world frame (the first joint's).
        signs: Per revolute joint (in order), +1 or -1: its axis along ``n`` or against it.
    """

    name: ClassVar[str] = "parallel_axes"
    dof: ClassVar[int] = 4
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    branch_labels: tuple[str, ...] = ("elbow left", "elbow right")
    #: The candidates are the projection of a pose on what the arm reaches: the partial-pose
    #: solver measures them (a full pose on this arm goes there, see ``ClosedFormSolver``).
    projects: ClassVar[bool] = True

    def __init__(self, table: DHTable):
        directions, points, tool = _axes(table)
        kinds: list[str] = [row.joint_type for row in table.rows]
        self._build(table.name, directions, points, tool, kinds)

    @classmethod
    def from_axes(
        cls,
        name: str,
        directions: list[np.ndarray],
        points: list[np.ndarray],
        tool: np.ndarray,
        kinds: list[str],
    ) -> ParallelAxes:
        """The structure of a chain given by its joint axes (world, at ``q = 0``) and tool pose.

        Raises:
            StructureError: The axes are not all parallel, or the joint counts do not fit.
        """
        chain = cls.__new__(cls)
        chain._build(name, directions, points, tool, kinds)
        return chain

    def _build(
        self,
        name: str,
        directions: list[np.ndarray],
        points: list[np.ndarray],
        tool: np.ndarray,
        kinds: list[str],
    ) -> None:
        n = directions[0] / np.linalg.norm(directions[0])
        for i, u in enumerate(directions):
            if np.linalg.norm(np.cross(u, n)) > PARALLEL_TOL:
                raise StructureError(
                    name,
                    self.name,
                    f"{len(kinds)} joints whose axes are not all parallel (joint {i + 1}'s is not "
                    "parallel to joint 1's)",
                )
        self.revolute = [i for i, kind in enumerate(kinds) if kind == "revolute"]
        self.prismatic = [i for i, kind in enumerate(kinds) if kind == "prismatic"]
        if len(self.revolute) not in (2, 3) or len(self.prismatic) > 1:
            raise StructureError(
                name,
                self.name,
                f"{len(self.revolute)} revolute and {len(self.prismatic)} prismatic joints "
                "(parallel axes: 2 or 3 revolute, at most 1 prismatic)",
            )
        self.n = n
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        self.e1 = np.cross(n, helper)
        self.e1 /= np.linalg.norm(self.e1)
        self.e2 = np.cross(n, self.e1)
        self.signs = [float(np.sign(directions[i] @ n)) for i in self.revolute]
        centres = [self._plane(points[i]) for i in self.revolute] + [self._plane(tool[:3, 3])]
        self.origin = centres[0]
        self.links = [centres[k + 1] - centres[k] for k in range(len(self.revolute))]
        self.height = float((tool[:3, 3] - points[self.revolute[0]]) @ n)
        self.base_point = points[self.revolute[0]]
        self.prismatic_sign = (
            float(np.sign(directions[self.prismatic[0]] @ n)) if self.prismatic else 0.0
        )
        self.tool_rotation = tool[:3, :3]
        self.nq = len(kinds)

    def _plane(self, point: np.ndarray) -> np.ndarray:
        return np.array([point @ self.e1, point @ self.e2])

    @classmethod
    def recognise(cls, table: DHTable) -> ParallelAxes:
        """This structure when every axis of the table is parallel (see the module).

        Raises:
            StructureError: An axis not parallel to the first, or a joint count it does not take.
        """
        if table.dof != cls.dof:
            raise StructureError(table.name, cls.name, f"{table.dof} joints, not {cls.dof}")
        return cls(table)

    def yaw(self, rotation: np.ndarray) -> float:
        """The angle [rad] about ``n`` of the rotation about ``n`` nearest ``R R0^T``."""
        m = rotation @ self.tool_rotation.T
        e1, e2 = self.e1, self.e2
        return math.atan2(e2 @ m @ e1 - e1 @ m @ e2, e1 @ m @ e1 + e2 @ m @ e2)

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The two branches (2, dof) ``q`` [rad, m] of the target's projection (NaN: none)."""
        out = np.full((2, self.nq), np.nan)
        target = self._plane(np.asarray(position, dtype=float))
        links = self.links
        three = len(links) == 3
        if three:
            if rotation is None:
                return out
            psi = self.yaw(np.asarray(rotation, dtype=float))
            c, s = math.cos(psi), math.sin(psi)
            last = links[2]
            target = target - np.array([c * last[0] - s * last[1], s * last[0] + c * last[1]])
        w = target - self.origin
        l1, l2 = links[0], links[1]
        if not float(np.abs(w).max()) < 1e150:  # no arm reaches that far (and no overflow)
            return out
        a = float(l1 @ l2)
        b = float(l1[1] * l2[0] - l1[0] * l2[1])
        rho = math.hypot(a, b)
        if rho < 1e-15:
            # The tool on the last joint's axis (no second link in the plane): the position
            # fixes the first link's angle (its projection on the circle the tool goes round),
            # the yaw the last one's; one branch, of a full pose only.
            if three or rotation is None or not (float(l2 @ l2) < 1e-24 < float(l1 @ l1)):
                return out
            if float(w @ w) < 1e-24:  # on the first axis: the first angle is free
                return out
            phi1 = math.atan2(w[1], w[0]) - math.atan2(l1[1], l1[0])
            self._fill(out[0], [phi1, self.yaw(np.asarray(rotation, dtype=float))], position)
        else:
            cosine = (float(w @ w) - float(l1 @ l1) - float(l2 @ l2)) / (2.0 * rho)
            if abs(cosine) > 1.0 + 1e-12:
                return out
            spread = math.acos(max(-1.0, min(1.0, cosine)))
            centre = math.atan2(b, a)
            for k, beta in enumerate((centre + spread, centre - spread)):
                cb, sb = math.cos(beta), math.sin(beta)
                v = l1 + np.array([cb * l2[0] - sb * l2[1], sb * l2[0] + cb * l2[1]])
                phi1 = math.atan2(w[1], w[0]) - math.atan2(v[1], v[0])
                self._fill(out[k], [phi1, phi1 + beta] + ([psi] if three else []), position)
        for i in self.revolute:
            out[:, i] = np.remainder(out[:, i] + math.pi, 2.0 * math.pi) - math.pi
        return out

    def _fill(self, row: np.ndarray, phis: list[float], position: np.ndarray) -> None:
        """One branch ``q`` into ``row`` from the links' absolute angles ``phis`` [rad].

        Each joint angle is the change from the previous link's angle about ``n``, times its
        axis' sign; the slide [m] puts the tool at the position's height along ``n``.
        """
        previous = 0.0
        for j, (i, sign) in enumerate(zip(self.revolute, self.signs)):
            row[i] = sign * (phis[j] - previous)
            previous = phis[j]
        if self.prismatic:
            along = float((np.asarray(position) - self.base_point) @ self.n)
            row[self.prismatic[0]] = self.prismatic_sign * (along - self.height)

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets: (N, 2, dof)."""
        return np.array(
            [
                self.solve(p, None if rotations is None else r)
                for p, r in zip(positions, rotations if rotations is not None else positions)
            ]
        )


class ParallelAxes3(ParallelAxes):
    """:class:`ParallelAxes` of three joints (planar 3R, planar 2R with a slide)."""

    dof: ClassVar[int] = 3


class ParallelAxes2(ParallelAxes):
    """:class:`ParallelAxes` of two joints (a planar 2R that the planar 2R form does not take)."""

    dof: ClassVar[int] = 2
