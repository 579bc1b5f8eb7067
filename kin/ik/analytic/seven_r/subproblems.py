"""The sub-problems the seven-joint closed forms share, scalar and batched, and their scan.

``p cos t + q sin t = k`` (:func:`harmonic_roots`), ``Rz(ta) Rx(alpha) Rz(tb) v = d`` (a
Paden-Kahan sub-problem 2 about two axes a twist apart, :func:`rotation_pair`), their NumPy twins
over N equations, the outward scan of a free joint (:func:`scan`) and the packing of a form's
parameters for its compiled twin (:func:`pack_params`). Angles in radians, lengths in meters.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ThreadPoolExecutor

import numpy as np

from dh2urdf import DHTable

from ...angles import clip_unit

#: Slack on ``|cos| <= 1`` of the elbow and pair angles (rounding at the edge of the workspace).
COS_SLACK = 1e-12


def harmonic_roots(p: float, q: float, k: float) -> tuple[float, ...]:
    """Angles ``t`` [rad] with ``p cos t + q sin t = k``: two, one (a double root) or none.

    ``|k| / hypot(p, q)`` up to :data:`COS_SLACK` above 1 counts as 1 (rounding at the edge).
    """
    rho = math.hypot(p, q)
    if rho < 1e-15:
        return ()
    c = clip_unit(k / rho, COS_SLACK)
    if c is None:
        return ()
    phi, delta = math.atan2(q, p), math.acos(c)
    return (phi + delta, phi - delta) if delta > 0.0 else (phi,)


def fold_distance(p: float, q: float, k: float) -> float:
    """How far ``p cos t + q sin t = k`` is from a double root: ``| 1 - |k| / hypot(p, q) |``.

    0 for an equation too weak to solve (``hypot(p, q) < 1e-15``, as :func:`harmonic_roots`).
    Near 0 its two roots are near each other (or nearly exist): a small change of the arm
    adds or removes both.
    """
    rho = math.hypot(p, q)
    return abs(1.0 - abs(k) / rho) if rho >= 1e-15 else 0.0


def rotation_pair(
    sa: float, ca: float, vx: float, vy: float, vz: float, dx: float, dy: float, dz: float
) -> list[tuple[float, float]]:
    """Angles ``(ta, tb)`` with ``Rz(ta) Rx(alpha) Rz(tb) v = d`` (``|v| = |d|``), up to two pairs.

    The z row gives ``sa (vx sin tb + vy cos tb) + ca vz = dz`` (two ``tb``); ``ta`` then turns
    ``Rx(alpha) Rz(tb) v`` about z onto ``d``. ``sa, ca`` are ``sin alpha, cos alpha``.
    """
    heading = math.atan2(dy, dx)
    pairs = []
    for tb in harmonic_roots(sa * vy, sa * vx, dz - ca * vz):
        cb, sb = math.cos(tb), math.sin(tb)
        mx = vx * cb - vy * sb
        my = ca * (vx * sb + vy * cb) - sa * vz
        pairs.append((heading - math.atan2(my, mx), tb))
    return pairs


def scan(value: float, step: float, low: float, high: float) -> Iterator[float]:
    """``value``, then ``value + j step`` and ``value - j step`` for j = 1, 2, ... inside ``[low, high]``.

    The free joint's values [rad] outward from a start's: the first that gives a branch inside the
    limits is the nearest to the start's at that resolution. ``step <= 0``: ``value`` alone.
    """
    yield value
    if not step > 0.0:
        return
    j = 1
    while True:
        up, down = value + j * step, value - j * step
        if up > high and down < low:
            return
        if low <= up <= high:
            yield up
        if low <= down <= high:
            yield down
        j += 1


def limit_arcs(
    lower: Sequence[float], upper: Sequence[float], offsets: Sequence[float], joints: Sequence[int]
) -> tuple[float, ...]:
    """The joints' limits as arcs of their angle ``t = q + offset``, as the twins read them.

    Per joint: ``cos, sin`` of the middle of the limits, ``cos`` of half their span, then 1
    when the span is a whole turn or more (or not finite: every ``t``), else 0 (``arc`` in
    ``_closed7.c`` and ``_shoulder7.c``). The Python modules do not use them: the twins skip,
    without solving, the free-joint values where no branch, followed as directions, has every
    joint in its arc (``arc_admits`` in ``_twin.h``).
    """
    values: list[float] = []
    for j in joints:
        middle = 0.5 * (lower[j] + upper[j]) + offsets[j]
        half = 0.5 * (upper[j] - lower[j])
        if not half < math.pi:
            values += (1.0, 0.0, -1.0, 1.0)
        else:
            values += (math.cos(middle), math.sin(middle), math.cos(half), 0.0)
    return tuple(values)


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
    pool = _pool(workers)
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


def _pool(threads: int) -> ThreadPoolExecutor:
    """This process's thread pool of the batched closed forms (made on first use)."""
    global _POOL
    pid = os.getpid()
    if _POOL is None or _POOL[0] != pid:
        _POOL = (pid, ThreadPoolExecutor(max_workers=threads, thread_name_prefix="kin-batch"))
    return _POOL[1]


def harmonic_roots_array(p: np.ndarray, q: np.ndarray, k: np.ndarray) -> np.ndarray:
    """:func:`harmonic_roots` of N equations: (N, 2), NaN where a root is missing.

    A double root fills column 0 only (as the scalar returns one angle).
    """
    rho = np.hypot(p, q)
    with np.errstate(divide="ignore", invalid="ignore"):
        cosine = k / rho
    ok = (rho >= 1e-15) & (np.abs(cosine) <= 1.0 + COS_SLACK)
    phi = np.arctan2(q, p)
    delta = np.arccos(np.clip(cosine, -1.0, 1.0))
    out = np.stack((phi + delta, np.where(delta > 0.0, phi - delta, np.nan)), 1)
    out[~ok] = np.nan
    return out


def rotation_pair_array(sa: float, ca: float, v: np.ndarray, d: np.ndarray) -> np.ndarray:
    """:func:`rotation_pair` of N vector pairs (N, 3): ``(ta, tb)`` as (N, 2, 2)."""
    vx, vy, vz = v[:, 0], v[:, 1], v[:, 2]
    heading = np.arctan2(d[:, 1], d[:, 0])
    tb = harmonic_roots_array(sa * vy, sa * vx, d[:, 2] - ca * vz)
    out = np.empty((v.shape[0], 2, 2))
    for i in range(2):
        cb, sb = np.cos(tb[:, i]), np.sin(tb[:, i])
        mx = vx * cb - vy * sb
        my = ca * (vx * sb + vy * cb) - sa * vz
        out[:, i, 0] = heading - np.arctan2(my, mx)
        out[:, i, 1] = tb[:, i]
    return out
