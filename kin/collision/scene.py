"""A cell's fixed objects, from a scene file or a URDF of the cell, in the world frame [m].

Every key of a scene file, its unit and an example: ``docs/scenes.md``.

TOML: arrays of tables ``[[box]]`` (``size`` = [x, y, z]), ``[[sphere]]`` (``radius``),
``[[cylinder]]`` (``radius``, ``length``, along its z axis) and ``[[mesh]]`` (``file``, relative
to the scene file's folder, and ``scale``: one number or three, file units to meters), each with
an optional ``name`` (default ``box1``, ``sphere2``...), ``xyz`` and ``rpy`` (URDF roll-pitch-yaw)
placing it in the world frame (the arm's base frame). Top-level ``length_unit`` (``m``, the
default, ``cm``, ``mm``) and ``angle_unit`` (``rad``, the default, or ``deg``) say the units of
every length and angle, as a DH table's keys do; the same slips warn (:mod:`.scene_units`).
Sizes are at most 10 m, positions within 1 km, at most 1,000 shapes (:mod:`kin.collision.bounds`
says why).

``[[attached]]`` (TOML only): an object on a link of the robot, moving with it
(:mod:`.attached`): ``shape`` (``box``, ``sphere``, ``cylinder``, ``mesh``) and that kind's keys,
``link``, ``xyz``/``rpy`` in the link's frame (the file's units), ``touch_links`` it may touch.

A MoveIt PlanningScene, JSON or YAML (:mod:`.planning_scene`): its collision objects and its
allowed collision matrix. A URDF of the cell: the collision shapes of all its links, placed at its
joints' zero values from its root at the world origin; each link is one scene object.

The format is chosen by the suffix (``.toml``; ``.json``; ``.yaml``, ``.yml``; ``.urdf``,
``.xml``, ``.xacro``), else by the content: ``{`` first is JSON, a ``world:`` line is YAML,
anything else TOML.
"""

from __future__ import annotations

import re
import sys
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from dh2urdf.quoted_input import quoted
from dh2urdf.units import ANGLE_UNITS, LENGTH_UNITS, angle_to_radians

from ..exceptions import CollisionModelError
from .attached import AttachedObject
from .bounds import check_coordinates, check_count
from .scene_content import Scene, mesh_file
from .scene_units import UNIT_KEYS, UnitSlips, read_unit
from .scene_values import coordinate, factor, length, number, vector
from .urdf_shapes import Shape, link_shapes

__all__ = ["Scene", "load_scene", "read_scene"]

#: Kind -> (required keys, optional keys besides name, xyz, rpy).
_KINDS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "box": (("size",), ()),
    "cylinder": (("radius", "length"), ()),
    "mesh": (("file",), ("scale",)),
    "sphere": (("radius",), ()),
}
_COMMON = ("name", "xyz", "rpy")


def read_scene(path: str | Path) -> tuple[Shape, ...]:
    """The scene objects of a scene file (:func:`load_scene`), each placed in the world [m]."""
    return load_scene(path).objects


def load_scene(path: str | Path) -> Scene:
    """The scene of a TOML, PlanningScene (JSON, YAML) or URDF file (the module docstring).

    Warns:
        UnitWarning: An angle beyond a turn in a radian scene; a coordinate beyond 20 m.

    Raises:
        CollisionModelError: The file cannot be read, is not of its format, has an unknown key
            or kind, a size that is not a number in (0, 10 m], a position beyond 1 km or an
            angle that is not finite (:mod:`.bounds`), more than 1,000 shapes, a duplicate
            name, or a mesh that cannot be read; one line naming the file and the field.
    """
    where = str(path)
    suffix = Path(where).suffix.lower()
    if suffix in (".urdf", ".xml", ".xacro"):
        return Scene(where, _urdf_scene(where))
    try:
        from dh2urdf.input_file import read_input

        raw = read_input(where)
    except OSError as err:
        raise CollisionModelError(where, f"cannot read the scene ({err.strerror})") from err
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as err:
        raise CollisionModelError(where, f"not a scene: not UTF-8 text ({err.reason})") from None
    if suffix in (".json", ".yaml", ".yml") or (
        suffix != ".toml" and (text.lstrip().startswith("{") or _YAML_WORLD.search(text))
    ):
        from .planning_scene import read_planning_scene

        as_yaml = suffix in (".yaml", ".yml") or (
            suffix != ".json" and not text.lstrip().startswith("{")
        )
        return read_planning_scene(where, text, as_yaml)
    return _toml_scene(where, text)


#: A YAML document's top-level ``world:`` key (a PlanningScene).
_YAML_WORLD = re.compile(r"^world\s*:", re.M)


def _toml_scene(where: str, text: str) -> Scene:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # Python 3.10
        import tomli as tomllib

    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise CollisionModelError(where, f"not a TOML scene: {err}") from None
    except ValueError as err:  # Python's integer-string limit (a 5000-digit integer)
        from dh2urdf.long_numbers import long_integer_problem

        said = long_integer_problem(text, err) or str(err)
        raise CollisionModelError(where, said) from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        raise CollisionModelError(where, "not a TOML scene: arrays nested too deep") from None
    angle_unit, length_unit = (read_unit(where, document, key) for key in UNIT_KEYS)
    slips = UnitSlips.of_toml(where, angle_unit, length_unit)
    units = (LENGTH_UNITS[length_unit], ANGLE_UNITS[angle_unit], slips)
    check_count(where, sum(len(e) for e in document.values() if isinstance(e, list)))
    shapes: list[Shape] = []
    attached: list[AttachedObject] = []
    for kind, entries in document.items():
        if kind in UNIT_KEYS:
            continue
        if kind not in _KINDS and kind != "attached":
            raise CollisionModelError(
                where,
                f"unknown key {kind!r}; choose [[box]], [[cylinder]], [[mesh]], [[sphere]], "
                "[[attached]], angle_unit, length_unit",
            )
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            raise CollisionModelError(where, f"{kind}: write it as [[{kind}]] tables")
        for index, entry in enumerate(entries):
            if kind == "attached":
                attached.append(_attached(where, index, entry, *units))
            else:
                shapes.append(_object(where, kind, index, entry, *units))
    seen: set[str] = set()
    for name in [shape.owner for shape in shapes] + [thing.name for thing in attached]:
        if name in seen:
            raise CollisionModelError(where, f"name {name!r} is given to two objects")
        seen.add(name)
    slips.warn()
    return Scene(where, tuple(shapes), attached=tuple(attached))


#: An ``[[attached]]`` entry's keys besides its shape's.
_ATTACHED = ("shape", "link", "touch_links")


def _attached(
    where: str, index: int, entry: dict[str, Any], meters: float, radians: float, slips: UnitSlips
) -> AttachedObject:
    """One ``[[attached]]``: ``shape`` (a kind), its keys, ``link``, ``xyz``/``rpy`` in the link."""
    field = f"attached[{index}]"
    kind = entry.get("shape")
    if kind not in _KINDS:
        raise CollisionModelError(
            where, f"{field}.shape: {quoted(kind)}; choose: {', '.join(_KINDS)}"
        )
    link = entry.get("link")
    if link is None:
        raise CollisionModelError(where, f"{field}.link: missing; name the link it hangs on")
    if not isinstance(link, str) or not link:
        raise CollisionModelError(where, f"{field}.link: {quoted(link)} is not a link name")
    touch = entry.get("touch_links", [])
    if not isinstance(touch, list) or not all(isinstance(t, str) and t for t in touch):
        raise CollisionModelError(
            where, f"{field}.touch_links: {quoted(touch)} is not a list of link names"
        )
    rest = {key: value for key, value in entry.items() if key not in _ATTACHED}
    rest.setdefault("name", f"attached{index + 1}")
    shape = _object(where, kind, index, rest, meters, radians, slips, field, _ATTACHED)
    return AttachedObject(shape.owner, entry["link"], (shape,), tuple(touch))


def _object(
    where: str,
    kind: str,
    index: int,
    entry: dict[str, Any],
    meters: float,
    radians: float,
    slips: UnitSlips,
    field: str = "",
    extra: tuple[str, ...] = (),
) -> Shape:
    """One TOML object: lengths [length_unit] times ``meters``, angles [angle_unit] ``radians``.

    ``field`` names it in messages (default ``box[0]``...); ``extra`` are the other keys its table
    may hold (an ``[[attached]]`` entry's, read by the caller).
    """
    field = field or f"{kind}[{index}]"
    required, optional = _KINDS[kind]
    for key in entry:
        if key not in (*required, *optional, *_COMMON, *extra):
            choices = ", ".join((*required, *optional, *_COMMON, *extra))
            raise CollisionModelError(where, f"{field}.{key}: unknown key; choose: {choices}")
    for key in required:
        if key not in entry:
            raise CollisionModelError(where, f"{field}.{key}: missing")
    name = entry.get("name", f"{kind}{index + 1}")
    if not isinstance(name, str) or not name:
        raise CollisionModelError(where, f"{field}.name: {name!r} is not a non-empty string")
    size = partial(length, meters=meters, slip=slips.hint)
    place = partial(coordinate, meters=meters, slip=slips.hint)
    xyz = vector(where, f"{field}.xyz", entry.get("xyz", [0.0, 0.0, 0.0]), place)
    written = vector(where, f"{field}.rpy", entry.get("rpy", [0.0, 0.0, 0.0]), number)
    for axis, value in enumerate(xyz.tolist()):
        slips.place(f"{field}.xyz[{axis}]", value)
    for axis, value in enumerate(written.tolist()):
        slips.angle(f"{field}.rpy[{axis}]", value)
    rpy = [angle_to_radians(value, radians) for value in written.tolist()]
    placement = pin.SE3(pin.rpy.rpyToMatrix(*rpy), xyz)
    import coal

    geometry: coal.CollisionGeometry
    if kind == "box":
        geometry = coal.Box(*vector(where, f"{field}.size", entry["size"], size).tolist())
    elif kind == "sphere":
        geometry = coal.Sphere(size(where, f"{field}.radius", entry["radius"]))
    elif kind == "cylinder":
        radius = size(where, f"{field}.radius", entry["radius"])
        geometry = coal.Cylinder(radius, size(where, f"{field}.length", entry["length"]))
    else:
        scale_value = entry.get("scale", 1.0)
        if isinstance(scale_value, list):
            scale = vector(where, f"{field}.scale", scale_value, factor)
        else:
            scale = np.full(3, factor(where, f"{field}.scale", scale_value))
        geometry = mesh_file(where, f"{field}.file", entry["file"], scale)
    return Shape(name, name, geometry, placement, kind)


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
