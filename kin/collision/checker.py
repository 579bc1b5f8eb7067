"""Collision and distance queries of a :class:`~kin.collision.CollisionModel` at joint vectors.

One checker serves many threads: each thread gets its own Pinocchio data and geometry data on
first use (as the IK solvers keep theirs). Points are in the world frame (the arm's base) [m].

``in_collision`` is the hot call (IK branches, path samples, reach voxels): it uses geometry data
that asks coal for the verdict only (no contact points), the same pair queries as a bare
``pin.computeCollisions`` (behind a broad phase of world boxes when the model has meshes or many
pairs: :class:`_PerThread`; else pair by pair, the pairs most often in contact first:
:mod:`.pair_order`), and passes an array whose values sum to a finite number straight to it
(anything else, or Pinocchio's size error, sends ``q`` to
:func:`kin.configuration.as_joint_vector`, which converts it or names the bad value).

**One verdict** (:mod:`.requests`): a pair is in contact when coal's verdict-only query finds it
closer than the padding plus :data:`~kin.collision.requests.CONTACT_TOLERANCE`. ``in_collision``,
``in_collision_batch`` and ``collisions`` ask that same query of every pair (``collisions`` of all
of them, on a second geometry data), so they agree at every configuration; ``collisions`` then
measures each pair it lists with coal's distance query (depth and points). ``distance`` is that
distance query's smallest value: a configuration where it is below 0 is in collision, one where it
is above the tolerance is free, and in between it is in collision with depth 0.
"""

from __future__ import annotations

import os
import threading
from dataclasses import dataclass
from functools import partial
from math import isfinite
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from ..configuration import as_joint_vector
from .model import CollisionModel
from .requests import prepare_requests

__all__ = ["BROAD_PHASE_PAIRS", "Closest", "CollisionChecker", "Contact"]

_FLOAT64 = np.dtype(np.float64)
#: Pairs above which the verdicts go through the broad phase even without meshes [count]: a large
#: scene's pairs are mostly far apart, and their boxes clear them faster than a test each.
BROAD_PHASE_PAIRS = 256


@dataclass(frozen=True)
class Contact:
    """Two shapes in contact.

    Attributes:
        a: Link (base side) or link of a scene pair.
        b: Link or scene object.
        depth: How far the padded shapes overlap [m], >= 0: the padding minus coal's signed
            distance of the pair; 0 for a pair within
            :data:`~kin.collision.requests.CONTACT_TOLERANCE` of touching.
        point_a: Nearest (or deepest) point on ``a``, world frame [m], shape (3,).
        point_b: Nearest (or deepest) point on ``b``, world frame [m], shape (3,).
    """

    a: str
    b: str
    depth: float
    point_a: np.ndarray
    point_b: np.ndarray


@dataclass(frozen=True)
class Closest:
    """The closest checked pair.

    Attributes:
        a: Link (base side) or link of a scene pair.
        b: Link or scene object.
        distance: Distance between the padded shapes [m]; negative when they overlap. Below 0
            the configuration is in collision; above
            :data:`~kin.collision.requests.CONTACT_TOLERANCE` it is free by every query.
        point_a: Nearest point on ``a``, world frame [m], shape (3,).
        point_b: Nearest point on ``b``, world frame [m], shape (3,).
    """

    a: str
    b: str
    distance: float
    point_a: np.ndarray
    point_b: np.ndarray


class CollisionChecker:
    """Collision queries of one model, safe to call from many threads at once.

    Args:
        model: The collision model (:func:`kin.collision.load_collision_model`).

    Attributes:
        broad_phase: Whether the verdicts go through coal's broad phase (world boxes first):
            when a shape is a mesh's hull, whose exact test (GJK, about 1-2 us a pair) costs
            far more than a box test, or the model has more than :data:`BROAD_PHASE_PAIRS`
            pairs; a few primitives are tested exactly pair by pair, which stops sooner at the
            first contact (see :class:`_PerThread`), in the order of :mod:`.pair_order` (the
            pairs most often in contact first).
    """

    def __init__(self, model: CollisionModel):
        self.model = model
        self._robot = model.robot
        self._pin_model = model.robot.model
        self._geometry = model.geometry_model
        self._nq = model.robot.nq
        self.broad_phase = len(model.pair_owners) > BROAD_PHASE_PAIRS or any(
            _costly(g.geometry) for g in self._geometry.geometryObjects
        )
        self._verdict_geometry = self._geometry
        if not self.broad_phase:
            from .pair_order import verdict_geometry_model

            self._verdict_geometry = verdict_geometry_model(
                self._pin_model, self._geometry, model.padding
            )
        self._local = _PerThread(self)
        self._pool_lock = threading.Lock()
        self._pools: dict[int, Any] = {}

    def _new_geometry_data(self, every: bool) -> pin.GeometryData:
        """Geometry data with the model's padding: of every pair (``every``), else the verdicts'."""
        geometry_data = pin.GeometryData(self._geometry if every else self._verdict_geometry)
        self._prepare(geometry_data)
        return geometry_data

    def _prepare(self, geometry_data: pin.GeometryData) -> None:
        prepare_requests(geometry_data, self.model.padding)

    def _q(self, q: npt.ArrayLike) -> np.ndarray:
        """``q`` itself when it is a finite float64 vector of size nq, else the checked copy."""
        if (
            q.__class__ is np.ndarray
            and q.dtype is _FLOAT64  # type: ignore[union-attr]
            and q.ndim == 1  # type: ignore[union-attr]
            and len(q) == self._nq  # type: ignore[arg-type]
            and isfinite(sum(q.tolist()))  # type: ignore[union-attr]
        ):
            return q  # type: ignore[return-value]
        return as_joint_vector(self._robot, q)  # converts, or raises the detailed error

    def in_collision(self, q: npt.ArrayLike) -> bool:
        """Whether any checked pair is in contact at ``q`` [rad, m] (stops at the first).

        Raises:
            kin.JointVectorError: Wrong size or non-finite values.
        """
        # The input check costs a fifth of Pinocchio's call on a small arm: an array whose values
        # sum to a finite float goes to Pinocchio as it is; anything else (a list, a string, a
        # 2-D array, complex or object values: no tolist, a sum or isfinite that fails, or
        # Pinocchio's size or type error) to as_joint_vector, which converts it or raises the
        # detailed error. Pinocchio takes an int, bool or float32 array as its float64 values.
        try:
            if isfinite(sum(q.tolist())):  # type: ignore[union-attr]
                return self._local.check(q, True)  # type: ignore[no-any-return]
        except (AttributeError, TypeError, ValueError):
            pass
        return self._local.check(as_joint_vector(self._robot, q), True)  # type: ignore[no-any-return]

    def collisions(self, q: npt.ArrayLike) -> tuple[Contact, ...]:
        """The pairs in contact at ``q`` [rad, m], the deepest contact of each, deepest first.

        A pair is listed exactly when :meth:`in_collision` counts it (the same verdict-only
        query, of every pair); its depth and points are coal's distance query's.

        Raises:
            kin.JointVectorError: Wrong size or non-finite values.
        """
        local = self._local
        geometry_data = local.every
        pin.computeCollisions(
            self._pin_model, local.data, self._geometry, geometry_data, self._q(q), False
        )
        deepest: dict[tuple[str, str], Contact] = {}
        padding = self.model.padding
        for index, result in enumerate(geometry_data.collisionResults):
            if not result.isCollision():
                continue
            measured = pin.computeDistance(self._geometry, geometry_data, index)
            # the signed distance (negative inside) against the padding: depth >= 0
            depth = max(0.0, padding - float(measured.min_distance))
            a, b = self.model.pair_owners[index]
            known = deepest.get((a, b))
            if known is None or depth > known.depth:
                deepest[(a, b)] = Contact(
                    a,
                    b,
                    depth,
                    np.array(measured.getNearestPoint1()),
                    np.array(measured.getNearestPoint2()),
                )
        return tuple(sorted(deepest.values(), key=lambda c: -c.depth))

    def distance(self, q: npt.ArrayLike) -> Closest:
        """The closest checked pair at ``q`` [rad, m] and its distance [m] (padding taken off).

        Below 0, :meth:`in_collision` is True at ``q``; above
        :data:`~kin.collision.requests.CONTACT_TOLERANCE`, False.

        Raises:
            kin.JointVectorError: Wrong size or non-finite values.
            ValueError: The model checks no pair.
        """
        if not self.model.pair_owners:
            raise ValueError("the collision model checks no pair: no distance to give")
        local = self._local
        geometry_data = local.every
        index = pin.computeDistances(
            self._pin_model, local.data, self._geometry, geometry_data, self._q(q)
        )
        result = geometry_data.distanceResults[index]
        a, b = self.model.pair_owners[index]
        return Closest(
            a,
            b,
            float(result.min_distance) - self.model.padding,
            np.array(result.getNearestPoint1()),
            np.array(result.getNearestPoint2()),
        )

    def _batch(self, qs: npt.ArrayLike) -> np.ndarray:
        values = np.asarray(qs, dtype=float)
        if values.ndim != 2 or values.shape[1] != self._robot.nq:
            from ..exceptions import JointVectorError

            raise JointVectorError(
                f"joint vectors must have shape (N, {self._robot.nq}), got {values.shape}",
                self._robot.nq,
                values.shape[-1] if values.ndim else 0,
            )
        if not np.isfinite(values).all():
            row = int(np.flatnonzero(~np.isfinite(values).all(axis=1))[0])
            as_joint_vector(self._robot, values[row])
        return values

    def in_collision_batch(self, qs: npt.ArrayLike, threads: int | None = None) -> np.ndarray:
        """:meth:`in_collision` of each row of ``qs`` (N, nq) [rad, m], on all cores.

        Args:
            qs: Joint vectors, one per row.
            threads: Threads to use (default: the cores this process may use).

        Returns:
            Boolean array (N,).
        """
        values = self._batch(qs)
        if len(values) == 0:
            return np.zeros(0, dtype=bool)
        count = threads or _cores()
        with self._pool_lock:
            result = pin.computeCollisionsInParallel(
                count, self._pool(count), np.asfortranarray(values.T), True
            )
        return np.asarray(result, dtype=bool).reshape(len(values))

    def _pool(self, count: int) -> Any:
        """The batches' pool of ``count`` threads' data, made at the first batch (under the lock).

        With meshes, coal's dynamic AABB tree as broad phase (Pinocchio binds no pool of the naive
        manager the single call uses): 1.5-2x faster than the plain pool on UR5. Kept from batch
        to batch (making one costs 1-1.5 ms on Panda): its verdicts do not depend on what it
        computed before, since GJK starts from its default guess (:mod:`.requests`; a pool once
        called a Panda configuration free after other batches, when GJK started from the
        previous answer: tests/collision/test_collision_batch_history.py).
        """
        pool = self._pools.get(count)
        if pool is None:
            pool = (
                pin.BroadPhaseManagerPool_DynamicAABBTreeCollisionManager
                if self.broad_phase
                else pin.GeometryPool
            )(self._pin_model, self._verdict_geometry, count)
            for geometry_data in pool.getGeometryDatas():
                self._prepare(geometry_data)
            self._pools[count] = pool
        return pool

    def distances_batch(self, qs: npt.ArrayLike) -> np.ndarray:
        """:meth:`distance` of each row of ``qs`` (N, nq) [rad, m].

        A loop: Pinocchio's bindings keep Python's lock through ``computeDistances``, so threads
        gain nothing (measured on Panda, 1,000 configurations: 0.095 s looped, 0.098 s on 2).

        Returns:
            Distances [m], shape (N,).
        """
        values = self._batch(qs)
        return np.array([self.distance(q).distance for q in values], dtype=float)


class _PerThread(threading.local):
    """One thread's Pinocchio data and geometry data (the verdicts' pairs, and every pair).

    ``check(q, stop_at_first)`` is Pinocchio's computeCollisions over the verdict-only data. With
    :attr:`CollisionChecker.broad_phase`, through coal's naive broad phase: FK and the shapes'
    world boxes once, each box grown by half the padding, and the exact test only for the pairs
    whose boxes overlap (the same coal call as without the broad phase, so the same verdict; 3-4x
    faster on free UR5 and Panda configurations, where every pair must be cleared). The naive
    manager keeps no state between calls but the boxes it recomputes (the tree managers were
    slower for 7-12 shapes). Without it (primitives only), every pair in order up to the first
    contact: on humanoid7 in the test cell the boxes cost 1.2 us a call where it collides (two
    thirds of random configurations) and save as much where it is free.
    """

    def __init__(self, checker: CollisionChecker):
        self.data = checker._pin_model.createData()
        self.verdict = checker._new_geometry_data(every=False)
        self.every = checker._new_geometry_data(every=True)
        if checker.broad_phase:
            self.manager = pin.BroadPhaseManager_NaiveCollisionManager(
                checker._pin_model, checker._geometry, self.verdict
            )
            self.check = partial(pin.computeCollisions, checker._pin_model, self.data, self.manager)
        else:
            self.check = partial(
                pin.computeCollisions,
                checker._pin_model,
                self.data,
                checker._verdict_geometry,
                self.verdict,
            )


def _costly(geometry: object) -> bool:
    """Whether coal's exact test of ``geometry`` is GJK on many vertices (a mesh or its hull)."""
    import coal

    return (
        geometry.getObjectType() != coal.OBJECT_TYPE.OT_GEOM  # type: ignore[attr-defined]
        or geometry.getNodeType() == coal.NODE_TYPE.GEOM_CONVEX  # type: ignore[attr-defined]
    )


def _cores() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)
