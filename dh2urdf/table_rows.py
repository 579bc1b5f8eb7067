"""One ``[[joints]]`` row of a DH table file as a :class:`~dh2urdf.dh_table.DHRow`.

Its fields (type, a, alpha, d, theta, limits, and the optional ones the format lists in
:mod:`dh2urdf.table_file`) are checked and scaled to SI units; every error names the file, the
row and the field. Lengths [m], angles [rad].
"""

from __future__ import annotations

import math
from typing import Any

from .dh_table import DHRow
from .exceptions import TableError
from .link_meshes import parse_meshes
from .link_volumes import VOLUME_KEYS, parse_volumes
from .quoted_input import quoted
from .table_values import MAX_ANGLE, MAX_MASS, check_keys
from .table_values import length as _length
from .table_values import number as _number
from .table_values import positive as _positive
from .table_values import xml_text as _xml_text
from .units import angle_to_radians

__all__ = ["DEFAULT_EFFORT", "DEFAULT_VELOCITY", "parse_row"]

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
_JOINT_TYPES = ("prismatic", "revolute")

#: Defaults when a row gives no velocity / effort limit (SI: rad/s or m/s, N m or N).
DEFAULT_VELOCITY = {"revolute": math.pi, "prismatic": 0.5}
DEFAULT_EFFORT = {"revolute": 100.0, "prismatic": 100.0}


def parse_row(path: str, index: int, data: Any, meters: float, radians: float) -> DHRow:
    """Row ``index`` (1-based) of ``[[joints]]`` as a :class:`DHRow` in SI units.

    ``meters`` and ``radians``: the scales of the table's length and angle units.

    Raises:
        TableError: A field missing, unknown or out of range; the message names file, row, field.
    """
    if not isinstance(data, dict):
        raise TableError(path, "expected a table of fields", index, None)
    check_keys(path, data, _ROW_KEYS, index, "a joint row")
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
        velocity = _rate(path, data, index, "velocity", q_scale)
    effort = DEFAULT_EFFORT[joint_type]
    if "effort" in data:
        effort = _rate(path, data, index, "effort", 1.0)
    acceleration = None
    if "acceleration" in data:
        acceleration = _rate(path, data, index, "acceleration", q_scale)
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


def _rate(path: str, data: dict[str, Any], index: int, key: str, scale: float) -> float:
    """The row's ``key`` (a velocity, effort or acceleration limit) times ``scale``, positive."""
    value = _number(path, data[key], index, key) * scale
    if value <= 0:
        raise TableError(path, f"expected a positive {key}, got {quoted(data[key])}", index, key)
    return value
