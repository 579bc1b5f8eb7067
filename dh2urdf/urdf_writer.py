"""Convert a :class:`DHTable` into URDF text, in meters and radians, without yourdfpy.

Frames and links of the generated URDF:

- ``base_link``: the URDF root; a fixed joint ``base_joint`` places ``frame0`` (DH frame 0) on it
  with the table's ``[base]`` transform.
- ``frame{i}``: DH frame ``i`` (i = 0..n). Modified (Craig) tables: joint ``i`` goes from
  ``frame{i-1}`` to ``frame{i}`` with origin ``Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``.
  Standard tables: joint ``i`` goes from ``frame{i-1}`` to the moving link ``link{i}`` with origin
  ``Rz(theta_i) Tz(d_i)``, and a fixed joint ``frame{i}_joint`` with origin
  ``Tx(a_i) Rx(alpha_i)`` places ``frame{i}`` on it. A row's tilt ``beta`` (Hayati's,
  :mod:`dh2urdf.dh_table`) follows its twist, ``Rx(alpha) Ry(beta)``, in either origin. Every
  joint moves about (or along) its z axis: ``axis xyz="0 0 1"``, or ``"0 0 -1"`` for a reversed
  row (``direction = -1``), the URDF's joint variable being the table's q (same limits).
- ``tool``: fixed on ``frame{n}`` with the table's ``[tool]`` transform.

Each link gets simple visuals (a cylinder along each joint axis; the body: capsules along the
link offsets and the row's housing cylinders, :mod:`dh2urdf.link_volumes`; the meshes the table
names, :mod:`dh2urdf.link_meshes`), the body as collision geometry (where a body has a collision
mesh, without its default 1 cm sticks, which stay drawn), and an inertial (but the root ``base_link``, which KDL wants without one). A row's
``mass`` makes the inertial of its moving link that of a uniform solid cylinder along the link's
segment (a solid sphere when the segment has no length), about its center of mass; without masses
the inertials are placeholders and the file says so in a comment.

The ``<mujoco>`` element (MuJoCo's URDF extension) keeps fixed links as bodies
(``fusestatic="false"``), so MuJoCo loads every DH frame and the tool.

The elements are plain values (:mod:`dh2urdf.urdf_elements`) written as text with string
formatting, so building a model from a table imports neither yourdfpy nor trimesh (0.7 s);
:func:`dh2urdf.yourdfpy_model.build_urdf` gives the same URDF as a yourdfpy model, checked by
yourdfpy, where one is wanted.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .dh_table import DHRow, DHTable
from .link_inertials import cylinder_inertia as cylinder_inertia
from .link_inertials import primitive_inertial
from .link_volumes import DEFAULT_RADIUS, segment_radii
from .mesh_elements import mesh_elements
from .transforms import clean, rot_x, rot_y, rot_z, translation
from .urdf_elements import (
    Box,
    Collision,
    Cylinder,
    Inertial,
    Joint,
    Limit,
    Link,
    Material,
    Robot,
    Sphere,
    Visual,
    robot_xml,
)

#: Radius of the cylinder drawn along each joint axis [m].
JOINT_RADIUS = 0.02
#: Length of the cylinder drawn along each joint axis [m].
JOINT_LENGTH = 0.06
#: Radius of the segments drawn along link offsets when a row states none [m].
SEGMENT_RADIUS = DEFAULT_RADIUS
#: Mass given to each link [kg]; the URDF is for kinematics, not dynamics.
LINK_MASS = 0.1

_JOINT_MATERIAL = Material(name="joint", rgba=np.array([0.9, 0.5, 0.1, 1.0]))
_LINK_MATERIAL = Material(name="link", rgba=np.array([0.6, 0.6, 0.65, 1.0]))
_TOOL_MATERIAL = Material(name="tool", rgba=np.array([0.2, 0.6, 0.9, 1.0]))


def _segment(
    start: np.ndarray, end: np.ndarray, name: str, radius: float = SEGMENT_RADIUS
) -> list[Visual]:
    """A cylinder from ``start`` to ``end`` (link frame, [m]); none if they coincide."""
    vector = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    length = float(np.linalg.norm(vector))
    if length < 1e-9:
        return []
    z = vector / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    origin = np.eye(4)
    origin[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    origin[:3, 3] = (np.asarray(start) + np.asarray(end)) / 2.0
    geometry = Cylinder(radius=radius, length=length)
    return [Visual(name=name, origin=clean(origin), geometry=geometry, material=_LINK_MATERIAL)]


def _joint_visual(name: str, prismatic: bool = False) -> Visual:
    """A cylinder (revolute) or box (prismatic) along the z axis of the joint frame."""
    geometry: Box | Cylinder
    if prismatic:
        geometry = Box(size=np.array([0.03, 0.03, JOINT_LENGTH]))
    else:
        geometry = Cylinder(radius=JOINT_RADIUS, length=JOINT_LENGTH)
    return Visual(name=name, origin=np.eye(4), geometry=geometry, material=_JOINT_MATERIAL)


def _inertial() -> Inertial:
    """Placeholder inertial: a small solid sphere of radius JOINT_RADIUS and mass LINK_MASS."""
    moment = 0.4 * LINK_MASS * JOINT_RADIUS**2
    return Inertial(origin=np.eye(4), mass=LINK_MASS, inertia=np.eye(3) * moment)


def _collisions(visuals: list[Visual]) -> tuple[Collision, ...]:
    """Collision geometry: the body among ``visuals`` (segments, their ends, housings)."""
    return tuple(
        Collision(name=f"{v.name}_collision", origin=v.origin, geometry=v.geometry)
        for v in visuals
        if v.material is _LINK_MATERIAL
    )


def _end_sphere(point: np.ndarray, name: str, radius: float) -> Visual:
    """The sphere closing a capsule at ``point`` (link frame, [m])."""
    origin = clean(translation(*np.asarray(point, dtype=float)))
    geometry = Sphere(radius=radius)
    return Visual(name=name, origin=origin, geometry=geometry, material=_LINK_MATERIAL)


def _capsule_ends(chain: list[_Drawn]) -> dict[str, list[Visual]]:
    """Per link, the spheres closing the capsules, but at the chain's first start and last end.

    ``chain`` holds the drawn segments base to tool (zero-length ones left out); a segment whose
    row states no radius stays a plain cylinder.
    """
    spheres: dict[str, list[Visual]] = {}
    for k, (link, start, end, name, radius, capsule) in enumerate(chain):
        if not capsule:
            continue
        ends = [(start, f"{name}_start")] if k > 0 else []
        ends += [(end, f"{name}_end")] if k < len(chain) - 1 else []
        spheres.setdefault(link, []).extend(_end_sphere(p, n, radius) for p, n in ends)
    return spheres


#: A drawn segment: link, start, end (link frame [m]), name, radius [m], whether a capsule.
_Drawn = tuple[str, np.ndarray, np.ndarray, str, float, bool]


def _housings(row: DHRow, T_link_frame: np.ndarray) -> list[Visual]:
    """The row's housing cylinders on its moving link (``T_link_frame``: DH frame i in it)."""
    visuals = []
    for n, housing in enumerate(row.housings):
        start, end = (
            T_link_frame[:3, :3] @ np.array(p) + T_link_frame[:3, 3]
            for p in (housing.start, housing.end)
        )
        visuals += _segment(start, end, f"housing{row.index}_{n}", housing.radius)
    return visuals


def _link(
    name: str,
    visuals: list[Visual],
    inertial: Inertial | None,
    massless: bool,
    meshes: list[Collision],
    unchecked: set[str],
) -> Link:
    """A link; without ``inertial`` a placeholder one, or none when ``massless`` (all masses given).

    Its collisions: the body among ``visuals`` but the ``unchecked`` sticks, then ``meshes``.
    """
    # The root link carries no inertial: KDL (ROS tools, TRAC-IK) rejects a root inertia.
    if name == "base_link":
        inertial = None
    elif inertial is None and not massless:
        inertial = _inertial()
    body = [v for v in visuals if v.name not in unchecked]
    collisions = _collisions(body) + tuple(meshes)
    return Link(name=name, inertial=inertial, visuals=tuple(visuals), collisions=collisions)


def _fixed(name: str, parent: str, child: str, origin: np.ndarray) -> Joint:
    return Joint(name=name, type="fixed", parent=parent, child=child, origin=clean(origin))


def urdf_elements(table: DHTable, mesh_folder: str | Path | None = None) -> Robot:
    """The links, joints and materials of a table's URDF (NumPy only, no XML library).

    Args:
        table: The DH table (SI units).
        mesh_folder: Name the table's mesh files relative to this folder (where the URDF is
            written); None: by their absolute paths.

    Returns:
        The elements, in the order they are written.
    """
    visuals: dict[str, list[Visual]] = {"base_link": [], "frame0": []}
    joints = [_fixed("base_joint", "base_link", "frame0", table.T_world_base)]
    inertials: dict[str, Inertial] = {}
    order = ["base_link", "frame0"]
    chain: list[_Drawn] = []  # the body's segments, base to tool
    carrier = {"base_link": 0, "frame0": 0}  # link -> the joint that moves it
    meshes: dict[str, list[Collision]] = {}  # link -> its collision meshes

    def add_meshes(link: str, row: DHRow | None, T_link_frame: np.ndarray) -> None:
        index = 0 if row is None else row.index
        found = table.base_meshes if row is None else row.meshes
        drawn, checked = mesh_elements(found, T_link_frame, f"mesh{index}", mesh_folder)
        visuals.setdefault(link, []).extend(drawn)
        meshes.setdefault(link, []).extend(checked)

    def segment(
        link: str, start: np.ndarray, end: np.ndarray, name: str, radius: float, capsule: bool
    ) -> list[Visual]:
        drawn = _segment(start, end, name, radius)
        visuals.setdefault(link, []).extend(drawn)
        if drawn:
            ends = np.asarray(start, float), np.asarray(end, float)
            chain.append((link, *ends, name, radius, capsule))
        return drawn

    add_meshes("frame0", None, np.eye(4))
    base_offset = table.T_world_base[:3, 3]
    segment("base_link", np.zeros(3), base_offset, "base_offset", SEGMENT_RADIUS, False)
    for i, row in enumerate(table.rows, start=1):
        parent = f"frame{i - 1}"
        prismatic = row.joint_type == "prismatic"
        radius_a, radius_d = segment_radii(row)
        capsule_a = row.radius_a is not None or row.radius is not None  # stated: a capsule
        capsule_d = row.radius_d is not None or row.radius is not None
        visuals[f"frame{i}"] = []
        twist = rot_x(row.alpha) @ rot_y(row.beta) if row.beta else rot_x(row.alpha)
        if table.convention == "modified":
            pre = twist @ translation(x=row.a)
            origin = pre @ rot_z(row.theta) @ translation(z=row.d)
            segment(parent, np.zeros(3), pre[:3, 3], f"a{i - 1}", radius_a, capsule_a)
            child = f"frame{i}"
            visuals[child].append(_joint_visual(f"{row.name}_axis", prismatic))
            drawn = segment(
                child, np.array([0, 0, -row.d]), np.zeros(3), f"d{i}", radius_d, capsule_d
            )
            T_link_frame = np.eye(4)
            order.append(child)
        else:
            origin = rot_z(row.theta) @ translation(z=row.d)
            segment(parent, np.zeros(3), np.array([0, 0, row.d]), f"d{i}", radius_d, capsule_d)
            child = f"link{i}"
            visuals[child] = [_joint_visual(f"{row.name}_axis", prismatic)]
            drawn = segment(
                child, np.zeros(3), np.array([row.a, 0, 0]), f"a{i}", radius_a, capsule_a
            )
            T_link_frame = translation(x=row.a) @ twist
            order += [child, f"frame{i}"]
        visuals[child] += _housings(row, T_link_frame)
        add_meshes(child, row, T_link_frame)
        carrier.update({child: i, f"frame{i}": i})
        if row.mass is not None:
            radius = row.radius if row.radius is not None else SEGMENT_RADIUS
            inertials[child] = primitive_inertial(row.mass, radius, drawn)
        joints.append(
            Joint(
                name=row.name,
                type=row.joint_type,
                parent=parent,
                child=child,
                origin=clean(origin),
                axis=np.array([0.0, 0.0, float(row.direction)]),
                limit=Limit(
                    effort=row.effort, velocity=row.velocity, lower=row.lower, upper=row.upper
                ),
            )
        )
        if table.convention == "standard":
            joints.append(
                _fixed(f"frame{i}_joint", child, f"frame{i}", translation(x=row.a) @ twist)
            )
    last = f"frame{table.dof}"
    segment(last, np.zeros(3), table.T_last_tool[:3, 3], "tool_offset", SEGMENT_RADIUS, False)
    for link, spheres in _capsule_ends(chain).items():
        visuals[link] += spheres
    tool_marker = Visual(
        name="tool_marker",
        origin=np.eye(4),
        geometry=Sphere(radius=0.015),
        material=_TOOL_MATERIAL,
    )
    visuals["tool"] = [tool_marker]
    order.append("tool")
    joints.append(_fixed("tool_joint", last, "tool", table.T_last_tool))
    massless = all(row.mass is not None for row in table.rows)
    # a body (the links one joint moves) with a collision mesh: its default sticks are not checked
    meshed = {carrier[link] for link, found in meshes.items() if found}
    unchecked = {
        name for link, *_, name, _, capsule in chain if not capsule and carrier[link] in meshed
    }
    links = tuple(
        _link(name, visuals[name], inertials.get(name), massless, meshes.get(name, []), unchecked)
        for name in order
    )
    return Robot(
        name=table.name,
        links=links,
        joints=tuple(joints),
        materials=(_JOINT_MATERIAL, _LINK_MATERIAL, _TOOL_MATERIAL),
    )


#: MuJoCo's URDF extension ``<mujoco><compiler .../></mujoco>``: keep fixed links (DH frames,
#: tool) as bodies, keep visuals.
MUJOCO_COMPILER = {
    "fusestatic": "false",
    "discardvisual": "false",
    "balanceinertia": "true",
    "inertiafromgeom": "false",
    "angle": "radian",
}

_PLACEHOLDER_NOTE = (
    " Inertials are placeholders for visualization, not dynamics: the table gives no link\n"
    "     masses (add mass [kg] and radius to its [[joints]] rows for solid-cylinder inertials). "
)


def _comment(text: str) -> str:
    """``text`` safe inside an XML comment (no ``--``, no trailing ``-``)."""
    while "--" in text:
        text = text.replace("--", "- -")
    return text + " " if text.endswith("-") else text


def _table_file(table: DHTable) -> str:
    """The table's file name (``TABLE.toml`` for a table built in memory)."""
    return "TABLE.toml" if table.path is None else Path(table.path).name


def urdf_string(table: DHTable, mesh_folder: str | Path | None = None) -> str:
    """URDF text of a table, with a header comment naming its source and the MuJoCo extension.

    Written from :func:`urdf_elements` without yourdfpy (the same text its writer gives). The
    table's mesh files are named by their absolute paths, or relative to ``mesh_folder``.
    """
    note = _PLACEHOLDER_NOTE if any(row.mass is None for row in table.rows) else None
    body = robot_xml(urdf_elements(table, mesh_folder), MUJOCO_COMPILER, note)
    header = (
        f"<!-- Generated by dh2urdf from the DH table '{_comment(table.name)}' "
        f"({table.convention} convention).\n"
        f"     Source: {_comment(table.source)}\n"
        "     Units: meters, radians. Do not edit: regenerate it from the table with\n"
        f"     dh2urdf {_comment(_table_file(table))} -o FILE.urdf -->\n"
    )
    return '<?xml version="1.0" encoding="utf-8"?>\n' + header + body


def write_text_atomic(text: str, path: str | Path) -> Path:
    """Write ``text`` to ``path`` whole or not at all (see :func:`dh2urdf.output_file.write_atomic`).

    Raises:
        OutputFileError: ``path`` is a device, FIFO, socket or folder, or its folder is missing.
        OutputWriteError: The disk filled up (or another I/O error) part-way; nothing was written.
    """
    from .output_file import write_text_atomic as write

    return write(path, text)


def write_urdf(table: DHTable, path: str | Path) -> Path:
    """Write the URDF of a table to ``path`` atomically (nothing half-written on error).

    Its mesh files are named relative to the folder of ``path``.
    """
    folder = Path(path).resolve().parent
    return write_text_atomic(urdf_string(table, folder if _has_meshes(table) else None), path)


def _has_meshes(table: DHTable) -> bool:
    return bool(table.base_meshes) or any(row.meshes for row in table.rows)
