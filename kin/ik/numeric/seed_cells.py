"""The seed table's grid, and boxes of its samples: where the nearest samples of a far target lie.

:func:`grid_of` sorts the samples into the uniform grid of the table's neighbourhood lookups.
A target outside that grid (beyond the sampled workspace: a long rail, a far point), or one
asking for more samples than its neighbourhood holds, is answered exactly without ranking every
sample: a sample's pose distance is at least its position distance, which is at least the
distance from the target to a box holding the sample. :class:`SampleBoxes` groups the samples
into a few hundred boxes (blocks of :data:`BLOCK` cells, each box the tight bounds of its
samples); the ``k`` boxes nearest the target hold at least ``k`` samples, the ``k``-th smallest
pose distance among them bounds the answer's, and only boxes within that bound are ranked
(:meth:`SampleBoxes.far_candidates`). Lengths in [m], squared distances in [m^2].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BLOCK", "SampleBoxes", "grid_of", "spans_dict"]

#: Cells per box edge: a box spans up to ``BLOCK^3`` grid cells.
BLOCK = 4


@dataclass(frozen=True)
class SampleBoxes:
    """The samples grouped into boxes: each box's bounds, and the box of each sample.

    Attributes:
        lower: Each box's lower corner (B, 3) [m] (the least coordinates of its samples).
        upper: Each box's upper corner (B, 3) [m].
        box_of: Per entry of the table's ``owners`` (samples sorted by cell), its box's row (N,).
        by_box: The entries of ``owners`` grouped by box (box 0's first, each box's ascending),
            (N,): box ``b``'s are ``by_box[starts[b]:starts[b + 1]]``.
        starts: Where each box's entries begin in ``by_box``, and N at the end (B + 1,).
    """

    lower: np.ndarray
    upper: np.ndarray
    box_of: np.ndarray
    by_box: np.ndarray
    starts: np.ndarray

    @classmethod
    def of(
        cls, positions: np.ndarray, owners: np.ndarray, origin: np.ndarray, size: float
    ) -> SampleBoxes:
        """Boxes of :data:`BLOCK` cells of edge ``size`` [m] from ``origin``, tight on the samples."""
        placed = positions[owners]
        block = np.floor((placed - origin) / (size * BLOCK)).astype(np.int64)
        span = block.max(axis=0, initial=0) + 1
        key = (block[:, 0] * span[1] + block[:, 1]) * span[2] + block[:, 2]
        keys, box_of = np.unique(key, return_inverse=True)
        order = np.argsort(box_of, kind="stable")
        starts = np.searchsorted(box_of[order], np.arange(len(keys)))
        lower = np.minimum.reduceat(placed[order], starts) if len(keys) else placed[:0]
        upper = np.maximum.reduceat(placed[order], starts) if len(keys) else placed[:0]
        ends = np.append(starts, len(order)).astype(np.intp)
        return cls(lower, upper, box_of, order.astype(np.intp), ends)

    def bounds(self, position: np.ndarray) -> np.ndarray:
        """Squared distance (B,) [m^2] from ``position`` to each box."""
        gap = np.maximum(np.maximum(self.lower - position, 0.0), position - self.upper)
        return np.einsum("ij,ij->i", gap, gap)

    def members(self, boxes: np.ndarray) -> np.ndarray:
        """Positions in ``owners`` of the samples of ``boxes``, box by box.

        Their slices of :attr:`by_box`, gathered without a pass over every sample.
        """
        begin, end = self.starts[boxes], self.starts[boxes + 1]
        if len(boxes) == 1:
            return self.by_box[begin[0] : end[0]]
        counts = end - begin
        # each member's place in by_box: its box's begin plus its rank within the box
        rank = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
        return self.by_box[np.repeat(begin, counts) + rank]

    def far_candidates(
        self,
        owners: np.ndarray,
        lifted: np.ndarray,
        query: np.ndarray,
        position: np.ndarray,
        k: int,
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Samples that hold the ``k`` nearest of a target, ascending, with their distances.

        Args:
            owners: The table's sample indices sorted by cell.
            lifted: The table's lifted rows (one per sample): ``lifted @ query`` is the squared
                pose distance [m^2] (:meth:`~.seed_table.SeedTable.ranked`).
            query: The target's row of that product.
            position: The target's position [m], shape (3,).
            k: Number of samples wanted (at least 1).

        Returns:
            ``(samples, squared distances)``, the samples ascending, holding the ``k`` nearest
            (ties included); None for a position too large to bound (rank every sample then).
        """
        px, py, pz = position.tolist()
        if not max(abs(px), abs(py), abs(pz)) < 1e6:
            return None
        bounds = self.bounds(position)
        m = len(bounds)
        if m == 0:
            return None
        nearest = np.argpartition(bounds, k - 1)[:k] if k < m else np.arange(m)
        first = owners[self.members(nearest)]  # every box holds a sample: k boxes, >= k samples
        distances = lifted[first] @ query
        if first.size < k:
            return None
        kth = float(np.partition(distances, k - 1)[k - 1])
        if not kth == kth:  # NaN: rank every sample
            return None
        # The lifted distances round to about 1e-15 of the squared lengths in them: a margin
        # far above that keeps every sample whose rounded distance could reach the k-th.
        within = kth + 1e-9 * (1.0 + px * px + py * py + pz * pz)
        samples = np.sort(owners[self.members(np.flatnonzero(bounds <= within))])
        return samples, lifted[samples] @ query


def spans_dict(
    keys: np.ndarray, begins: np.ndarray, ends: np.ndarray
) -> dict[int, tuple[int, int]]:
    """``{key: (begin, end)}``, built in slices of 1024.

    A table built in a background thread must not hold the interpreter lock for milliseconds in
    one C call: a solve with a budget of a few milliseconds waits on it.
    """
    spans: dict[int, tuple[int, int]] = {}
    for i in range(0, len(keys), 1024):
        part = slice(i, i + 1024)
        spans.update(
            zip(
                keys[part].tolist(),
                zip(begins[part].tolist(), ends[part].tolist(), strict=True),
                strict=True,
            )
        )
    return spans


def grid_of(
    positions: np.ndarray, cell_size: float
) -> tuple[dict[int, tuple[int, int]], np.ndarray, np.ndarray, tuple[int, int, int]]:
    """A uniform grid over the tool positions: each cell's own samples.

    A query gathers the 27 cells around the target's on its first visit (``_neighbourhood``).
    The grid has one empty layer of cells around the samples, so that a cell's neighbours are
    never outside it.

    Returns:
        ``(spans, owners, origin, shape)``: cell key -> ``(begin, end)`` into ``owners``, the
        sample indices sorted by cell.
    """
    origin = positions.min(axis=0) - cell_size
    cell = np.floor((positions - origin) / cell_size).astype(np.int64)
    shape = tuple(int(v) for v in cell.max(axis=0) + 2)
    nx, ny, nz = shape
    key = (cell[:, 0] * ny + cell[:, 1]) * nz + cell[:, 2]
    owner = np.argsort(key, kind="stable")
    key = key[owner]
    starts = np.flatnonzero(np.concatenate(([True], key[1:] != key[:-1])))
    ends = np.append(starts[1:], len(key))
    spans = spans_dict(key[starts], starts, ends)
    return spans, owner, origin, (nx, ny, nz)
