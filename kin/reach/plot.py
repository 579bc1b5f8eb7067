"""A picture of a reachability map: horizontal slices of its index (matplotlib, imported here)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..exceptions import KinError
from .grid import ReachMap
from .map_file import write_whole

__all__ = ["PLOT_SLICES", "plot_reach_map"]

#: Horizontal slices drawn by :func:`plot_reach_map`.
PLOT_SLICES = 4


def plot_reach_map(
    reach_map: ReachMap, path: str | Path, unit: str = "m", slices: int = PLOT_SLICES
) -> Path:
    """Write ``slices`` horizontal (constant z) slices of the map to a figure, atomically.

    The slices are evenly spaced over the z range of voxels with a nonzero index; each shows the
    index as colour (one colour bar, 0 to 1) over x and y in ``unit``. The format follows the
    suffix (``.png``, ``.svg``, ``.pdf``); matplotlib is imported here, drawn on its Agg canvas.

    Raises:
        KinError: matplotlib is missing.
    """
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as err:
        raise KinError("pictures need matplotlib: pip install 'matplotlib>=3.7'") from err
    from dh2urdf.command_line import length_scale

    path = Path(path)
    scale = length_scale(unit)
    centers, index = reach_map.centers_m / scale, reach_map.index
    side = index.shape[2]
    layers = np.flatnonzero(index.reshape(-1, side).max(axis=0) > 0)
    lo, hi = (int(layers[0]), int(layers[-1])) if len(layers) else (0, side - 1)
    picks = sorted(set(np.linspace(lo, hi, slices + 2)[1:-1].round().astype(int).tolist()))
    v = reach_map.voxel_m / scale
    x, y = centers[:, 0, 0, 0], centers[0, :, 0, 1]
    extent = (x[0] - v / 2, x[-1] + v / 2, y[0] - v / 2, y[-1] + v / 2)
    figure = Figure(figsize=(4.2 * len(picks) + 1.2, 4.6), dpi=100, layout="constrained")
    FigureCanvasAgg(figure)
    image = None
    axes_list = figure.subplots(1, len(picks), squeeze=False)[0]
    for axes, layer in zip(axes_list, picks, strict=True):
        image = axes.imshow(
            index[:, :, layer].T,
            origin="lower",
            extent=extent,
            vmin=0.0,
            vmax=1.0,
            cmap="viridis",
            interpolation="nearest",
        )
        axes.set_title(f"z = {centers[0, 0, layer, 2]:.3g} {unit}")
        axes.set_xlabel(f"x [{unit}]")
        axes.set_ylabel(f"y [{unit}]")
        axes.set_aspect("equal")
    assert image is not None  # at least one slice
    label = "reachability index" + (", collision-free" if reach_map.collisions else "")
    figure.colorbar(image, ax=list(axes_list), shrink=0.85, label=label)
    figure.suptitle(
        f"{reach_map.robot}: reachability index ({reach_map.orientations} orientations, "
        f"{v:.3g} {unit} voxels)" + (f"\n{reach_map.collisions}" if reach_map.collisions else "")
    )
    kind = path.suffix.lower().lstrip(".") or "png"
    write_whole(path, lambda handle: figure.savefig(handle, format=kind))
    return path
