"""Arms whose joint axes are all parallel: SCARA (RRPR, RRRP), planar 3R, planar 2R with a slide.

Every revolute axis and every prismatic direction is parallel to one unit vector ``n``: the tool
moves in the plane normal to ``n`` by the revolute joints, along ``n`` by the prismatic one, and
turns about ``n`` only (the chain's geometry and its two-link solves: :mod:`.plane_chain`).

Given a pose, the yaw ``psi`` is the angle of ``R_target R0^T`` about ``n`` (the nearest rotation
about ``n`` when the target is tilted: the arm cannot tilt its tool); with three revolute joints
``phi3 = psi`` and the wrist point ``W = P - Rot(psi) L3`` is a two-link problem, two branches
(the elbow's two sides); with two, the position alone gives the two branches. The candidates are
the projection of the target on what the arm reaches; the partial-pose solver
(:mod:`kin.ik.partial_pose`) measures them on the target's constrained components and reports
the nearest pose when they miss.

A position leaves the yaw free (:meth:`ParallelAxes.free_branches`): with the tool on the last
axis (a SCARA's RRPR) the last joint keeps the seed's value; else (a planar 3R, a tool off the
last axis) the yaw is the seed's ``psi``, or, when no branch there is inside the joint limits,
the nearest one of a 1-degree sweep away from it (:mod:`.free_angle`) that has one. The
branches are exact at that yaw: the stated value of the free angle.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable

from ...exceptions import StructureError
from ...targets.target import PoseTarget, PositionTarget, Target
from ..branches import REACH_TOL, Branches
from ..closed_form_structure import BatchBranches, candidate_branches
from ..per_target_batch import branches_of_each, solve_each
from .free_angle import compiled_walk, free_angle_branches, free_label
from .plane_chain import PlaneChain, joint_axes, solve_angles


class ParallelAxes:
    """The closed form of an arm with every joint axis parallel (see the module).

    Attributes:
        chain: The arm's plane chain (its geometry and two-link solves).
        offsets: DH angle offsets ``theta`` [rad] of the table.
        lower, upper: Joint limits [rad] or [m].
        is_revolute: Per joint whether it is revolute.
    """

    name: ClassVar[str] = PlaneChain.name
    dof: ClassVar[int] = 4
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget, PoseTarget)
    branch_labels: tuple[str, ...] = ("elbow left", "elbow right")
    #: The candidates are the projection of a pose on what the arm reaches: the partial-pose
    #: solver measures them (a full pose on this arm goes there, see ``ClosedFormSolver``).
    projects: ClassVar[bool] = True
    #: The sweep of a free yaw walked by its compiled twin when built (False: in Python).
    compiled: bool = True

    def __init__(self, table: DHTable):
        directions, points, tool = joint_axes(table)
        kinds: list[str] = [row.joint_type for row in table.rows]
        self.chain = PlaneChain(table.name, directions, points, tool, kinds)
        self.lower = np.array([row.lower for row in table.rows], dtype=float)
        self.upper = np.array([row.upper for row in table.rows], dtype=float)
        self.is_revolute = np.array([kind == "revolute" for kind in kinds])
        self.offsets = tuple(row.theta for row in table.rows)

    @classmethod
    def recognise(cls, table: DHTable) -> ParallelAxes:
        """This structure when every axis of the table is parallel (see the module).

        Raises:
            StructureError: An axis not parallel to the first, or a joint count it does not take.
        """
        if table.dof != cls.dof:
            raise StructureError(table.name, cls.name, f"{table.dof} joints, not {cls.dof}")
        return cls(table)

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The two branches (2, dof) ``q`` [rad, m] of the target's projection (NaN: none).

        A position (``rotation`` None) on three revolute joints: :meth:`free_branches` from
        ``q = 0``.
        """
        chain = self.chain
        if rotation is None and len(chain.links) == 3:
            return self.free_branches(position, np.zeros(chain.nq))[0]
        return np.array(chain.solve_chain(position, rotation), dtype=float)

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets (N, 3) [m], rotations (N, 3, 3) or None: (N, B, dof)."""
        return solve_each(self, positions, rotations)

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """:meth:`solve_batch`; no elbow side (all False)."""
        return branches_of_each(self, positions, rotations)

    def free_branches(self, position: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray, str]:
        """Both branches (2, dof) of a position, the free yaw stated (see the module).

        Args:
            position: Tool point in the world [m].
            seed: The joint vector [rad, m] whose yaw (or last joint) is kept.

        Returns:
            The branches ``q`` (NaN: none) and what the free angle is (``""``: none is free).
        """
        chain = self.chain
        last = chain.revolute[-1]
        point = (float(position[0]), float(position[1]), float(position[2]))
        if not chain.prismatic and abs(chain.along(np.asarray(point)) - chain.height) > REACH_TOL:
            return np.full((2, chain.nq), np.nan), ""  # off the plane the tool moves in
        if len(chain.links) == 2:
            return self._free_last_of_two(point, seed)
        if chain.tool_on_axis:  # the last joint does not move the tool point: the seed's
            q = np.array(chain.solve_angle(point, 0.0), dtype=float)
            q[:, last] = np.where(np.isnan(q[:, last]), np.nan, seed[last])
            return q, f"joint {last + 1} free: the seed's value"
        data = chain.walk_data(self.lower.tolist(), self.upper.tolist()) if self.compiled else None
        q, angle, swept = free_angle_branches(
            lambda psis: solve_angles(chain, np.asarray(point), psis),
            chain.last_angle(seed),
            (self.lower, self.upper, self.is_revolute),
            lambda psi: chain.solve_angle(point, psi),
            walk=None if data is None else compiled_walk(data, [chain.in_plane(point)]),
        )
        return q, free_label("yaw", angle, swept)

    def _free_last_of_two(
        self, point: tuple[float, float, float], seed: np.ndarray
    ) -> tuple[np.ndarray, str]:
        """:meth:`free_branches` of two revolute joints: none free, or the tool on the last axis.

        The tool on the last axis: the first angle puts it on its circle, the last is the seed's.
        """
        chain = self.chain
        l1, l2 = chain.links
        if not float(l2 @ l2) < 1e-24 < float(l1 @ l1):
            return np.array(chain.solve_chain(np.asarray(point), None), dtype=float), ""
        last, first = chain.revolute[-1], chain.revolute[0]
        q = np.full((2, chain.nq), np.nan)
        wx, wy = chain.in_plane(point)
        if abs(math.hypot(wx, wy) - math.sqrt(float(l1 @ l1))) <= REACH_TOL:
            phi1 = math.atan2(wy, wx) - math.atan2(l1[1], l1[0])
            q[0] = chain.branch([phi1, phi1], point)
            q[0, last] = seed[last]
            q[0, first] = math.remainder(q[0, first], 2.0 * math.pi)
        return q, f"joint {last + 1} free: the seed's value"

    def branches(self, target: Target, seed: list[float]) -> Branches:
        """The branches (DH angles) of a position (the yaw stated) or of a pose's projection."""
        if isinstance(target, PoseTarget):
            q = self.solve(target.position, target.rotation)
            return candidate_branches(self, q, self.offsets)
        q, free = self.free_branches(target.position, np.asarray(seed, dtype=float))
        branches = candidate_branches(self, q, self.offsets)
        if free:
            branches.thetas = [(t, f"{label}, {free}") for t, label in branches.thetas]
        return branches


class ParallelAxes3(ParallelAxes):
    """:class:`ParallelAxes` of three joints (planar 3R, planar 2R with a slide)."""

    dof: ClassVar[int] = 3


class ParallelAxes2(ParallelAxes):
    """:class:`ParallelAxes` of two joints (a planar 2R that the planar 2R form does not take)."""

    dof: ClassVar[int] = 2
