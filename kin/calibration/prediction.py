"""What the parameter model predicts the tracker measures, and its Jacobian, for N joint vectors.

The chain is the product of the rows in the measurement frame, ``B T_1(q_1) ... T_n(q_n)``, with
``B`` the estimated pose of DH frame 0 (:mod:`kin.calibration.parameters`). Every parameter moves
the chain by a rotation about, or a translation along, a known axis of a frame on the way (for
``theta`` the joint axis, for ``a`` the common normal, for ``beta`` the row's y axis), so the
Jacobian is exact and analytic: a point ``y`` moves by ``w x (y - c)`` for a rotation about the
unit axis ``w`` through ``c`` and by ``w`` for a translation; the measured frame turns by ``w``
(world axes, the measurement frame). Checked against finite differences in the tests.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .parameters import ParameterModel


@dataclass(frozen=True)
class Prediction:
    """Predicted measurements of N joint vectors.

    Attributes:
        points: Measured points in the measurement frame, (N, K, 3) [m]: the K markers, or the
            tool origin (K = 1) for full poses.
        rotations: Tool rotations in the measurement frame (N, 3, 3), or None for markers.
        point_jacobian: d points / d x, (N, K, 3, P) [m per parameter unit], or None.
        rotation_jacobian: The tool's small rotation (measurement-frame axes) per parameter,
            (N, 3, P) [rad per parameter unit], or None.
    """

    points: np.ndarray
    rotations: np.ndarray | None
    point_jacobian: np.ndarray | None
    rotation_jacobian: np.ndarray | None


def _rot(axis: int, angle: np.ndarray) -> np.ndarray:
    """(N, 4, 4) rotations about x (0), y (1) or z (2) by ``angle`` (N,) [rad]."""
    n = angle.shape[0]
    out = np.zeros((n, 4, 4))
    out[:, axis, axis] = out[:, 3, 3] = 1.0
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    c, s = np.cos(angle), np.sin(angle)
    out[:, i, i] = out[:, j, j] = c
    out[:, i, j], out[:, j, i] = -s, s
    return out


def _move(frames: np.ndarray, axis: int, length: np.ndarray | float) -> np.ndarray:
    """``frames`` translated along their own axis ``axis`` by ``length`` [m]."""
    out = frames.copy()
    out[:, :3, 3] += frames[:, :3, axis] * np.reshape(length, (-1, 1))
    return out


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def left_jacobian(phi: np.ndarray) -> np.ndarray:
    """SO(3) left Jacobian of a rotation vector: ``Exp(phi + d) = Exp(J_l d) Exp(phi)``."""
    theta = float(np.linalg.norm(phi))
    k = _skew(phi)
    if theta < 1e-8:
        return np.eye(3) + 0.5 * k
    return (
        np.eye(3)
        + (1.0 - np.cos(theta)) / theta**2 * k
        + (theta - np.sin(theta)) / theta**3 * (k @ k)
    )


#: An effect on the chain: (parameter index, True for a rotation, axis (N, 3), point (N, 3)).
Effect = tuple[int, bool, np.ndarray, np.ndarray | None]


def _chain(model: ParameterModel, x: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, list[Effect]]:
    """The last DH frame in the measurement frame (N, 4, 4) and every row parameter's effect."""
    n = q.shape[0]
    frames = np.broadcast_to(model.T_measurement_base(x), (n, 4, 4)).copy()
    effects: list[Effect] = []
    where = {(p.row, p.kind): i for i, p in enumerate(model.parameters) if p.row is not None}
    standard = model.table.convention == "standard"

    def effect(row: int, kind: str, rotation: bool, axis: int) -> None:
        origin = frames[:, :3, 3] if rotation else None
        effects.append((where[(row, kind)], rotation, frames[:, :3, axis], origin))

    for i, row in enumerate(model.table.rows):
        v = model.row_values(x, i)
        moved = row.direction * q[:, i]
        revolute = row.joint_type == "revolute"
        angle = v["theta"] + moved if revolute else np.full(n, v["theta"])
        length = v["d"] if revolute else v["d"] + moved
        if standard:
            effect(i, "theta", True, 2)
            effect(i, "d", False, 2)
            frames = _move(frames @ _rot(2, angle), 2, length)
            effect(i, "a", False, 0)
            frames = _move(frames, 0, v["a"])
            effect(i, "alpha", True, 0)
            frames = frames @ _rot(0, np.full(n, v["alpha"]))
            if i in model.beta_rows:
                effect(i, "beta", True, 1)
                frames = frames @ _rot(1, np.full(n, v["beta"]))
        else:
            effect(i, "alpha", True, 0)
            frames = frames @ _rot(0, np.full(n, v["alpha"]))
            if i in model.beta_rows:
                effect(i, "beta", True, 1)
                frames = frames @ _rot(1, np.full(n, v["beta"]))
            effect(i, "a", False, 0)
            frames = _move(frames, 0, v["a"])
            effect(i, "theta", True, 2)
            effect(i, "d", False, 2)
            frames = _move(frames @ _rot(2, angle), 2, length)
    return frames, effects


def predict(
    model: ParameterModel, x: np.ndarray, q: np.ndarray, jacobian: bool = False
) -> Prediction:
    """Predicted measurements of joint vectors ``q`` (N, n) [rad] / [m] with parameters ``x``."""
    x = np.asarray(x, dtype=float)
    q = np.atleast_2d(np.asarray(q, dtype=float))
    last, effects = _chain(model, x, q)
    R_last, p_last = last[:, :3, :3], last[:, :3, 3]
    if model.markers == 0:
        tool = model.T_last_tool(x)
        points = (p_last + R_last @ tool[:3, 3])[:, None, :]
        rotations: np.ndarray | None = R_last @ tool[:3, :3]
    else:
        offsets = np.array([model.marker(x, k) for k in range(1, model.markers + 1)])  # (K, 3)
        points = p_last[:, None, :] + np.einsum("nij,kj->nki", R_last, offsets)
        rotations = None
    if not jacobian:
        return Prediction(points, rotations, None, None)
    n, k = points.shape[:2]
    size = len(model.parameters)
    J_p = np.zeros((n, k, 3, size))
    J_r = np.zeros((n, 3, size))
    for index, rotation, axis, origin in effects:
        if origin is not None:
            J_p[:, :, :, index] = np.cross(axis[:, None, :], points - origin[:, None, :])
            J_r[:, :, index] = axis
        else:
            J_p[:, :, :, index] = axis[:, None, :]
    base = model.T_measurement_base(x)
    turned = base[:3, :3] @ left_jacobian(x[model.slice("base", "r")]).T  # R_B J_r(phi)
    for j, index in enumerate(model.slice("base", "t")):
        J_p[:, :, :, index] = model.T0_base[:3, j]
    for j, index in enumerate(model.slice("base", "r")):
        w = turned[:, j]
        J_p[:, :, :, index] = np.cross(w, points - base[:3, 3])
        J_r[:, :, index] = w
    if model.markers == 0:
        for j, index in enumerate(model.slice("tool", "t")):
            J_p[:, 0, :, index] = R_last[:, :, j]
        right = left_jacobian(x[model.slice("tool", "r")]).T  # J_r(phi) = J_l(phi)^T
        assert rotations is not None
        for j, index in enumerate(model.slice("tool", "r")):
            J_r[:, :, index] = rotations @ right[:, j]
    else:
        for m in range(model.markers):
            for j, index in enumerate(model.slice(f"marker{m + 1}", "t")):
                J_p[:, m, :, index] = R_last[:, :, j]
    return Prediction(points, rotations, J_p, J_r if model.markers == 0 else None)
