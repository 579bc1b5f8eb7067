"""Ctrl-C (or SIGTERM) that never lands inside a write: whole output lines, then exit 130 (143).

A stream (``kin ik --stdin``) must stop at once on SIGINT while it waits for input or computes,
yet keep what it has computed and never cut an output line. Between
:meth:`InterruptGate.hold` and :meth:`InterruptGate.release` (its answers made and being written)
a first SIGINT is only noted, and raised as ``KeyboardInterrupt`` by ``release``; elsewhere it
raises at once, as Python's default handler does. A second SIGINT while held raises at once: the
way out of a write blocked on a reader that never reads. SIGTERM is handled the same way (where
the command stops on it, :mod:`dh2urdf.stop_signals`), and noted so that the exit code is 143.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

from dh2urdf.stop_signals import STOP_SIGNALS, note_stop, stop_handler


class InterruptGate:
    """SIGINT's (and SIGTERM's) handler while a stream runs; see the module docstring.

    Attributes:
        installed: Whether the gate is SIGINT's handler (False outside the main thread, or when
            SIGINT was not Python's default handler: then nothing is held).
    """

    def __init__(self) -> None:
        self.installed = False
        self._holding = False
        self._pending = False

    def handle(self, signum: int, frame: FrameType | None) -> None:
        """SIGINT (SIGTERM) handler: note a first one while held, else raise ``KeyboardInterrupt``."""
        note_stop(signum)
        if self._holding and not self._pending:
            self._pending = True
            return
        self._pending = False  # raised now: nothing left for release()
        raise KeyboardInterrupt

    def hold(self) -> None:
        """From now on a first SIGINT is only noted (until :meth:`release`)."""
        self._holding = True

    def release(self) -> None:
        """SIGINT raises at once again.

        Raises:
            KeyboardInterrupt: A SIGINT came while held.
        """
        self._holding = False
        if self._pending:
            self._pending = False
            raise KeyboardInterrupt


@contextmanager
def interrupt_gate() -> Iterator[InterruptGate]:
    """An :class:`InterruptGate` as SIGINT's and SIGTERM's handler for the block, the previous after.

    The gate is installed only in the main thread and in place of the handlers that stop a
    command (Python's default for SIGINT, :func:`dh2urdf.stop_signals.stop_on_sigterm`): a
    signal ignored or handled otherwise by the caller stays so.
    """
    gate = InterruptGate()
    previous: dict[int, object] = {}
    try:
        for signum in STOP_SIGNALS:
            if signal.getsignal(signum) is stop_handler(signum):
                previous[signum] = signal.signal(signum, gate.handle)
    except ValueError:  # not the main thread: signals are not ours to take
        pass
    gate.installed = signal.SIGINT in previous
    try:
        yield gate
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)  # type: ignore[arg-type]
