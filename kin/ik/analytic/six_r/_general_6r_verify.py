"""The general 6R batch verified in its compiled twin: every branch into the limits and measured.

:func:`kin.ik.solve_batch` of a general 6R arm whose twin is built takes its branches
(:meth:`.general_6r.General6R.solve_batch`) to the twin's ``verify`` instead of the NumPy
judge of :class:`~..batch.BatchSolver`: each of the 16 branches of a target moved to the ``2 pi``
copy inside the limits nearest the target's seed (the limit rule, :mod:`kin.ik.limit_rule`, as
``wrap_into`` of ``kin/_native/ik/analytic/six_r/_six_r_twin.h`` repeats it) and measured by a plain DH product of
the table (``check_branches_n``, the 6R twins' verifier); the verdicts of
:class:`~..batch.BatchSolver` (the tests compare the two).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...limit_rule import LIMIT_TOL
from ..batch import BatchResult
from ..joint_directions import forward_table, to_joint
from .general_6r import General6R
from .six_r_twin import MISSING, OFF_TARGET, check_params


def check_block(solver: Any) -> np.ndarray | None:
    """The twin's ``check`` block of a :class:`~..batch.BatchSolver`, or None (not a twin's arm).

    The forward table (``q' = direction * q``) with the solver's limits of ``q'`` [rad] and its
    tolerances [m], [rad]; no offsets to go through (the batch wraps the joint values
    themselves, not ``theta`` minus the offsets).
    """
    structure = solver.structure
    if not isinstance(structure, General6R) or structure._twin is None:
        return None
    module = structure._twin[0]
    check = check_params(
        module,
        forward_table(solver.table),
        solver._lower,
        solver._upper,
        solver.tolerance_position,
        solver.tolerance_rotation,
    )
    for name, offset, _ in module.CHECK_LAYOUT:
        if name == "has_offsets":
            check[offset] = 0.0
    return check


def verified_batch(solver: Any, check: np.ndarray, T: np.ndarray, seeds: np.ndarray) -> BatchResult:
    """Every branch of N tool poses ``T`` (N, 4, 4) [m], verified in the twin.

    Args:
        solver: The arm's :class:`~..batch.BatchSolver` (a general 6R structure with its twin).
        check: :func:`check_block` of ``solver``.
        T: ``T_world_tool`` of the targets (N, 4, 4) [m].
        seeds: The arm's seeds (N, 6) [rad].

    Returns:
        What ``solver.solve_poses(T, seeds)`` returns, its judge in C.
    """
    structure = solver.structure
    module = structure._twin[0]
    directions = solver._directions
    p = np.ascontiguousarray(T[:, :3, 3])
    r = np.ascontiguousarray(T[:, :3, :3])
    q = np.ascontiguousarray(structure.solve_batch(p, r))
    start = np.ascontiguousarray(seeds if directions is None else seeds * directions, dtype=float)
    info = np.empty(q.shape[:2] + (4,))
    module.verify(check, q, start, p, r, info)
    status = info[..., 0]
    exists = status != MISSING
    reached = exists & (status != OFF_TARGET)
    with np.errstate(invalid="ignore"):
        inside = (q >= solver._lower - LIMIT_TOL) & (q <= solver._upper + LIMIT_TOL)
    position_error = np.where(exists, info[..., 1], np.nan)
    rotation_error = np.where(exists, info[..., 2], np.nan)
    if directions is not None:
        q = to_joint(q, directions)
    return BatchResult(
        tuple(structure.branch_labels),
        q,
        reached,
        inside.all(axis=-1) & exists,
        np.zeros(status.shape, dtype=bool),
        position_error,
        rotation_error,
    )
