"""Sample files: joint values and the pose a source printed for them, as CSV with a header.

Format (comments start with ``#``, anywhere on a line; blank lines are skipped)::

    # humanoid7, paper 000 Tables II-VIII, column "DH solution" [deg, cm]
    label,q1,q2,q3,q4,q5,q6,q7,x,y,z
    case 1,0,-90,90,0,0,90,0,86.33,0,0
    case 2,-90,-60,-30,0,30,60,90,-19.94,-58.788,-28.37

Columns, in any order, named in the header:

- ``q1`` .. ``qN``: the joint values, one per joint of the table (required): revolute in the
  table's ``angle_unit``, prismatic in its ``length_unit``;
- ``x``, ``y``, ``z``: the printed tool position in the table's ``length_unit`` (required);
- optionally an orientation: ``roll``, ``pitch``, ``yaw`` (URDF convention
  ``Rz(yaw) Ry(pitch) Rx(roll)``, in the table's ``angle_unit``) or ``r11`` .. ``r33`` (the
  rotation matrix, row by row: column ``j`` is tool axis ``j`` in world axes);
- optionally ``label``: a name for the sample (default ``line <n>``); quote it if it holds a
  comma (``"Table II, case 1"``).

A printed value may be left empty when the source does not give it. The number of decimals of
each printed value is its precision: a sample is reproduced when every printed value is the
computed one at that precision (rounded, or truncated under that reading).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from dh2urdf.input_file import read_input

from .exceptions import AuditError

Orientation = Literal["none", "rpy", "matrix"]

POSITION = ("x", "y", "z")
RPY = ("roll", "pitch", "yaw")
MATRIX = tuple(f"r{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3))


@dataclass(frozen=True, eq=False)
class SampleSet:
    """Printed samples of one source, in the units of the audited table's file.

    Attributes:
        path: The sample file.
        labels: One name per sample.
        lines: 1-based line of each sample in the file.
        q: Joint values (N, dof): revolute [table angle unit], prismatic [table length unit].
        values: Printed values (N, K): position [table length unit], then the orientation
            (rpy [table angle unit] or matrix entries [-]); NaN where the source gives none.
        decimals: Decimals of each printed value (N, K): its precision is ``10**-decimals``.
        columns: Names of the K value columns (``x, y, z`` then the orientation's).
        orientation: ``"none"``, ``"rpy"`` or ``"matrix"``.
        q_decimals: Decimals of each printed joint value (N, dof), or None (exact values).
    """

    path: str
    labels: tuple[str, ...]
    lines: tuple[int, ...]
    q: np.ndarray
    values: np.ndarray
    decimals: np.ndarray
    columns: tuple[str, ...]
    orientation: Orientation
    q_decimals: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.labels)


def _decimals(text: str) -> int:
    mantissa = text.lower().split("e")[0]
    places = len(mantissa.split(".")[1]) if "." in mantissa else 0
    if "e" in text.lower():
        places -= int(text.lower().split("e")[1])
    return max(places, 0)


def _header(path: str, line: int, names: list[str], dof: int) -> tuple[list[str], Orientation]:
    joints = [f"q{i}" for i in range(1, dof + 1)]
    given = [n for n in names if n.startswith("q") and n[1:].isdigit()]
    if sorted(given, key=lambda n: int(n[1:])) != joints:
        raise AuditError(
            f"the header names joint columns {', '.join(given) or 'none'}; the table has "
            f"{dof} joints: q1..q{dof}",
            path,
            line,
        )
    has_rpy, has_matrix = any(n in RPY for n in names), any(n in MATRIX for n in names)
    if has_rpy and has_matrix:
        raise AuditError("give the orientation as roll, pitch, yaw or as r11..r33", path, line)
    orientation: Orientation = "rpy" if has_rpy else "matrix" if has_matrix else "none"
    wanted = [*joints, *POSITION, *{"none": (), "rpy": RPY, "matrix": MATRIX}[orientation]]
    allowed = {*wanted, "label"}
    unknown = [n for n in names if n not in allowed]
    missing = [n for n in wanted if n not in names]
    duplicate = sorted({n for n in names if names.count(n) > 1})
    if unknown or missing or duplicate:
        problem = "; ".join(
            f"{what}: {', '.join(items)}"
            for what, items in (("unknown", unknown), ("missing", missing), ("twice", duplicate))
            if items
        )
        raise AuditError(
            f"bad header ({problem}); columns: label (optional), q1..q{dof}, x, y, z, "
            "optionally roll, pitch, yaw or r11..r33",
            path,
            line,
        )
    return wanted, orientation


def _cells(raw: str) -> list[str]:
    """The comma-separated cells of a line (quotes allowed), without its ``#`` comment."""
    text = raw.split("#", 1)[0]
    return [cell.strip() for cell in next(csv.reader([text]), [""])] if text.strip() else [""]


def read_samples(path: str | Path, dof: int) -> SampleSet:
    """Read a sample file for a table of ``dof`` joints.

    Raises:
        AuditError: The file is missing or empty, its header is wrong, or a line has the wrong
            number of columns or a value that is not a finite number; the message names the file
            and the line.
    """
    where = str(path)
    try:
        text = read_input(path).decode("utf-8-sig")  # a spreadsheet's BOM is no header
    except OSError as err:
        raise AuditError(f"cannot read the sample file ({err.strerror})", where) from err
    except UnicodeDecodeError as err:
        raise AuditError(f"cannot read the sample file ({err})", where) from err
    rows = [(n, _cells(raw)) for n, raw in enumerate(text.splitlines(), start=1)]
    rows = [(n, cells) for n, cells in rows if cells != [""]]
    if not rows:
        raise AuditError("empty sample file: expected a header line and samples", where)
    header_line, names = rows[0]
    wanted, orientation = _header(where, header_line, names, dof)
    if len(rows) == 1:
        raise AuditError("no samples after the header", where, header_line)
    index = {name: k for k, name in enumerate(names)}
    labels, lines, numbers, decimals = [], [], [], []
    for line, cells in rows[1:]:
        if len(cells) != len(names):
            raise AuditError(
                f"expected {len(names)} comma-separated values ({', '.join(names)}), "
                f"got {len(cells)}",
                where,
                line,
            )
        row, places = [], []
        for name in wanted:
            cell = cells[index[name]]
            if cell == "" and not name.startswith("q"):
                row.append(math.nan)
                places.append(0)
                continue
            try:
                value = float(cell)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise AuditError(f"column '{name}': not a finite number: {cell!r}", where, line)
            row.append(value)
            places.append(_decimals(cell))
        label = cells[index["label"]] if "label" in index else ""
        labels.append(label or f"line {line}")
        lines.append(line)
        numbers.append(row)
        decimals.append(places)
    table = np.array(numbers, dtype=float)
    return SampleSet(
        path=where,
        labels=tuple(labels),
        lines=tuple(lines),
        q=table[:, :dof],
        values=table[:, dof:],
        decimals=np.array(decimals, dtype=int)[:, dof:],
        columns=tuple(wanted[dof:]),
        orientation=orientation,
        q_decimals=np.array(decimals, dtype=int)[:, :dof],
    )
