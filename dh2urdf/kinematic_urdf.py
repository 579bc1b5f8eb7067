"""The kinematic URDF of a DH table: links, joints and inertials, no drawing; no yourdfpy.

:func:`kinematic_urdf` writes the same tree as :func:`dh2urdf.urdf_writer.urdf_string` (the same
links and joints in the same order, the same origins, limits and inertials) without its visuals
and collision geometry, with the standard library's XML writer: a model built from a table file
(``kin fk --robot my_arm.toml``) never waits for yourdfpy and trimesh (0.7 s), which the full
writer needs. Pinocchio builds the same model from either text; the tests compare the two models
frame by frame on every shipped table and random ones.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ElementTree

import numpy as np

from .dh_table import DHRow, DHTable
from .transforms import clean, rot_x, rot_z, translation

__all__ = ["JOINT_RADIUS", "LINK_MASS", "SEGMENT_RADIUS", "kinematic_urdf"]

#: Radius of the cylinder drawn along each joint axis [m] (the placeholder inertial's sphere).
JOINT_RADIUS = 0.02
#: Radius of the segments drawn along link offsets [m].
SEGMENT_RADIUS = 0.01
#: Mass given to each link without one in the table [kg]; the URDF is for kinematics.
LINK_MASS = 0.1


def _rpy(rotation: np.ndarray) -> tuple[float, float, float]:
    """URDF roll-pitch-yaw of a rotation matrix (``R = Rz(yaw) Ry(pitch) Rx(roll)``)."""
    r = rotation
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if math.hypot(r[0, 0], r[1, 0]) > 1e-12:
        return math.atan2(r[2, 1], r[2, 2]), pitch, math.atan2(r[1, 0], r[0, 0])
    return math.atan2(-r[1, 2], r[1, 1]), pitch, 0.0


def _origin(parent: ElementTree.Element, matrix: np.ndarray) -> None:
    matrix = clean(matrix)
    xyz = " ".join(repr(float(v)) for v in matrix[:3, 3])
    rpy = " ".join(repr(float(v)) for v in _rpy(matrix[:3, :3]))
    ElementTree.SubElement(parent, "origin", xyz=xyz, rpy=rpy)


def _segment_origin(start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, float] | None:
    """Origin (z along the segment, at its middle) and length of a link cylinder, as drawn."""
    vector = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    length = float(np.linalg.norm(vector))
    if length < 1e-9:
        return None
    z = vector / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    origin = np.eye(4)
    origin[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    origin[:3, 3] = (np.asarray(start) + np.asarray(end)) / 2.0
    return origin, length


def cylinder_inertia(mass: float, radius: float, length: float) -> np.ndarray:
    """Inertia of a uniform solid cylinder about its center, axis z (a sphere if length 0)."""
    if length <= 0.0:
        return np.eye(3) * 0.4 * mass * radius**2
    side = mass * (3.0 * radius**2 + length**2) / 12.0
    return np.diag([side, side, 0.5 * mass * radius**2])


def _inertial(link: ElementTree.Element, origin: np.ndarray, mass: float, inertia: np.ndarray):  # noqa: ANN202
    element = ElementTree.SubElement(link, "inertial")
    _origin(element, origin)
    ElementTree.SubElement(element, "mass", value=repr(float(mass)))
    names = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    values = (
        inertia[0, 0],
        inertia[0, 1],
        inertia[0, 2],
        inertia[1, 1],
        inertia[1, 2],
        inertia[2, 2],
    )
    ElementTree.SubElement(
        element, "inertia", {n: repr(float(v)) for n, v in zip(names, values, strict=True)}
    )


def kinematic_urdf(table: DHTable) -> str:
    """The URDF text of ``table`` for building a model: the full writer's tree, no geometry."""
    robot = ElementTree.Element("robot", name=table.name)
    massless = all(row.mass is not None for row in table.rows)
    placeholder = (np.eye(4), LINK_MASS, np.eye(3) * 0.4 * LINK_MASS * JOINT_RADIUS**2)
    links: list[tuple[str, tuple | None]] = [("base_link", None), ("frame0", None)]
    joints: list[tuple[str, str, str, str, np.ndarray, DHRow | None]] = [
        ("base_joint", "fixed", "base_link", "frame0", table.T_world_base, None)
    ]
    for i, row in enumerate(table.rows, start=1):
        parent = f"frame{i - 1}"
        radius = row.radius if row.radius is not None else SEGMENT_RADIUS
        if table.convention == "modified":
            origin = (
                rot_x(row.alpha) @ translation(x=row.a) @ rot_z(row.theta) @ translation(z=row.d)
            )
            child = f"frame{i}"
            segment = _segment_origin(np.array([0.0, 0.0, -row.d]), np.zeros(3))
        else:
            origin = rot_z(row.theta) @ translation(z=row.d)
            child = f"link{i}"
            segment = _segment_origin(np.zeros(3), np.array([row.a, 0.0, 0.0]))
        inertial = None
        if row.mass is not None:
            if segment is None:
                inertial = (np.eye(4), row.mass, cylinder_inertia(row.mass, radius, 0.0))
            else:
                inertial = (segment[0], row.mass, cylinder_inertia(row.mass, radius, segment[1]))
        links.append((child, inertial))
        joints.append((row.name, row.joint_type, parent, child, origin, row))
        if table.convention == "standard":
            links.append((f"frame{i}", None))
            frame = translation(x=row.a) @ rot_x(row.alpha)
            joints.append((f"frame{i}_joint", "fixed", child, f"frame{i}", frame, None))
    links.append(("tool", None))
    joints.append(("tool_joint", "fixed", f"frame{table.dof}", "tool", table.T_last_tool, None))
    for name, inertial in links:
        link = ElementTree.SubElement(robot, "link", name=name)
        if name == "base_link":  # KDL wants a root without inertia (as the full writer)
            continue
        if inertial is None and not massless:
            inertial = placeholder
        if inertial is not None:
            _inertial(link, *inertial)
    for name, kind, parent, child, origin, moving in joints:
        joint = ElementTree.SubElement(robot, "joint", name=name, type=kind)
        ElementTree.SubElement(joint, "parent", link=parent)
        ElementTree.SubElement(joint, "child", link=child)
        _origin(joint, origin)
        if moving is not None:
            ElementTree.SubElement(joint, "axis", xyz="0.0 0.0 1.0")
            ElementTree.SubElement(
                joint,
                "limit",
                effort=repr(float(moving.effort)),
                velocity=repr(float(moving.velocity)),
                lower=repr(float(moving.lower)),
                upper=repr(float(moving.upper)),
            )
    return ElementTree.tostring(robot, encoding="unicode")
