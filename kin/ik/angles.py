"""Angles and rotations, the small steps every solver shares (one place each).

- :func:`wrap`, :func:`wrap_array`: an angle in ``(-pi, pi]`` [rad];
- :func:`clip_unit`, :func:`clip_cosines`: a cosine or sine for ``acos``/``asin``, rounding at
  the edge of the workspace (up to :data:`SLACK` beyond +-1) set to +-1, farther rejected;
- :func:`rpy_matrix`, :func:`rpy_matrices`: URDF roll-pitch-yaw as ``Rz(yaw) Ry(pitch) Rx(roll)``;
- :func:`quaternion_matrix`: a unit quaternion ``(w, x, y, z)`` as a rotation matrix.

The angle nearest a seed inside the joint limits is :mod:`kin.ik.limit_rule`'s; the rotation
error the judge's (:func:`kin.ik.judge.rotation_error`, :func:`kin.ik.judge.rotation_angles`).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

_TWO_PI = 2.0 * math.pi
#: Slack on ``|cos| <= 1`` (rounding at the edge of the workspace) [-].
SLACK = 1e-12


def wrap(angle: float) -> float:
    """``angle`` [rad] in (-pi, pi]."""
    out = math.remainder(angle, _TWO_PI)
    return out + _TWO_PI if out <= -math.pi else out


def wrap_array(angle: np.ndarray) -> np.ndarray:
    """:func:`wrap` of every element [rad] (NaN stays NaN)."""
    out = angle - _TWO_PI * np.round(angle / _TWO_PI)
    return np.where(out <= -math.pi, out + _TWO_PI, out)


def clip_unit(value: float, slack: float = SLACK) -> float | None:
    """``value`` in [-1, 1]; within ``slack`` beyond it, +-1; farther, None (no real angle).

    NaN stays NaN.
    """
    if value > 1.0:
        return None if value > 1.0 + slack else 1.0
    if value < -1.0:
        return None if value < -1.0 - slack else -1.0
    return value


def clip_cosines(cosine: np.ndarray) -> np.ndarray:
    """:func:`clip_unit` of every element: within :data:`SLACK` of +-1 set to +-1; beyond, NaN."""
    out = np.clip(cosine, -1.0, 1.0)
    return np.where(np.abs(cosine) > 1.0 + SLACK, np.nan, out)


def rpy_matrix(roll: float, pitch: float, yaw: float) -> list[list[float]]:
    """URDF roll-pitch-yaw [rad] as the rotation ``Rz(yaw) Ry(pitch) Rx(roll)`` (rows)."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]


def rpy_matrices(rpy: npt.ArrayLike) -> np.ndarray:
    """URDF roll-pitch-yaw (N, 3) [rad] as rotations ``Rz(yaw) Ry(pitch) Rx(roll)`` (N, 3, 3).

    The batched :func:`rpy_matrix`, the same products in the same order.
    """
    rpy = np.asarray(rpy, dtype=float)
    cr, sr = np.cos(rpy[:, 0]), np.sin(rpy[:, 0])
    cp, sp = np.cos(rpy[:, 1]), np.sin(rpy[:, 1])
    cy, sy = np.cos(rpy[:, 2]), np.sin(rpy[:, 2])
    out = np.empty((len(rpy), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 0, 2] = (
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
    )
    out[:, 1, 0], out[:, 1, 1], out[:, 1, 2] = (
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
    )
    out[:, 2, 0], out[:, 2, 1], out[:, 2, 2] = -sp, cp * sr, cp * cr
    return out


def quaternion_matrix(w: float, x: float, y: float, z: float) -> list[list[float]]:
    """The rotation (rows) of the quaternion ``w + xi + yj + zk``, normalised here (not zero)."""
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
