"""The planar 2R structure, and the two-link chain every closed form here solves.

The chain is ``p = l1 (cos b1, sin b1) + l2 (cos(b1 + b2), sin(b1 + b2))`` with ``b1, b2`` the
angles of the link vectors; the law of cosines gives ``b2`` (two signs, the elbow branches) and
``b1`` follows. :func:`two_link` (scalar) and :func:`two_link_batch` (NumPy) are shared by the
3- and 5-joint structures. :class:`Planar2R` is a closed-form structure plug-in
(:mod:`.closed_form_structure`): two joints with parallel axes (``alpha1 = alpha2 = 0``), the
tool point moving in a plane.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable

from ...targets.target import PositionTarget, Target
from ..branches import REACH_TOL, Branches
from ..closed_form_structure import BatchBranches, TableStructure
from ..structure import BaseFrame, Checker, Link, tool_point

#: |cos b2| above which the two elbow branches are merged (stretched or folded arm).
MERGE_COS = 1.0 - 1e-13


def two_link(
    x: float, y: float, link1: Link, link2: Link, free_t1: float = 0.0
) -> tuple[list[tuple[float, float, float]], float, str]:
    """Joint angles of a two-link chain reaching ``(x, y)`` in its plane.

    Args:
        x: Target point in the plane of the chain, from the first joint's axis, x [m].
        y: Target point, y [m].
        link1: First link vector, its angle measured from joint 1's DH x axis.
        link2: Second link vector, its angle measured from joint 2's DH x axis.
        free_t1: DH angle of joint 1 [rad] to use when it is free (target on the first axis with
            equal link lengths).

    Returns:
        ``(solutions, gap, singular)``: per branch ``(t1, t2, sin b2)`` (DH angles [rad], and
        the sign-carrying sine of the elbow angle), the distance to the reachable annulus [m]
        (<= 0 when reachable), and ``""`` or the reason the branches merge or a joint is free.
    """
    l1, l2 = link1.length, link2.length
    r = math.hypot(x, y)
    gap = max(r - (l1 + l2), abs(l1 - l2) - r)
    if gap > REACH_TOL:
        return [], gap, ""
    cos_b2 = (x * x + y * y - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    if abs(cos_b2) < MERGE_COS and r > REACH_TOL:
        # the usual case, two distinct elbow branches (the same values as the general case below)
        sin_b2 = math.sqrt(1.0 - cos_b2 * cos_b2)
        a1, a2 = link1.angle, link2.angle
        base, k1, k2 = math.atan2(y, x), l1 + l2 * cos_b2, l2 * sin_b2
        return (
            [
                (base - math.atan2(k2, k1) - a1, math.atan2(sin_b2, cos_b2) - a2 + a1, sin_b2),
                (base - math.atan2(-k2, k1) - a1, math.atan2(-sin_b2, cos_b2) - a2 + a1, -sin_b2),
            ],
            gap,
            "",
        )
    singular = ""
    if abs(cos_b2) >= MERGE_COS:
        cos_b2 = math.copysign(1.0, cos_b2)
        singular = "arm fully stretched" if cos_b2 > 0 else "arm fully folded"
        signs: tuple[float, ...] = (1.0,)
    else:
        signs = (1.0, -1.0)
    sin_abs = math.sqrt(max(0.0, 1.0 - cos_b2 * cos_b2))
    free = r <= REACH_TOL and abs(l1 - l2) <= REACH_TOL
    if free:
        singular = "target on the first joint's axis: that joint is free (seed value kept)"
    solutions = []
    for sign in signs:
        sin_b2 = sign * sin_abs
        b2 = math.atan2(sin_b2, cos_b2)
        if free:
            b1 = free_t1 + link1.angle
        else:
            b1 = math.atan2(y, x) - math.atan2(l2 * sin_b2, l1 + l2 * cos_b2)
        t1 = b1 - link1.angle
        t2 = b2 - link2.angle + link1.angle
        solutions.append((t1, t2, sin_b2))
    return solutions, gap, singular


def two_link_batch(
    x: np.ndarray, y: np.ndarray, link1: Link, link2: Link
) -> tuple[np.ndarray, ...]:
    """Vectorized :func:`two_link`: ``(t1, t2, sin_b2, exists)``, each (N, 2) (elbow +, -)."""
    l1, l2 = link1.length, link2.length
    r = np.hypot(x, y)
    exists = np.maximum(r - (l1 + l2), abs(l1 - l2) - r) <= REACH_TOL
    cos_b2 = np.clip((x * x + y * y - l1 * l1 - l2 * l2) / (2.0 * l1 * l2), -1.0, 1.0)
    cos_b2 = np.where(np.abs(cos_b2) >= MERGE_COS, np.sign(cos_b2), cos_b2)
    sin_abs = np.sqrt(np.maximum(0.0, 1.0 - cos_b2 * cos_b2))
    sin_b2 = np.stack([sin_abs, -sin_abs], axis=-1)
    cos_b2 = cos_b2[..., None]
    b2 = np.arctan2(sin_b2, cos_b2)
    b1 = np.arctan2(y, x)[..., None] - np.arctan2(l2 * sin_b2, l1 + l2 * cos_b2)
    t1 = b1 - link1.angle
    t2 = b2 - link2.angle + link1.angle
    return t1, t2, sin_b2, np.broadcast_to(exists[..., None], t1.shape)


def without_missing(thetas: np.ndarray, exists: np.ndarray, offsets: Sequence[float]) -> np.ndarray:
    """Joint vectors ``thetas - offsets`` (N, B, dof), NaN where the branch does not exist."""
    q = thetas - np.asarray(offsets)
    q[~exists] = np.nan
    return q


@dataclass(frozen=True)
class Planar2R(TableStructure):
    """Two-joint planar arm: the tool point is ``Rz(t1) l1 + Rz(t1 + t2) l2`` at height ``z``.

    Attributes:
        link1, link2: In-plane link vectors (the second includes the tool point).
        height: z of the plane of motion in frame 0 [m].
        offsets: DH angle offsets ``theta`` [rad] (DH angle = q + offset).
        base: DH frame 0 in the world.
    """

    name: ClassVar[str] = "planar2r"
    dof: ClassVar[int] = 2
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget,)
    branch_labels: ClassVar[tuple[str, ...]] = ("elbow +", "elbow -")

    link1: Link
    link2: Link
    height: float

    @classmethod
    def recognise(cls, table: DHTable) -> Planar2R:
        """Parameters of a two-joint planar arm.

        Raises:
            StructureError: The table is not a planar 2R arm.
        """
        check = Checker(table, "planar 2R")
        check.rows(2)
        row1, row2 = table.rows
        check.alpha(row1, (0.0,))
        check.alpha(row2, (0.0,))
        tool = tool_point(table)
        return cls(
            link1=check.link(row1.a, 0.0, f"row 1 ('{row1.name}')"),
            link2=check.link(row2.a + tool[0], tool[1], f"row 2 ('{row2.name}') with the tool"),
            height=row1.d + row2.d + tool[2],
            offsets=(row1.theta, row2.theta),
            base=BaseFrame.of(table),
        )

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """Both elbow branches of a position target (see :func:`solve_planar2r`)."""
        x, y, z = self.base.point(target.position.tolist())
        return solve_planar2r(self, x, y, z, free_t1=seed[0] + self.offsets[0])

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """Both elbow branches of N tool points (N, 3) [m] (``rotations`` is ignored)."""
        p0 = self.base.points(positions)
        t1, t2, sin_b, exists = two_link_batch(p0[:, 0], p0[:, 1], self.link1, self.link2)
        exists = exists & (np.abs(p0[:, 2] - self.height) <= REACH_TOL)[:, None]
        q = without_missing(np.stack([t1, t2], axis=-1), exists, self.offsets)
        return BatchBranches(q, sin_b < 0)


def solve_planar2r(
    structure: Planar2R, x: float, y: float, z: float, free_t1: float = 0.0
) -> Branches:
    """Both elbow branches of a planar 2R arm for a tool point in frame 0.

    Labels: ``"elbow up"`` puts the elbow on the counter-clockwise side of the line from the base
    to the target (above it when the target is along +x), ``"elbow down"`` on the other side.

    Args:
        structure: The arm's parameters.
        x: Tool point in frame 0, x [m].
        y: Tool point in frame 0, y [m].
        z: Tool point in frame 0, z [m]; must be the height of the plane of motion.
        free_t1: DH angle of joint 1 [rad] kept when that joint is free.
    """
    branches = Branches()
    off_plane = abs(z - structure.height)
    solutions, gap, singular = two_link(x, y, structure.link1, structure.link2, free_t1)
    if off_plane > REACH_TOL or not solutions:
        total = math.hypot(off_plane, max(gap, 0.0))
        return branches.out_of_reach(
            total,
            f"out of reach by {total:.6g} m ({off_plane:.3g} m off the plane of motion, "
            f"{max(gap, 0.0):.3g} m outside the reachable annulus)",
        )
    for t1, t2, sin_b2 in solutions:
        label = "elbow up" if sin_b2 < 0 else "elbow down"
        if len(solutions) == 1:
            label = (
                "elbow straight"
                if abs(t2 + structure.link2.angle - structure.link1.angle) < 1
                else "elbow folded"
            )
        branches.thetas.append(((t1, t2), label))
    if singular:
        branches.singular(singular)
    return branches
