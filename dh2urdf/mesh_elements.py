"""A DH table's meshes as URDF ``<visual>`` and ``<collision>`` elements of its links.

Each :class:`~dh2urdf.link_meshes.LinkMesh` of a row goes on the link that moves with DH frame
``i`` (``link{i}`` in a standard table, ``frame{i}`` in a modified one), each of ``[[base_mesh]]``
on ``frame0``, its origin the table's ``T_frame_mesh`` carried into that link's frame. The file
is named by its absolute path, or relative to the folder the URDF is written to
(``mesh_folder``), where the URDF's readers look for a relative name.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .link_meshes import LinkMesh, mesh_name
from .transforms import clean
from .urdf_elements import Collision, Material, Mesh, Visual

__all__ = ["MESH_MATERIAL", "mesh_elements"]

#: Colour of a table's meshes (a light grey, as the preview draws a maker's collision meshes).
MESH_MATERIAL = Material(name="mesh", rgba=np.array([0.72, 0.74, 0.78, 1.0]))


def mesh_elements(
    meshes: Sequence[LinkMesh],
    T_link_frame: np.ndarray,
    prefix: str,
    mesh_folder: str | Path | None = None,
) -> tuple[list[Visual], list[Collision]]:
    """The visuals and collisions of ``meshes`` fixed in a DH frame placed at ``T_link_frame``.

    Args:
        meshes: The meshes, each with its ``T_frame_mesh`` [m].
        T_link_frame: The DH frame in the link that carries it (4x4, [m]).
        prefix: Element names are ``{prefix}_{n}`` (``mesh3_0``: row 3's first mesh).
        mesh_folder: Write file names relative to this folder; None: absolute.
    """
    visuals: list[Visual] = []
    collisions: list[Collision] = []
    for n, mesh in enumerate(meshes):
        origin = clean(np.asarray(T_link_frame, dtype=float) @ mesh.origin)
        geometry = Mesh(filename=mesh_name(mesh.file, mesh_folder), scale=mesh.scale)
        name = f"{prefix}_{n}"
        if mesh.visual:
            visuals.append(Visual(name, origin, geometry, MESH_MATERIAL))
        if mesh.collision:
            collisions.append(Collision(f"{name}_collision", origin, geometry))
    return visuals, collisions
