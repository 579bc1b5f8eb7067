"""The URDF of a DH table as a yourdfpy model, validated by yourdfpy (:func:`build_urdf`).

For yourdfpy's own tools (scene graph, meshes, its validation) and for tests that check the text of
:func:`dh2urdf.urdf_writer.urdf_string` against yourdfpy's writer. yourdfpy (and trimesh, which it
imports: about 0.7 s) is imported inside the functions, only when a model is asked for.
"""

from __future__ import annotations

from typing import Any

from .dh_table import DHTable
from .exceptions import UrdfBuildError
from .urdf_elements import Box, Cylinder, Material, Mesh
from .urdf_writer import urdf_elements

__all__ = ["build_urdf"]


def _yourdfpy_geometry(geometry: Any) -> Any:
    import yourdfpy

    if isinstance(geometry, Cylinder):
        return yourdfpy.Geometry(
            cylinder=yourdfpy.Cylinder(radius=geometry.radius, length=geometry.length)
        )
    if isinstance(geometry, Box):
        return yourdfpy.Geometry(box=yourdfpy.Box(size=geometry.size))
    if isinstance(geometry, Mesh):
        mesh = yourdfpy.Mesh(filename=geometry.filename, scale=list(geometry.scale))
        return yourdfpy.Geometry(mesh=mesh)
    return yourdfpy.Geometry(sphere=yourdfpy.Sphere(radius=geometry.radius))


def _yourdfpy_material(material: Material | None) -> Any:
    import yourdfpy

    if material is None:
        return None
    return yourdfpy.Material(name=material.name, color=yourdfpy.Color(material.rgba))


def build_urdf(table: DHTable) -> Any:
    """The URDF of a DH table as a yourdfpy model, validated by yourdfpy (imports yourdfpy).

    For reading the model with yourdfpy's tools; building a kinematic model needs only the text
    (:func:`dh2urdf.urdf_writer.urdf_string`), which does not import yourdfpy. The elements are
    the text's (:func:`dh2urdf.urdf_writer.urdf_elements`); this module stands above the writer.

    Args:
        table: The DH table (SI units).

    Returns:
        The yourdfpy model, without scene graph or meshes.

    Raises:
        UrdfBuildError: yourdfpy's validation rejects the model.
    """
    import yourdfpy

    robot = urdf_elements(table)
    links = [
        yourdfpy.Link(
            name=link.name,
            inertial=None
            if link.inertial is None
            else yourdfpy.Inertial(
                origin=link.inertial.origin, mass=link.inertial.mass, inertia=link.inertial.inertia
            ),
            visuals=[
                yourdfpy.Visual(
                    name=v.name,
                    origin=v.origin,
                    geometry=_yourdfpy_geometry(v.geometry),
                    material=_yourdfpy_material(v.material),
                )
                for v in link.visuals
            ],
            collisions=[
                yourdfpy.Collision(
                    name=c.name, origin=c.origin, geometry=_yourdfpy_geometry(c.geometry)
                )
                for c in link.collisions
            ],
        )
        for link in robot.links
    ]
    joints = [
        yourdfpy.Joint(
            name=joint.name,
            type=joint.type,
            parent=joint.parent,
            child=joint.child,
            origin=joint.origin,
            axis=joint.axis,
            limit=None
            if joint.limit is None
            else yourdfpy.Limit(
                effort=joint.limit.effort,
                velocity=joint.limit.velocity,
                lower=joint.limit.lower,
                upper=joint.limit.upper,
            ),
        )
        for joint in robot.joints
    ]
    model = yourdfpy.URDF(
        robot=yourdfpy.Robot(
            name=robot.name,
            links=links,
            joints=joints,
            materials=[_yourdfpy_material(m) for m in robot.materials],
        ),
        build_scene_graph=False,
        load_meshes=False,
    )
    if not model.validate():
        raise UrdfBuildError(
            f"{table.path or table.name}: the generated URDF is invalid: {model.errors}"
        )
    return model
