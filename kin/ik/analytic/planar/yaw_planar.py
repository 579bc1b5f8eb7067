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

A position leaves the pitch free: the four branches at the seed's pitch, or at the nearest
pitch of a 1-degree sweep with a branch inside the limits
(:func:`~.parallel_axes.free_angle_branches`); the labels state it.
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
from .parallel_axes import (
    PARALLEL_TOL,
    ParallelAxes,
    Row,
    _axes,
    free_angle_branches,
    free_label,
)

#: A 3-vector as an array or plain floats.
Vector = Sequence[float] | np.ndarray


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


class YawPlanar:
    """Base yaw and three parallel pitch joints (see the module).

    Attributes:
        n1: Joint 1's axis in the world frame.
        o1: A point on it [m].
        n2: The pitch axes' direction at ``q1 = 0``.
        h: The tool point's offset along ``n2`` from joint 1's axis [m] (constant).
        chain: The planar 3R of joints 2-4 at ``q1 = 0``.
        offsets: DH angle offsets ``theta`` [rad].
    """

    name: ClassVar[str] = "yaw_planar"
    dof: ClassVar[int] = 4
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget, PoseTarget)
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
        self.lower = np.array([row.lower for row in table.rows])
        self.upper = np.array([row.upper for row in table.rows])
        self.chain = ParallelAxes.from_axes(
            table.name,
            directions[1:],
            points[1:],
            tool,
            ["revolute"] * 3,
            (self.lower[1:], self.upper[1:]),
        )  # raises when joints 2-4 are not parallel
        self.n1, self.o1, self.n2 = n1, points[0], n2
        self.side = np.cross(n1, n2)
        self.h = float((tool[:3, 3] - self.o1) @ n2)
        self.offsets = tuple(row.theta for row in table.rows)
        # plain floats of the single-target path (:meth:`candidates_at`)
        self._axes = tuple(tuple(v.tolist()) for v in (self.n1, self.o1, self.n2, self.side))

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
                about the pitch axes, :meth:`~.parallel_axes.ParallelAxes.last_angle`).
        """
        count = 1 if pitches is None else len(pitches)
        out = np.full((count, 4, 4), np.nan)
        p = np.asarray(position, dtype=float) - self.o1
        for k, phi in enumerate(plane_yaws(p, self.n2, self.side, self.h)):
            back = pin.exp3(self.n1 * -phi)
            point = self.o1 + back @ p
            if pitches is None:
                assert rotation is not None
                branches = self.chain.solve(point, back @ np.asarray(rotation))[None]
            else:
                branches = self.chain.solve_angles(point, pitches)
            out[:, 2 * k : 2 * k + 2, 0] = math.remainder(phi, 2.0 * math.pi)
            out[:, 2 * k : 2 * k + 2, 1:] = branches
        return out

    def candidates_at(self, position: Vector, pitch: float) -> list[Row]:
        """:meth:`candidates` of a position at one pitch [rad] in plain floats: four rows.

        The same branches as ``candidates(position, None, [pitch])[0]`` (all NaN: none),
        without NumPy's cost on one value (the seed's pitch of every position target).
        """
        (n1x, n1y, n1z), o1, n2, side = self._axes
        px, py, pz = (float(position[i]) - o1[i] for i in range(3))
        rows: list[Row] = []
        for phi in plane_yaws((px, py, pz), n2, side, self.h):
            # Rodrigues: p turned by -phi about n1, back in the world
            c, s = math.cos(phi), -math.sin(phi)
            dot = (n1x * px + n1y * py + n1z * pz) * (1.0 - c)
            point = (
                o1[0] + c * px + s * (n1y * pz - n1z * py) + dot * n1x,
                o1[1] + c * py + s * (n1z * px - n1x * pz) + dot * n1y,
                o1[2] + c * pz + s * (n1x * py - n1y * px) + dot * n1z,
            )
            yaw = math.remainder(phi, 2.0 * math.pi)
            rows.extend((yaw, *row) for row in self.chain.solve_angle(point, pitch))
        rows.extend([(math.nan,) * 4] * (4 - len(rows)))
        return rows

    def free_branches(self, position: np.ndarray, seed: Sequence[float]) -> tuple[np.ndarray, str]:
        """The four branches (4, 4) of a position at the stated pitch, and what it is."""
        q, pitch, swept = free_angle_branches(
            lambda pitches: self.candidates(position, None, pitches),
            self.chain.last_angle(list(seed)[1:]),
            (self.lower, self.upper, np.ones(4, dtype=bool)),
            lambda pitch: self.candidates_at(position, pitch),
        )
        return q, free_label("pitch", pitch, swept)

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The four branches (4, 4) ``q`` [rad] of the target's projection (NaN: none).

        A position (``rotation`` None): :meth:`free_branches` from ``q = 0``.
        """
        if rotation is None:
            return self.free_branches(position, (0.0,) * 4)[0]
        return self.candidates(position, rotation)[0]

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """The branches (DH angles) of a position (the pitch stated) or a pose's projection."""
        if isinstance(target, PoseTarget):
            q = self.solve(target.position, target.rotation)
            return candidate_branches(self, q, self.offsets)
        q, free = self.free_branches(target.position, seed)
        branches = candidate_branches(self, q, self.offsets)
        branches.thetas = [(t, f"{label}, {free}") for t, label in branches.thetas]
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
