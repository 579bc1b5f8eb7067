"""One planning problem in OMPL's terms: the joint space, the checks, the goals and the stop rule.

The checks OMPL calls back are the project's own:

* a state is valid when it is within the joint limits (the space's bounds) and
  :meth:`kin.collision.CollisionChecker.in_collision` calls it free;
* a motion between two states is valid when both ends are free and
  :class:`kin.path.collision_check.MotionCheck` shows every point of the straight joint motion
  free by its rule (the step bound from the distances at the ends and the links' largest motion,
  halved where it cannot tell): not a fixed resolution. A motion it cannot show apart at
  :data:`RESOLUTION` is refused, so every edge OMPL keeps, and every shortcut its simplifier
  takes, is certified.

Both first ask the spheres that enclose the arm's shapes (:mod:`kin.plan.sphere_motion`: the same
rule on spheres, compiled where built): a state or motion they show free is free; only where they
cannot tell does the exact rule run, which asks coal only where the spheres' per-pair bounds
cannot tell either (once the search has done :data:`FAST_AFTER` checks:
:mod:`kin.path.pair_distances`).

The search is bounded by work, not by the clock: :class:`Budget` stops it after ``max_checks``
configurations checked (states and the points between them), so the same seed gives the same
path on a busy machine and an idle one; the wall-clock cap stops it too, and the answer then says
``timeout``. A Ctrl-C (or any error) inside a callback stops the search and is raised again once
OMPL has returned, never thrown through its C++ frames.
"""

from __future__ import annotations

import math
import time
import weakref
from functools import cache
from typing import TYPE_CHECKING, Any

import numpy as np

from ..path.collision_check import MotionCheck
from .sphere_motion import sphere_motion

if TYPE_CHECKING:  # pragma: no cover
    from ..collision import CollisionChecker

__all__ = [
    "FAST_AFTER",
    "RESOLUTION",
    "Budget",
    "CertifiedSpace",
    "ShownMotions",
    "exact_rule",
    "joint_bounds",
    "prepare",
    "silence_ompl",
]

#: Link motion [m] below which the motion rule stops halving a motion it cannot show free: the
#: motion is then refused (a planner edge that grazes a shape within this is not taken).
RESOLUTION = 1e-4
#: Checks after which a search turns to the fast checks [count]: below it, fitting the spheres
#: (0.1-0.3 s a model, once) would cost more than it saves.
FAST_AFTER = 500
#: Verdicts kept per problem (states are checked as the ends of motions many times).
_CACHE = 200_000


_RULES: weakref.WeakKeyDictionary[CollisionChecker, dict[bool, MotionCheck]] = (
    weakref.WeakKeyDictionary()
)


def exact_rule(checker: CollisionChecker, fast: bool = False) -> MotionCheck:
    """The exact motion rule of ``checker`` at :data:`RESOLUTION`, made once per checker.

    Its remembered distances are the same values whichever plan reads them, so plans share it
    (one plan at a time: :func:`kin.plan.plan` holds a lock). ``fast``: per-pair sphere bounds
    first (:mod:`kin.path.pair_distances`).
    """
    rules = _RULES.setdefault(checker, {})
    rule = rules.get(fast)
    if rule is None:
        rule = rules[fast] = MotionCheck(checker, RESOLUTION, fast=fast)
    return rule


def prepare(checker: CollisionChecker) -> None:
    """Make what every plan with ``checker`` uses, once: its spheres' tests and its exact rule.

    :func:`kin.plan.plan` makes them on its first call with a checker (tens of milliseconds for
    an arm in a cell of a few boxes, more for the first model of an arm: its spheres are fitted);
    call this to have that done before.
    """
    sphere_motion(checker.model)
    exact_rule(checker)


def silence_ompl() -> Any:
    """Import OMPL's modules with its log off (it prints to stdout): ``(base, geometric, util)``."""
    from ompl import base, geometric, util

    util.setLogLevel(util.LogLevel.LOG_NONE)
    return base, geometric, util


class Budget:
    """The stop rule: work spent, the wall-clock cap, or an exception raised in a callback.

    Args:
        max_checks: Configurations checked before the search stops [count].
        time_limit: Wall-clock cap [s] (``math.inf``: none).
    """

    def __init__(self, max_checks: int, time_limit: float):
        self.max_checks = max_checks
        self.time_limit = time_limit
        self.checks = 0
        self.started = time.perf_counter()
        self.timed_out = False
        self.raised: BaseException | None = None

    def spent(self) -> bool:
        """Whether the search must stop now (OMPL's termination condition)."""
        if self.raised is not None or self.checks >= self.max_checks:
            return True
        if time.perf_counter() - self.started >= self.time_limit:
            self.timed_out = True
            return True
        return False

    def reraise(self) -> None:
        """Raise the exception a callback caught, if any."""
        if self.raised is not None:
            raised, self.raised = self.raised, None
            raise raised


def joint_bounds(
    robot: Any, points: np.ndarray, unbounded: float = math.pi
) -> tuple[np.ndarray, np.ndarray]:
    """The joint space's box [rad] / [m]: the limits, an infinite one at +-``unbounded``.

    Widened to hold ``points`` (the start and the goals), each row of which is within the limits.
    """
    lower = np.where(np.isfinite(robot.lower), robot.lower, -unbounded)
    upper = np.where(np.isfinite(robot.upper), robot.upper, unbounded)
    return np.minimum(lower, points.min(axis=0)), np.maximum(upper, points.max(axis=0))


class ShownMotions:
    """The straight motions a plan's rules have shown free, known by their two ends.

    A motion is the same set of joint vectors either way round, so ``q0 -> q1`` and ``q1 -> q0``
    are one entry; the ends are compared bit for bit (float64). At most :data:`_CACHE` are kept
    (then all are forgotten at once: a motion not found is checked again, never assumed).
    """

    def __init__(self) -> None:
        self._keys: set[bytes] = set()

    @staticmethod
    def _key(q0: np.ndarray, q1: np.ndarray) -> bytes:
        a, b = q0.tobytes(), q1.tobytes()
        return a + b if a <= b else b + a

    def add(self, q0: np.ndarray, q1: np.ndarray) -> None:
        """Remember that the straight motion q0 -> q1 was shown free (float64 vectors)."""
        if len(self._keys) >= _CACHE:
            self._keys.clear()
        self._keys.add(self._key(q0, q1))

    def holds(self, q0: np.ndarray, q1: np.ndarray) -> bool:
        """Whether the straight motion q0 -> q1 (either way round) was shown free."""
        return self._key(q0, q1) in self._keys


class CertifiedSpace:
    """The OMPL space information of a robot's joint space with the certified checks.

    Args:
        checker: The collision checker of the robot (its model's shapes, scene and padding).
        lower: Lower joint bounds [rad] / [m], shape (nq,).
        upper: Upper joint bounds [rad] / [m], shape (nq,).
        budget: The stop rule (its ``checks`` counts the work).
        fast: After :data:`FAST_AFTER` checks, bound the pairs by spheres first and ask coal
            only where the bounds do not decide (:mod:`kin.path.pair_distances`): the same
            verdicts and the same checks, less work once the spheres are fitted (0.1-0.3 s a
            model, once).
        exact: False: the spheres alone judge (:mod:`kin.plan.sphere_motion`), and a state or
            motion they do not show free is refused: no coal, a conservative search.
        shown: Where the motions shown free are remembered (shared by the spaces of one plan, so
            that its final check knows them); None: a memory of its own.

    Attributes:
        space: The ``RealVectorStateSpace``.
        si: Its ``SpaceInformation`` (validity checker and motion validator set, set up).
    """

    def __init__(
        self,
        checker: CollisionChecker,
        lower: np.ndarray,
        upper: np.ndarray,
        budget: Budget,
        fast: bool = True,
        exact: bool = True,
        shown: ShownMotions | None = None,
    ):
        ob, _, _ = silence_ompl()
        self.checker = checker
        self.shown = ShownMotions() if shown is None else shown
        self.budget = budget
        self.nq = len(lower)
        self._motion: MotionCheck | None = None  # the exact rule, made when first needed
        self._fast = fast
        self.spheres = sphere_motion(checker.model) if fast or not exact else None
        #: False: the spheres alone judge (what they do not show free is refused): no coal.
        self.exact = exact or self.spheres is None
        self._free: dict[bytes, bool] = {}
        self.space = ob.RealVectorStateSpace(self.nq)
        bounds = ob.RealVectorBounds(self.nq)
        for i in range(self.nq):
            bounds.setLow(i, float(lower[i]))
            bounds.setHigh(i, float(upper[i]))
        self.space.setBounds(bounds)
        self.si = ob.SpaceInformation(self.space)
        # OMPL holds the callbacks: they reach this object weakly, so that no reference cycle runs
        # through C++ (nanobind reports such objects as leaked at exit)
        me = weakref.proxy(self)
        self.si.setStateValidityChecker(lambda state: me._valid(state))
        self._validator = _validator_class()(self.si, me)
        self.si.setMotionValidator(self._validator)
        self.si.setup()

    def state(self, q: np.ndarray) -> Any:
        """A new OMPL state holding ``q``."""
        state = self.space.allocState()
        for i, value in enumerate(q.tolist()):
            state[i] = value
        return state

    def q(self, state: Any) -> np.ndarray:
        """The joint vector of an OMPL state [rad] / [m]."""
        return np.array([state[i] for i in range(self.nq)])

    def _checks(self) -> MotionCheck:
        """The exact rule (per-pair sphere bounds first after :data:`FAST_AFTER` checks)."""
        if self._motion is None or (self._fast and self.budget.checks >= FAST_AFTER):
            fast = self._fast and self.budget.checks >= FAST_AFTER
            if fast:
                self._fast = False
            self._motion = exact_rule(self.checker, fast)
        return self._motion

    def free(self, q: np.ndarray) -> bool:
        """The checker's verdict at ``q``, counted once per configuration."""
        key = q.tobytes()
        verdict = self._free.get(key)
        if verdict is None:
            self.budget.checks += 1
            spheres = self.spheres
            verdict = (spheres is not None and spheres.state_free(q)) or (
                self.exact and not self._checks().in_collision(q)
            )
            if len(self._free) >= _CACHE:
                self._free.clear()
            self._free[key] = verdict
        return verdict

    def distances(self, q: np.ndarray) -> np.ndarray:
        """Per checked pair, the distance at ``q`` [m] (lower bounds with the fast checks).

        The motion rule's ends, remembered by :class:`kin.path.pair_distances.PairDistances`.
        """
        return self._checks().distances(q)

    def motion_free(self, q0: np.ndarray, q1: np.ndarray, most: int | None = None) -> bool:
        """Whether every point of the straight motion q0 -> q1 is free by the rule.

        False, without a look, once the budget is spent (the motion is not shown free); also
        when the exact rule would need more than ``most`` checks [count] (None: the budget's).
        """
        if self.budget.spent() or not (self.free(q0) and self.free(q1)):
            return False
        if self.spheres is not None:
            left = max(self.budget.max_checks - self.budget.checks, 1)
            shown, used = self.spheres.motion_free(q0, q1, RESOLUTION, left)
            self.budget.checks += used
            if shown:
                self.shown.add(q0, q1)
            if shown or not self.exact:
                return shown
        motion = self._checks()
        # a motion the spheres could not show free often collides across its middle: the
        # checker's verdict there (one check, stops at the first contact) refuses it before the
        # rule measures its ends' distances
        self.budget.checks += 1
        if motion.in_collision(0.5 * (q0 + q1)):
            return False
        before = motion.checks
        remaining = max(self.budget.max_checks - self.budget.checks, 1)
        if most is not None:
            remaining = min(remaining, most)
        found = motion.between(
            q0, q1, self.distances(q0), self.distances(q1), max_checks=before + remaining,
            first=False, middle_free=True,
        )  # fmt: skip
        self.budget.checks += motion.checks - before
        if found is None:
            self.shown.add(q0, q1)
        return found is None

    def _valid(self, state: Any) -> bool:
        if self.budget.raised is not None:
            return False
        try:
            return self.free(self.q(state))
        except BaseException as err:  # noqa: BLE001 - raised again after OMPL returns
            self.budget.raised = err
            return False


@cache
def _validator_class() -> type:
    """A subclass of OMPL's ``MotionValidator`` calling :meth:`CertifiedSpace.motion_free`."""
    ob, _, _ = silence_ompl()

    class CertifiedMotionValidator(ob.MotionValidator):  # type: ignore[misc, name-defined]
        def __init__(self, si: Any, owner: CertifiedSpace):
            super().__init__(si)
            self.owner = owner

        def checkMotion(self, s1: Any, s2: Any, *last_valid: Any) -> bool:  # noqa: N802
            owner = self.owner
            if owner.budget.raised is not None:
                return False
            try:
                return owner.motion_free(owner.q(s1), owner.q(s2))
            except BaseException as err:  # noqa: BLE001 - raised again after OMPL returns
                owner.budget.raised = err
                return False

    return CertifiedMotionValidator
