"""Pictures of a sampled workspace: three orthogonal density views and a 3-D view (PNG).

Matplotlib is imported inside :func:`plot_workspace` and drawn through its Agg canvas (no pyplot,
no global backend switch), so ``import kin`` stays light and nothing needs a display.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from dh2urdf.command_line import length_scale

from ..exceptions import KinError
from .monte_carlo import WorkspaceMap

#: Most voxel centres drawn in the 3-D view (an evenly strided subset beyond that).
MAX_3D_POINTS = 25_000
_VIEWS = (("top view", 0, 1), ("front view", 0, 2), ("side view", 1, 2))
_AXIS = "xyz"


def _surface(occupancy: np.ndarray) -> np.ndarray:
    """Occupied voxels with at least one empty face neighbour (the workspace's outer skin)."""
    padded = np.pad(occupancy, 1)
    inner = occupancy.copy()
    for axis in range(3):
        for shift in (-1, 1):
            inner &= np.roll(padded, shift, axis=axis)[1:-1, 1:-1, 1:-1]
    return occupancy & ~inner


def _figure(work: WorkspaceMap, unit: str):  # noqa: ANN202
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.colors import LogNorm
        from matplotlib.figure import Figure
    except ImportError as err:
        raise KinError("pictures need matplotlib: pip install 'matplotlib>=3.7'") from err
    stats, grid = work.stats, work.grid
    scale = length_scale(unit)
    v = grid.voxel_size_m / scale
    lo = np.asarray(grid.origin_m) / scale
    hi = lo + grid.voxels_per_side * v
    base = np.asarray(work.base_origin_m) / scale
    figure = Figure(figsize=(12, 10), dpi=100, layout="constrained")
    FigureCanvasAgg(figure)
    for k, (name, a, b) in enumerate(_VIEWS):
        axes = figure.add_subplot(2, 2, k + 1)
        counts = work.projections[k].T.astype(float)
        counts[counts == 0] = np.nan
        image = axes.imshow(
            counts,
            origin="lower",
            extent=(lo[a], hi[a], lo[b], hi[b]),
            norm=LogNorm(vmin=1, vmax=max(2.0, np.nanmax(counts))),
            cmap="viridis",
            interpolation="nearest",
        )
        axes.set_title(
            f"{name} ({_AXIS[a].upper()}{_AXIS[b].upper()}): tool samples per {v:.3g} {unit} cell"
        )
        axes.set_xlabel(f"{_AXIS[a]} [{unit}]")
        axes.set_ylabel(f"{_AXIS[b]} [{unit}]")
        axes.set_aspect("equal")
        axes.plot(base[a], base[b], "r+", markersize=14, mew=2, label="base frame origin")
        axes.legend(loc="upper left", fontsize=8)
        figure.colorbar(image, ax=axes, shrink=0.8, label="tool samples")
    axes3d = figure.add_subplot(2, 2, 4, projection="3d")
    centers = np.argwhere(_surface(work.occupancy))
    if len(centers) > MAX_3D_POINTS:
        centers = centers[:: -(-len(centers) // MAX_3D_POINTS)]
    xyz = lo + (centers + 0.5) * v
    axes3d.scatter(xyz[:, 0], xyz[:, 1], xyz[:, 2], c=xyz[:, 2], s=1, cmap="viridis", alpha=0.4)
    axes3d.set_title(f"3-D view: surface voxels of the workspace ({v:.3g} {unit} edge)")
    for setter, letter in zip((axes3d.set_xlabel, axes3d.set_ylabel, axes3d.set_zlabel), _AXIS):
        setter(f"{letter} [{unit}]")
    span = (xyz.max(axis=0) - xyz.min(axis=0)).max() if len(xyz) else 1.0
    middle = (xyz.max(axis=0) + xyz.min(axis=0)) / 2 if len(xyz) else np.zeros(3)
    for setter, c in zip((axes3d.set_xlim, axes3d.set_ylim, axes3d.set_zlim), middle):
        setter(c - span / 2, c + span / 2)
    figure.suptitle(
        f"{stats.robot} workspace: {stats.n_samples:,} samples (seed {stats.seed}); "
        f"radius from base axis {stats.min_radius_m / scale:.3g} to "
        f"{stats.max_radius_m / scale:.4g} {unit}; volume {stats.volume_m3:.4g} m³{'' if stats.volume_converged else ' (not converged)'}",
        fontsize=13,
    )
    return figure


def plot_workspace(work: WorkspaceMap, path: str | Path, unit: str = "m") -> Path:
    """Write the figure of ``work`` to ``path`` atomically (a temporary file, then a rename).

    The format follows the suffix: ``.png``, ``.svg`` or ``.pdf``.

    Args:
        work: A sampled workspace (:func:`kin.workspace.monte_carlo.workspace`).
        path: The PNG file to write.
        unit: Length unit of the axes: ``"m"``, ``"cm"`` or ``"mm"``.

    Raises:
        KinError: matplotlib is missing.
        OutputFileError: ``path`` is a device, FIFO, socket or folder, or its folder is missing.
        OutputWriteError: The disk filled up part-way; a previous file is unchanged.
    """
    path = Path(path)
    kind = path.suffix.lower().lstrip(".") or "png"
    if kind not in ("png", "svg", "pdf"):
        raise KinError(f"{path}: unknown figure type '.{kind}'; use .png, .svg or .pdf")
    figure = _figure(work, unit)
    from dh2urdf.output_file import write_atomic

    from ..exceptions import OutputFileError, OutputWriteError

    write_atomic(
        path, lambda handle: figure.savefig(handle, format=kind), OutputFileError, OutputWriteError
    )
    return path
