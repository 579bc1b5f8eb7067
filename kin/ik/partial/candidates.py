"""The closed form's branches for a partial target, moved into the limits nearest the seed.

Units: joint values [rad] (or [m] for prismatic joints).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np

from ..targets.target import AxisTarget, PoseTarget, PositionTarget
from .context import PartialContext
from .task import PartialTask, sweep

__all__ = ["candidates", "kept"]


def candidates(
    ctx: PartialContext, task: PartialTask, seed: np.ndarray, grid: bool = False
) -> Iterator[list[tuple[np.ndarray, str]]]:
    """The closed form's branches for the target (moved into the limits nearest the seed).

    One group of branches per tool rotation, computed when the caller asks for the next. A
    target with one free rotation (an axis target's roll, a mask that frees one rotation
    component) gives the branches of one rotation (``grid`` False: the seed's roll, or the
    mask's given rotation) or of the other :data:`~.settings.ROLL_GRID` - 1 rotations of a turn
    about the free axis, nearest that one first (``grid`` True, :func:`~.task.sweep`).
    """
    structure = ctx.structure
    if structure is None:
        return
    kinds = structure.target_kinds
    target = task.target
    labels = structure.branch_labels
    try:
        if PoseTarget in kinds and (isinstance(target, AxisTarget) or target.mask is not None):
            yield from _swept(ctx, task, seed, grid)
            return
        if PoseTarget in kinds and isinstance(target, PoseTarget):
            raw = np.asarray(structure.solve(target.position, target.rotation), dtype=float)
        elif PositionTarget in kinds:  # the position's branches, judged on the rest
            raw = np.asarray(structure.solve(target.position, None), dtype=float)
        else:
            return
    except (ValueError, ArithmeticError, np.linalg.LinAlgError):
        return
    yield kept(ctx, raw, list(labels), seed, True)


def _swept(
    ctx: PartialContext, task: PartialTask, seed: np.ndarray, grid: bool
) -> Iterator[list[tuple[np.ndarray, str]]]:
    """The branches of each rotation of the sweep, one group per rotation."""
    structure = ctx.structure
    at_seed, turned = ctx.fk(seed)
    position = task.near(at_seed)  # a free component is any value: the seed's instead
    rotations, names = sweep(task, turned, grid)
    if ctx.pose_candidates is None:  # the structure's batch, then one group each
        positions = np.repeat(position[None, :], len(rotations), axis=0)
        raw = np.asarray(structure.solve_batch(positions, rotations), dtype=float)
        raw = raw.reshape(len(rotations), -1, raw.shape[-1])
        for k, name in enumerate(names):
            labels = [f"{label}, {name}" for label in structure.branch_labels]
            yield kept(ctx, raw[k], labels, seed, True)
        return
    for k, name in enumerate(names):  # the closed form's own branches
        branches = ctx.pose_candidates(position, rotations[k : k + 1], seed)
        yield kept(
            ctx, [q for q, _ in branches], [f"{b}, {name}" for _, b in branches], seed, False
        )


def kept(
    ctx: PartialContext, raw: Any, names: list[str], seed: np.ndarray, forward: bool
) -> list[tuple[np.ndarray, str]]:
    """The finite joint vectors of ``raw`` moved into the limits nearest the seed, named.

    ``forward``: ``raw`` is in the structure's forward table (``q' = direction * q``).
    """
    out = []
    for q, name in zip(raw, names):
        q = np.asarray(q, dtype=float) * (ctx.directions if forward else 1.0)
        if q.shape == (ctx.nq,) and np.isfinite(q).all() and np.abs(q).max() < 1e9:
            out.append((ctx.wrapped(q, seed)[0], name))
    return out
