"""The elements of a generated URDF as small frozen values, and their XML text.

Building a model from a table needs only the URDF text, so this module writes it with NumPy and
string formatting: no yourdfpy (which imports trimesh, about 0.7 s) and no lxml. The text is the
one yourdfpy's ``URDF.write_xml`` and lxml's ``pretty_print`` give for the same elements (elements
and attributes in yourdfpy's order, numbers as ``str`` of the same values, an origin's rotation as
static x-y-z Euler angles, lxml's escaping and two-space indentation);
``tests/dh2urdf/test_dh2urdf_urdf_text.py`` compares the two on every shipped table and on generated ones. ``dh2urdf.urdf_writer.build_urdf``
turns the same elements into a yourdfpy model where one is wanted.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: Below this ``cos(pitch)`` an origin's rotation is treated as gimbal-locked (yaw set to 0).
_GIMBAL_EPS = float(np.finfo(float).eps) * 4.0


@dataclass(frozen=True, eq=False)
class Cylinder:
    """A cylinder along the z axis of its origin: ``radius`` and ``length`` [m]."""

    radius: float
    length: float


@dataclass(frozen=True, eq=False)
class Box:
    """A box centred on its origin: edge lengths ``size`` (x, y, z) [m]."""

    size: np.ndarray


@dataclass(frozen=True, eq=False)
class Sphere:
    """A sphere centred on its origin: ``radius`` [m]."""

    radius: float


@dataclass(frozen=True, eq=False)
class Mesh:
    """A mesh file: ``filename`` as the URDF names it, ``scale`` per axis [m per file unit]."""

    filename: str
    scale: tuple[float, float, float]


Geometry = Cylinder | Box | Sphere | Mesh


@dataclass(frozen=True, eq=False)
class Material:
    """A named colour: ``rgba`` in [0, 1]."""

    name: str
    rgba: np.ndarray


@dataclass(frozen=True, eq=False)
class Visual:
    """A drawn shape: ``origin`` is its 4x4 pose in the link frame [m]."""

    name: str
    origin: np.ndarray
    geometry: Geometry
    material: Material | None = None


@dataclass(frozen=True, eq=False)
class Collision:
    """A collision shape: ``origin`` is its 4x4 pose in the link frame [m]."""

    name: str
    origin: np.ndarray
    geometry: Geometry


@dataclass(frozen=True, eq=False)
class Inertial:
    """Mass [kg] and inertia about the centre of mass [kg m^2], ``origin`` in the link frame."""

    origin: np.ndarray
    mass: float
    inertia: np.ndarray


@dataclass(frozen=True, eq=False)
class Link:
    """A URDF link: its inertial (None: none written), visuals and collisions."""

    name: str
    inertial: Inertial | None = None
    visuals: tuple[Visual, ...] = ()
    collisions: tuple[Collision, ...] = ()


@dataclass(frozen=True, eq=False)
class Limit:
    """Joint limits: effort [N m] or [N], velocity [rad/s] or [m/s], lower/upper [rad] or [m]."""

    effort: float
    velocity: float
    lower: float
    upper: float


@dataclass(frozen=True, eq=False)
class Joint:
    """A URDF joint from ``parent`` to ``child`` at ``origin`` (4x4, in the parent frame)."""

    name: str
    type: str
    parent: str
    child: str
    origin: np.ndarray
    axis: np.ndarray | None = None
    limit: Limit | None = None


@dataclass(frozen=True, eq=False)
class Robot:
    """The whole URDF: links, joints and materials, written in this order."""

    name: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    materials: tuple[Material, ...] = field(default=())


def origin_rpy(origin: np.ndarray) -> tuple[Any, Any, Any]:
    """URDF roll, pitch, yaw [rad] of a 4x4 pose's rotation ``R = Rz(yaw) Ry(pitch) Rx(roll)``.

    Computed with NumPy scalars, in the operations yourdfpy uses (static x-y-z Euler angles), so
    the printed decimals are the same; yaw is 0 when the pitch is at +-90 degrees.
    """
    R = np.asarray(origin, dtype=np.float64)[:3, :3]
    cos_pitch = np.sqrt(R[0, 0] * R[0, 0] + R[1, 0] * R[1, 0])
    pitch = np.arctan2(-R[2, 0], cos_pitch)
    if cos_pitch > _GIMBAL_EPS:
        return np.arctan2(R[2, 1], R[2, 2]), pitch, np.arctan2(R[1, 0], R[0, 0])
    return np.arctan2(-R[1, 2], R[1, 1]), pitch, 0.0


# --- XML text, as lxml's pretty printer writes it -------------------------------------------

_ATTRIBUTE_ESCAPES = str.maketrans(
    {
        "&": "&amp;",
        "<": "&lt;",
        ">": "&gt;",
        '"': "&quot;",
        "\n": "&#10;",
        "\r": "&#13;",
        "\t": "&#9;",
    }
)


@dataclass(frozen=True)
class _Element:
    tag: str
    attributes: tuple[tuple[str, str], ...] = ()
    children: tuple[_Element | _Comment, ...] = ()


@dataclass(frozen=True)
class _Comment:
    text: str


def _element(tag: str, attributes: dict[str, str] | None = None, *children: Any) -> _Element:
    kept = tuple(child for child in children if child is not None)
    return _Element(tag, tuple((attributes or {}).items()), kept)


def _numbers(values: Iterable[Any]) -> str:
    return " ".join(map(str, values))


def _origin(origin: np.ndarray) -> _Element:
    xyz = np.asarray(origin)[:3, 3].copy()
    return _element("origin", {"xyz": _numbers(xyz), "rpy": _numbers(origin_rpy(origin))})


def _geometry(geometry: Geometry) -> _Element:
    if isinstance(geometry, Cylinder):
        shape = _element(
            "cylinder", {"radius": str(geometry.radius), "length": str(geometry.length)}
        )
    elif isinstance(geometry, Box):
        shape = _element("box", {"size": _numbers(geometry.size)})
    elif isinstance(geometry, Mesh):
        shape = _element("mesh", {"filename": geometry.filename, "scale": _numbers(geometry.scale)})
    else:
        shape = _element("sphere", {"radius": str(geometry.radius)})
    return _element("geometry", None, shape)


def _material(material: Material | None) -> _Element | None:
    if material is None:
        return None
    color = _element("color", {"rgba": _numbers(material.rgba)})
    return _element("material", {"name": material.name}, color)


def _inertial(inertial: Inertial | None) -> _Element | None:
    if inertial is None:
        return None
    I = np.asarray(inertial.inertia)  # noqa: E741 (the usual name of an inertia matrix)
    moments = {
        "ixx": I[0, 0],
        "ixy": I[0, 1],
        "ixz": I[0, 2],
        "iyy": I[1, 1],
        "iyz": I[1, 2],
        "izz": I[2, 2],
    }
    return _element(
        "inertial",
        None,
        _origin(inertial.origin),
        _element("mass", {"value": str(inertial.mass)}),
        _element("inertia", {key: str(value) for key, value in moments.items()}),
    )


def _link(link: Link) -> _Element:
    visuals = [
        _element(
            "visual",
            {"name": visual.name},
            _geometry(visual.geometry),
            _origin(visual.origin),
            _material(visual.material),
        )
        for visual in link.visuals
    ]
    collisions = [
        _element(
            "collision", {"name": shape.name}, _geometry(shape.geometry), _origin(shape.origin)
        )
        for shape in link.collisions
    ]
    return _element("link", {"name": link.name}, _inertial(link.inertial), *visuals, *collisions)


def _joint(joint: Joint) -> _Element:
    limit = None
    if joint.limit is not None:
        values = joint.limit
        limit = _element(
            "limit",
            {
                "effort": str(values.effort),
                "velocity": str(values.velocity),
                "lower": str(values.lower),
                "upper": str(values.upper),
            },
        )
    axis = None if joint.axis is None else _element("axis", {"xyz": _numbers(joint.axis)})
    return _element(
        "joint",
        {"name": joint.name, "type": joint.type},
        _element("parent", {"link": joint.parent}),
        _element("child", {"link": joint.child}),
        _origin(joint.origin),
        axis,
        limit,
    )


def _render(node: _Element | _Comment, depth: int, lines: list[str]) -> None:
    indent = "  " * depth
    if isinstance(node, _Comment):
        lines.append(f"{indent}<!--{node.text}-->")
        return
    attributes = "".join(
        f' {key}="{value.translate(_ATTRIBUTE_ESCAPES)}"' for key, value in node.attributes
    )
    if not node.children:
        lines.append(f"{indent}<{node.tag}{attributes}/>")
        return
    lines.append(f"{indent}<{node.tag}{attributes}>")
    for child in node.children:
        _render(child, depth + 1, lines)
    lines.append(f"{indent}</{node.tag}>")


def robot_xml(
    robot: Robot, mujoco_compiler: dict[str, str] | None = None, note: str | None = None
) -> str:
    """XML text of ``robot`` (no XML declaration), ending with a newline.

    Args:
        robot: The elements to write.
        mujoco_compiler: Attributes of ``<mujoco><compiler .../></mujoco>`` (MuJoCo's URDF
            extension), written first inside ``<robot>``; None for none.
        note: Text of a comment written next, before the links; None for none.
    """
    first: list[_Element | _Comment] = []
    if mujoco_compiler is not None:
        first.append(_element("mujoco", None, _element("compiler", mujoco_compiler)))
    if note is not None:
        first.append(_Comment(note))
    root = _element(
        "robot",
        {"name": robot.name},
        *first,
        *(_link(link) for link in robot.links),
        *(_joint(joint) for joint in robot.joints),
        *(_material(material) for material in robot.materials),
    )
    lines: list[str] = []
    _render(root, 0, lines)
    return "\n".join(lines) + "\n"
