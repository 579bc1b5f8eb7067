"""Closed-form IK of the five-joint family: base yaw, three parallel pitch joints, wrist roll.

Shared by ``ned5``, ``lab5`` and ``scorbot`` (with its shoulder offset ``a1``). The roll axis and
the tool point lie in the vertical arm plane through the base axis, so:

1. the base yaw puts that plane through the target (two ways: shoulder front and back);
2. the approach axis ``a`` (the roll axis, wrist to tool) fixes the in-plane angle
   ``phi = theta2 + theta3 + theta4`` and the wrist centre ``p - reach a - a4 x4``;
3. :func:`~ik.planar2r.two_link` gives ``theta2, theta3`` (elbow up and down), ``theta4`` follows;
4. the wrist roll comes from the target rotation (full pose) or is given (position + pitch).

A full pose is reachable only if ``a`` and ``p`` lie in one vertical plane through the base axis
(5 joints for 6 constraints); other poses are reported, not approximated.
"""

from __future__ import annotations

import math

from .branches import REACH_TOL, Branches
from .offset3r import ELBOW_LABELS, elbow_label
from .planar2r import MERGE_COS, two_link
from .structure import FiveDof

#: Largest out-of-plane component of the approach axis (or target point, [m]) of a reachable pose.
PLANE_TOL = 1e-9


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
    l1, l2, angle1, angle2 = link2.length, link3.length, link2.angle, link3.angle
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
        # two_link's usual case inlined (same expressions, same values); the rest goes through it
        r = math.hypot(u, v)
        gap = max(r - (l1 + l2), abs(l1 - l2) - r)
        gaps.append(gap)
        if gap > REACH_TOL:
            continue
        if r5 is not None:
            # the roll is the angle of x5 = r5[:, 0] in the (x4, y4) plane; in frame 0,
            # x4 = (cos phi e_r, s sin phi) and y4 = z4 x x4 = s s4 (sin t1, -cos t1, 0)
            t5 = math.atan2(
                s * s4 * (n1 * rx - c1 * ry),
                math.cos(phi) * (c1 * rx + n1 * ry) + s * math.sin(phi) * rz,
            )
        cos_b = (u * u + v * v - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
        if abs(cos_b) < MERGE_COS and r > REACH_TOL:
            sin_b = math.sqrt(1.0 - cos_b * cos_b)
            base, k1, k2 = math.atan2(v, u), l1 + l2 * cos_b, l2 * sin_b
            t2, t2_other = base - math.atan2(k2, k1) - angle1, base - math.atan2(-k2, k1) - angle1
            b = math.atan2(sin_b, cos_b)
            t3, t3_other = b - angle2 + angle1, -b - angle2 + angle1
            # the two elbow branches have opposite (non-zero) sin b: one is up, the other down
            up, down = ELBOW_LABELS[shoulder]
            if (
                s * (1.0 if u >= 0.0 else -1.0) * sin_b < 0.0
            ):  # elbow_label(s, u, sin_b) == "elbow up"
                up, down = down, up
            append(((t1, t2, t3, phi - t2 - t3, t5), down))
            append(((t1, t2_other, t3_other, phi - t2_other - t3_other, t5), up))
            continue
        solutions, _, singular = two_link(u, v, link2, link3)
        if len(solutions) == 2:
            (t2, t3, sin_b), (t2_other, t3_other, _) = solutions
            elbow = elbow_label(s, u, sin_b)
            append(((t1, t2, t3, phi - t2 - t3, t5), f"{shoulder}, {elbow}"))
            elbow = "elbow down" if elbow == "elbow up" else "elbow up"
            append(
                ((t1, t2_other, t3_other, phi - t2_other - t3_other, t5), f"{shoulder}, {elbow}")
            )
        else:
            for t2, t3, _ in solutions:
                append(((t1, t2, t3, phi - t2 - t3, t5), f"{shoulder}, {singular}"))
        if singular and solutions:
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
