"""Inverse kinematics along a Cartesian path: one joint vector per sample, each from the last.

:func:`follow_path` picks the method from the robot's solver (:func:`path_solver`, the solver
table's ``path`` front end, :mod:`kin.ik.solver_table`):

- a closed-form solver: every sample in closed form, on one branch
  (:func:`~kin.path.branch_follow.follow_closed_form`);
- a numeric solver, or no solver that fits (a 6-DOF arm without a closed form): the first sample
  by the numeric solver (:class:`kin.ik.NumericIK`), the others by velocity-limited differential
  IK sub-steps (:func:`~kin.path.differential_follow.follow_differential`).

Either way the result is measured by forward kinematics (:func:`~kin.path.result.measure_path`),
and a sample that cannot be reached without a jump stops the motion there (``stopped_at``).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Literal

import numpy as np
import numpy.typing as npt

from ..configuration import as_joint_vector
from ..ik import StructureError
from ..ik.routing import PARTIAL, SHORT
from ..ik.solver import IKSolver
from ..ik.solver_table import FRONT_ENDS, bind_timeout, front_end_solver
from ..robot_model import RobotModel
from .branch_follow import TurnUnwrapper, follow_closed_form
from .cartesian import CartesianPath
from .differential_follow import follow_differential
from .exceptions import PathError
from .result import PathResult, Trace, measure_path

logger = logging.getLogger(__name__)

Method = Literal["auto", "closed_form", "differential"]

#: Default largest change of one joint between two samples [rad] / [m].
MAX_JOINT_STEP = 0.35
#: Random starts of the first sample's numeric solve when no seed is given.
START_SEEDS = 8


def follow_path(
    robot: RobotModel,
    path: CartesianPath,
    seed: npt.ArrayLike | None = None,
    *,
    method: Method = "auto",
    solver: IKSolver | None = None,
    branch: str | None = None,
    max_joint_step: float = MAX_JOINT_STEP,
    substep: float = 0.05,
    max_substeps: int = 40,
    position_tol: float = 1e-6,
    rotation_tol: float = 1e-5,
    timeout: float = 0.5,
    between: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> PathResult:
    """Joint path along ``path``, each sample's IK seeded from the previous one.

    Args:
        robot: The robot.
        path: The Cartesian path (:func:`~kin.path.cartesian.line`, ``polyline``).
        seed: Joint vector the first sample's solution should be near [rad] / [m], or None.
        method: ``"auto"`` (from the robot's solver), ``"closed_form"`` or ``"differential"``.
        solver: The solver :func:`path_solver` gives for ``method`` (None: built here).
        branch: Closed form: branch label of the first sample (None: nearest ``seed``).
        max_joint_step: Largest change of one joint between samples [rad] / [m]; a larger one
            stops the motion (a jump is not a path).
        substep: Differential method: largest change of one joint per sub-step [rad] / [m].
        max_substeps: Differential method: sub-steps allowed per sample.
        position_tol: Differential method: a sample is reached this close [m].
        rotation_tol: Differential method: ... and turned this little from it [rad].
        timeout: Time budget of the numeric solve of the first sample [s].
        between: Points checked between consecutive samples for the deviation (1: midpoint).
        progress: Called with (samples followed, samples) as the motion goes on (the last call
            says all of them when the whole path is followed), or None.

    Raises:
        PathError: Unknown method, a branch the first sample does not have, a pitch path for the
            differential method.
        kin.ik.TargetError: The robot's solver does not take this kind of target.
        kin.JointVectorError: ``seed`` is not one finite value per joint.
    """
    seed_q = None if seed is None else as_joint_vector(robot, seed)
    solver = path_solver(robot, method) if solver is None else solver
    if progress is not None:
        progress(0, len(path))  # at once: a numeric first sample may take its whole budget
    closed = bool(solver.closed_form_kinds)
    if closed or solver.route(path.target(0)) in (PARTIAL, SHORT):
        # A partial pose (a mask, a free tool axis, a pose on a short arm) is solved per sample
        # from the previous one (kin.ik.partial_pose), every answer verified: the nearest is kept.
        chosen = "closed_form" if closed else "partial"
        trace = follow_closed_form(robot, solver, path, seed_q, branch, max_joint_step, progress)
    else:
        chosen = "differential"
        start = _solve_first(robot, solver, path, seed_q, timeout)
        if isinstance(start, Trace):
            trace = start
        else:
            trace = follow_differential(
                robot,
                path,
                start,
                substep=substep,
                max_substeps=max_substeps,
                position_tol=position_tol,
                rotation_tol=rotation_tol,
                max_joint_step=max_joint_step,
                progress=progress,
            )
    if progress is not None and trace.stopped_at is None:
        progress(len(path), len(path))
    q = np.array(trace.q, dtype=float).reshape(-1, robot.nq)
    measured = measure_path(robot, path, q, between)
    logger.debug("path of %d samples: %s", len(path), trace.message or "complete")
    return PathResult(
        success=trace.stopped_at is None,
        q=q,
        path=path,
        method=chosen,
        branches=tuple(trace.branches),
        branch_changes=tuple(trace.branch_changes),
        stopped_at=trace.stopped_at,
        message=trace.message,
        max_deviation=measured.max_deviation,
        max_rotation_error=measured.max_rotation_error,
        max_joint_step=measured.max_joint_step,
        max_step_joint=measured.max_step_joint,
    )


def path_solver(robot: RobotModel, method: Method = "auto") -> IKSolver:
    """The solver of ``robot``'s paths: its own, or the numeric one (asked, or no closed form).

    The solver table's ``path`` front end (:data:`kin.ik.solver_table.FRONT_ENDS`): ``auto`` the
    robot's own, ``closed_form`` only a closed form, ``differential`` the numeric solver, each
    with ``near_seed`` (a path's samples are seeded by the previous one). Its ``target_kinds``
    say which waypoints the path takes.

    Raises:
        PathError: Unknown method, or ``"closed_form"`` for a robot no closed form fits.
    """
    choices = FRONT_ENDS["path"].choices
    if method not in choices:
        raise PathError(f"unknown method {method!r}; choose one of: {', '.join(choices)}", "method")
    try:
        return front_end_solver(robot, "path", method)
    except StructureError as err:
        raise PathError(f"'{robot.name}' has no closed-form solver", "method") from err


def _solve_first(
    robot: RobotModel,
    solver: IKSolver,
    path: CartesianPath,
    seed: np.ndarray | None,
    timeout: float,
) -> np.ndarray | Trace:
    """A solution of sample 0, or the stopped trace saying why there is none.

    With ``seed``, the solution nearest it. Without, the solver is started from the middle of
    the limits and from :data:`START_SEEDS` seeded random joint vectors, each solution's revolute
    joints are turned by whole turns toward mid-range, and the solution farthest from the joint
    limits (relative to each range) is kept: a start at a limit leaves the differential steps no
    room.
    """
    target = path.target(0)
    if seed is not None:
        starts = [seed]
    else:
        lower, upper = robot.lower, robot.upper
        random = np.random.default_rng(0).uniform(lower, upper, (START_SEEDS, robot.nq))
        starts = [(lower + upper) / 2.0, *random]
    solve = bind_timeout(solver, timeout / len(starts))
    solutions, why = [], ""
    for start in starts:
        result = solve(target, start)
        solutions += [np.asarray(s.q, dtype=float) for s in result.solutions]
        why = f"{result.status}: {result.message}"
    if not solutions:
        return Trace(q=[], branches=[], branch_changes=[]).stop(
            0, f"no solution inside the limits ({why})"
        )
    # The same pose a whole turn away: revolute joints as near the seed (or mid-range) as allowed.
    lower, upper = robot.lower, robot.upper
    unwrap = TurnUnwrapper(robot)
    solutions = [unwrap(q, (lower + upper) / 2.0 if seed is None else seed) for q in solutions]
    if seed is not None:
        return min(solutions, key=lambda q: float(np.abs(q - seed).max()))
    span = np.maximum(upper - lower, 1e-12)
    return max(solutions, key=lambda q: float((np.minimum(q - lower, upper - q) / span).min()))
