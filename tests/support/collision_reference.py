"""A direct coal check of a URDF's collision shapes, built apart from :mod:`kin.collision`.

The reference the collision tests compare the checker with. Nothing here imports ``kin``: the
``<collision>`` elements are read with ElementTree, ``package://`` paths resolved by walking up
from the URDF, the shapes made with coal's own constructors, placed by Pinocchio's forward
kinematics of the ORIGINAL URDF (the maker's, not the DH model), and every pair asked of
``coal.collide`` / ``coal.distance`` one by one. The scene TOML is read with ``tomllib``.

Signed distance of a pair [m]: the smallest distance between its shapes when apart, minus the
largest penetration depth when some of them overlap.
"""

from __future__ import annotations

import math
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin

from support.urdf_reference import place_frames

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

#: How a mesh enters the check: its triangles (a BVH), or its convex hull (coal's qhull).
MESH_MODES = ("bvh", "convex")


@dataclass(frozen=True)
class Shape:
    """One collision shape: the link or scene object that owns it, in the owner's frame."""

    owner: str
    geometry: coal.CollisionGeometry
    local: pin.SE3
    primitive: bool


def _floats(text: str | None, default: tuple[float, ...]) -> np.ndarray:
    return np.array([float(v) for v in text.split()] if text else default, dtype=float)


def _origin(element: ET.Element) -> pin.SE3:
    origin = element.find("origin")
    xyz = _floats(None if origin is None else origin.get("xyz"), (0.0, 0.0, 0.0))
    rpy = _floats(None if origin is None else origin.get("rpy"), (0.0, 0.0, 0.0))
    return pin.SE3(pin.rpy.rpyToMatrix(*rpy), xyz)


def resolve_mesh(filename: str, urdf_path: Path) -> Path:
    """The file a URDF mesh names: ``package://NAME/rest`` found above the URDF's folder."""
    if filename.startswith("file://"):
        return Path(filename[len("file://") :])
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://") :].partition("/")
        for folder in urdf_path.resolve().parents:
            if folder.name == package:
                return folder / rest
            if (folder / package).is_dir():
                return folder / package / rest
        raise FileNotFoundError(filename)
    return (urdf_path.parent / filename).resolve()


def _mesh(path: Path, scale: np.ndarray, mode: str) -> coal.CollisionGeometry:
    bvh = coal.MeshLoader().load(str(path), scale)
    if mode == "bvh":
        return bvh
    bvh.buildConvexHull(True, "Qt")
    return bvh.convex


def _geometry(
    geometry: ET.Element, urdf_path: Path | None, mode: str
) -> tuple[coal.CollisionGeometry, bool]:
    shape = geometry[0]
    if shape.tag == "box":
        return coal.Box(*_floats(shape.get("size"), ())), True
    if shape.tag == "sphere":
        return coal.Sphere(float(shape.get("radius", "nan"))), True
    if shape.tag == "cylinder":
        return coal.Cylinder(
            float(shape.get("radius", "nan")), float(shape.get("length", "nan"))
        ), True
    if shape.tag == "mesh" and urdf_path is not None:
        path = resolve_mesh(shape.get("filename", ""), urdf_path)
        return _mesh(path, _floats(shape.get("scale"), (1.0, 1.0, 1.0)), mode), False
    raise ValueError(f"unsupported collision geometry <{shape.tag}>")


def urdf_shapes(text: str, urdf_path: Path | None, mode: str = "convex") -> list[Shape]:
    """Every ``<collision>`` of every link of the URDF ``text``, in its link's frame."""
    shapes = []
    for link in ET.fromstring(text).iter("link"):
        for collision in link.findall("collision"):
            geometry, primitive = _geometry(collision.find("geometry"), urdf_path, mode)
            shapes.append(Shape(link.get("name", ""), geometry, _origin(collision), primitive))
    return shapes


def scene_shapes(path: Path) -> list[Shape]:
    """The boxes, spheres and cylinders of a scene TOML, in the world frame [m, rad]."""
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    shapes = []
    for kind, entries in data.items():
        for index, entry in enumerate(entries):
            name = entry.get("name", f"{kind}{index}")
            xyz = np.array(entry.get("xyz", (0.0, 0.0, 0.0)), dtype=float)
            rotation = pin.rpy.rpyToMatrix(*np.array(entry.get("rpy", (0.0, 0.0, 0.0)), float))
            if kind == "box":
                geometry = coal.Box(*map(float, entry["size"]))
            elif kind == "sphere":
                geometry = coal.Sphere(float(entry["radius"]))
            elif kind == "cylinder":
                geometry = coal.Cylinder(float(entry["radius"]), float(entry["length"]))
            else:
                raise ValueError(f"{path}: the reference reads no [[{kind}]]")
            shapes.append(Shape(name, geometry, pin.SE3(rotation, xyz), True))
    return shapes


def _signed_distance(a: Shape, ma: pin.SE3, b: Shape, mb: pin.SE3) -> float:
    ta = coal.Transform3s(ma.rotation, ma.translation)
    tb = coal.Transform3s(mb.rotation, mb.translation)
    request = coal.CollisionRequest(coal.CollisionRequestFlag.CONTACT, 1)
    result = coal.CollisionResult()
    if coal.collide(a.geometry, ta, b.geometry, tb, request, result):
        return min(c.penetration_depth for c in result.getContacts())  # <= 0: overlap
    return float(
        coal.distance(a.geometry, ta, b.geometry, tb, coal.DistanceRequest(), coal.DistanceResult())
    )


class CollisionReference:
    """Pinocchio FK of the original URDF + coal, pair by pair.

    Args:
        text: The URDF text (the maker's, or the DH writer's for a table robot).
        urdf_path: Its file, to resolve meshes (None: primitives only).
        joint_names: The URDF joints ``q`` holds, in order; every other joint stays at 0.
        base: The link the world frame sits on (default: the URDF's root).
        scene: A scene TOML, or None.
        mesh_mode: ``"bvh"`` or ``"convex"`` (see :data:`MESH_MODES`).
    """

    def __init__(
        self,
        text: str,
        urdf_path: Path | None,
        joint_names: tuple[str, ...],
        base: str | None = None,
        scene: Path | None = None,
        mesh_mode: str = "convex",
    ):
        self.model = pin.buildModelFromXML(text)
        self.data = self.model.createData()
        self.joints = [self.model.joints[self.model.getJointId(name)] for name in joint_names]
        root = ET.fromstring(text)
        children = {j.find("child").get("link") for j in root.findall("joint")}
        links = [link.get("name") for link in root.findall("link")]
        self.base = base if base is not None else next(n for n in links if n not in children)
        self.parent = {
            j.find("child").get("link"): j.find("parent").get("link") for j in root.findall("joint")
        }
        self.child = {j.get("name"): j.find("child").get("link") for j in root.findall("joint")}
        self.moving = {
            j.find("child").get("link") for j in root.findall("joint") if j.get("type") != "fixed"
        }
        self.shapes = urdf_shapes(text, urdf_path, mesh_mode)
        self.scene = scene_shapes(scene) if scene is not None else []
        self.frames = {
            name: self.model.getFrameId(name, pin.FrameType.BODY)
            for name in {s.owner for s in self.shapes} | {self.base}
        }

    @property
    def links(self) -> set[str]:
        """The links that have collision shapes."""
        return {s.owner for s in self.shapes}

    @property
    def scene_names(self) -> set[str]:
        """The scene objects' names."""
        return {s.owner for s in self.scene}

    def chain(self, tip: str) -> list[str]:
        """The links from the base to ``tip``, base first."""
        links = [tip]
        while links[-1] != self.base:
            links.append(self.parent[links[-1]])
        return links[::-1]

    def carrier(self, link: str, joints: set[str] | None = None) -> str:
        """The link just after the last moving joint above ``link`` (``link`` rides on it).

        With ``joints``, only those joints move (the others held): the chain's.
        """
        moving = self.moving if joints is None else {self.child[j] for j in joints}
        while link in self.parent and link not in moving:
            link = self.parent[link]
        return link

    def adjacent(self) -> set[frozenset[str]]:
        """Link pairs joined by one joint (MoveIt's rule: links without shapes skipped)."""
        pairs = set()
        for link in self.links:
            parent = self.parent.get(link)
            while parent is not None and parent not in self.links:
                parent = self.parent.get(parent)
            if parent is not None:
                pairs.add(frozenset((link, parent)))
        return pairs

    def placements(self, q: np.ndarray) -> dict[str, list[tuple[Shape, pin.SE3]]]:
        """Owner -> its shapes placed in the world frame at ``q`` [rad / m]."""
        place_frames(self.model, self.data, self.joints, q)
        world = self.data.oMf[self.frames[self.base]].inverse()
        placed: dict[str, list[tuple[Shape, pin.SE3]]] = {}
        for shape in self.shapes:
            placed.setdefault(shape.owner, []).append(
                (shape, world * self.data.oMf[self.frames[shape.owner]] * shape.local)
            )
        for shape in self.scene:
            placed.setdefault(shape.owner, []).append((shape, shape.local))
        return placed

    def signed_distances(
        self, q: np.ndarray, pairs: list[tuple[str, str]]
    ) -> dict[tuple[str, str], tuple[float, bool]]:
        """(a, b) -> (signed distance [m], True when every shape of both is a primitive)."""
        placed = self.placements(q)
        out = {}
        for a, b in pairs:
            best = math.inf
            for sa, ma in placed.get(a, ()):
                for sb, mb in placed.get(b, ()):
                    best = min(best, _signed_distance(sa, ma, sb, mb))
            primitive = all(s.primitive for s, _ in placed.get(a, ()) + placed.get(b, ()))
            out[(a, b)] = (best, primitive)
        return out
