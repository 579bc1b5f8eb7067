"""Batched forward kinematics of a DH table in NumPy: many joint vectors at once, no Pinocchio.

For the work that needs FK of thousands to millions of configurations (workspace sampling, table
audits, batched IK verification), where a Pinocchio call per configuration costs microseconds of
Python each. The product is the table's own (``T_world_base``, one DH transform per row in its
convention, ``T_last_tool``), computed column by column on arrays of length N; the tests check it
against Pinocchio's FK of the generated URDF and against an independent DH product.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from .exceptions import JointVectorError


def _joint_array(table: DHTable, q: npt.ArrayLike) -> np.ndarray:
    array = np.asarray(q, dtype=float)
    if array.ndim not in (1, 2) or array.shape[-1] != table.dof:
        raise JointVectorError(
            f"'{table.name}' has {table.dof} joints: joint vectors must have shape "
            f"(N, {table.dof}), got {array.shape}",
            expected=table.dof,
            got=int(array.shape[-1]) if array.ndim else 0,
        )
    return array.reshape(-1, table.dof)


def batch_forward_kinematics(
    table: DHTable, q: npt.ArrayLike, *, frames: bool = False
) -> np.ndarray:
    """Poses of the tool (or of every DH frame and the tool) for N joint vectors.

    Args:
        table: The DH table (SI units).
        q: Joint vectors, shape (N, dof) or (dof,) [rad] for revolute, [m] for prismatic joints.
        frames: False: only the tool. True: DH frames 0..dof and the tool.

    Returns:
        ``T_world_tool`` of shape (N, 4, 4); with ``frames``, (N, dof + 2, 4, 4) holding
        ``T_world_frame0 .. T_world_frame{dof}, T_world_tool`` (world = the URDF root).

    Raises:
        JointVectorError: ``q`` does not have ``dof`` columns.
    """
    q = _joint_array(table, q)
    n = q.shape[0]
    base = np.asarray(table.T_world_base, dtype=float)
    ones = np.ones(n)
    cols = [base[:3, j][:, None] * ones for j in range(3)]  # rotation columns, each (3, N)
    p = base[:3, 3][:, None] * ones
    stored: list[tuple[list[np.ndarray], np.ndarray]] = [(cols, p)] if frames else []
    modified = table.convention == "modified"
    for i, row in enumerate(table.rows):
        if row.joint_type == "prismatic":
            ct, st = math.cos(row.theta), math.sin(row.theta)
            d: float | np.ndarray = q[:, i] + row.d
        else:
            angle = q[:, i] + row.theta
            ct, st = np.cos(angle), np.sin(angle)  # type: ignore[assignment]
            d = row.d
        ca, sa = math.cos(row.alpha), math.sin(row.alpha)
        c0, c1, c2 = cols
        if modified:  # Rx(alpha) Tx(a) Rz(theta) Tz(d)
            if row.a != 0.0:
                p = p + row.a * c0
            c1, c2 = c1 * ca + c2 * sa, c2 * ca - c1 * sa
            c0, c1 = c0 * ct + c1 * st, c1 * ct - c0 * st
            p = p + d * c2
        else:  # Rz(theta) Tz(d) Tx(a) Rx(alpha)
            c0, c1 = c0 * ct + c1 * st, c1 * ct - c0 * st
            p = p + d * c2
            if row.a != 0.0:
                p = p + row.a * c0
            c1, c2 = c1 * ca + c2 * sa, c2 * ca - c1 * sa
        cols = [c0, c1, c2]
        if frames:
            stored.append((cols, p))
    tool = np.asarray(table.T_last_tool, dtype=float)
    tool_cols = [sum(cols[k] * tool[k, j] for k in range(3)) for j in range(3)]
    tool_p = p + sum(cols[k] * tool[k, 3] for k in range(3))
    stored.append((tool_cols, tool_p))  # type: ignore[arg-type]
    if not frames:
        stored = stored[-1:]
    out = np.zeros((n, len(stored), 4, 4))
    for f, (frame_cols, frame_p) in enumerate(stored):
        for j in range(3):
            out[:, f, :3, j] = frame_cols[j].T
        out[:, f, :3, 3] = frame_p.T
    out[:, :, 3, 3] = 1.0
    return out if frames else out[:, 0]


def batch_tool_positions(table: DHTable, q: npt.ArrayLike) -> np.ndarray:
    """Tool points ``p_world_tool`` (N, 3) [m] of N joint vectors.

    See :func:`batch_forward_kinematics` for the arguments.
    """
    return batch_forward_kinematics(table, q)[:, :3, 3]
