"""The free angle a position target leaves: its stated value, swept to when the seed's misses.

A position on an arm of parallel axes (the chain's yaw ``psi``) or on a ``yaw_planar`` arm (the
pitch) fixes every joint but one angle. The branches are solved exactly at a stated value of it:
the seed's, or, when no branch there is inside the joint limits, the nearest value with one on a
10-degree sweep refined in 1-degree steps (a 1-degree sweep of the whole turn when the coarse one
has none). :func:`free_angle_branches` walks that sweep; with a plain-float solve of one value it
stops at the first value with a branch inside the limits (the single-target path: no NumPy on a
handful of values), and the NumPy path takes the whole-turn sweep only.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable

import numpy as np

#: Steps of the sweep of a free angle over a turn (:func:`sweep_angles`): 1 degree.
SWEEP_STEPS = 360
#: Steps of the first, coarse sweep: 10 degrees (:func:`free_angle_branches`).
COARSE_STEPS = 36
#: Slack on the joint limits [rad] or [m] of the sweep's choice (the judge decides after).
LIMIT_SLACK = 1e-10

#: One branch ``q`` [rad, m] as plain floats (all NaN: none), the single-target path.
Row = tuple[float, ...]
#: Joint limits of the single-target path: ``(lower, upper, revolute)`` per joint, as tuples.
Bounds = tuple[tuple[float, ...], tuple[float, ...], tuple[bool, ...]]


def sweep_angles(start: float, steps: int = SWEEP_STEPS) -> np.ndarray:
    """Angles [rad] of a turn in ``steps`` equal steps from ``start``, nearest it first.

    ``start + d, start - d, start + 2 d, ...`` with ``d = 2 pi / steps`` (``start`` itself not
    included), ``steps - 1`` values.
    """
    k = np.arange(1, steps // 2 + 1)
    order = np.stack([k, -k], axis=1).reshape(-1)[: steps - 1]
    return start + order * (2.0 * math.pi / steps)


def inside_limits(
    q: np.ndarray, lower: np.ndarray, upper: np.ndarray, revolute: np.ndarray
) -> np.ndarray:
    """Whether each joint vector of ``q`` (..., nq) has every value inside the limits.

    A revolute angle [rad] counts as inside when a ``2 pi`` copy of it is; a slide [m] must be.
    NaN rows are outside.
    """
    copy = np.where(revolute, lower + np.remainder(q - lower, 2.0 * math.pi), q)
    with np.errstate(invalid="ignore"):
        ok = (copy >= lower - LIMIT_SLACK) & (copy <= upper + LIMIT_SLACK)
    return np.asarray(ok.all(axis=-1))


def row_inside(row: Row, limits: Bounds) -> bool:
    """:func:`inside_limits` of one branch in plain floats (``limits`` as tuples)."""
    for value, lower, upper, revolute in zip(row, *limits):
        copy = lower + (value - lower) % (2.0 * math.pi) if revolute else value
        if not lower - LIMIT_SLACK <= copy <= upper + LIMIT_SLACK:
            return False
    return True


def first_inside(
    candidates: np.ndarray, lower: np.ndarray, upper: np.ndarray, revolute: np.ndarray
) -> int | None:
    """Index of the first of K candidate sets (K, B, nq) with a branch inside the limits.

    Else the first with a branch at all (it is reachable, only outside the limits), else None.
    """
    inside = inside_limits(candidates, lower, upper, revolute).any(axis=1)
    if inside.any():
        return int(inside.argmax())
    exists = (~np.isnan(candidates).any(axis=-1)).any(axis=1)
    return int(exists.argmax()) if exists.any() else None


def _ring(reach: int) -> list[int]:
    """Steps [1 degree] of the fine sweep before a coarse hit ``reach`` steps away, nearest first."""
    ring = range(max(reach - SWEEP_STEPS // COARSE_STEPS + 1, 1), reach)
    return [step for k in ring for step in (k, -k)]


def _coarse_steps() -> list[int]:
    """Steps [10 degrees] of the coarse sweep, nearest first (:func:`sweep_angles`' order)."""
    half = range(1, COARSE_STEPS // 2 + 1)
    return [step for k in half for step in (k, -k)][: COARSE_STEPS - 1]


def _first_hit(
    solve_one: Callable[[float], list[Row]],
    inside_one: Callable[[float], bool] | None,
    angles: Iterable[float],
    bounds: Bounds,
) -> tuple[list[Row], float] | None:
    """The branches at the first of ``angles`` [rad] with one inside the limits, and that angle."""
    for angle in angles:
        if inside_one is not None:
            if inside_one(angle):
                return solve_one(angle), angle
            continue
        rows = solve_one(angle)
        for row in rows:
            if row_inside(row, bounds):
                return rows, angle
    return None


def free_angle_branches(
    solve_at: Callable[[np.ndarray], np.ndarray],
    start: float,
    limits: tuple[np.ndarray, np.ndarray, np.ndarray],
    solve_one: Callable[[float], list[Row]] | None = None,
    inside_one: Callable[[float], bool] | None = None,
    walk: Callable[[float], float] | None = None,
) -> tuple[np.ndarray, float, bool]:
    """The branches of a position at a stated value of the free angle that the position leaves.

    The seed's value ``start`` when a branch there is inside the limits; else the nearest it
    with a branch inside them on a 10-degree sweep refined in 1-degree steps, or on a 1-degree
    sweep when the coarse one has none (else a value with a branch at all).

    Args:
        solve_at: The branches (K, B, nq) [rad, m] at K values of the free angle [rad].
        start: The seed's value of the free angle [rad].
        limits: ``(lower, upper, revolute)`` per joint: limits [rad] or [m], and which are
            revolute (:func:`inside_limits`).
        solve_one: ``solve_at`` of one value in plain floats (the same branches, faster than
            NumPy on one value): the seed's value and the 10- and 1-degree steps near it, each
            stopping at the first value with a branch inside the limits; None: ``solve_at``.
        inside_one: With ``solve_one``, whether ``solve_one`` of a value has a branch inside the
            limits, faster than building the branches (None: build them and check).
        walk: With ``solve_one``, the compiled twin of the walk (:func:`compiled_walk`): from
            ``start``, the first value of the 10- then 1-degree steps with a branch inside the
            limits, NaN when no 10-degree step has one (None: the walk in Python).

    Returns:
        The branches (B, nq) (NaN rows: none), the free angle's value [rad] and whether it
        was swept to (not the seed's).
    """
    if solve_one is not None:
        return _swept_in_floats(solve_at, start, limits, solve_one, inside_one, walk)
    q = solve_at(np.array([start]))
    if inside_limits(q, *limits).any():
        return q[0], start, False
    # 10-degree steps first; a hit is brought nearer the seed's value in 1-degree steps over the
    # 10 degrees before it (either side); no hit: every 1-degree step.
    coarse = sweep_angles(start, COARSE_STEPS)
    swept = solve_at(coarse)
    hits = inside_limits(swept, *limits).any(axis=1)
    if hits.any():
        k = int(hits.argmax())
        reach = round(abs(coarse[k] - start) / (2.0 * math.pi) * SWEEP_STEPS)
        offsets = np.array(_ring(reach), dtype=float) * (2.0 * math.pi / SWEEP_STEPS)
        if offsets.size:
            fine = solve_at(start + offsets)
            near = inside_limits(fine, *limits).any(axis=1)
            if near.any():
                j = int(near.argmax())
                return fine[j], float(start + offsets[j]), True
        return swept[k], float(coarse[k]), True
    return _whole_turn(solve_at, start, limits, q)


def _swept_in_floats(
    solve_at: Callable[[np.ndarray], np.ndarray],
    start: float,
    limits: tuple[np.ndarray, np.ndarray, np.ndarray],
    solve_one: Callable[[float], list[Row]],
    inside_one: Callable[[float], bool] | None,
    walk: Callable[[float], float] | None,
) -> tuple[np.ndarray, float, bool]:
    """:func:`free_angle_branches` with the seed's value and the near steps in plain floats."""
    bounds: Bounds = (
        tuple(limits[0].tolist()),
        tuple(limits[1].tolist()),
        tuple(limits[2].tolist()),
    )
    rows = solve_one(start)
    if any(row_inside(row, bounds) for row in rows):
        return np.array(rows, dtype=float), start, False
    if walk is not None:
        angle = walk(start)
        if math.isnan(angle):
            return _whole_turn(solve_at, start, limits, np.array(rows, dtype=float)[None])
        return np.array(solve_one(angle), dtype=float), angle, True
    coarse_step = 2.0 * math.pi / COARSE_STEPS
    steps = _coarse_steps()
    hit = _first_hit(solve_one, inside_one, (start + k * coarse_step for k in steps), bounds)
    if hit is None:
        return _whole_turn(solve_at, start, limits, np.array(rows, dtype=float)[None])
    found, angle = hit
    reach = round(abs(angle - start) / (2.0 * math.pi) * SWEEP_STEPS)
    fine_step = 2.0 * math.pi / SWEEP_STEPS
    near = _first_hit(solve_one, inside_one, (start + k * fine_step for k in _ring(reach)), bounds)
    if near is not None:
        found, angle = near
    return np.array(found, dtype=float), float(angle), True


def _whole_turn(
    solve_at: Callable[[np.ndarray], np.ndarray],
    start: float,
    limits: tuple[np.ndarray, np.ndarray, np.ndarray],
    q: np.ndarray,
) -> tuple[np.ndarray, float, bool]:
    """The 1-degree sweep of the whole turn (no 10-degree step has a branch inside the limits).

    ``q`` (1, B, nq): the branches at the seed's value ``start`` [rad], kept when no step has a
    branch inside the limits and the seed's value has a branch at all.
    """
    angles = sweep_angles(start)
    swept = solve_at(angles)
    found = first_inside(swept, *limits)
    if found is not None and (inside_limits(swept[found], *limits).any() or np.isnan(q).all()):
        return swept[found], float(angles[found]), True
    return q[0], start, False


def compiled_walk(
    chain: tuple[float, ...], points: list[tuple[float, float]]
) -> Callable[[float], float] | None:
    """The compiled twin of the walk (``kin/_native/ik/analytic/planar/_pitch_sweep.c``) of a planar 3R chain.

    Args:
        chain: :meth:`~.plane_chain.PlaneChain.walk_data` with its joints' limits [rad].
        points: The target in the chain's plane [m] (:meth:`~.plane_chain.PlaneChain.in_plane`),
            one per base yaw (at most 4).

    Returns:
        ``start -> psi`` [rad] of :func:`free_angle_branches`' walk (NaN: no 10-degree step
        has a branch inside the limits), or None: the twin is not built.
    """
    module = _twin()
    if module is None:
        return None
    data = chain + tuple(value for point in points for value in point)
    first_inside = module.first_inside
    return lambda start: float(first_inside(start, data))


_TWIN: list = []


def _twin():  # noqa: ANN202 - a module or None
    """The compiled walk, loaded on first use (:func:`kin._native.twin`)."""
    if not _TWIN:
        from kin._native import twin

        _TWIN.append(twin("_pitch_sweep"))
    return _TWIN[0]


def free_label(word: str, angle: float, swept: bool) -> str:
    """What a free angle [rad] was set to, for the branch labels."""
    if not swept:
        return f"{word} free: the seed's"
    value = math.degrees(math.remainder(angle, 2.0 * math.pi))
    return f"{word} free: {value:.4g} deg, the nearest the seed's with a branch inside the limits"
