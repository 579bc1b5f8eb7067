"""Batched forward kinematics of a DH table in NumPy: many joint vectors at once, no Pinocchio.

For the work that needs FK of thousands to millions of configurations (workspace sampling, table
audits, batched IK verification), where a Pinocchio call per configuration costs microseconds of
Python each. The product is the table's own (``T_world_base``, one DH transform per row in its
convention, the DH angle ``theta + direction * q`` or length ``d + direction * q``, a row's
Hayati tilt ``Ry(beta)`` after its twist (:mod:`dh2urdf.dh_table`), ``T_last_tool``), computed column by column on arrays of length N; the tests check it
against Pinocchio's FK of the generated URDF and against an independent DH product.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from .exceptions import JointVectorError

#: Joint vectors per block: the block's arrays stay in the CPU cache (faster than one pass).
_BLOCK = 8192


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


def _rotation_terms(angle: float) -> tuple[float, float]:
    """Cos and sin of a fixed angle, exact at multiples of 90 deg (so products can be skipped)."""
    c, s = math.cos(angle), math.sin(angle)
    return (0.0 if abs(c) < 1e-15 else c), (0.0 if abs(s) < 1e-15 else s)


def _rotate(u: np.ndarray, v: np.ndarray, c, s) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """``(u c + v s, v c - u s)``, without the products by exact 0 and 1 (fixed twists)."""
    if isinstance(c, float) and c == 0.0:  # +-90 deg: a swap with a sign
        return (v, -u) if s > 0 else (-v, u)
    if isinstance(s, float) and s == 0.0:
        return (u, v) if c > 0 else (-u, -v)
    return u * c + v * s, v * c - u * s


def _chain(table: DHTable, q: np.ndarray, keep: frozenset[int] | None):
    """Yield ``(k, cols, p)`` of DH frames ``k`` in ``keep`` (all if None) and the tool (k = -1).

    ``cols`` are the rotation columns and ``p`` the origin of ``T_world_frame``, each (3, N).
    """
    n = q.shape[0]
    base = np.asarray(table.T_world_base, dtype=float)
    ones = np.ones(n)
    cols = [base[:3, j][:, None] * ones for j in range(3)]  # rotation columns, each (3, N)
    p = base[:3, 3][:, None] * ones
    if keep is None or 0 in keep:
        yield 0, cols, p
    modified = table.convention == "modified"
    for i, row in enumerate(table.rows):
        value = q[:, i] if row.direction == 1 else -q[:, i]  # a reversed row: -q
        if row.joint_type == "prismatic":
            ct, st = _rotation_terms(row.theta)
            d: float | np.ndarray = value + row.d
        else:
            angle = value + row.theta
            ct, st = np.cos(angle), np.sin(angle)  # type: ignore[assignment]
            d = row.d
        ca, sa = _rotation_terms(row.alpha)
        c0, c1, c2 = cols
        if modified:  # Rx(alpha) Ry(beta) Tx(a) Rz(theta) Tz(d)
            c1, c2 = _rotate(c1, c2, ca, sa)
            if row.beta != 0.0:
                c2, c0 = _rotate(c2, c0, *_rotation_terms(row.beta))
            if row.a != 0.0:
                p = p + row.a * c0
            c0, c1 = _rotate(c0, c1, ct, st)
            p = p + d * c2
        else:  # Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta)
            c0, c1 = _rotate(c0, c1, ct, st)
            if not (isinstance(d, float) and d == 0.0):
                p = p + d * c2
            if row.a != 0.0:
                p = p + row.a * c0
            c1, c2 = _rotate(c1, c2, ca, sa)
            if row.beta != 0.0:  # Ry(beta): (c0, c2) -> (c0 cb - c2 sb, c2 cb + c0 sb)
                c2, c0 = _rotate(c2, c0, *_rotation_terms(row.beta))
        cols = [c0, c1, c2]
        if keep is None or i + 1 in keep:
            yield i + 1, cols, p
    tool = np.asarray(table.T_last_tool, dtype=float)
    tool_cols = [sum(cols[k] * tool[k, j] for k in range(3)) for j in range(3)]
    tool_p = p + sum(cols[k] * tool[k, 3] for k in range(3))
    yield -1, tool_cols, tool_p


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
    out = np.zeros((n, table.dof + 2 if frames else 1, 4, 4))
    keep: frozenset[int] | None = None if frames else frozenset()
    for start in range(0, n, _BLOCK):
        block = out[start : start + _BLOCK]
        for f, (_, frame_cols, frame_p) in enumerate(
            _chain(table, q[start : start + _BLOCK], keep)
        ):
            for j in range(3):
                block[:, f, :3, j] = frame_cols[j].T
            block[:, f, :3, 3] = frame_p.T
    out[:, :, 3, 3] = 1.0
    return out if frames else out[:, 0]


def batch_frame_origins(
    table: DHTable, q: npt.ArrayLike, frames: tuple[int, ...] = ()
) -> tuple[np.ndarray, ...]:
    """Origins of DH frames ``frames`` and of the tool, without building the 4x4 poses.

    Args:
        table: The DH table (SI units).
        q: Joint vectors (N, dof) or (dof,) [rad] / [m].
        frames: DH frame numbers 0..dof whose origins are wanted, besides the tool.

    Returns:
        ``p_world_frame{k}`` for each ``k`` in ``frames``, then ``p_world_tool``, each (3, N) [m]
        (coordinates first: rows x, y, z).
    """
    q = _joint_array(table, q)
    out = np.empty((len(frames) + 1, 3, q.shape[0]))
    order = {k: i for i, k in enumerate(frames)} | {-1: len(frames)}
    for start in range(0, q.shape[0], _BLOCK):
        for k, _, p in _chain(table, q[start : start + _BLOCK], frozenset(frames)):
            out[order[k], :, start : start + _BLOCK] = p
    return tuple(out)


def batch_tool_positions(table: DHTable, q: npt.ArrayLike) -> np.ndarray:
    """Tool points ``p_world_tool`` (N, 3) [m] of N joint vectors.

    See :func:`batch_forward_kinematics` for the arguments.
    """
    return batch_frame_origins(table, q)[-1].T
