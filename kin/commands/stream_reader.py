"""The reader of ``kin ik --stdin``: input lines in batches, and each line as a request.

Three ways read a line, each giving the same targets (the same float64 values):

- :func:`plain_groups`: the plainest lines of a batch, ``{"target": [x, y, z]}`` and
  ``{"target": [x, y, z], "rpy": [r, p, y]}``, read together for the batch stage: those spelled as
  ``json.dumps`` writes them by the compiled reader (``kin/_native/commands/_plain_lines.c``, handed in
  by the caller), the others by the json module's scanner (:func:`decoded`);
- :meth:`LineReader.request`: any line, with every check and warning (the lines the batch stage
  does not take).

:func:`line_batches` cuts the input into batches of the lines already there, without waiting.
Units: a line's lengths in ``--unit`` and angles in rad (deg with ``--deg``), made SI here.
"""

from __future__ import annotations

import json
import os
import select
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TextIO

import numpy as np

from dh2urdf.quoted_input import quoted

from ..ik.targets.target import Target
from .joint_units import JointUnits
from .targets import build_target, check_kind

if TYPE_CHECKING:
    from ..named_states import NamedStates

#: Bytes per read of the input [B] (a pipe holds 64 KiB).
READ = 1 << 16
#: Most bytes read into one batch while more input is already there [B]: each batch has costs
#: of its own (arrays, thread hand-offs), so batches of a few thousand lines run faster.
CHUNK = 1 << 20

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
_decoder = json.JSONDecoder()
_decode = _decoder.decode
#: The decoder's scanner: ``(value, end)`` of the JSON value at an index of a string.
_scan = _decoder.scan_once  # type: ignore[attr-defined]  # set by JSONDecoder.__init__

#: The compiled reader's signature: the lines' kinds (0: not plain, 1: a position, 2: a pose)
#: as bytes and their six values each (target, rpy) as float64 bytes.
PlainReader = Callable[[Sequence[str | bytes]], tuple[bytes, bytes]]


@dataclass(frozen=True)
class LineReader:
    """Reads one input line into a target, a seed and whether it asks for every branch.

    Attributes:
        robot: Robot name (in error messages).
        nq: Number of joints.
        units: Its joint units on the command line (``"seed_q"``).
        kinds: Target classes the solver accepts (None: the solver checks).
        seed: Default seed [rad] / [m], or None.
        length: Meters per ``--unit``.
        angle: Radians per input angle unit.
        states: The robot's named states (``"seed_q": "ready"``), or None (none).
    """

    robot: str
    nq: int
    units: JointUnits
    kinds: tuple[type, ...] | None
    seed: np.ndarray | None
    length: float
    angle: float
    states: NamedStates | None = None

    def request(self, line: str | bytes) -> tuple[Target, np.ndarray | None, bool]:
        """The target, seed [rad, m] and ``"all"`` (every branch asked) of one input line.

        Raises:
            KinError, ValueError: A bad line (not JSON, unknown key, bad values, wrong kind).
        """
        try:
            text = line.decode() if isinstance(line, bytes) else line
            request = _decode(text)
        except (ValueError, RecursionError) as err:  # RecursionError: nested too deep
            from dh2urdf.long_numbers import long_integer_problem

            whole = line.decode(errors="replace") if isinstance(line, bytes) else line
            too_long = long_integer_problem(whole, err) if isinstance(err, ValueError) else None
            raise ValueError(too_long or f"not JSON: {err}") from None
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
        if isinstance(seed_q, str):
            if self.states is None:
                raise ValueError(f'"seed_q": no named states to look {quoted(seed_q)} up in')
            seed = self.states.q(seed_q)
        elif seed_q is not None:
            if not isinstance(seed_q, list):
                raise ValueError(
                    f'"seed_q" must be a list of numbers or a named state, got {quoted(seed_q)}'
                )
            seed = self.units.to_si(seed_q, '"seed_q"')
        return target, seed, every


def plain_groups(
    lines: Sequence[str | bytes], read_plain: PlainReader | None
) -> Iterator[tuple[list[int], Any, Any]]:
    """The plainest lines of a batch, by kind: ``(indices, targets, rpys or None)`` per group.

    Poses first, then positions; those the compiled reader ``read_plain`` takes (arrays, in
    the user's units), then the others the json module reads (lists as it gives them). Lazily:
    the caller starts a group's batch stage before the next group is read. A line with
    ``true``/``false`` anywhere, or that is not one JSON object of those two forms, is in no
    group (the line-by-line path reads it).
    """
    rest: Sequence[int] = range(len(lines))  # the lines for the json module, by index
    if read_plain is not None:
        kinds, values = read_plain(lines)
        kind = np.frombuffer(kinds, dtype=np.uint8)
        read = np.frombuffer(values).reshape(-1, 6)
        for code, poses in ((2, True), (1, False)):
            rows = np.flatnonzero(kind == code)
            if rows.size:
                yield rows.tolist(), read[rows, :3], read[rows, 3:] if poses else None
        rest = np.flatnonzero(kind == 0).tolist()
        if not rest:
            return
    groups: dict[bool, list[tuple[int, Any, Any]]] = {True: [], False: []}
    for position, request in decoded([lines[i] for i in rest]):
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
            yield indices, points, angles


def decoded(lines: Sequence[str | bytes]) -> list[tuple[int, Any]]:
    """``(index, value)`` of the lines that are one JSON value without ``true`` or ``false``.

    Each line by the decoder's scanner from its first character (about 1.5 us a line instead
    of 2.1 us through ``decode``), kept when the value ends the line; a line with anything
    else around its value (spaces too) goes through ``decode``; a line that is not one JSON
    value is left out (the line-by-line path says what is wrong with it).
    """
    found = []
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
        found.append((index, value))
    return found


def input_waiting(source: object) -> bool:
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


def line_batches(
    source: TextIO | Iterable[str], read: int = READ, chunk: int = CHUNK
) -> Iterator[Sequence[str | bytes]]:
    """The input lines, in batches of those already there (read without waiting).

    From a file descriptor (pipe, terminal, file): a batch is what one ``os.read`` of ``read``
    bytes gives, and what further reads give while more input is already there (``select``),
    up to ``chunk`` bytes; its complete lines (a line typed or written alone is a batch of one).
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
        data = os.read(fd, read)  # waits for input
        if not data:
            break
        parts, size = [pending, data], len(pending) + len(data)
        while size < chunk and _fd_waiting(fd):
            more = os.read(fd, read)
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
