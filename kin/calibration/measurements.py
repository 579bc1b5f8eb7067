"""Measurement files of a calibration: joint values and the tracker's positions or poses per row.

CSV: a header row naming the columns, the robot's joint names (or ``q1`` .. ``qn``), then ``x``,
``y``, ``z`` (one measured point), or ``x1, y1, z1, x2, ...`` (several markers), and for full poses
``qx, qy, qz, qw`` (unit quaternion) or ``roll, pitch, yaw`` (URDF: ``Rz(yaw) Ry(pitch) Rx(roll)``);
``#`` starts a comment line. JSON lines: one object per line with the same keys (``"q": [...]``
for the joints). Lengths in ``unit`` (m by default), joint angles and roll-pitch-yaw in radians
unless ``degrees``. Every bad value is named by file, line and column (:class:`CalibrationError`).
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from dh2urdf import DHTable
from dh2urdf.input_file import read_input
from dh2urdf.quoted_input import quoted
from dh2urdf.units import LENGTH_UNITS

from .exceptions import CalibrationError

#: Tolerance on a quaternion's norm [1]: further from 1 is a typo, not rounding.
QUATERNION_NORM_TOL = 1e-3
#: A spread of the measured points this many times the arm's reach says "wrong unit".
SLIP_FACTOR = 20.0


@dataclass(frozen=True, eq=False)
class Measurements:
    """Measured rows, in meters and radians.

    Attributes:
        q: Joint values (N, n) [rad] / [m].
        points: Measured points in the measurement frame (N, K, 3) [m] (the tool origin, K = 1,
            for full poses).
        rotations: Measured tool rotations (N, 3, 3), or None (positions only).
        lines: 1-based file line of each row (N,).
        path: The file (``"<memory>"`` for arrays).
    """

    q: np.ndarray
    points: np.ndarray
    rotations: np.ndarray | None
    lines: np.ndarray
    path: str = "<memory>"

    @property
    def markers(self) -> int:
        """Measured points per row, or 0 for full poses."""
        return 0 if self.rotations is not None else int(self.points.shape[1])

    @property
    def count(self) -> int:
        """Number of rows."""
        return int(self.q.shape[0])

    def subset(self, rows: np.ndarray) -> Measurements:
        """The measurements of some rows (indices or a mask)."""
        rot = None if self.rotations is None else self.rotations[rows]
        return Measurements(self.q[rows], self.points[rows], rot, self.lines[rows], self.path)


def _joint_columns(header: list[str], table: DHTable) -> list[str]:
    """The joint columns in row order: the robot's joint names, else ``q1`` .. ``qn``."""
    names = list(table.joint_names)
    generic = [f"q{i}" for i in range(1, table.dof + 1)]
    expected = names if any(h in names for h in header) else generic
    found = [h for h in header if h in names or re.fullmatch(r"q\d+", h)]
    if sorted(found) != sorted(expected):
        raise CalibrationError(
            f"the header names {len(found)} joint columns; the robot '{table.name}' has "
            f"{table.dof} joints: name one column per joint, {', '.join(names)} (or q1..q{table.dof})"
        )
    return expected


def _layout(path: str, header: list[str], table: DHTable) -> tuple[list[str], list[list[str]], str]:
    """Joint columns, point columns (per marker) and the orientation kind of a header."""
    joints = _joint_columns(header, table)
    if {"x", "y", "z"} <= set(header):
        points = [["x", "y", "z"]]
    else:
        points = []
        k = 1
        while {f"x{k}", f"y{k}", f"z{k}"} <= set(header):
            points.append([f"x{k}", f"y{k}", f"z{k}"])
            k += 1
    if not points:
        raise CalibrationError(
            "the header names no measured point: add columns x, y, z (or x1, y1, z1, ...)", path, 1
        )
    orientation = "none"
    if {"qx", "qy", "qz", "qw"} <= set(header):
        orientation = "quaternion"
    elif {"roll", "pitch", "yaw"} <= set(header):
        orientation = "rpy"
    if orientation != "none" and len(points) > 1:
        raise CalibrationError(
            "full poses go with one point (x, y, z), not several markers", path, 1
        )
    known = set(joints) | {c for p in points for c in p} | {"label"}
    known |= {
        "quaternion": {"qx", "qy", "qz", "qw"},
        "rpy": {"roll", "pitch", "yaw"},
        "none": set(),
    }[orientation]
    for column in header:
        if column not in known:
            raise CalibrationError(
                "unknown column: expected joint columns, x, y, z (or x1, y1, z1, ...), "
                "qx, qy, qz, qw or roll, pitch, yaw, label",
                path,
                1,
                column,
            )
    return joints, points, orientation


def _records(path: str, text: str) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Header and (line, cells) of a CSV or JSON-lines text."""
    lines = text.splitlines()
    first = next(
        (i for i, line in enumerate(lines) if line.strip() and not line.lstrip().startswith("#")),
        None,
    )
    if first is None:
        raise CalibrationError("no header row and no measurements", path)
    if lines[first].lstrip().startswith("{"):
        return _json_records(path, lines)
    rows: list[tuple[int, list[str]]] = []
    for i, line in enumerate(lines):
        if i < first or not line.strip() or line.lstrip().startswith("#"):
            continue
        cells = [c.strip() for c in next(csv.reader(io.StringIO(line)))]
        rows.append((i + 1, cells))
    header, body = rows[0][1], rows[1:]
    for number, cells in body:
        if len(cells) != len(header):
            raise CalibrationError(
                f"{len(cells)} values; the header names {len(header)} columns", path, number
            )
    return header, body


def _json_records(path: str, lines: list[str]) -> tuple[list[str], list[tuple[int, list[str]]]]:
    header: list[str] | None = None
    body = []
    for i, line in enumerate(lines):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            record = json.loads(line)
        except json.JSONDecodeError as err:
            raise CalibrationError(f"not a JSON object: {err.msg}", path, i + 1) from err
        if not isinstance(record, dict):
            raise CalibrationError("not a JSON object", path, i + 1)
        flat: dict[str, str] = {}
        for key, value in record.items():
            if key == "q" and isinstance(value, list):
                flat.update({f"q{j}": str(v) for j, v in enumerate(value, start=1)})
            else:
                flat[key] = str(value)
        if header is None:
            header = list(flat)
        elif set(flat) != set(header):
            raise CalibrationError(
                f"keys {quoted(sorted(flat))} differ from the first line's {quoted(sorted(header))}",
                path,
                i + 1,
            )
        body.append((i + 1, [flat[k] for k in header]))
    assert header is not None
    return header, body


def _number(path: str, line: int, column: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise CalibrationError(
            f"{quoted(text)} is not a finite number: remove or fix the row", path, line, column
        )
    return value


def _reach(table: DHTable) -> float:
    """Sum of the arm's lengths and the tool offset [m] (at least 0.1 m)."""
    total = float(np.linalg.norm(table.T_last_tool[:3, 3]))
    for row in table.rows:
        travel = max(abs(row.lower), abs(row.upper)) if row.joint_type == "prismatic" else 0.0
        total += abs(row.a) + abs(row.d) + travel
    return max(total, 0.1)


def read_measurements(
    path: str | Path, table: DHTable, unit: str = "m", degrees: bool = False
) -> Measurements:
    """Read a measurement file (CSV or JSON lines) for the arm of ``table``.

    Args:
        path: The file.
        table: The nominal arm (joint names, count and limits).
        unit: Length unit of the file's positions and prismatic joints (``m``, ``cm``, ``mm``).
        degrees: Joint angles and roll-pitch-yaw in degrees (else radians).

    Raises:
        CalibrationError: A missing or unknown column, a row of the wrong length, a value that is
            not a finite number, a joint value outside its limits, a quaternion not of unit
            norm, or positions whose spread says they are in another unit (the slip check).
    """
    name = str(path)
    try:
        text = read_input(path).decode("utf-8-sig")
    except (OSError, UnicodeDecodeError) as err:
        raise CalibrationError(f"cannot read it: {err}", name) from err
    header, body = _records(name, text)
    try:
        joints, points, orientation = _layout(name, header, table)
    except CalibrationError as err:
        if err.path is None:
            raise CalibrationError(str(err), name, 1) from None
        raise
    meters = LENGTH_UNITS[unit]
    angle = math.pi / 180.0 if degrees else 1.0
    col = {c: i for i, c in enumerate(header)}
    n = len(body)
    q = np.zeros((n, table.dof))
    pts = np.zeros((n, len(points), 3))
    rot = np.zeros((n, 3, 3))
    for r, (line, cells) in enumerate(body):
        for j, (column, row) in enumerate(zip(joints, table.rows)):
            value = _number(name, line, column, cells[col[column]])
            q[r, j] = value * (angle if row.joint_type == "revolute" else meters)
            if not row.lower - 1e-9 <= q[r, j] <= row.upper + 1e-9:
                shown = angle if row.joint_type == "revolute" else meters
                unit_name = ("deg" if degrees else "rad") if row.joint_type == "revolute" else unit
                raise CalibrationError(
                    f"{value:g} {unit_name} is outside the joint's limits "
                    f"[{row.lower / shown:g}, {row.upper / shown:g}] {unit_name}"
                    + ("" if degrees or row.joint_type != "revolute" else " (degrees? pass --deg)"),
                    name,
                    line,
                    column,
                )
        for k, names in enumerate(points):
            pts[r, k] = [_number(name, line, c, cells[col[c]]) * meters for c in names]
        if orientation == "quaternion":
            quat = np.array(
                [_number(name, line, c, cells[col[c]]) for c in ("qx", "qy", "qz", "qw")]
            )
            if abs(np.linalg.norm(quat) - 1.0) > QUATERNION_NORM_TOL:
                raise CalibrationError(
                    f"quaternion norm {np.linalg.norm(quat):.6g}, expected 1", name, line, "qw"
                )
            rot[r] = Rotation.from_quat(quat).as_matrix()
        elif orientation == "rpy":
            rpy = [_number(name, line, c, cells[col[c]]) * angle for c in ("roll", "pitch", "yaw")]
            rot[r] = Rotation.from_euler("xyz", rpy).as_matrix()
    lines = np.array([line for line, _ in body], dtype=int)
    found = Measurements(q, pts, rot if orientation != "none" else None, lines, name)
    _check_unit(found, table, unit)
    return found


def _check_unit(found: Measurements, table: DHTable, unit: str) -> None:
    """The slip check: points spread over far more (or less) than the arm reaches."""
    if found.count < 2:
        return
    reach = _reach(table)
    flat = found.points.reshape(-1, 3)
    distance = np.linalg.norm(flat - np.median(flat, axis=0), axis=1)
    far = int(np.argmax(distance))
    row, k = divmod(far, found.points.shape[1])
    column = "x" if found.points.shape[1] == 1 else f"x{k + 1}"
    line = int(found.lines[row])
    if distance[far] > SLIP_FACTOR * reach:
        raise CalibrationError(
            f"the measured points spread over {distance[far]:.4g} {unit} from their median, "
            f"{distance[far] / reach:.0f} times the arm's reach ({reach:.3g} m): millimetres read "
            "as meters? pass --unit mm",
            found.path,
            line,
            column,
        )
    spread = float(distance.max())
    if spread < reach / (SLIP_FACTOR * 10.0) and np.ptp(found.q, axis=0).max() > 0.1:
        raise CalibrationError(
            f"the measured points spread over only {spread * 1e3:.3g} mm while the joints move: "
            f"meters read as {unit}? check --unit",
            found.path,
            line,
            column,
        )
