"""Four-joint arms: a base yaw, then three parallel pitch joints (AL5D, Orion5, many hobby arms).

Joint 1's axis ``n1`` is normal to the three parallel axes of joints 2-4 (direction ``n2`` at
``q1 = 0``). The base yaw turns the plane of the pitch chain about ``n1``; the chain itself is a
planar 3R (:class:`~.plane_chain.PlaneChain` of three joints). The tool point keeps its
offset ``h`` along ``n2`` from joint 1's axis, so:

1. the yaw ``phi = q1`` puts the target on the chain's plane: ``n2(phi) . (p - o1) = h`` with
   ``n2(phi) = cos(phi) n2 + sin(phi) (n1 x n2)``, two solutions (the arm reaching in front or
   over its back);
2. the target turned back by ``-phi`` about ``n1`` is a pose of the planar 3R: its yaw about
   ``n2`` (the approach pitch) and its wrist point give the two elbow branches.

Four branches. A pose whose approach leaves the arm's plane is projected: the candidates are
the nearest poses the arm reaches there, which the partial-pose solver
(:mod:`kin.ik.partial_pose`) measures and, when they miss, reports as the nearest pose.

A position leaves the pitch free: the four branches at the seed's pitch, or at the nearest
pitch of a 1-degree sweep with a branch inside the limits
(:func:`~.free_angle.free_angle_branches`); the labels state it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
import pinocchio as pin

from dh2urdf import DHTable

from ...targets.target import PoseTarget, PositionTarget, Target
from ..branches import Branches
from ..closed_form_structure import candidate_branches
from .base_yaw import BaseYaw, Point, Vector, plane_yaws
from .free_angle import Row, compiled_walk, free_angle_branches, free_label, row_inside
from .plane_chain import PlaneChain, solve_angles


class YawPlanar(BaseYaw):
    """Base yaw and three parallel pitch joints (see the module).

    Attributes:
        chain: The planar 3R of joints 2-4 at ``q1 = 0``.
        (the base yaw's: :class:`~.base_yaw.BaseYaw`)
    """

    name: ClassVar[str] = "yaw_planar"
    #: The sweep of a free pitch walked by its compiled twin when built (False: in Python).
    compiled: bool = True
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget, PoseTarget)

    def __init__(self, table: DHTable):
        directions, points, tool = self._base_yaw(table)
        self.chain = PlaneChain(
            table.name, directions[1:], points[1:], tool, ["revolute"] * 3
        )  # raises when joints 2-4 are not parallel
        self._bounds = (tuple(self.lower.tolist()), tuple(self.upper.tolist()))
        self._walk_data = self.chain.walk_data(self._bounds[0][1:], self._bounds[1][1:])

    @classmethod
    def recognise(cls, table: DHTable) -> YawPlanar:
        """This structure when the table is a base yaw and three parallel pitch joints.

        Raises:
            StructureError: What does not fit.
        """
        return cls(table)

    def candidates(
        self, position: np.ndarray, rotation: np.ndarray | None, pitches: np.ndarray | None = None
    ) -> np.ndarray:
        """The four branches (K, 4, 4) ``q`` [rad] of a pose (K = 1) or a position at K pitches.

        Args:
            position: Tool point in the world [m].
            rotation: ``R_world_tool`` (its projection on the arm's poses is solved), or None.
            pitches: With ``rotation`` None, the chain's pitch [rad] (K,) (the last link's angle
                about the pitch axes, :meth:`~.plane_chain.PlaneChain.last_angle`).
        """
        count = 1 if pitches is None else len(pitches)
        out = np.full((count, 4, 4), np.nan)
        p = np.asarray(position, dtype=float) - self.o1
        for k, phi in enumerate(plane_yaws(p, self.n2, self.side, self.h)):
            back = pin.exp3(self.n1 * -phi)
            point = self.o1 + back @ p
            if pitches is None:
                assert rotation is not None
                branches = np.array(self.chain.solve_chain(point, back @ np.asarray(rotation)))
            else:
                branches = solve_angles(self.chain, point, pitches)
            out[:, 2 * k : 2 * k + 2, 0] = math.remainder(phi, 2.0 * math.pi)
            out[:, 2 * k : 2 * k + 2, 1:] = branches
        return out

    def candidates_at(self, position: Vector, pitch: float) -> list[Row]:
        """:meth:`candidates` of a position at one pitch [rad] in plain floats: four rows.

        The same branches as ``candidates(position, None, [pitch])[0]`` (all NaN: none),
        without NumPy's cost on one value (the seed's pitch of every position target).
        """
        return self._at_pitch(self.plane_points(position), pitch)

    def _at_pitch(self, planes: list[tuple[float, Point, float, float]], pitch: float) -> list[Row]:
        """The four rows at one pitch [rad] of the points turned onto the chain's plane."""
        rows: list[Row] = []
        for yaw, point, _, _ in planes:
            rows.extend((yaw, *row) for row in self.chain.solve_angle(point, pitch))
        rows.extend([(math.nan,) * 4] * (4 - len(rows)))
        return rows

    def _pose_rows(self, position: np.ndarray, rotation: np.ndarray) -> list[Row]:
        """The four rows of a pose's projection in plain floats (:meth:`candidates` of a pose)."""
        rows: list[Row] = []
        for yaw, point, c, s in self.plane_points(position):
            back = self.turned_back(rotation, c, s)
            rows.extend((yaw, *row) for row in self.chain.solve_chain(point, back))
        rows.extend([(math.nan,) * 4] * (4 - len(rows)))
        return rows

    def free_branches(self, position: np.ndarray, seed: Sequence[float]) -> tuple[np.ndarray, str]:
        """The four branches (4, 4) of a position at the stated pitch, and what it is.

        The base yaws and the turned points are solved once; each pitch of the sweep is then
        the planar 3R's wrist alone (:meth:`~.plane_chain.PlaneChain.solve_angle`).
        """
        planes = self.plane_points(position)
        # A branch is inside the limits when its yaw is and its pitch chain's joints are: the
        # sweep asks the chain of the yaws inside them only.
        yaw_bounds = ((self._bounds[0][0],), (self._bounds[1][0],), (True,))
        chain_bounds = (self._bounds[0][1:], self._bounds[1][1:], (True,) * 3)
        points = [plane[1] for plane in planes if row_inside((plane[0],), yaw_bounds)]

        def inside_at(pitch: float) -> bool:
            return any(
                row_inside(row, chain_bounds)
                for point in points
                for row in self.chain.solve_angle(point, pitch)
            )

        walk = None
        if self.compiled and self._walk_data is not None:
            walk = compiled_walk(self._walk_data, [self.chain.in_plane(p) for p in points])
        q, pitch, swept = free_angle_branches(
            lambda pitches: self.candidates(position, None, pitches),
            self.chain.last_angle(list(seed)[1:]),
            (self.lower, self.upper, np.ones(4, dtype=bool)),
            lambda pitch: self._at_pitch(planes, pitch),
            inside_at,
            walk,
        )
        return q, free_label("pitch", pitch, swept)

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The four branches (4, 4) ``q`` [rad] of the target's projection (NaN: none).

        A position (``rotation`` None): :meth:`free_branches` from ``q = 0``.
        """
        if rotation is None:
            return self.free_branches(position, (0.0,) * 4)[0]
        return np.array(self._pose_rows(position, rotation), dtype=float)

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """The branches (DH angles) of a position (the pitch stated) or a pose's projection."""
        if isinstance(target, PoseTarget):
            q = self.solve(target.position, target.rotation)
            return candidate_branches(self, q, self.offsets)
        q, free = self.free_branches(target.position, seed)
        branches = candidate_branches(self, q, self.offsets)
        branches.thetas = [(t, f"{label}, {free}") for t, label in branches.thetas]
        return branches
