"""Stage 1 of the numeric pipeline: damped Newton from the seed-table samples nearest the target.

The starts are the posture preference, the caller's seed and the seed-table samples whose tool
poses are nearest to the target. A redundant problem (more joints than the target constrains, or
a posture preference) has many solutions, and the caller (a user, a Cartesian path) expects the
one nearest the joint vector it gave, not a jump to a sample's branch: the posture is the first
start, and so is the seed when its tool is within ``seed_radius`` of the target; both run their
whole iteration budget. A seed farther, within ``seed_reach`` (and ``seed_turn``), is the first
start too, on a ``seed_leash``: that run gives up as soon as it has moved farther than that from
the seed, or stalls (stage 0 may have run it already). Otherwise the seed goes first only when
its tool pose is at least as near as the nearest sample's, else second. From each start, clamped
damped Newton steps on Pinocchio (:mod:`kin.ik.numeric.damped_newton`); the other starts give up
early when stuck: the next start is cheaper than the remaining steps.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from operator import le
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from ..result import IKResult
from .numeric_target import NumericTarget
from .seed_table import DEFAULT_ROTATION_WEIGHT, nearest_first

if TYPE_CHECKING:
    from .context import NumericContext
    from .search import Search

#: :attr:`IKResult.method` of a start from the seed table, and from the caller's seed / posture.
SEED_TABLE = "seed_table"
DAMPED_NEWTON = "damped_newton"


def solve_from_starts(ik: NumericContext, search: Search) -> IKResult | None:
    """Damped Newton from each start in turn; the first verified result, else None.

    Without a seed table only the posture and the caller's seed. The cap is checked before each
    start (:meth:`~.search.Search.expired`).
    """
    for label, q0, index, patience, leash in seed_table_starts(ik, search):
        if search.expired():
            break
        outcome = search.newton(q0, patience, leash)
        method = SEED_TABLE if index >= 0 else DAMPED_NEWTON
        message = f"damped Newton from {label}, {outcome.iterations} steps"
        done = search.accept(outcome, method, message)
        if done is not None:
            return done
    return None


def seed_table_starts(
    ik: NumericContext, search: Search
) -> Iterator[tuple[str, np.ndarray, int, int | None, float | None]]:
    """Start joint vectors, most promising first (ranked lazily: most targets need one).

    A posture preference is the first start. The caller's seed (unless equal to the posture, or
    already run by stage 0: ``search.seed_tried``) follows it for a redundant problem when its
    tool is near the target (:func:`seed_leash`); otherwise it goes first (else second) when its
    tool pose is at least as near as the nearest sample's.

    Yields ``(label, q0, index, patience, leash)``: ``index`` is the seed-table sample's, -1 for
    the caller's; ``patience`` and ``leash`` those of the damped Newton run (None: the whole
    budget; no leash).
    """
    table = search.table
    target = search.target
    posture = target.posture
    patience, count = ik.settings.patience, ik.settings.nearest
    if posture is not None:  # the caller's preference: always first, the whole budget
        posture = np.asarray(posture, dtype=float)
        yield "the preferred posture", posture, -1, None, None
    seed: np.ndarray | None = None
    if search.seed is not None and not search.seed_tried:
        seed = search.seed
        if posture is not None and np.array_equal(seed, posture):
            seed = None  # the same run again
    if seed is not None:
        first = seed_leash(ik, search, seed)
        if first == math.inf:  # a solution near it: before any sample's, the whole budget
            yield "the given seed", seed, -1, None, None
            seed = None
        elif first is not None:  # likewise, on a leash
            yield "the given seed", seed, -1, patience, first
            seed = None
    if table is None:  # no samples this call: the seed alone
        if seed is not None:
            yield "the given seed", seed, -1, patience, None
        return
    found = table.ranked(target.position, target.rotation)
    if found is None or found[0].size < count:  # outside the grid: every sample
        candidates, distances = table.nearest(target.position, target.rotation, k=count), None
        first_index = 0
    else:
        candidates, distances = found
        first_index = int(distances.argmin())
    # Else the caller's seed goes first when its tool pose is at least as near as the nearest
    # sample's (in the table's pose embedding), else second.
    ahead = False
    if seed is not None:
        nearest = (
            embedding_distance(ik, table.q[candidates[first_index]], target)
            if distances is None
            else float(distances[first_index])
        )
        ahead = not seed_beyond(ik, search, seed, nearest)
        if ahead:
            yield "the given seed", seed, -1, patience, None
    index = int(candidates[first_index])
    yield f"seed-table sample {index}", table.q[index], index, patience, None
    if seed is not None and not ahead:
        yield "the given seed", seed, -1, patience, None
    if distances is None:
        rest = candidates[1:].tolist()
    else:
        ranked = nearest_first(distances, count)
        rest = [candidates[i] for i in ranked if i != first_index][: count - 1]
    for i in rest:
        index = int(i)
        yield f"seed-table sample {index}", table.q[index], index, patience, None


def seed_leash(ik: NumericContext, search: Search, seed: np.ndarray) -> float | None:
    """The leash [rad] of damped Newton from the caller's seed as the first start, or None.

    For a redundant target (:func:`redundant`) whose seed's tool is near it (the caller, a user or
    a Cartesian path, expects the solution near the seed): within ``seed_radius`` (settings) in the
    pose embedding the whole budget (``math.inf``: no leash); within ``seed_reach`` (and a tool
    rotation within ``seed_turn`` of the target's) the run gives up as soon as it moves farther
    than ``seed_leash`` from the seed, or stalls (``patience``): the solution near
    the seed is not where it goes. None otherwise: the seed is no first start. One forward
    kinematics of the seed; its embedding distance is kept in ``search.seed_distance``.
    """
    # In this order: most seeds are far, and a solve from such a seed pays this.
    target = search.target
    if not redundant(ik, target):
        return None
    settings = ik.settings
    pose = ik.judge.tool_pose(seed)
    distance = _translation2(pose, target)
    reach = max(settings.seed_reach, settings.seed_radius)
    if distance > reach * reach:  # the common case of a far seed
        if target.rotation is None:
            search.seed_distance = distance
        else:  # a lower bound of the embedding distance (no rotation's share)
            search.seed_bound = distance
        return None
    values = seed.tolist()
    if not (all(map(le, ik.lows, values)) and all(map(le, values, ik.highs))):
        return seed_leash(ik, search, np.minimum(np.maximum(seed, ik.lower), ik.upper))
    share, inner = _rotation_share(ik, pose, target)
    distance += share
    search.seed_distance = distance
    if distance <= settings.seed_radius * settings.seed_radius:
        return math.inf
    if inner < 1.0 + 2.0 * math.cos(settings.seed_turn):
        return None
    return settings.seed_leash


def seed_distance(ik: NumericContext, search: Search, seed: np.ndarray) -> float:
    """:func:`embedding_distance` of the caller's seed, measured once per solve."""
    distance = search.seed_distance
    if distance is None:
        distance = search.seed_distance = embedding_distance(ik, seed, search.target)
    return distance


def seed_beyond(ik: NumericContext, search: Search, seed: np.ndarray, bound: float) -> bool:
    """Whether :func:`seed_distance` exceeds ``bound`` (a known lower bound spares measuring)."""
    lower = search.seed_bound
    if lower is not None and lower > bound:
        return True
    return seed_distance(ik, search, seed) > bound


def redundant(ik: NumericContext, target: NumericTarget) -> bool:
    """Whether many joint vectors reach ``target``: a posture, or more joints than it constrains.

    A position constrains three coordinates, a full pose six.
    """
    return target.posture is not None or ik.nq > (3 if target.rotation is None else 6)


def embedding_distance(ik: NumericContext, q: np.ndarray, target: NumericTarget) -> float:
    """Squared distance of ``q``'s tool pose to the target in the seed table's embedding."""
    values = q.tolist()
    if not (all(map(le, ik.lows, values)) and all(map(le, values, ik.highs))):
        q = np.minimum(np.maximum(q, ik.lower), ik.upper)
    pose = ik.judge.tool_pose(q)
    return _translation2(pose, target) + _rotation_share(ik, pose, target)[0]


def _translation2(pose: pin.SE3, target: NumericTarget) -> float:
    """Squared distance of a tool pose's origin to the target position [m^2]."""
    x, y, z = pose.translation.tolist()
    tx, ty, tz = target.position.tolist()
    x, y, z = x - tx, y - ty, z - tz
    return x * x + y * y + z * z


def _rotation_share(
    ik: NumericContext, pose: pin.SE3, target: NumericTarget
) -> tuple[float, float]:
    """The rotation's share of the embedding distance [m^2] and ``<R, R_t>`` (3.0 without one).

    ``|R - R_t|_F^2 = 6 - 2 <R, R_t>`` for rotations, and ``<R, R_t> = 1 + 2 cos(angle)``.
    """
    if target.rotation is None:
        return 0.0, 3.0
    inner = float(np.vdot(pose.rotation, target.rotation))
    return DEFAULT_ROTATION_WEIGHT**2 * (6.0 - 2.0 * inner), inner
