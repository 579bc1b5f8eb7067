"""The general 6R closed form's passes in its compiled twin (``kin/_native/ik/analytic/six_r/_general6r.c``).

:class:`.general_6r.General6R` asks the twin for the first elimination's pass of every pose
(:func:`in_threads`: row blocks over the processors). A pose that pass does not solve cleanly
(fewer distinct branches than real roots, or an odd number: a root whose joints do not polish
onto the target, two solutions sharing the eliminated joint's angle) is solved again in the twin
(:func:`resolve`): by the fallback eliminations at the pose itself, their branches merged, and,
as in the NumPy path, by every cut of the loop at the nearby poses of
:data:`.general_6r.NUDGES`, each candidate polished back onto the pose (the NumPy path's last
resort, :meth:`.general_6r.General6R.solve_batch`). Left to the NumPy path: a pose the twin
cannot answer (a singular pencil or leading matrix: root count -1), one unclean at a multiple
root (-2: the NumPy path's careful pass reads every solution sharing the eliminated joint's
angle), and one still unclean after the nudges.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ._general_6r_chain import BRANCHES, distinct, distinct_again

#: Poses from which the first pass runs in threads (a pose costs about 0.1 ms: a block of 16
#: outweighs a thread's hand-over many times).
THREAD_ROWS = 32


def in_threads(
    first_pass: Any, block: np.ndarray, T: np.ndarray, out: np.ndarray, roots: np.ndarray
) -> None:
    """The twin's ``first_pass(block, T, out, roots)`` in row blocks over the processors.

    Its loop runs without the interpreter lock and each pose's answer is its own: the answers
    of one call. Below :data:`THREAD_ROWS` poses, or inside a batch thread, one call.
    """
    import threading

    from ..twin_support import batch_threads, thread_pool

    n, workers = T.shape[0], batch_threads()
    inside = threading.current_thread().name.startswith("kin-batch")
    if n < THREAD_ROWS or workers < 2 or inside:
        first_pass(block, T, out, roots)
        return
    bounds = np.linspace(0, n, 4 * workers + 1).astype(int).tolist()
    pool = thread_pool(workers)
    jobs = [
        pool.submit(first_pass, block, T[a:b], out[a:b], roots[a:b])
        for a, b in zip(bounds[:-1], bounds[1:])
        if b > a
    ]
    for job in jobs:
        job.result()


def branch_count(out: np.ndarray) -> np.ndarray:
    """The distinct branches of each pose (N,) in ``out`` (N, 16, 6) (NaN rows after them)."""
    return np.asarray((~np.isnan(out[..., 0])).sum(axis=1))


def unclean(out: np.ndarray, roots: np.ndarray) -> np.ndarray:
    """(N,) the poses a pass did not solve cleanly: fewer branches than real roots, or odd."""
    found = branch_count(out)
    return np.asarray((found < roots) | (found % 2 == 1))


def merged(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """The distinct branches (n, 16, 6) [rad] of two answers (n, 16, 6) of the same n poses."""
    both = np.concatenate((first, second), axis=1)
    pose, branch = np.nonzero(~np.isnan(both[..., 0]))
    return distinct(first.shape[0], pose, both[pose, branch])


def _rows(out: np.ndarray, keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pose index (M,) and branch (M, 6) [rad] of the branches in ``out`` of the poses ``keep``."""
    pose, branch = np.nonzero(~np.isnan(out[..., 0]) & keep[:, None])
    return pose, out[pose, branch]


def _pass(
    first_pass: Any, block: np.ndarray, T: np.ndarray, targets: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """One pass of the twin over poses ``T`` (n, 4, 4) [m]: branches (n, 16, 6), roots (n,).

    ``targets``: the poses the candidates are polished onto (``T`` are nearby poses).
    """
    n = T.shape[0]
    out, roots = np.empty((n, BRANCHES, 6)), np.empty(n)
    if targets is None:
        first_pass(block, T, out, roots)
    else:
        first_pass(block, np.ascontiguousarray(T), out, roots, targets)
    return out, roots


def resolve(
    first_pass: Any,
    T: np.ndarray,
    out: np.ndarray,
    roots: np.ndarray,
    fallbacks: Sequence[np.ndarray],
    cuts: Sequence[np.ndarray],
    nudges: Sequence[np.ndarray],
) -> None:
    """The branches of poses ``T`` (n, 4, 4) [m] that the first pass left unclean, in place.

    ``out`` (n, 16, 6) [rad] and ``roots`` (n,) are the first pass's answers of these poses;
    ``fallbacks`` the twin blocks of the further eliminations, asked in turn at the poses still
    unclean (the root count of the latest that answers is the one to reach); ``cuts`` the blocks
    of every cut of the loop, asked at each nearby pose ``T @ nudge`` of the poses still unclean
    after them. Every pass's branches are merged with those found before
    (:func:`~._general_6r_chain.distinct_again`). A pose a fallback finds unclean at a multiple
    root (its root count -2: solutions sharing the eliminated joint's angle, which only the
    NumPy path's careful pass reads) is left with ``roots`` -2 for the NumPy path.
    """
    T = np.ascontiguousarray(T)
    n = T.shape[0]
    pose, u = _rows(out, np.ones(n, dtype=bool))
    poses, rows = [pose], [u]
    left = np.arange(n)
    for block in fallbacks:
        more, more_roots = _pass(first_pass, block, T[left])
        answered = more_roots >= 0.0
        pose, u = _rows(more, answered)
        poses.append(left[pose])
        rows.append(u)
        roots[left[answered]] = more_roots[answered]
        roots[left[more_roots == -2.0]] = -2.0  # a multiple root: the NumPy path's
        distinct_again(out, np.concatenate(poses), np.concatenate(rows), left)
        left = left[unclean(out[left], roots[left]) & (roots[left] >= 0.0)]
        if not left.size:
            break
    nudged = np.nonzero(roots >= 0.0)[0]
    targets = T[nudged]
    aims = np.ascontiguousarray(np.tile(targets, (len(nudges), 1, 1)))
    which = np.tile(nudged, len(nudges))
    stacked = np.concatenate([targets @ nudge for nudge in nudges])  # every nudge, one pass a cut
    for more, more_roots in _passes(first_pass, cuts, stacked, aims):
        pose, u = _rows(more, more_roots >= 0.0)
        poses.append(which[pose])
        rows.append(u)
    distinct_again(out, np.concatenate(poses), np.concatenate(rows), nudged)


def _passes(
    first_pass: Any, blocks: Sequence[np.ndarray], T: np.ndarray, targets: np.ndarray
) -> list[tuple[np.ndarray, np.ndarray]]:
    """:func:`_pass` of each block over the same poses, the blocks in the batch threads.

    In turn instead in one of those threads (a batch solved inside another's block) or on one
    processor.
    """
    import threading

    from ..twin_support import batch_threads, thread_pool

    workers = batch_threads()
    inside = threading.current_thread().name.startswith("kin-batch")
    if workers < 2 or len(blocks) < 2 or inside:
        return [_pass(first_pass, block, T, targets) for block in blocks]
    pool = thread_pool(workers)
    jobs = [pool.submit(_pass, first_pass, block, T, targets) for block in blocks]
    return [job.result() for job in jobs]
