"""``kin ik --stdin``: one JSON target per input line, one JSON answer per output line.

Start-up (imports, model, solver, seed table) is paid once; then each line costs one solve. An
input line is an object: ``"target": [x, y, z]`` [--unit], optionally one of ``"rpy"``,
``"quat"``, ``"pitch"`` (with ``"roll"``) [rad, or deg with --deg], ``"position_only"``,
``"seed_q"`` (revolute [rad or deg], prismatic [--unit], or the name of a named state such as
``"ready"``: :mod:`kin.named_states`; default: the command's --seed-q) and
``"all": true`` (the answer of --all for this line: every branch of a 7R arm, the rejected kept).

An answer is :meth:`kin.ik.IKResult.to_dict` (SI: q in rad / m, errors in m and rad, time in s)
with ``"line"`` (the 1-based input line number) and ``"q_units"``; ``"rejected"`` (solutions
outside the limits, or colliding with --scene/--srdf) is filled only with --all, ``"all": true``
or when there is no valid solution (then it holds the best attempt); ``"counts"`` says how many
answers of each kind there are and how many rejected ones are listed, whatever is listed
(:mod:`.ik_counts`). A bad line gives ``{"line": n, "error": "..."}`` and the run goes on; so does
a line whose solve fails in a way nobody foresaw (``"error": "internal error: ..."``, logged with
its traceback at debug level). A blank line gives ``{"line": n, "skipped": "blank line"}``. A unit slip of a line (an angle
beyond a turn without --deg) is listed in its answer's ``"warnings"``, not on stderr.
Exactly one output line per input line, in order; nothing else is written on stdout. The exit
code is 1 when any line had an error or no valid solution, else 0.

Answers are flushed before the command waits for more input, and at least every
:data:`FLUSH_EVERY` answers: a client that writes one line and waits gets its answer at once,
while a producer that queues thousands of lines does not pay one write per line. Ctrl-C writes
the answers of the lines solved so far (whole lines, in order: the answer of a prefix of the
input) and stops with ``KeyboardInterrupt`` (exit 130); one during a write waits for its end.

The parts: :mod:`.stream_reader` (batches of lines, each line's request), :mod:`.stream_batch`
(the compiled route: the lines of a batch answered together), :mod:`.stream_records` (the
records and their writing); this module runs them in turn and holds the compiled twins of the
plainest lines' reading and writing (``kin/_native/commands/_plain_lines.c``, if built).
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TextIO

import numpy as np

from kin._native import twin

from ..ik.result import IKResult
from ..ik.targets.target import PoseTarget, PositionTarget, Target
from .interrupt_gate import InterruptGate, interrupt_gate
from .joint_units import JointUnits
from .json_output import dumps
from .stream_batch import BatchRoute, BatchStage
from .stream_batch import rpy_matrices as rpy_matrices
from .stream_reader import CHUNK, KEYS, READ, LineReader, plain_groups
from .stream_reader import input_waiting as _input_waiting
from .stream_reader import line_batches as _line_batches
from .stream_records import FLUSH_EVERY as FLUSH_EVERY
from .stream_records import error_record, numbered, write_records
from .stream_records import result_record as result_record

if TYPE_CHECKING:
    from ..named_states import NamedStates

__all__ = ["FLUSH_EVERY", "KEYS", "StreamSolver", "line_batches", "result_record", "rpy_matrices"]

#: Bytes per read of the input, and most bytes per batch [B] (:func:`line_batches`).
_READ = READ
_CHUNK = CHUNK
_twin = twin(
    "_plain_lines"
)  # the plainest lines read and answered in C (kin/_native/commands/_plain_lines.c)
if _twin is not None:
    _read_plain, _write_plain = _twin.read, _twin.write
else:  # pragma: no cover - the json module reads them all, %-format writes
    _read_plain = _write_plain = None


def line_batches(source: TextIO | Iterable[str]) -> Iterator[Sequence[str | bytes]]:
    """The input lines in batches of those already there (:func:`.stream_reader.line_batches`).

    Reads of :data:`_READ` bytes, batches of up to :data:`_CHUNK` bytes.
    """
    return _line_batches(source, _READ, _CHUNK)


@dataclass(frozen=True)
class StreamSolver:
    """Answers JSON target lines for one robot and solver.

    Attributes:
        robot: Robot name.
        nq: Number of joints.
        units: Its joint units on the command line.
        solve: ``solve(target, seed)`` of the chosen solver, time budget bound.
        kinds: Target classes the solver accepts (None: the solver checks).
        seed: Default seed [rad] / [m], or None.
        length: Meters per ``--unit``.
        angle: Radians per input angle unit.
        all_solutions: Answers keep the rejected solutions (``--all``).
        batch: ``batch(points (N, 3), rotations (N, 3, 3) or None, seeds (N, nq))``, which
            starts answering the lines of a read batch together where the solver's first stage
            can and returns what finishes it: ``() -> (q, position errors, rotation errors)``
            (:func:`kin.ik.batch_solve.start_free_joint_answers`, NaN rows where it gives none:
            those lines are solved one by one), or None.
        pipeline: The solver's name, as the answers of ``batch`` report it.
        solve_all: ``solve(target, seed)`` asking for every branch (a line's ``"all": true``),
            or None (the solver has no such option: ``solve``, the rejected kept).
        states: The robot's named states, for a line's ``"seed_q": "ready"``, or None.
    """

    robot: str
    nq: int
    units: JointUnits
    solve: Callable[[Target, np.ndarray | None], IKResult]
    kinds: tuple[type, ...] | None
    seed: np.ndarray | None
    length: float
    angle: float
    all_solutions: bool = False
    batch: BatchStage | None = None
    pipeline: str = "numeric"
    solve_all: Callable[[Target, np.ndarray | None], IKResult] | None = None
    states: NamedStates | None = None

    def answer(self, line: str | bytes) -> dict[str, Any]:
        """The answer to one input line.

        Raises:
            KinError, ValueError: A bad line (not JSON, unknown key, bad values, wrong kind).
        """
        target, seed, every = self.request(line)
        solve = self._solver(every)
        return result_record(solve(target, seed), target, self.all_solutions or every)

    def _solver(self, every: bool) -> Callable[[Target, np.ndarray | None], IKResult]:
        """The solve of a line: with every branch when it asks (``"all": true``) and can."""
        return self.solve_all if every and self.solve_all is not None else self.solve

    def request(self, line: str | bytes) -> tuple[Target, np.ndarray | None, bool]:
        """The target, seed [rad, m] and ``"all"`` (every branch asked) of one input line.

        Raises:
            KinError, ValueError: A bad line (not JSON, unknown key, bad values, wrong kind).
        """
        return self._reader.request(line)

    @functools.cached_property
    def _reader(self) -> LineReader:
        """The line-by-line reader (:class:`.stream_reader.LineReader`)."""
        units, kinds, seed = self.units, self.kinds, self.seed
        length, angle, states = self.length, self.angle, self.states
        return LineReader(self.robot, self.nq, units, kinds, seed, length, angle, states)

    @functools.cached_property
    def _route(self) -> BatchRoute | None:
        """The compiled route (:class:`.stream_batch.BatchRoute`), or None (no batch stage)."""
        if self.batch is None:
            return None
        units, seed, pipeline = self.units, self.seed, self.pipeline
        return BatchRoute(self.batch, self.nq, seed, self.length, self.angle, units, pipeline)

    def run(self, source: TextIO | Iterable[str], out: TextIO) -> int:
        """Answer every line of ``source`` on ``out``, one JSON line each.

        Every answer is flushed before the stream waits for more input (see
        :func:`line_batches`): a client that writes a line and waits gets its answer. When more
        input is already there, the next batch is read first and its batch stage started (its
        compiled scans run in threads while this batch's answers are made and written).

        Returns:
            1 when any line had an error or no valid solution, else 0.
        """
        q_units = list(self.units.si_labels)
        batches = line_batches(source)
        number = 0  # lines read so far
        failed = False
        started: _Started | None = None
        with interrupt_gate() as gate:
            while True:
                if started is None:  # wait for input
                    lines = next(batches, None)
                    if lines is None:
                        break
                    started = self._start(lines, number)
                    number += len(lines)
                ahead = None
                if _input_waiting(source):  # read it now: its scans run while these are answered
                    lines = next(batches, None)
                    if lines is not None:
                        ahead = self._start(lines, number)
                        number += len(lines)
                try:
                    records = self._records(started, gate)
                except _Interrupted as stop:  # Ctrl-C: the answers made so far, whole, then 130
                    write_records(stop.records, out, dumps, q_units)
                    raise
                failed |= write_records(records, out, dumps, q_units)
                gate.release()  # a Ctrl-C during the write stops the stream now
                if getattr(out, "broken", False):  # the reader is gone (| head): stop reading
                    break
                started = ahead
        return 1 if failed else 0

    def _start(self, lines: Sequence[str | bytes], before: int) -> _Started:
        """A batch of input lines (the first is line ``before + 1``) with its batch stage started.

        The plainest lines (:func:`.stream_reader.plain_groups`: by the compiled reader
        :data:`_read_plain` where it takes them, else by the json module's scanner) are read
        and their compiled scans started (:meth:`.stream_batch.BatchRoute.start`), group by
        group; the answers are made by :meth:`_records`. The lines the batch reads and leaves
        are added to ``tried`` with their targets (the line-by-line path solves them without
        reading them again).
        """
        tried: dict[int, Target] = {}
        finish: list[Callable[[], dict[int, str]]] = []
        route = self._route
        if route is not None and not self.all_solutions:
            write = _write_plain
            for indices, targets, rpys in plain_groups(lines, _read_plain):
                finish.append(route.start(indices, targets, rpys, before, tried, write))
        return _Started(lines, before, tried, finish)

    def _records(self, started: _Started, gate: InterruptGate) -> list[dict[str, Any] | str]:
        """The answers of a batch of input lines (:meth:`_start`), in order; ``gate`` held after.

        Lines the batch stage takes (:attr:`batch`: full poses or positions, without --all) are
        solved together (those of the plainest form, ``{"target": [...], "rpy": [...]}`` or a
        target alone, read together too: :meth:`_start`); the others, and those it leaves
        unanswered, one by one.

        Raises:
            _Interrupted: Ctrl-C while solving, with the answers of the lines before the first
                one not solved (``gate`` held).
        """
        lines, before = started.lines, started.before
        records: list[dict[str, Any] | str | None] = [None] * len(lines)
        notes: list[list[str]] = [[] for _ in lines]
        try:
            self._solve_batch(started, records, notes)
            gate.hold()  # answered: a Ctrl-C from now on waits until they are written
        except KeyboardInterrupt:
            gate.hold()
            solved = records.index(None) if None in records else len(records)
            raise _Interrupted(numbered(records[:solved], notes, before)) from None
        return numbered(records, notes, before)

    def _solve_batch(
        self,
        started: _Started,
        records: list[dict[str, Any] | str | None],
        notes: list[list[str]],
    ) -> None:
        """Fill ``records`` and ``notes`` (each line's answer and warnings, by line index).

        In line order, but for the lines the batch stage solves together at the end.
        """
        lines, before = started.lines, started.before
        # Lines the batch stage read and left, with their targets: one by one at once (not read
        # again: the same target as request() makes of them, no warning, the default seed).
        tried = started.tried
        for finish in started.finish:
            for index, encoded in finish().items():
                records[index] = encoded
        together: list[tuple[int, Target, np.ndarray | None]] = []
        request = self._reader.request
        for index, line in enumerate(lines):
            if records[index] is not None:
                continue
            number = before + index + 1
            known = tried.get(index)
            if known is not None:
                records[index] = self._solved(number, known, self.seed)
                continue
            if not line or line.isspace():
                records[index] = {"skipped": "blank line"}
                continue
            try:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    target, seed, every = request(line)
                notes[index] = [" ".join(str(w.message).split()) for w in caught]
            except Exception as err:  # noqa: BLE001 - one line fails, never the stream
                records[index] = error_record(number, err)
                continue
            if self._batched(target) and not every:
                together.append((index, target, seed))
            else:
                records[index] = self._solved(number, target, seed, every)
        if together:
            route = self._route
            assert route is not None
            for index, solved in route.solve_together(together, before, self._solved).items():
                records[index] = solved

    def _batched(self, target: Target) -> bool:
        """Whether ``target`` goes to the batch stage."""
        if self.batch is None or self.all_solutions:
            return False
        cls = target.__class__
        return cls is PositionTarget or (cls is PoseTarget and target.mask is None)  # type: ignore[union-attr]

    def _solved(
        self, number: int, target: Target, seed: np.ndarray | None, every: bool = False
    ) -> dict[str, Any]:
        """The answer of one target by the solver (an error record if it raises).

        ``every``: the line asks for every branch (``"all": true``).
        """
        try:
            solve = self._solver(every)
            return result_record(solve(target, seed), target, self.all_solutions or every)
        except Exception as err:  # noqa: BLE001 - one line fails, never the stream
            return error_record(number, err)


class _Interrupted(KeyboardInterrupt):
    """Ctrl-C while a batch was solved: the answers of its lines before the first unsolved."""

    def __init__(self, records: list[dict[str, Any] | str]) -> None:
        super().__init__()
        self.records = records


@dataclass(frozen=True)
class _Started:
    """A batch of input lines (the first is line ``before + 1``), its batch stage started.

    ``tried``: the lines it read and left, with their targets (filled as ``finish`` runs);
    ``finish``: what gives the encoded answers of the others (:meth:`StreamSolver._start`).
    """

    lines: Sequence[str | bytes]
    before: int
    tried: dict[int, Target]
    finish: list[Callable[[], dict[int, str]]]
