"""Damped Newton (Levenberg-Marquardt) iterations on Pinocchio, clamped to the joint limits.

The fast path of the numeric solver: from a good starting joint vector, a few steps

    dq = z + J^T (J J^T + lambda I)^-1 (e - J z),    q <- clip(q + dq, lower, upper)

reach the target. ``e`` is the tool error in world-aligned axes at the tool origin
(``p_target - p`` [m] and ``log3(R_target R^T)`` [rad]), ``J`` the matching
``LOCAL_WORLD_ALIGNED`` frame Jacobian (position rows only for a position-only target), ``z`` a
pull toward a preferred posture that the null space of ``J`` keeps off the task, and
``lambda = damping + error_damping * |e|^2`` the Levenberg-Marquardt damping. A joint that the
clamp stops at a limit while the step pushes it outward is frozen (its column removed) and the
step recomputed once: the other joints take over its share.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

try:
    from scipy.linalg import lapack

    def _solve_spd(matrix: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, int]:
        _, x, info = lapack.dposv(matrix, rhs)
        return x, info

except ImportError:  # pragma: no cover - SciPy comes with osqp

    def _solve_spd(matrix: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, int]:
        try:
            return np.linalg.solve(matrix, rhs), 0
        except np.linalg.LinAlgError:
            return rhs, 1


_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@dataclass(frozen=True)
class NewtonOutcome:
    """Result of one damped Newton run.

    Attributes:
        q: Final joint vector [rad], inside the limits.
        converged: Both errors are below the tolerances at ``q``.
        iterations: Steps taken.
        position_error: ``|p - p_target|`` at ``q`` [m].
        rotation_error: Rotation angle to the target at ``q`` [rad] (0 if position only).
    """

    q: np.ndarray
    converged: bool
    iterations: int
    position_error: float
    rotation_error: float


def damped_newton(
    model: pin.Model,
    data: pin.Data,
    frame_id: int,
    q0: np.ndarray,
    position: np.ndarray,
    rotation: np.ndarray | None,
    max_iterations: int = 30,
    position_tol: float = 1e-6,
    rotation_tol: float = 1e-5,
    damping: float = 1e-9,
    error_damping: float = 1e-3,
    max_step: float = 0.5,
    posture: np.ndarray | None = None,
    posture_gain: float = 0.1,
) -> NewtonOutcome:
    """Run clamped damped Newton steps from ``q0`` toward a tool target.

    Args:
        model: Pinocchio model (its position limits are the clamp).
        data: Pinocchio data of ``model`` (overwritten).
        frame_id: Index of the tool frame.
        q0: Start joint vector [rad] (clipped into the limits).
        position: Target position in the world frame [m].
        rotation: Target rotation ``R_world_tool``, or None for position only.
        max_iterations: Maximum number of steps.
        position_tol: Stop when the position error is below this [m] ...
        rotation_tol: ... and the rotation error below this [rad].
        damping: Constant Levenberg-Marquardt damping [m^2] (on ``J J^T``).
        error_damping: Damping proportional to the squared error [1].
        max_step: Largest joint change per step, infinity norm [rad].
        posture: Preferred joint vector [rad] pulled toward in the null space, or None.
        posture_gain: Fraction of the posture error pulled per step [1].
    """
    lower, upper = model.lowerPositionLimit, model.upperPositionLimit
    q = np.minimum(np.maximum(np.asarray(q0, dtype=float), lower), upper)
    full = rotation is not None
    rows = slice(0, 6) if full else slice(0, 3)
    m = 6 if full else 3
    e = np.empty(m)
    diagonal = slice(None, None, m + 1)
    frame_placements = data.oMf
    iterations = 0
    while True:
        # One Pinocchio call gives the Jacobian and updates the frame placement (data.oMf).
        jacobian = pin.computeFrameJacobian(model, data, q, frame_id, _LWA)[rows]
        pose = frame_placements[frame_id]
        e[:3] = position - pose.translation
        position_error = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        rotation_error = 0.0
        if full:
            e[3:] = pin.log3(rotation @ pose.rotation.T)
            rotation_error = math.sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
        if position_error < position_tol and rotation_error < rotation_tol:
            return NewtonOutcome(q, True, iterations, position_error, rotation_error)
        if iterations >= max_iterations:
            return NewtonOutcome(q, False, iterations, position_error, rotation_error)
        iterations += 1
        squared = position_error * position_error + rotation_error * rotation_error
        lam = damping + error_damping * squared
        z = None if posture is None else posture_gain * (posture - q)
        dq = _step(jacobian, e, lam, diagonal, z)
        if squared > 1e-4:  # far from the target: bound the step
            scale = float(np.abs(dq).max())
            if scale > max_step:
                dq *= max_step / scale
        stepped = q + dq
        blocked = (stepped < lower) | (stepped > upper)
        if blocked.any():
            jacobian = jacobian.copy()
            jacobian[:, blocked] = 0.0
            if z is not None:
                z[blocked] = 0.0
            dq = _step(jacobian, e, lam, diagonal, z)
            scale = float(np.abs(dq).max())
            if scale > max_step:
                dq *= max_step / scale
            stepped = np.minimum(np.maximum(q + dq, lower), upper)
        q = stepped


def _step(
    jacobian: np.ndarray, e: np.ndarray, lam: float, diagonal: slice, z: np.ndarray | None
) -> np.ndarray:
    """``z + J^T (J J^T + lam I)^-1 (e - J z)`` through a Cholesky solve."""
    rhs = e if z is None else e - jacobian @ z
    normal = jacobian @ jacobian.T
    normal.flat[diagonal] += lam
    x, info = _solve_spd(normal, rhs)
    if info != 0:  # not positive definite (no damping at an exact singularity)
        x = np.linalg.lstsq(normal, rhs, rcond=None)[0]
    dq = jacobian.T @ x
    return dq if z is None else dq + z
