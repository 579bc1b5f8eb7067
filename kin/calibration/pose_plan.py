"""Where to measure: N configurations that make every identifiable parameter observable.

D-optimal selection, greedy: from a pool of candidates (uniform within the joint limits, seeded,
the colliding ones removed when a checker is given), add one at a time the configuration that
most increases ``log det(J^T J)`` of the column-scaled regressor of the identifiable parameters
(the nominal arm, its own base and tool, positions or full poses), a small ridge keeping the first
steps defined. The same criterion figaroh calls D-optimality; the report states the determinant's
share and the condition number of the chosen set. The work is bounded by the pool size and N,
never by the clock.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from dh2urdf import DHTable

from .calibration import needed_rows, preference_order, probe_tool
from .exceptions import CalibrationError
from .fit import Noise, residuals
from .identifiability import RANK_TOLERANCE, identify
from .measurements import Measurements
from .parameters import build_model
from .synthetic import random_configurations

#: Candidates per requested configuration (at least MIN_POOL).
POOL_FACTOR = 40
MIN_POOL = 1000
#: Ridge added to the information matrix while it is still singular [1].
RIDGE = 1e-6


@dataclass(frozen=True, eq=False)
class PosePlan:
    """Planned configurations.

    Attributes:
        q: The configurations (N, n) [rad] / [m], in the order chosen.
        identifiable: Names of the parameters they make observable.
        condition_number: Of the chosen set's column-scaled regressor [1].
        candidates: Collision-free candidates the set was chosen from.
        rejected: Candidates removed as colliding.
        needed: Fewest rows that determine the identifiable parameters at all.
    """

    q: np.ndarray
    identifiable: tuple[str, ...]
    condition_number: float
    candidates: int
    rejected: int
    needed: int


def plan_poses(
    table: DHTable,
    count: int,
    *,
    poses: bool = False,
    seed: int = 0,
    collides: Callable[[np.ndarray], np.ndarray] | None = None,
    noise: Noise | None = None,
) -> PosePlan:
    """``count`` configurations chosen D-optimally for calibrating ``table``.

    Args:
        table: The nominal arm.
        count: Configurations wanted.
        poses: Plan for full-pose measurements (else positions of one point).
        seed: Seed of the candidate pool.
        collides: Mask of colliding configurations for (M, n) joint vectors, or None.
        noise: Weights of positions against rotations.

    Raises:
        CalibrationError: Fewer collision-free candidates than ``count``.
    """
    noise = noise or Noise()
    pool = random_configurations(
        table, max(MIN_POOL, POOL_FACTOR * count), np.random.default_rng(seed)
    )
    rejected = 0
    if collides is not None:
        hit = np.asarray(collides(pool), dtype=bool)
        rejected = int(hit.sum())
        pool = pool[~hit]
    if len(pool) < count:
        raise CalibrationError(
            f"only {len(pool)} collision-free candidates for {count} configurations"
        )
    model, x = build_model(
        table, 0 if poses else 1, np.array(table.T_world_base), probe_tool(table)
    )
    fake = Measurements(
        pool,
        np.zeros((len(pool), 1, 3)),
        np.tile(np.eye(3), (len(pool), 1, 1)) if poses else None,
        np.arange(len(pool)),
    )
    J = residuals(model, x, fake, noise, jacobian=True)[1]
    assert J is not None
    order, _, _ = preference_order(model, fake)
    keep = identify(J, model.names, order, RANK_TOLERANCE).identifiable
    per = 6 if poses else 3
    blocks = J[:, keep].reshape(len(pool), per, -1)
    blocks = blocks / np.linalg.norm(J[:, keep], axis=0)
    size = blocks.shape[2]
    info = RIDGE * np.eye(size)
    chosen: list[int] = []
    free = np.ones(len(pool), dtype=bool)
    for _ in range(count):
        inverse = np.linalg.inv(info)
        # gain of a block B: log det(I + B A^-1 B^T)
        inner = (blocks @ inverse) @ np.transpose(blocks, (0, 2, 1)) + np.eye(per)
        gain = np.linalg.slogdet(inner)[1]
        gain[~free] = -np.inf
        best = int(np.argmax(gain))
        chosen.append(best)
        free[best] = False
        info = info + blocks[best].T @ blocks[best]
    picked = blocks[chosen].reshape(-1, size)
    singular = np.linalg.svd(picked, compute_uv=False)
    full = picked.shape[0] >= size and singular[-1] > 0
    condition = float(singular[0] / singular[-1]) if full else float("inf")
    names = tuple(n for n, k in zip(model.names, keep) if k)
    needed = needed_rows(0 if poses else 1, len(names))
    return PosePlan(pool[chosen], names, condition, len(pool), rejected, needed)
