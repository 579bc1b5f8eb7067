"""Voxels of a reachability map in meshcat: one point per voxel reached, coloured by its index.

A map of ``kin reach`` (:class:`kin.reach.map.ReachMap`) holds an index in [0, 1] per voxel
centre (world frame, meters). The voxels with an index above 0 are drawn as a point cloud, each
point a voxel's edge wide, its colour read off a viridis-like ramp (dark purple for few
orientations, yellow for all): the same colours as the PNG's slices.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .exceptions import ViewerInputError

__all__ = ["index_colors", "show_reach_voxels"]

# Viridis at 0, 1/4, 1/2, 3/4, 1 (matplotlib's values), interpolated linearly in between.
_RAMP = np.array(
    [
        [0.267, 0.005, 0.329],
        [0.229, 0.322, 0.546],
        [0.128, 0.567, 0.551],
        [0.369, 0.789, 0.383],
        [0.993, 0.906, 0.144],
    ]
)


def index_colors(index: npt.ArrayLike) -> np.ndarray:
    """RGB in [0, 1] (N, 3) of indices (N,) in [0, 1] (clipped), on a viridis-like ramp."""
    values = np.clip(np.asarray(index, dtype=float).reshape(-1), 0.0, 1.0)
    stops = np.linspace(0.0, 1.0, len(_RAMP))
    return np.stack([np.interp(values, stops, _RAMP[:, c]) for c in range(3)], axis=1)


def show_reach_voxels(
    viewer: object,
    centers: npt.ArrayLike,
    index: npt.ArrayLike,
    voxel: float,
    name: str = "reach",
) -> np.ndarray:
    """Draw the voxels with an index above 0 on a :class:`~kin.viewer.RobotViewer`.

    Args:
        viewer: The viewer (its ``show_points`` draws the cloud under ``markers/<name>``).
        centers: Voxel centres (..., 3) in the world frame [m].
        index: Their indices (...) in [0, 1], the same leading shape.
        voxel: Voxel edge [m] (the drawn point size).
        name: Marker name.

    Returns:
        The centres drawn (M, 3) [m].

    Raises:
        ViewerInputError: Shapes that do not match, or no voxel with an index above 0.
    """
    points = np.asarray(centers, dtype=float)
    values = np.asarray(index, dtype=float)
    if points.shape[-1:] != (3,) or values.shape != points.shape[:-1]:
        raise ViewerInputError(
            f"reach voxels: centres (..., 3) and indices (...) of one shape, got "
            f"{points.shape} and {values.shape}"
        )
    points, values = points.reshape(-1, 3), values.reshape(-1)
    reached = values > 0.0
    if not reached.any():
        raise ViewerInputError("reach voxels: no voxel has an index above 0 (nothing to draw)")
    drawn = points[reached]
    viewer.show_points(  # type: ignore[attr-defined]
        drawn, rgb=index_colors(values[reached]), size=float(voxel), name=name
    )
    return drawn
