"""Monte Carlo workspace of a DH table: reach statistics, bounding box, voxel volume (meters).

Joint vectors are drawn uniformly within the joint limits, the tool points computed by batched
NumPy FK (:mod:`kin.batch_fk`), and the points reduced chunk by chunk: minima and maxima, a
voxel occupancy grid and three projected histograms. The chunks are made as they are needed (a
generator), so that memory stays bounded for any number of samples. Chunk ``i`` draws from
:func:`chunk_seed` ``(seed, i)``, the ``i``-th child of ``SeedSequence(seed)``, made from its
index alone (a chunk run again gives the same samples), and every reduction is exact (min, max, logical or, integer sums), so the statistics depend on ``seed``, ``n`` and
``chunk_size`` only, never on how the chunks are spread over processes or a Dask cluster
(:mod:`kin.workspace.run`).

Points of reference: the *base axis* is the world z axis through the origin of DH frame 0 (the
base frame); the *shoulder* is the origin of DH frame 1 of each sample. With ``a1 = 0`` (humanoid7,
pickplace3, ur5) that point is fixed on joint 1's axis, the shoulder; otherwise it turns with
joint 1 (scorbot's 16 mm offset), and for planar2 (``a1 = 0.3 m``) it is the elbow.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass

import numpy as np

from dh2urdf import DHTable

from ..exceptions import KinError
from .chunk import ChunkReduction, reduce_chunk
from .grid import WorkspaceGrid, reach_bound

__all__ = [
    "ChunkReduction",
    "WorkspaceGrid",
    "WorkspaceMap",
    "WorkspaceStats",
    "chunk_seed",
    "chunk_sizes",
    "chunk_tasks",
    "reach_bound",
    "reduce_chunk",
    "workspace",
]

#: Joint vectors per chunk: the unit of seeding, work and reduction.
DEFAULT_CHUNK_SIZE = 100_000

#: Largest chunk: its joint vectors and FK temporaries are held at once (about 1 kB each).
MAX_CHUNK_SIZE = 1_000_000

#: Most samples: the per-column counts are 64-bit integers.
MAX_SAMPLES = 2**63 - 1

#: The volume counts as converged when doubling the samples grows it by less than this [1].
CONVERGED_GROWTH = 0.01


@dataclass(frozen=True)
class WorkspaceStats:
    """Reach of the tool over N joint vectors drawn uniformly within the limits (SI units).

    The volume is that of the voxels hit by at least one sample (``voxel_size_m`` edges). It has
    two biases of opposite signs: voxels over the surface count whole (about half a voxel layer
    too much), and voxels no sample hit yet count nothing, which dominates while samples are
    few per voxel (humanoid7 at the default 1M samples and 1.7 cm voxels: 1.43 m^3, against
    1.95 m^3 at 40M). So it comes with a convergence check and an estimate of the second bias:

    - ``volume_error_m3``: the growth from N/2 to N samples, ``V_N - (V_even + V_odd) / 2``
      (the even and the odd samples give ``V_even`` and ``V_odd``): how far the figure still
      moves when the samples double. Not an error bar: the figure only grows.
    - ``volume_converged``: that growth is below :data:`CONVERGED_GROWTH` of the volume.
    - ``volume_estimate_m3``: the volume with the voxels not hit yet, estimated from the voxels
      hit once (``f1``) and twice (``f2``) by Chao's estimator ``f1^2 / (2 f2)`` (a lower
      bound of the unseen count in expectation): closer to the converged figure, still low.

    The same growth for ``area_xy_m2``, the area of the workspace seen from above (grid columns
    hit), which for a planar arm in the xy plane is its workspace area.

    Attributes:
        robot: Table name.
        n_samples: Joint vectors drawn.
        seed: Seed of ``np.random.SeedSequence``.
        chunk_size: Joint vectors per chunk (with ``seed``, fixes the samples).
        voxel_size_m: Voxel edge of the volume and area [m].
        reach_bound_m: Upper bound of the distance from the base origin (:func:`reach_bound`).
        min_radius_m: Smallest tool distance from the base axis [m].
        max_radius_m: Largest tool distance from the base axis [m].
        min_shoulder_distance_m: Smallest tool distance from the origin of DH frame 1 [m].
        max_shoulder_distance_m: Largest tool distance from the origin of DH frame 1 [m].
        bbox_min_m: Smallest x, y, z of the tool in world axes [m].
        bbox_max_m: Largest x, y, z of the tool in world axes [m].
        occupied_voxels: Voxels hit.
        volume_m3: ``occupied_voxels * voxel_size_m**3`` [m^3].
        volume_error_m3: Growth of the volume from N/2 to N samples [m^3].
        volume_converged: Whether that growth is below :data:`CONVERGED_GROWTH` of the volume.
        volume_estimate_m3: The volume with Chao's estimate of the voxels not hit yet [m^3].
        area_xy_m2: Area of the grid columns hit, seen along z [m^2].
        area_xy_error_m2: Half-sample estimate of its sampling error [m^2].
    """

    robot: str
    n_samples: int
    seed: int
    chunk_size: int
    voxel_size_m: float
    reach_bound_m: float
    min_radius_m: float
    max_radius_m: float
    min_shoulder_distance_m: float
    max_shoulder_distance_m: float
    bbox_min_m: tuple[float, float, float]
    bbox_max_m: tuple[float, float, float]
    occupied_voxels: int
    volume_m3: float
    volume_error_m3: float
    volume_converged: bool
    volume_estimate_m3: float
    area_xy_m2: float
    area_xy_error_m2: float

    def to_dict(self) -> dict:
        """The fields as a JSON-ready dict (keys name their units)."""
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}


@dataclass(frozen=True, eq=False)
class WorkspaceMap:
    """The statistics, with the grid and reductions the pictures are drawn from.

    Attributes:
        stats: The reach statistics.
        grid: The voxel grid.
        occupancy: Voxels hit, (side, side, side) bool, indexed (x, y, z).
        projections: Sample counts per grid column seen along z (xy), y (xz) and x (yz).
    """

    stats: WorkspaceStats
    grid: WorkspaceGrid
    occupancy: np.ndarray
    projections: np.ndarray

    @property
    def base_origin_m(self) -> tuple[float, float, float]:
        """Origin of DH frame 0 in world axes [m] (the grid's centre)."""
        half = self.grid.voxels_per_side * self.grid.voxel_size_m / 2.0
        return tuple(o + half for o in self.grid.origin_m)  # type: ignore[return-value]


def _check_sizes(n: int, chunk_size: int) -> None:
    """Raise :class:`KinError` unless ``n`` and ``chunk_size`` are whole numbers in range."""
    for name, value, most in (("n", n, MAX_SAMPLES), ("chunk_size", chunk_size, MAX_CHUNK_SIZE)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer):
            raise KinError(f"{name} must be a whole number, got {value!r}")
        if not 1 <= value <= most:
            raise KinError(f"{name} must be from 1 to {most:,}, got {value:,}")


def chunk_sizes(n: int, chunk_size: int = DEFAULT_CHUNK_SIZE) -> Iterator[int]:
    """Sizes of the chunks of ``n`` samples, made as read: ``chunk_size`` each, the last the rest.

    Raises:
        KinError: ``n`` or ``chunk_size`` not a whole number from 1 to :data:`MAX_SAMPLES` or
            :data:`MAX_CHUNK_SIZE`.
    """
    _check_sizes(n, chunk_size)
    return (min(chunk_size, n - start) for start in range(0, int(n), int(chunk_size)))


def chunk_seed(seed: int, index: int) -> np.random.SeedSequence:
    """The seed of chunk ``index``: ``SeedSequence(seed).spawn(index + 1)[index]``, made alone."""
    return np.random.SeedSequence(seed, spawn_key=(index,))


def chunk_tasks(
    table: DHTable, grid: WorkspaceGrid, n: int, seed: int, chunk_size: int
) -> Iterator[tuple[DHTable, WorkspaceGrid, int, np.random.SeedSequence]]:
    """The arguments of :func:`reduce_chunk` for every chunk, made one at a time as read."""
    for index, size in enumerate(chunk_sizes(n, chunk_size)):
        yield table, grid, size, chunk_seed(seed, index)


def summarize(
    table: DHTable, grid: WorkspaceGrid, total: ChunkReduction, seed: int, chunk_size: int
) -> WorkspaceMap:
    """The :class:`WorkspaceMap` of the merged reduction of every chunk."""
    side, v = grid.voxels_per_side, grid.voxel_size_m
    halves = np.unpackbits(total.occupancy, axis=1, count=side**3).astype(bool)
    occupancy = (halves[0] | halves[1]).reshape(side, side, side)
    half_grids = halves.reshape(2, side, side, side)
    voxels = int(occupancy.sum())
    half_voxels = half_grids.sum(axis=(1, 2, 3))
    columns = int(occupancy.any(axis=2).sum())
    half_columns = half_grids.any(axis=3).sum(axis=(1, 2))
    e = total.extremes
    stats = WorkspaceStats(
        robot=table.name,
        n_samples=total.n_samples,
        seed=seed,
        chunk_size=chunk_size,
        voxel_size_m=v,
        reach_bound_m=reach_bound(table),
        min_radius_m=float(e[0]),
        max_radius_m=float(-e[1]),
        min_shoulder_distance_m=float(e[2]),
        max_shoulder_distance_m=float(-e[3]),
        bbox_min_m=tuple(float(x) for x in e[4:7]),  # type: ignore[arg-type]
        bbox_max_m=tuple(float(-x) for x in e[7:10]),  # type: ignore[arg-type]
        occupied_voxels=voxels,
        volume_m3=voxels * v**3,
        volume_error_m3=float(voxels - half_voxels.mean()) * v**3,
        volume_converged=bool(voxels - half_voxels.mean() < CONVERGED_GROWTH * max(voxels, 1)),
        volume_estimate_m3=(voxels + _unseen(total.hits)) * v**3,
        area_xy_m2=columns * v**2,
        area_xy_error_m2=float(columns - half_columns.mean()) * v**2,
    )
    return WorkspaceMap(stats, grid, occupancy, total.projections)


def _unseen(hits: np.ndarray) -> float:
    """Chao's estimate of the voxels no sample hit yet, from those hit once and twice.

    ``f1^2 / (2 f2)``, or ``f1 (f1 - 1) / 2`` without voxels hit twice.
    """
    f1 = int(np.count_nonzero(hits == 1))
    f2 = int(np.count_nonzero(hits == 2))
    return f1 * f1 / (2.0 * f2) if f2 else f1 * (f1 - 1) / 2.0


def _estimating(
    progress: Callable[[int, int], None] | None, estimate: Callable[[float], None]
) -> Callable[[int, int], None]:
    """``progress``, and ``estimate`` of the run's duration [s] at the first chunk's end."""
    import time

    start = time.monotonic()
    told = False

    def report(done: int, n: int) -> None:
        nonlocal told
        if not told and done > 0:
            told = True
            estimate((time.monotonic() - start) * n / done)
        if progress is not None:
            progress(done, n)

    return report


def workspace(
    table: DHTable,
    n: int,
    seed: int = 0,
    *,
    voxel_size_m: float | None = None,
    chunk_size: int = DEFAULT_CHUNK_SIZE,
    workers: int = 1,
    client: object | None = None,
    progress: Callable[[int, int], None] | None = None,
    estimate: Callable[[float], None] | None = None,
) -> WorkspaceMap:
    """Sample the workspace of ``table`` with ``n`` joint vectors.

    Args:
        table: The DH table (SI units).
        n: Number of joint vectors.
        seed: Seed of the ``np.random.SeedSequence`` whose children seed the chunks.
        voxel_size_m: Voxel edge [m]; default ``2 * reach_bound / 100``.
        chunk_size: Joint vectors per chunk.
        workers: Processes (1: in this process); a process that dies is replaced and its
            chunks run again.
        client: A ``distributed.Client``: the chunks run on its cluster (``workers`` ignored).
        progress: Called with (samples done, n) as chunks finish.
        estimate: Called once, when the first chunk is done, with the whole run's estimated
            duration [s] (the rate so far times ``n``).

    Raises:
        KinError: Bad ``n`` (a whole number from 1 to :data:`MAX_SAMPLES`), ``chunk_size``
            (1 to :data:`MAX_CHUNK_SIZE`) or voxel size.
        RunFaultError: The Dask scheduler was lost, or a chunk kept losing its worker process.
    """
    from .run import run_chunks

    _check_sizes(n, chunk_size)
    grid = WorkspaceGrid.around(table, voxel_size_m)
    tasks = chunk_tasks(table, grid, n, seed, chunk_size)
    if estimate is not None:
        progress = _estimating(progress, estimate)
    total = run_chunks(tasks, workers=workers, client=client, progress=progress, n=n)
    return summarize(table, grid, total, seed, chunk_size)
