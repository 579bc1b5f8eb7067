"""Write a :class:`DHTable` as a table file (TOML), in the format users write by hand.

Lengths in meters and angles in radians (``length_unit = "m"``, ``angle_unit = "rad"``), every
number written with all its digits (``repr``), so that :func:`~dh2urdf.load_table` of the text
gives the same table: the rows exactly (a nonzero tilt ``beta`` included), with the acceleration, mass, radii,
``[[joints.housing]]`` and ``[[joints.mesh]]`` they state (their body, :mod:`dh2urdf.link_volumes`,
:mod:`dh2urdf.link_meshes`; mesh files relative to the table's folder), ``[states]``, ``[base]`` and
``[tool]`` through ``xyz`` and ``rpy`` (URDF roll-pitch-yaw) when that keeps every digit, else
``quat_wxyz`` (near pitch +-90 deg). A ``[drives]`` section is not written.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .dh_table import DHRow, DHTable
from .link_meshes import LinkMesh, mesh_name

__all__ = ["table_text", "write_table"]


def _number(value: float) -> str:
    text = repr(float(value))
    return "0.0" if text == "-0.0" else text


def _string(text: str) -> str:
    escaped = text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", " ")
    return f'"{escaped}"'


def _rpy(rotation: np.ndarray) -> tuple[float, float, float]:
    """URDF roll-pitch-yaw of a rotation matrix: ``R = Rz(yaw) Ry(pitch) Rx(roll)`` [rad]."""
    r = np.asarray(rotation, dtype=float)
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if math.hypot(r[0, 0], r[1, 0]) > 1e-12:
        roll = math.atan2(r[2, 1], r[2, 2])
        yaw = math.atan2(r[1, 0], r[0, 0])
    else:  # gimbal lock: yaw 0, all of it in roll
        roll = math.atan2(-r[1, 2], r[1, 1])
        yaw = 0.0
    return roll, pitch, yaw


def _quaternion(rotation: np.ndarray) -> tuple[float, float, float, float]:
    """Unit quaternion (W X Y Z, W >= 0) of a rotation matrix (Shepperd's method)."""
    r = np.asarray(rotation, dtype=float)
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(1.0 + trace)
        w, x, y, z = (
            0.25 * s,
            (r[2, 1] - r[1, 2]) / s,
            (r[0, 2] - r[2, 0]) / s,
            (r[1, 0] - r[0, 1]) / s,
        )
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        w, x, y, z = (
            (r[2, 1] - r[1, 2]) / s,
            0.25 * s,
            (r[0, 1] + r[1, 0]) / s,
            (r[0, 2] + r[2, 0]) / s,
        )
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        w, x, y, z = (
            (r[0, 2] - r[2, 0]) / s,
            (r[0, 1] + r[1, 0]) / s,
            0.25 * s,
            (r[1, 2] + r[2, 1]) / s,
        )
    else:
        s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        w, x, y, z = (
            (r[1, 0] - r[0, 1]) / s,
            (r[0, 2] + r[2, 0]) / s,
            (r[1, 2] + r[2, 1]) / s,
            0.25 * s,
        )
    sign = -1.0 if w < 0.0 else 1.0
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    return sign * w / norm, sign * x / norm, sign * y / norm, sign * z / norm


def _fixed(name: str, matrix: np.ndarray) -> list[str]:
    """The ``[name]`` section: ``xyz`` and ``rpy``, or ``quat_wxyz`` when rpy loses digits.

    Near pitch +-90 deg roll and yaw are ill-conditioned: the quaternion keeps every digit.
    """
    if np.array_equal(matrix, np.eye(4)):
        return []
    xyz = ", ".join(_number(v) for v in matrix[:3, 3])
    rotation = matrix[:3, :3]
    rpy = _rpy(rotation)
    if np.abs(_rpy_matrix(rpy) - rotation).max() <= 1e-15:
        return ["", f"[{name}]", f"xyz = [{xyz}]", f"rpy = [{', '.join(map(_number, rpy))}]"]
    quat = ", ".join(_number(v) for v in _quaternion(rotation))
    return ["", f"[{name}]", f"xyz = [{xyz}]", f"quat_wxyz = [{quat}]"]


def _rpy_matrix(rpy: tuple[float, float, float]) -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)``."""
    from .transforms import xyz_rpy

    return xyz_rpy((0.0, 0.0, 0.0), rpy)[:3, :3]


def _meshes(key: str, meshes: tuple[LinkMesh, ...], folder: Path | None) -> list[str]:
    """The ``[[key]]`` entries of ``meshes``: file relative to ``folder`` (None: absolute)."""
    lines = []
    for mesh in meshes:
        origin = np.asarray(mesh.origin)
        lines += [
            f"[[{key}]]",
            f"file = {_string(mesh_name(mesh.file, folder))}",
            f"xyz = [{', '.join(map(_number, origin[:3, 3]))}]",
            f"rpy = [{', '.join(map(_number, _rpy(origin[:3, :3])))}]",
            f"scale = [{', '.join(map(_number, mesh.scale))}]",
        ]
        if mesh.use != "both":
            lines.append(f"use = {_string(mesh.use)}")
    return lines


def _row_extras(row: DHRow, folder: Path | None = None) -> list[str]:
    """The row's optional keys it states: limits of motion, mass and body (link volumes, meshes).

    Keys the row leaves out stay out, so that reading the text gives the same defaults.
    """
    lines = []
    for key in ("acceleration", "mass", "radius", "radius_a", "radius_d"):
        value = getattr(row, key)
        if value is not None:
            lines.append(f"{key} = {_number(value)}")
    for housing in row.housings:
        lines += [
            "[[joints.housing]]",
            f"from = [{', '.join(map(_number, housing.start))}]",
            f"to = [{', '.join(map(_number, housing.end))}]",
            f"radius = {_number(housing.radius)}",
        ]
    for contact in row.allowed_contacts:
        lines += [
            "[[joints.allow_contact]]",
            f"row = {contact.row}",
            f"reason = {_string(contact.reason)}",
        ]
    return lines + _meshes("joints.mesh", row.meshes, folder)


def table_text(table: DHTable, header: str = "", mesh_folder: str | Path | None = None) -> str:
    """The TOML text of ``table`` (SI units); ``header`` becomes leading ``#`` comment lines.

    Mesh files are written relative to ``mesh_folder`` (the table file's folder), or absolute.
    """
    folder = None if mesh_folder is None else Path(mesh_folder)
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    lines += [
        f"name = {_string(table.name)}",
        f"description = {_string(table.description)}",
        f"source = {_string(table.source)}",
        f"convention = {_string(table.convention)}",
        'length_unit = "m"',
        'angle_unit = "rad"',
    ]
    for row in table.rows:
        lines += [
            "",
            "[[joints]]",
            f"name = {_string(row.name)}",
            f"type = {_string(row.joint_type)}",
            f"a = {_number(row.a)}",
            f"alpha = {_number(row.alpha)}",
            f"d = {_number(row.d)}",
            f"theta = {_number(row.theta)}",
        ]
        if row.beta != 0.0:  # Hayati's tilt (dh2urdf.dh_table): plain DH rows leave it out
            lines.append(f"beta = {_number(row.beta)}")
        lines += [
            f"limits = [{_number(row.lower)}, {_number(row.upper)}]",
            f"velocity = {_number(row.velocity)}",
            f"effort = {_number(row.effort)}",
        ]
        if row.continuous:
            lines.append("continuous = true")
        if row.direction != 1:
            lines.append(f"direction = {row.direction}")
        lines += _row_extras(row, folder)
    lines += _fixed("base", np.asarray(table.T_world_base))
    lines += _fixed("tool", np.asarray(table.T_last_tool))
    if table.base_meshes:
        lines += ["", *_meshes("base_mesh", table.base_meshes, folder)]
    if table.states:
        lines += ["", "[states]"]
        lines += [f"{s.name} = [{', '.join(map(_number, s.q))}]" for s in table.states]
    return "\n".join(lines) + "\n"


def write_table(table: DHTable, path: str | Path, header: str = "") -> None:
    """Write ``table`` to ``path`` whole or not at all (:func:`dh2urdf.output_file.write_atomic`).

    Raises:
        OutputFileError: ``path`` is a device, FIFO, socket or folder, or its folder is missing.
        OutputWriteError: The disk filled up (or another I/O error) part-way; nothing was written.
    """
    from .output_file import write_text_atomic

    folder = Path(path).resolve().parent
    write_text_atomic(path, table_text(table, header, folder))
