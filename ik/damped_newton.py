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
    # The loop runs a few microseconds per step: names are bound once, buffers are reused,
    # scalar work is done on Python floats (a NumPy call costs about a microsecond).
    lower, upper = model.lowerPositionLimit, model.upperPositionLimit
    q = np.minimum(np.maximum(np.asarray(q0, dtype=float), lower), upper)
    bounds = tuple(zip(lower.tolist(), upper.tolist(), strict=True))
    full = rotation is not None
    m = 6 if full else 3
    identity = _IDENTITY[m]
    e = np.empty(m)
    e_position = e[:3]
    e_rotation = e[3:]
    normal = np.empty((m, m))
    normal_diagonal = np.einsum("ii->i", normal)  # a writable view of the diagonal
    # Views of the tool placement in ``data``: every Jacobian call below refreshes them.
    pose = data.oMf[frame_id]
    translation, orientation = pose.translation, pose.rotation
    jacobian_of, log3, subtract, matmul = pin.computeFrameJacobian, pin.log3, np.subtract, np.matmul
    solve_spd = _solve_spd
    position_tol2, rotation_tol2 = position_tol * position_tol, rotation_tol * rotation_tol
    rotation_error2 = 0.0
    iterations = 0
    while True:
        # One Pinocchio call: forward kinematics, the tool placement and its Jacobian.
        jacobian = jacobian_of(model, data, q, frame_id, _LWA)
        subtract(position, translation, out=e_position)
        if full:
            e_rotation[:] = log3(rotation @ orientation.T)
        else:
            jacobian = jacobian[:3]
        squares = (e * e).tolist()
        position_error2 = squares[0] + squares[1] + squares[2]
        if full:
            rotation_error2 = squares[3] + squares[4] + squares[5]
        if position_error2 < position_tol2 and rotation_error2 < rotation_tol2:
            return NewtonOutcome(
                q, True, iterations, math.sqrt(position_error2), math.sqrt(rotation_error2)
            )
        if iterations >= max_iterations:
            return NewtonOutcome(
                q, False, iterations, math.sqrt(position_error2), math.sqrt(rotation_error2)
            )
        iterations += 1
        squared = position_error2 + rotation_error2
        lam = damping + error_damping * squared
        if posture is None:  # the common case, inlined: dq = J^T (J J^T + lam I)^-1 e
            z = None
            matmul(jacobian, jacobian.T, out=normal)
            normal_diagonal += lam
            x, info = solve_spd(normal, e)
            dq = x @ jacobian if info == 0 else _step(jacobian, e, lam, identity, None)
        else:
            z = posture_gain * (posture - q)
            dq = _step(jacobian, e, lam, identity, z)
        if squared > 1e-4:  # far from the target: bound the step
            _bound(dq, max_step)
        stepped = q + dq
        values = stepped.tolist()
        if any(v < lo or v > hi for v, (lo, hi) in zip(values, bounds)):
            # Freeze the joints the clamp stops while the step pushes them outward.
            blocked = (stepped < lower) | (stepped > upper)
            jacobian = jacobian.copy()
            jacobian[:, blocked] = 0.0
            if z is not None:
                z[blocked] = 0.0
            dq = _step(jacobian, e, lam, identity, z)
            _bound(dq, max_step)
            stepped = np.minimum(np.maximum(q + dq, lower), upper)
        q = stepped


_IDENTITY = {3: np.eye(3), 6: np.eye(6)}


def _bound(dq: np.ndarray, max_step: float) -> None:
    """Scale ``dq`` in place so that its largest entry is at most ``max_step`` [rad]."""
    scale = max(map(abs, dq.tolist()))
    if scale > max_step:
        dq *= max_step / scale


def _step(
    jacobian: np.ndarray, e: np.ndarray, lam: float, identity: np.ndarray, z: np.ndarray | None
) -> np.ndarray:
    """``z + J^T (J J^T + lam I)^-1 (e - J z)`` through a Cholesky solve."""
    rhs = e if z is None else e - jacobian @ z
    normal = jacobian @ jacobian.T + lam * identity
    x, info = _solve_spd(normal, rhs)
    if info != 0:  # not positive definite (no damping at an exact singularity)
        x = np.linalg.lstsq(normal, rhs, rcond=None)[0]
    dq = x @ jacobian
    return dq if z is None else dq + z
