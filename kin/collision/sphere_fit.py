"""Spheres that enclose a collision shape: the fast, conservative stand-in for it.

Every point of the shape lies in one of its spheres, so the distance between two shapes is at
least the smallest distance between their sphere sets (and a shape's distance to a point at
least the point's distance to the nearest sphere less its radius): a lower bound, never more
(:mod:`kin.collision.sphere_bound` uses it to skip the exact query where the bound already
shows a pair apart).

How a shape is covered: a sphere is its own cover; every other shape is first made a convex
polytope that contains it (a box its 8 corners, a mesh its convex hull's vertices, a cylinder
the prism circumscribed about it with :data:`PRISM_SIDES` sides, a capsule the prism about its
cylinder and one sphere of its radius at each end), whose principal axes (of its vertices) are
cut into a grid: the thinnest axis never, the others into cells about :data:`CELL_RATIO` times
the thinnest extent long, at most :data:`MOST_SPHERES` cells. The part of the polytope in each
cell is itself a convex polytope, whose vertices are the polytope's vertices in the cell and the
points where its hull's edges cross the cell's faces; the smallest ball of those points (to
within a few 1e-4, then its radius taken to the farthest one) contains their hull, so the cell's
part. A swept-sphere radius of coal's is added to every radius.

:func:`largest_gap` measures how far a cover reaches beyond its shape: the largest distance from
a point of the spheres' union to the shape [m] (coal's distance from points on the union's
boundary), the figure docs/planning.md states per link.
"""

from __future__ import annotations

import hashlib
import math
from itertools import combinations

import coal
import numpy as np
from scipy.spatial import ConvexHull, QhullError

__all__ = [
    "CELL_RATIO",
    "MOST_SPHERES",
    "PRISM_SIDES",
    "enclosing_spheres",
    "largest_gap",
    "swept_radius",
]

#: Length of a grid cell over the shape's thinnest extent [ratio]: smaller is tighter and more
#: spheres.
CELL_RATIO = 1.0
#: Most spheres covering one shape [count].
MOST_SPHERES = 12
#: Sides of the prism circumscribed about a cylinder (its radius grows by 1 / cos(pi / n) - 1,
#: 0.5 % at 32).
PRISM_SIDES = 32
#: Steps of Badoiu and Clarkson's walk to the smallest ball (its radius within about
#: 1 / sqrt(steps) of the smallest; the radius kept is the farthest point's from the center).
_BALL_STEPS = 1000
#: Covers remembered (by shape content) [count].
_KEPT = 4096
_FITTED: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
#: Added to every radius [m]: floating-point rounding of the fit's own arithmetic.
_ROUNDING = 1e-9


def enclosing_spheres(
    geometry: coal.CollisionGeometry, cell_ratio: float = CELL_RATIO, most: int = MOST_SPHERES
) -> tuple[np.ndarray, np.ndarray]:
    """Spheres whose union contains ``geometry``, in the geometry's own frame.

    Remembered by the shape's kind and sizes (a mesh's: its hull's points), so that the same
    arm in another scene is not fitted again.

    Args:
        geometry: A coal shape: ``Sphere``, ``Box``, ``Cylinder``, ``Capsule``, ``Convex`` (any
            other is covered through its local bounding box).
        cell_ratio: Grid cell length over the thinnest extent (see the module).
        most: Most spheres.

    Returns:
        Centers (k, 3) [m] and radii (k,) [m].
    """
    key = (_content(geometry), cell_ratio, most)
    found = _FITTED.get(key)
    if found is None:
        if len(_FITTED) >= _KEPT:
            _FITTED.clear()
        found = _FITTED[key] = _fit(geometry, cell_ratio, most)
    return found[0].copy(), found[1].copy()


def swept_radius(geometry: coal.CollisionGeometry) -> float:
    """A shape's swept-sphere radius in coal (the margin it grows by) [m], 0 without one."""
    sweep = getattr(geometry, "getSweptSphereRadius", None)
    return 0.0 if sweep is None else float(sweep())


def _content(geometry: coal.CollisionGeometry) -> tuple:
    """What a shape's cover depends on: its kind, sizes, swept radius (a hull: its points)."""
    swept = swept_radius(geometry)
    kind = type(geometry).__name__
    if isinstance(geometry, coal.Sphere):
        return kind, float(geometry.radius), swept
    if isinstance(geometry, coal.Box):
        return kind, tuple(np.asarray(geometry.halfSide, dtype=float).tolist()), swept
    if isinstance(geometry, (coal.Cylinder, coal.Capsule)):
        return kind, float(geometry.radius), float(geometry.halfLength), swept
    if isinstance(geometry, coal.Convex):
        points = np.array(geometry.points(), dtype=float).reshape(-1, 3)
        return kind, hashlib.sha256(points.tobytes()).hexdigest(), swept
    geometry.computeLocalAABB()
    box = geometry.aabb_local
    return kind, tuple(np.asarray(box.min_).tolist()), tuple(np.asarray(box.max_).tolist()), swept


def _fit(
    geometry: coal.CollisionGeometry, cell_ratio: float, most: int
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`enclosing_spheres`, not remembered."""
    swept = swept_radius(geometry)
    ends = np.zeros((0, 3))
    end_radii = np.zeros(0)
    if isinstance(geometry, coal.Sphere):
        return np.zeros((1, 3)), np.array([geometry.radius + swept + _ROUNDING])
    if isinstance(geometry, coal.Box):
        centers, radii = _box_cover(np.asarray(geometry.halfSide, dtype=float), cell_ratio, most)
        return centers, radii + swept + _ROUNDING
    if isinstance(geometry, coal.Cylinder) and geometry.halfLength >= geometry.radius:
        centers, radii = _slabs(
            float(geometry.radius), float(geometry.halfLength), cell_ratio, most
        )
        return centers, radii + swept + _ROUNDING
    if isinstance(geometry, (coal.Cylinder, coal.Capsule)):
        vertices = _prism(float(geometry.radius), float(geometry.halfLength))
        if isinstance(geometry, coal.Capsule):
            ends = np.array([[0.0, 0.0, geometry.halfLength], [0.0, 0.0, -geometry.halfLength]])
            end_radii = np.full(2, float(geometry.radius))
            most = max(1, most - 2)
    elif isinstance(geometry, coal.Convex):
        vertices = np.array(geometry.points(), dtype=float).reshape(-1, 3)
    else:
        geometry.computeLocalAABB()
        box = geometry.aabb_local
        vertices = _box_corners(0.5 * (np.asarray(box.max_) - np.asarray(box.min_)))
        vertices += 0.5 * (np.asarray(box.max_) + np.asarray(box.min_))
    centers, radii = _cover(vertices, cell_ratio, most)
    centers = np.vstack([centers, ends])
    radii = np.concatenate([radii, end_radii]) + swept + _ROUNDING
    return centers, radii


def _counts(extent: np.ndarray, cell_ratio: float, most: int) -> tuple[int, int]:
    """Cells along the longest and the middle extent (the module's grid; ``extent`` sorted)."""
    # a flat cross-section is cut across into pieces about twice as wide as thick, a round one
    # not (its halves need balls nearly as large as the whole); then the length into cells
    # cell_ratio times the pieces' width
    across = max(1, min(most, round(extent[1] / max(2.0 * extent[2], 1e-12))))
    width = max(extent[1] / across, 1e-12)
    return max(1, min(most // across, round(extent[0] / (cell_ratio * width)))), across


def _box_cover(half: np.ndarray, cell_ratio: float, most: int) -> tuple[np.ndarray, np.ndarray]:
    """A box's grid cells (boxes too), each in the ball through its corners."""
    order = np.argsort(-half, kind="stable")
    counts = np.ones(3, dtype=int)
    counts[order[:2]] = _counts(2.0 * half[order], cell_ratio, most)
    cell = half / counts  # the cells' half sizes
    axes = [-half[i] + cell[i] * (2 * np.arange(counts[i]) + 1) for i in range(3)]
    centers = np.array(np.meshgrid(*axes, indexing="ij")).reshape(3, -1).T
    return centers, np.full(len(centers), float(np.linalg.norm(cell)))


def _slabs(
    radius: float, half_length: float, cell_ratio: float, most: int
) -> tuple[np.ndarray, np.ndarray]:
    """A cylinder no wider than long, cut across its axis into slabs in the balls through their rims."""
    count = max(1, min(most, round(half_length / (cell_ratio * radius))))
    half = half_length / count
    z = -half_length + half * (2 * np.arange(count) + 1)
    centers = np.column_stack([np.zeros(count), np.zeros(count), z])
    return centers, np.full(count, math.hypot(radius, half))


def _box_corners(half: np.ndarray) -> np.ndarray:
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    return signs * half


def _prism(radius: float, half_length: float) -> np.ndarray:
    """Vertices of the prism with :data:`PRISM_SIDES` sides circumscribed about a cylinder."""
    angles = 2.0 * math.pi * np.arange(PRISM_SIDES) / PRISM_SIDES
    outer = radius / math.cos(math.pi / PRISM_SIDES)
    ring = np.column_stack([outer * np.cos(angles), outer * np.sin(angles)])
    return np.vstack(
        [np.column_stack([ring, np.full(PRISM_SIDES, z)]) for z in (-half_length, half_length)]
    )


def _cover(vertices: np.ndarray, cell_ratio: float, most: int) -> tuple[np.ndarray, np.ndarray]:
    """Spheres covering the convex hull of ``vertices``, one per grid cell (the module's grid)."""
    middle = vertices.mean(axis=0)
    _, _, rows = np.linalg.svd(vertices - middle, full_matrices=False)
    axes = rows if rows.shape[0] == 3 else np.eye(3)  # principal axes, longest first
    coordinates = (vertices - middle) @ axes.T
    low, high = coordinates.min(axis=0), coordinates.max(axis=0)
    extent = high - low
    counts = _counts(extent, cell_ratio, most)
    centers, radii = [], []
    for i in range(counts[0]):
        part = _clip(vertices, axes[0], *_bounds(low[0], extent[0], counts[0], i, middle, axes[0]))
        for j in range(counts[1]):
            piece = part
            if counts[1] > 1 and len(piece):
                piece = _clip(
                    part, axes[1], *_bounds(low[1], extent[1], counts[1], j, middle, axes[1])
                )
            if len(piece):
                center, radius = _ball(piece)
                centers.append(center)
                radii.append(radius)
    return np.array(centers), np.array(radii)


def _bounds(
    low: float, extent: float, count: int, index: int, middle: np.ndarray, axis: np.ndarray
) -> tuple[float, float]:
    """Cell ``index``'s range along ``axis`` in world coordinates (the outer cells open-ended)."""
    offset = float(middle @ axis)
    lo = -math.inf if index == 0 else offset + low + extent * index / count
    hi = math.inf if index == count - 1 else offset + low + extent * (index + 1) / count
    return lo, hi


def _edges(points: np.ndarray) -> np.ndarray:
    """Pairs of point indices that include every edge of the points' hull (all pairs if flat)."""
    try:
        simplices = ConvexHull(points).simplices
    except (QhullError, ValueError):  # flat, collinear or too few: every pair
        return np.array(list(combinations(range(len(points)), 2)), dtype=int).reshape(-1, 2)
    pairs = np.vstack([simplices[:, [0, 1]], simplices[:, [1, 2]], simplices[:, [0, 2]]])
    return np.unique(np.sort(pairs, axis=1), axis=0)


def _clip(points: np.ndarray, axis: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Points whose hull is the hull of ``points`` between ``lo <= x . axis <= hi``.

    The vertices within the slab and the crossings of the hull's edges with its two planes.
    """
    s = points @ axis
    found = [points[(s >= lo) & (s <= hi)]]
    edges = _edges(points)
    a, b = s[edges[:, 0]], s[edges[:, 1]]
    for plane in (lo, hi):
        if not math.isfinite(plane):
            continue
        cross = (a - plane) * (b - plane) < 0.0
        t = (plane - a[cross]) / (b[cross] - a[cross])
        start, end = points[edges[cross, 0]], points[edges[cross, 1]]
        found.append(start + t[:, None] * (end - start))
    return np.vstack(found)


def _ball(points: np.ndarray) -> tuple[np.ndarray, float]:
    """A ball containing ``points``: near the smallest (Badoiu-Clarkson), radius to the farthest."""
    center = points.mean(axis=0)
    best, reach = center, math.inf
    for step in range(1, _BALL_STEPS):
        squares = ((points - center) ** 2).sum(axis=1)
        far = int(np.argmax(squares))
        if squares[far] < reach:
            best, reach = center, float(squares[far])
        center = center + (points[far] - center) / (step + 1)
    return best, float(np.sqrt(((points - best) ** 2).sum(axis=1).max()))


def largest_gap(
    geometry: coal.CollisionGeometry,
    centers: np.ndarray,
    radii: np.ndarray,
    samples: int = 400,
) -> float:
    """The largest distance from a point of the spheres' union to ``geometry`` [m].

    Measured with coal at ``samples`` points (a Fibonacci lattice) on each sphere that are not
    inside another sphere of the set: points of the union's boundary, where the largest
    distance is reached.

    Args:
        geometry: The shape, in its own frame (as :func:`enclosing_spheres` gives the spheres).
        centers: Sphere centers (k, 3) [m].
        radii: Radii (k,) [m].
        samples: Points per sphere.
    """
    k = np.arange(samples) + 0.5
    polar = np.arccos(1.0 - 2.0 * k / samples)
    turn = math.pi * (1.0 + math.sqrt(5.0)) * k
    unit = np.column_stack(
        [np.cos(turn) * np.sin(polar), np.sin(turn) * np.sin(polar), np.cos(polar)]
    )
    point = coal.Sphere(1e-9)
    request, result = coal.DistanceRequest(), coal.DistanceResult()
    here = coal.Transform3s()
    largest = 0.0
    for center, radius in zip(centers, radii):
        surface = center + radius * unit
        inside = ((surface[:, None, :] - centers[None]) ** 2).sum(axis=2) < (radii - 1e-9) ** 2
        for p in surface[~inside.any(axis=1)]:
            here.setTranslation(p)
            result.clear()
            gap = coal.distance(point, here, geometry, coal.Transform3s(), request, result)
            largest = max(largest, float(gap))
    return largest
