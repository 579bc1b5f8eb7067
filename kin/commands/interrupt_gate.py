"""Ctrl-C that never lands inside a write: whole output lines, then exit 130.

A stream (``kin ik --stdin``) must stop at once on SIGINT while it waits for input or computes,
yet keep what it has computed and never cut an output line. Between
:meth:`InterruptGate.hold` and :meth:`InterruptGate.release` (its answers made and being written)
a first SIGINT is only noted, and raised as ``KeyboardInterrupt`` by ``release``; elsewhere it
raises at once, as Python's default handler does. A second SIGINT while held raises at once: the
way out of a write blocked on a reader that never reads.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType


class InterruptGate:
    """SIGINT's handler while a stream runs; see the module docstring.

    Attributes:
        installed: Whether the gate is SIGINT's handler (False outside the main thread, or when
            SIGINT was not Python's default handler: then nothing is held).
    """

    def __init__(self) -> None:
        self.installed = False
        self._holding = False
        self._pending = False

    def handle(self, signum: int, frame: FrameType | None) -> None:
        """SIGINT handler: note a first signal while held, else raise ``KeyboardInterrupt``."""
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
    """An :class:`InterruptGate` as SIGINT's handler for the block, the previous one after.

    The gate is installed only in the main thread and in place of Python's default handler: a
    SIGINT ignored or handled by the caller stays so.
    """
    gate = InterruptGate()
    previous = None
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        try:
            previous = signal.signal(signal.SIGINT, gate.handle)
        except ValueError:  # not the main thread: signals are not ours to take
            previous = None
    if previous is None:
        yield gate
        return
    gate.installed = True
    try:
        yield gate
    finally:
        signal.signal(signal.SIGINT, previous)
