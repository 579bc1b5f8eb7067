"""Read a DH table file (TOML) into a :class:`DHTable`, with errors that name file, row and field.

Format (see ``dh2urdf/tables/*.toml`` for complete examples)::

    name = "myarm"                 # optional, defaults to the file stem
    description = "..."
    source = "paper X, Table 1"
    convention = "standard"        # or "modified" (Craig)
    length_unit = "mm"             # m | cm | mm
    angle_unit = "deg"             # deg | rad

    [[joints]]                     # one per joint, base to tip
    name = "shoulder"              # optional
    type = "revolute"              # revolute | prismatic
    a = 0.0
    alpha = 90.0
    d = 105.0
    theta = 0.0                    # offset added to q (revolute)
    beta = 0.0                     # optional: Hayati's tilt about y after alpha (dh_table.py)
    limits = [-90.0, 90.0]         # of the joint variable q
    continuous = false             # optional: a revolute joint without limits (give [-180, 180])
    direction = 1                  # optional: -1 reverses the joint (DH angle theta - q)
    velocity = 90.0                # optional, angle_unit/s or length_unit/s
    effort = 10.0                  # optional, N m or N
    acceleration = 360.0           # optional, angle_unit/s^2 or length_unit/s^2 (path timing)
    mass = 1.5                     # optional, kg: the link gets a solid-cylinder inertial
    radius = 40.0                  # optional, length_unit: radius of the row's segments
    radius_a = 40.0                # optional: of the a segment only (radius_d: the d segment)
    [[joints.housing]]             # optional cylinders in DH frame i: dh2urdf/link_volumes.py
    [[joints.mesh]]                # optional meshes in DH frame i: dh2urdf/link_meshes.py

    [base]                         # optional: xyz + rpy, xyz + quat_wxyz, or a DH-style row
    xyz = [0.0, 0.0, 0.0]          #   a, alpha, d, theta
    rpy = [0.0, 0.0, 0.0]          # (or quat_wxyz = [1.0, 0.0, 0.0, 0.0]: W X Y Z, unit)

    [tool]                         # optional, same forms as [base]

    [drives.shoulder]              # optional stepper drives: dh2urdf/drive_section.py
    [[base_mesh]]                  # optional meshes in DH frame 0: dh2urdf/link_meshes.py
    [states]                       # optional named joint vectors: dh2urdf/table_states.py
"""

from __future__ import annotations

import re
import sys

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib
from pathlib import Path
from typing import Any

import numpy as np

from .dh_table import DHTable
from .drive_section import parse_drives
from .exceptions import TableError
from .input_file import read_input
from .joint_cap import MAX_JOINTS
from .link_meshes import parse_meshes
from .long_numbers import long_integer_problem
from .quoted_input import quoted
from .table_frames import fixed_transform
from .table_rows import DEFAULT_EFFORT, DEFAULT_VELOCITY, parse_row
from .table_states import parse_states
from .table_units import warn_units
from .table_values import MAX_LENGTH, MAX_MASS, check_keys
from .table_values import xml_text as _xml_text
from .units import ANGLE_UNITS, LENGTH_UNITS

__all__ = [
    "DEFAULT_EFFORT",
    "DEFAULT_VELOCITY",
    "MAX_LENGTH",
    "MAX_MASS",
    "load_table",
    "parse_table",
]

_TOP_KEYS = {
    "name",
    "description",
    "source",
    "notes",
    "convention",
    "length_unit",
    "angle_unit",
    "joints",
    "base",
    "tool",
    "drives",
    "base_mesh",
    "states",
}
_CONVENTIONS = ("modified", "standard")


def _string(
    path: str, data: dict[str, Any], key: str, choices: tuple[str, ...] | None = None
) -> str:
    if key not in data:
        hint = f" (one of: {', '.join(choices)})" if choices else ""
        raise TableError(path, f"missing required field{hint}", None, key)
    value = data[key]
    if not isinstance(value, str):
        raise TableError(path, f"expected a string, got {quoted(value)}", None, key)
    if choices is not None and value not in choices:
        raise TableError(
            path, f"unknown value {quoted(value)}; choose one of: {', '.join(choices)}", None, key
        )
    return value


def parse_table(
    data: dict[str, Any], path: str = "<string>", default_name: str = "robot"
) -> DHTable:
    """Build a :class:`DHTable` from parsed TOML data.

    Args:
        data: The parsed TOML document.
        path: Where it came from, for error messages.
        default_name: Robot name when the document has no ``name``.

    Raises:
        TableError: The document is malformed; the message names the file, row and field.
    """
    check_keys(path, data, _TOP_KEYS, None, "the table")
    convention = _string(path, data, "convention", _CONVENTIONS)
    length_unit = _string(path, data, "length_unit", tuple(sorted(LENGTH_UNITS)))
    angle_unit = _string(path, data, "angle_unit", tuple(sorted(ANGLE_UNITS)))
    meters, radians = LENGTH_UNITS[length_unit], ANGLE_UNITS[angle_unit]
    texts = {}
    for key in ("name", "description", "source"):
        value = data.get(key, default_name if key == "name" else "")
        if not isinstance(value, str):
            raise TableError(path, f"expected a string, got {quoted(value)}", None, key)
        if key == "name" and not value.strip():
            raise TableError(
                path, f"expected a non-empty robot name, got {quoted(value)}", None, key
            )
        texts[key] = _xml_text(path, value, None, key)
    joints = data.get("joints")
    if not isinstance(joints, list) or not joints:
        raise TableError(path, "expected at least one [[joints]] row", None, "joints")
    if len(joints) > MAX_JOINTS:
        raise TableError(
            path,
            f"{len(joints)} [[joints]] rows; at most {MAX_JOINTS} are supported",
            None,
            "joints",
        )
    rows = tuple(parse_row(path, i, row, meters, radians) for i, row in enumerate(joints, start=1))
    seen: dict[str, int] = {}
    for row in rows:
        if row.name in seen:
            raise TableError(
                path,
                f"joint name {quoted(row.name)} is already used by row {seen[row.name]}",
                row.index,
                "name",
            )
        seen[row.name] = row.index
    base = np.eye(4)
    tool = np.eye(4)
    if "base" in data:
        base = fixed_transform(path, data["base"], "base", convention, meters, radians)
    if "tool" in data:
        tool = fixed_transform(path, data["tool"], "tool", convention, meters, radians)
    warn_units(path, rows, data, base, tool)
    return DHTable(
        name=texts["name"],
        description=texts["description"],
        source=texts["source"],
        convention=convention,  # type: ignore[arg-type]
        rows=rows,
        T_world_base=base,
        T_last_tool=tool,
        path=path,
        drives=parse_drives(path, data["drives"], rows, radians) if "drives" in data else (),
        base_meshes=parse_meshes(
            path, data.get("base_mesh", []), None, "base_mesh", meters, radians
        ),
        states=parse_states(path, data.get("states", {}), rows, meters, radians),
    )


_TOML_PLACE = re.compile(r"\(at line (\d+), column (\d+)\)|\(at end of document\)")


def _toml_error(raw: bytes, text: str, err: Exception) -> str:
    """``err``'s message with the byte offset of the place it names (line and column kept)."""
    message = " ".join(str(err).split())
    place = _TOML_PLACE.search(message)
    if place is None:
        return message
    if place.group(1) is None:
        return f"{message[: place.start()].rstrip()} at the end of the file (byte {len(raw)})"
    line, column = int(place.group(1)), int(place.group(2))
    lines = text.split("\n")
    start = sum(len(item) + 1 for item in lines[: line - 1]) + column - 1
    offset = len(text[:start].encode("utf-8")) + (3 if raw.startswith(_UTF8_BOM) else 0)
    return f"{message[: place.start()].rstrip()} at byte {offset} (line {line}, column {column})"


_UTF8_BOM = b"\xef\xbb\xbf"
_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")


def load_table(path: str | Path) -> DHTable:
    """Read a DH table file (UTF-8, with or without a byte-order mark).

    Args:
        path: A ``.toml`` table file.

    Raises:
        TableError: The file is missing, not UTF-8 text, not TOML (the message gives the byte
            offset, line and column), or malformed.
    """
    path = Path(path)
    try:
        raw = read_input(path)
    except OSError as err:
        raise TableError(str(path), f"cannot read the file ({err.strerror})") from err
    if raw.startswith(_UTF16_BOMS):
        raise TableError(str(path), "not UTF-8 text: the file is UTF-16; save it as UTF-8")
    try:
        text = raw.decode("utf-8-sig")  # a byte-order mark, as Windows editors write, is skipped
    except UnicodeDecodeError as err:
        start = err.start + (3 if raw.startswith(_UTF8_BOM) else 0)
        line = raw.count(b"\n", 0, start) + 1
        column = start - (raw.rfind(b"\n", 0, start) + 1) + 1
        raise TableError(
            str(path),
            f"not UTF-8 text: byte {start} (line {line}, column {column}) is "
            f"0x{raw[start]:02x}; save the file as UTF-8",
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise TableError(str(path), f"not valid TOML: {_toml_error(raw, text, err)}") from err
    except ValueError as err:  # Python's integer-string limit (a 5000-digit integer)
        raise TableError(str(path), long_integer_problem(text, err) or str(err)) from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        raise TableError(
            str(path), "not a DH table: arrays or inline tables nested too deep for TOML's reader"
        ) from None
    return parse_table(data, str(path), default_name=path.stem)
