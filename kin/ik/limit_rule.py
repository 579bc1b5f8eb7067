"""The limit rule: an angle moved into the joint limits, the ``2 pi`` copy nearest a seed.

One rule for every solver that moves angles into the limits: the single call of a closed form
(:mod:`.analytic.branch_verification`), its batches (:mod:`.analytic.batch`, through
:func:`kin.ik.solve_batch`), the free-joint scans of the 7R forms and the compiled twins
(``nearest_copy`` and ``wrap_into`` in ``kin/_native/ik/analytic/six_r/_six_r_twin.h``, operation for operation):

- the candidates are ``value + 2 pi k``; one inside ``[lower, upper]`` (with :data:`LIMIT_TOL`
  [rad] of slack for angles computed exactly at a limit) beats one outside;
- among those inside, the nearest the seed wins; among those outside, the least violation,
  then the nearest the seed; on a tie, the first of ``base, base - 2 pi, base + 2 pi,
  base - 4 pi, base + 4 pi`` (``base``: the copy nearest the seed).

:func:`nearest_copy` is the rule; :func:`wrap_into` the same answer, comparing only the
candidates that can win; :func:`nearest_copies` the rule on arrays; :func:`nearest_inside` its
answer when inside, else None; :func:`turn_copies` every copy within the limits (a planner's goal
twins).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

TWO_PI = 2.0 * math.pi
#: Slack on the joint limits [rad] for angles computed exactly at a limit.
LIMIT_TOL = 1e-10
#: Closer than this to the seed [rad], an angle inside the limits is the copy that
#: :func:`nearest_copy` picks (the other copies are more than ``pi`` away). The margin below
#: ``pi`` covers the round-off of seeds up to :data:`FAST_SEED` in magnitude.
FAST_COPY = math.pi - 1e-9
#: Seeds up to this magnitude [rad] take the fast interval of :data:`FAST_COPY`.
FAST_SEED = 1e5
#: The shifts of the candidates from ``base``, in the order that breaks ties [rad].
_SHIFTS = (0.0, -TWO_PI, TWO_PI, -2 * TWO_PI, 2 * TWO_PI)


def nearest_copy(value: float, seed: float, lower: float, upper: float) -> tuple[float, bool]:
    """The ``value + 2 pi k`` inside ``[lower, upper]`` closest to ``seed``, else the least outside.

    Args:
        value: Angle [rad].
        seed: Angle the copy should be near [rad].
        lower: Lower joint limit [rad].
        upper: Upper joint limit [rad].

    Returns:
        The copy [rad] and whether it is inside the limits (within :data:`LIMIT_TOL`).
    """
    base = value - TWO_PI * round((value - seed) / TWO_PI)
    best, best_key = base, (math.inf, math.inf)
    for candidate in (base, base - TWO_PI, base + TWO_PI, base - 2 * TWO_PI, base + 2 * TWO_PI):
        violation = max(lower - LIMIT_TOL - candidate, candidate - upper - LIMIT_TOL, 0.0)
        key = (violation, abs(candidate - seed))
        if key < best_key:
            best, best_key = candidate, key
    return best, best_key[0] == 0.0


def wrap_into(value: float, seed: float, lower: float, upper: float) -> tuple[float, bool]:
    """:func:`nearest_copy`, comparing only the candidates that can win (same keys, same order).

    When the copy nearest the seed, ``base``, is below the limits, the copies below it have a
    larger violation and never win; going up, a copy that is no longer below the limits (inside
    or above them) beats every copy after it: usually the first one up, the only one compared
    here (the others go through :func:`nearest_copy`). Likewise above the limits.
    """
    base = value - TWO_PI * round((value - seed) / TWO_PI)
    lower_tol = lower - LIMIT_TOL
    violation = lower_tol - base
    if violation > 0.0:  # below the limits: the copy above decides
        candidate = base + TWO_PI
        if lower_tol - candidate > 0.0:  # still below
            return nearest_copy(value, seed, lower, upper)
        candidate_violation = candidate - upper - LIMIT_TOL
    else:
        violation = base - upper - LIMIT_TOL
        if violation > 0.0:  # above the limits: the copy below decides
            candidate = base - TWO_PI
            if candidate - upper - LIMIT_TOL > 0.0:  # still above
                return nearest_copy(value, seed, lower, upper)
            candidate_violation = lower_tol - candidate
        elif -FAST_COPY < base - seed < FAST_COPY:
            return base, True
        else:
            return nearest_copy(value, seed, lower, upper)
    if candidate_violation < 0.0:
        candidate_violation = 0.0
    if candidate_violation < violation or (
        candidate_violation == violation and abs(candidate - seed) < abs(base - seed)
    ):
        return candidate, candidate_violation == 0.0
    return base, False


def nearest_inside(value: float, seed: float, lower: float, upper: float) -> float | None:
    """The copy of :func:`wrap_into` when it is inside the limits [rad], else None."""
    copy, inside = wrap_into(value, seed, lower, upper)
    return copy if inside else None


def turn_copies(
    value: float, lower: float, upper: float, near: float, most: int = 3
) -> list[float]:
    """``value`` and its copies ``value + 2 pi k`` within ``[lower, upper]`` nearest ``near`` [rad].

    At most ``most`` values in all, ``value`` always among them (inside or not; the other copies
    inside, with :data:`LIMIT_TOL` of slack), nearest ``near`` first. Non-finite values or limits
    give ``value`` alone.
    """
    if not all(math.isfinite(x) for x in (value, lower, upper, near)):
        return [value]
    low = math.ceil((lower - LIMIT_TOL - value) / TWO_PI)
    high = math.floor((upper + LIMIT_TOL - value) / TWO_PI)
    middle = round((near - value) / TWO_PI)  # the copy nearest ``near``
    turns = range(max(low, middle - most), min(high, middle + most) + 1)
    copies = sorted((value + k * TWO_PI for k in turns if k != 0), key=lambda c: abs(c - near))
    return [value, *copies[: most - 1]]


def nearest_copies(
    values: npt.ArrayLike, seeds: npt.ArrayLike, lower: npt.ArrayLike, upper: npt.ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`nearest_copy` of every angle: the same keys, comparisons and order, on arrays.

    Args:
        values: Angles (..., nq) [rad]; a NaN stays NaN (outside).
        seeds: Seeds broadcast against ``values`` [rad].
        lower: Lower limits (nq,) [rad].
        upper: Upper limits (nq,) [rad].

    Returns:
        The copies (..., nq) [rad] and, per angle, whether it is inside the limits.
    """
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:  # one joint vector
        q, inside = nearest_copies(values[None], seeds, lower, upper)
        return q[0], inside[0]
    shape = values.shape
    seed = np.ascontiguousarray(np.broadcast_to(np.asarray(seeds, dtype=float), shape))
    lows = np.broadcast_to(np.asarray(lower, dtype=float), shape[-1:]) - LIMIT_TOL
    uppers = np.broadcast_to(np.asarray(upper, dtype=float), shape[-1:])
    with np.errstate(invalid="ignore"):
        base = values - TWO_PI * np.round((values - seed) / TWO_PI)
        near = np.abs(base - seed) < FAST_COPY  # nearer the seed than the other copies
        near &= base == base  # not NaN
        done = np.empty(shape, dtype=bool)
        for j, (low, high) in enumerate(zip(lows.tolist(), uppers.tolist())):  # one joint
            column = base[..., j]
            inside = column >= low
            inside &= column - high - LIMIT_TOL <= 0.0
            # Inside the limits and near the seed: the copy nearest_copy picks.
            ok = inside & near[..., j]
            done[..., j] = ok
            rest = ~ok
            rest &= column == column  # not NaN
            if rest.any():
                column[rest], done[..., j][rest] = _wrap_into(
                    column[rest], seed[..., j][rest], low, high
                )
    return base, done


def _wrap_into(
    base: np.ndarray, seed: np.ndarray, low: float, upper: float
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`wrap_into` of the copies ``base`` nearest ``seed`` (1-D, not NaN), on arrays."""
    below = low - base  # the violation of base below the limits when positive
    above = base - upper - LIMIT_TOL  # and above
    is_below = below > 0.0
    outside = is_below | (above > 0.0)
    candidate = base + np.where(is_below, TWO_PI, -TWO_PI)  # one turn toward the limits
    violation = np.where(is_below, below, above)
    further = np.where(is_below, candidate - upper - LIMIT_TOL, low - candidate)
    candidate_violation = np.maximum(further, 0.0)
    take = candidate_violation < violation
    tie = candidate_violation == violation
    if tie.any():  # the nearer the seed
        take |= tie & (np.abs(candidate - seed) < np.abs(base - seed))
    take &= outside
    copies = np.where(take, candidate, base)
    inside = take & (candidate_violation == 0.0)
    # Inside but far from the seed, or two turns outside: every candidate compared.
    still = np.where(is_below, low - candidate, candidate - upper - LIMIT_TOL) > 0.0
    hard = ~outside | still
    if hard.any():
        copies[hard], inside[hard] = _nearest_copies(base[hard], seed[hard], low, upper)
    return copies, inside


def _nearest_copies(
    base: np.ndarray, seeds: np.ndarray, low: float, upper: float
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`nearest_copies` of the copies ``base`` nearest ``seeds``, every candidate compared."""
    best = base
    best_violation = np.full(base.shape, math.inf)
    best_distance = np.full(base.shape, math.inf)
    with np.errstate(invalid="ignore"):
        for shift in _SHIFTS:
            candidate = base + shift if shift else base
            violation = np.maximum(np.maximum(low - candidate, candidate - upper - LIMIT_TOL), 0.0)
            distance = np.abs(candidate - seeds)
            better = (violation < best_violation) | (
                (violation == best_violation) & (distance < best_distance)
            )
            best = np.where(better, candidate, best)
            best_violation = np.where(better, violation, best_violation)
            best_distance = np.where(better, distance, best_distance)
    return best, best_violation == 0.0
