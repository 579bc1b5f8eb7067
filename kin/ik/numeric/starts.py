"""Stage 1 of the numeric pipeline: damped Newton from the seed-table samples nearest the target.

The starts are the posture preference (first), the caller's seed (first when its tool pose is at
least as near as the nearest sample's, else second) and the seed-table samples whose tool poses are
nearest to the target. From each, clamped damped Newton steps on Pinocchio
(:mod:`kin.ik.numeric.damped_newton`) that give up early when stuck: the next start is cheaper than
the remaining steps.
"""

from __future__ import annotations

from collections.abc import Iterator
from operator import le
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..result import IKResult
from .damped_newton import load_linalg
from .numeric_target import NumericTarget

if TYPE_CHECKING:
    from .search import Search
    from .solver import NumericIK

#: :attr:`IKResult.method` of a start from the seed table, and from the caller's seed / posture.
SEED_TABLE = "seed_table"
DAMPED_NEWTON = "damped_newton"


def solve_from_starts(
    ik: NumericIK, search: Search, seed_q: npt.ArrayLike | None
) -> IKResult | None:
    """Damped Newton from each start in turn; the first verified result, else None.

    The first run of the process loads SciPy's LAPACK (:func:`.damped_newton.load_linalg`)
    outside the budget: the deadline moves by the loading time.
    """
    search.deadline += load_linalg()
    for label, q0, index in seed_table_starts(ik, search.target, seed_q):
        outcome = search.newton(q0, ik.patience)
        method = SEED_TABLE if index >= 0 else DAMPED_NEWTON
        message = f"damped Newton from {label}, {outcome.iterations} steps"
        done = search.accept(outcome, method, message)
        if done is not None:
            return done
        if search.expired():
            break
    return None


def seed_table_starts(
    ik: NumericIK, target: NumericTarget, seed_q: npt.ArrayLike | None
) -> Iterator[tuple[str, np.ndarray, int]]:
    """Start joint vectors, most promising first (ranked lazily: most targets need one).

    A posture preference is the first start; the caller's seed goes first (else second) when
    its tool pose is at least as near as the nearest sample's.

    Yields ``(label, q0, index)``: ``index`` is the seed-table sample's, -1 for the caller's.
    """
    table = ik.table
    extra: list[tuple[str, np.ndarray, int]] = []
    if target.posture is not None:  # the caller's preference: always first
        yield "the preferred posture", np.asarray(target.posture, dtype=float), -1
    if seed_q is not None:
        extra.append(("the given seed", ik.seed_vector(seed_q), -1))
    found = table.ranked(target.position, target.rotation)
    if found is None or found[0].size < ik.nearest:  # outside the grid: the KD-tree
        candidates, distances = table.nearest(target.position, target.rotation, k=ik.nearest), None
        first = 0
    else:
        candidates, distances = found
        first = int(distances.argmin())
    # A caller's start goes first when its tool pose is at least as near as the nearest
    # sample's (in the table's pose embedding), else second.
    ahead: list[tuple[str, np.ndarray, int]] = []
    behind: list[tuple[str, np.ndarray, int]] = []
    if extra:
        nearest = (
            embedding_distance(ik, table.q[candidates[first]], target)
            if distances is None
            else float(distances[first])
        )
        for start in extra:
            near = embedding_distance(ik, start[1], target) <= nearest
            (ahead if near else behind).append(start)
    yield from ahead
    index = int(candidates[first])
    yield f"seed-table sample {index}", table.q[index], index
    yield from behind
    if distances is None:
        rest = candidates[1:].tolist()
    else:
        ranked = np.argsort(distances, kind="stable")[: ik.nearest]
        rest = [candidates[i] for i in ranked if i != first][: ik.nearest - 1]
    for i in rest:
        index = int(i)
        yield f"seed-table sample {index}", table.q[index], index


def embedding_distance(ik: NumericIK, q: np.ndarray, target: NumericTarget) -> float:
    """Squared distance of ``q``'s tool pose to the target in the seed table's embedding."""
    values = q.tolist()
    if not (all(map(le, ik._lows, values)) and all(map(le, values, ik._highs))):
        q = np.minimum(np.maximum(q, ik.lower), ik.upper)
    pose = ik.judge.tool_pose(q)
    x, y, z = np.subtract(pose.translation, target.position).tolist()
    distance = x * x + y * y + z * z
    if target.rotation is not None:  # |R - R_t|_F^2 = 6 - 2 <R, R_t> for rotations
        inner = float(np.vdot(pose.rotation, target.rotation))
        distance += ik.table.rotation_weight**2 * (6.0 - 2.0 * inner)
    return distance
