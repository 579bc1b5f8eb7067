"""Every branch of a 7R arm's free-joint closed form over a stated set of free-joint values.

A 7R arm has a one-parameter self-motion: the closed forms of this package hold one joint, the
free joint (joint 1 of :mod:`.seven_dof`, joint 7 of :mod:`.spherical_shoulder7`, joint 1 or 7
of :mod:`.general_7r`), and give up to 8 (or 16) joint vectors for each of its values. This
module states the values (:func:`free_grid`), asks the form for all its branches at each
(``branches_at``, limits ignored), and turns them into joint vectors inside the limits:

1. :func:`distinct`: branches equal modulo a turn joint by joint are one (a double root, a
   value given twice);
2. :func:`windings`: each branch in every ``2 pi`` copy of its joints inside the limits (a joint
   of xArm7 turns +-2 pi: up to two copies each), the form ssik's ``enumerate_windings`` also
   returns.

The judge's check of each one (pose and limits) is the caller's
(:mod:`kin.ik.numeric.all_branches`). Angles in [rad].
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

#: Free-joint values of the default grid (:func:`free_grid`).
GRID = 32
#: Two branches closer than this joint by joint, modulo a turn, are one [rad].
DISTINCT = 1e-6

_TWO_PI = 2.0 * math.pi


class BranchesAt(Protocol):
    """What a free-joint closed form offers for the enumeration."""

    #: The free joint (0-based).
    free: int

    def branches_at(
        self, position: np.ndarray, rotation: np.ndarray | None, values: np.ndarray
    ) -> np.ndarray | None:
        """Every branch (G, B, 7) [rad] at free-joint values (G,), NaN rows; None: not taken."""
        ...


def free_grid(low: float, high: float, count: int = GRID) -> np.ndarray:
    """``count`` free-joint values [rad] evenly spaced inside ``[low, high]``, over one turn at most.

    The midpoints of ``count`` equal cells of ``[low, low + min(high - low, 2 pi)]`` (never the
    limits themselves); a range wider than a turn gets the other turns from :func:`windings`.
    A range that is not finite counts from ``-pi``.
    """
    if not math.isfinite(low):
        low = -math.pi
    span = min(high - low, _TWO_PI) if math.isfinite(high) else _TWO_PI
    return low + (np.arange(count) + 0.5) * (span / count)


def distinct(rows: np.ndarray, tol: float = DISTINCT) -> np.ndarray:
    """The rows (M, n) [rad] without those equal to an earlier one modulo a turn (within ``tol``).

    Order kept: of equal rows the first stays. Rows are compared in the order of their first
    joint round the circle, each with the next ones while that joint is within ``tol`` (the
    branches at one free-joint value share it: a handful each).
    """
    count = rows.shape[0]
    if count < 2:
        return rows
    key = np.mod(rows[:, 0], _TWO_PI)
    order = np.argsort(key, kind="stable")
    key = key[order]
    duplicate = np.zeros(count, dtype=bool)
    for offset in range(1, count):
        other = np.roll(order, -offset)
        near = np.mod(np.roll(key, -offset) - key, _TWO_PI) < tol
        if not near.any():
            break
        gap = rows[order[near]] - rows[other[near]]
        same = np.abs(gap - _TWO_PI * np.round(gap / _TWO_PI)).max(axis=1) < tol
        duplicate[np.maximum(order[near], other[near])[same]] = True
    return rows[~duplicate]


def windings(
    rows: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Every joint vector ``rows + 2 pi k`` (joint by joint) inside ``[lower, upper]``.

    Args:
        rows: Joint vectors (M, n) [rad] (revolute joints).
        lower: Lower limits (n,) [rad] (no tolerance, as the judge); a joint whose limits span
            three turns or more (not finite) keeps its value.
        upper: Upper limits (n,) [rad].

    Returns:
        The copies (K, n), row by row in order, and the index (K,) of the row each comes from;
        a row with a joint that has no copy inside its limits gives none.
    """
    out, source = rows, np.arange(rows.shape[0])
    for j in range(rows.shape[1]):
        low, high = float(lower[j]), float(upper[j])
        if not high - low < _TWO_PI * 3:  # unlimited (continuous): the value as it is
            continue
        values = out[:, j]
        first = np.ceil((low - values) / _TWO_PI)  # the lowest k with values + 2 pi k >= low
        count = np.floor((high - values) / _TWO_PI) - first + 1
        count = np.where(np.isfinite(count), np.maximum(count, 0), 0).astype(int)
        index = np.repeat(np.arange(out.shape[0]), count)
        step = np.arange(index.size) - np.repeat(np.cumsum(count) - count, count)
        copies = out[index]
        copies[:, j] = values[index] + _TWO_PI * (first[index] + step)
        inside = (copies[:, j] >= low) & (copies[:, j] <= high)  # rounding at a limit
        out, source = copies[inside], source[index][inside]
    return out, source


def branches_over(
    closed: BranchesAt, position: np.ndarray, rotation: np.ndarray | None, values: np.ndarray
) -> np.ndarray | None:
    """The closed form's branches at ``values`` (G,) [rad], distinct, limits ignored: (M, 7).

    None when the form does not take the target (a position where it needs a full pose).
    """
    found = closed.branches_at(position, rotation, np.asarray(values, dtype=float))
    if found is None:
        return None
    rows = found.reshape(-1, 7)
    return distinct(rows[np.isfinite(rows).all(axis=1)])
