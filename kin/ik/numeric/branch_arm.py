"""What every ``all_branches`` call on one solver shares, made once per solver (:func:`branch_arm`).

The free joint, its grid (:func:`~kin.ik.analytic.seven_r.branches7.free_grid`), the default
seed inside the limits, the limits as C arrays, and the compiled route the form has: its twin's
``all_branches`` (:class:`~kin.ik.analytic.seven_r.seven_dof.SevenDofIK`,
:class:`~kin.ik.analytic.seven_r.spherical_shoulder7.SphericalShoulder7RIK`), or the general 7R
form's rows sifted by a twin (:func:`form_rows`, :func:`_held_rows` on a snapped arm). Used by
:mod:`.all_branches`. Angles in [rad].
"""

from __future__ import annotations

import dataclasses
import functools
import math
import weakref
from collections.abc import Callable
from typing import Any

import numpy as np

from kin.configuration import default_seed, seed_inside

from ..analytic.seven_r.branches7 import GRID, free_grid
from ..analytic.seven_r.general_7r import General7RIK
from ..analytic.seven_r.seven_dof import SevenDofIK
from ..analytic.six_r.general_6r import KEEP_TOL
from ..analytic.twin_support import chain_block
from .free_joint import seed_block


@dataclasses.dataclass(frozen=True)
class BranchArm:
    """What every call on one solver shares, made once (:func:`branch_arm`).

    Attributes:
        free: The free joint (0-based).
        grid: The :func:`free_grid` values [rad] over its range, sorted, read-only.
        near: The default seed moved inside the limits [rad].
        limits: The lower and upper limits, C-contiguous float64 (7,) [rad].
        compiled: The twin's ``all_branches`` bound to the Params of the same form without
            limits (joints in ``[-pi, pi]``, as ``branches_at``) and the Seed block of the table
            (:func:`.free_joint.seed_block`: the judge's DH product); None: the Python path.
        sift: A form without that twin (the general 7R form): a twin's ``sift_rows`` bound to
            the table's chain (:func:`~kin.ik.analytic.twin_support.chain_block`), which takes the form's own
            branches from there; None: the Python path.
        rows: The general 7R form on a snapped arm's form (``General7RIK.ideal``): its twin's
            ``held_rows`` (:func:`_held_rows`), the form's branches without the NaN rows (as
            :func:`form_rows`); None: :func:`form_rows`.
    """

    free: int
    grid: np.ndarray
    near: np.ndarray
    limits: tuple[np.ndarray, np.ndarray]
    compiled: Callable[..., Any] | None
    sift: Callable[..., Any] | None
    rows: Callable[[Any, np.ndarray], np.ndarray | None] | None = None


#: Each live solver's :class:`BranchArm` by its ``id`` (with a weak reference to it: the entry leaves
#: with the solver), a plain dict lookup per call.
_ARMS: dict[int, tuple[weakref.ref[Any], BranchArm]] = {}


def _remember(ik: Any, arm: BranchArm) -> None:
    """Keep ``arm`` as the solver ``ik``'s, until ``ik`` is gone."""
    key = id(ik)
    _ARMS[key] = (weakref.ref(ik, lambda _gone: _ARMS.pop(key, None)), arm)


def branch_arm(ik: Any, closed: Any) -> BranchArm:
    """The :class:`BranchArm` of the solver ``ik`` with its free-joint closed form ``closed``."""
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
    grid.setflags(write=False)
    arm = BranchArm(free, grid, near, limits, compiled, sift, rows)
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
    """:func:`form_rows` of a general form on a snapped arm: its twin's ``held_rows``.

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


def form_rows(closed: Any, target: Any, grid: np.ndarray) -> np.ndarray | None:
    """The form's branches at ``grid`` without their NaN rows (M, 7) [rad], not yet distinct."""
    position = np.asarray(getattr(target, "position"), dtype=float)
    found = closed.branches_at(position, np.asarray(target.rotation, dtype=float), grid)
    if found is None:
        return None
    rows = found.reshape(-1, 7)
    return np.ascontiguousarray(rows[np.isfinite(rows).all(axis=1)])
