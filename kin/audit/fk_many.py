"""Forward kinematics of many variants of one table at once: readings x samples in one pass.

The readings of a table differ in their DH values, convention, base and tool, never in the
number or the types of their joints; :func:`many_tool_poses` stacks them and their joint vectors
into arrays of length ``R * N`` and runs the DH product column by column over all of them (both
conventions computed, each reading keeping its own), the way :func:`kin.batch_forward_kinematics`
does for one table. Tests check the two against each other.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from dh2urdf import DHTable


def _rotate(u: np.ndarray, v: np.ndarray, c: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, ...]:
    """Axes ``u``, ``v`` (3, M) turned by the angle of cosine ``c``, sine ``s`` about ``u x v``."""
    return u * c + v * s, v * c - u * s


def many_tool_poses(tables: Sequence[DHTable], q: np.ndarray) -> np.ndarray:
    """Tool poses ``T_world_tool`` (R, N, 4, 4) [m] of R variants of one table at their q.

    Args:
        tables: R tables with the same joints (number and types), SI values.
        q: Joint values (R, N, dof) [rad, m]: one set of N joint vectors per table.
    """
    r_count, n, dof = q.shape
    first = tables[0]
    m = r_count * n

    def per_sample(values: np.ndarray) -> np.ndarray:  # (R,) -> (M,)
        return np.repeat(values, n)

    base = np.stack([t.T_world_base for t in tables])  # (R, 4, 4)
    tool = np.stack([t.T_last_tool for t in tables])
    cols = [np.repeat(base[:, :3, j].T, n, axis=1) for j in range(3)]  # each (3, M)
    p = np.repeat(base[:, :3, 3].T, n, axis=1)
    modified = per_sample(np.array([t.convention == "modified" for t in tables]))
    joints = q.reshape(m, dof)
    for i, row in enumerate(first.rows):
        a = per_sample(np.array([t.rows[i].a for t in tables]))
        alpha = per_sample(np.array([t.rows[i].alpha for t in tables]))
        d = per_sample(np.array([t.rows[i].d for t in tables]))
        theta = per_sample(np.array([t.rows[i].theta for t in tables]))
        beta = np.array([t.rows[i].beta for t in tables])  # Hayati's tilt (dh2urdf.dh_table)
        value = joints[:, i] * per_sample(np.array([float(t.rows[i].direction) for t in tables]))
        if row.joint_type == "prismatic":
            d = d + value
        else:
            theta = theta + value
        ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
        c0, c1, c2 = cols
        # standard: Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta)
        s0, s1 = _rotate(c0, c1, ct, st)
        sp = p + d * c2 + a * s0
        s1, s2 = _rotate(s1, c2, ca, sa)
        # modified: Rx(alpha) Ry(beta) Tx(a) Rz(theta) Tz(d)
        m0 = c0
        m1, m2 = _rotate(c1, c2, ca, sa)
        if beta.any():
            cb, sb = np.cos(per_sample(beta)), np.sin(per_sample(beta))
            s2, s0 = _rotate(s2, s0, cb, sb)
            m2, m0 = _rotate(m2, m0, cb, sb)
        mp = p + a * m0
        m0, m1 = _rotate(m0, m1, ct, st)
        mp = mp + d * m2
        cols = [np.where(modified, m0, s0), np.where(modified, m1, s1), np.where(modified, m2, s2)]
        p = np.where(modified, mp, sp)
    tool_m = np.repeat(tool, n, axis=0)  # (M, 4, 4)
    out = np.zeros((m, 4, 4))
    for j in range(3):
        out[:, :3, j] = sum(cols[k] * tool_m[:, k, j] for k in range(3)).T
    out[:, :3, 3] = (p + sum(cols[k] * tool_m[:, k, 3] for k in range(3))).T
    out[:, 3, 3] = 1.0
    return out.reshape(r_count, n, 4, 4)
