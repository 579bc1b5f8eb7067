"""A cell's fixed objects, from a scene TOML or a URDF of the cell, in the world frame [m].

TOML: arrays of tables ``[[box]]`` (``size`` = [x, y, z]), ``[[sphere]]`` (``radius``),
``[[cylinder]]`` (``radius``, ``length``, along its z axis) and ``[[mesh]]`` (``file``, relative
to the scene file's folder, and ``scale``: one number or three), each with an optional ``name``
(default ``box1``, ``sphere2``...), ``xyz`` [m] and ``rpy`` [rad] (URDF roll-pitch-yaw) placing
it in the world frame (the arm's base frame). Every length is in meters; sizes are at most 10 m,
positions within 1 km, at most 1,000 shapes (:mod:`kin.collision.bounds` says why).

A URDF of the cell: the collision shapes of all its links, placed at its joints' zero values
from its root at the world origin; each link is one scene object.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from ..exceptions import CollisionModelError
from .bounds import check_coordinates, check_count, check_sizes
from .urdf_shapes import Shape, link_shapes, load_mesh

__all__ = ["read_scene"]

#: Kind -> (required keys, optional keys besides name, xyz, rpy).
_KINDS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "box": (("size",), ()),
    "cylinder": (("radius", "length"), ()),
    "mesh": (("file",), ("scale",)),
    "sphere": (("radius",), ()),
}
_COMMON = ("name", "xyz", "rpy")


def read_scene(path: str | Path) -> tuple[Shape, ...]:
    """The scene objects of a TOML or URDF file, each shape's placement in the world [m].

    Raises:
        CollisionModelError: The file cannot be read, is not TOML (or XML for a URDF), has an
            unknown key or kind, a size that is not a number in (0, 10 m], a position beyond
            1 km or an angle that is not finite (:mod:`.bounds`), more than 1,000 shapes, a
            duplicate name, or a mesh that cannot be read.
    """
    where = str(path)
    if Path(where).suffix.lower() in (".urdf", ".xml", ".xacro"):
        return _urdf_scene(where)
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # Python 3.10
        import tomli as tomllib

    try:
        from dh2urdf.input_file import read_input

        raw = read_input(where)
    except OSError as err:
        raise CollisionModelError(where, f"cannot read the scene ({err.strerror})") from err
    try:
        document = tomllib.loads(raw.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise CollisionModelError(where, f"not a TOML scene: {err}") from None
    except ValueError as err:  # Python's integer-string limit (a 5000-digit integer)
        from dh2urdf.long_numbers import long_integer_problem

        said = long_integer_problem(raw.decode("utf-8"), err) or str(err)
        raise CollisionModelError(where, said) from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        raise CollisionModelError(where, "not a TOML scene: arrays nested too deep") from None
    check_count(where, sum(len(e) for e in document.values() if isinstance(e, list)))
    shapes: list[Shape] = []
    for kind, entries in document.items():
        if kind not in _KINDS:
            raise CollisionModelError(
                where, f"unknown key {kind!r}; choose [[box]], [[cylinder]], [[mesh]], [[sphere]]"
            )
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            raise CollisionModelError(where, f"{kind}: write it as [[{kind}]] tables")
        for index, entry in enumerate(entries):
            shapes.append(_object(where, kind, index, entry))
    seen: set[str] = set()
    for shape in shapes:
        if shape.owner in seen:
            raise CollisionModelError(where, f"name {shape.owner!r} is given to two objects")
        seen.add(shape.owner)
    return tuple(shapes)


def _object(where: str, kind: str, index: int, entry: dict[str, Any]) -> Shape:
    field = f"{kind}[{index}]"
    required, optional = _KINDS[kind]
    for key in entry:
        if key not in (*required, *optional, *_COMMON):
            choices = ", ".join((*required, *optional, *_COMMON))
            raise CollisionModelError(where, f"{field}.{key}: unknown key; choose: {choices}")
    for key in required:
        if key not in entry:
            raise CollisionModelError(where, f"{field}.{key}: missing")
    name = entry.get("name", f"{kind}{index + 1}")
    if not isinstance(name, str) or not name:
        raise CollisionModelError(where, f"{field}.name: {name!r} is not a non-empty string")
    xyz = _vector(where, f"{field}.xyz", entry.get("xyz", [0.0, 0.0, 0.0]), _coordinate)
    rpy = _vector(where, f"{field}.rpy", entry.get("rpy", [0.0, 0.0, 0.0]), _number)
    placement = pin.SE3(pin.rpy.rpyToMatrix(*rpy), xyz)
    import coal

    geometry: coal.CollisionGeometry
    if kind == "box":
        geometry = coal.Box(*_vector(where, f"{field}.size", entry["size"]).tolist())
    elif kind == "sphere":
        geometry = coal.Sphere(_length(where, f"{field}.radius", entry["radius"]))
    elif kind == "cylinder":
        radius = _length(where, f"{field}.radius", entry["radius"])
        geometry = coal.Cylinder(radius, _length(where, f"{field}.length", entry["length"]))
    else:
        file = entry["file"]
        if not isinstance(file, str) or not file:
            raise CollisionModelError(where, f"{field}.file: {file!r} is not a file name")
        scale_value = entry.get("scale", 1.0)
        if isinstance(scale_value, list):
            scale = _vector(where, f"{field}.scale", scale_value, _factor)
        else:
            scale = np.full(3, _factor(where, f"{field}.scale", scale_value))
        mesh = Path(file) if Path(file).is_absolute() else Path(where).resolve().parent / file
        try:
            geometry = load_mesh(mesh, scale)
        except OSError as err:
            raise CollisionModelError(where, f"{field}.file: {err}") from err
    return Shape(name, name, geometry, placement, kind)


def _number(where: str, field: str, value: Any) -> float:
    """A finite number (an angle [rad] or a scale factor)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CollisionModelError(where, f"{field}: {value!r} is not a number")
    try:
        number = float(value)
    except OverflowError:  # an integer beyond float range
        raise CollisionModelError(where, f"{field}: the number is not finite") from None
    if not math.isfinite(number):
        raise CollisionModelError(where, f"{field}: {value!r} is not finite")
    return number


def _length(where: str, field: str, value: Any) -> float:
    """A size [m] in (0, MAX_SIZE] (:mod:`.bounds`)."""
    number = _number(where, field, value)
    check_sizes(where, field, (number,))
    return number


def _factor(where: str, field: str, value: Any) -> float:
    """A scale factor > 0."""
    number = _number(where, field, value)
    if number <= 0.0:
        raise CollisionModelError(where, f"{field}: {number!r} must be > 0")
    return number


def _coordinate(where: str, field: str, value: Any) -> float:
    """A coordinate [m] within +-MAX_COORDINATE (:mod:`.bounds`)."""
    number = _number(where, field, value)
    check_coordinates(where, field, (number,))
    return number


def _vector(where: str, field: str, value: Any, check: Any = _length) -> np.ndarray:
    """Three values, each read by ``check`` (:func:`_length`, :func:`_coordinate`, :func:`_number`)."""
    if not isinstance(value, list) or len(value) != 3:
        raise CollisionModelError(where, f"{field}: {value!r} is not a list of 3 numbers")
    return np.array([check(where, f"{field}[{i}]", v) for i, v in enumerate(value)])


def _urdf_scene(where: str) -> tuple[Shape, ...]:
    from dh2urdf.exceptions import UrdfChainError
    from dh2urdf.urdf_chain import urdf_text
    from dh2urdf.urdf_parse import build_pinocchio_model, parse_urdf_xml

    try:
        root, text = parse_urdf_xml(urdf_text(where), where)
        model = build_pinocchio_model(text, where)
    except UrdfChainError as err:
        raise CollisionModelError("", str(err)) from err
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    links = [link.get("name", "") for link in root.iter("link")]
    shapes = []
    for shape in link_shapes(root, links, where, strict_meshes=True):
        world = data.oMf[model.getFrameId(shape.owner, pin.FrameType.BODY)] * shape.placement
        check_coordinates(where, f"link {shape.owner!r}: its shape's place", world.translation)
        shapes.append(Shape(shape.owner, shape.name, shape.geometry, world, shape.kind))
    check_count(where, len(shapes))
    return tuple(shapes)
