"""Lower bounds of every checked pair's distance, from spheres enclosing the arm's shapes.

Each shape the arm carries (its links' shapes, fingers, attached objects) is covered by spheres
that enclose it (:func:`kin.collision.sphere_fit.enclosing_spheres`), fixed in its joint's frame.
At a configuration, one Pinocchio ``forwardKinematics`` places every sphere (NumPy over all of
them at once), and per checked pair:

* two arm shapes: the smallest distance between their spheres (centers' distance less both
  radii);
* an arm shape and a scene object: the smallest distance from a sphere's center to the object
  less its radius, the object exact when it is a box, sphere, cylinder or capsule (the signed
  distance of a point to it), any other (a mesh's hull) through its bounding box, which encloses
  it;
* two shapes that both hang on the world (the base's against the scene): coal's distance, once.

Every shape lies within its cover, so each value is at most the distance between the padded
shapes (the padding taken off, as :class:`kin.path.collision_check.MotionCheck` gives it): a
pair whose bound is above the contact tolerance is apart, whatever coal would say; a pair whose
bound is not is undecided, never in contact on that account (the caller asks coal).
"""

from __future__ import annotations

import threading
import weakref
from typing import TYPE_CHECKING

import coal
import numpy as np
import pinocchio as pin

from .requests import prepare_requests
from .sphere_fit import enclosing_spheres, largest_gap, swept_radius

if TYPE_CHECKING:  # pragma: no cover
    from .model import CollisionModel

__all__ = ["SphereBound", "sphere_bound"]

#: Taken off every sphere bound [m]: the rounding of the bounds' own arithmetic (a few 1e-16 m^2
#: in a squared distance of meters), far below coal's error.
_ROUNDING = 1e-9

_MADE: weakref.WeakKeyDictionary[CollisionModel, SphereBound] = weakref.WeakKeyDictionary()


def sphere_bound(model: CollisionModel) -> SphereBound:
    """The :class:`SphereBound` of ``model``, made once per model (fitting takes 0.1-1 s)."""
    found = _MADE.get(model)
    if found is None:
        found = _MADE[model] = SphereBound(model)
    return found


class SphereBound:
    """Per-pair distance lower bounds of one collision model at joint vectors.

    Args:
        model: The collision model (its geometry model's pairs, in order, and its padding).

    Attributes:
        centers: Sphere centers in their joint's frame, shape (S, 3) [m].
        radii: Sphere radii, shape (S,) [m].
        objects: Per sphere, the geometry object it covers.
    """

    def __init__(self, model: CollisionModel):
        self.model = model
        self.pin_model = model.robot.model
        self._local = threading.local()  # each thread's Pinocchio data (one bound, many users)
        geometry = model.geometry_model.geometryObjects
        scene = {i for i, owner in enumerate(model.owners) if owner in model.scene_objects}
        arm = [i for i in range(len(geometry)) if i not in scene]
        centers, radii, objects, joints = [], [], [], []
        for index in arm:
            obj = geometry[index]
            local, radius = enclosing_spheres(obj.geometry)
            rotation, translation = obj.placement.rotation, obj.placement.translation
            centers.append(local @ rotation.T + translation)
            radii.append(radius)
            objects += [index] * len(radius)
            joints += [int(obj.parentJoint)] * len(radius)
        self.centers = np.vstack(centers) if centers else np.zeros((0, 3))
        self.radii = np.concatenate(radii) if radii else np.zeros(0)
        self.objects = np.array(objects, dtype=int)
        self._joints = np.array(joints, dtype=int)
        self._homogeneous = np.vstack([self.centers.T, np.ones(len(self.radii))])  # (4, S)
        # in the (4 nj, S) product, sphere s's coordinate i is at row 4 joint(s) + i, column s
        spheres = np.arange(len(self.radii))
        self._placed = (
            (4 * self._joints[:, None] + np.arange(3)[None]) * len(self.radii) + spheres[:, None]
        ).ravel()
        self._row = {index: row for row, index in enumerate(arm)}  # arm object -> cover row
        self._starts = np.searchsorted(self.objects, arm) if arm else np.zeros(0, dtype=int)
        self._scene = _SceneShapes([geometry[i] for i in sorted(scene)])
        self._column = {index: k for k, index in enumerate(sorted(scene))}  # scene object -> k
        self._pairs(model, geometry, scene)

    def _pairs(self, model: CollisionModel, geometry, scene: set[int]) -> None:  # noqa: ANN001
        """Sort the pairs into the three kinds of the module, with their index arrays."""
        pairs = list(model.geometry_model.collisionPairs)
        self.count = len(pairs)
        self._fixed = np.zeros(self.count)
        fixed: list[int] = []
        self_pairs: list[int] = []
        scene_pairs: list[int] = []
        starts: list[int] = []
        arm_rows: list[int] = []
        columns: list[int] = []
        first: list[np.ndarray] = []
        second: list[np.ndarray] = []
        placed = 0
        spheres_of = {i: np.flatnonzero(self.objects == i) for i in self._row}
        data = pin.GeometryData(model.geometry_model)
        prepare_requests(data, model.padding)
        q0 = pin.neutral(self.pin_model)
        pin.updateGeometryPlacements(
            self.pin_model, self.pin_model.createData(), model.geometry_model, data, q0
        )
        for k, pair in enumerate(pairs):
            a, b = int(pair.first), int(pair.second)
            if geometry[a].parentJoint == 0 and geometry[b].parentJoint == 0:
                fixed.append(k)
                found = pin.computeDistance(model.geometry_model, data, k)
                self._fixed[k] = float(found.min_distance) - model.padding
            elif a in scene or b in scene:
                scene_pairs.append(k)
                arm_rows.append(self._row[b if a in scene else a])
                columns.append(self._column[a if a in scene else b])
            else:
                self_pairs.append(k)
                i, j = np.meshgrid(spheres_of[a], spheres_of[b], indexing="ij")
                starts.append(placed)
                placed += i.size
                first.append(i.ravel())
                second.append(j.ravel())
        self.fixed_pairs = np.array(fixed, dtype=int)
        self._self_pairs = np.array(self_pairs, dtype=int)
        self._scene_pairs = np.array(scene_pairs, dtype=int)
        self._first = np.concatenate(first) if first else np.zeros(0, dtype=int)
        self._second = np.concatenate(second) if second else np.zeros(0, dtype=int)
        self._self_starts = np.array(starts, dtype=int)
        self._both_radii = self.radii[self._first] + self.radii[self._second] + _ROUNDING
        self._flat = self._first * len(self.radii) + self._second
        self._scene_flat = np.array(arm_rows, dtype=int) * self._scene.count + self._scene.order(
            columns
        )
        # the pairs the spheres bound, in the order lower_bounds finds them
        self._moving = np.concatenate([self._self_pairs, self._scene_pairs]).astype(int)
        self._radii_column = self.radii[None, :, None]

    def world_centers(self, q: np.ndarray) -> np.ndarray:
        """The spheres' centers at joint vectors ``q`` (N, nq) [rad] / [m]: (N, S, 3) [m], world.

        One Pinocchio ``forwardKinematics`` per row; the rest one NumPy product for all rows.
        """
        model = self.pin_model
        data = getattr(self._local, "data", None)
        if data is None:
            data = self._local.data = model.createData()
        placements = []
        for row in q:
            pin.forwardKinematics(model, data, row)
            placements.append([m.np for m in data.oMi.tolist()])
        # (N, 4 nj, 4) times the homogeneous local centers (4, S): every sphere on every joint,
        # then each sphere's own joint taken
        product = np.array(placements).reshape(len(q), -1, 4) @ self._homogeneous
        return product.reshape(len(q), -1).take(self._placed, axis=1).reshape(len(q), -1, 3)

    def lower_bounds(self, q: np.ndarray) -> np.ndarray:
        """Per collision pair of the model (in order), a lower bound of its distance [m].

        The distance between the padded shapes as coal's would be with the padding taken off,
        where the bound is positive; ``-inf`` where the spheres do not show the pair apart.

        Args:
            q: Joint vector (nq,) or vectors (N, nq) [rad] / [m], finite, of the robot's size
                (not checked here).

        Returns:
            Shape (P,), or (N, P) for ``q`` of shape (N, nq).
        """
        rows = np.atleast_2d(q)
        out = np.repeat(self._fixed[None], len(rows), axis=0)
        if len(self.radii):
            centers = self.world_centers(rows)
            found = []
            if len(self._self_pairs):  # the smallest center distance less the radii
                apart = centers.take(self._first, axis=1) - centers.take(self._second, axis=1)
                between = np.sqrt(np.einsum("npi,npi->np", apart, apart)) - self._both_radii
                found.append(np.minimum.reduceat(between, self._self_starts, axis=1))
            if len(self._scene_pairs):  # the smallest distance to the shape less the radius
                clear = self._scene.distances(centers) - self._radii_column
                per_object = np.minimum.reduceat(clear, self._starts, axis=1)
                found.append(per_object.reshape(len(rows), -1).take(self._scene_flat, axis=1))
            bounds = np.concatenate(found, axis=1) - self.model.padding
            out[:, self._moving] = np.where(bounds > 0.0, bounds, -np.inf)
        return out if np.ndim(q) == 2 else out[0]

    def gaps(self, samples: int = 200) -> dict[str, float]:
        """Per owner (link or attached object), the largest gap of its shapes' covers [m].

        :func:`~kin.collision.sphere_fit.largest_gap` of each shape, the largest per owner.
        """
        geometry = self.model.geometry_model.geometryObjects
        found: dict[str, float] = {}
        for index in self._row:
            obj = geometry[index]
            local, radius = enclosing_spheres(obj.geometry)
            gap = largest_gap(obj.geometry, local, radius, samples)
            owner = self.model.owners[index]
            found[owner] = max(found.get(owner, 0.0), gap)
        return found


class _SceneShapes:
    """Signed distances from points to the scene's shapes, all of them at once (NumPy).

    The shapes are kept by kind (boxes, spheres, cylinders, capsules), each kind's columns
    together; :meth:`order` maps a shape's index in the scene to its column.
    """

    def __init__(self, objects: list[pin.GeometryObject]):
        self.count = len(objects)
        kinds = [_kind(obj.geometry) for obj in objects]
        ranked = sorted(range(self.count), key=lambda k: (_KINDS.index(kinds[k]), k))
        self._column = np.empty(self.count, dtype=int)
        self._column[ranked] = np.arange(self.count)
        sizes = np.array([_sizes(objects[k].geometry) for k in ranked]).reshape(-1, 7)
        rotations = np.array([objects[k].placement.rotation for k in ranked]).reshape(-1, 3, 3)
        translations = np.array([objects[k].placement.translation for k in ranked]).reshape(-1, 3)
        # a bounding box's center may sit off its shape's frame (a mesh's hull)
        translations = translations + np.einsum("kij,kj->ki", rotations, sizes[:, 3:6])
        # local = (p - t) R = p R - t R: one product for every shape (3, 3K) and an offset (3K,)
        self._rotations = rotations.transpose(1, 0, 2).reshape(3, -1)
        self._offsets = np.einsum("ki,kij->kj", translations, rotations).ravel()
        self._half = sizes[:, :3]
        self._swept = sizes[:, 6]
        ordered = [kinds[k] for k in ranked]
        self._slices = [
            (kind, ordered.index(kind), len(ordered) - ordered[::-1].index(kind))
            for kind in _KINDS
            if kind in ordered
        ]

    def order(self, columns: list[int]) -> np.ndarray:
        """The columns of :meth:`distances` of the scene's shapes ``columns``."""
        return self._column[np.asarray(columns, dtype=int)]

    def distances(self, points: np.ndarray) -> np.ndarray:
        """Distance from each point (N, S, 3) to each shape, negative inside: (N, S, K) [m]."""
        n, s = points.shape[:2]
        local = (points.reshape(-1, 3) @ self._rotations - self._offsets).reshape(n, s, -1, 3)
        out = np.empty((n, s, self.count))
        for kind, a, b in self._slices:
            here, half = local[:, :, a:b], self._half[a:b]
            if kind == "box":
                beyond = np.abs(here) - half
                found = np.sqrt(np.einsum("nski,nski->nsk", *2 * (np.maximum(beyond, 0.0),)))
                found += np.minimum(beyond.max(axis=3), 0.0)
            elif kind == "sphere":
                found = np.sqrt(np.einsum("nski,nski->nsk", here, here)) - half[:, 0]
            elif kind == "cylinder":
                radial = np.hypot(here[..., 0], here[..., 1]) - half[:, 0]
                axial = np.abs(here[..., 2]) - half[:, 1]
                found = np.hypot(np.maximum(radial, 0.0), np.maximum(axial, 0.0))
                found += np.minimum(np.maximum(radial, axial), 0.0)
            else:  # capsule: the distance to its segment less its radius
                along = here[..., 2] - np.clip(here[..., 2], -half[:, 1], half[:, 1])
                found = np.sqrt(here[..., 0] ** 2 + here[..., 1] ** 2 + along**2) - half[:, 0]
            out[:, :, a:b] = found - self._swept[a:b]
        return out


#: The kinds of scene shape, in their column order.
_KINDS = ("box", "sphere", "cylinder", "capsule")


def _kind(geometry: coal.CollisionGeometry) -> str:
    if isinstance(geometry, coal.Sphere):
        return "sphere"
    if isinstance(geometry, coal.Cylinder):
        return "cylinder"
    if isinstance(geometry, coal.Capsule):
        return "capsule"
    return "box"  # a box, or any other shape through its bounding box


def _sizes(geometry: coal.CollisionGeometry) -> list[float]:
    """Half sizes (3), the box's center in the shape's frame (3), the swept radius [m]."""
    swept = swept_radius(geometry)
    if isinstance(geometry, coal.Sphere):
        return [geometry.radius, 0.0, 0.0, 0.0, 0.0, 0.0, swept]
    if isinstance(geometry, (coal.Cylinder, coal.Capsule)):
        return [geometry.radius, geometry.halfLength, 0.0, 0.0, 0.0, 0.0, swept]
    if isinstance(geometry, coal.Box):
        return [*np.asarray(geometry.halfSide, dtype=float), 0.0, 0.0, 0.0, swept]
    geometry.computeLocalAABB()
    box = geometry.aabb_local
    low, high = np.asarray(box.min_, dtype=float), np.asarray(box.max_, dtype=float)
    return [*(0.5 * (high - low)), *(0.5 * (high + low)), swept]
