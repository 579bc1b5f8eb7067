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

import math
import re
import sys
import warnings

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib
from pathlib import Path
from typing import Any

import numpy as np

from .dh_table import DHRow, DHTable, dh_link_transform
from .drive_section import parse_drives
from .exceptions import TableError, UnitWarning
from .input_file import read_input
from .joint_cap import MAX_JOINTS
from .link_meshes import parse_meshes
from .link_volumes import VOLUME_KEYS, parse_volumes
from .long_numbers import long_integer_problem
from .quoted_input import quoted
from .table_states import parse_states
from .table_values import MAX_ANGLE, MAX_LENGTH, MAX_MASS
from .table_values import length as _length
from .table_values import number as _number
from .table_values import positive as _positive
from .table_values import xml_text as _xml_text
from .transforms import xyz_rpy
from .units import ANGLE_UNITS, LENGTH_UNITS, angle_to_radians

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
_ROW_KEYS = {
    "name",
    "type",
    "a",
    "alpha",
    "d",
    "theta",
    "limits",
    "velocity",
    "effort",
    "acceleration",
    "mass",
    *VOLUME_KEYS,
    "mesh",
    "continuous",
    "direction",
    "beta",
}
_REQUIRED_ROW_KEYS = ("type", "a", "alpha", "d", "theta", "limits")
_CONVENTIONS = ("modified", "standard")
_JOINT_TYPES = ("prismatic", "revolute")

#: Defaults when a row gives no velocity / effort limit (SI: rad/s or m/s, N m or N).
DEFAULT_VELOCITY = {"revolute": math.pi, "prismatic": 0.5}
DEFAULT_EFFORT = {"revolute": 100.0, "prismatic": 100.0}


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


def _check_keys(
    path: str, data: dict[str, Any], allowed: set[str], row: int | None, what: str
) -> None:
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise TableError(
            path,
            f"unknown field in {what}; allowed fields: {', '.join(sorted(allowed))}",
            row,
            quoted(unknown[0])[1:-1],
        )


def _fixed_transform(
    path: str, data: Any, key: str, convention: str, meters: float, radians: float
) -> np.ndarray:
    if not isinstance(data, dict):
        raise TableError(path, "expected a table ([base] / [tool])", None, key)
    dh_keys = {"a", "alpha", "d", "theta"}
    if "quat_wxyz" in data and set(data) <= {"xyz", "quat_wxyz"}:
        return _xyz_quaternion(path, data, key, meters)
    if set(data) <= {"xyz", "rpy"}:
        xyz = data.get("xyz", [0.0, 0.0, 0.0])
        rpy = data.get("rpy", [0.0, 0.0, 0.0])
        values: list[tuple[float, float, float]] = []
        for sub, vec, scale in (("xyz", xyz, meters), ("rpy", rpy, radians)):
            if not isinstance(vec, list) or len(vec) != 3:
                raise TableError(
                    path, f"expected a list of 3 numbers, got {quoted(vec)}", None, f"{key}.{sub}"
                )
            if sub == "xyz":
                x, y, z = (_length(path, v, None, f"{key}.xyz", meters) for v in vec)
            else:
                x, y, z = (
                    angle_to_radians(_number(path, v, None, f"{key}.rpy"), scale) for v in vec
                )
            values.append((x, y, z))
        return xyz_rpy(values[0], values[1])
    if set(data) <= dh_keys:
        p = {k: _number(path, data.get(k, 0.0), None, f"{key}.{k}") for k in dh_keys}
        return dh_link_transform(
            convention,  # type: ignore[arg-type]
            _length(path, p["a"], None, f"{key}.a", meters),
            angle_to_radians(p["alpha"], radians),
            _length(path, p["d"], None, f"{key}.d", meters),
            angle_to_radians(p["theta"], radians),
        )
    raise TableError(
        path,
        "give either xyz/rpy, xyz/quat_wxyz or a DH-style row a/alpha/d/theta, not "
        + ", ".join(sorted(data)),
        None,
        key,
    )


def _xyz_quaternion(path: str, data: dict[str, Any], key: str, meters: float) -> np.ndarray:
    """``xyz`` [length_unit] and a unit quaternion ``quat_wxyz`` (W X Y Z) as a 4x4 transform.

    The quaternion is exact where roll-pitch-yaw is not (near pitch +-90 deg), so the tables
    read from URDFs (:mod:`.urdf_to_dh`) write it.
    """
    xyz = data.get("xyz", [0.0, 0.0, 0.0])
    quat = data["quat_wxyz"]
    for sub, vec, size in (("xyz", xyz, 3), ("quat_wxyz", quat, 4)):
        if not isinstance(vec, list) or len(vec) != size:
            raise TableError(
                path, f"expected a list of {size} numbers, got {quoted(vec)}", None, f"{key}.{sub}"
            )
    x, y, z = (_length(path, v, None, f"{key}.xyz", meters) for v in xyz)
    w, qx, qy, qz = (_number(path, v, None, f"{key}.quat_wxyz") for v in quat)
    norm = math.sqrt(w * w + qx * qx + qy * qy + qz * qz)
    if not abs(norm - 1.0) < 1e-6:
        raise TableError(
            path,
            f"expected a unit quaternion (W X Y Z), got norm {norm:.6g}",
            None,
            f"{key}.quat_wxyz",
        )
    w, qx, qy, qz = w / norm, qx / norm, qy / norm, qz / norm
    out = np.eye(4)
    out[:3, :3] = [
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * w), 2 * (qx * qz + qy * w)],
        [2 * (qx * qy + qz * w), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * w)],
        [2 * (qx * qz - qy * w), 2 * (qy * qz + qx * w), 1 - 2 * (qx * qx + qy * qy)],
    ]
    out[:3, 3] = (x, y, z)
    return out


def _row(path: str, index: int, data: Any, meters: float, radians: float) -> DHRow:
    if not isinstance(data, dict):
        raise TableError(path, "expected a table of fields", index, None)
    _check_keys(path, data, _ROW_KEYS, index, "a joint row")
    for key in _REQUIRED_ROW_KEYS:
        if key not in data:
            raise TableError(path, "missing required field", index, key)
    joint_type = data["type"]
    if joint_type not in _JOINT_TYPES:
        raise TableError(
            path,
            f"unknown joint type {quoted(joint_type)}; choose one of: {', '.join(_JOINT_TYPES)}",
            index,
            "type",
        )
    name = data.get("name", f"joint{index}")
    if not isinstance(name, str) or not name.strip():
        raise TableError(path, f"expected a non-empty string, got {quoted(name)}", index, "name")
    _xml_text(path, name, index, "name")
    continuous = data.get("continuous", False)
    if continuous is not True and continuous is not False:
        raise TableError(
            path, f"expected true or false, got {quoted(continuous)}", index, "continuous"
        )
    if continuous and joint_type != "revolute":
        raise TableError(path, "only a revolute joint can be continuous", index, "continuous")
    direction = data.get("direction", 1)
    if isinstance(direction, bool) or not isinstance(direction, int) or direction not in (1, -1):
        raise TableError(
            path,
            f"expected 1 or -1, got {quoted(direction)}: write direction = -1 for a joint that moves "
            "the other way (DH angle theta - q, length d - q), else leave the field out",
            index,
            "direction",
        )
    limits = data["limits"]
    if not isinstance(limits, list) or len(limits) != 2:
        raise TableError(path, f"expected [lower, upper], got {quoted(limits)}", index, "limits")
    q_scale = radians if joint_type == "revolute" else meters
    if joint_type == "prismatic":
        lower = _length(path, limits[0], index, "limits", meters)
        upper = _length(path, limits[1], index, "limits", meters)
    else:
        lower = _number(path, limits[0], index, "limits") * q_scale
        upper = _number(path, limits[1], index, "limits") * q_scale
        if max(abs(lower), abs(upper)) > MAX_ANGLE:
            raise TableError(
                path,
                f"a revolute limit beyond {MAX_ANGLE:g} rad, got {quoted(limits)}: for a joint "
                "without limits write continuous = true",
                index,
                "limits",
            )
    if lower > upper:
        raise TableError(
            path,
            f"lower limit {quoted(limits[0])} is above upper limit {quoted(limits[1])}",
            index,
            "limits",
        )
    velocity = DEFAULT_VELOCITY[joint_type]
    if "velocity" in data:
        velocity = _number(path, data["velocity"], index, "velocity") * q_scale
        if velocity <= 0:
            raise TableError(
                path,
                f"expected a positive velocity, got {quoted(data['velocity'])}",
                index,
                "velocity",
            )
    effort = DEFAULT_EFFORT[joint_type]
    if "effort" in data:
        effort = _number(path, data["effort"], index, "effort")
        if effort <= 0:
            raise TableError(
                path, f"expected a positive effort, got {quoted(data['effort'])}", index, "effort"
            )
    acceleration = None
    if "acceleration" in data:
        acceleration = _number(path, data["acceleration"], index, "acceleration") * q_scale
        if acceleration <= 0:
            raise TableError(
                path,
                f"expected a positive acceleration, got {quoted(data['acceleration'])}",
                index,
                "acceleration",
            )
    mass = _positive(path, data["mass"], index, "mass", 1.0, MAX_MASS) if "mass" in data else None
    volumes = parse_volumes(path, data, index, meters)
    meshes = parse_meshes(path, data.get("mesh", []), index, "mesh", meters, radians)
    return DHRow(
        index=index,
        name=name,
        joint_type=joint_type,
        a=_length(path, data["a"], index, "a", meters),
        alpha=angle_to_radians(_number(path, data["alpha"], index, "alpha"), radians),
        d=_length(path, data["d"], index, "d", meters),
        theta=angle_to_radians(_number(path, data["theta"], index, "theta"), radians),
        beta=angle_to_radians(_number(path, data.get("beta", 0.0), index, "beta"), radians),
        lower=lower,
        upper=upper,
        velocity=velocity,
        effort=effort,
        acceleration=acceleration,
        mass=mass,
        **volumes,
        meshes=meshes,
        continuous=continuous,
        direction=direction,
    )


#: An angle above this in a table said to be in radians is probably in degrees [rad].
RADIAN_SUSPECT = 2 * math.pi + 1e-9
#: A revolute limit above this (four turns) in a radian table is probably in degrees [rad]:
#: real multi-turn joints stop within two turns (ABB and FANUC joint 6: +-400 to 450 deg).
LIMIT_SUSPECT = 8 * math.pi + 1e-9
#: An arm longer than this (its lengths laid end to end) is probably not in meters [m].
LENGTH_SUSPECT = 20.0


def _fixed_angles(data: dict[str, Any]) -> list[tuple[str, float]]:
    """The angles of ``[base]`` and ``[tool]`` as written (rpy, or a DH-style alpha/theta)."""
    angles = []
    for key in ("base", "tool"):
        section = data.get(key)
        if isinstance(section, dict):
            angles += [(f"{key}.rpy", float(v)) for v in section.get("rpy", [])]
            angles += [
                (f"{key}.{k}", float(section[k])) for k in ("alpha", "theta") if k in section
            ]
    return angles


def _tool_extent(
    rows: tuple[DHRow, ...], convention: str, base: np.ndarray, tool: np.ndarray
) -> float:
    """The tool's largest distance from the world origin [m] over a few joint vectors.

    ``q = 0``, the lower and the upper limits, and eight seeded vectors inside the limits
    (revolute ones within a turn of the lower limit). Where the lengths laid end to end are long only because two
    nearly parallel axes put their common normal far away (a URDF that rounds pi to 3.1416:
    ``d`` of tens of km, out and back), the tool stays near: no unit slip there.
    """
    lower = np.array([row.lower for row in rows], dtype=float)
    upper = np.array([row.upper for row in rows], dtype=float)
    revolute = np.array([row.joint_type == "revolute" for row in rows])
    high = np.where(revolute, np.minimum(upper, lower + 2.0 * math.pi), upper)
    samples = [np.zeros(len(rows)), lower, upper]
    samples += list(
        np.random.default_rng(0).uniform(lower, np.maximum(high, lower), (8, len(rows)))
    )
    extent = 0.0
    with np.errstate(all="ignore"):  # extreme tables: an overflow is an infinite extent
        for q in samples:
            pose = base
            for row, value in zip(rows, q.tolist()):
                pose = pose @ row.transform(convention, value)  # type: ignore[arg-type]
            distance = float(np.linalg.norm((pose @ tool)[:3, 3]))
            extent = max(extent, distance) if math.isfinite(distance) else math.inf
    return extent


def _warn_units(
    path: str,
    rows: tuple[DHRow, ...],
    data: dict[str, Any],
    base: np.ndarray,
    tool: np.ndarray,
) -> None:
    """One :class:`UnitWarning` per suspicious unit: degrees in a radian table, a giant arm.

    Angles beyond a turn: alpha, theta and beta of every row, the rpy or alpha/theta of ``[base]``
    and ``[tool]``; beyond four turns: revolute limits (multi-turn joints are real; prismatic
    limits are lengths). Length: every ``|a| + |d|``, the largest
    prismatic travel and the base and tool offsets, laid end to end.
    """
    if data["angle_unit"] == "rad":
        angles: list[tuple[str, float, float, str]] = []
        turn, turns = (RADIAN_SUSPECT, "a turn"), (LIMIT_SUSPECT, "four turns")
        for row in rows:
            where = f"{path}, joint row {row.index}, field"
            written = data["joints"][row.index - 1]  # as written: the rows' are reduced
            angles += [
                (f"{where} 'alpha'", float(written["alpha"]), *turn),
                (f"{where} 'theta'", float(written["theta"]), *turn),
                (f"{where} 'beta'", float(written.get("beta", 0.0)), *turn),
            ]
            if row.joint_type == "revolute":
                angles += [(f"{where} 'limits'", v, *turns) for v in (row.lower, row.upper)]
        angles += [(f"{path}, field '{key}'", v, *turn) for key, v in _fixed_angles(data)]
        for where, value, bound, words in angles:
            if abs(value) > bound:
                warnings.warn(
                    f"{where}: {value:g} rad is more than {words}: are the angles in degrees? "
                    'then write angle_unit = "deg"',
                    UnitWarning,
                    stacklevel=3,
                )
                break
    length = sum(abs(row.a) + abs(row.d) for row in rows)
    length += sum(
        max(abs(row.lower), abs(row.upper)) for row in rows if row.joint_type == "prismatic"
    )
    length += float(np.linalg.norm(base[:3, 3])) + float(np.linalg.norm(tool[:3, 3]))
    if length > LENGTH_SUSPECT and _tool_extent(rows, data["convention"], base, tool) > (
        LENGTH_SUSPECT
    ):
        hint = 'length_unit = "mm"' if data["length_unit"] == "m" else "the length unit"
        warnings.warn(
            f"{path}: the arm's lengths add up to {length:g} m (more than {LENGTH_SUSPECT:g} m): "
            f"are they in millimeters? then write {hint}",
            UnitWarning,
            stacklevel=3,
        )


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
    _check_keys(path, data, _TOP_KEYS, None, "the table")
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
    rows = tuple(_row(path, i, row, meters, radians) for i, row in enumerate(joints, start=1))
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
        base = _fixed_transform(path, data["base"], "base", convention, meters, radians)
    if "tool" in data:
        tool = _fixed_transform(path, data["tool"], "tool", convention, meters, radians)
    _warn_units(path, rows, data, base, tool)
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
