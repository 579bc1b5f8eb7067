"""A MoveIt PlanningScene message (JSON, or YAML when PyYAML is installed) read as a scene.

Read, in moveit_msgs' field names (``docs/scenes.md`` shows a file):

- ``world.collision_objects``: each ``id`` is one scene object; ``header.frame_id`` must be the
  robot's base link or ``world`` (:func:`check_frames`: no transforms are looked up);
  ``pose`` (optional, the identity) places the object, and each of its ``primitives``
  (``type`` BOX 1, SPHERE 2, CYLINDER 3, or their names; ``dimensions`` as shape_msgs orders
  them: BOX [x, y, z], SPHERE [radius], CYLINDER [height, radius], along z) and ``meshes``
  (shape_msgs ``vertices`` and ``triangles``, or, beyond the message, ``file`` and ``scale`` as
  a TOML scene's ``[[mesh]]``) sits at ``pose * primitive_poses[i]`` (``mesh_poses[i]``). A pose
  is ``position`` {x, y, z} [m] and ``orientation`` {x, y, z, w}, normalised as MoveIt does
  (all zeros is the identity). Meshes enter as their convex hulls.
- ``allowed_collision_matrix``: ``entry_names``, ``entry_values[i].enabled[j]`` (true: the pair
  may touch, MoveIt's meaning) and ``default_entry_names``/``default_entry_values`` for pairs the
  matrix leaves out (both named: both must allow). Allowed link pairs and link-object pairs are
  not checked (reason ``"acm"``), as an SRDF's pairs.

Lengths are meters (ROS REP 103); a coordinate beyond 20 m warns (:mod:`.scene_units`). The
other keys of a PlanningScene (``robot_state``, ``link_padding``...) are ignored; planes, cones,
octomaps and objects to remove or move are refused, each in one line naming the field.
"""

from __future__ import annotations

import json
from functools import partial
from typing import Any

import numpy as np
import pinocchio as pin

from dh2urdf.quoted_input import quoted

from ..exceptions import CollisionModelError
from .allowed_matrix import AllowedMatrix, read_matrix
from .bounds import check_count
from .message_fields import field_list, field_mapping, known_keys
from .scene_content import Scene, check_frames, mesh_file
from .scene_units import ROS_METERS, UnitSlips
from .scene_values import coordinate, factor, length, number, vector
from .urdf_shapes import Shape

__all__ = ["AllowedMatrix", "check_frames", "read_planning_scene"]

#: The fields of moveit_msgs/PlanningScene (only ``world`` and the matrix are read).
_TOP = (
    "allowed_collision_matrix",
    "fixed_frame_transforms",
    "is_diff",
    "link_padding",
    "link_scale",
    "name",
    "object_colors",
    "robot_model_name",
    "robot_state",
    "world",
)
#: The fields of moveit_msgs/CollisionObject (``type`` and subframes are ignored).
_OBJECT = (
    "header",
    "id",
    "mesh_poses",
    "meshes",
    "operation",
    "plane_poses",
    "planes",
    "pose",
    "primitive_poses",
    "primitives",
    "subframe_names",
    "subframe_poses",
    "type",
)
#: shape_msgs/SolidPrimitive types read, and the names of their dimensions in order.
_PRIMITIVES = {1: "box", 2: "sphere", 3: "cylinder"}
_DIMENSIONS = {"box": ("x", "y", "z"), "sphere": ("radius",), "cylinder": ("height", "radius")}
#: moveit_msgs/CollisionObject operations other than ADD (0).
_OPERATIONS = {1: "REMOVE", 2: "APPEND", 3: "MOVE"}


def read_planning_scene(where: str, text: str, as_yaml: bool) -> Scene:
    """The scene of a PlanningScene's JSON (or YAML) ``text`` read from ``where``.

    Raises:
        CollisionModelError: The text is not JSON (YAML), PyYAML is missing for YAML, or a field
            is missing or wrong; one line naming the file and the field.
    """
    document = _parse(where, text, as_yaml)
    if not isinstance(document, dict):
        raise CollisionModelError(where, "not a PlanningScene: the top is not a mapping")
    known_keys(where, "", document, _TOP)
    world = document.get("world", {})
    if not isinstance(world, dict):
        raise CollisionModelError(where, f"world: {quoted(world)} is not a mapping")
    known_keys(where, "world", world, ("collision_objects", "octomap"))
    octomap = world.get("octomap")
    if octomap and (not isinstance(octomap, dict) or _octomap_data(octomap)):
        raise CollisionModelError(
            where, "world.octomap: octomaps are not read; give the cell as collision objects"
        )
    entries = field_list(where, "world.collision_objects", world.get("collision_objects", []))
    check_count(where, sum(_shape_count(entry) for entry in entries))
    slips = UnitSlips(where, "", ROS_METERS)
    shapes: list[Shape] = []
    frames: list[tuple[str, str]] = []
    seen: set[str] = set()
    for index, entry in enumerate(entries):
        field = f"world.collision_objects[{index}]"
        name, frame, placed = _object(where, field, entry, slips)
        if name in seen:
            raise CollisionModelError(where, f"{field}.id: {name!r} is given to two objects")
        seen.add(name)
        frames.append((f"{field}.header.frame_id", frame))
        shapes += placed
    matrix = None
    if "allowed_collision_matrix" in document:
        matrix = read_matrix(where, document["allowed_collision_matrix"])
    slips.warn()
    return Scene(where, tuple(shapes), tuple(frames), matrix)


def _parse(where: str, text: str, as_yaml: bool) -> Any:
    if not as_yaml:
        try:
            return json.loads(text)
        except RecursionError:
            raise CollisionModelError(where, "not JSON: nested too deep") from None
        except ValueError as err:  # JSONDecodeError, or Python's integer-string limit
            raise CollisionModelError(where, f"not JSON: {' '.join(str(err).split())}") from None
    try:
        import yaml
    except ImportError:
        raise CollisionModelError(
            where,
            "a YAML PlanningScene needs PyYAML (pip install pyyaml), or give it as JSON (.json)",
        ) from None
    try:
        return yaml.safe_load(text)
    except RecursionError:
        raise CollisionModelError(where, "not YAML: nested too deep") from None
    except (yaml.YAMLError, ValueError) as err:
        said = " ".join(str(err).split())
        raise CollisionModelError(where, f"not YAML: {quoted(said, 200)[1:-1]}") from None


def _octomap_data(octomap: dict[Any, Any]) -> bool:
    """Whether an octomap_msgs/OctomapWithPose holds cells (an echoed empty scene has none)."""
    inner = octomap.get("octomap")
    return isinstance(inner, dict) and bool(inner.get("data"))


def _shape_count(entry: Any) -> int:
    if not isinstance(entry, dict):
        return 0
    return sum(len(v) for k in ("primitives", "meshes") if isinstance(v := entry.get(k), list))


def _object(where: str, field: str, entry: Any, slips: UnitSlips) -> tuple[str, str, list[Shape]]:
    """One collision object: its id, its frame and its shapes placed in that frame."""
    entry = field_mapping(where, field, entry, _OBJECT)
    name = entry.get("id")
    if not isinstance(name, str) or not name:
        raise CollisionModelError(where, f"{field}.id: {quoted(name)} is not a non-empty string")
    header = field_mapping(
        where, f"{field}.header", entry.get("header"), ("frame_id", "seq", "stamp")
    )
    frame = header.get("frame_id")
    if not isinstance(frame, str) or not frame:
        raise CollisionModelError(
            where, f"{field}.header.frame_id: {quoted(frame)} is not a frame name (the base link)"
        )
    operation = entry.get("operation", 0)
    said = _OPERATIONS.get(operation) if type(operation) is int else operation
    if said in _OPERATIONS.values():
        raise CollisionModelError(
            where, f"{field}.operation: {said} is an edit of a scene; only objects added are read"
        )
    if entry.get("planes"):
        raise CollisionModelError(
            where, f"{field}.planes: planes (infinite) are not read; give a thin BOX"
        )
    pose = _pose(where, f"{field}.pose", entry["pose"]) if "pose" in entry else pin.SE3.Identity()
    shapes: list[Shape] = []
    for shapes_key, poses_key in (("primitives", "primitive_poses"), ("meshes", "mesh_poses")):
        given = field_list(where, f"{field}.{shapes_key}", entry.get(shapes_key, []))
        poses = field_list(where, f"{field}.{poses_key}", entry.get(poses_key, []))
        if len(poses) != len(given):
            raise CollisionModelError(
                where,
                f"{field}.{poses_key}: {len(poses)} pose(s) for {len(given)} {shapes_key}; give "
                "one each",
            )
        for k, (shape, shape_pose) in enumerate(zip(given, poses)):
            at = f"{field}.{shapes_key}[{k}]"
            if shapes_key == "primitives":
                kind, geometry = _primitive(where, at, shape)
            else:
                kind, geometry = "mesh", _mesh(where, at, shape)
            placement = pose * _pose(where, f"{field}.{poses_key}[{k}]", shape_pose)
            place = f"{field}.{poses_key}[{k}].position"
            for axis, value in zip("xyz", placement.translation.tolist()):
                coordinate(where, f"{place}.{axis}", value, slip=ROS_METERS)
                slips.place(f"{place}.{axis}", value)
            shapes.append(Shape(name, f"{name}[{len(shapes)}]", geometry, placement, kind))
    if not shapes:
        raise CollisionModelError(where, f"{field}: no primitives and no meshes")
    if len(shapes) == 1:
        only = shapes[0]
        shapes = [Shape(name, name, only.geometry, only.placement, only.kind)]
    return name, frame, shapes


def _pose(where: str, field: str, value: Any) -> pin.SE3:
    """A geometry_msgs/Pose: position [m], orientation x, y, z, w (MoveIt's normalisation)."""
    value = field_mapping(where, field, value, ("orientation", "position"))
    position = field_mapping(where, f"{field}.position", value.get("position", {}), ("x", "y", "z"))
    xyz = [
        coordinate(where, f"{field}.position.{k}", position.get(k, 0.0), slip=ROS_METERS)
        for k in "xyz"
    ]
    keys = ("x", "y", "z", "w")
    orientation = field_mapping(where, f"{field}.orientation", value.get("orientation", {}), keys)
    if not orientation:
        return pin.SE3(np.eye(3), np.array(xyz))
    x, y, z, w = (number(where, f"{field}.orientation.{k}", orientation.get(k, 0.0)) for k in keys)
    norm = float(np.linalg.norm([x, y, z, w]))
    if norm == 0.0:  # MoveIt: "Empty quaternion found in pose message. Setting to neutral"
        return pin.SE3(np.eye(3), np.array(xyz))
    if not np.isfinite(norm):
        raise CollisionModelError(where, f"{field}.orientation: its norm is not finite")
    rotation = pin.Quaternion(w / norm, x / norm, y / norm, z / norm).toRotationMatrix()
    return pin.SE3(rotation, np.array(xyz))


def _primitive(where: str, field: str, value: Any) -> tuple[str, Any]:
    """A shape_msgs/SolidPrimitive as ``(kind, coal geometry)``."""
    import coal

    value = field_mapping(where, field, value, ("dimensions", "type"))
    code = value.get("type")
    if isinstance(code, str):
        code = {v.upper(): k for k, v in _PRIMITIVES.items()}.get(code.upper(), code)
    if type(code) is not int or code not in _PRIMITIVES:
        raise CollisionModelError(
            where,
            f"{field}.type: {quoted(code)} is not read; choose BOX (1), SPHERE (2), "
            "CYLINDER (3)" + (" (a CONE is not)" if code in (4, "CONE") else ""),
        )
    kind = _PRIMITIVES[code]
    names = _DIMENSIONS[kind]
    dimensions = value.get("dimensions")
    if not isinstance(dimensions, list) or len(dimensions) != len(names):
        raise CollisionModelError(
            where,
            f"{field}.dimensions: {quoted(dimensions)} is not {len(names)} number(s) "
            f"[{', '.join(names)}] for a {kind.upper()}",
        )
    sizes = vector(
        where, f"{field}.dimensions", dimensions, partial(length, slip=ROS_METERS), len(names)
    ).tolist()
    if kind == "box":
        return kind, coal.Box(*sizes)
    if kind == "sphere":
        return kind, coal.Sphere(sizes[0])
    return kind, coal.Cylinder(sizes[1], sizes[0])


def _mesh(where: str, field: str, value: Any) -> Any:
    """A shape_msgs/Mesh (vertices, triangles) or a mesh file (``file``, ``scale``): its hull."""
    from .mesh_file import checked_vertices
    from .urdf_shapes import convex_hull

    if isinstance(value, dict) and "file" in value:
        value = field_mapping(where, field, value, ("file", "scale"))
        scale_value = value.get("scale", 1.0)
        if isinstance(scale_value, list):
            scale = vector(where, f"{field}.scale", scale_value, factor)
        else:
            scale = np.full(3, factor(where, f"{field}.scale", scale_value))
        return mesh_file(where, f"{field}.file", value["file"], scale)
    value = field_mapping(where, field, value, ("triangles", "vertices"))
    vertices = field_list(where, f"{field}.vertices", value.get("vertices", []))
    triangles = field_list(where, f"{field}.triangles", value.get("triangles", []))
    points = []
    for i, vertex in enumerate(vertices):
        at = f"{field}.vertices[{i}]"
        vertex = field_mapping(where, at, vertex, ("x", "y", "z"))
        points.append([coordinate(where, f"{at}.{k}", vertex.get(k, 0.0)) for k in "xyz"])
    used: set[int] = set()
    for t, triangle in enumerate(triangles):
        at = f"{field}.triangles[{t}]"
        corners = field_mapping(where, at, triangle, ("vertex_indices",)).get("vertex_indices")
        if (
            not isinstance(corners, list)
            or len(corners) != 3
            or not all(type(c) is int and 0 <= c < len(points) for c in corners)
        ):
            raise CollisionModelError(
                where,
                f"{at}.vertex_indices: {quoted(corners)} is not 3 indices of the "
                f"{len(points)} vertices",
            )
        used.update(corners)
    try:
        hull_points = checked_vertices(np.array([points[i] for i in sorted(used)]).reshape(-1, 3))
        return convex_hull(hull_points, "the mesh")
    except OSError as err:
        raise CollisionModelError(where, f"{field}: {err}") from err
