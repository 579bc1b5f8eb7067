"""Closed-form IK of the five-joint family: base yaw, three parallel pitch joints, wrist roll.

Shared by ``ned5``, ``lab5`` and ``scorbot`` (with its shoulder offset ``a1``). The roll axis and
the tool point lie in the vertical arm plane through the base axis, so:

1. the base yaw puts that plane through the target (two ways: shoulder front and back);
2. the approach axis ``a`` (the roll axis, wrist to tool) fixes the in-plane angle
   ``phi = theta2 + theta3 + theta4`` and the wrist centre ``p - reach a - a4 x4``;
3. :func:`~.planar2r.two_link` gives ``theta2, theta3`` (elbow up and down), ``theta4`` follows;
4. the wrist roll comes from the target rotation (full pose) or is given (position + pitch).

A full pose is reachable only if ``a`` and ``p`` lie in one vertical plane through the base axis
(5 joints for 6 constraints); other poses are reported, not approximated.

:class:`FiveDof` is a closed-form structure plug-in (:mod:`.closed_form_structure`): base yaw,
three parallel pitch joints and a wrist roll (``alpha1 = +-90``, ``alpha2 = alpha3 = 0``,
``alpha4 = +-90``, ``a5 = 0``) with the tool point on the roll axis and no lateral offset
(``d2 + d3 + d4 = 0``); ``a1`` (SCORBOT shoulder offset) and ``a4`` are allowed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable

from ...targets.target import PitchTarget, PoseTarget, Target
from ..branches import REACH_TOL, Branches
from ..closed_form_structure import BatchBranches, TableStructure
from ..planar.offset3r import elbow_branches, yaw_over_pitch
from ..planar.planar2r import two_link_batch, without_missing
from ..structure import LENGTH_TOL, BaseFrame, Link, near, tool_point

#: Largest out-of-plane component of the approach axis (or target point, [m]) of a reachable pose.
PLANE_TOL = 1e-9


@dataclass(frozen=True)
class FiveDof(TableStructure):
    """Base yaw, three parallel pitch joints, wrist roll; tool point on the roll axis.

    Attributes:
        sign1: Sign of ``alpha1``.
        sign4: Sign of ``alpha4``: the roll axis is at ``theta2 + theta3 + theta4 - sign4 pi/2``
            in the arm plane.
        a1: Radial shoulder offset [m].
        d1: Shoulder height [m].
        link2, link3: In-plane link vectors of the upper arm and forearm.
        a4: Wrist link along ``x4`` [m] (usually 0).
        reach: Distance from the wrist centre (frame 4 origin) to the tool point along the roll
            axis [m] (``d5`` plus the tool's offset along it).
        R_roll_tool: Rotation of the tool in the frame ``Rz(theta5)`` leaves (``Rx(alpha5)`` times
            the tool rotation).
        offsets: DH angle offsets [rad].
        base: DH frame 0 in the world.
        roll_tool_rows: ``R_roll_tool`` as rows of floats, or None when it is the identity
            (derived, for the scalar solver).
    """

    name: ClassVar[str] = "fivedof"
    dof: ClassVar[int] = 5
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget, PitchTarget)
    branch_labels: ClassVar[tuple[str, ...]] = (
        "shoulder 1, elbow +",
        "shoulder 1, elbow -",
        "shoulder 2, elbow +",
        "shoulder 2, elbow -",
    )

    sign1: float
    sign4: float
    a1: float
    d1: float
    link2: Link
    link3: Link
    a4: float
    reach: float
    R_roll_tool: np.ndarray
    roll_tool_rows: tuple[tuple[float, ...], ...] | None = field(
        init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        rows = tuple(tuple(row) for row in np.asarray(self.R_roll_tool, dtype=float).tolist())
        identity = rows == ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        object.__setattr__(self, "roll_tool_rows", None if identity else rows)

    @classmethod
    def recognise(cls, table: DHTable) -> FiveDof:
        """Parameters of a base yaw + three pitch + wrist roll arm.

        Raises:
            StructureError: The table does not have that structure.
        """
        check, sign1 = yaw_over_pitch(table, "five-joint (yaw, 3 pitch, roll)", 5, 2)
        row1, row2, row3, row4, row5 = table.rows
        sign4 = math.copysign(1.0, check.alpha(row4, (math.pi / 2, -math.pi / 2)))
        lateral = row2.d + row3.d + row4.d
        if not near(lateral, 0.0, LENGTH_TOL):
            raise check.fail(
                f"rows 2-4: d2 + d3 + d4 = {lateral:g} m, expected 0 (pitch joints in a plane "
                "through the base axis)"
            )
        check.zero(row5, "a", "the tool point must be on the wrist-roll axis")
        ca, sa = math.cos(row5.alpha), math.sin(row5.alpha)
        rot_x = np.array([[1.0, 0.0, 0.0], [0.0, ca, -sa], [0.0, sa, ca]])
        tool = rot_x @ tool_point(table)
        if math.hypot(tool[0], tool[1]) > LENGTH_TOL:
            raise check.fail(
                f"tool point ({tool[0]:g}, {tool[1]:g}) m off the wrist-roll axis, expected on "
                "the axis"
            )
        return cls(
            sign1=sign1,
            sign4=sign4,
            a1=row1.a,
            d1=row1.d,
            link2=check.link(row2.a, 0.0, f"row 2 ('{row2.name}')"),
            link3=check.link(row3.a, 0.0, f"row 3 ('{row3.name}')"),
            a4=row4.a,
            reach=row5.d + float(tool[2]),
            R_roll_tool=rot_x @ np.asarray(table.T_last_tool[:3, :3], dtype=float),
            offsets=tuple(row.theta for row in table.rows),
            base=BaseFrame.of(table),
        )

    @property
    def approach_in_tool(self) -> tuple[float, float, float]:
        """The approach (roll) axis in the tool frame."""
        x, y, z = self.R_roll_tool[2, :].tolist()
        return x, y, z

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """All branches of a full pose or a pitch target (see :func:`solve_pose`, :func:`solve_pitch`).

        ``seed`` [rad]: joint 1 kept when it is free; the wrist roll of a pitch target without one.
        """
        x, y, z = self.base.point(target.position.tolist())
        free_t1 = seed[0] + self.offsets[0]
        if isinstance(target, PoseTarget):
            r0 = self.base.rotation(target.rotation.tolist())
            return solve_pose(self, (x, y, z), r0, free_t1=free_t1)
        assert isinstance(target, PitchTarget)
        roll = seed[4] if target.roll is None else target.roll
        return solve_pitch(self, (x, y, z), target.pitch, roll + self.offsets[4], free_t1=free_t1)

    def approach(self, target: PitchTarget, seed: Sequence[float]) -> tuple[float, float, float]:
        """The pitch target's approach axis in the world frame."""
        p0 = self.base.point(target.position.tolist())
        rho = math.hypot(p0[0], p0[1])
        angle = math.atan2(p0[1], p0[0]) if rho > 0.0 else seed[0] + self.offsets[0]
        cp = math.cos(target.pitch)
        a = (cp * math.cos(angle), cp * math.sin(angle), -math.sin(target.pitch))
        return self.base.vector_to_world(a)

    def _five(self, p0: np.ndarray, a0: np.ndarray, base1: np.ndarray) -> tuple[np.ndarray, ...]:
        """DH angles (N, 4, 5) (roll 0), existence and elbow side of both shoulders."""
        columns = []
        for base in (base1, base1 + np.pi):
            c1, n1 = np.cos(base), np.sin(base)
            a_r = a0[:, 0] * c1 + a0[:, 1] * n1
            sin_psi = self.sign1 * a0[:, 2]
            cos_phi, sin_phi = -self.sign4 * sin_psi, self.sign4 * a_r
            phi = np.arctan2(sin_phi, cos_phi)
            p_r = p0[:, 0] * c1 + p0[:, 1] * n1
            u = p_r - self.reach * a_r - self.a4 * cos_phi - self.a1
            v = self.sign1 * (p0[:, 2] - self.d1) - self.reach * sin_psi - self.a4 * sin_phi
            t2, t3, sin_b, exists = two_link_batch(u, v, self.link2, self.link3)
            up = self.sign1 * np.where(u >= 0, 1.0, -1.0)[:, None] * sin_b < 0
            t1 = np.broadcast_to(base[:, None], t2.shape)
            t4 = phi[:, None] - t2 - t3
            columns.append((np.stack([t1, t2, t3, t4, np.zeros_like(t2)], -1), exists, up))
        thetas = np.concatenate([c[0] for c in columns], axis=1)
        exists = np.concatenate([c[1] for c in columns], axis=1)
        up = np.concatenate([c[2] for c in columns], axis=1)
        return thetas, exists, up

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """All branches of N full poses: positions (N, 3) [m], rotations (N, 3, 3), world."""
        if rotations is None:
            raise ValueError("a five-joint arm's closed form takes full poses or pitch targets")
        p0 = self.base.points(positions)
        r0 = self.base.rotations(rotations)
        r5 = r0 if self.roll_tool_rows is None else r0 @ self.R_roll_tool.T
        a0 = r5[:, :, 2]
        use_p = np.hypot(p0[:, 0], p0[:, 1]) >= np.hypot(a0[:, 0], a0[:, 1]) * (
            self.link2.length + self.link3.length
        )
        base1 = np.where(use_p, np.arctan2(p0[:, 1], p0[:, 0]), np.arctan2(a0[:, 1], a0[:, 0]))
        normal = np.stack([np.sin(base1), -np.cos(base1)], -1)
        in_plane = (np.abs((a0[:, :2] * normal).sum(-1)) <= PLANE_TOL) & (
            np.abs((p0[:, :2] * normal).sum(-1)) <= PLANE_TOL
        )
        thetas, exists, up = self._five(p0, a0, base1)
        exists = exists & in_plane[:, None]
        # wrist roll: angle from x4 to the roll frame's x axis about the approach axis
        t1, phi = thetas[..., 0], thetas[..., 1] + thetas[..., 2] + thetas[..., 3]
        c1, n1, cp, sp = np.cos(t1), np.sin(t1), np.cos(phi), np.sin(phi)
        x4 = (cp * c1, cp * n1, self.sign1 * sp)
        z4 = (self.sign4 * sp * c1, self.sign4 * sp * n1, -self.sign1 * self.sign4 * cp)
        y4 = (
            z4[1] * x4[2] - z4[2] * x4[1],
            z4[2] * x4[0] - z4[0] * x4[2],
            z4[0] * x4[1] - z4[1] * x4[0],
        )
        x5 = [r5[:, k, 0][:, None] for k in range(3)]
        thetas[..., 4] = np.arctan2(
            y4[0] * x5[0] + y4[1] * x5[1] + y4[2] * x5[2],
            x4[0] * x5[0] + x4[1] * x5[1] + x4[2] * x5[2],
        )
        return BatchBranches(without_missing(thetas, exists, self.offsets), up)

    def pitch_batch_branches(
        self, positions: np.ndarray, pitch: np.ndarray, roll: np.ndarray
    ) -> BatchBranches:
        """All branches of N tool points (N, 3) [m] with approach pitch and wrist roll q5 [rad]."""
        p0 = self.base.points(positions)
        h = np.arctan2(p0[:, 1], p0[:, 0])
        a0 = np.stack([np.cos(pitch) * np.cos(h), np.cos(pitch) * np.sin(h), -np.sin(pitch)], -1)
        thetas, exists, up = self._five(p0, a0, h)
        thetas[..., 4] = (roll + self.offsets[4])[:, None]
        approach = self.base.vectors_to_world(a0)
        return BatchBranches(without_missing(thetas, exists, self.offsets), up, approach)


def _branches(
    structure: FiveDof,
    bases: list[tuple[float, str]],
    p: tuple[float, float, float],
    a: tuple[float, float, float],
    r5: list[list[float]] | None,
    t5: float,
    branches: Branches,
) -> list[float]:
    """Append the elbow branches of each base angle to ``branches``; return the gaps of the wrist centre.

    The wrist roll is ``t5``, or, for a full pose, the angle that turns frame 4 into the roll frame
    ``r5`` (the same for both elbow branches: it depends on ``t1`` and ``phi`` only).
    """
    s, s4 = structure.sign1, structure.sign4
    reach, a4, a1 = structure.reach, structure.a4, structure.a1
    link2, link3 = structure.link2, structure.link3
    px, py, pz = p
    ax, ay, a_z = a
    height = s * (pz - structure.d1)
    # in-plane approach angle psi: (cos psi, sin psi) = (a . e_r, s a_z); x4 at phi = psi + s4 pi/2
    sin_psi = s * a_z
    cos_phi = -s4 * sin_psi
    if r5 is not None:
        rx, ry, rz = r5[0][0], r5[1][0], r5[2][0]
    append = branches.thetas.append
    gaps = []
    for t1, shoulder in bases:
        c1, n1 = math.cos(t1), math.sin(t1)
        a_r = ax * c1 + ay * n1  # approach along e_r
        sin_phi = s4 * a_r
        phi = math.atan2(sin_phi, cos_phi)
        # wrist centre O3 = p - reach a - a4 x4 in plane coordinates (u along e_r from the shoulder, v up)
        p_r = px * c1 + py * n1
        u = p_r - reach * a_r - a4 * cos_phi - a1
        v = height - reach * sin_psi - a4 * sin_phi
        elbows, gap, singular = elbow_branches(s, u, v, link2, link3, shoulder)
        gaps.append(gap)
        if not elbows:
            continue
        if r5 is not None:
            # the roll is the angle of x5 = r5[:, 0] in the (x4, y4) plane; in frame 0,
            # x4 = (cos phi e_r, s sin phi) and y4 = z4 x x4 = s s4 (sin t1, -cos t1, 0)
            t5 = math.atan2(
                s * s4 * (n1 * rx - c1 * ry),
                math.cos(phi) * (c1 * rx + n1 * ry) + s * math.sin(phi) * rz,
            )
        for t2, t3, label in elbows:
            append(((t1, t2, t3, phi - t2 - t3, t5), label))
        if singular:
            branches.singular(singular)
    return gaps


def _finish(structure: FiveDof, branches: Branches, gaps: list[float]) -> Branches:
    if not branches.thetas and branches.status != "out_of_reach":
        gap = min(gaps) if gaps else 0.0
        branches.out_of_reach(
            gap, f"out of reach by {gap:.6g} m (wrist centre outside the arm's annulus)"
        )
    return branches


def solve_pose(
    structure: FiveDof,
    p: tuple[float, float, float],
    r_tool: list[list[float]],
    free_t1: float = 0.0,
) -> Branches:
    """All branches for a full tool pose in frame 0.

    Args:
        structure: The arm's parameters.
        p: Tool point in frame 0 [m].
        r_tool: Tool rotation in frame 0 (rows).
        free_t1: DH angle of joint 1 [rad] kept when it is free (tool point and approach axis on
            the base axis).
    """
    branches = Branches()
    rt = structure.roll_tool_rows
    # roll frame r5 = r_tool rt^T; its z column is the approach axis
    if rt is None:
        r5 = r_tool
    else:
        r5 = [[sum(r_tool[i][k] * rt[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    a = (r5[0][2], r5[1][2], r5[2][2])
    # the arm plane contains p, a and the base axis: take its direction from the largest of them
    scale = (
        structure.link2.length + structure.link3.length + abs(structure.reach) + abs(structure.a4)
    )
    rho = math.hypot(p[0], p[1])
    size, dx, dy = max((rho, p[0], p[1]), (scale * math.hypot(a[0], a[1]), a[0], a[1]))
    if size <= REACH_TOL:
        bases = [(free_t1, "shoulder front")]
        branches.singular(
            "tool point and approach axis on the base axis: base yaw is free (seed value kept)"
        )
    else:
        t1 = math.atan2(dy, dx)
        c1, n1 = math.cos(t1), math.sin(t1)
        front = (p[0] * c1 + p[1] * n1) >= 0.0 or rho <= REACH_TOL
        bases = [
            (t1, "shoulder front" if front else "shoulder back"),
            (t1 + math.pi, "shoulder back" if front else "shoulder front"),
        ]
        normal = (n1, -c1)
        off_axis = abs(a[0] * normal[0] + a[1] * normal[1])
        off_point = abs(p[0] * normal[0] + p[1] * normal[1])
        if off_axis > PLANE_TOL or off_point > PLANE_TOL:
            return branches.out_of_reach(
                off_point if off_point > PLANE_TOL else None,
                f"pose not reachable by a five-joint arm: the approach axis is "
                f"{math.degrees(math.asin(min(1.0, off_axis))):.4g} deg and the tool point {off_point:.3g} m "
                "out of the vertical plane through the base axis that contains them",
            )
    return _finish(structure, branches, _branches(structure, bases, p, a, r5, 0.0, branches))


def solve_pitch(
    structure: FiveDof,
    p: tuple[float, float, float],
    pitch: float,
    t5: float,
    free_t1: float = 0.0,
) -> Branches:
    """All branches for a tool point in frame 0 with the approach pitch (see :class:`PitchTarget`).

    Args:
        structure: The arm's parameters.
        p: Tool point in frame 0 [m].
        pitch: Approach angle below the horizontal, away from the base axis [rad].
        t5: DH angle of the wrist roll [rad] (``q5 + theta5``).
        free_t1: DH angle of joint 1 [rad] used when the target is on the base axis (the pitch is
            then measured from that joint's radial direction).
    """
    branches = Branches()
    rho = math.hypot(p[0], p[1])
    if rho <= REACH_TOL:
        h_angle = free_t1
        bases = [(free_t1, "shoulder front")]
        branches.singular("target on the base axis: base yaw is free (seed value kept)")
    else:
        h_angle = math.atan2(p[1], p[0])
        bases = [(h_angle, "shoulder front"), (h_angle + math.pi, "shoulder back")]
    cp, sp = math.cos(pitch), math.sin(pitch)
    a = (cp * math.cos(h_angle), cp * math.sin(h_angle), -sp)
    return _finish(structure, branches, _branches(structure, bases, p, a, None, t5, branches))
