"""The motion rule's distances: per pair, measured only where the rule reads them, remembered.

:class:`PairDistances` gives the distance of every checked pair at a configuration
(:meth:`~PairDistances.at`: the end of a motion), of chosen pairs only
(:meth:`~PairDistances.of`: a midpoint, where the rule reads only the pairs it has not yet shown
apart), and fills in pairs it did not measure when a caller needs them
(:meth:`~PairDistances.sharpen`). Each array's measured pairs are remembered with it, per
configuration (:data:`_CACHE_BYTES` at most), so that a pair is asked of coal once per
configuration. An unmeasured entry holds a lower bound: ``-inf``, or with ``fast`` the spheres' bound.

``fast`` (:mod:`kin.collision.sphere_bound`): at an end, every pair's distance is first bounded
from below by spheres enclosing the arm's shapes, one NumPy pass for all pairs; a rule that
holds with lower bounds holds with the distances, so coal is asked only of the pairs whose bound
does not suffice. The verdict (:meth:`~PairDistances.in_collision`) is free when every bound is
above :data:`PROVEN_APART`; otherwise coal's verdict-only query of each pair whose bound is not
(the checker's own query, :mod:`kin.collision.requests`): a pair bounded above it is apart by
more than the contact tolerance plus coal's error, so that query calls it free too, and the
verdict is :meth:`kin.collision.CollisionChecker.in_collision`'s at every configuration.

Every value coal gives is the same query the checker's distances ask
(:func:`~kin.collision.requests.prepare_requests`: GJK from its default guess), pair by pair or
all at once: the rule reaches the same verdicts, with the same checks, in either mode.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from ..collision.requests import CONTACT_TOLERANCE, prepare_requests

if TYPE_CHECKING:  # pragma: no cover
    from ..collision import CollisionChecker

__all__ = ["PROVEN_APART", "PairDistances"]

#: A bound above which a pair is apart for every query [m]: twice the contact tolerance (coal's
#: error near contact is below half the tolerance, :mod:`kin.collision.requests`).
PROVEN_APART = 2.0 * CONTACT_TOLERANCE
#: Memory of the remembered distances [bytes] (9 a pair and configuration; then all forgotten at
#: once): 50,000 configurations of a 100-pair model, fewer of a large scene's.
_CACHE_BYTES = 45_000_000


class PairDistances:
    """Per-pair distances of one checker's model at joint vectors (one thread's: it keeps data).

    Args:
        checker: The collision checker (its model's pairs, padding and verdict).
        fast: Bound every pair by spheres first (the module).

    Attributes:
        exact_pairs: Pairs measured or judged by coal so far [count].
    """

    def __init__(self, checker: CollisionChecker, fast: bool = False):
        model = checker.model
        self.checker = checker
        self.count = len(model.pair_owners)
        self._pin_model = model.robot.model
        self._geometry = model.geometry_model
        self._data = self._pin_model.createData()
        self._geometry_data = pin.GeometryData(self._geometry)
        prepare_requests(self._geometry_data, model.padding)
        self._padding = model.padding
        self._placed: bytes | None = None
        self._known: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
        self._capacity = max(100, _CACHE_BYTES // (9 * max(self.count, 1)))
        self.bound = None
        if fast:
            from ..collision.sphere_bound import sphere_bound

            self.bound = sphere_bound(model)
        self.exact_pairs = 0

    def at(self, q: np.ndarray) -> np.ndarray:
        """Every pair's distance at ``q`` [m], padding taken off (with ``fast``: lower bounds).

        The same array at the same ``q`` while it is remembered; :meth:`sharpen` fills it in.
        """
        key = q.tobytes()
        known = self._known.get(key)
        if known is not None and known[1].all():
            return known[0]
        if self.bound is not None:
            if known is not None:
                return known[0]
            values = self.bound.lower_bounds(q)
            exact = np.zeros(self.count, dtype=bool)
            exact[self.bound.fixed_pairs] = True  # measured by coal when the bound was made
        else:
            self._place(q, key)
            pin.computeDistances(self._geometry, self._geometry_data)
            values = np.array(
                [r.min_distance for r in self._geometry_data.distanceResults], dtype=float
            )
            values -= self._padding
            exact = np.ones(self.count, dtype=bool)
            self.exact_pairs += self.count
        self._remember(key, values, exact)
        return values

    def of(self, q: np.ndarray, pairs: np.ndarray, below: np.ndarray | None = None) -> np.ndarray:
        """The distances of ``pairs`` at ``q`` [m]; for the others ``below`` or ``-inf``.

        ``below``: lower bounds of the pairs' distances at ``q`` (e.g. from a motion's ends), an
        array this object then owns (filled in, returned).
        """
        values = np.full(self.count, -np.inf) if below is None else below  # now this object's
        exact = np.zeros(self.count, dtype=bool)
        self._remember(q.tobytes(), values, exact)
        self.sharpen(q, values, pairs)
        return values

    def sharpen(self, q: np.ndarray, d: np.ndarray, pairs: np.ndarray) -> bool:
        """Coal's distances of ``pairs`` into ``d`` (an array of this object's at ``q``) [m].

        Pairs already measured in ``d`` are not asked again. Returns whether any was asked.
        """
        key = q.tobytes()
        known = self._known.get(key)
        if known is None or known[0] is not d:  # forgotten: ``d``'s own entries are unknown
            known = self._remember(key, d, np.zeros(self.count, dtype=bool))
        exact = known[1]
        todo = pairs[~exact[pairs]]
        if len(todo) == 0:
            return False
        self._place(q, key)
        for k in todo.tolist():
            found = pin.computeDistance(self._geometry, self._geometry_data, k)
            d[k] = found.min_distance - self._padding
        exact[todo] = True
        self.exact_pairs += len(todo)
        return True

    def smallest(self, q: np.ndarray, below: np.ndarray) -> float:
        """The smallest distance of any pair at ``q`` [m], padding taken off: coal's, exactly.

        The pairs are asked in the order of ``below`` (lower bounds of their distances at ``q``
        [m], e.g. :meth:`kin.collision.sphere_bound.SphereBound.lower_bounds`), until the next
        bound is above the smallest distance found by more than the contact tolerance (coal's
        error is below half of it): the pairs left cannot be closer, and the value is the one
        :meth:`kin.collision.CollisionChecker.distance` gives at ``q``.
        """
        self._place(q, q.tobytes())
        best = np.inf
        for k in np.argsort(below, kind="stable").tolist():
            if below[k] > best + CONTACT_TOLERANCE:
                break
            found = pin.computeDistance(self._geometry, self._geometry_data, k)
            best = min(best, found.min_distance - self._padding)
            self.exact_pairs += 1
        return float(best)

    def in_collision(self, q: np.ndarray, below: np.ndarray | None = None) -> bool:
        """The checker's verdict at ``q``; with ``fast``, coal asked only where the bounds fail.

        Args:
            q: Joint vector [rad] / [m] (float64, finite, of the robot's size).
            below: With ``fast``: lower bounds of the pairs' distances at ``q`` [m] (e.g. from
                :meth:`of`); None: :meth:`at`'s when it has given them, else the checker's own
                query (where no bounds are at hand it costs less than making them).
        """
        if self.bound is None:
            return bool(self.checker.in_collision(q))
        key = q.tobytes()
        if below is None:
            known = self._known.get(key)
            if known is None:  # no bounds at hand: the checker's query (a few us, stops early)
                return bool(self.checker.in_collision(q))
            below = known[0]
        unsure = np.flatnonzero(below <= PROVEN_APART)
        if len(unsure) == 0:
            return False
        self._place(q, key)
        self.exact_pairs += len(unsure)
        return any(
            pin.computeCollision(self._geometry, self._geometry_data, k) for k in unsure.tolist()
        )

    def _remember(
        self, key: bytes, values: np.ndarray, exact: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        if len(self._known) >= self._capacity:
            self._known.clear()
        known = self._known[key] = (values, exact)
        return known

    def _place(self, q: np.ndarray, key: bytes) -> None:
        """The shapes' placements at ``q`` in this object's geometry data (once per ``q``)."""
        if self._placed != key:
            pin.updateGeometryPlacements(
                self._pin_model, self._data, self._geometry, self._geometry_data, q
            )
            self._placed = key
