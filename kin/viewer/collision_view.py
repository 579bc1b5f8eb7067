"""Collision overlays of a :class:`~kin.viewer.RobotViewer`: the cell, red links, the closest pair.

Scene objects (a collision model's, read by ``kin.collision.scene.read_scene``) go under
``scene/cell/<name>`` in a neutral grey (those in collision in :data:`COLLISION_RGB`), each
node's transform its world placement; a mesh object is drawn as the convex hull the collision
queries use. The objects attached to a link (``model.attached``) go under
``scene/attached/<name>`` in :data:`ATTACHED_RGB` (red when in collision), the shapes the queries
use, and ride on their link in every configuration shown (:mod:`.riders`). A colliding link's
visual geometries are drawn again, in place, in :data:`COLLISION_RGB`. The closest pair is a rod between its two witness points with a ball on
each, under ``scene/markers/closest``, thick enough to be seen in a picture of the whole arm.
Lengths in meters, world frame (the arm's base).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin
from pinocchio.visualize.meshcat_visualizer import loadPrimitive

from dh2urdf.output_text import shown_name

from .camera_view import Obstacle
from .geometry_points import local_box
from .markers import draw_rod, draw_sphere, hex_color
from .riders import Rider
from .robot_viewer import RobotViewer

if TYPE_CHECKING:
    from ..collision import Closest, CollisionModel

__all__ = [
    "ATTACHED_OPACITY",
    "ATTACHED_RGB",
    "CLOSEST_RGB",
    "COLLISION_RGB",
    "SCENE_OPACITY",
    "SCENE_RGB",
    "link_nodes",
    "show_attached",
    "show_closest",
    "show_colliding_links",
    "show_scene",
]

#: Scene objects: a neutral grey (RGB in [0, 1]), see-through so a wall hides no link.
SCENE_RGB = (0.62, 0.62, 0.62)
SCENE_OPACITY = 0.35
#: Objects attached to a link: teal, unlike the grey cell, the sky-blue background, the red of a
#: collision, the magenta closest pair, the orange joints and the yellow target; nearly opaque,
#: so that a tool triad inside a held part still shows a little.
ATTACHED_RGB = (0.0, 0.62, 0.52)
ATTACHED_OPACITY = 0.85
#: Links in collision: pure red (no green or blue in any shade of it).
COLLISION_RGB = (1.0, 0.0, 0.0)
#: The closest pair's rod and end balls: magenta, unlike the sky-blue background, the grey
#: cell, the red of a collision, the orange joints and the yellow target.
CLOSEST_RGB = (0.9, 0.0, 0.9)
#: Their radii per arm length (:attr:`RobotViewer.arm_length`): a UR5 framed in an 800 x 600
#: picture draws the rod about 6 px thick.
CLOSEST_ROD_RADIUS = 0.008
CLOSEST_BALL_RADIUS = 0.02


def show_scene(viewer: RobotViewer, model: CollisionModel, colliding: Iterable[str] = ()) -> int:
    """Draw a collision model's scene objects: grey, or red for those named in ``colliding``.

    The shapes drawn are the ones checked (a mesh object as its convex hull), unpadded, each
    under ``scene/cell/<shape>`` with its world placement as the node's transform. Each one's
    box joins :attr:`RobotViewer.obstacles`: the camera looks at the arm past them.

    Args:
        viewer: The viewer.
        model: The collision model (``kin.collision.load_collision_model(..., scene=...)``).
        colliding: Scene objects in collision (``Contact.b`` of the contacts).

    Returns:
        The number of shapes drawn.
    """
    grey = mg.MeshLambertMaterial(
        color=hex_color(SCENE_RGB), opacity=SCENE_OPACITY, transparent=True
    )
    red = mg.MeshLambertMaterial(color=hex_color(COLLISION_RGB), opacity=0.6, transparent=True)
    scene, hit = set(model.scene_objects), set(colliding)
    drawn = 0
    for obj, owner in zip(model.geometry_model.geometryObjects, model.owners):
        if owner not in scene:
            continue
        node = viewer.scene["cell"][_node_name(obj.name.removeprefix("scene/"))]
        node.set_object(loadPrimitive(obj), red if owner in hit else grey)
        T = obj.placement.homogeneous
        node.set_transform(T)
        box = local_box(obj)
        if box is not None:
            viewer.obstacles.append(Obstacle(T, box.min(axis=0), box.max(axis=0)))
        drawn += 1
    return drawn


def show_attached(
    viewer: RobotViewer, model: CollisionModel, colliding: Iterable[str] = ()
) -> tuple[str, ...]:
    """Draw the objects attached to links: teal, or red for those named in ``colliding``.

    Each shape is the one checked (a mesh as its convex hull), unpadded, under
    ``scene/attached/<shape>``; it rides on the joint of ``viewer.robot.model`` that carries its
    link (:meth:`RobotViewer.add_rider`), so it moves with the arm in every configuration shown
    from now on: call it before :meth:`RobotViewer.show_path` for the animation to carry it.
    Called again (with the colliding objects), it redraws them in place.

    Args:
        viewer: The viewer of ``model.robot``.
        model: The collision model (its ``attached`` objects; ``kin.collision.load_collision_model``).
        colliding: Attached objects in collision (names from the contacts).

    Returns:
        The meshcat paths drawn.
    """
    things = {thing.name for thing in model.attached}
    hit = set(colliding)
    materials = {
        colour: mg.MeshLambertMaterial(
            color=hex_color(colour), opacity=ATTACHED_OPACITY, transparent=True
        )
        for colour in (ATTACHED_RGB, COLLISION_RGB)
    }
    drawn = []
    for obj, owner in zip(model.geometry_model.geometryObjects, model.owners):
        if owner not in things:
            continue
        node = f"scene/attached/{_node_name(obj.name)}"
        material = materials[COLLISION_RGB if owner in hit else ATTACHED_RGB]
        viewer.viewer[node].set_object(loadPrimitive(obj), material)
        corners = local_box(obj)
        viewer.add_rider(Rider(node, int(obj.parentJoint), obj.placement.homogeneous, corners))
        drawn.append(node)
    return tuple(drawn)


def link_nodes(viewer: RobotViewer, link: str) -> tuple[str, ...]:
    """Meshcat paths of the visual geometries the viewer draws for ``link``."""
    model = viewer.meshes.model if viewer.meshes is not None else viewer.robot.model
    return tuple(
        node
        for node, obj in zip(viewer.geometry_nodes, viewer.visual_model.geometryObjects)
        if model.frames[obj.parentFrame].name == link
    )


def show_colliding_links(viewer: RobotViewer, links: Iterable[str]) -> tuple[str, ...]:
    """Draw every visual geometry of ``links`` again, in place, in :data:`COLLISION_RGB`.

    Args:
        viewer: The viewer (its arm already displayed).
        links: Link names (``Contact.a`` / ``Contact.b`` of the arm's links).

    Returns:
        The meshcat paths redrawn in red.
    """
    wanted = set(links)
    model = viewer.meshes.model if viewer.meshes is not None else viewer.robot.model
    material = mg.MeshLambertMaterial(color=hex_color(COLLISION_RGB))
    redrawn = []
    for node, obj in zip(viewer.geometry_nodes, viewer.visual_model.geometryObjects):
        if model.frames[obj.parentFrame].name not in wanted:
            continue
        geometry = _drawable(obj)
        if geometry is None:
            continue
        viewer.viewer[node].set_object(geometry, material)
        redrawn.append(node)
    viewer.display(viewer.q)  # a new object takes its node's transform again in a live viewer
    return tuple(redrawn)


def show_closest(viewer: RobotViewer, closest: Closest, unit: str = "m", scale: float = 1.0) -> str:
    """Draw the closest pair: a rod between its witness points and a ball on each.

    Both are seen through whatever stands in front of them (a pair under the arm still shows).

    Args:
        viewer: The viewer.
        closest: The closest pair (``CollisionChecker.distance``; points in the world [m]).
        unit: Unit of the label's distance.
        scale: Meters per ``unit``.

    Returns:
        The label, e.g. ``closest: link3 / table 0.0412 m``.
    """
    a = np.asarray(closest.point_a, dtype=float)
    b = np.asarray(closest.point_b, dtype=float)
    node = viewer.scene["markers"]["closest"]
    node.delete()
    draw_rod(node["rod"], a, b, CLOSEST_ROD_RADIUS * viewer.arm_length, CLOSEST_RGB, on_top=True)
    for name, point in (("a", a), ("b", b)):
        draw_sphere(node[name], CLOSEST_BALL_RADIUS * viewer.arm_length, CLOSEST_RGB, on_top=True)
        node[name].set_transform(_translation(point))
    distance = float(closest.distance)
    pair = f"{shown_name(closest.a)} / {shown_name(closest.b)}"
    return f"closest: {pair} {distance / scale:.4f} {unit}"


def _drawable(obj: pin.GeometryObject) -> object | None:
    """A meshcat geometry of a visual object in its own frame (node scale applied by meshcat)."""
    import coal

    if isinstance(obj.geometry, coal.ShapeBase):
        return loadPrimitive(obj)
    suffix = obj.meshPath.rsplit(".", 1)[-1].lower() if obj.meshPath else ""
    loaders = {"stl": mg.StlMeshGeometry, "obj": mg.ObjMeshGeometry, "dae": mg.DaeMeshGeometry}
    if suffix in loaders:
        return loaders[suffix].from_file(obj.meshPath)
    return None


def _node_name(name: str) -> str:
    """A meshcat path element: no slash."""
    return name.replace("/", "_") or "object"


def _translation(point: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = point
    return T
