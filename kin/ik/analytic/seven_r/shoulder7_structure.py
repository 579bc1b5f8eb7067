"""The structure of 7R arms with a spherical shoulder and two meeting wrist axes (Panda, xArm7).

:func:`spherical_shoulder7` recognises it in a DH table (either convention, any base and tool):
axes 1, 2 and 3 meet in one point ``S`` (the shoulder), joint 4 is an elbow, axes 5 and 6 meet in
one point ``W``; joint 7 is general. It rewrites the chain ``M_1 Rz(t_1) M_2 ... M_7 Rz(t_7) M_8``
(see :mod:`.spherical_shoulder7`, which solves it) and reads the points the closed form needs.
Lengths in [m], angles in [rad].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from dh2urdf import DHRow, DHTable
from dh2urdf.transforms import rot_x, translation

from ..structure import ANGLE_TOL, LENGTH_TOL, Checker, deg

#: Solver name in :class:`~kin.ik.exceptions.StructureError` messages.
SOLVER = "seven-joint (spherical shoulder, wrist axes 5-6 meeting, joint 7 free)"
#: Tolerance [m] of the computed shoulder and wrist points on their axes (a sanity check: the
#: table's lengths are checked exactly, within :data:`~.structure.LENGTH_TOL`).
POINT_TOL = 1e-9
Vec = tuple[float, float, float]


def joint_factors(table: DHTable) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(L_i, R_i)`` (4x4) of every row: joint ``i`` is ``L_i Rz(q_i + theta_i) R_i``."""
    eye = np.eye(4)
    if table.convention == "modified":
        return [(rot_x(r.alpha) @ translation(x=r.a, z=r.d), eye) for r in table.rows]
    return [(translation(z=r.d), translation(x=r.a) @ rot_x(r.alpha)) for r in table.rows]


@dataclass(frozen=True, eq=False)
class SphericalShoulder7R:
    """A 7R arm whose axes 1-3 meet at a shoulder point and axes 5, 6 at a wrist point.

    Attributes:
        frames: ``M_1 .. M_8`` (4x4, [m]): the fixed transforms between the joint rotations.
        offsets: DH angle offsets ``theta_1 .. theta_7`` [rad] (DH angle = q + offset).
        shoulder: ``S`` on axis 1, in frame ``K`` (``M_1``): ``(0, 0, z)`` [m].
        shoulder3: ``S`` in frame ``J_3`` [m] (on axis 3).
        wrist4: ``W`` in frame ``J_4`` [m].
        wrist6: ``W`` in frame ``J_6`` [m] (on axis 6).
    """

    frames: tuple[np.ndarray, ...] = field(repr=False)
    offsets: tuple[float, ...]
    shoulder: Vec
    shoulder3: Vec
    wrist4: Vec
    wrist6: Vec

    @property
    def twists(self) -> tuple[float, ...]:
        """``alpha_i'`` [rad] of ``M_i = (Rx(alpha_i'), translation)``, index ``i`` = 2 .. 7.

        Indices 0 and 1 are unused (0.0): ``M_1`` and ``M_8`` hold the base and the tool.
        """
        return (0.0, 0.0) + tuple(math.atan2(m[2, 1], m[1, 1]) for m in self.frames[1:7])


def spherical_shoulder7(table: DHTable) -> SphericalShoulder7R:
    """Recognise a :class:`SphericalShoulder7R` table and read its parameters.

    Raises:
        StructureError: Not seven revolute joints; axes 1-3 not meeting in one point (row and
            parameter named); axes 5, 6 not meeting; consecutive axes of the shoulder or the wrist
            parallel; the shoulder or the wrist point on the elbow axis.
    """
    check = Checker(table, SOLVER)
    check.revolute(7)
    rows = table.rows
    modified = table.convention == "modified"

    def between(axis: int) -> DHRow:
        """The row holding the common normal (a, alpha) of axes ``axis`` and ``axis + 1``."""
        return rows[axis] if modified else rows[axis - 1]

    for axis, what in ((1, "shoulder"), (2, "shoulder"), (5, "wrist")):
        row = between(axis)
        why = f"axes {axis} and {axis + 1} must meet at the {what} point"
        check.zero(row, "a", why)
        if abs(math.sin(row.alpha)) <= ANGLE_TOL:
            raise check.fail(
                f"row {row.index} ('{row.name}'): alpha = {deg(row.alpha)}, expected an angle "
                f"other than 0 or 180 deg (axes {axis} and {axis + 1} must not be parallel)"
            )
    check.zero(rows[1], "d", "axes 1, 2 and 3 must meet in one point")

    factors = joint_factors(table)
    frames = [np.asarray(table.T_world_base, dtype=float) @ factors[0][0]]
    frames += [factors[i - 1][1] @ factors[i][0] for i in range(1, 7)]
    frames.append(factors[6][1] @ np.asarray(table.T_last_tool, dtype=float))
    shoulder = _meeting(frames[1])  # axes 1 and 2, in K
    shoulder2 = inverse_point(frames[1], shoulder)
    shoulder3 = inverse_point(frames[2], shoulder2)
    wrist5 = _meeting(frames[5])  # axes 5 and 6, in J_5
    wrist6 = inverse_point(frames[5], wrist5)
    for point, where in ((shoulder2, "axis 2"), (shoulder3, "axis 3"), (wrist6, "axis 6")):
        if math.hypot(point[0], point[1]) > POINT_TOL:  # pragma: no cover - exact checks above
            raise check.fail(f"the computed {where} point is off its axis")
    wrist4 = tuple((frames[4] @ (*wrist5, 1.0))[:3].tolist())
    u = inverse_point(frames[3], shoulder3)  # S just before Rz(t4)
    for point, what in ((u, "shoulder"), (wrist4, "wrist")):
        if math.hypot(point[0], point[1]) <= LENGTH_TOL:
            raise check.fail(
                f"the {what} point lies on axis 4: the elbow does not change the "
                "shoulder-wrist distance"
            )
    return SphericalShoulder7R(
        frames=tuple(frames),
        offsets=tuple(row.theta for row in rows),
        shoulder=shoulder,
        shoulder3=shoulder3,
        wrist4=(wrist4[0], wrist4[1], wrist4[2]),
        wrist6=wrist6,
    )


def _meeting(frame: np.ndarray) -> Vec:
    """Where the next axis (z of ``frame``, seen from its parent) meets the parent's z axis."""
    p, z = frame[:3, 3], frame[:3, 2]
    # p + s z on the parent's z axis: p_xy + s z_xy = 0 (least squares; z_xy != 0).
    s = -float(p[:2] @ z[:2]) / float(z[:2] @ z[:2])
    return 0.0, 0.0, float(p[2] + s * z[2])


def inverse_point(frame: np.ndarray, point: Sequence[float]) -> Vec:
    """A parent-frame point seen from ``frame`` (4x4): ``frame^-1 point``."""
    x, y, z = (frame[:3, :3].T @ (np.asarray(point, dtype=float) - frame[:3, 3])).tolist()
    return x, y, z
