"""Target values checked once: finite numbers of the right size, rotation matrices, angles.

A NaN or infinite value is a :class:`~kin.ik.TargetError` that names the field (``position[1]``,
``rotation[2][0]``, ``pitch``); a matrix off a rotation by at most :data:`ROTATION_SNAP` is
snapped to the nearest one (SVD), a farther one refused. The arrays returned are read-only copies.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from ..exceptions import TargetError

__all__ = [
    "FLOAT64",
    "ROTATION_EXACT",
    "ROTATION_SNAP",
    "checked_angle",
    "checked_floats",
    "checked_rotation",
    "checked_vector",
    "orthonormality",
]

#: Largest ``max |R^T R - I|`` of a target rotation replaced by its nearest rotation matrix; a
#: farther matrix is refused.
ROTATION_SNAP = 1e-3
#: Largest ``max |R^T R - I|`` taken as it is (the rounding of a product of rotations).
ROTATION_EXACT = 1e-12
#: NumPy's float64, compared by identity on the short way of :func:`checked_floats`.
FLOAT64 = np.dtype(float)


def checked_vector(values: npt.ArrayLike, size: int, what: str) -> np.ndarray:
    """``values`` as a new float array of ``size`` finite numbers (a TargetError names the field)."""
    return checked_floats(values, size, what)[0]


def checked_floats(values: npt.ArrayLike, size: int, what: str) -> tuple[np.ndarray, list[float]]:
    """:func:`checked_vector`, and its values as Python floats (row-major).

    A float64 array of the right size (what a solve loop hands in) takes the short way: one
    copy, one sum of Python floats for the finiteness check (about 0.6 us; the general way,
    through ``np.array`` and a reshape, about 1.3 us).
    """
    if type(values) is np.ndarray and values.dtype is FLOAT64 and values.size == size:
        array = values.flatten()  # a copy, one-dimensional
    else:
        try:
            array = np.array(values, dtype=float).reshape(-1)
        except (TypeError, ValueError, OverflowError) as err:
            raise TargetError(f"{what} must be {size} numbers, got {values!r}") from err
        if array.size != size:
            raise TargetError(f"{what} must be {size} numbers, got {array.size}")
    floats = array.tolist()
    # A finite sum means every value is finite (a NaN or an infinity makes it NaN or infinite);
    # a sum that overflows is looked at value by value.
    if not math.isfinite(sum(floats)) and not all(map(math.isfinite, floats)):
        i = int(np.flatnonzero(~np.isfinite(array))[0])
        where = f"{what}[{i}]" if size <= 3 else f"{what}[{i // 3}][{i % 3}]"
        raise TargetError(f"{where} is {array[i]}: every target value must be a finite number")
    array.setflags(write=False)  # checked once: it cannot change after (a copy of the input)
    return array, floats


def orthonormality(*entries: float) -> tuple[float, float]:
    """``max |R^T R - I|`` and ``det R`` of a 3x3 matrix given row-major (9 finite floats).

    A matrix whose entry's square overflows has deviation ``inf`` and determinant NaN.
    """
    a, b, c, d, e, f, g, h, i = entries
    # The entries of R^T R - I (symmetric: six of them), the diagonal first: an entry whose
    # square overflows makes a diagonal one infinite, and a NaN after it (inf - inf off the
    # diagonal) does not replace that maximum.
    deviation = max(
        abs(a * a + d * d + g * g - 1.0),
        abs(b * b + e * e + h * h - 1.0),
        abs(c * c + f * f + i * i - 1.0),
        abs(a * b + d * e + g * h),
        abs(a * c + d * f + g * i),
        abs(b * c + e * f + h * i),
    )
    if deviation == math.inf:
        return deviation, math.nan
    return deviation, a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def checked_rotation(values: npt.ArrayLike) -> np.ndarray:
    """A rotation matrix from 9 numbers (row-major): checked, snapped to SO(3) when nearly one.

    The check runs on Python floats (a few microseconds): a target is built once per solve.
    """
    if type(values) is np.ndarray and values.dtype is FLOAT64 and values.shape == (3, 3):
        matrix = values.copy()  # the short way of a solve loop's float64 3x3 (about 1 us less)
        (a, b, c), (d, e, f), (g, h, i) = matrix.tolist()
        if not math.isfinite(a + b + c + d + e + f + g + h + i):
            matrix = checked_floats(values, 9, "rotation")[0].reshape(3, 3)  # names the entry
    else:
        flat, floats = checked_floats(values, 9, "rotation")
        matrix = flat.reshape(3, 3)
        a, b, c, d, e, f, g, h, i = floats
    deviation, determinant = orthonormality(a, b, c, d, e, f, g, h, i)
    if deviation <= ROTATION_EXACT and determinant > 0.0:
        matrix.setflags(write=False)
        return matrix
    if deviation <= ROTATION_SNAP and determinant > 0.0:
        u, _, vt = np.linalg.svd(matrix)
        snapped = u @ vt
        snapped.setflags(write=False)
        return snapped
    raise TargetError(
        f"rotation is not a rotation matrix (max |R^T R - I| = {deviation:.3g}, "
        f"det = {determinant:.3g}): give orthonormal axes with det +1 "
        f"(a matrix off by at most {ROTATION_SNAP:g} is rounded to the nearest rotation)"
    )


def checked_angle(value: object, what: str) -> float:
    """``value`` as a finite float [rad] (a TargetError names the field)."""
    try:
        angle = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError) as err:
        raise TargetError(f"{what} must be a number [rad], got {value!r}") from err
    if not math.isfinite(angle):
        raise TargetError(f"{what} is {angle}: every target value must be a finite number")
    return angle
