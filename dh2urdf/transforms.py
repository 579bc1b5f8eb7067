"""Elementary homogeneous transforms (4x4, meters and radians) used to build DH frames."""

from __future__ import annotations

import math

import numpy as np


def rot_x(angle: float) -> np.ndarray:
    """Rotation about x by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]], dtype=float)


def rot_y(angle: float) -> np.ndarray:
    """Rotation about y by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]], dtype=float)


def rot_z(angle: float) -> np.ndarray:
    """Rotation about z by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=float)


def translation(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    """Pure translation by (x, y, z) [m]."""
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def xyz_rpy(xyz: tuple[float, float, float], rpy: tuple[float, float, float]) -> np.ndarray:
    """URDF origin: translation ``xyz`` [m] and rotation Rz(yaw) Ry(pitch) Rx(roll) [rad]."""
    roll, pitch, yaw = rpy
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    out = np.eye(4)
    out[:3, :3] = [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
    out[:3, 3] = xyz
    return out


def clean(matrix: np.ndarray, tol: float = 1e-15) -> np.ndarray:
    """Return a copy with round-off below ``tol`` snapped to 0 and +-1 (readable URDF numbers)."""
    out = np.array(matrix, dtype=float)
    out[np.abs(out) < tol] = 0.0
    out[np.abs(out - 1.0) < tol] = 1.0
    out[np.abs(out + 1.0) < tol] = -1.0
    return out
