"""Marker geometry drawn with meshcat's primitives: axis triads, spheres, rods, point clouds.

Every function draws under one meshcat node (a ``meshcat.Visualizer`` path) and leaves the
node's own transform to the caller, so that a marker can follow a robot frame or be animated.
Lengths in meters, colors as RGB in [0, 1].
"""

from __future__ import annotations

from collections.abc import Sequence

import meshcat.geometry as mg
import meshcat.transformations as tf
import numpy as np
import numpy.typing as npt

from .exceptions import ViewerInputError

__all__ = ["AXIS_COLORS", "draw_points", "draw_rod", "draw_sphere", "draw_triad", "hex_color"]

#: Colors of the x, y and z axes of a triad (red, green, blue).
AXIS_COLORS: tuple[int, int, int] = (0xE0302A, 0x2DB83D, 0x2A64E0)

# meshcat's cylinder lies along its y axis: the rotation that lays it along x, y and z.
_AXIS_ROTATIONS = (
    tf.rotation_matrix(-np.pi / 2, [0.0, 0.0, 1.0]),
    np.eye(4),
    tf.rotation_matrix(np.pi / 2, [1.0, 0.0, 0.0]),
)


def hex_color(rgb: Sequence[float]) -> int:
    """``0xRRGGBB`` of an RGB triple in [0, 1].

    Raises:
        ViewerInputError: Not three numbers in [0, 1].
    """
    values = np.asarray(rgb, dtype=float).reshape(-1)
    if values.shape != (3,) or not np.all((values >= 0.0) & (values <= 1.0)):
        raise ViewerInputError(f"a color is three numbers in [0, 1], got {list(rgb)!r}")
    red, green, blue = (int(round(255 * v)) for v in values)
    return (red << 16) | (green << 8) | blue


def draw_triad(node: object, length: float, radius: float | None = None) -> None:
    """Draw the x (red), y (green) and z (blue) axes of a frame as cylinders from its origin.

    Args:
        node: meshcat node of the frame; its transform is the frame pose ``T_world_frame``.
        length: Axis length [m].
        radius: Axis radius [m] (default ``length / 25``).
    """
    radius = length / 25.0 if radius is None else radius
    for name, rotation, color in zip("xyz", _AXIS_ROTATIONS, AXIS_COLORS):
        axis = node[name]  # type: ignore[index]
        axis.set_object(mg.Cylinder(length, radius), mg.MeshLambertMaterial(color=color))
        offset = tf.translation_matrix(0.5 * length * np.eye(3)["xyz".index(name)])
        axis.set_transform(offset @ rotation)


#: three.js render order of an on-top marker: after every other object, the see-through body pieces
#: (transparent, drawn back to front) included, which would otherwise be blended over it.
ON_TOP_ORDER = 1000


class _OnTop(mg.Mesh):  # type: ignore[misc]
    """A meshcat mesh whose three.js object carries ``renderOrder``.

    meshcat's ``set_property`` lowercases the property's name, so the order travels in the object.
    """

    def lower(self) -> dict:
        """The object's JSON, with its render order."""
        data = super().lower()
        data["object"]["renderOrder"] = ON_TOP_ORDER
        return data


def _set_object(node: object, geometry: object, material: object, on_top: bool) -> None:
    """``node.set_object``; an on-top marker is also drawn last (:data:`ON_TOP_ORDER`)."""
    if on_top:
        node.set_object(_OnTop(geometry, material))  # type: ignore[attr-defined]
    else:
        node.set_object(geometry, material)  # type: ignore[attr-defined]


def _material(rgb: Sequence[float], opacity: float = 1.0, on_top: bool = False) -> object:
    """A shaded material; ``on_top``: drawn over whatever stands in front (three.js depthTest off).

    three.js draws transparent materials after the opaque ones: an on-top marker is one, opaque.
    """
    if on_top:
        return mg.MeshLambertMaterial(
            color=hex_color(rgb), opacity=opacity, transparent=True, depthTest=False
        )
    return mg.MeshLambertMaterial(color=hex_color(rgb), opacity=opacity, transparent=opacity < 1.0)


def draw_sphere(
    node: object, radius: float, rgb: Sequence[float], opacity: float = 1.0, on_top: bool = False
) -> None:
    """Draw a sphere centred on the node's origin.

    Args:
        node: meshcat node; its transform places the centre.
        radius: Sphere radius [m].
        rgb: Color, RGB in [0, 1].
        opacity: 1 opaque, 0 invisible.
        on_top: Seen through whatever stands in front of it (a marker that must not hide).
    """
    _set_object(node, mg.Sphere(radius), _material(rgb, opacity, on_top), on_top)


def draw_rod(
    node: object,
    start: npt.ArrayLike,
    end: npt.ArrayLike,
    radius: float,
    rgb: Sequence[float],
    on_top: bool = False,
) -> bool:
    """Draw a cylinder from ``start`` to ``end``, and set the node's transform to lay it there.

    WebGL draws lines one pixel wide whatever their width: a rod stays visible.

    Args:
        node: meshcat node; its transform is set (the points are in its parent's frame).
        start: One end [m], shape (3,).
        end: The other end [m], shape (3,).
        radius: Rod radius [m].
        rgb: Color, RGB in [0, 1].
        on_top: Seen through whatever stands in front of it.

    Returns:
        False (nothing drawn) when the two ends are the same point.
    """
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    axis = b - a
    length = float(np.linalg.norm(axis))
    if not length > 0.0:
        return False
    _set_object(node, mg.Cylinder(length, radius), _material(rgb, on_top=on_top), on_top)
    y = axis / length  # meshcat's cylinder lies along its own y axis
    helper = np.eye(3)[int(np.argmin(np.abs(y)))]
    x = np.cross(y, helper)
    x /= np.linalg.norm(x)
    pose = np.eye(4)
    pose[:3, :3] = np.column_stack([x, y, np.cross(x, y)])
    pose[:3, 3] = 0.5 * (a + b)
    node.set_transform(pose)  # type: ignore[attr-defined]
    return True


def draw_points(node: object, points: npt.ArrayLike, rgb: npt.ArrayLike, size: float = 0.01) -> int:
    """Draw a point cloud.

    Args:
        node: meshcat node; the points are in its frame (the world when it has no transform).
        points: Positions, shape (N, 3) [m].
        rgb: One color for all points (3,) or one per point (N, 3), RGB in [0, 1].
        size: Point size [m] (perspective: far points look smaller).

    Returns:
        The number of points drawn.

    Raises:
        ViewerInputError: Points not (N, 3) finite with N >= 1, or colors of the wrong shape.
    """
    position = np.asarray(points, dtype=float)
    if position.ndim != 2 or position.shape[1] != 3 or len(position) == 0:
        raise ViewerInputError(f"points must have shape (N, 3) with N >= 1, got {position.shape}")
    if not np.all(np.isfinite(position)):
        raise ViewerInputError("points must be finite")
    colors = np.asarray(rgb, dtype=float)
    if colors.shape == (3,):
        colors = np.broadcast_to(colors, position.shape)
    if colors.shape != position.shape or not np.all((colors >= 0.0) & (colors <= 1.0)):
        raise ViewerInputError(
            f"point colors must be (3,) or {position.shape} in [0, 1], got shape {colors.shape}"
        )
    cloud = mg.PointCloud(
        position.T.astype(np.float32), colors.T.astype(np.float32), size=float(size)
    )
    node.set_object(cloud)  # type: ignore[attr-defined]
    return len(position)
