"""Stage 1 of the numeric pipeline: damped Newton from the seed-table samples nearest the target.

The starts are the posture preference, the caller's seed and the seed-table samples whose tool
poses are nearest to the target. A redundant problem (more joints than the target constrains, or
a posture preference) has many solutions, and the caller (a user, a Cartesian path) expects the
one nearest the joint vector it gave, not a jump to a sample's branch: the posture is the first
start, and so is the seed when its tool is within ``seed_radius`` of the target; both run their
whole iteration budget. Otherwise the seed goes first only when its tool pose is at least as near
as the nearest sample's, else second. From each start, clamped damped Newton steps on Pinocchio
(:mod:`kin.ik.numeric.damped_newton`); the other starts give up early when stuck: the next start
is cheaper than the remaining steps.
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
    for label, q0, index, patience in seed_table_starts(ik, search.target, seed_q):
        outcome = search.newton(q0, patience)
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
) -> Iterator[tuple[str, np.ndarray, int, int | None]]:
    """Start joint vectors, most promising first (ranked lazily: most targets need one).

    A posture preference is the first start. The caller's seed (unless equal to the posture)
    follows it for a redundant problem (:func:`redundant`) when its tool is within
    ``ik.seed_radius`` of the target; otherwise it goes first (else second) when its tool pose
    is at least as near as the nearest sample's.

    Yields ``(label, q0, index, patience)``: ``index`` is the seed-table sample's, -1 for the
    caller's; ``patience`` that of the damped Newton run (None: the whole budget).
    """
    table = ik.table
    posture = target.posture
    if posture is not None:  # the caller's preference: always first, the whole budget
        posture = np.asarray(posture, dtype=float)
        yield "the preferred posture", posture, -1, None
    seed: np.ndarray | None = None
    if seed_q is not None:
        seed = ik.seed_vector(seed_q)
        if posture is not None and np.array_equal(seed, posture):
            seed = None  # the same run again
    if seed is not None:
        seed_distance = embedding_distance(ik, seed, target)
        if redundant(ik, target) and seed_distance <= ik.seed_radius * ik.seed_radius:
            yield "the given seed", seed, -1, None  # a solution near it: before any sample's
            seed = None
    found = table.ranked(target.position, target.rotation)
    if found is None or found[0].size < ik.nearest:  # outside the grid: the KD-tree
        candidates, distances = table.nearest(target.position, target.rotation, k=ik.nearest), None
        first = 0
    else:
        candidates, distances = found
        first = int(distances.argmin())
    # Else the caller's seed goes first when its tool pose is at least as near as the nearest
    # sample's (in the table's pose embedding), else second.
    ahead = False
    if seed is not None:
        nearest = (
            embedding_distance(ik, table.q[candidates[first]], target)
            if distances is None
            else float(distances[first])
        )
        ahead = seed_distance <= nearest
        if ahead:
            yield "the given seed", seed, -1, ik.patience
    index = int(candidates[first])
    yield f"seed-table sample {index}", table.q[index], index, ik.patience
    if seed is not None and not ahead:
        yield "the given seed", seed, -1, ik.patience
    if distances is None:
        rest = candidates[1:].tolist()
    else:
        ranked = np.argsort(distances, kind="stable")[: ik.nearest]
        rest = [candidates[i] for i in ranked if i != first][: ik.nearest - 1]
    for i in rest:
        index = int(i)
        yield f"seed-table sample {index}", table.q[index], index, ik.patience


def redundant(ik: NumericIK, target: NumericTarget) -> bool:
    """Whether many joint vectors reach ``target``: a posture, or more joints than it constrains.

    A position constrains three coordinates, a full pose six.
    """
    return target.posture is not None or ik.model.nq > (3 if target.rotation is None else 6)


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
