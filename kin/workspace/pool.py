"""A pool of worker processes for independent chunks that survives the death of a worker.

Each worker has a pipe of its own (not a queue shared by all, whose reader a worker killed half-way
through writing a result leaves waiting forever, as ``ProcessPoolExecutor``'s does), so that a
worker that dies (killed, out of memory) costs only its own chunks: they run again on a new
worker. At most ``per_worker`` chunks are handed to each worker at a time, read from an iterator
as workers free up, so that any number of chunks runs in bounded memory.

Workers are forked with SIGINT and SIGTERM blocked, ignore SIGINT once started and die of
SIGTERM: Ctrl-C (and a SIGTERM to the command, :mod:`dh2urdf.stop_signals`) is the parent's, even
when it lands while the pool starts; tasks are made with both held too (:func:`_next_task`). On
Ctrl-C, SIGTERM, an error or the generator's close, the workers are killed at once, not waited
for.

A worker never outlives its parent, however the parent ends (even SIGKILL): it closes the
parent's ends of every pipe it inherited by the fork (its own included), so that the parent's
death reads as end of file, and on Linux the kernel kills it when the thread that forked it ends
(``PR_SET_PDEATHSIG``; the pool is used from the main thread by the commands). Otherwise a worker
left waiting on a pipe it holds both ends of waits forever, and keeps the command's standard
output open (``kin workspace --workers 2 | cat`` never ended).
"""

from __future__ import annotations

import logging
import os
import signal
import sys
import threading
from collections import deque
from collections.abc import Callable, Generator, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field
from typing import Any

from dh2urdf.stop_signals import STOP_SIGNALS

from ..exceptions import RunFaultError

logger = logging.getLogger(__name__)

#: Times one chunk may lose its worker process before the run stops with a RunFaultError.
MAX_LOSSES = 3


@contextmanager
def _stops_held() -> Iterator[None]:
    """SIGINT and SIGTERM held meanwhile, delivered on exit: a process forked inside starts so.

    Without it a Ctrl-C that lands while the pool forks a worker reaches the worker before the
    worker ignores it, or interrupts the parent between the fork and the worker's entry in the
    pool. Blocking the signal in this thread is not enough: the kernel then delivers it to
    another thread of the process (OpenBLAS's, say) and Python still runs the handler here, at
    once; so the handler only notes it meanwhile, and the previous one runs on exit (a SIGTERM
    left to its default action ends the process then: its workers follow, see the module).
    """
    main = threading.current_thread() is threading.main_thread()
    if not main:
        yield
        return
    noted: list[int] = []
    previous = {
        signum: signal.signal(signum, lambda signum, frame: noted.append(signum))
        for signum in STOP_SIGNALS
    }
    mask = (
        signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
        if hasattr(signal, "pthread_sigmask")
        else None
    )
    try:
        yield
    finally:
        if mask is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a pending one is noted here
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        for number in dict.fromkeys(noted):
            handler = previous[signal.Signals(number)]
            if callable(handler):
                handler(number, None)  # Python's default and the commands' raise KeyboardInterrupt
            elif handler == signal.SIG_DFL:
                signal.raise_signal(number)  # the default action, now


#: ``prctl`` option: the signal the kernel sends this process when its parent thread ends.
_PR_SET_PDEATHSIG = 1


def _die_with_parent(parent: int) -> bool:
    """Linux: be killed when the thread that forked this process ends; False: it already has.

    Elsewhere (or without a C library to call) only the end of file on the pipe tells.
    """
    if not sys.platform.startswith("linux"):
        return True
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    except (OSError, AttributeError):
        return True
    return os.getppid() == parent  # the parent died before prctl: nobody would send it


def _serve(
    conn: Any, function: Callable[[Any], Any], inherited: list[Any], parent: int | None
) -> None:
    """A worker's loop: ``function`` of each task received, its result (or error) sent back.

    Args:
        conn: The worker's end of its pipe.
        function: What each task is given to.
        inherited: The parent's ends of the pipes (the worker's own, earlier workers'), copied
            by the fork: closed here, so that the parent's death reads as end of file.
        parent: The parent's process id when the worker is to die with the thread that forked
            it (the main thread), else None.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # the parent's _kill, or the pool's SIGTERM
    for end in inherited:
        end.close()
    if parent is not None and not _die_with_parent(parent):
        return
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):  # the parent is gone
            return
        if task is None:
            return
        try:
            reply = (True, function(task))
        except Exception as err:  # the parent raises it
            reply = (False, err)
        try:
            conn.send(reply)
        except OSError:  # the parent is gone (a broken pipe)
            return
        except Exception as err:  # an error that does not pickle: its text instead
            with suppress(OSError):
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
    inherited = [parent_end, *(worker.conn for worker in pool)]
    main = threading.current_thread() is threading.main_thread()
    parent = os.getpid() if main else None
    with _stops_held():
        process = context.Process(
            target=_serve, args=(child_end, function, inherited, parent), daemon=True
        )
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
    with _stops_held():
        return next(tasks, None)


def _kill(pool: list[_Worker]) -> None:
    """Kill every worker at once; a Ctrl-C or SIGTERM meanwhile is ignored (the run ends anyway)."""
    main = threading.current_thread() is threading.main_thread()
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in STOP_SIGNALS} if main else {}
    try:
        for worker in pool:
            worker.process.terminate()
        for worker in pool:
            worker.process.join()
            worker.conn.close()
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


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
