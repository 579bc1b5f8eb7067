"""The record writer of ``kin ik --stdin``: each answer as one JSON line, written in order.

An answer is :meth:`kin.ik.IKResult.to_dict` (SI: q in rad / m, errors in m and rad, time in s)
with ``"line"`` and ``"q_units"`` (:func:`result_record`, :func:`numbered`); a bad line's is
``{"line": n, "error": "..."}`` (:func:`error_record`). The batch stage's verified answers are
made here too, with the same keys in the same order: as records (:func:`batch_record`) or
encoded at once (:func:`encode_found`, by the compiled writer ``kin/_native/commands/_plain_lines.c``
when the caller hands it, else by one %-format per line). :func:`write_records` writes them,
:data:`FLUSH_EVERY` lines per write.
"""

from __future__ import annotations

import json
import logging
from collections.abc import Callable, Sequence
from typing import Any, TextIO

import numpy as np

from ..exceptions import KinError
from ..ik.batch_solve import FREE_JOINT_STAGE
from ..ik.numeric.free_joint import FROM_SEED
from ..ik.result import IKResult, counts_record
from ..ik.targets.target import PositionTarget, Target

logger = logging.getLogger(__name__)

#: Most answers written between two flushes while input lines are already there.
FLUSH_EVERY = 32

#: The compiled writer's signature: ``(pieces, values (N, k), line numbers (N,))`` -> the lines.
PlainWriter = Callable[[tuple[str, ...], np.ndarray, np.ndarray], list[str]]


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


def batch_record(
    pipeline: str,
    q: list[float],
    position_error: float,
    rotation_error: float | None,
    each: float,
) -> dict[str, Any]:
    """The record of a line the batch stage answered: joint vector [rad, m], errors [m, rad].

    ``rotation_error``: None for a position; ``each``: the stage's time per line [s].
    """
    solution = {
        "q": q,
        "branch": "",
        "within_limits": True,
        "position_error_m": position_error,
        "rotation_error_rad": rotation_error,
    }
    return {
        "success": True,
        "solver": pipeline,
        "status": "ok",
        "message": FROM_SEED,
        "solutions": [solution],
        "rejected": [],
        "method": FREE_JOINT_STAGE,
        "distance_to_workspace_m": None,
        "iterations": 0,
        "time_s": each,
        "free": [],
        "counts": counts_record(1, 0, 0),
    }


def encode_found(
    pipeline: str,
    si_labels: Sequence[str],
    chosen: list[int],
    q: np.ndarray,
    position_error: np.ndarray,
    rotation_error: np.ndarray | None,
    first: int,
    each: float,
    write_plain: PlainWriter | None,
) -> dict[int, str]:
    """The encoded answers (whole lines) of the batch stage's verified lines, by line index.

    Args:
        pipeline: The solver's name.
        si_labels: The joint units of ``q`` (``"q_units"``).
        chosen: The lines' indices in their batch.
        q: Their joint vectors [rad, m], (N, nq).
        position_error: Their position errors [m], (N,).
        rotation_error: Their rotation errors [rad], (N,), or None for positions.
        first: The line number of index 0.
        each: The batch stage's time per line [s].
        write_plain: The compiled writer, or None (one %-format per line: the values' reprs,
            as the json module writes a finite float).
    """
    poses = rotation_error is not None
    head = (
        f'{{"success": true, "solver": {json.dumps(pipeline)}, "status": "ok", '
        f'"message": {json.dumps(FROM_SEED)}, "solutions": [{{"q": ['
    )
    tail = (
        f'"rejected": [], "method": "{FREE_JOINT_STAGE}", "distance_to_workspace_m": null, '
        f'"iterations": 0, "time_s": {each!r}, "free": [], '
        f'"counts": {json.dumps(counts_record(1, 0, 0))}, "line": '
    )
    units = json.dumps(list(si_labels))
    after = ', "position_error_m": '
    rotation = ', "rotation_error_rad": '
    if write_plain is not None:  # the compiled writer: the values' texts read back the same
        columns = [q, position_error[:, None]]
        if rotation_error is not None:
            columns.append(rotation_error[:, None])
        pieces = (
            head,
            *[", "] * (q.shape[1] - 1),
            '], "branch": "", "within_limits": true' + after,
            *([rotation] if poses else []),
            ("}], " if poses else rotation + "null}], ") + tail,
            ', "q_units": ' + units + "}\n",
        )
        numbers = np.array(chosen, dtype=np.int64) + first
        return dict(zip(chosen, write_plain(pieces, np.hstack(columns), numbers)))
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
    answers: dict[int, str] = {}
    values = q.tolist()
    if rotation_error is not None:
        solved = zip(chosen, values, position_error.tolist(), rotation_error.tolist())
        for index, row, position, rotation_value in solved:
            answers[index] = line_format % (*row, position, rotation_value, first + index)
    else:
        for index, row, position in zip(chosen, values, position_error.tolist()):
            answers[index] = line_format % (*row, position, first + index)
    return answers


def error_record(number: int, err: Exception) -> dict[str, Any]:
    """The answer of a line that failed: its message, or an internal error's (logged)."""
    text = " ".join(str(err).split())
    if isinstance(err, (KinError, ValueError, TypeError)):
        return {"error": text}
    logger.debug("line %d: unexpected error", number, exc_info=True)
    return {"error": f"internal error: {type(err).__name__}: {text}"}


def numbered(
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


def write_records(
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
