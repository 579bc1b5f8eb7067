"""Independent forward kinematics of a DH table file in plain NumPy, for tests.

Reads the TOML itself (``tomllib``), applies units, joint offsets and the ``[base]`` / ``[tool]``
transforms itself, and multiplies the DH matrices for many configurations at once. It imports
neither ``dh2urdf`` nor ``kin``: agreeing with them is evidence, not a tautology.

Conventions:

- standard: ``T_{i-1,i} = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``;
- modified (Craig): ``T_{i-1,i} = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``;
- revolute joint: DH angle ``theta + direction * q``; prismatic joint: DH length
  ``d + direction * q`` (``direction`` 1, or -1 on a row that says ``direction = -1``);
- ``[base]`` / ``[tool]``: ``xyz`` + ``rpy`` with ``R = Rz(yaw) Ry(pitch) Rx(roll)``, or a DH-style
  row ``a, alpha, d, theta`` in the table's convention, in the table's units.
"""

from __future__ import annotations

import math
import sys

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

_METERS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}
_RADIANS = {"rad": 1.0, "deg": math.pi / 180.0}


@dataclass(frozen=True)
class ReferenceTable:
    """A DH table in SI units, as arrays (one entry per joint, base to tip).

    Attributes:
        convention: ``"standard"`` or ``"modified"``.
        names: Joint names.
        prismatic: True for prismatic joints.
        a: Link lengths [m].
        alpha: Link twists [rad].
        d: Link offsets [m] (offset added to q for prismatic joints).
        theta: Joint angle offsets [rad] (added to q for revolute joints).
        lower: Lower limits of q [rad] or [m].
        upper: Upper limits of q [rad] or [m].
        T_world_base: URDF root to DH frame 0 (4x4, [m]).
        T_last_tool: Last DH frame to tool (4x4, [m]).
        direction: Per joint 1.0, or -1.0 for a reversed joint (all ones if None).
    """

    convention: str
    names: tuple[str, ...]
    prismatic: np.ndarray
    a: np.ndarray
    alpha: np.ndarray
    d: np.ndarray
    theta: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    T_world_base: np.ndarray
    T_last_tool: np.ndarray
    direction: np.ndarray | None = None

    @property
    def dof(self) -> int:
        """Number of joints."""
        return len(self.names)


def _rx(angle: np.ndarray) -> np.ndarray:
    """Batch of rotations about x, shape (..., 4, 4)."""
    angle = np.asarray(angle, dtype=float)
    out = np.zeros(angle.shape + (4, 4))
    c, s = np.cos(angle), np.sin(angle)
    out[..., 0, 0] = 1.0
    out[..., 1, 1], out[..., 1, 2] = c, -s
    out[..., 2, 1], out[..., 2, 2] = s, c
    out[..., 3, 3] = 1.0
    return out


def _ry(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]], dtype=float)


def _rz(angle: np.ndarray) -> np.ndarray:
    """Batch of rotations about z, shape (..., 4, 4)."""
    angle = np.asarray(angle, dtype=float)
    out = np.zeros(angle.shape + (4, 4))
    c, s = np.cos(angle), np.sin(angle)
    out[..., 0, 0], out[..., 0, 1] = c, -s
    out[..., 1, 0], out[..., 1, 1] = s, c
    out[..., 2, 2] = 1.0
    out[..., 3, 3] = 1.0
    return out


def _trans(axis: int, value: np.ndarray) -> np.ndarray:
    """Batch of translations along one axis, shape (..., 4, 4)."""
    value = np.asarray(value, dtype=float)
    out = np.broadcast_to(np.eye(4), value.shape + (4, 4)).copy()
    out[..., axis, 3] = value
    return out


def dh_matrices(convention: str, a, alpha, d, theta) -> np.ndarray:
    """DH link transforms for arrays of parameters (broadcast), shape (..., 4, 4)."""
    a, alpha, d, theta = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (a, alpha, d, theta))
    )
    if convention == "standard":
        return _rz(theta) @ _trans(2, d) @ _trans(0, a) @ _rx(alpha)
    if convention == "modified":
        return _rx(alpha) @ _trans(0, a) @ _rz(theta) @ _trans(2, d)
    raise ValueError(f"unknown convention {convention!r}")


def _angle(value, radians: float):
    """An angle as written, reduced modulo a turn in its unit (exact), then in radians."""
    return np.fmod(value, 360.0 if radians != 1.0 else 2.0 * math.pi) * radians


def _fixed(data: dict, convention: str, meters: float, radians: float) -> np.ndarray:
    if set(data) <= {"xyz", "rpy"}:
        x, y, z = (v * meters for v in data.get("xyz", [0.0, 0.0, 0.0]))
        roll, pitch, yaw = (_angle(v, radians) for v in data.get("rpy", [0.0, 0.0, 0.0]))
        out = _rz(yaw) @ _ry(pitch) @ _rx(roll)
        out[:3, 3] = (x, y, z)
        return out
    return dh_matrices(
        convention,
        data.get("a", 0.0) * meters,
        _angle(data.get("alpha", 0.0), radians),
        data.get("d", 0.0) * meters,
        _angle(data.get("theta", 0.0), radians),
    )


def load_reference(path: str | Path) -> ReferenceTable:
    """Read a (valid) DH table file into SI arrays."""
    data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    meters = _METERS[data["length_unit"]]
    radians = _RADIANS[data["angle_unit"]]
    convention = data["convention"]
    joints = data["joints"]
    prismatic = np.array([j["type"] == "prismatic" for j in joints])
    q_scale = np.where(prismatic, meters, radians)
    limits = np.array([j["limits"] for j in joints], dtype=float) * q_scale[:, None]
    return ReferenceTable(
        convention=convention,
        names=tuple(j.get("name", f"joint{i}") for i, j in enumerate(joints, start=1)),
        prismatic=prismatic,
        a=np.array([j["a"] for j in joints], dtype=float) * meters,
        alpha=_angle(np.array([j["alpha"] for j in joints], dtype=float), radians),
        d=np.array([j["d"] for j in joints], dtype=float) * meters,
        theta=_angle(np.array([j["theta"] for j in joints], dtype=float), radians),
        lower=limits[:, 0],
        upper=limits[:, 1],
        T_world_base=_fixed(data.get("base", {}), convention, meters, radians),
        T_last_tool=_fixed(data.get("tool", {}), convention, meters, radians),
        direction=np.array([j.get("direction", 1) for j in joints], dtype=float),
    )


def fk_frames(table: ReferenceTable, q: np.ndarray) -> np.ndarray:
    """Poses of DH frames 0..n and the tool in the URDF root frame.

    Args:
        table: The reference table.
        q: Joint values, shape (N, dof) [rad] or [m].

    Returns:
        Array of shape (N, dof + 2, 4, 4): ``T_world_frame0 .. T_world_frame{n}, T_world_tool``.
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    if table.direction is not None:
        q = q * table.direction
    theta = np.where(table.prismatic, table.theta, q + table.theta)
    d = np.where(table.prismatic, q + table.d, table.d)
    links = dh_matrices(table.convention, table.a, table.alpha, d, theta)  # (N, dof, 4, 4)
    out = np.empty((q.shape[0], table.dof + 2, 4, 4))
    out[:, 0] = table.T_world_base
    for i in range(table.dof):
        out[:, i + 1] = out[:, i] @ links[:, i]
    out[:, -1] = out[:, -2] @ table.T_last_tool
    return out


def rotation_angle(R1: np.ndarray, R2: np.ndarray) -> np.ndarray:
    """Angle [rad] of ``R1^T R2`` for batches of rotations (..., 3, 3), accurate near zero."""
    R = np.swapaxes(R1, -1, -2) @ R2
    vee = np.stack(
        [R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1
    )
    sin = 0.5 * np.linalg.norm(vee, axis=-1)
    cos = 0.5 * (np.trace(R, axis1=-2, axis2=-1) - 1.0)
    return np.arctan2(sin, cos)


def random_configurations(
    lower: np.ndarray, upper: np.ndarray, count: int, seed: int
) -> np.ndarray:
    """``count`` uniform joint vectors within [lower, upper], seeded, shape (count, dof)."""
    rng = np.random.default_rng(seed)
    return rng.uniform(lower, upper, size=(count, len(lower)))
