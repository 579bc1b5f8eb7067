"""Products of stacks of 4x4 rigid transforms [m] and rotations about z [rad], fast in NumPy.

What the general 6R elimination (:mod:`._general_6r_elimination`) and its polish
(:mod:`.general_6r`) multiply: ``Rz(angle)`` of N angles, inverses, and products of a stack
with ``Rz`` (column or row arithmetic on large stacks, where NumPy's matmul loops matrix by
matrix) or with one fixed transform (one BLAS call).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt


def rot_z(angle: npt.ArrayLike) -> np.ndarray:
    """``Rz(angle)`` as 4x4 transforms, (..., 4, 4), of angles (...) [rad]."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros(angle.shape + (4, 4))
    out[..., 0, 0] = c
    out[..., 0, 1] = -s
    out[..., 1, 0] = s
    out[..., 1, 1] = c
    out[..., 2, 2] = 1.0
    out[..., 3, 3] = 1.0
    return out


#: Stacks of at most this many transforms are multiplied by NumPy's matmul, larger ones by
#: column or row arithmetic (:func:`times_rz`, :func:`rz_times`).
SMALL_STACK = 64


def times_rz(X: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """``X Rz(angle)`` (angle.shape + (4, 4)) of transforms ``X`` broadcast to them [rad].

    Column arithmetic (``Rz`` mixes columns 0 and 1 only) on stacks of more than
    :data:`SMALL_STACK`: faster there than NumPy's matmul, which loops matrix by matrix; on
    smaller ones (a single pose's roots) the matmul's fewer calls are faster.
    """
    if angle.size <= SMALL_STACK:
        return X @ rot_z(angle)
    c, s = np.cos(angle)[..., None], np.sin(angle)[..., None]
    out = np.empty(angle.shape + (4, 4))
    out[...] = X
    x0, x1 = X[..., :, 0], X[..., :, 1]
    out[..., :, 0] = x0 * c + x1 * s
    out[..., :, 1] = x1 * c - x0 * s
    return out


def rz_times(angle: np.ndarray, X: np.ndarray) -> np.ndarray:
    """``Rz(angle) X`` (angle.shape + (4, 4)) of transforms ``X`` broadcast to them (row arithmetic).

    As :func:`times_rz`, a matmul on stacks of at most :data:`SMALL_STACK`.
    """
    if angle.size <= SMALL_STACK:
        return rot_z(angle) @ X
    c, s = np.cos(angle)[..., None], np.sin(angle)[..., None]
    out = np.empty(angle.shape + (4, 4))
    out[...] = X
    x0, x1 = X[..., 0, :], X[..., 1, :]
    out[..., 0, :] = x0 * c - x1 * s
    out[..., 1, :] = x0 * s + x1 * c
    return out


def times(X: np.ndarray, C: np.ndarray) -> np.ndarray:
    """``X C`` of a stack of 4x4 transforms ``X`` (..., 4, 4) and one ``C`` (4, 4): one BLAS call."""
    if C.ndim == 2 and X.flags.c_contiguous:
        return (X.reshape(-1, 4) @ C).reshape(X.shape)
    return X @ C


def inverse(T: np.ndarray) -> np.ndarray:
    """Inverse of rigid transforms (..., 4, 4) [m]."""
    out = np.zeros_like(T)
    rt = np.swapaxes(T[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", rt, T[..., :3, 3])
    out[..., 3, 3] = 1.0
    return out
