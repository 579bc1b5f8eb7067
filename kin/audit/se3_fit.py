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
    """The rotation nearest to ``matrix`` (3x3) in the Frobenius norm."""
    u, _, vt = np.linalg.svd(matrix)
    d = np.sign(np.linalg.det(u @ vt)) or 1.0
    return u @ np.diag([1.0, 1.0, d]) @ vt


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
    r_t, r_u = T_table[:, :3, :3], T_ref[:, :3, :3]
    eye = np.eye(3)
    # Column-major vec: vec(X R_t) = (R_t^T kron I) vec(X); vec(R_u Y) = (I kron R_u) vec(Y).
    n = len(r_t)
    left = np.einsum("nji,kl->nikjl", r_t, eye).reshape(n, 9, 9)
    right = np.einsum("ij,nkl->nikjl", eye, r_u).reshape(n, 9, 9)
    system = np.concatenate([left, -right], axis=2).reshape(9 * n, 18)
    _, singular, vt = np.linalg.svd(system, full_matrices=False)
    determined = singular[-2] > UNIQUE_GAP * singular[0]  # null space of one vector at most
    if determined:
        v = vt[-1]
        x, y = v[:9].reshape(3, 3, order="F"), v[9:].reshape(3, 3, order="F")
        scale = np.cbrt(np.linalg.det(x)) or 1.0
        x, y = x / scale, y / scale
    else:
        x, y = _joint_rotations(T_table, T_ref)
    r_b = project_to_so3(x)
    r_e = project_to_so3(y).T
    # Translations: [R_B R_t, I] [p_E; p_B] = p_u - R_B p_t.
    lhs = np.concatenate([r_b @ r_t, np.broadcast_to(eye, (n, 3, 3))], axis=2).reshape(3 * n, 6)
    rhs = (T_ref[:, :3, 3] - T_table[:, :3, 3] @ r_b.T).reshape(3 * n)
    solution, _, rank, _ = np.linalg.lstsq(lhs, rhs, rcond=None)
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = r_b, solution[3:]
    tool[:3, :3], tool[:3, 3] = r_e, solution[:3]
    mapped = base @ T_table @ tool
    position = np.linalg.norm(mapped[:, :3, 3] - T_ref[:, :3, 3], axis=1)
    rotation = rotation_angles(mapped[:, :3, :3], r_u)
    unique = bool(determined and rank == 6)
    return BaseToolFit(base, tool, float(position.max()), float(rotation.max()), unique)


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
