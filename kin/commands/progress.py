"""The progress bar of the long commands (``kin reach``, ``kin workspace``, ``kin path``).

One line on stderr, redrawn in place (a carriage return) at most :data:`REDRAW_INTERVAL` apart:
the command's name, a bar, the count done of the total, the percentage and the time left
(estimated from the rate so far). It is drawn only on a terminal and not with ``--quiet``: a
log file or a pipe gets nothing. Closing it ends the line with a newline (when it drew), so the
next line (the result, or ``interrupted`` after Ctrl-C) starts on its own.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from types import TracebackType
from typing import TextIO

__all__ = ["REDRAW_INTERVAL", "ProgressBar", "format_seconds"]

#: Shortest time between two redraws [s] (about ten a second); the last count is always drawn.
REDRAW_INTERVAL = 0.1
#: Characters of the bar itself.
BAR_WIDTH = 24


def format_seconds(seconds: float) -> str:
    """``seconds`` [s] as ``M:SS`` or ``H:MM:SS`` (rounded up to the next second)."""
    whole = int(-(-max(seconds, 0.0) // 1))
    hours, rest = divmod(whole, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


class ProgressBar:
    """A progress bar on a terminal; a callable ``(done, total)`` for the library's ``progress``.

    Use it as a context manager (or call :meth:`close`): the line ends with a newline then.

    Args:
        prog: The command's name, the line's prefix (``kin reach``).
        what: What is counted (``poses``, ``samples``), after the count.
        quiet: Draw nothing (the command's ``--quiet``).
        stream: Where to draw (None: ``sys.stderr`` as it is now); nothing unless it is a
            terminal (``isatty()``).
        clock: Monotonic time [s] (tests give their own).
    """

    def __init__(
        self,
        prog: str,
        what: str = "",
        *,
        quiet: bool = False,
        stream: TextIO | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.prog = prog
        self.what = what
        self.stream = sys.stderr if stream is None else stream
        self.enabled = not quiet and _is_terminal(self.stream)
        self.clock = clock
        self.start = clock()
        self._last_draw: float | None = None
        self._width = 0  # of the line drawn last (a shorter one is padded over it)

    def __call__(self, done: int, total: int) -> None:
        """Show ``done`` of ``total``; redrawn only if :data:`REDRAW_INTERVAL` has passed."""
        if not self.enabled:
            return
        now = self.clock()
        last = self._last_draw
        if last is not None and now - last < REDRAW_INTERVAL and done < total:
            return
        self._last_draw = now
        self._draw(self.line(done, total, now - self.start))

    def line(self, done: int, total: int, elapsed: float) -> str:
        """The text of the bar after ``elapsed`` [s] with ``done`` of ``total`` counted."""
        fraction = min(max(done / total, 0.0), 1.0) if total > 0 else 1.0
        filled = int(fraction * BAR_WIDTH)
        bar = "#" * filled + "-" * (BAR_WIDTH - filled)
        if done >= total:
            left = f"{format_seconds(elapsed)} in all"
        elif done > 0 and elapsed > 0:
            left = f"{format_seconds(elapsed * (total - done) / done)} left"
        else:
            left = "--:-- left"
        what = f" {self.what}" if self.what else ""
        return f"{self.prog}: [{bar}] {done:,}/{total:,}{what} {100 * fraction:3.0f}% {left}"

    def _draw(self, text: str) -> None:
        padding = " " * max(0, self._width - len(text))
        self._width = len(text)
        try:
            self.stream.write(f"\r{text}{padding}")
            self.stream.flush()
        except (OSError, ValueError):  # the terminal went away: the work goes on, silently
            self.enabled = False

    def close(self) -> None:
        """End the line with a newline, if anything was drawn (once)."""
        if self.enabled and self._last_draw is not None:
            try:
                self.stream.write("\n")
                self.stream.flush()
            except (OSError, ValueError):
                pass
        self.enabled = False

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.close()


def _is_terminal(stream: TextIO) -> bool:
    """Whether ``stream`` is a terminal (False for a closed or odd stream)."""
    try:
        return bool(stream.isatty())
    except (AttributeError, OSError, ValueError):
        return False
