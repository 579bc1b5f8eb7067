"""The targets of a batch checked: arrays of numbers of the right shape, rotations snapped.

:func:`checked_array` refuses a non-finite value or a wrong shape, :func:`checked_rotations` a
matrix that is no rotation (within :data:`~kin.ik.targets.target.ROTATION_SNAP`, then snapped to the
nearest one); the message names the array and the row (:class:`~kin.ik.TargetError`).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from ..exceptions import TargetError
from .target import ROTATION_SNAP

__all__ = ["checked_array", "checked_rotations"]


def checked_array(values: npt.ArrayLike, shape: tuple[int, ...], what: str) -> np.ndarray:
    """``values`` as a float array of ``shape`` (-1: any length), every row finite.

    Raises:
        TargetError: Not numbers, a wrong shape or a value that is not finite.
    """
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError, OverflowError) as err:
        raise TargetError(f"{what} must be numbers of shape {shape}, got {values!r}") from err
    if array.shape[1:] != shape[1:] or (shape[0] >= 0 and array.shape[0] != shape[0]):
        raise TargetError(f"{what} must have shape {shape}, got {array.shape}")
    bad = ~np.isfinite(array.reshape(array.shape[0], -1)).all(axis=1)
    if bad.any():
        raise TargetError(f"{what}[{int(np.flatnonzero(bad)[0])}] is not finite")
    return array


def checked_rotations(values: npt.ArrayLike, n: int) -> np.ndarray:
    """N rotation matrices, each within :data:`ROTATION_SNAP` of one (snapped), else refused."""
    rotations = checked_array(values, (n, 3, 3), "rotations")
    r = rotations.reshape(n, 9).T  # (9, N): row-major entries, each over the N matrices
    columns = (r[0::3], r[1::3], r[2::3])
    deviation = np.zeros(n)
    with np.errstate(all="ignore"):
        # max |R^T R - I| from the six distinct dot products of the columns, and det R as
        # the expansion along the first row (elementwise: a tenth of einsum's and det's time)
        for i in range(3):
            for j in range(i, 3):
                a, b = columns[i], columns[j]
                gram = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] - (1.0 if i == j else 0.0)
                np.maximum(deviation, np.abs(gram), out=deviation)
        r0, r1, r2, r3, r4, r5, r6, r7, r8 = r
        determinant = r0 * (r4 * r8 - r5 * r7) - r1 * (r3 * r8 - r5 * r6) + r2 * (r3 * r7 - r4 * r6)
    bad = ~((deviation <= ROTATION_SNAP) & (determinant > 0.0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise TargetError(
            f"rotations[{i}] is not a rotation matrix (max |R^T R - I| = {deviation[i]:.3g}, "
            f"det = {determinant[i]:.3g})"
        )
    snap = deviation > 1e-12
    if snap.any():
        u, _, vt = np.linalg.svd(rotations[snap])
        rotations[snap] = u @ vt
    return rotations
