"""Follow a Cartesian path with a closed-form solver, on one branch.

At each sample the closed form gives every branch. The follower keeps the branch of the previous
sample (same label, nearest joint vector); when no solution of that branch is within
``max_joint_step`` of the previous joint vector, it takes the nearest solution of any branch if
that one is within the bound (labels are not stable everywhere: over the base axis, a "shoulder
front" solution continues as "shoulder back") and records the branch change. When no solution is
within the bound, the motion stops there: at a joint limit, out of reach, or before a jump.

Revolute joint values are compared modulo 2 pi where the limits allow the shifted value, so a
wrist roll with limits wider than a turn does not jump by 2 pi; a continuous joint (no limits)
always takes the value nearest the previous sample's, so it crosses pi without a jump.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ..ik.result import IKResult, IKSolution
from ..robot_model import RobotModel
from .cartesian import CartesianPath
from .exceptions import PathError
from .result import Trace

TWO_PI = 2.0 * math.pi


class TurnUnwrapper:
    """Shift revolute joint values by whole turns toward a reference, inside the limits."""

    def __init__(self, robot: RobotModel):
        self.revolute = np.array([row.joint_type == "revolute" for row in robot.table.rows])
        #: Joints without limits (continuous rows): turned toward the reference always, so a
        #: path crosses pi smoothly (its values leave [-pi, pi]: the same joint positions).
        self.continuous = np.array([row.continuous for row in robot.table.rows], dtype=bool)
        self.lower = robot.lower
        self.upper = robot.upper

    def free(self, q: np.ndarray, reference: np.ndarray) -> np.ndarray:
        """Shifted toward ``reference`` by whole turns, limits ignored."""
        turns = np.round((reference - q) / TWO_PI) * self.revolute
        return np.asarray(q, dtype=float) + TWO_PI * turns

    def __call__(self, q: np.ndarray, reference: np.ndarray | None) -> np.ndarray:
        """``q`` with revolute joints turned toward ``reference`` where the limits allow."""
        if reference is None:
            return np.asarray(q, dtype=float)
        q = np.array(q, dtype=float)
        turns = np.round((reference - q) / TWO_PI) * self.revolute
        shifted = q + TWO_PI * turns
        inside = ((shifted >= self.lower) & (shifted <= self.upper)) | self.continuous
        return np.where(inside, shifted, q)


def follow_closed_form(
    robot: RobotModel,
    solver: object,
    path: CartesianPath,
    seed: np.ndarray | None,
    branch: str | None,
    max_joint_step: float,
    progress: Callable[[int, int], None] | None = None,
) -> Trace:
    """Solve every sample in closed form, staying on one branch.

    Args:
        robot: The robot.
        solver: A closed-form solver (``solve(target, seed) -> IKResult``, every branch).
        path: The Cartesian path.
        seed: Joint vector the first sample's solution should be nearest to [rad] / [m], or None
            (the solver's first solution).
        branch: Branch label the first sample must take, or None.
        max_joint_step: Largest change of one joint between samples [rad] / [m].
        progress: Called with (samples done, samples) before each sample, or None.

    Raises:
        PathError: ``branch`` is not a branch of the first sample.
    """
    unwrap = TurnUnwrapper(robot)
    trace = Trace(q=[], branches=[], branch_changes=[])
    for index in range(len(path)):
        if progress is not None:
            progress(index, len(path))
        previous = trace.q[-1] if trace.q else None
        result: IKResult = solver.solve(path.target(index), previous if index else seed)  # type: ignore[attr-defined]
        reference = previous if previous is not None else seed
        candidates = [(s, unwrap(s.q, reference)) for s in result.solutions]
        if previous is None:
            if branch is not None:
                labels = sorted({s.branch for s in result.solutions + result.rejected})
                candidates = [c for c in candidates if c[0].branch == branch]
                if not candidates and branch not in labels:
                    raise PathError(
                        f"branch {branch!r} is not a solution of the first sample; "
                        f"its branches: {'; '.join(map(repr, labels)) or 'none'}",
                        "branch",
                    )
            if not candidates:
                return trace.stop(index, _no_solution(robot, result))
            pick = candidates[0] if seed is None else min(candidates, key=_nearest(seed))
            trace.q.append(pick[1])
            trace.branches.append(pick[0].branch)
            continue
        chosen = _continue(candidates, previous, trace.branches[-1], max_joint_step)
        if chosen is None:
            return trace.stop(index, _why_not(robot, result, previous, unwrap, max_joint_step))
        if chosen[0].branch != trace.branches[-1]:
            trace.branch_changes.append(index)
        trace.q.append(chosen[1])
        trace.branches.append(chosen[0].branch)
    return trace


def _nearest(reference: np.ndarray):  # noqa: ANN202
    return lambda candidate: float(np.abs(candidate[1] - reference).max())


def _continue(
    candidates: Sequence[tuple[IKSolution, np.ndarray]],
    previous: np.ndarray,
    label: str,
    bound: float,
) -> tuple[IKSolution, np.ndarray] | None:
    """The same-branch solution nearest ``previous`` within ``bound``, else any branch's."""
    step = _nearest(previous)
    same = [c for c in candidates if c[0].branch == label]
    for pool in (same, candidates):
        if pool:
            best = min(pool, key=step)
            if step(best) <= bound:
                return best
    return None


def _no_solution(robot: RobotModel, result: IKResult) -> str:
    """Why the first sample has no solution inside the limits."""
    if result.rejected:
        return (
            f"every solution is outside the joint limits ({_outside(robot, result.rejected[0].q)})"
        )
    return f"unreachable: {result.message}"


def _why_not(
    robot: RobotModel,
    result: IKResult,
    previous: np.ndarray,
    unwrap: TurnUnwrapper,
    bound: float,
) -> str:
    """Why no solution continues the motion from ``previous``."""
    for solution in result.solutions + result.rejected:
        # The continuation may be a whole turn away from the value in the limits.
        q = unwrap.free(solution.q, previous)
        if np.abs(q - previous).max() <= bound and not _inside(robot, q):
            return f"joint limit: {_outside(robot, q)}"
    if not result.solutions and not result.rejected:
        return f"unreachable: {result.message}"
    every = [unwrap(s.q, previous) for s in result.solutions + result.rejected]
    gap = min(float(np.abs(q - previous).max()) for q in every)
    return (
        f"no solution within {bound:.3g} of the previous joint vector (nearest {gap:.3g} away): "
        "the motion would jump (a singularity or a branch boundary)"
    )


def _inside(robot: RobotModel, q: np.ndarray) -> bool:
    """Whether ``q`` is inside the limits (a continuous joint has none)."""
    inside = (q >= robot.lower) & (q <= robot.upper)
    return bool((inside | continuous_joints(robot)).all())


def continuous_joints(robot: RobotModel) -> np.ndarray:
    """Per joint, whether it is continuous (no limits; its table row says ``continuous``)."""
    return np.array([row.continuous for row in robot.table.rows], dtype=bool)


def _outside(robot: RobotModel, q: np.ndarray) -> str:
    """``"joint 'name' = value outside [lower, upper]"`` for the first joint out of its limits."""
    lower, upper = robot.lower, robot.upper
    for j, (value, lo, hi) in enumerate(zip(q, lower, upper)):
        if value < lo or value > hi:
            name = robot.joint_names[j]
            return f"joint '{name}' = {value:.4g} outside [{lo:.4g}, {hi:.4g}]"
    return "a joint at its limit"
