"""Mesh files as meshcat draws them readably: STL facets with normals, see-through COLLADA.

Pinocchio's ``MeshcatVisualizer`` sends a mesh file to the browser as it is. Two things then go
wrong in the picture:

- three.js lights an STL facet by the normal the file stores; many makers' STL files store zero
  normals (example-robot-data's UR and Panda collision meshes all do), and those meshes are drawn
  black, flat silhouettes that hide what they overlap. :func:`stl_with_normals` gives the file
  with each facet's normal computed from its vertices (counter-clockwise, as STL orders them).
- a COLLADA file is sent with its own materials, and ``meshColor``'s alpha is lost: a table's
  see-through mesh (:mod:`.see_through`) stayed opaque. A see-through COLLADA mesh is sent as
  meshcat's mesh geometry instead (the browser merges its pieces into one), drawn with the
  material of ``meshColor``.

:class:`ReadableMeshes` is Pinocchio's visualizer with both. Lengths as in the files (the node's
scale carries the URDF's ``scale``).
"""

from __future__ import annotations

import io
import re
from pathlib import Path

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin
from pinocchio.visualize import MeshcatVisualizer

__all__ = ["ReadableMeshes", "stl_with_normals"]

#: One facet of a binary STL file.
_FACET = np.dtype([("normal", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("attribute", "<u2")])
_VERTEX = re.compile(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)")


def stl_with_normals(path: str | Path) -> bytes:
    """A binary STL of the file's facets, each with its unit normal computed from its vertices.

    A facet without area keeps a zero normal. An ASCII STL is read by its ``vertex`` lines.

    Raises:
        OSError: The file cannot be read.
        ValueError: Not an STL file (a binary one of the wrong size, an ASCII one without facets).
    """
    data = Path(path).read_bytes()
    count = int.from_bytes(data[80:84], "little") if len(data) >= 84 else -1
    if count >= 0 and len(data) == 84 + _FACET.itemsize * count:
        vertices = np.frombuffer(data, _FACET, count, 84)["vertices"].astype(float)
    else:
        found = _VERTEX.findall(data)
        if not found or len(found) % 3:
            raise ValueError(f"{path}: not an STL file")
        vertices = np.array(found, dtype=float).reshape(-1, 3, 3)
    normals = np.cross(vertices[:, 1] - vertices[:, 0], vertices[:, 2] - vertices[:, 0])
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.divide(normals, lengths, out=np.zeros_like(normals), where=lengths > 0.0)
    facets = np.zeros(len(vertices), _FACET)
    facets["normal"], facets["vertices"] = normals, vertices
    header = b"kin: facet normals computed from the vertices".ljust(80, b" ")
    return header + len(facets).to_bytes(4, "little") + facets.tobytes()


class ReadableMeshes(MeshcatVisualizer):  # type: ignore[misc]
    """Pinocchio's meshcat visualizer, with STL normals and see-through COLLADA meshes."""

    def loadMeshFromFile(self, geometry_object: pin.GeometryObject) -> object:  # noqa: N802
        """The meshcat geometry of a mesh file (Pinocchio's, but for STL and see-through DAE)."""
        path = geometry_object.meshPath
        suffix = Path(path).suffix.lower()
        try:
            if suffix == ".stl":
                return mg.StlMeshGeometry.from_stream(io.BytesIO(stl_with_normals(path)))
            if suffix == ".dae" and float(geometry_object.meshColor[3]) < 1.0:
                return mg.DaeMeshGeometry.from_file(path)
        except (OSError, ValueError, UnicodeDecodeError):
            pass  # Pinocchio's own loading (and its warning)
        return super().loadMeshFromFile(geometry_object)
