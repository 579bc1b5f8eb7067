"""The voxel grid of a workspace: a cube around the base frame origin that holds every reach.

Its half side is :func:`reach_bound`, a bound of the tool's distance from DH frame 0's origin
read off the table, so that the grid is known before any sample is drawn and the chunks'
occupancy grids can be merged by a logical or.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dh2urdf import DHTable

from ..exceptions import KinError

#: Voxels along each side of the grid by default (the voxel is ``2 * reach_bound / this``).
DEFAULT_VOXELS_PER_SIDE = 100
_MAX_VOXELS_PER_SIDE = 256


def reach_bound(table: DHTable) -> float:
    """Upper bound of the tool's distance from the base frame origin [m].

    The sum over rows of ``|a| + |d|`` (a prismatic joint adds ``max(|lower|, |upper|)``) plus
    the length of the tool offset: each DH step moves the point by at most that much.
    """
    total = float(np.linalg.norm(np.asarray(table.T_last_tool)[:3, 3]))
    for row in table.rows:
        total += abs(row.a) + abs(row.d)
        if row.joint_type == "prismatic":
            total += max(abs(row.lower), abs(row.upper))
    return total


@dataclass(frozen=True)
class WorkspaceGrid:
    """A cubic voxel grid around the base frame origin that holds every reachable point.

    Attributes:
        origin_m: Lower corner of the grid in world axes [m].
        voxel_size_m: Edge of a voxel [m].
        voxels_per_side: Voxels along x, y and z.
    """

    origin_m: tuple[float, float, float]
    voxel_size_m: float
    voxels_per_side: int

    @classmethod
    def around(cls, table: DHTable, voxel_size_m: float | None = None) -> WorkspaceGrid:
        """The grid of ``table``: centred on DH frame 0's origin, sides 2 x :func:`reach_bound`.

        Raises:
            KinError: ``voxel_size_m`` would need more than 256 voxels per side.
        """
        bound = max(reach_bound(table), 1e-6)
        size = voxel_size_m or 2.0 * bound / DEFAULT_VOXELS_PER_SIDE
        if not (0 < size <= 4.0 * bound and math.isfinite(bound)):
            raise KinError(
                f"voxel size {size:g} m for a reach of {bound:g} m: give a positive voxel of at "
                f"most {4.0 * bound:.3g} m (twice the workspace's width)"
            )
        side = math.ceil(2.0 * bound / size) + 1
        if not size > 0 or side > _MAX_VOXELS_PER_SIDE:
            raise KinError(
                f"voxel size {size:g} m needs {side} voxels per side for a reach of "
                f"{bound:g} m; at most {_MAX_VOXELS_PER_SIDE}: give a voxel of at least "
                f"{2.0 * bound / (_MAX_VOXELS_PER_SIDE - 1):.3g} m"
            )
        center = np.asarray(table.T_world_base)[:3, 3]
        origin = tuple(float(c - side * size / 2.0) for c in center)
        return cls(origin, float(size), side)  # type: ignore[arg-type]

    def indices(self, points: np.ndarray) -> np.ndarray:
        """Voxel indices (3, N) of points (3, N) [m], clipped to the grid."""
        scaled = (points - np.asarray(self.origin_m)[:, None]) / self.voxel_size_m
        return np.clip(np.floor(scaled), 0, self.voxels_per_side - 1).astype(np.int64)
