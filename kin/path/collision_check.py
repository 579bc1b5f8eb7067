"""Collision check of a joint path: every sample, and the motion between samples.

**One verdict** (:mod:`kin.collision.requests`): a pair is in contact when its distance (padding
taken off) is below :data:`~kin.collision.requests.CONTACT_TOLERANCE` (10 um), and every
configuration this module calls in contact, a sample or a point between two, is one where
:meth:`kin.collision.CollisionChecker.in_collision` says so (the samples by its batch, the points
between them by itself), so a path is never called colliding at a place the checker calls free,
nor free through a place it calls colliding. The distances are coal's, asked through the same
requests as the checker's (:func:`~kin.collision.requests.prepare_requests`: GJK to 1e-8 m from
its default guess, signed).

The rule between two samples (a step bound, conservative advancement): on the straight joint
segment from ``q0`` to ``q1``, a point of a shape carried by joint ``k`` moves at most

    B = sum over the revolute joints j at or above k of |q1_j - q0_j| * R_jk
        + sum over the prismatic joints j at or above k of |q1_j - q0_j|

where ``R_jk`` bounds the distance of the shape's (padded) points from joint j's axis: the lengths
of the joint origins' links from j to k (a prismatic joint's travel taken at its larger end value
on the segment) plus the shape's bounding-sphere reach from joint k's origin. Two shapes close by
at most ``B_a + B_b`` (a scene object does not move); on an all-revolute arm, the joints that
carry both shapes of a self pair (those at or above the last joint they share) move them together
as one rigid body and leave their distance unchanged, so they are left out of both sums: the
pair's bound ``B_ab`` counts only the joints between the two shapes (a forearm and a wrist held
6 mm apart are not pulled apart by the shoulder's motion). A pair whose distances at the two ends
satisfy ``(d0 - tol) + (d1 - tol) > B_ab``, ``tol`` the contact tolerance, stays beyond the
tolerance in between (the lower bounds ``d0 - B t`` and ``d1 - B (1 - t)`` stay above ``tol``):
no point between is in contact. Otherwise the segment is halved and the midpoint judged by
``in_collision`` (a colliding midpoint is named, after the earlier half is searched for an earlier
contact), down to a bound of ``tolerance`` [m]: a pair that cannot be shown beyond the contact
tolerance at that scale is reported as a collision not proven (``proven`` False: closer than the
contact tolerance plus ``tolerance``, every point checked free).

Where contact begins on the way into the first colliding sample: bisection on the segment from
the last free sample (on the sample verdict) until the links' motion bound between a free point and
a colliding one is at most ``tolerance`` [m] (1e-6 m by default), the colliding one named; the
motion before the free point is checked by the rule above, so an earlier contact on the segment
is named instead. Between two free samples the halving names the first contact the same way (the
earlier half first).
"""

from __future__ import annotations

import dataclasses
from collections import deque
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..collision.requests import CONTACT_TOLERANCE
from .pair_distances import PairDistances
from .path_collision import TOLERANCE, PathCollision, PathCollisionCheck

if TYPE_CHECKING:
    from ..collision import CollisionChecker

__all__ = ["MotionCheck", "PathCollision", "PathCollisionCheck", "check_path_collisions"]


class _Distances:
    """Per-pair distances and per-shape motion bounds of one checker's model.

    With ``fast``, the distances at the ends of a motion are bounded by spheres first
    (:mod:`kin.path.pair_distances`): the same verdicts, less work.
    """

    def __init__(self, checker: CollisionChecker, fast: bool = False):
        model = checker.model
        self.model = model
        self.checker = checker
        self.pin_model = model.robot.model
        #: The pairs' distances, measured where the rule reads them.
        self.measured = PairDistances(checker, fast)
        self.pairs = [(p.first, p.second) for p in model.geometry_model.collisionPairs]
        self.first = np.array([p[0] for p in self.pairs], dtype=int)
        self.second = np.array([p[1] for p in self.pairs], dtype=int)
        nj = self.pin_model.njoints
        self.parents = list(self.pin_model.parents)
        self.links = [float(np.linalg.norm(p.translation)) for p in self.pin_model.jointPlacements]
        # revolute (RX, RY, RZ, RevoluteUnaligned) or prismatic (PX, ..., PrismaticUnaligned)
        self.kinds = [j.shortname()[len("JointModel") :][:1] for j in self.pin_model.joints]
        self.idx_q = [j.idx_q for j in self.pin_model.joints]
        unknown = [self.pin_model.names[i] for i in range(1, nj) if self.kinds[i] not in "RP"]
        if unknown or self.pin_model.nq != model.robot.nq:
            raise ValueError(
                f"path collision check: joints {unknown} are neither revolute nor prismatic"
            )
        # bounding reach of each shape from its joint's origin [m], padding included
        self.reach = []
        self.parent = []
        for obj in model.geometry_model.geometryObjects:
            geometry = obj.geometry
            geometry.computeLocalAABB()
            center = obj.placement.rotation @ np.asarray(geometry.aabb_center) + np.asarray(
                obj.placement.translation
            )
            self.reach.append(float(np.linalg.norm(center) + geometry.aabb_radius + model.padding))
            self.parent.append(int(obj.parentJoint))
        #: All revolute: the bound is linear in |dq| (object x joint arms), else None.
        self.arms = self._arms() if all(k == "R" for k in self.kinds[1:]) else None
        #: All revolute: per pair and joint, the pair's reach (the joints carrying both left out).
        self.pair_arms = self._pair_arms(self.arms) if self.arms is not None else None

    def _arms(self) -> np.ndarray:
        """Per object and joint, the reach R_jk of the module's rule [m] (revolute arms)."""
        arms = np.zeros((len(self.reach), self.pin_model.nq))
        for index, (joint, reach) in enumerate(zip(self.parent, self.reach)):
            arm, k = reach, joint
            while k > 0:
                arms[index, self.idx_q[k]] += arm
                arm += self.links[k]
                k = self.parents[k]
        return arms

    def _ancestors(self, joint: int) -> set[int]:
        """The joints that carry ``joint``'s body: ``joint`` and every joint above it."""
        found = set()
        while joint > 0:
            found.add(joint)
            joint = self.parents[joint]
        return found

    def _pair_arms(self, arms: np.ndarray) -> np.ndarray:
        """Per pair and joint, the reach of the rule on the two shapes, shared joints left out."""
        out = np.zeros((len(self.pairs), arms.shape[1]))
        for index, (a, b) in enumerate(self.pairs):
            shared = self._ancestors(self.parent[a]) & self._ancestors(self.parent[b])
            out[index] = arms[a] + arms[b]
            for joint in shared:
                out[index, self.idx_q[joint]] = 0.0
        return out

    def pair_motion(self, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
        """Per collision pair, the bound on how much its two shapes close along q0 -> q1 [m]."""
        if self.pair_arms is not None:
            return self.pair_arms @ np.abs(q1 - q0)
        motion = self.motion(q0, q1)
        return motion[self.first] + motion[self.second]

    def motion(self, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
        """Per geometry object, the bound B on its points' motion along q0 -> q1 [m]."""
        dq = np.abs(q1 - q0)
        if self.arms is not None:
            return self.arms @ dq
        out = np.zeros(len(self.reach))
        for index, (joint, reach) in enumerate(zip(self.parent, self.reach)):
            bound = 0.0
            arm = reach  # distance bound from the current joint's origin
            k = joint
            while k > 0:
                iq = self.idx_q[k]
                if self.kinds[k] == "R":
                    bound += dq[iq] * arm
                else:
                    bound += dq[iq]
                    arm += max(abs(q0[iq]), abs(q1[iq]))  # the joint's travel shifts its child
                arm += self.links[k]  # from joint k's origin to its parent's
                k = self.parents[k]
            out[index] = bound
        return out


def check_path_collisions(
    checker: CollisionChecker,
    q: npt.ArrayLike,
    *,
    tolerance: float = TOLERANCE,
    max_checks: int = 100_000,
) -> PathCollisionCheck:
    """Check every sample of a joint path and the straight joint motion between them.

    Args:
        checker: The collision checker (its model's shapes, scene, allowed pairs and padding).
        q: Joint path, shape (M, nq) [rad] / [m] (e.g. :attr:`kin.path.PathResult.q`).
        tolerance: Bound [m] below which a pair not shown apart counts as in collision.
        max_checks: Most configurations checked between samples (then the rest counts as not
            shown free, reported as a collision not proven).

    Returns:
        The verdict and the first colliding place (sample or motion), in path order.

    Raises:
        kin.JointVectorError: A sample of the wrong size or with non-finite values.
    """
    path = np.asarray(q, dtype=float)
    if path.ndim != 2:
        path = path.reshape(-1, checker.model.robot.nq)
    if len(path) == 0:
        return PathCollisionCheck(True, None, np.zeros(0, dtype=bool), 0)
    at_samples = checker.in_collision_batch(path)
    motion = MotionCheck(checker, tolerance)
    if motion.helper is None:
        return PathCollisionCheck(True, None, at_samples, 0, resolution=tolerance)
    ends = [motion.distances(path[0])]
    for i in range(len(path)):
        if at_samples[i]:
            first = _entry(checker, motion, path, i, ends[-1], max_checks)
            return PathCollisionCheck(False, first, at_samples, motion.checks, resolution=tolerance)
        if i + 1 == len(path) or at_samples[i + 1]:
            continue
        ends.append(motion.distances(path[i + 1]))
        found = motion.between(path[i], path[i + 1], ends[-2], ends[-1], i, max_checks)
        if found is not None:
            return PathCollisionCheck(False, found, at_samples, motion.checks, resolution=tolerance)
    return PathCollisionCheck(True, None, at_samples, motion.checks, resolution=tolerance)


def _entry(
    checker: CollisionChecker,
    motion: MotionCheck,
    path: np.ndarray,
    index: int,
    before: np.ndarray,
    max_checks: int,
) -> PathCollision:
    """Where contact begins on the way into the colliding sample ``index``.

    Bisection between sample ``index - 1`` (free, :meth:`MotionCheck.distances` ``before``) and
    sample ``index`` (in contact) on the verdict of
    :meth:`~kin.collision.CollisionChecker.in_collision`, until the links' motion bound between
    the free end and the colliding one is at most the rule's tolerance [m]; then the motion from
    sample ``index - 1`` to that free end is checked by the rule, so an earlier contact on the
    segment is named instead (a place only closer than the tolerance there is the approach to
    this contact, or a near miss: not named). The first sample is named itself.
    """
    if index == 0 or motion.helper is None:
        a, b, kind = _colliding_pair(checker, path[index])
        return PathCollision(0, 0.0, path[index].copy(), a, b, kind, True, True)
    q0, q1 = path[index - 1], path[index]
    bound = 2.0 * float(motion.helper.motion(q0, q1).max())  # two shapes close at most this
    low, high = 0.0, 1.0
    while bound * (high - low) > motion.tolerance and high - low > 1e-15:
        middle = 0.5 * (low + high)
        if checker.in_collision(q0 + middle * (q1 - q0)):
            high = middle
        else:
            low = middle
    q_free = q0 + low * (q1 - q0)
    if low > 0.0:
        earlier = motion.between(
            q0, q_free, before, motion.distances(q_free), index - 1, max_checks
        )
        if earlier is not None and earlier.proven:
            return dataclasses.replace(earlier, fraction=earlier.fraction * low)
    q_contact = q0 + high * (q1 - q0)
    a, b, kind = _colliding_pair(checker, q_contact)
    return PathCollision(index - 1, high, q_contact, a, b, kind, high >= 1.0, True)


class MotionCheck:
    """The rule of this module on single joint motions, the subdivisions counted.

    Args:
        checker: The collision checker.
        tolerance: Bound [m] below which a pair not shown apart counts as in collision.
        fast: Judge by spheres first and ask coal only of the pairs they leave undecided
            (:mod:`kin.collision.sphere_checks`): the same verdicts and checks, less work; the
            distances it gives are then lower bounds (``-inf`` where not shown apart).

    Attributes:
        checks: Configurations checked between the ends so far.
    """

    def __init__(self, checker: CollisionChecker, tolerance: float = TOLERANCE, fast: bool = False):
        self.checker = checker
        self.tolerance = tolerance
        self.helper = _Distances(checker, fast) if checker.model.pair_owners else None
        self.checks = 0

    def in_collision(self, q: np.ndarray) -> bool:
        """The checker's verdict at ``q``, a float64 joint vector (spheres first with ``fast``)."""
        if self.helper is None:
            return bool(self.checker.in_collision(q))
        return self.helper.measured.in_collision(q)

    def distances(self, q: np.ndarray) -> np.ndarray:
        """Per collision pair, the distance at ``q`` [m] (contact below the contact tolerance).

        Empty without pairs.
        """
        return np.zeros(0) if self.helper is None else self.helper.measured.at(q)

    def between(
        self,
        q0: np.ndarray,
        q1: np.ndarray,
        d0: np.ndarray,
        d1: np.ndarray,
        segment: int = 0,
        max_checks: int = 100_000,
        first: bool = True,
        middle_free: bool = False,
    ) -> PathCollision | None:
        """The first colliding place on the straight motion q0 -> q1 (free ends), or None.

        Args:
            q0: Start [rad] / [m].
            q1: End [rad] / [m].
            d0: :meth:`distances` at ``q0`` [m].
            d1: :meth:`distances` at ``q1`` [m].
            segment: The segment index the answer names.
            max_checks: Most checks in all (:attr:`checks` included): the rest is not shown free.
            first: True: the first colliding place along the motion. False: any (a planner's
                question, free or not): the halves are judged coarsest first, and a colliding
                midpoint is named without searching the half before it (the same verdict, less
                work on a motion that collides).
            middle_free: The checker's verdict at the motion's middle, ``0.5 * (q0 + q1)``, is
                known to be free (the caller asked it): its distances are measured there, the
                verdict not asked again.
        """
        if self.helper is None:
            return None
        found, used = _segment(
            self.helper, q0, q1, d0, d1, self.tolerance, max_checks - self.checks, first,
            middle_free,
        )  # fmt: skip
        self.checks += used
        if found is None:
            return None
        t, q_at, index, proven = found
        a, b = self.checker.model.pair_owners[index]
        kind = "scene" if b in self.checker.model.scene_objects else "self"
        return PathCollision(segment, t, q_at, a, b, kind, False, proven)


def _colliding_pair(checker: CollisionChecker, q: np.ndarray) -> tuple[str, str, str]:
    contacts = checker.collisions(q)
    a, b = (contacts[0].a, contacts[0].b) if contacts else checker.model.pair_owners[0]
    return a, b, "scene" if b in checker.model.scene_objects else "self"


def _segment(
    helper: _Distances,
    q0: np.ndarray,
    q1: np.ndarray,
    d0: np.ndarray,
    d1: np.ndarray,
    tolerance: float,
    budget: int,
    first: bool = True,
    middle_free: bool = False,
) -> tuple[tuple[float, np.ndarray, int, bool] | None, int]:
    """First colliding place on q0 -> q1 (fraction, q, pair index, proven), checks used.

    ``first`` False: any colliding place (breadth-first: the coarsest midpoints first).
    ``middle_free``: the checker's verdict at the middle of q0 -> q1 is known to be free.
    """
    checks = 0
    measured = helper.measured
    # first: depth-first, earliest half first, so the first place found is the first along the
    # segment; else breadth-first, so a motion that collides over a stretch is caught early
    stack = deque([(0.0, 1.0, q0, q1, d0, d1, np.arange(len(helper.pairs)))])
    take = stack.pop if first else stack.popleft
    while stack:
        t0, t1, qa, qb, da, db, open_pairs = take()
        closing = helper.pair_motion(qa, qb)
        bound = closing[open_pairs]
        # apart beyond the contact tolerance all along: (da - tol) + (db - tol) > bound
        unresolved = da[open_pairs] + db[open_pairs] - 2.0 * CONTACT_TOLERANCE <= bound
        if unresolved.any():  # an entry not measured is a lower bound: measure it and look again
            todo = open_pairs[unresolved]
            if measured.sharpen(qa, da, todo) | measured.sharpen(qb, db, todo):
                unresolved = da[open_pairs] + db[open_pairs] - 2.0 * CONTACT_TOLERANCE <= bound
        if not unresolved.any():
            continue
        open_pairs = open_pairs[unresolved]
        bound = bound[unresolved]
        tm = 0.5 * (t0 + t1)
        qm = 0.5 * (qa + qb)
        if bound.max() <= tolerance or checks >= budget:
            index = int(open_pairs[np.argmin(da[open_pairs] + db[open_pairs])])
            return (tm, qm, index, False), checks
        checks += 1
        # the halves read only the open pairs; with fast, the others keep lower bounds from the
        # ends (a pair closes at most half its bound on each half), which decide the verdict
        below = None if measured.bound is None else np.maximum(da, db) - 0.5 * closing
        dm = measured.of(qm, open_pairs, below)
        known = middle_free and t0 == 0.0 and t1 == 1.0
        if not known and measured.in_collision(qm, dm):  # the verdict, whatever the distances
            index = int(open_pairs[np.argmin(dm[open_pairs])])
            if not first:
                return (tm, qm, index, True), checks
            # the earlier half may hold an earlier contact: look there first
            found, used = _segment(helper, qa, qm, da, dm, tolerance, budget - checks)
            checks += used
            if found is not None and found[3]:  # an earlier contact (not just a near miss)
                t, q_at, i, proven = found
                return (t0 + t * (tm - t0), q_at, i, proven), checks
            return (tm, qm, index, True), checks
        halves = [(tm, t1, qm, qb, dm, db, open_pairs), (t0, tm, qa, qm, da, dm, open_pairs)]
        stack.extend(halves if first else halves[::-1])
    return None, checks
