"""Where the workspace chunks run: this process, a process pool, or a Dask cluster.

Every way gives the same :class:`~kin.workspace.chunk.ChunkReduction` (the merge is exact and does not
depend on order). The chunk tasks come from an iterator and are submitted as workers free up, at
most :data:`IN_FLIGHT_PER_WORKER` per worker at a time, so that any number of chunks runs in
bounded memory. Dask is optional (``pip install "dh-kinematics[dask]"``) and imported only when a
client is given or :func:`dask_client` is called, never by ``import kin``.

Faults: a worker process that dies (killed, out of memory) is replaced and its chunks run again
(:mod:`kin.workspace.pool`). A chunk is seeded by its index (:func:`kin.workspace.monte_carlo.chunk_seed`), so its
rerun gives the same reduction and the result equals an undisturbed run's. On Dask the scheduler
reruns a lost worker's chunks itself. A lost scheduler, or a chunk that loses its worker process
every time, raises :class:`~kin.exceptions.RunFaultError`.
"""

from __future__ import annotations

import logging
import signal
from collections.abc import Callable, Collection, Generator, Iterable, Iterator
from contextlib import closing, contextmanager, suppress
from itertools import islice
from typing import Any

from ..exceptions import KinError, RunFaultError
from .chunk import reduce_chunk
from .pool import run_unordered

#: The install hint of the optional Dask extra.
DASK_HINT = 'pip install "dh-kinematics[dask]"'

#: Chunks handed to each worker ahead of its results (the bound on memory in flight).
IN_FLIGHT_PER_WORKER = 2


def _chunk(task: tuple) -> Any:
    return reduce_chunk(*task)


def _ignore_sigint() -> None:
    """Worker processes leave Ctrl-C to the parent (no traceback per worker)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextmanager
def dask_faults(client: Any, futures: Collection[Any]) -> Iterator[None]:
    """Dask's errors of a lost scheduler or of killed workers, raised as one RunFaultError.

    On leaving early (Ctrl-C, an error), ``futures`` (read then: a set may change meanwhile) are
    cancelled, unless the scheduler is gone (cancelling would wait for it to come back).

    Raises:
        RunFaultError: The scheduler went away (the futures were cancelled, a connection
            closed), or a chunk killed every worker it ran on (``KilledWorker``).
    """
    from concurrent.futures import CancelledError

    from distributed import KilledWorker

    address = getattr(getattr(client, "scheduler", None), "address", None) or "?"
    faults = (CancelledError, KilledWorker, OSError, TimeoutError)
    lost = False
    try:
        yield
    except KilledWorker as err:
        lost = True
        raise RunFaultError(f"a chunk killed every Dask worker it ran on: {err}") from err
    except faults as err:
        lost = True
        raise RunFaultError(
            f"lost the Dask scheduler at {address} during the run ({type(err).__name__}): "
            "start it again and rerun"
        ) from err
    finally:
        running = [future for future in futures if not future.done()]
        if running and not lost:
            with suppress(*faults):
                client.cancel(running)


def _on_dask(tasks: Iterator[tuple], client: Any) -> Generator[Any, None, None]:
    """The reductions of the chunks, run on ``client``'s cluster, as they finish.

    At most :data:`IN_FLIGHT_PER_WORKER` chunks per worker thread are on the cluster at a time.

    Raises:
        RunFaultError: The scheduler went away, or a chunk killed its workers.
    """
    from distributed import as_completed as dask_completed

    from dh2urdf.stop_signals import raise_lost_stop

    pending: set[Any] = set()
    with dask_faults(client, pending):
        threads = sum(client.nthreads().values())
        first = islice(tasks, IN_FLIGHT_PER_WORKER * max(threads, 1))
        pending.update(client.submit(_chunk, task, pure=False) for task in first)
        finished = dask_completed(list(pending))
        for future in finished:
            raise_lost_stop()  # a SIGTERM whose raise a GC callback swallowed
            pending.discard(future)
            result = future.result()
            for task in islice(tasks, 1):  # the next chunk, if any, takes its place
                successor = client.submit(_chunk, task, pure=False)
                pending.add(successor)
                finished.add(successor)
            yield result


def run_chunks(
    tasks: Iterable[tuple],
    *,
    workers: int = 1,
    client: Any = None,
    progress: Callable[[int, int], None] | None = None,
    n: int = 0,
) -> Any:
    """Reduce every chunk task and merge the reductions.

    Args:
        tasks: Arguments of :func:`kin.workspace.chunk.reduce_chunk`, one tuple per chunk; read as
            workers free up (a generator keeps any number of chunks in bounded memory).
        workers: Worker processes (1: run here, one chunk after another); one that dies is
            replaced and its chunks run again.
        client: A ``distributed.Client``; the chunks go to its cluster (``workers`` ignored).
        progress: Called with (samples done, n) after each chunk.
        n: Total samples (for ``progress``).

    Raises:
        RunFaultError: The Dask scheduler was lost, or a chunk kept losing its worker process.
    """
    chunks = iter(tasks)
    if client is not None:
        results: Generator[Any, None, None] = _on_dask(chunks, client)
    elif workers > 1:
        results = run_unordered(_chunk, chunks, workers, per_worker=IN_FLIGHT_PER_WORKER)
    else:
        results = (_chunk(task) for task in chunks)
    total = None
    with closing(results):  # on Ctrl-C the workers stop here, not when a generator is collected
        for result in results:
            total = result if total is None else total.merge(result)
            if progress is not None:
                progress(total.n_samples, n)
    return total


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
        # After a lost scheduler, closing stops the client's reconnection with a logged traceback.
        logging.disable(logging.CRITICAL)
        try:
            client.close()
        finally:
            logging.disable(logging.NOTSET)
