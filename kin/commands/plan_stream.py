"""``kin plan --stdin``: one JSON request per input line, one answer line each, in input order.

In this process (:func:`_run_here`) the lines are planned one after another and each answer is
written and flushed at once: a client that writes a line and waits gets its answer. With
``--workers N`` (a local Dask cluster of N single-threaded processes) or ``--scheduler ADDRESS``
(:func:`_run_on_dask`) runs of up to :data:`TASK_LINES` lines are planned by the workers, at most
:data:`IN_FLIGHT_PER_THREAD` runs per worker thread at a time (memory stays flat over any number
of lines), and the answers are written in input order as the earliest ones come back. Each
worker builds the robot and the collision model once (:func:`.plan_lines.answer_lines`); OMPL's
random seed is process-wide, and each plan seeds it (:mod:`kin.plan.planner`), so a line's
answer does not depend on where it ran.

Ctrl-C or SIGTERM: the answers already written stay whole (and, on Dask, the finished ones that
follow them in order are written first), then ``kin plan: interrupted`` (exit 130) or
``terminated`` (143). A progress bar (plans answered of the lines read; of the whole file when
stdin is one) is drawn on stderr when it is a terminal and stdin is not.
"""

from __future__ import annotations

import argparse
import os
import stat
import sys
from collections import deque
from collections.abc import Callable, Iterable
from typing import Any, TextIO

from ..cli import positive_int

__all__ = [
    "IN_FLIGHT_PER_THREAD",
    "TASK_LINES",
    "add_stream_options",
    "check_stream_options",
    "run_stream",
]

#: Input lines planned by one Dask task (a plan takes milliseconds to seconds; a task's own
#: cost is about a millisecond).
TASK_LINES = 4
#: Tasks on the cluster per worker thread ahead of the answers being written.
IN_FLIGHT_PER_THREAD = 4


def add_stream_options(parser: argparse.ArgumentParser) -> None:
    """Add ``--stdin``, ``--workers``, ``--scheduler`` and ``--quiet`` to ``kin plan``."""
    add = parser.add_argument
    add("--stdin", action="store_true", help="read JSON plan requests from stdin, one per line")
    add(
        "--workers",
        type=positive_int,
        help="with --stdin: plan on a local Dask cluster of N processes",
    )
    add(
        "--scheduler",
        metavar="ADDRESS",
        help="with --stdin: plan on the Dask scheduler at ADDRESS (tcp://host:8786)",
    )
    add("--quiet", action="store_true", help="with --stdin: no progress bar on stderr")


def check_stream_options(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Exit 2 with one line for options that do not go with (or without) ``--stdin``."""
    if not args.stdin:
        given = [f"--{name}" for name in ("workers", "scheduler") if getattr(args, name)]
        if given:
            parser.error(f"{', '.join(given)} plan many requests: give --stdin")
        return
    per_line = {
        "--goal": args.goal,
        "--target": args.target,
        "--rpy": args.rpy,
        "--quat": args.quat,
        "--mask": args.mask,
        "--axis": args.axis,
        "-o": args.output,
    }
    given = [name for name, value in per_line.items() if value is not None]
    if given:
        parser.error(f"--stdin reads each goal from its line: drop {', '.join(given)}")
    if args.workers is not None and args.scheduler is not None:
        parser.error("give --workers N (a local cluster) or --scheduler ADDRESS, not both")


def run_stream(args: argparse.Namespace, prog: str) -> int:
    """Answer every line of stdin on stdout (see the module docstring).

    Returns:
        1 when a line had an error or no path, else 0.
    """
    from .plan_lines import PlanLines, StreamSetup
    from .progress import ProgressBar

    setup = StreamSetup.of(args)
    here = PlanLines(setup)  # bad options fail here, once, before any line is read
    quiet = args.quiet or _is_terminal(sys.stdin)
    total = _lines_in_file(sys.stdin)
    with ProgressBar(prog, "plans", quiet=quiet) as bar:
        progress = _Progress(bar, total)
        if args.workers is None and args.scheduler is None:
            return _run_here(here, sys.stdin, sys.stdout, progress)
        from ..reach.cluster import reach_client

        scheduler = args.scheduler or f"local-cluster:{args.workers}"
        with reach_client(scheduler) as client:
            return _run_on_dask(setup, client, sys.stdin, sys.stdout, progress)


class _Progress:
    """The bar's count: plans answered of the lines read (or of the file's lines)."""

    def __init__(self, bar: Callable[[int, int], None], total: int | None):
        self.bar = bar
        self.total = total
        self.read = 0
        self.done = 0

    def lines_read(self, count: int) -> None:
        self.read += count
        self.bar(self.done, max(self.read, self.total or 0))

    def answered(self, count: int) -> None:
        self.done += count
        self.bar(self.done, max(self.read, self.total or 0))


def _run_here(lines: Any, source: TextIO, out: TextIO, progress: _Progress) -> int:
    """Plan each line in this process; each answer written and flushed before the next plan."""
    from .interrupt_gate import interrupt_gate
    from .json_output import dumps
    from .stream_reader import line_batches

    number = 0
    failed = False
    with interrupt_gate() as gate:
        for batch in line_batches(source):
            progress.lines_read(len(batch))
            for line in batch:
                number += 1
                record, bad = lines.answer(number, line)
                failed |= bad
                gate.hold()  # a Ctrl-C during the write: after it, the line whole
                out.write(dumps(record) + "\n")
                out.flush()
                gate.release()
                progress.answered(1)
                if getattr(out, "broken", False):  # the reader is gone (| head): stop
                    return 1 if failed else 0
    return 1 if failed else 0


def _run_on_dask(setup: Any, client: Any, source: TextIO, out: TextIO, progress: _Progress) -> int:
    """Plan the lines on ``client``'s cluster; the answers written in input order.

    Raises:
        RunFaultError: The scheduler went away, or a task killed every worker it ran on.
    """
    from dh2urdf.stop_signals import raise_lost_stop

    from ..workspace.run import dask_faults
    from .interrupt_gate import interrupt_gate
    from .plan_lines import answer_lines
    from .stream_reader import input_waiting, line_batches

    threads = max(sum(client.nthreads().values()), 1)
    window: deque[Any] = deque()  # the tasks in input order
    writer = _Writer(out, progress)
    number = 0
    with interrupt_gate() as gate, dask_faults(client, window):
        try:
            for batch in line_batches(source):
                progress.lines_read(len(batch))
                for start in range(0, len(batch), TASK_LINES):
                    run = [_encoded(line) for line in batch[start : start + TASK_LINES]]
                    while len(window) >= IN_FLIGHT_PER_THREAD * threads:
                        writer.write_head(window, gate)
                        raise_lost_stop()
                    task = client.submit(answer_lines, setup, number + 1, run, pure=False)
                    window.append(task)
                    number += len(run)
                    writer.write_done(window, gate)
                if not input_waiting(source):  # a client waits for its answers: all of them
                    writer.write_all(window, gate)
                if writer.broken:
                    break
            writer.write_all(window, gate)
        except KeyboardInterrupt:
            gate.hold()  # the finished answers that follow the written ones, then stop
            writer.write_done(window, None)
            raise
    return 1 if writer.failed else 0


class _Writer:
    """Writes the answers of Dask tasks in input order."""

    def __init__(self, out: TextIO, progress: _Progress):
        self.out = out
        self.progress = progress
        self.failed = False

    @property
    def broken(self) -> bool:
        """The reader of the output is gone."""
        return bool(getattr(self.out, "broken", False))

    def write_head(self, window: deque[Any], gate: Any) -> None:
        """Wait for the first task of ``window``, write its answers and drop it.

        Dropped only once written: a Ctrl-C while waiting leaves it in ``window``.
        """
        answers = window[0].result()
        if gate is not None:
            gate.hold()  # from here on a Ctrl-C waits until the answers are written
        window.popleft()
        self.write(answers, gate)

    def write(self, answers: Iterable[tuple[str, bool]], gate: Any) -> None:
        """Write one task's answers whole (a Ctrl-C meanwhile raised after them)."""
        if gate is not None:
            gate.hold()
        count = 0
        for text, failed in answers:
            self.out.write(text)
            self.failed |= failed
            count += 1
        self.out.flush()
        if gate is not None:
            gate.release()
        self.progress.answered(count)

    def write_done(self, window: deque[Any], gate: Any) -> None:
        """Write the answers of the finished tasks at the head of ``window``."""
        while window and window[0].done():
            self.write_head(window, gate)

    def write_all(self, window: deque[Any], gate: Any) -> None:
        """Wait for every task in ``window`` and write its answers, in order."""
        from dh2urdf.stop_signals import raise_lost_stop

        while window:
            self.write_head(window, gate)
            raise_lost_stop()


def _encoded(line: str | bytes) -> bytes:
    """An input line as bytes (a task's argument)."""
    return line if isinstance(line, bytes) else line.encode()


def _is_terminal(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, OSError, ValueError):
        return False


def _lines_in_file(source: Any) -> int | None:
    """The lines left in ``source`` when it is a regular file (for the bar), else None."""
    try:
        fd = source.fileno()
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        offset = os.lseek(fd, 0, os.SEEK_CUR)
        size = os.fstat(fd).st_size
    except (AttributeError, OSError, ValueError):
        return None
    count, position, last = 0, offset, b"\n"
    while position < size:
        block = os.pread(fd, 1 << 20, position)
        if not block:
            break
        count += block.count(b"\n")
        position += len(block)
        last = block[-1:]
    return count + (last != b"\n")
