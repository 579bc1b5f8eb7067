"""``NumericIK.solve(..., all_branches=True)``: the redundancy of a 7R arm exposed, branch by branch.

On an arm with a free-joint closed form (:mod:`.free_joint`: Panda, FR3, xArm7, humanoid7, iiwa,
Gen3, any 7R URDF it fits) and a full-pose target, every branch of the closed form at a stated
set of free-joint values:

- :data:`~kin.ik.analytic.seven_r.branches7.GRID` values evenly spaced over the free joint's
  range (:func:`~kin.ik.analytic.seven_r.branches7.free_grid`: the midpoints of equal cells, over
  one turn at most, the other turns as copies);
- the seed's value (the seed moved inside the limits first).

The usual answer (:meth:`~.solver.NumericIK.solve`) is not solved: it may lie at another value
of the free joint (a seed-table sample's, a scan's), and it is one of the branches at its own
value (``free_values=[q[free]]``). With no branch at these values, the call is the usual one
(an answer elsewhere, or its status says why there is none: ``out_of_reach``, ``timeout``, ...).

Each branch goes into the limits in every ``2 pi`` copy of its joints
(:func:`~kin.ik.analytic.seven_r.branches7.windings`) and is measured by the judge's batched
twin (:func:`kin.batch_forward_kinematics` of the robot's table, :func:`~kin.ik.judge.batch_pose_errors`;
limits without tolerance): kept within :data:`BRANCH_TOLERANCE` (or the caller's tolerances,
when tighter). A branch off by less than :data:`NEAR_MISS` (a near-double root, an idealised
table's answer) is first polished on the true chain (:func:`~kin.ik.analytic.idealised.polish`).
Branches equal modulo a turn within ``DISTINCT`` are one; the rest are returned nearest the seed
first (Euclidean distance in joint space). Branches on target with no copy inside the limits are
the result's ``rejected``.

Where the form has a compiled twin (:class:`~kin.ik.analytic.seven_r.seven_dof.SevenDofIK`,
:class:`~kin.ik.analytic.seven_r.spherical_shoulder7.SphericalShoulder7RIK` on a table of
revolute rows turning forward), each set of values is one C call
(``all_branches``, ``kin/_native/ik/analytic/seven_r/_branches7.h``): the same steps in the same order, the judge's
errors by the table's DH product; a near miss hands the target back to this module's path
(``tests/native/test_all_branches_twin.py`` holds the two to the same answers).

Any other arm or target (a position, a mask, an axis) gets the usual answer.
"""

from __future__ import annotations

import functools
import time
from typing import Any

import numpy as np
import numpy.typing as npt

from kin.batch_fk import batch_forward_kinematics
from kin.configuration import seed_inside

from ..analytic.idealised import polish
from ..analytic.seven_r.branches7 import GRID, branches_over, distinct, windings
from ..judge import POSITION_TOLERANCE, ROTATION_TOLERANCE, batch_pose_errors
from ..result import IKResult, IKSolution
from ..targets.target import PoseTarget
from .branch_arm import BranchArm, branch_arm, form_rows
from .free_joint import METHOD
from .numeric_target import NumericTarget
from .search import PIPELINE

#: Largest pose error of a returned branch [m] and [rad] (the closed forms' rounding is far below).
BRANCH_TOLERANCE = 1e-9
#: A branch off by less than this [m] / [rad] is polished on the true chain before it is judged.
NEAR_MISS = 1e-3


def solve_all_branches(
    ik: Any,
    target: object,
    seed: npt.ArrayLike | None = None,
    *,
    free_values: npt.ArrayLike | None = None,
    position_tol: float = POSITION_TOLERANCE,
    rotation_tol: float = ROTATION_TOLERANCE,
    **options: Any,
) -> IKResult:
    """Every verified branch of a full-pose target at the stated free-joint values (see the module).

    Args:
        ik: The solver.
        target: Tool target (a :class:`~kin.ik.PoseTarget` without mask or a
            :class:`NumericTarget` with a rotation gets every branch; any other the usual answer).
        seed: Start joint vector [rad], moved into the limits; None: the solver's default.
        free_values: The free-joint values [rad] instead of the grid and the seed's (the peer
            comparison asks at the values of ssik's answers).
        position_tol: Success tolerance [m] (a branch's is at most :data:`BRANCH_TOLERANCE`).
        rotation_tol: Success tolerance [rad] (a branch's is at most :data:`BRANCH_TOLERANCE`).
        **options: The rest of :meth:`NumericIK.solve`'s options (``timeout``, ...).

    Returns:
        ``IKResult`` whose ``solutions`` are the branches, nearest the seed first; the usual
        answer's result when the arm or target has none (or none verifies).
    """
    start = time.perf_counter()
    closed = ik.closed_form
    rotation = getattr(target, "rotation", None)
    full_pose = (target.__class__ is PoseTarget and target.mask is None) or isinstance(  # type: ignore[attr-defined]
        target, NumericTarget
    )
    usual = functools.partial(
        ik.solve, target, seed, position_tol=position_tol, rotation_tol=rotation_tol, **options
    )
    if closed is None or not hasattr(closed, "branches_at") or rotation is None or not full_pose:
        return usual()
    if not getattr(target, "finite", True):
        return usual()  # its invalid_target
    arm = branch_arm(ik, closed)
    free = arm.free
    near = arm.near if seed is None else seed_inside(ik.robot, ik.seed_vector(seed))
    near = np.asarray(near, dtype=float)
    tolerances = (min(BRANCH_TOLERANCE, position_tol), min(BRANCH_TOLERANCE, rotation_tol))
    if free_values is None:
        grid = _with(arm.grid, float(near[free]))
    else:
        grid = np.unique(np.asarray(free_values, dtype=float))
    found = _found(ik, arm, closed, target, rotation, grid, near, tolerances)
    if not found[0]:
        return usual()  # none at these values: the usual answer, or why there is none
    solutions, rejected = found
    return IKResult(
        True,
        PIPELINE,
        "ok",
        f"{len(solutions)} branches at {grid.size} values of joint {free + 1} (a grid of "
        f"{GRID} over its range, the seed's), each verified"
        if free_values is None
        else f"{len(solutions)} branches at {grid.size} given values of joint {free + 1}",
        solutions,
        rejected,
        time=time.perf_counter() - start,
        method=METHOD,
    )


def _with(grid: np.ndarray, value: float) -> np.ndarray:
    """The sorted ``grid`` [rad] with ``value`` [rad] in its place (once; a new array if added)."""
    at = int(np.searchsorted(grid, value))
    if at < grid.size and grid[at] == value:
        return grid
    return np.insert(grid, at, value)


def _found(
    ik: Any,
    arm: BranchArm,
    closed: Any,
    target: Any,
    rotation: Any,
    grid: np.ndarray,
    near: np.ndarray,
    tolerances: tuple[float, float],
) -> tuple[tuple[IKSolution, ...], tuple[IKSolution, ...]]:
    """The branches at ``grid`` inside the limits, nearest ``near`` first, and those rejected.

    The compiled twin's when the form has one (a near miss hands the target back), else the
    general form's sifted rows, else :func:`_branches`; ``((), ())`` when the form does not
    take the target.
    """
    found = None
    if arm.compiled is not None:
        found = arm.compiled(target, grid, *arm.limits, near, *tolerances, NEAR_MISS, *_MADE)
    elif arm.sift is not None:
        rows = form_rows(closed, target, grid) if arm.rows is None else arm.rows(target, grid)
        if rows is not None:
            found = arm.sift(target, rows, *arm.limits, near, *tolerances, NEAR_MISS, *_MADE)
    if found is None:
        position: np.ndarray = np.array(getattr(target, "position"), dtype=float)
        found = _branches(
            ik, closed, position, np.array(rotation, dtype=float), grid, near, tolerances
        )
    return ((), ()) if found is None else found


def _branches(
    ik: Any,
    closed: Any,
    position: np.ndarray,
    rotation: np.ndarray,
    grid: np.ndarray,
    near: np.ndarray,
    tolerances: tuple[float, float],
) -> tuple[tuple[IKSolution, ...], tuple[IKSolution, ...]] | None:
    """The branches at ``grid`` inside the limits, nearest ``near`` first, and those rejected.

    The reference path of :func:`solve_all_branches` (the compiled twin's ``all_branches``
    repeats it); None when the form does not take the target.
    """
    found = branches_over(closed, position, rotation, grid)
    if found is None:
        return None
    on_target = distinct(_on_target(ik, found, position, rotation, tolerances))
    inside, source = windings(on_target, ik.lower, ik.upper)
    errors = _errors(ik, inside, position, rotation)
    keep = (errors[0] < tolerances[0]) & (errors[1] < tolerances[1])
    keep &= (inside >= ik.lower).all(axis=1) & (inside <= ik.upper).all(axis=1)
    order = np.flatnonzero(keep)
    order = order[np.argsort(((inside[order] - near) ** 2).sum(axis=1), kind="stable")]
    solutions = _solutions(inside[order], errors[0][order], errors[1][order], True)
    outside = on_target[np.setdiff1d(np.arange(on_target.shape[0]), source)]
    rejected: tuple[IKSolution, ...] = ()
    if outside.shape[0]:
        rejected = _solutions(outside, *_errors(ik, outside, position, rotation), False)
    return solutions, rejected


#: The classes and the array maker the compiled ``all_branches`` builds its answer with.
_MADE = (IKSolution, np.empty)


def _errors(
    ik: Any, rows: np.ndarray, position: np.ndarray, rotation: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Position [m] and rotation [rad] errors of joint vectors (M, 7): the judge's batched twin."""
    poses = batch_forward_kinematics(ik.robot.table, rows)
    count = rows.shape[0]
    position_error, rotation_error = batch_pose_errors(
        poses, np.broadcast_to(position, (count, 3)), np.broadcast_to(rotation, (count, 3, 3))
    )
    assert rotation_error is not None
    return position_error, rotation_error


def _on_target(
    ik: Any,
    rows: np.ndarray,
    position: np.ndarray,
    rotation: np.ndarray,
    tolerances: tuple[float, float],
) -> np.ndarray:
    """The rows (M, 7) on target within ``tolerances``, near misses polished on the true chain."""
    if not rows.shape[0]:
        return rows
    position_error, rotation_error = _errors(ik, rows, position, rotation)
    exact = (position_error < tolerances[0]) & (rotation_error < tolerances[1])
    near = ~exact & (position_error < NEAR_MISS) & (rotation_error < NEAR_MISS)
    if not near.any():
        return rows[exact]
    judge = ik.judge
    polished = np.array(
        [
            polish(judge.model, judge.data, judge.frame_id, q, position, rotation, ik.compiled_step)
            for q in rows[near]
        ]
    )
    position_error, rotation_error = _errors(ik, polished, position, rotation)
    good = (position_error < tolerances[0]) & (rotation_error < tolerances[1])
    return np.concatenate((rows[exact], polished[good]))


def _solutions(
    rows: np.ndarray, position_error: np.ndarray, rotation_error: np.ndarray, inside: bool
) -> tuple[IKSolution, ...]:
    """Joint vectors (M, 7) [rad] with their errors [m], [rad] as solutions (``within_limits=inside``)."""
    return tuple(
        IKSolution(q, "", inside, p, r)
        for q, p, r in zip(rows.copy(), position_error.tolist(), rotation_error.tolist())
    )
