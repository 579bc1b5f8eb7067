"""A pool of worker processes for independent chunks that survives the death of a worker.

Each worker has a pipe of its own (not a queue shared by all, whose reader a worker killed half-way
through writing a result leaves waiting forever, as ``ProcessPoolExecutor``'s does), so that a
worker that dies (killed, out of memory) costs only its own chunks: they run again on a new
worker. At most ``per_worker`` chunks are handed to each worker at a time, read from an iterator
as workers free up, so that any number of chunks runs in bounded memory.

Workers are forked with SIGINT blocked and ignore it once started: Ctrl-C is the parent's, even
when it lands while the pool starts; tasks are made with it held too (:func:`_next_task`). On
Ctrl-C, an error or the generator's close, the workers are killed at once, not waited for.
"""

from __future__ import annotations

import logging
import signal
import threading
from collections import deque
from collections.abc import Callable, Generator, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from .exceptions import RunFaultError

logger = logging.getLogger(__name__)

#: Times one chunk may lose its worker process before the run stops with a RunFaultError.
MAX_LOSSES = 3


@contextmanager
def _sigint_held() -> Iterator[None]:
    """SIGINT held meanwhile and delivered on exit: a process forked inside starts with it blocked.

    Without it a Ctrl-C that lands while the pool forks a worker reaches the worker before the
    worker ignores it, or interrupts the parent between the fork and the worker's entry in the
    pool. Blocking the signal in this thread is not enough: the kernel then delivers it to
    another thread of the process (OpenBLAS's, say) and Python still runs the handler here, at
    once; so the handler only notes it meanwhile, and the previous one runs on exit.
    """
    main = threading.current_thread() is threading.main_thread()
    if not main:
        yield
        return
    noted: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: noted.append(signum))
    mask = (
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        if hasattr(signal, "pthread_sigmask")
        else None
    )
    try:
        yield
    finally:
        if mask is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a pending one is noted here
        signal.signal(signal.SIGINT, previous)
        if noted and callable(previous):
            previous(signal.SIGINT, None)  # Python's default raises KeyboardInterrupt
        elif noted and previous == signal.SIG_DFL:
            signal.raise_signal(signal.SIGINT)  # the default action, now


def _serve(conn: Any, function: Callable[[Any], Any]) -> None:
    """A worker's loop: ``function`` of each task received, its result (or error) sent back."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    while True:
        try:
            task = conn.recv()
        except EOFError:  # the parent is gone
            return
        if task is None:
            return
        try:
            reply = (True, function(task))
        except Exception as err:  # the parent raises it
            reply = (False, err)
        try:
            conn.send(reply)
        except Exception as err:  # an error that does not pickle
            conn.send((False, RuntimeError(f"{type(err).__name__}: {err}")))


@dataclass(eq=False)
class _Worker:
    """A worker process, the parent's end of its pipe, and its tasks in order (task, losses)."""

    process: Any
    conn: Any
    tasks: deque[tuple[Any, int]] = field(default_factory=deque)


def _start(context: Any, function: Callable[[Any], Any], pool: list[_Worker]) -> None:
    """Fork a worker and add it to ``pool``, SIGINT held until it is there.

    A Ctrl-C delivered between the fork and the worker's entry in the pool would leave a worker
    nobody kills: it ignores SIGINT and holds its own pipe open, so it would wait forever (and
    keep the command's output open).
    """
    parent_end, child_end = context.Pipe()
    with _sigint_held():
        process = context.Process(target=_serve, args=(child_end, function), daemon=True)
        process.start()
        pool.append(_Worker(process, parent_end))
        child_end.close()  # the worker's death then reads as EOF here, never as a wait


def _next_task(tasks: Iterator[Any]) -> Any:
    """The next task (None: no more), made with SIGINT held.

    A task made lazily may import a module on the way (NumPy imports ``numpy.random`` at its
    first use), and a KeyboardInterrupt raised at some moments of that import is lost (the
    import completes, no exception, nothing printed): the run would go on, its workers ignoring
    Ctrl-C. Held, it is raised here, after the task is made.
    """
    with _sigint_held():
        return next(tasks, None)


def _kill(pool: list[_Worker]) -> None:
    """Kill every worker at once; a second Ctrl-C meanwhile is ignored (the run ends anyway)."""
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        for worker in pool:
            worker.process.terminate()
        for worker in pool:
            worker.process.join()
            worker.conn.close()
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)


def _received(worker: _Worker) -> tuple[bool, Any] | None:
    """The worker's next reply, or None when it died (EOF, or a reply cut short)."""
    try:
        return worker.conn.recv()
    except (EOFError, OSError):
        return None


def run_unordered(
    function: Callable[[Any], Any],
    tasks: Iterator[Any],
    workers: int,
    *,
    per_worker: int = 2,
) -> Generator[Any, None, None]:
    """``function(task)`` of every task, run by ``workers`` processes, in the order they finish.

    Args:
        function: A module-level function (the workers are forked: it is not pickled).
        tasks: Picklable tasks, read as workers free up.
        workers: Worker processes.
        per_worker: Tasks handed to a worker ahead of its results.

    Raises:
        RunFaultError: One task lost its worker :data:`MAX_LOSSES` times.
        Exception: A task's own error, as the worker raised it.
    """
    import multiprocessing
    from multiprocessing.connection import wait

    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else None)
    pool: list[_Worker] = []
    again: deque[tuple[Any, int]] = deque()  # tasks of dead workers, first to run
    try:
        while True:
            while len(pool) < workers:
                _start(context, function, pool)
            for worker in list(pool):
                while len(worker.tasks) < per_worker:
                    entry = again.popleft() if again else (_next_task(tasks), 0)
                    if entry[0] is None:
                        break
                    try:
                        worker.conn.send(entry[0])
                    except OSError:  # it died since the last look: the task was never sent
                        again.appendleft(entry)
                        _replace(pool, worker, again)
                        break
                    worker.tasks.append(entry)
            busy = [worker for worker in pool if worker.tasks]
            if not busy and again:  # every worker died before taking its task: start new ones
                continue
            if not busy:  # every task done: the idle workers go
                _kill(pool)
                return
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            results = []
            for worker in busy:
                if worker.conn in ready:
                    reply = _received(worker)
                elif worker.process.sentinel in ready:
                    reply = None
                else:
                    continue
                if reply is None:
                    _replace(pool, worker, again)
                    continue
                worker.tasks.popleft()
                ok, value = reply
                if not ok:
                    raise value
                results.append(value)
            yield from results
    except BaseException:
        _kill(pool)
        raise


def _replace(pool: list[_Worker], dead: _Worker, again: deque[tuple[Any, int]]) -> None:
    """Drop a dead worker; its tasks go first in line again (one more loss each).

    Raises:
        RunFaultError: A task has lost its worker :data:`MAX_LOSSES` times.
    """
    pool.remove(dead)
    dead.process.join()
    dead.conn.close()
    lost = [(task, losses + 1) for task, losses in dead.tasks]
    if any(losses >= MAX_LOSSES for _, losses in lost):
        raise RunFaultError(
            f"a chunk's worker process died {MAX_LOSSES} times (out of memory? killed?): give "
            "fewer workers or smaller chunks"
        )
    logger.warning(
        "worker process %d died (exit code %s); %d chunks run again on a new one",
        dead.process.pid,
        dead.process.exitcode,
        len(lost),
    )
    again.extendleft(reversed(lost))
