"""One chunk of a Monte Carlo workspace: its joint vectors drawn and its tool points reduced.

Every reduction is exact (min, max, logical or, integer sums), so merging chunks in any order,
in this process, in worker processes or on a Dask cluster (:mod:`kin.workspace.run`), gives the
same statistics (:mod:`kin.workspace.monte_carlo`). Lengths in meters.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dh2urdf import DHTable

from ..batch_fk import batch_frame_origins
from .grid import WorkspaceGrid

__all__ = ["HIT_CAP", "ChunkReduction", "reduce_chunk"]

#: Largest per-voxel sample count kept (only 1 and 2 matter to the estimate).
HIT_CAP = 3


@dataclass(frozen=True, eq=False)
class ChunkReduction:
    """Reduced samples of one or more chunks (exact to merge, in any order).

    Attributes:
        n_samples: Joint vectors drawn.
        extremes: Minima and maxima: radius from the base axis, distance from the shoulder
            [m] as (min_r, -max_r, min_s, -max_s, min x, min y, min z, -max x, -max y, -max z):
            every entry merges by ``np.minimum``.
        occupancy: Packed voxel occupancy of the even and odd samples, (2, bytes).
        projections: Sample counts per column of the grid seen along z, y and x: (3, side, side).
        hits: Samples per voxel, capped at :data:`HIT_CAP` (uint8, side**3): the voxels hit
            once and twice give the estimate of the voxels not hit yet.
    """

    n_samples: int
    extremes: np.ndarray
    occupancy: np.ndarray
    projections: np.ndarray
    hits: np.ndarray

    def merge(self, other: ChunkReduction) -> ChunkReduction:
        """Both reductions together."""
        hits = np.minimum(self.hits.astype(np.uint16) + other.hits, HIT_CAP).astype(np.uint8)
        return ChunkReduction(
            self.n_samples + other.n_samples,
            np.minimum(self.extremes, other.extremes),
            self.occupancy | other.occupancy,
            self.projections + other.projections,
            hits,
        )


def reduce_chunk(table: DHTable, grid: WorkspaceGrid, n: int, seed: np.random.SeedSequence):
    """Draw ``n`` joint vectors from ``seed`` and reduce their tool points (one chunk)."""
    rng = np.random.default_rng(seed)
    q = table.lower + (table.upper - table.lower) * rng.random((n, table.dof))
    shoulder, tool = batch_frame_origins(table, q, (1,))
    base = np.asarray(table.T_world_base)[:3, 3][:, None]
    radius = np.hypot(tool[0] - base[0], tool[1] - base[1])
    distance = np.linalg.norm(tool - shoulder, axis=0)
    extremes = np.concatenate(
        [
            [radius.min(), -radius.max(), distance.min(), -distance.max()],
            tool.min(axis=1),
            -tool.max(axis=1),
        ]
    )
    side = grid.voxels_per_side
    ix, iy, iz = grid.indices(tool)
    flat = (ix * side + iy) * side + iz
    occupancy = np.zeros((2, side**3), dtype=bool)
    occupancy[0, flat[0::2]] = True
    occupancy[1, flat[1::2]] = True
    projections = np.stack(
        [
            np.bincount(a * side + b, minlength=side * side).reshape(side, side)
            for a, b in ((ix, iy), (ix, iz), (iy, iz))
        ]
    )
    hits = np.minimum(np.bincount(flat, minlength=side**3), HIT_CAP).astype(np.uint8)
    return ChunkReduction(n, extremes, np.packbits(occupancy, axis=1), projections, hits)
