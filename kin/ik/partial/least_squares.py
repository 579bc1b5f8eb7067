"""Weighted least squares on a partial target's rows: Levenberg-Marquardt inside the limits.

The residual is ``e = (p_target - p, w log3(R_target R^T))`` in world axes ([m], and [rad]
weighted by :data:`~.settings.ROTATION_WEIGHT` [m/rad]), the rows the target keeps
(:class:`~.task.PartialTask`). Where the pose is not reachable the steps end at the nearest pose
the arm reaches in that weighted sense.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .context import PartialContext
from .settings import MAX_ITERATIONS, MAX_STEP
from .task import PartialTask

__all__ = ["least_squares"]

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def least_squares(
    ctx: PartialContext,
    task: PartialTask,
    q0: np.ndarray,
    position_tol: float,
    rotation_tol: float,
) -> tuple[np.ndarray, float]:
    """Levenberg-Marquardt from ``q0`` inside the (search) limits; the last q and its weighted cost.

    Args:
        ctx: The solver's model handles.
        task: The target's rows and errors.
        q0: The start [rad] (or [m]), clamped into the search limits first.
        position_tol: The steps stop below this position error [m].
        rotation_tol: ... and this rotation error [rad].
    """
    lower, upper = ctx.search_lower, ctx.search_upper
    q = np.minimum(np.maximum(q0, lower), upper)
    rows, weights = task.rows, task.weights[:, None]
    model, data, frame_id = ctx.model, ctx.data, ctx.frame_id
    identity = np.eye(ctx.nq)

    def evaluate(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, bool]:
        frame_jacobian = pin.computeFrameJacobian(model, data, q, frame_id, _LWA)
        pose = data.oMf[frame_id]
        full = task.error(pose.translation, pose.rotation)
        position_error, rotation_error = task.errors(full)
        e = full[rows] * weights[:, 0]
        jacobian = task.jacobian(full, pose.rotation, frame_jacobian)[rows] * weights
        done = position_error < position_tol and rotation_error < rotation_tol
        return e, jacobian, float(e @ e), done

    e, jacobian, cost, done = evaluate(q)
    lam = 1e-3
    for _ in range(MAX_ITERATIONS):
        if done:
            break
        normal = jacobian.T @ jacobian
        gradient = jacobian.T @ e
        improved = False
        while lam < 1e10:
            try:
                dq = np.linalg.solve(normal + lam * identity, gradient)
                # A joint at a bound that the step pushes further out is held there and the
                # step taken by the others (an active set): clamping alone bends the step.
                held = ((q <= lower) & (dq < 0.0)) | ((q >= upper) & (dq > 0.0))
                if held.any():
                    free = ~held
                    dq = np.zeros(ctx.nq)
                    dq[free] = np.linalg.solve(
                        normal[np.ix_(free, free)] + lam * identity[: free.sum(), : free.sum()],
                        gradient[free],
                    )
            except np.linalg.LinAlgError:
                lam *= 10.0
                continue
            scale = float(np.abs(dq).max())
            if scale > MAX_STEP:
                dq *= MAX_STEP / scale
            stepped = np.minimum(np.maximum(q + dq, lower), upper)
            e_new, jacobian_new, cost_new, done_new = evaluate(stepped)
            if cost_new < cost:
                improved = True
                progress = cost - cost_new
                q, e, jacobian, cost, done = stepped, e_new, jacobian_new, cost_new, done_new
                lam = max(lam / 3.0, 1e-12)
                break
            lam *= 4.0
        if not improved or progress <= 1e-15 * max(cost, 1e-300) + 1e-30:
            break  # a minimum of the weighted error (the nearest reachable pose, or stuck)
    return q, cost
