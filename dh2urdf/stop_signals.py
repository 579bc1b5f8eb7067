"""How a command stops: Ctrl-C (SIGINT) and SIGTERM alike, as a ``KeyboardInterrupt``.

SIGTERM (``kill PID``, ``timeout``, a job scheduler, a container's stop) ends a command the way
Ctrl-C does: what is done is kept (a stream's answers written whole), worker processes are ended,
no file is left half-written. Only the exit code and the line on stderr tell them apart:
``prog: interrupted`` and 130 after SIGINT, ``prog: terminated`` and 143 after SIGTERM (128 plus
the signal's number, the code a shell reports for a process the signal ended, so that a
supervisor sees what it asked for).

:func:`listen_to_stops` makes both signals raise ``KeyboardInterrupt`` in the main thread (a
SIGINT inherited as ignored, ``cmd &`` in a script, is taken back; a SIGTERM ignored by the
caller stays ignored); code that holds a signal for a while (:mod:`kin.workspace.pool`,
:mod:`kin.commands.interrupt_gate`) notes a SIGTERM with :func:`note_stop` so that the exit
code still says which signal came.

:func:`run_process` runs a command as the process's whole life (``python -m kin``, the console
scripts): once the command has been stopped, or has returned, a further SIGINT or SIGTERM is
ignored, so that a second Ctrl-C landing while the interpreter shuts down cannot end the
process by the signal (exit -2, a traceback) after its line was written.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable
from types import FrameType
from typing import Any

__all__ = [
    "STOP_SIGNALS",
    "hold_stops",
    "listen_to_stops",
    "note_stop",
    "raise_lost_stop",
    "run_process",
    "stop_handler",
    "stop_on_sigterm",
    "terminated",
]

#: The signals that stop a command, each raised as ``KeyboardInterrupt``.
STOP_SIGNALS: tuple[signal.Signals, ...] = (signal.SIGINT, signal.SIGTERM)


class _Seen:
    """Whether a SIGTERM came since :func:`listen_to_stops` (one command run per process)."""

    terminated = False
    #: Whether the command is the process's whole life (:func:`run_process`).
    process = False


def note_stop(signum: int) -> None:
    """Note that the stop signal ``signum`` came (a SIGTERM makes :func:`terminated` true)."""
    if signum == signal.SIGTERM:
        _Seen.terminated = True


def terminated() -> bool:
    """Whether the stop was a SIGTERM (exit 143), not a Ctrl-C (exit 130)."""
    return _Seen.terminated


def raise_lost_stop() -> None:
    """Raise ``KeyboardInterrupt`` when a SIGTERM came and its raise was lost.

    A ``KeyboardInterrupt`` raised while Python runs a garbage-collector callback (Dask's
    ``GCDiagnosis``) or a ``__del__`` is printed as "Exception ignored" and dropped: a loop that
    waits for work (a Dask cluster's chunks) calls this after each piece, so the stop still
    comes (seen: `kin reach --scheduler local-cluster:2` ran on for minutes after SIGTERM).
    """
    if _Seen.terminated:
        raise KeyboardInterrupt


def stop_on_sigterm(signum: int, frame: FrameType | None) -> None:
    """SIGTERM's handler in a command: noted, then raised as Ctrl-C's ``KeyboardInterrupt``."""
    note_stop(signum)
    raise KeyboardInterrupt


def stop_handler(signum: int) -> Callable[[int, FrameType | None], Any]:
    """The handler that stops a command on ``signum`` (one of :data:`STOP_SIGNALS`)."""
    return signal.default_int_handler if signum == signal.SIGINT else stop_on_sigterm


def hold_stops() -> None:
    """Once a command has stopped, in a process that ends with it: ignore every stop signal.

    Sets SIGINT and SIGTERM to ``SIG_IGN`` for the rest of the process when the command runs
    under :func:`run_process` (in the main thread); does nothing when it is called in-process (a
    test, a script), whose later signals are its caller's. Ignored, not blocked: a blocked
    signal sent to the process is delivered to any thread that does not block it (OpenBLAS's
    worker threads), whose default action for SIGTERM ends the process.
    """
    if _Seen.process and threading.current_thread() is threading.main_thread():
        for signum in STOP_SIGNALS:
            signal.signal(signum, signal.SIG_IGN)


def run_process(main: Callable[[], int]) -> int:
    """Run ``main`` as the process's command; stop signals are ignored once it returns.

    Returns:
        ``main``'s exit code.
    """
    _Seen.process = True
    try:
        return main()
    finally:
        hold_stops()


def listen_to_stops() -> Callable[[], None]:
    """Make SIGINT and SIGTERM raise ``KeyboardInterrupt`` here; what puts SIGTERM's back.

    In the main thread only (signals are not another thread's to take). SIGINT: an inherited
    SIG_IGN (``cmd &`` in a script, ``timeout -s INT``) is replaced, as a command that computes
    for minutes must stop on ``kill -INT``. SIGTERM: the default action (death, the command's
    workers left running) is replaced; a handler or SIG_IGN set by the caller is kept.

    Returns:
        A function that restores SIGTERM's previous handler (a command called in-process, by a
        test or a script, leaves the process as it found it).
    """
    _Seen.terminated = False
    if threading.current_thread() is not threading.main_thread():
        return lambda: None
    if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    previous = signal.getsignal(signal.SIGTERM)
    if previous != signal.SIG_DFL:
        return lambda: None
    signal.signal(signal.SIGTERM, stop_on_sigterm)

    def restore() -> None:
        if signal.getsignal(signal.SIGTERM) is stop_on_sigterm:
            signal.signal(signal.SIGTERM, previous)

    return restore
