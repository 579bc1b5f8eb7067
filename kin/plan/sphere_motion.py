"""The motion rule on spheres: states and straight joint motions shown free without coal.

The rule of :mod:`kin.path.collision_check` (a step bound from the distances at a motion's ends
and the links' largest motion, halved where it cannot tell), applied to the spheres that enclose
every shape the arm carries (:func:`kin.collision.sphere_fit.enclosing_spheres`, as
:mod:`kin.collision.sphere_bound` places them). One *test* is a sphere of one shape against a
sphere of the other shape of a checked pair, or a sphere against a scene shape of a checked pair
(the signed distance of its center to the box, sphere, cylinder or capsule, less its radius; any
other shape through its bounding box). A test's value is a lower bound of its pair's distance
(padding taken off), so:

* a state is **shown free** when every test is above
  :data:`~kin.path.pair_distances.PROVEN_APART` (twice the contact tolerance);
* a straight motion q0 -> q1 is **shown free** when, for every test, ``(d0 - tol) + (d1 - tol)
  > B``, ``tol`` the contact tolerance and ``B`` the most the test's two sphere centers can close
  along the motion: the sum over the joints that move one center relative to the other of
  ``|q1_j - q0_j|`` times the center's distance bound from joint ``j``'s axis (from the axis of
  the joint whose frame holds it, its distance to it; from an axis further up, its distance from
  its joint's origin plus the links in between; the joints that carry both centers of a self test
  are left out, they move the pair as one body). A test value changes at most as fast as its centers
  move (a distance less constant radii, or a convex shape's signed distance), so each test stays
  above the tolerance all along, and with it every pair it bounds. Where a test does not hold,
  the motion is halved (its two halves inherit the tests still open) down to
  ``resolution`` [m] of closing. The motion's midpoint is looked at first: a test at or below
  the tolerance there (a group's coarse test and one of its others) refuses the motion at once,
  one check, as the halving would at its first midpoint (no segment with a point not above the
  tolerance holds the rule), without first measuring the ends.

Nothing here ever says "in collision": a state or motion it does not show free is left to the
exact rule (coal), which decides. Each pair of shapes is a *group* of tests whose first is a
coarse test of one sphere about each shape's whole cover: when it holds, the group's other tests
are skipped.

The arithmetic runs in a compiled twin (``kin/_native/plan/_sphere_motion.c``) when it is built,
else in the NumPy form here; the two reach the same verdicts (``tests/native/test_sphere_motion.py``).
Only arms whose joints are all revolute with one coordinate each (``RX``, ``RY``, ``RZ``,
``RevoluteUnaligned``) are covered: :func:`sphere_motion` is None for any other arm, or when a
pair of shapes fixed to the world is itself within twice the contact tolerance.
"""

from __future__ import annotations

import weakref
from typing import TYPE_CHECKING, Any

import numpy as np

from ..collision.requests import CONTACT_TOLERANCE
from ..path.pair_distances import PROVEN_APART
from .sphere_tests import sphere_tests

if TYPE_CHECKING:  # pragma: no cover
    from ..collision.model import CollisionModel

__all__ = ["SphereMotion", "sphere_motion"]

_MADE: weakref.WeakKeyDictionary[CollisionModel, SphereMotion | None] = weakref.WeakKeyDictionary()


def sphere_motion(model: CollisionModel) -> SphereMotion | None:
    """The :class:`SphereMotion` of ``model``, made once per model; None where it does not apply."""
    if model in _MADE:
        return _MADE[model]
    found = SphereMotion.of(model)
    _MADE[model] = found
    return found


def _native() -> Any:
    try:
        from .._native import twin

        return twin("_sphere_motion")
    except (ImportError, KeyError):  # not declared in this build's registry
        return None


class SphereMotion:
    """The tests of one collision model, and the rule on them (the module).

    Made by :meth:`of`. Attributes are the arrays the compiled twin is built from.

    Attributes:
        nq: Joints [count].
        tests: Tests [count]; ``groups`` + 1 starts of the groups in them.
    """

    def __init__(self, arrays: dict[str, np.ndarray]):
        self.arrays = arrays
        self.nq = int(arrays["qidx"].max()) + 1
        self.tests = len(arrays["test_a"])
        self._arms = arrays["test_arms"].reshape(self.tests, self.nq)
        native = _native()
        self._native = native
        self._capsule = None if native is None else native.make(*arrays.values())

    @classmethod
    def of(cls, model: CollisionModel) -> SphereMotion | None:
        """The tests of ``model`` (:func:`kin.plan.sphere_tests.sphere_tests`), or None."""
        arrays = sphere_tests(model)
        return None if arrays is None else cls(arrays)

    # -- the rule ---------------------------------------------------------------------------

    def state_free(self, q: np.ndarray) -> bool:
        """Whether every test is above twice the contact tolerance at ``q`` (float64, (nq,))."""
        if self._capsule is not None:
            return bool(self._native.state(self._capsule, q, PROVEN_APART))
        values = self._values(self._centers(q))
        return bool(self._group_holds(values > PROVEN_APART).all())

    def motion_free(
        self, q0: np.ndarray, q1: np.ndarray, resolution: float, max_checks: int
    ) -> tuple[bool, int]:
        """Whether the straight motion q0 -> q1 is shown free; the midpoints checked [count].

        Args:
            q0: Start (float64, (nq,)) [rad].
            q1: End [rad].
            resolution: Closing bound [m] below which a test that does not hold is given up.
            max_checks: Most midpoints; then the motion is not shown.
        """
        if self._capsule is not None:
            shown, checks = self._native.motion(
                self._capsule, q0, q1, CONTACT_TOLERANCE, resolution, max_checks
            )
            return bool(shown), int(checks)
        return self._motion(q0, q1, resolution, max_checks)

    def _centers(self, q: np.ndarray) -> np.ndarray:
        """Every sphere's center at ``q`` in the world (S, 3) [m]: the twin's arithmetic."""
        a = self.arrays
        nj = len(a["parent"])
        frames = [np.eye(4)]
        for j in range(1, nj):
            placement = np.eye(4)
            placement[:3, :3] = a["placement"][j, :9].reshape(3, 3)
            placement[:3, 3] = a["placement"][j, 9:]
            u = a["axis"][j]
            angle = q[a["qidx"][j]]
            cross = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
            turn = np.eye(4)
            turn[:3, :3] = (
                np.cos(angle) * np.eye(3)
                + np.sin(angle) * cross
                + (1.0 - np.cos(angle)) * np.outer(u, u)
            )
            frames.append(frames[a["parent"][j]] @ placement @ turn)
        stacked = np.array(frames)[a["sphere_joint"]]
        return np.einsum("sij,sj->si", stacked[:, :3, :3], a["sphere_center"]) + stacked[:, :3, 3]

    def _values(self, centers: np.ndarray) -> np.ndarray:
        """Every test's value at the centers [m]."""
        a = self.arrays
        first = centers[a["test_a"]]
        out = np.empty(self.tests)
        self_tests = a["test_b"] >= 0
        out[self_tests] = np.linalg.norm(
            first[self_tests] - centers[a["test_b"][self_tests]], axis=1
        )
        scene = ~self_tests
        if scene.any():
            out[scene] = _shape_distances(a, a["test_k"][scene], first[scene])
        return out - a["test_offset"]

    def _group_holds(self, holds: np.ndarray) -> np.ndarray:
        """Per group, whether its coarse test holds or all its members do."""
        starts = self.arrays["group_start"]
        found = np.ones(len(starts) - 1, dtype=bool)
        for g in range(len(starts) - 1):
            a, b = starts[g], starts[g + 1]
            found[g] = bool(holds[a]) or bool(holds[a + 1 : b].all())
        return found

    def _motion(
        self, q0: np.ndarray, q1: np.ndarray, resolution: float, max_checks: int
    ) -> tuple[bool, int]:
        """The NumPy form of the twin's ``motion``: the same halving, the same verdict."""
        starts = self.arrays["group_start"]
        tol = CONTACT_TOLERANCE
        if max_checks >= 1:  # the midpoint first: a test at or below tol there refuses at once
            middle = self._values(self._centers(0.5 * (q0 + q1)))
            if not self._group_holds(middle > tol).all():
                return False, 1
        stack = [(q0, q1, list(range(len(starts) - 1)))]
        checks = 0
        while stack:
            qa, qb, open_groups = stack.pop()
            dq = np.abs(qb - qa)
            da, db = self._values(self._centers(qa)), self._values(self._centers(qb))
            bound = self._arms @ dq
            holds = (da - tol) + (db - tol) > bound
            never = ~holds & ((da <= tol) | (db <= tol) | (bound <= resolution))
            kept = []
            for g in open_groups:
                first, end = starts[g], starts[g + 1]
                if holds[first]:
                    continue
                if never[first + 1 : end].any():
                    return False, checks
                if not holds[first + 1 : end].all():
                    kept.append(g)
            if not kept:
                continue
            if len(stack) + 2 > 60 or checks >= max_checks:
                return False, checks
            checks += 1
            middle = 0.5 * (qa + qb)
            stack.append((middle, qb, kept))
            stack.append((qa, middle, kept))
        return True, checks


def _shape_distances(a: dict[str, np.ndarray], k: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Signed distance of each point to its scene shape ``k`` [m] (negative inside)."""
    R = a["shape_rotation"][k].reshape(-1, 3, 3)
    x = np.einsum("nji,nj->ni", R, points - a["shape_center"][k])  # R^T (p - c)
    h = a["shape_half"][k]
    kind = a["shape_kind"][k]
    out = np.empty(len(k))
    box = kind == 0
    beyond = np.abs(x[box]) - h[box]
    out[box] = np.linalg.norm(np.maximum(beyond, 0.0), axis=1) + np.minimum(beyond.max(axis=1), 0.0)
    ball = kind == 1
    out[ball] = np.linalg.norm(x[ball], axis=1) - h[ball, 0]
    tube = kind == 2
    radial = np.hypot(x[tube, 0], x[tube, 1]) - h[tube, 0]
    axial = np.abs(x[tube, 2]) - h[tube, 1]
    out[tube] = np.hypot(np.maximum(radial, 0.0), np.maximum(axial, 0.0)) + np.minimum(
        np.maximum(radial, axial), 0.0
    )
    pill = kind == 3
    z = x[pill, 2] - np.clip(x[pill, 2], -h[pill, 1], h[pill, 1])
    out[pill] = np.sqrt(x[pill, 0] ** 2 + x[pill, 1] ** 2 + z**2) - h[pill, 0]
    return out
