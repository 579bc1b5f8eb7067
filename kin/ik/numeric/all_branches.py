"""``NumericIK.solve(..., all_branches=True)``: the redundancy of a 7R arm exposed, branch by branch.

The usual answer is solved first (:meth:`~.solver.NumericIK.solve`, unchanged). Then, on an arm
with a free-joint closed form (:mod:`.free_joint`: Panda, FR3, xArm7, humanoid7, iiwa, Gen3, any
7R URDF it fits) and a full-pose target, every branch of the closed form at a stated set of
free-joint values:

- :data:`~kin.ik.analytic.seven_r.branches7.GRID` values evenly spaced over the free joint's
  range (:func:`~kin.ik.analytic.seven_r.branches7.free_grid`: the midpoints of equal cells, over
  one turn at most, the other turns as copies);
- the seed's value (the seed moved inside the limits first) and the usual answer's.

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
revolute rows turning forward), all of it after the usual answer is one C call
(``all_branches``, ``kin/_native/_branches7.h``): the same steps in the same order, the judge's
errors by the table's DH product; a near miss hands the target back to this module's path
(``tests/test_all_branches_twin.py`` holds the two to the same answers).

Any other arm or target (a position, a mask, an axis) gets the usual answer.
"""

from __future__ import annotations

import bisect
import dataclasses
import functools
import math
import time
import weakref
from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

from kin.batch_fk import batch_forward_kinematics
from kin.configuration import default_seed, seed_inside

from ..analytic.idealised import polish
from ..analytic.seven_r.branches7 import GRID, branches_over, distinct, free_grid, windings
from ..analytic.seven_r.general_7r import General7RIK
from ..analytic.seven_r.seven_dof import SevenDofIK
from ..analytic.six_r.general_6r import KEEP_TOL
from ..judge import POSITION_TOLERANCE, ROTATION_TOLERANCE, batch_pose_errors
from ..result import IKResult, IKSolution
from ..target import PoseTarget
from .free_joint import METHOD, chain_block, seed_block
from .numeric_target import NumericTarget

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
        free_values: The free-joint values [rad] instead of the grid, the seed's and the usual
            answer's (the peer comparison asks at the values of ssik's answers).
        position_tol: Success tolerance of the usual answer [m].
        rotation_tol: Success tolerance of the usual answer [rad].
        **options: The rest of :meth:`NumericIK.solve`'s options (``timeout``, ...).

    Returns:
        ``IKResult`` whose ``solutions`` are the branches, nearest the seed first; the usual
        answer's result when the arm or target has none (or none verifies).
    """
    start = time.perf_counter()
    result = ik.solve(target, seed, position_tol=position_tol, rotation_tol=rotation_tol, **options)
    closed = ik.closed_form
    rotation = getattr(target, "rotation", None)
    full_pose = (target.__class__ is PoseTarget and target.mask is None) or isinstance(  # type: ignore[attr-defined]
        target, NumericTarget
    )
    if closed is None or not hasattr(closed, "branches_at") or rotation is None or not full_pose:
        return result
    if result.status == "invalid_target":
        return result
    arm = _arm(ik, closed)
    free = arm.free
    near = arm.near if seed is None else seed_inside(ik.robot, ik.seed_vector(seed))
    near = np.asarray(near, dtype=float)
    if free_values is None:  # np.unique of the grid, the seed's value and the answer's
        values = list(arm.grid)
        for value in (float(near[free]), *(float(s.q[free]) for s in result.solutions)):
            at = bisect.bisect_left(values, value)
            if at == len(values) or values[at] != value:
                values.insert(at, value)
        grid = np.array(values)
    else:
        grid = np.unique(np.asarray(free_values, dtype=float))
    tolerances = (min(BRANCH_TOLERANCE, position_tol), min(BRANCH_TOLERANCE, rotation_tol))
    found = None
    if arm.compiled is not None:
        found = arm.compiled(target, grid, *arm.limits, near, *tolerances, NEAR_MISS, *_MADE)
    elif arm.sift is not None:
        rows = _form_rows(closed, target, grid) if arm.rows is None else arm.rows(target, grid)
        if rows is not None:
            found = arm.sift(target, rows, *arm.limits, near, *tolerances, NEAR_MISS, *_MADE)
    if found is None:
        position: np.ndarray = np.array(getattr(target, "position"), dtype=float)
        found = _branches(
            ik, closed, position, np.array(rotation, dtype=float), grid, near, tolerances
        )
    if found is None or not found[0]:
        return result
    solutions, rejected = found
    return IKResult(
        True,
        result.solver,
        "ok",
        f"{len(solutions)} branches at {grid.size} values of joint {free + 1} (a grid of "
        f"{GRID} over its range, the seed's, the answer's), each verified"
        if free_values is None
        else f"{len(solutions)} branches at {grid.size} given values of joint {free + 1}",
        solutions,
        rejected,
        iterations=result.iterations,
        time=time.perf_counter() - start,
        method=METHOD,
    )


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


@dataclasses.dataclass(frozen=True)
class _Arm:
    """What every call on one solver shares, made once (:func:`_arm`).

    Attributes:
        free: The free joint (0-based).
        grid: The :func:`free_grid` values [rad] over its range.
        near: The default seed moved inside the limits [rad].
        limits: The lower and upper limits, C-contiguous float64 (7,) [rad].
        compiled: The twin's ``all_branches`` bound to the Params of the same form without
            limits (joints in ``[-pi, pi]``, as ``branches_at``) and the Seed block of the table
            (:func:`.free_joint.seed_block`: the judge's DH product); None: the Python path.
        sift: A form without that twin (the general 7R form): a twin's ``sift_rows`` bound to
            the table's chain (:func:`.free_joint.chain_block`), which takes the form's own
            branches from there; None: the Python path.
        rows: The general 7R form on a snapped arm's form (``General7RIK.ideal``): its twin's
            ``held_rows`` (:func:`_held_rows`), the form's branches without the NaN rows (as
            :func:`_form_rows`); None: :func:`_form_rows`.
    """

    free: int
    grid: tuple[float, ...]
    near: np.ndarray
    limits: tuple[np.ndarray, np.ndarray]
    compiled: Callable[..., Any] | None
    sift: Callable[..., Any] | None
    rows: Callable[[Any, np.ndarray], np.ndarray | None] | None = None


#: Each live solver's :class:`_Arm` by its ``id`` (with a weak reference to it: the entry leaves
#: with the solver), a plain dict lookup per call.
_ARMS: dict[int, tuple[weakref.ref[Any], _Arm]] = {}


def _remember(ik: Any, arm: _Arm) -> None:
    """Keep ``arm`` as the solver ``ik``'s, until ``ik`` is gone."""
    key = id(ik)
    _ARMS[key] = (weakref.ref(ik, lambda _gone: _ARMS.pop(key, None)), arm)


def _arm(ik: Any, closed: Any) -> _Arm:
    """The :class:`_Arm` of the solver ``ik`` with its free-joint closed form ``closed``."""
    entry = _ARMS.get(id(ik))
    if entry is not None and entry[0]() is ik and entry[1].free == closed.free:
        return entry[1]
    free = int(closed.free)
    grid = free_grid(float(ik.lower[free]), float(ik.upper[free]), GRID)
    compiled = sift = rows = None
    block = seed_block(closed, ik.robot.table, (0.0, 0.0, 0.0), 0.0)
    if block is not None and hasattr(closed.twin, "all_branches"):
        unlimited = _unlimited(closed)
        compiled = functools.partial(closed.twin.all_branches, unlimited.c_params.tobytes(), block)
    elif isinstance(closed, General7RIK) and hasattr(SevenDofIK.twin_module, "sift_rows"):
        block = chain_block(ik.robot.table, SevenDofIK.twin_module)
        if block is not None:
            sift = functools.partial(SevenDofIK.twin_module.sift_rows, block)  # type: ignore[union-attr]
            rows = _held_call(closed, ik.robot.table, block)
    near = np.array(seed_inside(ik.robot, default_seed(ik.robot)), dtype=float)
    limits = (np.ascontiguousarray(ik.lower, float), np.ascontiguousarray(ik.upper, float))
    arm = _Arm(free, tuple(grid.tolist()), near, limits, compiled, sift, rows)
    _remember(ik, arm)
    return arm


def _unlimited(closed: Any) -> Any:
    """The same free-joint form without limits (joints in ``[-pi, pi]``, as ``branches_at``)."""
    return type(closed)(closed.structure, [-math.pi] * 7, [math.pi] * 7)


def _held_call(
    closed: General7RIK, table: Any, block: bytes
) -> Callable[[Any, np.ndarray], np.ndarray | None] | None:
    """:func:`_held_rows` bound to the general form's snapped arm, or None (none, or no twin)."""
    ideal = closed.ideal
    if ideal is None or not hasattr(ideal.twin, "held_rows"):
        return None
    frames = seed_block(ideal, table, (0.0, 0.0, 0.0), 0.0)  # its frames: where targets go
    if frames is None:
        return None
    params = _unlimited(ideal).c_params.tobytes()
    return functools.partial(_held_rows, closed, ideal.twin.held_rows, params, frames, block)


def _held_rows(
    closed: General7RIK,
    call: Callable[..., int],
    params: bytes,
    frames: bytes,
    block: bytes,
    target: Any,
    grid: np.ndarray,
) -> np.ndarray | None:
    """:func:`_form_rows` of a general form on a snapped arm: its twin's ``held_rows``.

    The values it leaves (near a double root of the snapped arm) are solved by the 6R closed
    form (``branches_at(..., exact=True)``), their rows put in their place: the same rows in the
    same order as the form's :meth:`~General7RIK.branches_at`. None when the target is not a
    finite pose (the Python path says what is wrong).
    """
    out = np.empty((grid.size * 8, 7))
    counts = np.empty(grid.size)
    total = call(params, frames, block, target, grid, closed.free, KEEP_TOL, closed.fold_margin,
                 out, counts)  # fmt: skip
    if total < 0:
        return None
    left = np.flatnonzero(counts < 0)
    if not left.size:
        return out[:total]
    position = np.asarray(getattr(target, "position"), dtype=float)
    exact = closed.branches_at(position, np.asarray(target.rotation, dtype=float), grid[left], True)
    assert exact is not None
    pieces, start, extra = [], 0, iter(exact)
    for count in counts.astype(int).tolist():
        if count < 0:
            rows = next(extra)
            pieces.append(rows[np.isfinite(rows).all(axis=1)])
        else:
            pieces.append(out[start : start + count])
            start += count
    return np.ascontiguousarray(np.concatenate(pieces))


def _form_rows(closed: Any, target: Any, grid: np.ndarray) -> np.ndarray | None:
    """The form's branches at ``grid`` without their NaN rows (M, 7) [rad], not yet distinct."""
    position = np.asarray(getattr(target, "position"), dtype=float)
    found = closed.branches_at(position, np.asarray(target.rotation, dtype=float), grid)
    if found is None:
        return None
    rows = found.reshape(-1, 7)
    return np.ascontiguousarray(rows[np.isfinite(rows).all(axis=1)])


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
