"""From starts to one branch inside the limits, for a free-joint form solved in batches.

A form that gives every branch of many targets at many free-joint values in one call
(:class:`BatchedFreeForm`: :class:`~.general_7r.General7RIK`) answers the numeric solver's
first stage here: :func:`first_each` (one start per target, each at its own free value: one
batched solve), :func:`first` (the first of a target's starts with a branch inside the limits,
the free joint scanned outward in batches when asked) and the rule both share,
:func:`nearest_inside` (:func:`nearest_inside_each` on many sets at once). Angles [rad].
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ...limit_rule import nearest_copies

#: The coarsest scan step [rad]: a finer one repeats a scan at this step value for value, each a
#: 6R solve, so it is not run (the first free-joint scan of a call is at this step or coarser).
SCAN_STEP = 0.05
#: Values of a scan solved in the first batch after the start's own (the nearest ones).
NEAR_VALUES = 16


class BatchedFreeForm(Protocol):
    """What the scan asks of a free-joint form: its free joint, limits and batched branches."""

    #: The free joint (0-based).
    free: int
    #: Lower and upper joint limits [rad] (7,).
    lower: np.ndarray
    upper: np.ndarray

    def branches(self, targets: np.ndarray, values: np.ndarray, exact: bool = False) -> np.ndarray:
        """Every branch (n, B, 7) [rad] of targets (n, 4, 4) at free-joint values (n,), NaN rows."""
        ...  # pragma: no cover - the form's own


def nearest_inside(
    branches: np.ndarray, start: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> np.ndarray | None:
    """The branch (7,) inside the limits nearest ``start`` [rad], or None.

    Each joint goes to its 2 pi copy inside the limits nearest the start's value (the limit
    rule, :func:`kin.ik.limit_rule.nearest_copies`).

    Args:
        branches: Branches (B, 7) [rad], NaN rows.
        start: The start joint vector (7,) [rad].
        lower: Lower joint limits (7,) [rad].
        upper: Upper joint limits (7,) [rad].
    """
    found = nearest_inside_each(branches[None], start[None], lower, upper)[0]
    return found if found[0] == found[0] else None


def nearest_inside_each(
    branches: np.ndarray, starts: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> np.ndarray:
    """:func:`nearest_inside` of many branch sets at once: one limit-rule pass over all of them.

    Args:
        branches: Branch sets (n, B, 7) [rad], NaN rows.
        starts: The start joint vector of each set (n, 7), or one for all (7,) [rad].
        lower: Lower joint limits (7,) [rad].
        upper: Upper joint limits (7,) [rad].

    Returns:
        (n, 7) [rad]: per set, the branch inside the limits nearest its start; a NaN row where
        there is none.
    """
    starts = np.asarray(starts, dtype=float)
    if not branches.shape[1]:  # no branch at all
        return np.full((branches.shape[0], 7), np.nan)
    near = starts[..., None, :]  # (n, 1, 7) or (1, 7): against every branch of its set
    chosen, inside = nearest_copies(branches, near, lower, upper)
    ok = inside.all(axis=-1)  # (n, B)
    distance = np.where(ok, ((chosen - near) ** 2).sum(axis=-1), np.inf)
    best = distance.argmin(axis=-1)
    out = np.take_along_axis(chosen, best[:, None, None], axis=1)[:, 0]
    out[~ok.any(axis=-1)] = np.nan
    return out


def first_each(form: BatchedFreeForm, targets: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Per target its start's branch, at the start's free value, inside the limits (no scan).

    The batched :func:`first` of one start per target: one solve of all N targets.

    Args:
        form: The free-joint form.
        targets: ``T_world_tool`` (N, 4, 4).
        starts: One start joint vector per target [rad] (N, 7).

    Returns:
        (N, 7) [rad]: the branch nearest each start, NaN rows where there is none (or the
        start is not finite).
    """
    starts = np.asarray(starts, dtype=float).reshape(-1, 7)
    out = np.full(starts.shape, np.nan)
    rows = np.flatnonzero(np.isfinite(starts).all(axis=1) & np.isfinite(targets).all((1, 2)))
    if not rows.size:
        return out
    clipped = np.clip(starts[rows], form.lower, form.upper)
    branches = form.branches(targets[rows], clipped[:, form.free])
    out[rows] = nearest_inside_each(branches, clipped, form.lower, form.upper)
    return out


def first(
    form: BatchedFreeForm, target: np.ndarray, starts: np.ndarray, out: np.ndarray, step: float
) -> int:
    """The first start from which a branch inside the limits reaches the target.

    A start keeps its free joint's value (clipped into its limits); with ``step > 0`` and no
    branch there, the free joint is scanned outward, ``v +- step``, ``v +- 2 step``, ...,
    inside its limits, solved in batches (the nearest :data:`NEAR_VALUES` first), and the
    nearest value with a branch is taken. A step finer than :data:`SCAN_STEP` scans nothing.

    Args:
        form: The free-joint form.
        target: ``T_world_tool`` (4, 4).
        starts: Start joint vectors [rad] (k, 7); a row with a value that is not finite is
            skipped.
        out: Receives the branch nearest that start [rad] (7,).
        step: Free-joint scan step [rad] (0: no scan).

    Returns:
        The index of that start, or -1 (``out`` untouched).
    """
    starts = np.asarray(starts, dtype=float).reshape(-1, 7)
    finite = np.isfinite(starts).all(axis=1)
    clipped = np.clip(starts, form.lower, form.upper)
    if not step > 0.0:  # every start at its own free value: one batched solve
        rows = np.flatnonzero(finite)
        if not rows.size:
            return -1
        targets = np.broadcast_to(target, (rows.size, 4, 4))
        branches = form.branches(targets, clipped[rows, form.free])
        found = nearest_inside_each(branches, clipped[rows], form.lower, form.upper)
        hits = np.flatnonzero(found[:, 0] == found[:, 0])
        if not hits.size:
            return -1
        out[:] = found[hits[0]]
        return int(rows[hits[0]])
    if step < SCAN_STEP:
        return -1
    for row in np.flatnonzero(finite).tolist():
        scanned = _scan(form, target, clipped[row], step)
        if scanned is not None:
            out[:] = scanned
            return row
    return -1


def _scan(
    form: BatchedFreeForm, target: np.ndarray, start: np.ndarray, step: float
) -> np.ndarray | None:
    """The branch nearest ``start`` at the free value nearest its own that has one, or None."""
    low, high = form.lower[form.free], form.upper[form.free]
    value = start[form.free]
    count = int(max(value - low, high - value) // step)
    ring = np.arange(1, count + 1) * step
    values = np.concatenate(([value], np.stack((value + ring, value - ring), 1).ravel()))
    values = values[(values >= low) & (values <= high)]
    for chunk in (values[:1], values[1 : NEAR_VALUES + 1], values[NEAR_VALUES + 1 :]):
        if not chunk.size:
            continue
        branches = form.branches(np.broadcast_to(target, (chunk.size, 4, 4)), chunk)
        found = nearest_inside_each(branches, start, form.lower, form.upper)
        hits = np.flatnonzero(found[:, 0] == found[:, 0])
        if hits.size:
            return found[hits[0]]
    return None
