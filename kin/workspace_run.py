"""Where the workspace chunks run: this process, a process pool, or a Dask cluster.

Every way gives the same :class:`~kin.workspace.ChunkReduction` (the merge is exact and does not
depend on order). Dask is optional (``pip install "dh-kinematics[dask]"``) and imported only by
:func:`dask_client`, never by ``import kin``.
"""

from __future__ import annotations

import signal
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from .exceptions import KinError

#: The install hint of the optional Dask extra.
DASK_HINT = 'pip install "dh-kinematics[dask]"'


def _chunk(task: tuple) -> Any:
    from .workspace import reduce_chunk

    return reduce_chunk(*task)


def _ignore_sigint() -> None:
    """Worker processes leave Ctrl-C to the parent (no traceback per worker)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _merged(results: Iterator[Any], n: int, progress: Callable[[int, int], None] | None) -> Any:
    total = None
    for result in results:
        total = result if total is None else total.merge(result)
        if progress is not None:
            progress(total.n_samples, n)
    return total


def _merged_in_pool(
    tasks: Sequence[tuple],
    workers: int,
    progress: Callable[[int, int], None] | None,
    n: int,
) -> Any:
    """The merged reductions of the chunks, run by a pool of ``workers`` processes.

    On Ctrl-C (or any error) the workers are terminated at once, not waited for, right where the
    interrupt lands (not when a generator is collected later): a second Ctrl-C during that
    cleanup is ignored (the command is ending anyway), so that neither a worker nor the parent
    goes on computing, and nothing is left to hang at exit.
    """
    import multiprocessing

    pool = multiprocessing.get_context().Pool(workers, initializer=_ignore_sigint)
    try:
        total = _merged(pool.imap_unordered(_chunk, tasks), n, progress)
    except BaseException:
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            pool.terminate()
            pool.join()
        finally:
            signal.signal(signal.SIGINT, previous)
        raise
    pool.close()
    pool.join()
    return total


def _on_dask(tasks: Sequence[tuple], client: Any) -> Iterator[Any]:
    from distributed import as_completed as dask_completed

    futures = [client.submit(_chunk, task, pure=False) for task in tasks]
    try:
        for future in dask_completed(futures):
            yield future.result()
    finally:
        client.cancel(futures)


def run_chunks(
    tasks: Sequence[tuple],
    *,
    workers: int = 1,
    client: Any = None,
    progress: Callable[[int, int], None] | None = None,
    n: int = 0,
) -> Any:
    """Reduce every chunk task and merge the reductions.

    Args:
        tasks: Arguments of :func:`kin.workspace.reduce_chunk`, one tuple per chunk.
        workers: Processes of a ``ProcessPoolExecutor`` (1: run here, one chunk after another).
        client: A ``distributed.Client``; the chunks go to its cluster.
        progress: Called with (samples done, n) after each chunk.
        n: Total samples (for ``progress``).
    """
    if client is not None:
        results: Iterator[Any] = _on_dask(tasks, client)
    elif workers > 1 and len(tasks) > 1:
        return _merged_in_pool(tasks, workers, progress, n)
    else:
        results = (_chunk(task) for task in tasks)
    return _merged(results, n, progress)


@contextmanager
def dask_client(address: str) -> Iterator[Any]:
    """A ``distributed.Client`` connected to the scheduler at ``address``, closed on exit.

    Raises:
        KinError: Dask is not installed (the message names the extra), or the scheduler is
            unreachable.
    """
    try:
        from distributed import Client
    except ImportError as err:
        raise KinError(f"--scheduler needs Dask: {DASK_HINT}") from err
    try:
        client = Client(address, timeout="10s")
    except (OSError, TimeoutError, ValueError) as err:
        raise KinError(f"cannot reach the Dask scheduler at {address!r}: {err}") from err
    try:
        yield client
    finally:
        client.close()
