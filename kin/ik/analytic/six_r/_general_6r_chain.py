"""The chain of a general 6R arm: its constant transforms, forward kinematics, polish and merge.

What :mod:`.general_6r` does with the elimination's candidates (:mod:`._general_6r_elimination`):
the chain ``T_world_tool(u) = F0 Rz(u1) F1 ... Rz(u6) F6`` of the DH joint variables ``u``
[rad], Newton steps onto a target pose (:func:`polish`) and the distinct branches of a pose
(:func:`distinct`). ``kin/_native/ik/analytic/six_r/_general6r.c`` repeats them for its first pass.
"""

from __future__ import annotations

import math

import numpy as np

from dh2urdf import DHTable

from ...result import SAME_BRANCH
from ._stacked_transforms import SMALL_STACK, rot_z, times, times_rz

#: Number of branches (columns of :meth:`.General6R.solve`): a 6R arm has at most 16.
BRANCHES = 16
#: Newton steps of the polish, and the error it stops at [m, rad] (most roots start below it).
NEWTON_STEPS = 8
NEWTON_TOL = 1e-12
#: Two branches closer than this in every joint (modulo 2 pi) [rad] are one: the library's rule
#: of one branch (:data:`kin.ik.result.SAME_BRANCH`). 1e-7 kept two polished copies of one PiPER
#: branch 1.4e-7 rad apart on one machine (a ninth branch where the spherical-wrist family has 8).
SAME_TOL = SAME_BRANCH


def _rot_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    out = np.eye(4)
    out[1:3, 1:3] = [[c, -s], [s, c]]
    return out


def _trans(x: float = 0.0, z: float = 0.0) -> np.ndarray:
    out = np.eye(4)
    out[0, 3], out[2, 3] = x, z
    return out


def chain_transforms(table: DHTable) -> tuple[np.ndarray, np.ndarray]:
    """The constant transforms ``F0 .. F6`` (7, 4, 4) [m] and the joint directions (6,).

    ``T_world_tool(q) = F0 Rz(s1 q1) F1 ... Rz(s6 q6) F6`` with ``s_i`` the row's direction
    (+-1): the base and a modified row's ``Rx(alpha) Tx(a)`` before the joint, the offset
    ``theta`` into the transform before the joint, the tool into ``F6``.
    """
    F = [np.array(table.T_world_base, dtype=float)] + [np.eye(4) for _ in range(6)]
    signs = np.ones(6)
    for i, row in enumerate(table.rows):
        signs[i] = float(getattr(row, "direction", 1) or 1)
        if table.convention == "modified":
            F[i] = F[i] @ _rot_x(row.alpha) @ _trans(x=row.a) @ rot_z(row.theta)
            F[i + 1] = _trans(z=row.d)
        else:
            F[i] = F[i] @ rot_z(row.theta)
            F[i + 1] = _trans(z=row.d) @ _trans(x=row.a) @ _rot_x(row.alpha)
    F[6] = F[6] @ np.array(table.T_last_tool, dtype=float)
    return np.stack(F), signs


def forward(F: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tool poses (..., 4, 4), joint axes and joint origins (..., 6, 3) in the world [m].

    ``u`` (..., 6) [rad] are the DH joint variables (``s_i q_i``).
    """
    axes = np.empty(u.shape[:-1] + (6, 3))
    origins = np.empty(u.shape[:-1] + (6, 3))
    small = u.size <= 6 * SMALL_STACK  # the Rz of every joint at once, then matmuls
    R = rot_z(u) if small else None
    T = F[0]  # (4, 4): broadcast by the products
    for i in range(6):
        axes[..., i, :] = T[..., :3, 2]
        origins[..., i, :] = T[..., :3, 3]
        T = (
            T @ R[..., i, :, :] @ F[i + 1]
            if R is not None
            else times(times_rz(T, u[..., i]), F[i + 1])
        )
    return T, axes, origins


def _errors(T: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Error vectors (M, 6) of poses to targets, and the largest of each (M,).

    Position [m] and small-angle rotation [rad]; the largest is ``inf`` when the rotation is
    more than 90 deg off.
    """
    E = target[:, :3, :3] @ np.swapaxes(T[:, :3, :3], 1, 2)
    e = np.empty((T.shape[0], 6))
    np.subtract(target[:, :3, 3], T[:, :3, 3], out=e[:, :3])
    np.subtract(E[:, 2, 1], E[:, 1, 2], out=e[:, 3])
    np.subtract(E[:, 0, 2], E[:, 2, 0], out=e[:, 4])
    np.subtract(E[:, 1, 0], E[:, 0, 1], out=e[:, 5])
    e[:, 3:] *= 0.5
    size = np.abs(e).max(axis=1)
    trace = E[:, 0, 0] + E[:, 1, 1] + E[:, 2, 2]
    return e, np.where(trace > 1.0, size, np.inf)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross products of (..., 3) vectors (faster than ``np.cross`` on small stacks)."""
    return np.stack(
        (
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ),
        axis=-1,
    )


#: The damping of the polish's normal equations (keeps an exact singularity solvable).
_DAMPING = 1e-14 * np.eye(6)


def polish(F: np.ndarray, u: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Newton steps of DH joint variables ``u`` (M, 6) [rad] towards targets ``target`` (M, 4, 4).

    Each row stops once on target to :data:`NEWTON_TOL` or off it by more than 1 (m or rad,
    a root that is not one). Returns the polished ``u`` wrapped to [-pi, pi) and the largest
    error of each row (M,) [m or rad].
    """
    u = np.array(u, dtype=float)
    error = np.full(u.shape[0], np.inf)
    rows = np.arange(u.shape[0])
    for step in range(NEWTON_STEPS + 1):
        T, axes, origins = forward(F, u[rows])
        e, size = _errors(T, target[rows])
        error[rows] = size
        go = (size > NEWTON_TOL) & (size < 1.0)
        if step == NEWTON_STEPS or not go.any():
            break
        rows, e, T, axes, origins = rows[go], e[go], T[go], axes[go], origins[go]
        J = np.empty((rows.size, 6, 6))
        J[:, :3, :] = np.swapaxes(_cross(axes, T[:, None, :3, 3] - origins), 1, 2)
        J[:, 3:, :] = np.swapaxes(axes, 1, 2)
        JJt = J @ np.swapaxes(J, 1, 2) + _DAMPING
        delta = (np.swapaxes(J, 1, 2) @ np.linalg.solve(JJt, e[..., None]))[..., 0]
        u[rows] += np.clip(delta, -0.5, 0.5)
    return np.remainder(u + math.pi, 2.0 * math.pi) - math.pi, error


def distinct(n: int, pose: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Branches (n, 16, 6) [rad] of the polished rows ``u`` (M, 6) of poses ``pose`` (M,).

    Per pose, rows within :data:`SAME_TOL` of another row before them (modulo 2 pi) are
    dropped; the rest are ordered by ascending joint 1, NaN rows after.
    """
    out = np.full((n, BRANCHES, 6), np.nan)
    if not pose.size:
        return out
    # Joint 1 near +pi sorts with -pi (the same angle).
    order = np.lexsort(
        (np.where(u[:, 0] > math.pi - SAME_TOL, u[:, 0] - 2.0 * math.pi, u[:, 0]), pose)
    )
    pose, u = pose[order], u[order]
    # A duplicate follows its twin within the rows of equal pose and joint 1 (sorted).
    duplicate = np.zeros(pose.size, dtype=bool)
    for shift in range(1, pose.size):
        gap1 = np.remainder(u[shift:, 0] - u[:-shift, 0] + math.pi, 2.0 * math.pi) - math.pi
        near = (pose[shift:] == pose[:-shift]) & (np.abs(gap1) <= SAME_TOL)
        if not near.any():
            break
        gap = np.remainder(u[shift:] - u[:-shift] + math.pi, 2.0 * math.pi) - math.pi
        duplicate[shift:] |= near & (np.abs(gap).max(axis=1) <= SAME_TOL)
    keep = ~duplicate
    pose, u = pose[keep], u[keep]
    first = np.searchsorted(pose, pose)  # index of each pose's first row
    rank = np.arange(pose.size) - first
    fits = rank < BRANCHES
    out[pose[fits], rank[fits]] = u[fits]
    return out


def distinct_again(out: np.ndarray, pose: np.ndarray, u: np.ndarray, which: np.ndarray) -> None:
    """:func:`distinct` of the poses ``which`` (sorted indices) only, written into ``out``.

    The rows of the other poses are not read: a pose's branches depend on its own rows alone,
    so a pass that adds rows to a few poses of a batch merges those poses, not the batch.
    """
    rows = np.isin(pose, which)
    out[which] = distinct(which.size, np.searchsorted(which, pose[rows]), u[rows])
