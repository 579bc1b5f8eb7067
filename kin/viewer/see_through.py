"""A DH arm's body drawn see-through where it would hide the joints and the frame triads.

A DH table's URDF draws each joint as an orange cylinder of radius
:data:`dh2urdf.urdf_writer.JOINT_RADIUS` along its axis, and the preview puts the DH frames'
triads at the same places. Fitted link volumes (a row's ``radius``, its ``[[joints.housing]]``)
are wider than that marker and enclose it: drawn opaque, they hide every joint axis and triad,
which are what a reader of a DH table looks for. The meshes a table names (``[[joints.mesh]]``,
``[[base_mesh]]``: the maker's body, drawn beside the row's volumes) enclose them the same way.
Those body pieces are drawn with :data:`BODY_OPACITY` instead: the body keeps its true size (the
one collisions are checked with), and the joints and frames show through it. Pieces no wider than
the marker (the 1 cm default sticks) stay opaque, so a thin arm does not fade.
"""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin

from dh2urdf.urdf_writer import JOINT_RADIUS

__all__ = ["BODY_OPACITY", "see_through_body"]

#: Alpha of the body pieces wider than a joint marker (1 opaque, 0 invisible).
BODY_OPACITY = 0.45
#: Mesh files a table may name (lower case).
MESH_SUFFIXES = (".stl", ".dae", ".obj")


def see_through_body(
    visual_model: pin.GeometryModel, opacity: float = BODY_OPACITY
) -> tuple[str, ...]:
    """Give every round body piece wider than a joint marker, and every mesh, the alpha ``opacity``.

    Round pieces are the cylinders, spheres and capsules of the DH drawing; meshes are the
    table's (STL, COLLADA, OBJ files), whose own COLLADA materials give way to ``meshColor`` (the
    URDF's, which carries the alpha). Call it before the model is loaded into meshcat
    (Pinocchio's visualizer reads the alpha of ``meshColor``); the model changes in place.

    Args:
        visual_model: Visual geometry of a robot drawn from its DH table's URDF.
        opacity: Alpha given to the pieces [0, 1].

    Returns:
        The names of the geometry objects made see-through.
    """
    changed = []
    for obj in visual_model.geometryObjects:
        shape = obj.geometry
        round_shape = isinstance(shape, coal.Cylinder | coal.Sphere | coal.Capsule)
        mesh = obj.meshPath.lower().endswith(MESH_SUFFIXES)
        if mesh or (round_shape and shape.radius > JOINT_RADIUS + 1e-9):
            color = np.array(obj.meshColor, dtype=float)
            color[3] = min(color[3], opacity)
            obj.meshColor = color
            obj.overrideMaterial = True  # a COLLADA file's own materials would stay opaque
            changed.append(obj.name)
    return tuple(changed)
