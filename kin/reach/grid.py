"""The grid of a reachability map and the map itself: voxel centres, orientations, indices.

Voxel centres at ``origin + voxel * (i - k, j - k, l - k)`` for i, j, l in ``0 .. 2k``
(:func:`voxel_grid`), and K tool orientations spread evenly over SO(3) by a super-Fibonacci
spiral (:func:`super_fibonacci_rotations`); :class:`ReachMap` holds the index of each voxel
(:mod:`kin.reach.map` computes it). Lengths in meters, the world frame throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..exceptions import KinError

__all__ = [
    "MAX_ORIENTATIONS",
    "MAX_VOXELS_PER_SIDE",
    "ReachMap",
    "smallest_voxel",
    "super_fibonacci_rotations",
    "voxel_grid",
]

#: Most voxels along a side of the grid.
MAX_VOXELS_PER_SIDE = 256
#: Most orientations per voxel.
MAX_ORIENTATIONS = 100_000

# Alexa's constants: sqrt(2) and the real root of psi^4 = psi + 4.
_PHI = math.sqrt(2.0)
_PSI = 1.533751168755204288118041


@dataclass(frozen=True, eq=False)
class ReachMap:
    """The reachability map of a robot (world frame, SI units).

    Attributes:
        robot: Robot name.
        voxel_m: Voxel edge [m].
        centers_m: Voxel centres (n, n, n, 3) [m], indexed (x, y, z): ``centers_m[i, j, l]`` is
            the centre of the voxel i-th along x, j-th along y, l-th along z.
        index: Fraction of the orientations reached at each centre (n, n, n), in [0, 1].
        orientations: K, the tool orientations tried per voxel.
        rotations: Those orientations ``R_world_tool`` (K, 3, 3).
        max_reach_m: The arm's maximum reach from the base origin [m] (voxels whose centre is
            farther have index 0, unsolved).
        time_s: Wall time of the computation [s].
        collisions: ``""`` (poses and limits only), or what the answers were checked against:
            ``"collision-free answers only (scene cell.toml; 42 pairs, padding 0 m)"``.
    """

    robot: str
    voxel_m: float
    centers_m: np.ndarray
    index: np.ndarray
    orientations: int
    rotations: np.ndarray
    max_reach_m: float
    time_s: float
    collisions: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The map as a JSON-ready dict (SI units).

        Keys ``voxel_m``, ``centers_m``, ``index``, ``orientations`` (K), ``time_s``, and
        ``robot``, ``max_reach_m``.
        """
        return {
            "robot": self.robot,
            "voxel_m": self.voxel_m,
            "centers_m": self.centers_m.tolist(),
            "index": self.index.tolist(),
            "orientations": self.orientations,
            "max_reach_m": self.max_reach_m,
            "time_s": self.time_s,
            "collisions": self.collisions,
        }


def super_fibonacci_rotations(count: int) -> np.ndarray:
    """``count`` rotation matrices (count, 3, 3) spread evenly over SO(3) (super-Fibonacci).

    Raises:
        KinError: ``count`` is not a positive integer.
    """
    if not isinstance(count, int | np.integer) or count < 1:
        raise KinError(f"orientations must be a positive integer, got {count!r}")
    s = np.arange(count) + 0.5
    r = np.sqrt(s / count)
    big_r = np.sqrt(1.0 - s / count)
    alpha = 2.0 * math.pi * s / _PHI
    beta = 2.0 * math.pi * s / _PSI
    # Unit quaternions (w, x, y, z).
    w, x = r * np.sin(alpha), r * np.cos(alpha)
    y, z = big_r * np.sin(beta), big_r * np.cos(beta)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def smallest_voxel(reach: float) -> float:
    """The smallest voxel edge [m] whose grid holds ``reach`` [m] in :data:`MAX_VOXELS_PER_SIDE`."""
    return 2.0 * reach / (MAX_VOXELS_PER_SIDE - 1)


def voxel_grid(origin: np.ndarray, voxel: float, reach: float) -> np.ndarray:
    """Voxel centres (n, n, n, 3) [m] of the cube around ``origin`` that holds ``reach``."""
    half = max(0, math.ceil(reach / voxel - 0.5))
    side = 2 * half + 1
    if side > MAX_VOXELS_PER_SIDE:
        raise KinError(
            f"voxel {voxel:g} m needs {side} voxels per side for a reach of {reach:.4g} m; at "
            f"most {MAX_VOXELS_PER_SIDE}: give a voxel of at least {smallest_voxel(reach):.3g} m"
        )
    steps = (np.arange(side) - half) * voxel
    axes = np.meshgrid(steps, steps, steps, indexing="ij")
    return np.stack(axes, axis=-1) + origin
