"""Follow a Cartesian path with velocity-limited differential IK steps (redundant or numeric arms).

A numeric IK solve per sample may land anywhere in the redundancy (a seed 0.01 rad from a
solution can come back 0.46 rad away): right for one target, wrong for a path. Here each sample
is reached from the previous joint vector by sub-steps of :class:`kin.ik.DifferentialIK` (mink
QP, joint limits as hard constraints, every joint moving at most ``substep`` per sub-step), with
the previous joint vector as the posture preference, so consecutive joint vectors stay close.
When a sample cannot be reached within the sub-steps (a joint limit holds the arm back, or the
target is out of reach), the motion stops there.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pinocchio as pin

from ..ik import DifferentialIK, IKError, NumericTarget, PoseTarget, PositionTarget
from ..robot_model import RobotModel
from .branch_follow import continuous_joints
from .cartesian import CartesianPath
from .exceptions import PathError
from .result import Trace

#: Sub-steps in a row without a 1 % error decrease after which a sample is given up.
PATIENCE = 5
#: Weight of the rotation error in the progress measure [m/rad].
ROTATION_WEIGHT = 0.1


def follow_differential(
    robot: RobotModel,
    path: CartesianPath,
    q_start: np.ndarray,
    *,
    substep: float = 0.05,
    max_substeps: int = 40,
    position_tol: float = 1e-6,
    rotation_tol: float = 1e-5,
    max_joint_step: float = math.inf,
    progress: Callable[[int, int], None] | None = None,
) -> Trace:
    """Walk the samples from ``q_start`` (a solution of sample 0) by differential IK sub-steps.

    Args:
        robot: The robot.
        path: A position or pose path.
        q_start: Joint vector at sample 0 [rad] / [m], inside the limits.
        substep: Largest change of one joint per sub-step [rad] / [m].
        max_substeps: Sub-steps allowed per sample.
        position_tol: A sample is reached when the tool is this close [m] ...
        rotation_tol: ... and, for a pose path, turned this little from it [rad].
        max_joint_step: Largest change of one joint between samples [rad] / [m].
        progress: Called with (samples done, samples) before each sample, or None.

    Raises:
        PathError: A pitch path (the differential step takes positions and poses).
    """
    if path.kind not in (PoseTarget, PositionTarget):
        raise PathError(
            f"the differential path follower takes positions or poses, got {path.kind.__name__}",
            "waypoints",
        )
    ik = DifferentialIK(robot, velocity_limit=substep)
    model, data = robot.model, robot.model.createData()
    tool = model.getFrameId(robot.tool_frame)
    # A continuous joint has no limits: its path crosses pi (values leave [-pi, pi]).
    free = continuous_joints(robot)
    lower = np.where(free, -np.inf, model.lowerPositionLimit)
    upper = np.where(free, np.inf, model.upperPositionLimit)
    q = np.clip(np.asarray(q_start, dtype=float), lower, upper)
    trace = Trace(q=[q], branches=[""], branch_changes=[])

    def errors(q: np.ndarray, target: NumericTarget) -> tuple[float, float]:
        pin.framesForwardKinematics(model, data, q)
        pose = data.oMf[tool]
        position = float(np.linalg.norm(pose.translation - target.position))
        if target.rotation is None:
            return position, 0.0
        return position, float(np.linalg.norm(pin.log3(pose.rotation.T @ target.rotation)))

    for index in range(1, len(path)):
        if progress is not None:
            progress(index, len(path))
        sample = path.target(index)
        rotation = sample.rotation if isinstance(sample, PoseTarget) else None
        target = NumericTarget.from_arrays(sample.position, rotation, posture=q)
        ik.set_target(target)
        previous, best, stalled = q, math.inf, 0
        for _ in range(max_substeps):
            position, turn = errors(q, target)
            if position < position_tol and turn < rotation_tol:
                break
            measure = position + ROTATION_WEIGHT * turn
            stalled = stalled + 1 if measure > 0.99 * best else 0
            best = min(best, measure)
            if stalled >= PATIENCE:
                break
            try:
                q = np.clip(ik.step(q, 1.0), lower, upper)
            except IKError as err:
                return trace.stop(index, f"the QP found no step ({err})")
        position, turn = errors(q, target)
        if not (position < position_tol and turn < rotation_tol):
            return trace.stop(index, _why_not(robot, q, position, turn))
        step = float(np.abs(q - previous).max())
        if step > max_joint_step:
            return trace.stop(
                index,
                f"a joint would move {step:.3g} > {max_joint_step:.3g} in one step "
                "(near a singularity: more steps, or a larger bound)",
            )
        trace.q.append(q)
        trace.branches.append("")
    return trace


def _why_not(robot: RobotModel, q: np.ndarray, position: float, turn: float) -> str:
    """Joint limit or unreachable, with the remaining error."""
    miss = f"tool {position:.3g} m and {turn:.3g} rad from the sample"
    span = robot.upper - robot.lower
    at_limit = [
        f"'{name}' at its {'lower' if value - lo < hi - value else 'upper'} limit"
        for name, value, lo, hi, width in zip(robot.joint_names, q, robot.lower, robot.upper, span)
        if min(value - lo, hi - value) < 1e-6 * max(width, 1.0)
    ]
    if at_limit:
        return f"joint limit: {', '.join(at_limit)} ({miss})"
    return f"unreachable ({miss})"
