"""A mesh file's vertices, read and checked before coal's convex hull (qhull) sees them.

coal 3.0.3's ``buildConvexHull`` (qhull) kills the process (SIGSEGV) on a flat or collinear
mesh, on NaN, infinite or 1e308 vertices, on subnormal sizes and on a small mesh far from its
origin; on 2 million triangles it runs for minutes in C, where Ctrl-C is not seen. So:

- the file is opened as every input is (:mod:`dh2urdf.input_file`): a regular file, at most
  :data:`MAX_MESH_BYTES`, a folder, FIFO, device or link loop named as what it is;
- an STL (binary or ASCII) is read here with NumPy: its header gives the triangle count, checked
  against the file size before any triangle is read, and coal's loader (which builds a bounding
  volume tree of every triangle, and prints Eigen's complaints on NaN) is not called; another
  format (DAE, OBJ, ...) goes through coal's assimp loader, bounded by the same size cap, its
  C-level complaints captured;
- the scaled vertices must be finite, within :data:`MAX_COORDINATE` of the mesh origin, at
  most :data:`MAX_MESH_VERTICES` distinct ones (a larger mesh is refused, not simplified: a
  simplified mesh would no longer be enclosed by its hull), and span a solid: the extent along
  the thinnest principal axis of the centred vertices (a rank test) must reach
  :func:`flatness_tolerance`. Below it qhull crashed in every trial.

Errors are :class:`OSError` with one line: the reason, without coal's C++ source location.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from dh2urdf.input_file import open_input, read_input

from . import bounds

__all__ = [
    "MAX_COORDINATE",
    "MAX_MESH_BYTES",
    "MAX_MESH_VERTICES",
    "MIN_THICKNESS",
    "ROUNDOFF_RATIO",
    "THICKNESS_RATIO",
    "checked_vertices",
    "flatness_tolerance",
    "loader_reason",
    "mesh_vertices",
]

#: Largest mesh file read [bytes]: 32 MiB. The largest mesh of example-robot-data (go1's
#: trunk.dae, 29 MB, 175,000 vertices) loads in about 4 s on a busy 2-core machine; a larger
#: file would keep the process in C (deaf to Ctrl-C) for longer than a command's answer is worth.
MAX_MESH_BYTES = 32 * 2**20
#: Most distinct vertices of a mesh [vertices], above that 175,000: qhull of 200,000 points
#: on a sphere (its worst case, every point on the hull) takes about 2 s.
MAX_MESH_VERTICES = 200_000
#: Largest vertex coordinate after scaling, from the mesh's origin [m]: a shape's placement bound.
MAX_COORDINATE = bounds.MAX_COORDINATE
#: Thinnest extent of a mesh, relative to its longest [-]. qhull crashed on slabs of 1e-7 in
#: trials and built hulls from 1e-6 on: 1e-5 leaves a margin of a hundred.
THICKNESS_RATIO = 1e-5
#: Thinnest extent relative to the largest coordinate [-]: qhull's round-off grows with the
#: coordinates; a 1e-8 m thin mesh 1e6 m from its origin crashed it, 1e-7 m did not.
ROUNDOFF_RATIO = 1e-11
#: Thinnest extent of a mesh in any case [m]: subnormal sizes crashed qhull; nothing a robot or
#: a cell is modelled with is a nanometre thin.
MIN_THICKNESS = 1e-9

# A binary STL: an 80-byte header, a triangle count, then 50 bytes per triangle.
_STL_TRIANGLE = np.dtype([("normal", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("flags", "<u2")])
_STL_VERTEX = re.compile(rb"^[ \t]*vertex[ \t]+(\S+)[ \t]+(\S+)[ \t]+(\S+)", re.MULTILINE)
_DECIMATE = "simplify (decimate) the mesh: a convex hull needs few vertices"
_SHAPES = ("at one point", "on one line", "in one plane")


def mesh_vertices(path: Path, scale: np.ndarray) -> np.ndarray:
    """The distinct vertices of the mesh file ``path``, scaled, checked for a convex hull.

    Args:
        path: An STL, DAE, OBJ... file.
        scale: Factors per axis applied to the file's coordinates (3,) [m per file unit].

    Returns:
        The distinct vertices (n, 3) [m], 4 <= n <= :data:`MAX_MESH_VERTICES`.

    Raises:
        OSError: The file cannot be read (missing, not a regular file, too large, not a mesh),
            or its vertices are not finite, too far, too many, or do not span a solid.
    """
    if path.suffix.lower() == ".stl":
        vertices = _stl_vertices(read_input(path, MAX_MESH_BYTES, _DECIMATE))
    else:
        open_input(path, MAX_MESH_BYTES, _DECIMATE).close()  # a regular file of bounded size
        vertices = _loaded_vertices(path)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is found as not finite
        scaled = vertices * np.asarray(scale, dtype=float)
    return checked_vertices(scaled)


def checked_vertices(vertices: np.ndarray) -> np.ndarray:
    """The distinct rows of ``vertices`` (n, 3) [m], or OSError saying why qhull cannot take them."""
    if len(vertices) == 0:
        raise OSError("no triangles")
    bad = ~np.isfinite(vertices).all(axis=1)
    if bad.any():
        index = int(np.argmax(bad))
        raise OSError(
            f"vertex {index + 1} of {len(vertices)} is not finite after scaling: "
            f"{_point(vertices[index])}"
        )
    far = np.abs(vertices).max(axis=1) > MAX_COORDINATE
    if far.any():
        index = int(np.argmax(far))
        raise OSError(
            f"vertex {index + 1} of {len(vertices)} is {_point(vertices[index])} m after "
            f"scaling, beyond {MAX_COORDINATE:g} m from the mesh origin; check the scale"
        )
    distinct = np.unique(vertices, axis=0)
    if len(distinct) > MAX_MESH_VERTICES:
        raise OSError(
            f"{len(distinct):,} distinct vertices, more than the {MAX_MESH_VERTICES:,} a "
            f"convex hull is built from; {_DECIMATE}"
        )
    centred = distinct - distinct.mean(axis=0)
    axes = np.linalg.svd(centred, full_matrices=False)[2]
    extents = np.ptp(centred @ axes.T, axis=0)  # along the principal axes, longest first
    tolerance = flatness_tolerance(float(extents.max()), float(np.abs(distinct).max()))
    if extents[0] > bounds.MAX_SIZE:
        raise OSError(
            f"{extents[0]:.6g} m long after scaling, more than the {bounds.MAX_SIZE:g} m a "
            "collision shape may measure (kin.collision.bounds); check the scale"
        )
    rank = int((extents > tolerance).sum())
    if rank < 3:  # (fewer than 4 distinct vertices are always so)
        raise OSError(
            f"not a solid: its {len(distinct)} distinct vertices lie {_SHAPES[rank]}, extents "
            f"{_point(extents)} m where a convex hull needs {tolerance:.3g} m in each "
            "direction; make a plate a box, a rod a cylinder"
        )
    return distinct


def flatness_tolerance(length: float, largest: float) -> float:
    """The thinnest extent [m] qhull is given, whichever bound is largest.

    Args:
        length: The mesh's longest extent [m] (times :data:`THICKNESS_RATIO`).
        largest: Its largest coordinate magnitude [m] (times :data:`ROUNDOFF_RATIO`).

    Returns:
        That, or :data:`MIN_THICKNESS` if larger [m].
    """
    return max(THICKNESS_RATIO * length, ROUNDOFF_RATIO * largest, MIN_THICKNESS)


def _point(values: np.ndarray) -> str:
    return " ".join(f"{v:.3g}" for v in values)


def _stl_vertices(raw: bytes) -> np.ndarray:
    """Every triangle corner of an STL file's bytes (3 per triangle) [file units]."""
    if len(raw) >= 84:
        count = int.from_bytes(raw[80:84], "little")
        if len(raw) == 84 + 50 * count:  # binary, whatever its header says ("solid" too)
            triangles = np.frombuffer(raw, _STL_TRIANGLE, count=count, offset=84)
            return triangles["vertices"].reshape(-1, 3).astype(float)
    if not raw.lstrip().startswith(b"solid"):
        if len(raw) < 84:
            raise OSError(f"not an STL file: {len(raw)} bytes, not 'solid ...' text")
        count = int.from_bytes(raw[80:84], "little")
        raise OSError(
            f"not an STL file: not 'solid ...' text, nor binary: its header's {count:,} "
            f"triangles need {84 + 50 * count:,} bytes, the file has {len(raw):,}"
        )
    words = _STL_VERTEX.findall(raw)
    try:
        return np.array(words, dtype=np.bytes_).astype(float).reshape(-1, 3)
    except ValueError:
        bad = next(w for row in words for w in row if not _is_float(w))
        raise OSError(f"not an STL file: vertex coordinate {bad[:40]!r} is not a number") from None


def _is_float(word: bytes) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def _loaded_vertices(path: Path) -> np.ndarray:
    """The vertices coal's assimp loader reads from ``path`` [file units]."""
    import coal

    from dh2urdf.urdf_parse import captured_stderr

    mesh, error, _ = captured_stderr(lambda: coal.MeshLoader().load(str(path), np.ones(3)))
    if error is not None:
        raise OSError(loader_reason(str(error))) from error
    return np.array(mesh.vertices(), dtype=float).reshape(-1, 3)


def loader_reason(text: str) -> str:
    """The one line of coal loader error ``text``: its message, not its C++ source location."""
    said = text.partition("message:")[2] or text
    lines = [line.strip() for line in said.splitlines()]
    kept = [
        line
        for line in lines
        if line and not line.startswith(("Could not load resource", "Hint:", "From file:"))
    ]
    return "; ".join(kept) or "coal's loader cannot read it"
