"""The kinematic URDF of a DH table: links, joints and inertials, no drawing; no yourdfpy.

:func:`kinematic_urdf` writes the tree of :func:`dh2urdf.urdf_writer.urdf_string` (the same links
and joints in the same order, the same origins, limits and inertials, from the same elements,
:func:`dh2urdf.urdf_writer.urdf_elements`) without its visuals, collision geometry and materials:
the smallest text Pinocchio builds the same model from. Neither writer imports yourdfpy or trimesh
(0.7 s), so a model built from a table file (``kin fk --robot my_arm.toml``) starts as fast as a
shipped one; the tests compare the two models frame by frame on every shipped table.
"""

from __future__ import annotations

import dataclasses

from .dh_table import DHTable
from .urdf_elements import robot_xml
from .urdf_writer import JOINT_RADIUS, LINK_MASS, SEGMENT_RADIUS, urdf_elements

__all__ = ["JOINT_RADIUS", "LINK_MASS", "SEGMENT_RADIUS", "kinematic_urdf"]


def kinematic_urdf(table: DHTable) -> str:
    """The URDF text of ``table`` for building a model: the full writer's tree, no geometry."""
    robot = urdf_elements(table)
    bare = tuple(dataclasses.replace(link, visuals=(), collisions=()) for link in robot.links)
    return robot_xml(dataclasses.replace(robot, links=bare, materials=()))
