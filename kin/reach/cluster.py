"""The Dask client of a reachability map's run: none, the caller's, an address, or a local cluster."""

from __future__ import annotations

import contextlib
import logging
import os
import signal
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from ..exceptions import KinError

__all__ = ["reach_client"]


@contextmanager
def reach_client(scheduler: Any) -> Iterator[Any]:
    """The Dask client ``scheduler`` names (None for this process), closed on exit if opened."""
    if scheduler is None or scheduler == "local":
        yield None
        return
    if not isinstance(scheduler, str):
        yield scheduler  # a distributed.Client of the caller's
        return
    from ..workspace.run import DASK_HINT, _ignore_sigint, dask_client

    if not scheduler.startswith("local-cluster:"):
        with dask_client(scheduler) as client:
            yield client
        return
    workers = scheduler.removeprefix("local-cluster:")
    if not workers.isdigit() or int(workers) < 1:
        raise KinError(
            f"scheduler {scheduler!r}: give local-cluster:N with N a positive number of workers"
        )
    try:
        import dask
        from distributed import Client, LocalCluster
    except ImportError as err:
        raise KinError(f"--scheduler needs Dask: {DASK_HINT}") from err
    # Dask's nannies start workers with MALLOC_TRIM_THRESHOLD_=65536, which fixes glibc's mmap
    # threshold: every NumPy temporary of the batch IK is then mapped and faulted in afresh
    # (measured: 3x to 6x slower chunks). The workers of this cluster keep glibc's default,
    # and go without the statistical profiler (a sampling thread; no dashboard to show it).
    environ = dask.config.get("distributed.nanny.pre-spawn-environ", default={})
    kept = {k: v for k, v in environ.items() if k != "MALLOC_TRIM_THRESHOLD_"}
    settings = {
        "distributed.nanny.pre-spawn-environ": kept,
        "distributed.worker.profile.enabled": False,
    }
    with dask.config.set(settings):
        cluster = LocalCluster(
            n_workers=int(workers),
            threads_per_worker=1,
            dashboard_address=None,
            processes=True,
            silence_logs=logging.CRITICAL,  # a task's error still reaches the caller
        )
        with cluster, Client(cluster) as client:
            client.run(_ignore_sigint)  # Ctrl-C is the parent's: no traceback per worker
            pids = list(client.run(os.getpid).values())
            try:
                yield client
            except KeyboardInterrupt:
                # The scheduler lives in this process: torn down mid-run it logs, at CRITICAL, a
                # traceback for each message it can no longer send to the closed client.
                logging.getLogger("distributed").setLevel(logging.CRITICAL + 1)
                # A stop does not wait for the chunks at work (a closing cluster does: a minute
                # and more for a reach map's chunks): their workers are ended, their nannies
                # then closed with the cluster.
                for pid in pids:
                    with contextlib.suppress(OSError):
                        os.kill(pid, signal.SIGKILL)
                raise
