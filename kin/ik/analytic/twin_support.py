"""What the compiled twins of the 6R and 7R closed forms share: their parameters and their threads.

A closed form's twin (:mod:`kin._native`) reads its arm as one float64 vector in the layout the C
declares (:func:`pack_params`; a table's DH chain as the compiled checks read it:
:func:`chain_fields`; as a twin's Seed block: :func:`chain_block`), and a batch's rows run in this process's thread pool, the interpreter lock
released (:func:`call_first_many`, :class:`ScanJob`, :func:`batch_threads`, :func:`thread_pool`).
The 6R forms (:mod:`.six_r.six_r_family`, :mod:`.six_r.six_r_twin`, the general 6R's batches)
and the 7R forms (:mod:`.seven_r`) both import it; neither imports the other for it. Angles in
radians, lengths in meters.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any

import numpy as np

from dh2urdf import DHTable

__all__ = [
    "PARALLEL_ROWS",
    "ScanJob",
    "batch_threads",
    "call_first_many",
    "chain_block",
    "chain_fields",
    "pack_params",
    "thread_pool",
]


def pack_params(
    fields: dict[str, tuple[float, ...]], layout: Sequence[tuple[str, int, int]]
) -> np.ndarray:
    """``fields`` as one float64 vector in ``layout`` order: ``(name, offset, size)`` per field.

    Raises:
        ValueError: A field missing, of another size, left over, or a layout with gaps.
    """
    values: list[float] = []
    for name, offset, size in layout:
        field = fields.get(name)
        if field is None or len(field) != size or offset != len(values):
            raise ValueError(
                f"compiled layout field {name!r} (offset {offset}, size {size}) does not match "
                f"the Python parameters: {None if field is None else len(field)} values at "
                f"offset {len(values)}"
            )
        values.extend(field)
    extra = sorted(set(fields) - {name for name, _, _ in layout})
    if extra:
        raise ValueError(f"Python parameters not in the compiled layout: {extra}")
    return np.array(values, dtype=float)


def chain_fields(table: DHTable) -> dict[str, tuple[float, ...]]:
    """A table's DH chain as the compiled checks read it (``chain_step`` in ``_twin.h``).

    ``modified`` (1 for Craig's convention), per row ``a`` [m], ``cos_alpha``, ``sin_alpha``,
    ``d`` [m] and ``theta`` offsets [rad], then ``base`` and ``tool``: rows 0-2 of
    ``T_world_base`` and ``T_last_tool``, row-major [m]. For revolute rows turning forward (the
    callers check it).
    """
    rows = table.rows
    return {
        "modified": (float(table.convention == "modified"),),
        "a": tuple(float(row.a) for row in rows),
        "cos_alpha": tuple(math.cos(row.alpha) for row in rows),
        "sin_alpha": tuple(math.sin(row.alpha) for row in rows),
        "d": tuple(float(row.d) for row in rows),
        "theta": tuple(float(row.theta) for row in rows),
        "base": tuple(np.asarray(table.T_world_base, dtype=float)[:3].ravel().tolist()),
        "tool": tuple(np.asarray(table.T_last_tool, dtype=float)[:3].ravel().tolist()),
    }


def chain_block(
    table: DHTable,
    twin: Any,
    frames: dict[str, tuple[float, ...]] | None = None,
    base_origin: Sequence[float] = (0.0, 0.0, 0.0),
    reach: float = 0.0,
) -> bytes | None:
    """A Seed block (``twin.SEED_LAYOUT``) of ``table``'s chain, or None (not 7 forward revolute rows).

    ``frames``: the closed form's (``seed_frames``); None: identities and zeros, for the calls
    that read the chain alone (``sift_rows``, the judge's DH product of any 7R form's branches).
    """
    rows = table.rows
    if len(rows) != 7 or any(r.joint_type != "revolute" or r.direction != 1 for r in rows):
        return None
    if frames is None:
        eye = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
        zero = (0.0, 0.0, 0.0)
        frames = {"frame_r": eye, "frame_t": zero, "end_r": eye, "end_t": zero, "point": zero}
    fields = {
        **chain_fields(table),
        **frames,
        "reach": (*(float(v) for v in base_origin), float(reach)),
    }
    return pack_params(fields, twin.SEED_LAYOUT).tobytes()


def call_first_many(
    call: Callable[..., int],
    head: tuple,
    targets: np.ndarray | None,
    starts: np.ndarray,
    steps: Sequence[float],
    later: bool = False,
    width: int = 7,
) -> np.ndarray | ScanJob:
    """A compiled twin's ``first_many`` of N prepared targets: (N, 7) branches [rad], NaN rows.

    ``call(*head, targets, starts, out, steps)``: ``head`` its leading arguments (the packed
    parameters, and the mode where the twin takes one); ``targets`` (N, width) or None (no target
    this form takes: every row NaN); ``starts`` (N, 7) [rad]; ``steps`` the scan steps [rad].
    The twin's loop runs without the interpreter lock: N of :data:`PARALLEL_ROWS` or more are
    cut into :data:`_BLOCKS_PER_THREAD` blocks per processor (:func:`batch_threads`), which its
    threads take in turn (each row's answer is the same either way). With ``later``, the blocks (one at least) are started
    in the threads and a :class:`ScanJob` returned at once: the caller does other work (its
    Python runs while they do) and takes the answers from :meth:`ScanJob.result`. ``width``:
    the columns of each answer row (7; 9 for ``seeded_many``'s q and errors).
    """
    n = starts.shape[0]
    out = np.full((n, width), np.nan)
    if targets is None or not n:
        return ScanJob(out, []) if later else out
    starts = np.ascontiguousarray(starts, dtype=float)
    targets = np.ascontiguousarray(targets, dtype=float)
    scan_steps = np.asarray(steps, float)
    workers = batch_threads()
    blocks = workers * _BLOCKS_PER_THREAD
    if n < PARALLEL_ROWS or workers < 2:
        if not later:
            call(*head, targets, starts, out, scan_steps)
            return out
        blocks = 1
    bounds = np.linspace(0, n, blocks + 1).astype(int)
    pool = thread_pool(workers)
    parts = []
    for a, b in zip(bounds[:-1].tolist(), bounds[1:].tolist()):
        if b > a:
            block = np.full((b - a, width), np.nan)
            job = pool.submit(call, *head, targets[a:b], starts[a:b], block, scan_steps)
            parts.append((a, b, block, job))
    scan = ScanJob(out, parts)
    return scan if later else scan.result()


class ScanJob:
    """A :func:`call_first_many` running in the pool's threads (``later``)."""

    __slots__ = ("_out", "_parts")

    def __init__(self, out: np.ndarray, parts: list[tuple[int, int, np.ndarray, Future]]):
        self._out = out
        self._parts = parts

    def result(self) -> np.ndarray:
        """The (N, width) answer rows (branches [rad]), NaN rows, once every block is done.

        A block's error is raised here.
        """
        for a, b, block, job in self._parts:
            job.result()
            self._out[a:b] = block
        self._parts = []
        return self._out


#: Rows from which :func:`call_first_many` cuts the work into blocks for the processors.
PARALLEL_ROWS = 256

#: Blocks per thread: the threads take them in turn, so that one that drew the costlier rows
#: (a target's scan costs from one to dozens of closed-form solves) is helped by the others.
_BLOCKS_PER_THREAD = 4

#: The thread pool and the process that made it (a forked child makes its own: the parent's
#: threads do not exist there).
_POOL: tuple[int, ThreadPoolExecutor] | None = None


def batch_threads() -> int:
    """Threads of the batched closed forms: the processors this process may use (at most 8)."""
    try:
        count = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        count = os.cpu_count() or 1
    return max(1, min(count, 8))


def thread_pool(threads: int) -> ThreadPoolExecutor:
    """This process's thread pool of the batched closed forms (made on first use)."""
    global _POOL
    pid = os.getpid()
    if _POOL is None or _POOL[0] != pid:
        _POOL = (pid, ThreadPoolExecutor(max_workers=threads, thread_name_prefix="kin-batch"))
    return _POOL[1]
