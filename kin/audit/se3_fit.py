"""Constant base and tool transforms between two kinematic chains: ``T_ref(q) = B T_table(q) E``.

Rotations first, in closed form: ``R_ref = R_B R_table R_E`` gives ``R_B R_table - R_ref R_E^T
= 0``, linear and homogeneous in the 18 entries of ``R_B`` and ``R_E^T``; the right singular
vector of the smallest singular value, scaled to determinant 1 and projected onto SO(3), is the
least-squares answer (exact for exact data). When the rotations leave that null space wider than
one vector (all joint axes parallel: a planar arm), the positions decide instead: the
joint linear least-squares problem in ``R_B``, ``p_B``, ``R_E^T``, ``p_E^*`` (24 unknowns, with
``R_B p_table + p_B = R_ref p_E^* + p_ref``), minimum-norm, then projected. Then the
translations, linear least squares in ``p_B`` and ``p_E``:
``p_ref - R_B p_table = R_B R_table p_E + p_B``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class BaseToolFit:
    """Fitted transforms and how well they map the table onto the reference.

    Attributes:
        T_ref_base: ``B``, pose of the table's world frame in the reference root (4x4) [m].
        T_tool_ref: ``E``, pose of the reference frame in the table's tool frame (4x4) [m].
        position_residual_m: Largest distance between ``B T_table E`` and the reference [m].
        rotation_residual_rad: Largest rotation angle between them [rad].
        unique: The samples determine ``B`` and ``E``; False when a motion of both leaves every
            sample in place (a planar arm: a shift or turn along the common joint axis).
    """

    T_ref_base: np.ndarray
    T_tool_ref: np.ndarray
    position_residual_m: float
    rotation_residual_rad: float
    unique: bool


#: Second smallest over largest singular value of the rotation problem below which the rotations
#: leave ``B`` and ``E`` undetermined (more than one null vector).
UNIQUE_GAP = 1e-6


def project_to_so3(matrix: np.ndarray) -> np.ndarray:
    """The rotations nearest to ``matrix`` (..., 3, 3) in the Frobenius norm."""
    u, _, vt = np.linalg.svd(matrix)
    d = np.sign(np.linalg.det(u @ vt))
    u = u.copy()
    u[..., :, 2] *= np.where(d == 0.0, 1.0, d)[..., None]
    return u @ vt


def rotation_angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angles [rad] between rotations (..., 3, 3), accurate near 0: ``2 asin(|A - B|_F / sqrt 8)``."""
    chord = np.linalg.norm(a - b, axis=(-2, -1)) / np.sqrt(8.0)
    return 2.0 * np.arcsin(np.clip(chord, 0.0, 1.0))


def fit_base_tool(T_table: np.ndarray, T_ref: np.ndarray) -> BaseToolFit:
    """Least-squares ``B``, ``E`` with ``T_ref[k] = B T_table[k] E`` for every sample k.

    Args:
        T_table: Poses of the table's tool in its world frame (N, 4, 4) [m].
        T_ref: Poses of the reference frame in the reference root (N, 4, 4) [m].
    """
    return fit_base_tool_many(T_table[None], T_ref)[0]


def fit_base_tool_many(T_table: np.ndarray, T_ref: np.ndarray) -> list[BaseToolFit]:
    """:func:`fit_base_tool` for R tables against one reference, the R problems at once.

    Args:
        T_table: Poses of each table's tool (R, N, 4, 4) [m].
        T_ref: Poses of the reference frame (N, 4, 4) [m].

    The rotation system ``[R_t^T kron I, -(I kron R_u)]`` (9N x 18) is solved through its
    18 x 18 Gram matrix, whose diagonal blocks are ``N I`` (rotations are orthonormal): the
    eigenvector of its smallest eigenvalue is the null vector.
    """
    count, n = T_table.shape[:2]
    r_t, r_u = T_table[..., :3, :3], T_ref[:, :3, :3]
    eye = np.eye(3)
    # Column-major vec: vec(X R_t) = (R_t^T kron I) vec(X); vec(R_u Y) = (I kron R_u) vec(Y).
    left = np.einsum("rnji,kl->rnikjl", r_t, eye).reshape(count, n, 9, 9)
    right = np.einsum("ij,nkl->nikjl", eye, r_u).reshape(n, 9, 9)
    cross = np.einsum("rnij,nik->rjk", left, right)
    gram = np.zeros((count, 18, 18))
    gram[:, :9, :9] = gram[:, 9:, 9:] = n * np.eye(9)
    gram[:, :9, 9:], gram[:, 9:, :9] = -cross, -cross.transpose(0, 2, 1)
    values, vectors = np.linalg.eigh(gram)
    determined = values[:, 1] > UNIQUE_GAP**2 * values[:, -1]  # a null space of one vector
    v = vectors[:, :, 0]
    x = v[:, :9].reshape(count, 3, 3).transpose(0, 2, 1)  # column-major
    y = v[:, 9:].reshape(count, 3, 3).transpose(0, 2, 1)
    scale = np.cbrt(np.linalg.det(x))
    scale = np.where(scale == 0.0, 1.0, scale)[:, None, None]
    x, y = x / scale, y / scale
    for k in np.flatnonzero(~determined):
        x[k], y[k] = _joint_rotations(T_table[k], T_ref)
    r_b = project_to_so3(x)
    r_e = project_to_so3(y).transpose(0, 2, 1)
    # Translations: [R_B R_t, I] [p_E; p_B] = p_u - R_B p_t, through the 6 x 6 normal equations.
    turned = r_b[:, None] @ r_t  # (R, N, 3, 3)
    rhs = T_ref[None, :, :3, 3] - np.einsum("rij,rnj->rni", r_b, T_table[..., :3, 3])
    normal = np.zeros((count, 6, 6))
    normal[:, :3, :3] = normal[:, 3:, 3:] = n * eye
    normal[:, 3:, :3] = turned.sum(axis=1)
    normal[:, :3, 3:] = normal[:, 3:, :3].transpose(0, 2, 1)
    projected = np.concatenate([np.einsum("rnji,rnj->ri", turned, rhs), rhs.sum(axis=1)], axis=1)
    solution = np.einsum("rij,rj->ri", np.linalg.pinv(normal, rcond=1e-10), projected)
    spread = np.linalg.eigvalsh(normal)
    full_rank = spread[:, 0] > 1e-10 * spread[:, -1]
    base = np.broadcast_to(np.eye(4), (count, 4, 4)).copy()
    tool = base.copy()
    base[:, :3, :3], base[:, :3, 3] = r_b, solution[:, 3:]
    tool[:, :3, :3], tool[:, :3, 3] = r_e, solution[:, :3]
    mapped = base[:, None] @ T_table @ tool[:, None]
    position = np.linalg.norm(mapped[..., :3, 3] - T_ref[None, :, :3, 3], axis=2).max(axis=1)
    rotation = rotation_angles(mapped[..., :3, :3], r_u[None]).max(axis=1)
    return [
        BaseToolFit(
            base[k],
            tool[k],
            float(position[k]),
            float(rotation[k]),
            bool(determined[k] and full_rank[k]),
        )
        for k in range(count)
    ]


def _joint_rotations(T_table: np.ndarray, T_ref: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``R_B`` and ``R_E^T`` (unprojected) from rotations and positions together, minimum-norm.

    Unknowns ``vec(R_B), p_B, vec(F), p_F`` with ``F = R_E^T``: per sample ``R_B R_t - R_u F = 0``
    and ``R_B p_t + p_B - R_u p_F = p_u``, the position rows divided by the reach (unit weight).
    """
    r_t, r_u, p_t, p_u = T_table[:, :3, :3], T_ref[:, :3, :3], T_table[:, :3, 3], T_ref[:, :3, 3]
    n, eye = len(r_t), np.eye(3)
    reach = max(float(np.abs(p_u).max()), float(np.abs(p_t).max()), 1e-9)
    rotation = np.zeros((n, 9, 24))
    rotation[:, :, :9] = np.einsum("nji,kl->nikjl", r_t, eye).reshape(n, 9, 9)
    rotation[:, :, 12:21] = -np.einsum("ij,nkl->nikjl", eye, r_u).reshape(n, 9, 9)
    position = np.zeros((n, 3, 24))
    position[:, :, :9] = np.einsum("nj,kl->nkjl", p_t, eye).reshape(n, 3, 9)
    position[:, :, 9:12] = eye
    position[:, :, 21:24] = -r_u
    lhs = np.concatenate([rotation.reshape(9 * n, 24), position.reshape(3 * n, 24) / reach])
    rhs = np.concatenate([np.zeros(9 * n), p_u.reshape(3 * n) / reach])
    x = np.linalg.lstsq(lhs, rhs, rcond=None)[0]
    return x[:9].reshape(3, 3, order="F"), x[12:21].reshape(3, 3, order="F")
