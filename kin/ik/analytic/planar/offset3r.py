"""Closed-form IK of a base yaw and two parallel pitch joints with a shoulder (lateral) offset.

The arm plane (joints 2 and 3) is vertical and lies at ``lateral`` from the base axis along
``z1``. A tool point ``p`` at horizontal distance ``rho`` from the base axis is in that plane for
``sin(q1 + theta1 - atan2(py, px)) = sign1 * lateral / rho``: two base angles (shoulder left and
right, or front and back without offset); in the plane, :func:`~.planar2r.two_link` gives the
two elbow branches of each. Four branches in all. :class:`Offset3R` is a closed-form structure
plug-in (:mod:`.closed_form_structure`): base yaw, then two parallel pitch joints
(``alpha1 = +-90 deg``, ``alpha2 = alpha3 = 0``); the lateral offset ``d2 + d3 + tool z`` (the
shoulder offset) may be non-zero.
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
from .planar2r import two_link, two_link_batch, without_missing

#: Labels of the batch columns: base angle 1 (towards the target) and 2, elbow sine + and -.
BATCH_LABELS = ("base 1, elbow +", "base 1, elbow -", "base 2, elbow +", "base 2, elbow -")

#: Per shoulder label, the labels of its two elbow branches (up, down).
ELBOW_LABELS = {
    shoulder: (f"{shoulder}, elbow up", f"{shoulder}, elbow down")
    for shoulder in ("shoulder back", "shoulder front", "shoulder left", "shoulder right")
}


def yaw_over_pitch(table: DHTable, solver: str, joints: int, pitches: int) -> tuple[Checker, float]:
    """The checker of a base yaw over ``pitches`` parallel pitch joints (rows 2 on), its sign.

    Checks the table (a standard DH table of ``joints`` rows): row 1 a twist of +-90 degrees
    (the yaw's axis normal to the pitch axes), rows ``2 .. pitches + 1`` none. Returns the
    checker (for the structure's further checks) and the twist's sign, +1 or -1.

    Raises:
        StructureError: A row does not fit (the checker's message, naming ``solver``).
    """
    check = Checker(table, solver)
    check.rows(joints)
    rows = table.rows
    sign = math.copysign(1.0, check.alpha(rows[0], (math.pi / 2, -math.pi / 2)))
    for row in rows[1 : pitches + 1]:
        check.alpha(row, (0.0,))
    return check, sign


@dataclass(frozen=True)
class Offset3R(TableStructure):
    """Base yaw and two parallel pitch joints, with a possible shoulder (lateral) offset.

    Attributes:
        sign1: Sign of ``alpha1`` (+1 or -1): the arm plane's "up" is ``sign1 * z0``.
        a1: Radial offset of the shoulder axis from the base axis [m].
        d1: Height of the shoulder axis [m].
        lateral: Offset of the arm plane along ``z1`` [m] (``d2 + d3 + tool z``).
        link2, link3: In-plane link vectors (the last includes the tool point).
        offsets: DH angle offsets [rad].
        base: DH frame 0 in the world.
    """

    name: ClassVar[str] = "offset3r"
    dof: ClassVar[int] = 3
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget,)
    branch_labels: ClassVar[tuple[str, ...]] = BATCH_LABELS

    sign1: float
    a1: float
    d1: float
    lateral: float
    link2: Link
    link3: Link

    @classmethod
    def recognise(cls, table: DHTable) -> Offset3R:
        """Parameters of a base-yaw + two-pitch arm with shoulder offset.

        Raises:
            StructureError: The table does not have that structure.
        """
        check, sign1 = yaw_over_pitch(table, "offset 3R", 3, 2)
        row1, row2, row3 = table.rows
        tool = tool_point(table)
        return cls(
            sign1=sign1,
            a1=row1.a,
            d1=row1.d,
            lateral=row2.d + row3.d + tool[2],
            link2=check.link(row2.a, 0.0, f"row 2 ('{row2.name}')"),
            link3=check.link(row3.a + tool[0], tool[1], f"row 3 ('{row3.name}') with the tool"),
            offsets=(row1.theta, row2.theta, row3.theta),
            base=BaseFrame.of(table),
        )

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """All branches of a position target (see :func:`solve_offset3r`)."""
        x, y, z = self.base.point(target.position.tolist())
        return solve_offset3r(self, x, y, z, free_t1=seed[0] + self.offsets[0])

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """All branches of N tool points (N, 3) [m] (``rotations`` is ignored)."""
        p0 = self.base.points(positions)
        rho = np.hypot(p0[:, 0], p0[:, 1])
        phi = np.arctan2(p0[:, 1], p0[:, 0])
        with np.errstate(divide="ignore", invalid="ignore"):
            delta = np.arcsin(np.clip(self.sign1 * self.lateral / rho, -1.0, 1.0))
        reach = np.sqrt(np.maximum(0.0, rho * rho - self.lateral**2))
        v = self.sign1 * (p0[:, 2] - self.d1)
        columns = []
        for base, radial in ((phi + delta, reach), (phi + np.pi - delta, -reach)):
            u = radial - self.a1
            t2, t3, sin_b, exists = two_link_batch(u, v, self.link2, self.link3)
            exists = exists & (rho >= abs(self.lateral) - REACH_TOL)[:, None]
            up = self.sign1 * np.where(u >= 0, 1.0, -1.0)[:, None] * sin_b < 0
            t1 = np.broadcast_to(base[:, None], t2.shape)
            columns.append((np.stack([t1, t2, t3], -1), exists, up))
        thetas = np.concatenate([c[0] for c in columns], axis=1)
        exists = np.concatenate([c[1] for c in columns], axis=1)
        up = np.concatenate([c[2] for c in columns], axis=1)
        return BatchBranches(without_missing(thetas, exists, self.offsets), up)


def elbow_label(sign1: float, u: float, sin_b: float) -> str:
    """``"elbow up"`` when the elbow is above the line from shoulder to wrist (world z).

    Args:
        sign1: Sign of ``alpha1`` (the plane's ``y`` is ``sign1 * z0``).
        u: Radial coordinate of the wrist in the arm plane [m] (along the DH ``x1`` axis).
        sin_b: Sine of the elbow angle returned by :func:`two_link`.
    """
    side = sign1 * (1.0 if u >= 0.0 else -1.0) * sin_b
    return "elbow up" if side < 0.0 else "elbow down"


def elbow_branches(
    sign1: float, u: float, v: float, link2: Link, link3: Link, shoulder: str
) -> tuple[list[tuple[float, float, str]], float, str]:
    """The elbow branches ``(t2, t3, label)`` (DH angles [rad]) putting the wrist at ``(u, v)``.

    Args:
        sign1: Sign of ``alpha1`` (the plane's ``y`` is ``sign1 * z0``).
        u: Radial coordinate of the wrist in the arm plane from the shoulder axis [m].
        v: Its height in the arm plane [m].
        link2: The upper arm's in-plane link vector.
        link3: The forearm's (with the tool point, on a three-joint arm).
        shoulder: The shoulder label the elbow labels extend.

    Returns:
        The branches (none out of reach), the distance to the reachable annulus [m] (<= 0 when
        reachable) and ``""`` or why the elbow branches merge (see :func:`~.planar2r.two_link`).
    """
    solutions, gap, singular = two_link(u, v, link2, link3)
    if len(solutions) == 2:
        # the two elbow branches have opposite (non-zero) sin b: one is up, the other down
        (t2, t3, sin_b), (t2_other, t3_other, _) = solutions
        up, down = ELBOW_LABELS[shoulder]
        if elbow_label(sign1, u, sin_b) == "elbow down":
            up, down = down, up
        return [(t2, t3, up), (t2_other, t3_other, down)], gap, singular
    return [(t2, t3, f"{shoulder}, {singular}") for t2, t3, _ in solutions], gap, singular


def solve_offset3r(
    structure: Offset3R, x: float, y: float, z: float, free_t1: float = 0.0
) -> Branches:
    """All branches for a tool point in frame 0.

    Labels: ``"shoulder left"``/``"shoulder right"`` say on which side of the vertical plane through
    the base axis and the target the arm plane lies, seen from above looking at the target
    (``"shoulder front"``/``"shoulder back"`` when there is no lateral offset: the upper arm
    leans towards or away from the target); ``"elbow up"``/``"elbow down"`` say whether the
    elbow is above or below the line from shoulder to wrist.

    Args:
        structure: The arm's parameters.
        x: Tool point in frame 0, x [m].
        y: Tool point in frame 0, y [m].
        z: Tool point in frame 0, z [m].
        free_t1: DH angle of joint 1 [rad] kept when it is free (target on the base axis, no
            lateral offset).
    """
    branches = Branches()
    s, d = structure.sign1, structure.lateral
    rho = math.hypot(x, y)
    v = s * (z - structure.d1)
    if rho < abs(d) - REACH_TOL:
        gap = abs(d) - rho
        return branches.out_of_reach(
            gap,
            f"out of reach by at least {gap:.6g} m: closer to the base axis than the shoulder offset",
        )
    if rho <= REACH_TOL and abs(d) <= REACH_TOL:
        bases = [(free_t1, 0.0)]
        branches.singular("target on the base axis: base yaw is free (seed value kept)")
    else:
        phi = math.atan2(y, x)
        ratio = max(-1.0, min(1.0, s * d / rho))
        delta = math.asin(ratio)
        reach = math.sqrt(max(0.0, rho - abs(d))) * math.sqrt(rho + abs(d))  # no overflow
        if reach <= REACH_TOL:
            bases = [(phi + delta, 0.0)]
            branches.singular(
                "target at the shoulder-offset distance from the base axis: shoulder branches merge"
            )
        else:
            bases = [(phi + delta, reach), (phi + math.pi - delta, -reach)]
    gaps = []
    append = branches.thetas.append
    link2, link3 = structure.link2, structure.link3
    for t1, radial in bases:
        u = radial - structure.a1
        if d == 0.0 and rho <= REACH_TOL:
            shoulder = "shoulder front"
        elif abs(d) <= REACH_TOL:
            shoulder = "shoulder front" if radial >= 0.0 else "shoulder back"
        else:
            shoulder = "shoulder left" if -d * s * radial > 0.0 else "shoulder right"
        elbows, gap, singular = elbow_branches(s, u, v, link2, link3, shoulder)
        gaps.append(gap)
        for t2, t3, label in elbows:
            append(((t1, t2, t3), label))
        if singular and elbows:
            branches.singular(singular)
    if not branches.thetas:
        gap = min(gaps)
        return branches.out_of_reach(
            gap, f"out of reach by {gap:.6g} m (measured in the arm plane)"
        )
    return branches
