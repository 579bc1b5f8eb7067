"""Meshes a DH table names for its links: a file, where it sits in a DH frame, its scale.

A row's ``[[joints.mesh]]`` entries are fixed in DH frame ``i`` (the frame the row ends in, which
moves with joint ``i``, as its housings are); the table's ``[[base_mesh]]`` entries in DH frame
0 (the base). The URDF the writer emits carries each as a ``<mesh>`` of the link that moves with
that frame, in its ``<visual>`` and ``<collision>`` elements (or one of them, ``use``), beside the
row's stated volumes; a body with a collision mesh drops its default 1 cm sticks from the
collision elements (:mod:`dh2urdf.urdf_writer`).

Table syntax (``xyz`` in the table's ``length_unit``, ``rpy`` in its ``angle_unit``)::

    [[joints.mesh]]                # optional, any number; [[base_mesh]] for DH frame 0
    file = "meshes/forearm.stl"    # relative to the table file's folder, or absolute
    xyz = [0.0, 0.0, 0.0]          # the mesh's origin in DH frame i
    rpy = [0.0, 0.0, 0.0]          # URDF roll-pitch-yaw (about fixed x, then y, then z)
    scale = 0.001                  # meters per file unit: a number or [x, y, z] (default 1)
    use = "both"                   # "both" (default), "collision" or "visual"

The file must be an STL, COLLADA (``.dae``) or OBJ mesh: the formats coal's loader (collisions),
meshcat (the preview) and Pinocchio read. It is checked when the table is read (a regular file,
its content of that format), so a table that loads names meshes the URDF's readers can open.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .exceptions import TableError
from .input_file import open_input
from .quoted_input import quoted
from .table_values import length as _length
from .table_values import number as _number
from .table_values import xml_text as _xml_text
from .transforms import xyz_rpy
from .units import angle_to_radians

__all__ = ["MESH_SUFFIXES", "MESH_USES", "LinkMesh", "mesh_name", "parse_meshes"]

#: Mesh formats a table may name (file suffix, lower case).
MESH_SUFFIXES = (".dae", ".obj", ".stl")
#: Which URDF elements carry a mesh.
MESH_USES = ("both", "collision", "visual")
#: Largest scale factor [m per file unit]: 1 km per unit is no robot's mesh.
MAX_SCALE = 1e3

_KEYS = {"file", "xyz", "rpy", "scale", "use"}
#: Bytes read from the start of a mesh to tell its format.
_HEAD = 65536


@dataclass(frozen=True, eq=False)
class LinkMesh:
    """A mesh fixed in a DH frame.

    Attributes:
        file: The mesh file, an absolute path.
        origin: ``T_frame_mesh``: the mesh's origin in its DH frame (4x4, [m]).
        scale: Factors applied to the file's coordinates, per axis [m per file unit] (3,).
        use: ``"both"``, ``"collision"`` or ``"visual"``: the URDF elements that carry it.
    """

    file: str
    origin: np.ndarray
    scale: tuple[float, float, float]
    use: str = "both"

    @property
    def collision(self) -> bool:
        """Whether the mesh is collision geometry."""
        return self.use in ("both", "collision")

    @property
    def visual(self) -> bool:
        """Whether the mesh is drawn."""
        return self.use in ("both", "visual")


def parse_meshes(
    path: str, entries: Any, row: int | None, key: str, meters: float, radians: float
) -> tuple[LinkMesh, ...]:
    """The meshes of ``entries`` (a row's ``mesh`` list, or the table's ``base_mesh``).

    Args:
        path: The table file: errors name it, relative files are read from its folder.
        entries: The list as read from TOML.
        row: The row (1-based), or None for ``base_mesh``.
        key: ``"mesh"`` or ``"base_mesh"``, for errors.
        meters: Meters per length unit of the table.
        radians: Radians per angle unit of the table.

    Raises:
        TableError: One line naming the table, the row and the key: not a list of tables, an
            unknown key, a missing or unreadable file, a file that is not an STL, DAE or OBJ
            mesh, a scale that is not a positive finite number, a malformed ``xyz``/``rpy``.
    """
    if not isinstance(entries, list):
        raise TableError(path, f"expected [[{key}]] tables, got {quoted(entries)}", row, key)
    return tuple(
        _mesh(path, entry, row, f"{key}[{n}]", meters, radians) for n, entry in enumerate(entries)
    )


def _mesh(
    path: str, entry: Any, row: int | None, key: str, meters: float, radians: float
) -> LinkMesh:
    if not isinstance(entry, dict) or "file" not in entry or not set(entry) <= _KEYS:
        raise TableError(
            path,
            f"expected a table of file and optional xyz, rpy, scale, use, got {quoted(entry)}",
            row,
            key,
        )
    file = _file(path, entry["file"], row, f"{key}.file")
    vectors = []
    for side, factor in (("xyz", meters), ("rpy", radians)):
        vector = entry.get(side, [0.0, 0.0, 0.0])
        if not isinstance(vector, list) or len(vector) != 3:
            raise TableError(
                path, f"expected [x, y, z], got {quoted(vector)}", row, f"{key}.{side}"
            )
        if side == "xyz":
            vectors.append(tuple(_length(path, v, row, f"{key}.xyz", factor) for v in vector))
        else:
            values = (_number(path, v, row, f"{key}.rpy") for v in vector)
            vectors.append(tuple(angle_to_radians(v, factor) for v in values))
    use = entry.get("use", "both")
    if use not in MESH_USES:
        raise TableError(
            path, f"expected one of {', '.join(MESH_USES)}, got {quoted(use)}", row, f"{key}.use"
        )
    origin = xyz_rpy(vectors[0], vectors[1])  # type: ignore[arg-type]
    return LinkMesh(file, origin, _scale(path, entry.get("scale", 1.0), row, f"{key}.scale"), use)


def _scale(path: str, value: Any, row: int | None, key: str) -> tuple[float, float, float]:
    values = value if isinstance(value, list) else [value]
    if len(values) not in (1, 3):
        raise TableError(path, f"expected a number or [x, y, z], got {quoted(value)}", row, key)
    for v in values:
        if isinstance(v, bool) or not isinstance(v, int | float) or not 0.0 < v <= MAX_SCALE:
            raise TableError(
                path,
                f"expected a positive finite scale of at most {MAX_SCALE:g} m per file unit, "
                f"got {quoted(value)}",
                row,
                key,
            )
    floats = [float(v) for v in values]
    return (floats[0],) * 3 if len(floats) == 1 else (floats[0], floats[1], floats[2])


def _file(path: str, value: Any, row: int | None, key: str) -> str:
    """The absolute path of a mesh file the table names, checked to be a mesh of its suffix."""
    if not isinstance(value, str) or not value.strip() or "\x00" in value:
        raise TableError(path, f"expected a file name, got {quoted(value)}", row, key)
    _xml_text(path, value, row, key)  # the URDF names it
    file = Path(value).expanduser()
    if not file.is_absolute():
        folder = Path(path).parent if path != "<string>" else Path.cwd()
        file = folder / file
    file = Path(_absolute(file))
    suffix = file.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise TableError(
            path,
            f"{quoted(value)} is not a mesh file: give a {', '.join(MESH_SUFFIXES)} file",
            row,
            key,
        )
    try:
        with open_input(file, limit=2**62) as handle:  # the size is the collision model's check
            head = handle.read(_HEAD)
            size = handle.seek(0, 2)
    except FileNotFoundError:
        raise TableError(path, f"mesh not found: {file}", row, key) from None
    except OSError as err:
        raise TableError(path, f"cannot read the mesh {file} ({err.strerror})", row, key) from None
    problem = _format_problem(suffix, head, size)
    if problem is not None:
        raise TableError(path, f"{file} is not a{problem}", row, key)
    return str(file)


def mesh_name(file: str, folder: str | Path | None) -> str:
    """How a written file (table, URDF) in ``folder`` names the mesh ``file`` (absolute path).

    Relative to ``folder`` (``/`` separators) when the two share a folder below the file
    system's root; else, or without a folder, the absolute path.
    """
    if folder is None:
        return Path(file).as_posix()
    folder = _absolute(Path(folder))
    if os.path.commonpath([file, folder]) == os.path.dirname(os.path.abspath(os.sep)):
        return Path(file).as_posix()
    return Path(os.path.relpath(file, folder)).as_posix()


def _absolute(file: Path) -> str:
    """``file`` made absolute without resolving links (``..`` folded)."""
    return os.path.normpath(os.path.abspath(file))


def _format_problem(suffix: str, head: bytes, size: int) -> str | None:
    """What the file's first bytes say it is not (``"n STL mesh ..."``), or None when it looks right."""
    if suffix == ".stl":
        if head.lstrip()[:5].lower() == b"solid" and b"facet" in head.lower():
            return None  # ASCII STL
        if size >= 84 and len(head) >= 84:
            triangles = int.from_bytes(head[80:84], "little")
            if triangles > 0 and 84 + 50 * triangles == size:
                return None  # binary STL: its header's triangle count fits the file's size
        return "n STL mesh (neither ASCII 'solid ... facet' nor a binary STL of its size)"
    if suffix == ".dae":
        return None if b"<COLLADA" in head else " COLLADA mesh (no <COLLADA> element)"
    text = head.decode("utf-8", errors="replace")
    vertices = [line for line in text.splitlines() if line.startswith("v ")]
    if vertices and all(_numbers(line.split()[1:4]) for line in vertices[:3]):
        return None
    return "n OBJ mesh (no 'v x y z' vertex line at its start)"


def _numbers(words: list[str]) -> bool:
    try:
        return len(words) == 3 and all(math.isfinite(float(word)) for word in words)
    except ValueError:
        return False
