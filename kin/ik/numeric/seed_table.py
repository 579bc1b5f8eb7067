"""A precomputed table of sampled joint vectors and their tool poses, to start IK near the target.

The table samples joint vectors uniformly inside the limits (seeded, reproducible), computes the
tool pose of each with the table's NumPy DH product (:mod:`kin.batch_fk`, all samples at once; the
tests hold it to Pinocchio's FK), and answers "which samples have a tool pose nearest to this
target?". Poses are compared in an embedding where 1 rad of rotation weighs about
``rotation_weight`` [m]: ``(p, rotation_weight * vec(R))`` (``|R1 - R2|_F ~ sqrt(2) * angle``).

Queries look up a uniform grid over the tool positions first: on a cell's first query the samples
of its 3 x 3 x 3 neighbourhood and their lifted embeddings are gathered into one contiguous block
and kept; each query then ranks them by one matrix-vector product (a few microseconds). A target
outside the grid ranks the samples of the boxes that can hold its nearest (:mod:`.seed_cells`:
a box bounds its samples' distances); so does one asking for more samples than its
neighbourhood holds. Building a table of 20,000 samples takes about 30 ms; the samples and the
grid are cached on disk per table (:mod:`.seed_cache`).
"""

from __future__ import annotations

import functools
import logging
import math
from dataclasses import dataclass, field

import numpy as np

from kin import RobotModel, load_robot
from kin.batch_fk import batch_forward_kinematics

from . import seed_cache
from .sampling_box import sampling_limits
from .seed_cells import SampleBoxes, grid_of, spans_dict

logger = logging.getLogger(__name__)

#: Default weight of the rotation in the pose embedding [m], and edge of a grid cell [m].
DEFAULT_ROTATION_WEIGHT = 0.1
DEFAULT_CELL_SIZE = 0.06

#: Second entropy word of the table's random generator (any fixed value; keeps it apart).
_TABLE_STREAM = 0x5EED7AB1E


@dataclass(frozen=True, eq=False)
class SeedTable:
    """Sampled joint vectors with their tool poses.

    Attributes:
        q: Joint vectors [rad], shape (n, nq), inside the limits.
        positions: Tool positions in the world frame [m], shape (n, 3).
        rotations: Tool rotations ``R_world_tool`` flattened row-major, shape (n, 9).
        rotation_weight: Weight of ``vec(R)`` in the pose embedding [m].
    """

    q: np.ndarray
    positions: np.ndarray
    rotations: np.ndarray
    rotation_weight: float
    cell_size: float = 0.06
    _cells: dict[int, tuple[int, int]] | None = None
    _origin: np.ndarray | None = None
    _grid_shape: tuple[int, int, int] = (0, 0, 0)
    _lifted: np.ndarray | None = None
    _owners: np.ndarray | None = None
    #: The samples in boxes of grid cells (the search of a target outside the grid).
    _boxes: SampleBoxes | None = None
    #: Per cell key: the samples of its 3 x 3 x 3 neighbourhood and their lifted embeddings as
    #: one contiguous block (gathered on the cell's first query).
    _blocks: dict[int, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    #: Per cell key: its samples nearest to the cell's centre first (made on first use).
    _by_centre: dict[int, np.ndarray] = field(default_factory=dict)

    @functools.cached_property
    def _origin_list(self) -> list[float]:
        return [] if self._origin is None else self._origin.tolist()

    def __len__(self) -> int:
        return int(self.q.shape[0])

    def nearest(
        self, position: np.ndarray, rotation: np.ndarray | None = None, k: int = 1
    ) -> np.ndarray:
        """Indices of the ``k`` samples nearest to a target, nearest first.

        Args:
            position: Target position [m], shape (3,).
            rotation: Target rotation (3 x 3), or None to compare positions only.
            k: Number of samples.
        """
        k = max(1, min(int(k), len(self)))
        found = self._nearest_in_grid(position, rotation, k)
        if found is not None:
            return found
        if self._boxes is not None and self._owners is not None and self._lifted is not None:
            far = self._boxes.far_candidates(
                self._owners, self._lifted, self._query(position, rotation), position, k
            )
            if far is not None:  # the boxes that can hold the k nearest
                return far[0][nearest_first(far[1], k)]
        # No boxes (a table built by hand) or a position too large to bound: every sample.
        if self._lifted is None:
            points = np.hstack((self.positions, self.rotation_weight * self.rotations))
            if rotation is None:
                points, point = self.positions, position
            else:
                point = np.concatenate((position, self.rotation_weight * rotation.reshape(-1)))
            distances = np.einsum("ij,ij->i", points - point, points - point)
        else:
            distances = self._lifted @ self._query(position, rotation)
        return nearest_first(distances, k)

    def _query(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The target's row whose product with a lifted sample row is their squared distance."""
        px, py, pz = position.tolist()
        offset = px * px + py * py + pz * pz
        if rotation is None:
            return np.array((px, py, pz, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, offset))
        offset += 6.0 * self.rotation_weight * self.rotation_weight
        return np.array([px, py, pz, *rotation.ravel().tolist(), 1.0, offset])

    def ranked(
        self, position: np.ndarray, rotation: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The samples of the target's grid neighbourhood and their squared pose distances.

        Args:
            position: Target position [m], shape (3,).
            rotation: Target rotation (3 x 3), or None to compare positions only.

        Returns:
            ``(indices, squared distances [m^2])`` in no particular order, or None when the
            target's cell is outside the grid or empty.
        """
        key = self._cell_key(position)
        if key is None:
            return None
        # Each row of a block is ``(-2 p, -2 w^2 vec(R), |p|^2, 1)``: its product with
        # ``(p_t, vec(R_t), 1, |p_t|^2 + 6 w^2)`` is the squared distance (``|vec(R)|^2 = 3``
        # for a rotation); a position-only query has ``R_t = 0`` and no ``6 w^2``.
        owners, block = self._neighbourhood(key)
        if not owners.size:
            return None
        return owners, np.dot(block, self._query(position, rotation))

    def nearest_rows(self, position: np.ndarray, rotation: np.ndarray | None, k: int) -> np.ndarray:
        """The joint vectors of the ``k`` samples of the target's neighbourhood nearest it, (k, nq).

        Nearest in the pose embedding (position [m], rotation weighed); when the target's cell is
        outside the grid or empty (:meth:`ranked`), the ``k`` nearest of every sample
        (:meth:`nearest`), as the numeric search's starts take them: a target along a long rail
        beyond the sampled box (:mod:`.sampling_box`) starts from the samples at its edge.
        """
        found = self.ranked(position, rotation)
        if found is None or not found[0].size:
            return self.q[self.nearest(position, rotation, k)]
        candidates, distances = found
        return self.q[candidates[nearest_first(distances, k)]]

    def _neighbourhood(self, key: int) -> tuple[np.ndarray, np.ndarray]:
        """The samples of cell ``key``'s 3 x 3 x 3 neighbourhood and their lifted rows (cached)."""
        found = self._blocks.get(key)
        if found is None:
            cells, owners = self._cells, self._owners
            assert cells is not None and owners is not None and self._lifted is not None
            _, ny, nz = self._grid_shape
            parts = []
            for dx, dy, dz in _OFFSETS:
                span = cells.get(key + (dx * ny + dy) * nz + dz)
                if span is not None:
                    parts.append(owners[span[0] : span[1]])
            members = np.concatenate(parts) if parts else owners[:0]
            found = self._blocks[key] = (members, np.ascontiguousarray(self._lifted[members]))
        return found

    def _cell_key(self, position: np.ndarray) -> int | None:
        """The grid key of the cell holding ``position``, or None (no grid, outside it, not finite)."""
        if self._cells is None or self._owners is None or self._lifted is None:
            return None
        nx, ny, nz = self._grid_shape
        ox, oy, oz = self._origin_list
        size = self.cell_size
        px, py, pz = position.tolist()
        # Compared before flooring: a huge or non-finite coordinate never reaches an integer.
        fx, fy, fz = (px - ox) / size, (py - oy) / size, (pz - oz) / size
        if not (0.0 <= fx < nx and 0.0 <= fy < ny and 0.0 <= fz < nz):
            return None
        return (math.floor(fx) * ny + math.floor(fy)) * nz + math.floor(fz)

    def cell_samples(self, position: np.ndarray) -> np.ndarray | None:
        """The samples of the target's grid neighbourhood, nearest to the cell's centre first.

        A position-only lookup with no distance to the target computed (the cell's order is
        made once per cell): the first samples are near the target, not necessarily the nearest.

        Args:
            position: Target position [m], shape (3,).

        Returns:
            Sample indices, or None when the target's cell is outside the grid or empty.
        """
        key = self._cell_key(position)
        if key is None:
            return None
        found = self._by_centre.get(key)
        if found is None:
            owners = self._neighbourhood(key)[0]
            if not owners.size:
                return None
            _, ny, nz = self._grid_shape
            cell = np.array((key // (ny * nz), (key // nz) % ny, key % nz), dtype=float)
            centre = self._origin + (cell + 0.5) * self.cell_size  # type: ignore[operator]
            gap = self.positions[owners] - centre
            order = np.argsort(np.einsum("ij,ij->i", gap, gap), kind="stable")
            found = self._by_centre[key] = owners[order]
        return found

    def _nearest_in_grid(
        self, position: np.ndarray, rotation: np.ndarray | None, k: int
    ) -> np.ndarray | None:
        found = self.ranked(position, rotation)
        if found is None or found[0].size < k:
            return None
        candidates, distances = found
        return candidates[nearest_first(distances, k)]


def nearest_first(distances: np.ndarray, k: int) -> np.ndarray:
    """Indices of the ``k`` smallest ``distances``, smallest first, ties in index order.

    ``np.argsort(distances, kind="stable")[:k]`` without sorting them all: a partition, then a
    stable sort of the ones at or below the ``k``-th smallest (a neighbourhood of tens of
    thousands of samples then costs a pass, not a sort). NaN distances come last, as there.
    """
    n = distances.shape[0]
    if k >= n or 8 * k >= n:
        return np.argsort(distances, kind="stable")[:k]
    if k <= 0:
        return np.zeros(0, dtype=np.intp)
    kth = distances[np.argpartition(distances, k - 1)[k - 1]]
    if not kth == kth:  # fewer than k numbers: NaN among the k
        return np.argsort(distances, kind="stable")[:k]
    pick = np.flatnonzero(distances <= kth)  # in index order: the stable sort keeps it on ties
    return pick[np.argsort(distances[pick], kind="stable")[:k]]


#: The 27 cell offsets of a neighbourhood.
_OFFSETS = tuple((dx - 1, dy - 1, dz - 1) for dx, dy, dz in np.ndindex(3, 3, 3))


def build_seed_table(
    robot: RobotModel,
    size: int = 20000,
    seed: int = 0,
    rotation_weight: float = DEFAULT_ROTATION_WEIGHT,
    cell_size: float = DEFAULT_CELL_SIZE,
    cache: bool = True,
) -> SeedTable:
    """Sample ``size`` joint vectors uniformly inside the limits and tabulate their tool poses.

    The samples and the grid are cached on disk per table (see :mod:`.seed_cache`): a second
    process loads them instead of recomputing them.

    Args:
        robot: The robot.
        size: Number of samples.
        seed: Seed of the random generator (the table is reproducible).
        rotation_weight: Weight of the rotation in the pose embedding [m].
        cell_size: Edge of the lookup grid's cells [m].
        cache: Read and write the on-disk cache (False: always compute).
    """
    key = seed_cache.table_key(robot, size, seed, rotation_weight, cell_size) if cache else ""
    arrays = seed_cache.load(key) if cache else None
    if arrays is None:
        arrays = _sample(robot, size, seed, cell_size)
        if cache:
            seed_cache.store(key, arrays)
    return _assemble(arrays, rotation_weight, cell_size)


#: Arrays of a seed table that the disk cache keeps (the rest is derived from them).
CACHED_ARRAYS = seed_cache.CACHED_ARRAYS


def _sample(robot: RobotModel, size: int, seed: int, cell_size: float) -> dict[str, np.ndarray]:
    """The samples, their tool poses and the grid, as the arrays of :data:`CACHED_ARRAYS`."""
    seed_cache.BUILDS += 1
    model = robot.model
    # A stream of its own: a caller's ``default_rng(seed)`` draws are never table samples.
    rng = np.random.default_rng([seed, _TABLE_STREAM])
    # Inside the limits; a long rail (a mobile base's) within the arm's size (.sampling_box).
    lower, upper = sampling_limits(robot.table, model.lowerPositionLimit, model.upperPositionLimit)
    q = rng.uniform(lower, upper, size=(size, model.nq))
    # The table's DH product in NumPy, all samples at once (the tests hold it to Pinocchio's FK).
    return _arrays(q, batch_forward_kinematics(robot.table, q), cell_size)


def table_of_poses(
    q: np.ndarray,
    poses: np.ndarray,
    rotation_weight: float = DEFAULT_ROTATION_WEIGHT,
    cell_size: float = DEFAULT_CELL_SIZE,
) -> SeedTable:
    """The table of given samples: joint vectors ``q`` (N, n) and their tool poses (N, 4, 4).

    For a chain whose samples another FK gives (a chain with mimic joints:
    :mod:`kin.mimic.starts`); not cached on disk.
    """
    return _assemble(
        _arrays(np.asarray(q, dtype=float), poses, cell_size), rotation_weight, cell_size
    )


def _arrays(q: np.ndarray, poses: np.ndarray, cell_size: float) -> dict[str, np.ndarray]:
    """The arrays of :data:`CACHED_ARRAYS` of samples ``q`` and their poses (N, 4, 4)."""
    size = len(q)
    positions = np.ascontiguousarray(poses[:, :3, 3])
    rotations = np.ascontiguousarray(poses[:, :3, :3]).reshape(size, 9)
    cells, owners, origin, shape = grid_of(positions, cell_size)
    return {
        "q": q,
        "positions": positions,
        "rotations": rotations,
        "keys": np.fromiter(cells.keys(), dtype=np.int64, count=len(cells)),
        "spans": np.array(list(cells.values()), dtype=np.int64).reshape(-1, 2),
        "owners": owners.astype(np.int32 if size < 2**31 else np.int64),
        "origin": origin,
        "shape": np.array(shape, dtype=np.int64),
    }


def _assemble(arrays: dict[str, np.ndarray], rotation_weight: float, cell_size: float) -> SeedTable:
    """The :class:`SeedTable` of the arrays of :data:`CACHED_ARRAYS`."""
    q, positions, rotations = arrays["q"], arrays["positions"], arrays["rotations"]
    owners = arrays["owners"]
    spans_array = arrays["spans"]
    cells = spans_dict(arrays["keys"], spans_array[:, 0], spans_array[:, 1])
    size = len(q)
    # The lifted embedding of every sample (see ``SeedTable.ranked``); a cell's rows are gathered
    # into a contiguous block on its first query.
    lifted = np.hstack(
        (
            -2.0 * positions,
            (-2.0 * rotation_weight**2) * rotations,
            np.einsum("ij,ij->i", positions, positions)[:, None],
            np.ones((size, 1)),
        )
    )
    nx, ny, nz = (int(v) for v in arrays["shape"].tolist())
    return SeedTable(
        q,
        positions,
        rotations,
        rotation_weight,
        cell_size,
        cells,  # type: ignore[arg-type]
        arrays["origin"],
        (nx, ny, nz),
        lifted,
        owners,
        SampleBoxes.of(positions, owners, arrays["origin"], cell_size),
    )


@functools.lru_cache(maxsize=8)
def seed_table_for(robot_name: str, size: int = 20000, seed: int = 0) -> SeedTable:
    """The (cached) seed table of a shipped robot."""
    return build_seed_table(load_robot(robot_name), size=size, seed=seed)


def seed_table_of(robot: RobotModel, size: int) -> SeedTable:
    """The seed table of ``robot``: the cached one of a shipped robot, else its own, built now."""
    if _is_shipped(robot):
        return seed_table_for(robot.name, size)
    return build_seed_table(robot, size)  # a robot loaded from a table file


def _is_shipped(robot: RobotModel) -> bool:
    """Whether ``robot`` is the registry's (cached) model of its name."""
    try:
        return load_robot(robot.name) is robot
    except Exception:  # noqa: BLE001 - any name the registry does not know
        return False
