"""``kin ik --stdin``: one JSON target per input line, one JSON answer per output line.

Start-up (imports, model, solver, seed table) is paid once; then each line costs one solve. An
input line is an object: ``"target": [x, y, z]`` [--unit], optionally one of ``"rpy"``,
``"quat"``, ``"pitch"`` (with ``"roll"``) [rad, or deg with --deg], ``"position_only"``,
``"seed_q"`` (revolute [rad or deg], prismatic [--unit]; default: the command's --seed-q) and
``"all": true`` (the answer of --all for this line: every branch of a 7R arm, the rejected kept).

An answer is :meth:`kin.ik.IKResult.to_dict` (SI: q in rad / m, errors in m and rad, time in s)
with ``"line"`` (the 1-based input line number) and ``"q_units"``; ``"rejected"`` (solutions
outside the limits) is filled only with --all or when there is no valid solution (then it holds
the best attempt). A bad line gives ``{"line": n, "error": "..."}`` and the run goes on; so does
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
"""

from __future__ import annotations

import json
import logging
import os
import select
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any, TextIO

import numpy as np

from dh2urdf.quoted_input import quoted

from ..exceptions import KinError
from ..ik.batch_solve import FREE_JOINT_STAGE
from ..ik.numeric.free_joint import FROM_SEED
from ..ik.result import IKResult
from ..ik.target import PoseTarget, PositionTarget, Target
from .interrupt_gate import InterruptGate, interrupt_gate
from .joint_units import JointUnits
from .targets import build_target, check_kind

logger = logging.getLogger(__name__)

#: Most answers written between two flushes while input lines are already there.
FLUSH_EVERY = 32
#: Bytes per read of the input [B] (a pipe holds 64 KiB).
_READ = 1 << 16
#: Most bytes read into one batch while more input is already there [B]: each batch has costs
#: of its own (arrays, thread hand-offs), so batches of a few thousand lines run faster.
_CHUNK = 1 << 20

#: Keys an input line may have.
KEYS = (
    "target",
    "rpy",
    "quat",
    "mask",
    "axis",
    "tool_axis",
    "pitch",
    "roll",
    "position_only",
    "seed_q",
    "all",
)
_KEYS = frozenset(KEYS)
try:  # the plainest lines read and answered in C (kin/commands/_plain_lines.c), if built
    from ._plain_lines import read as _read_plain
    from ._plain_lines import write as _write_plain
except ImportError:  # pragma: no cover - the json module reads them all, %-format writes
    _read_plain = _write_plain = None
_decoder = json.JSONDecoder()
_decode = _decoder.decode
#: The decoder's scanner: ``(value, end)`` of the JSON value at an index of a string.
_scan = _decoder.scan_once  # type: ignore[attr-defined]  # set by JSONDecoder.__init__


def result_record(result: IKResult, target: Target, rejected: bool = True) -> dict[str, Any]:
    """``result.to_dict()`` (SI), rotation errors null when ``target`` leaves the rotation free.

    Args:
        result: The result.
        target: Its target.
        rejected: Keep the rejected solutions even when there are valid ones.
    """
    record = result.to_dict(rejected)
    if isinstance(target, PositionTarget):
        for key in ("solutions", "rejected"):
            for solution in record[key]:
                solution["rotation_error_rad"] = None
    return record


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
    batch: Callable[..., Callable[[], tuple[np.ndarray, np.ndarray, np.ndarray]]] | None = None
    pipeline: str = "numeric"
    solve_all: Callable[[Target, np.ndarray | None], IKResult] | None = None

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
        try:
            text = line.decode() if isinstance(line, bytes) else line
            request = _decode(text)
        except (ValueError, RecursionError) as err:  # RecursionError: nested too deep
            raise ValueError(f"not JSON: {err}") from None
        if not isinstance(request, dict):
            raise ValueError(f"a line must be a JSON object, got {type(request).__name__}")
        if not request.keys() <= _KEYS:
            unknown = sorted(request.keys() - _KEYS)
            raise ValueError(f"unknown key(s) {quoted(unknown)}; known: {', '.join(KEYS)}")
        if "target" not in request:
            raise ValueError('missing "target": [x, y, z]')
        position_only = request.get("position_only", False)
        if position_only is not True and position_only is not False:
            raise ValueError(f'"position_only" must be true or false, got {quoted(position_only)}')
        every = request.get("all", False)
        if every is not True and every is not False:
            raise ValueError(f'"all" must be true or false, got {quoted(every)}')
        target, given = build_target(
            request["target"],
            rpy=request.get("rpy"),
            quat=request.get("quat"),
            pitch=request.get("pitch"),
            roll=request.get("roll"),
            position_only=position_only,
            length=self.length,
            angle=self.angle,
            mask=request.get("mask"),
            axis=request.get("axis"),
            tool_axis=request.get("tool_axis"),
        )
        if self.kinds is not None:
            check_kind(self.robot, self.nq, self.kinds, target, given)
        seed = self.seed
        seed_q = request.get("seed_q")
        if seed_q is not None:
            if not isinstance(seed_q, list):
                raise ValueError(f'"seed_q" must be a list of numbers, got {quoted(seed_q)}')
            seed = self.units.to_si(seed_q, '"seed_q"')
        return target, seed, every

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
        # the records are fresh trees of dicts and lists: no need to look for cycles
        dumps = json.JSONEncoder(check_circular=False).encode
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
                    _write_records(stop.records, out, dumps, q_units)
                    raise
                failed |= _write_records(records, out, dumps, q_units)
                gate.release()  # a Ctrl-C during the write stops the stream now
                if getattr(out, "broken", False):  # the reader is gone (| head): stop reading
                    break
                started = ahead
        return 1 if failed else 0

    def _start(self, lines: Sequence[str | bytes], before: int) -> _Started:
        """A batch of input lines (the first is line ``before + 1``) with its batch stage started.

        The plainest lines (:meth:`_plain`) are read and their compiled scans started; the
        answers are made by :meth:`_records`.
        """
        tried: dict[int, Target] = {}
        finish: list[Callable[[], dict[int, str]]] = []
        if self.batch is not None and not self.all_solutions:
            finish = self._plain(lines, before, tried)
        return _Started(lines, before, tried, finish)

    def _records(self, started: _Started, gate: InterruptGate) -> list[dict[str, Any] | str]:
        """The answers of a batch of input lines (:meth:`_start`), in order; ``gate`` held after.

        Lines the batch stage takes (:attr:`batch`: full poses or positions, without --all) are
        solved together (those of the plainest form, ``{"target": [...], "rpy": [...]}`` or a
        target alone, read together too: :meth:`_plain`); the others, and those it leaves
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
            raise _Interrupted(_numbered(records[:solved], notes, before)) from None
        return _numbered(records, notes, before)

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
                    target, seed, every = self.request(line)
                notes[index] = [" ".join(str(w.message).split()) for w in caught]
            except Exception as err:  # noqa: BLE001 - one line fails, never the stream
                records[index] = _error_record(number, err)
                continue
            if self._batched(target) and not every:
                together.append((index, target, seed))
            else:
                records[index] = self._solved(number, target, seed, every)
        if together:
            for index, solved in self._solved_together(together, before).items():
                records[index] = solved

    def _plain(
        self, lines: Sequence[str | bytes], before: int, tried: dict[int, Target]
    ) -> list[Callable[[], dict[int, str]]]:
        """The plainest lines, read and their batch stage started: what gives their answers.

        Each callable returned gives the encoded answers of one group of lines, by line index.

        A line ``{"target": [x, y, z]}`` or ``{"target": [x, y, z], "rpy": [r, p, y]}`` of finite
        numbers (no ``true``/``false`` anywhere, no angle beyond a turn without --deg: those
        take the checks of :meth:`request`) is read with the others into arrays (one check for
        all) and answered by :attr:`batch`; what it answers is encoded here (the record of
        :func:`result_record`, the same keys in the same order). Every other line is left to
        the line-by-line path; those the batch read and did not answer are added to ``tried``
        (when the callable runs) with their targets (they go to the solver one by one, not to
        the batch again, and are not read again: the targets :meth:`request` would make, the
        same float64 values).

        The lines spelled as ``json.dumps`` writes those two forms are read by the compiled
        twin (:data:`_read_plain`, ``kin/commands/_plain_lines.c``: the same values as the json
        module's, about 4 us a line less); the others, and all without the twin, by
        :func:`_decoded`.
        """
        answers: list[Callable[[], dict[int, str]]] = []
        rest: Sequence[int] = range(len(lines))  # the lines for the json module, by index
        if _read_plain is not None:
            kinds, values = _read_plain(lines)
            kind = np.frombuffer(kinds, dtype=np.uint8)
            read = np.frombuffer(values).reshape(-1, 6)
            for code, poses in ((2, True), (1, False)):
                rows = np.flatnonzero(kind == code)
                if rows.size:
                    rpys = read[rows, 3:] if poses else None
                    answers.append(
                        self._plain_group(rows.tolist(), read[rows, :3], rpys, before, tried)
                    )
            rest = np.flatnonzero(kind == 0).tolist()
            if not rest:
                return answers
        groups: dict[bool, list[tuple[int, Any, Any]]] = {True: [], False: []}
        for position, request in _decoded([lines[i] for i in rest]):
            if request.__class__ is not dict:
                continue
            index = rest[position]
            size = len(request)
            if size == 1 and "target" in request:
                groups[False].append((index, request["target"], None))
            elif size == 2 and "target" in request and "rpy" in request:
                groups[True].append((index, request["target"], request["rpy"]))
        for poses, group in groups.items():
            if group:
                indices = [item[0] for item in group]
                points = [item[1] for item in group]
                angles = [item[2] for item in group] if poses else None
                answers.append(self._plain_group(indices, points, angles, before, tried))
        return answers

    def _plain_group(
        self,
        indices: list[int],
        targets: Any,
        rpys: Any,
        before: int,
        tried: dict[int, Target],
    ) -> Callable[[], dict[int, str]]:
        """:meth:`_plain` of the lines of one kind: their indices, targets and rpy (or None).

        ``targets`` and ``rpys`` as read (arrays, or the lists the json module gave), in the
        user's units. The batch stage is started here; the callable returned makes the answers
        (:meth:`_plain_answers`).
        """
        from dh2urdf.table_file import RADIAN_SUSPECT

        poses = rpys is not None
        try:
            with np.errstate(all="ignore"):
                given = np.array(targets, dtype=float)  # in --unit
                points = given * self.length
                angles = np.array(rpys, dtype=float) if poses else None
        except (TypeError, ValueError, OverflowError):
            return _no_answers
        if points.shape != (len(indices), 3) or (
            angles is not None and angles.shape != (len(indices), 3)
        ):
            return _no_answers
        keep = np.isfinite(points).all(axis=1)
        rotations = None
        if angles is not None:
            keep &= np.isfinite(angles).all(axis=1)
            if self.angle == 1.0:
                keep &= (np.abs(angles) <= RADIAN_SUSPECT).all(axis=1)
            # Reduced modulo a turn in the given unit first (angle_to_radians, vectorized).
            turns = np.fmod(np.where(keep[:, None], angles, 0.0), 2.0 * np.pi / self.angle)
            rotations = rpy_matrices(turns * self.angle)
        rows = np.flatnonzero(keep)
        if not rows.size:
            return _no_answers
        start = time.perf_counter()
        default = np.zeros(self.nq) if self.seed is None else self.seed
        seeds = np.broadcast_to(default, (rows.size, self.nq))
        assert self.batch is not None
        try:
            result = self.batch(points[rows], None if rotations is None else rotations[rows], seeds)
        except Exception:  # noqa: BLE001 - the lines go the line-by-line way instead
            logger.debug("batch stage failed", exc_info=True)
            return _no_answers
        launch = time.perf_counter() - start
        return partial(
            self._plain_answers, indices, given, angles, rows, result, launch, before, tried
        )

    def _plain_answers(
        self,
        indices: list[int],
        given: np.ndarray,
        angles: np.ndarray | None,
        rows: np.ndarray,
        result: Callable[[], tuple[np.ndarray, np.ndarray, np.ndarray]],
        launch: float,
        before: int,
        tried: dict[int, Target],
    ) -> dict[int, str]:
        """The encoded answers of :meth:`_plain_group`'s lines, by line index.

        ``given``, ``angles``: their targets and rpy as read (in --unit, and radians or degrees);
        ``rows`` of them went to the batch stage: ``result`` gives its answer; ``launch`` [s]
        it took to start. ``time_s`` of an answer: the time spent starting and finishing the
        batch stage, per line (not the time other lines took in between).
        """
        start = time.perf_counter()
        try:
            q, position_error, rotation_error = result()
        except Exception:  # noqa: BLE001 - the lines go the line-by-line way instead
            logger.debug("batch stage failed", exc_info=True)
            return {}
        poses = angles is not None
        each = repr((launch + time.perf_counter() - start) / rows.size)
        head = (
            f'{{"success": true, "solver": {json.dumps(self.pipeline)}, "status": "ok", '
            f'"message": {json.dumps(FROM_SEED)}, "solutions": [{{"q": ['
        )
        tail = (
            f'"rejected": [], "method": "{FREE_JOINT_STAGE}", "distance_to_workspace_m": null, '
            f'"iterations": 0, "time_s": {each}, "free": [], "line": '
        )
        units = json.dumps(list(self.units.si_labels))
        answers: dict[int, str] = {}
        found = ~np.isnan(q).any(axis=1)
        for row in rows[~found].tolist():  # made as request() makes them, from the same numbers
            rpy = None if angles is None else angles[row].tolist()
            try:
                target, _ = build_target(
                    given[row].tolist(), rpy=rpy, length=self.length, angle=self.angle
                )
            except (KinError, ValueError):  # request() says what is wrong with the line
                continue
            tried[indices[row]] = target
        first = before + 1  # the number of line index 0
        chosen = [indices[row] for row in rows[found].tolist()]
        after = ', "position_error_m": '
        rotation = ', "rotation_error_rad": '
        if _write_plain is not None:  # the compiled writer: the values' texts read back the same
            columns = [q[found], position_error[found, None]]
            if poses:
                columns.append(rotation_error[found, None])
            pieces = (
                head,
                *[", "] * (q.shape[1] - 1),
                '], "branch": "", "within_limits": true' + after,
                *([rotation] if poses else []),
                ("}], " if poses else rotation + "null}], ") + tail,
                ', "q_units": ' + units + "}\n",
            )
            numbers = np.array(chosen, dtype=np.int64) + first
            lines_out = _write_plain(pieces, np.hstack(columns), numbers)
            return dict(zip(chosen, lines_out))
        # A line by one %-format of the values' reprs (the json module's for a finite float),
        # from lists made once (a NumPy scalar per value costs more than the value's repr).
        line_format = "".join(
            (
                head.replace("%", "%%"),
                ", ".join(["%r"] * q.shape[1]),
                '], "branch": "", "within_limits": true' + after + "%r",
                rotation + ("%r}], " if poses else "null}], "),
                tail.replace("%", "%%"),
                '%d, "q_units": ',
                units.replace("%", "%%"),
                "}\n",
            )
        )
        values = q[found].tolist()
        if poses:
            solved = zip(
                chosen, values, position_error[found].tolist(), rotation_error[found].tolist()
            )
            for index, row, position, rotation_value in solved:
                answers[index] = line_format % (*row, position, rotation_value, first + index)
        else:
            for index, row, position in zip(chosen, values, position_error[found].tolist()):
                answers[index] = line_format % (*row, position, first + index)
        return answers

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
            return _error_record(number, err)

    def _solved_together(
        self, items: list[tuple[int, Target, np.ndarray | None]], before: int
    ) -> dict[int, dict[str, Any]]:
        """The answers of the batch stage's lines (poses and positions apart), by line index."""
        records: dict[int, dict[str, Any]] = {}
        assert self.batch is not None
        for poses in (True, False):
            group = [item for item in items if (item[1].__class__ is PoseTarget) == poses]
            if not group:
                continue
            start = time.perf_counter()
            points = np.array([target.position for _, target, _ in group])
            rotations = (
                np.array([target.rotation for _, target, _ in group])  # type: ignore[union-attr]
                if poses
                else None
            )
            default = np.zeros(self.nq) if self.seed is None else self.seed
            seeds = np.array([default if seed is None else seed for _, _, seed in group])
            try:
                q, position_error, rotation_error = self.batch(points, rotations, seeds)()
            except Exception:  # noqa: BLE001 - the lines go one by one instead
                logger.debug("batch stage failed", exc_info=True)
                q = np.full((len(group), self.nq), np.nan)
            each = (time.perf_counter() - start) / len(group)
            found = ~np.isnan(q).any(axis=1)
            for k, (index, target, seed) in enumerate(group):
                if not found[k]:
                    records[index] = self._solved(before + index + 1, target, seed)
                    continue
                solution = {
                    "q": q[k].tolist(),
                    "branch": "",
                    "within_limits": True,
                    "position_error_m": float(position_error[k]),
                    "rotation_error_rad": float(rotation_error[k]) if poses else None,
                }
                records[index] = {
                    "success": True,
                    "solver": self.pipeline,
                    "status": "ok",
                    "message": FROM_SEED,
                    "solutions": [solution],
                    "rejected": [],
                    "method": FREE_JOINT_STAGE,
                    "distance_to_workspace_m": None,
                    "iterations": 0,
                    "time_s": each,
                    "free": [],
                }
        return records


def _numbered(
    records: Sequence[dict[str, Any] | str | None], notes: list[list[str]], before: int
) -> list[dict[str, Any] | str]:
    """The answers of a batch's first lines with their line numbers and warnings.

    Args:
        records: Each line's answer (solved: none is None), encoded or a record.
        notes: Each line's warnings.
        before: The lines read before the batch.
    """
    out: list[dict[str, Any] | str] = []
    for index, answer in enumerate(records):
        assert answer is not None
        if isinstance(answer, str):
            out.append(answer)
            continue
        record = answer
        number = before + index + 1
        if "error" in record or "skipped" in record:
            out.append({"line": number, **record})
            continue
        if notes[index]:
            record["warnings"] = notes[index]
        record["line"] = number
        out.append(record)
    return out


def _write_records(
    records: list[dict[str, Any] | str],
    out: TextIO,
    dumps: Callable[[Any], str],
    q_units: list[str],
) -> bool:
    """Write answers on ``out``, :data:`FLUSH_EVERY` lines per write, and flush.

    Returns:
        Whether any line had an error or no valid solution.
    """
    write, flush = out.write, out.flush
    failed = False
    pending: list[str] = []  # written FLUSH_EVERY answers at a time, in one write
    for count, record in enumerate(records, start=1):
        if record.__class__ is str:  # a verified answer of the batch stage, encoded
            pending.append(record)  # type: ignore[arg-type]
        else:
            assert isinstance(record, dict)
            if "error" in record or ("success" in record and not record["success"]):
                failed = True
            if "success" in record:
                record["q_units"] = q_units
            pending.append(dumps(record) + "\n")
        if count % FLUSH_EVERY == 0:
            write("".join(pending))
            pending.clear()
            flush()
    write("".join(pending))
    flush()
    return failed


class _Interrupted(KeyboardInterrupt):
    """Ctrl-C while a batch was solved: the answers of its lines before the first unsolved."""

    def __init__(self, records: list[dict[str, Any] | str]) -> None:
        super().__init__()
        self.records = records


def _no_answers() -> dict[int, str]:
    """The answers of a group of plain lines the batch stage did not take: none."""
    return {}


@dataclass(frozen=True)
class _Started:
    """A batch of input lines (the first is line ``before + 1``), its batch stage started.

    ``tried``: the lines it read and left, with their targets (filled as ``finish`` runs);
    ``finish``: what gives the encoded answers of the others (:meth:`StreamSolver._plain`).
    """

    lines: Sequence[str | bytes]
    before: int
    tried: dict[int, Target]
    finish: list[Callable[[], dict[int, str]]]


def _input_waiting(source: object) -> bool:
    """Whether ``source`` (a file descriptor's stream) has input to read now, without waiting.

    False for a source without a descriptor, or where ``select`` does not take it (Windows
    pipes): the stream then never reads ahead.
    """
    try:
        fd = source.fileno()  # type: ignore[attr-defined]
    except (AttributeError, OSError, ValueError):
        return False
    return _fd_waiting(fd)


def _fd_waiting(fd: int) -> bool:
    """Whether ``fd`` can be read now without waiting; False where ``select`` does not take it."""
    try:
        return bool(select.select([fd], [], [], 0)[0])
    except (OSError, ValueError):
        return False


def _decoded(lines: Sequence[str | bytes]) -> list[tuple[int, Any]]:
    """``(index, value)`` of the lines that are one JSON value without ``true`` or ``false``.

    Each line by the decoder's scanner from its first character (about 1.5 us a line instead
    of 2.1 us through ``decode``), kept when the value ends the line; a line with anything
    else around its value (spaces too) goes through ``decode``; a line that is not one JSON
    value is left out (the line-by-line path says what is wrong with it).
    """
    decoded = []
    for index, line in enumerate(lines):
        if not line:
            continue
        try:
            text = line.decode() if isinstance(line, bytes) else line
        except UnicodeDecodeError:
            continue
        if "true" in text or "false" in text:
            continue
        try:
            value, end = _scan(text, 0)
        except (StopIteration, ValueError):
            end = -1
        if end != len(text):
            try:
                value = _decode(text)
            except ValueError:
                continue
        decoded.append((index, value))
    return decoded


def rpy_matrices(rpy: np.ndarray) -> np.ndarray:
    """URDF roll-pitch-yaw (N, 3) [rad] as rotation matrices ``Rz(yaw) Ry(pitch) Rx(roll)`` (N, 3, 3).

    The batched twin of :func:`kin.ik.target.rpy_matrix`.
    """
    cr, sr = np.cos(rpy[:, 0]), np.sin(rpy[:, 0])
    cp, sp = np.cos(rpy[:, 1]), np.sin(rpy[:, 1])
    cy, sy = np.cos(rpy[:, 2]), np.sin(rpy[:, 2])
    out = np.empty((len(rpy), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 0, 2] = (
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
    )
    out[:, 1, 0], out[:, 1, 1], out[:, 1, 2] = (
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
    )
    out[:, 2, 0], out[:, 2, 1], out[:, 2, 2] = -sp, cp * sr, cp * cr
    return out


def _error_record(number: int, err: Exception) -> dict[str, Any]:
    """The answer of a line that failed: its message, or an internal error's (logged)."""
    text = " ".join(str(err).split())
    if isinstance(err, (KinError, ValueError, TypeError)):
        return {"error": text}
    logger.debug("line %d: unexpected error", number, exc_info=True)
    return {"error": f"internal error: {type(err).__name__}: {text}"}


def line_batches(source: TextIO | Iterable[str]) -> Iterator[Sequence[str | bytes]]:
    """The input lines, in batches of those already there (read without waiting).

    From a file descriptor (pipe, terminal, file): a batch is what one ``os.read`` gives, and
    what further reads give while more input is already there (``select``), up to
    :data:`_CHUNK` bytes; its complete lines (a line typed or written alone is a batch of one).
    From anything else (e.g. ``StringIO``): one line per batch. The caller flushes its answers
    after each batch, so it never sits on an answer while waiting for input, and a fast
    producer does not cost a write per line.
    """
    try:
        fd = source.fileno()  # type: ignore[union-attr]
    except (AttributeError, OSError, ValueError):  # io.UnsupportedOperation is an OSError
        for line in source:
            yield [line]
        return
    pending = b""
    ended = False
    while not ended:
        chunk = os.read(fd, _READ)  # waits for input
        if not chunk:
            break
        parts, size = [pending, chunk], len(pending) + len(chunk)
        while size < _CHUNK and _fd_waiting(fd):
            more = os.read(fd, _READ)
            if not more:
                ended = True
                break
            parts.append(more)
            size += len(more)
        lines = b"".join(parts).split(b"\n")
        pending = lines.pop()
        if lines:
            yield lines
    if pending:
        yield [pending]
