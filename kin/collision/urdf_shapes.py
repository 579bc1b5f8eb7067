"""The ``<collision>`` shapes of a URDF's links as coal geometries, each in its link's frame.

Boxes, cylinders and spheres are kept as coal primitives (exact); a mesh (STL, DAE, OBJ: what
coal's assimp loader reads) enters as its convex hull (coal's qhull), which encloses it, once
:mod:`kin.collision.mesh_file` has checked its vertices (qhull crashes on degenerate ones). Mesh file
names are resolved as the preview resolves them: ``package://NAME/rest`` as ``NAME/rest`` in the
URDF's folder or one of its parents (:data:`PACKAGE_LEVELS` levels), ``file://`` and absolute
paths as they are, relative ones from the URDF's folder.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

import coal
import numpy as np
import pinocchio as pin

from ..exceptions import CollisionModelError
from .bounds import check_coordinates, check_sizes
from .mesh_file import loader_reason, mesh_vertices

__all__ = [
    "PACKAGE_LEVELS",
    "Shape",
    "convex_hull",
    "link_shapes",
    "load_mesh",
    "origin_of",
    "resolve_mesh",
]

logger = logging.getLogger("kin.collision")

#: Folders above the URDF searched for ``package://NAME/...`` (as kin.viewer.maker_meshes).
PACKAGE_LEVELS = 6


@dataclass(frozen=True, eq=False)
class Shape:
    """One collision shape of an owner (a link or a scene object).

    Attributes:
        owner: Link or scene object name.
        name: Shape name (unique in a model).
        geometry: The coal geometry (a primitive, or a mesh's convex hull).
        placement: ``T_owner_shape`` [m].
        kind: ``"box"``, ``"cylinder"``, ``"sphere"`` or ``"mesh"``.
    """

    owner: str
    name: str
    geometry: coal.CollisionGeometry
    placement: pin.SE3
    kind: str


def resolve_mesh(filename: str, folder: Path) -> Path:
    """The file a URDF mesh ``filename`` names (it may not exist), from the URDF's ``folder``."""
    if filename.startswith("package://"):
        rest = filename[len("package://") :]
        for parent in [folder, *folder.parents][:PACKAGE_LEVELS]:
            candidate = parent / rest
            if candidate.is_file():
                return candidate
        return folder / rest
    if filename.startswith("file://"):
        return Path(filename[len("file://") :])
    path = Path(filename)
    return path if path.is_absolute() else folder / path


def load_mesh(path: Path, scale: np.ndarray) -> coal.CollisionGeometry:
    """The convex hull of the mesh file ``path`` scaled by ``scale`` (3,) [m per file unit].

    The vertices are read and checked first (:func:`~kin.collision.mesh_file.mesh_vertices`):
    a file that is not a regular one, larger than ``MAX_MESH_BYTES``, with more than
    ``MAX_MESH_VERTICES`` distinct vertices (refused, not simplified), a vertex that is not finite
    or beyond ``MAX_COORDINATE`` after scaling, or flat, collinear or a point never reaches qhull.

    Raises:
        OSError: One line naming the file and the reason: missing, not a regular file, too
            large, not a mesh coal reads, or vertices a convex hull cannot be built from.
    """
    try:
        vertices = mesh_vertices(path, scale)
    except FileNotFoundError:
        raise OSError(f"mesh not found: {path}") from None
    except OSError as err:
        raise OSError(f"cannot read the mesh {path} ({err.strerror or err})") from err
    return convex_hull(vertices, f"the mesh {path}")


def convex_hull(vertices: np.ndarray, what: str) -> coal.CollisionGeometry:
    """The convex hull (qhull) of ``vertices`` (n, 3) [m] checked by ``mesh_file.checked_vertices``.

    Raises:
        OSError: qhull found no hull; the line names ``what`` (``the mesh FILE``).
    """
    points = coal.StdVec_Vec3s()
    points.extend(list(vertices))
    # the hull itself (qhull): a convex over the mesh's own triangles, which
    # buildConvexRepresentation gives, misleads GJK's hill climbing on a concave mesh
    try:
        hull = coal.Convex.convexHull(points, True, "Qt")
    except (RuntimeError, ValueError) as err:
        raise OSError(f"cannot read {what} (qhull: {loader_reason(str(err))})") from err
    if hull is None:
        raise OSError(f"cannot read {what} (qhull found no hull)")
    return hull


def _floats(text: str | None, count: int, where: str, field: str) -> np.ndarray:
    try:
        values = np.array([float(v) for v in (text or "").split()], dtype=float)
    except ValueError:
        raise CollisionModelError(where, f"{field}: {text!r} is not {count} numbers") from None
    if values.size != count or not np.isfinite(values).all():
        raise CollisionModelError(where, f"{field}: {text!r} is not {count} finite numbers")
    return values


def origin_of(element: ElementTree.Element, where: str, field: str) -> pin.SE3:
    """``T_parent_element`` of an element's ``<origin xyz= rpy=>`` (identity when absent)."""
    origin = element.find("origin")
    if origin is None:
        return pin.SE3.Identity()
    xyz = _floats(origin.get("xyz", "0 0 0"), 3, where, f"{field}.origin.xyz")
    check_coordinates(where, f"{field}.origin.xyz", xyz)
    rpy = _floats(origin.get("rpy", "0 0 0"), 3, where, f"{field}.origin.rpy")
    return pin.SE3(pin.rpy.rpyToMatrix(*rpy), xyz)


def _positive(element: ElementTree.Element, attribute: str, count: int, where: str, field: str):
    values = _floats(element.get(attribute), count, where, f"{field}.{attribute}")
    if not (values > 0.0).all():
        raise CollisionModelError(where, f"{field}.{attribute}: {values.tolist()} must be > 0 m")
    if attribute != "scale":  # a mesh's extent is checked on its vertices (mesh_file)
        check_sizes(where, f"{field}.{attribute}", values)
    return values


def link_shapes(
    root: ElementTree.Element, links: Iterable[str], where: str, *, strict_meshes: bool
) -> list[Shape]:
    """The collision shapes of ``links`` in the URDF ``root`` read from the file ``where``.

    Args:
        root: The URDF's ``<robot>`` element.
        links: The links whose shapes are wanted.
        where: The URDF file (mesh paths are resolved from its folder).
        strict_meshes: A missing or unreadable mesh raises (a scene) instead of one warning
            naming the file and the link, the link left without that shape (a robot).

    Raises:
        CollisionModelError: A size that is not a positive finite number, an unknown geometry
            element, or (``strict_meshes``) a mesh that cannot be read.
    """
    wanted = set(links)
    folder = Path(where).resolve().parent
    shapes: list[Shape] = []
    for link in root.iter("link"):
        name = link.get("name", "")
        if name not in wanted:
            continue
        for index, collision in enumerate(link.findall("collision")):
            field = f"link {name!r} collision[{index}]"
            geometry = collision.find("geometry")
            if geometry is None or len(geometry) == 0:
                continue
            shape = geometry[0]
            label = collision.get("name") or f"{name}_{index}"
            made = _geometry(shape, folder, where, field, name, strict_meshes)
            if made is not None:
                placement = origin_of(collision, where, field)
                shapes.append(Shape(name, f"{name}/{label}", made, placement, shape.tag))
    return shapes


def _geometry(
    shape: ElementTree.Element, folder: Path, where: str, field: str, link: str, strict: bool
) -> coal.CollisionGeometry | None:
    if shape.tag == "box":
        return coal.Box(*_positive(shape, "size", 3, where, field).tolist())
    if shape.tag == "cylinder":
        radius = _positive(shape, "radius", 1, where, field)[0]
        return coal.Cylinder(radius, _positive(shape, "length", 1, where, field)[0])
    if shape.tag == "sphere":
        return coal.Sphere(_positive(shape, "radius", 1, where, field)[0])
    if shape.tag == "capsule":
        radius = _positive(shape, "radius", 1, where, field)[0]
        return coal.Capsule(radius, _positive(shape, "length", 1, where, field)[0])
    if shape.tag == "mesh":
        scale = (
            _positive(shape, "scale", 3, where, field)
            if shape.get("scale") is not None
            else np.ones(3)
        )
        path = resolve_mesh(shape.get("filename", ""), folder)
        try:
            return load_mesh(path, scale)
        except OSError as err:
            if strict:
                raise CollisionModelError(where, f"{field}.filename: {err}") from err
            logger.warning("%s: link %r left without this shape: %s", where, link, err)
            return None
    raise CollisionModelError(
        where, f"{field}: unknown geometry <{shape.tag}>; choose box, cylinder, sphere or mesh"
    )
