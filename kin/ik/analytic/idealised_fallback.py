"""A rounded arm's "no" only when it is proved (:class:`IdealisedFallback`, issue 32 item 4).

A rounded table is solved on its idealised geometry (:mod:`.idealised`), whose tool is within
``position_bound`` [m] and ``rotation_bound`` [rad] of the true one at every joint vector. Near
a boundary of the workspace (a stretched or folded elbow, the wrist centre over the shoulder
axis) the two arms' reaches differ by up to that bound: the ideal arm may have no branch, or a
double root, where the true arm has two (a PUMA 560 written with 1.5708 for pi/2 and
``a5`` = 3 um: its stretched elbow reaches 8 um farther than the ideal one's). And where a
target's solutions form a continuum (a wrist at ``q5 = 0``, a free pitch), the closed form picks
one member, which may lie outside the limits while another lies inside. So when the polished
branches give no valid solution, before saying "no" the solver:

1. **Nearest ideal configurations.** Solves the ideal arm at the target moved by :data:`NUDGE`
   times the position bound along each world axis (both signs) and polishes those branches onto
   the true target. Wherever the ideal arm's reachable set has a smooth boundary (curvature
   radius far above the bound), one of the six lies inside it if the true arm reaches the target:
   the true answer's ideal pose is within the bound of the target, and one axis is within
   ``acos(1/sqrt 3)`` of the boundary's normal.
2. **The answer when it is proved.** No branch at the target nor at any of the six: the ideal
   arm's set misses the target by more than the bound (the premise above): ``out_of_reach``
   (with the distance to the reach when the target lies beyond it; beyond the reach plus the
   nudge, without trying the nudges). Only branches on target outside the limits, each
   isolated (:meth:`IdealisedFallback._isolated`: the polish moves a joint less than
   :data:`~.branch_verification.OUTSIDE_MARGIN` there; a redundant target's branch also lies
   farther than that margin outside), and none dropped near the target: ``outside_limits``
   (checked first when the target itself has branches; the nudges then cannot add a valid one).
3. **Else a numeric search** (:class:`~kin.ik.numeric.solver.NumericIK`, bounded by its work:
   the same answer on a busy machine), its answers polished and judged at the closed form's
   tolerances (its own answer when the polish does not reach them); none found: the branches
   outside the limits (``outside_limits``), or the search's ``not_found`` / ``timeout``.

Runs only when no branch of the target itself is valid: a rounded arm's usual solve is unchanged.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from ..result import IKResult, IKSolution
from ..target import PoseTarget, Target
from .branch_verification import OUTSIDE_MARGIN
from .branches import Branches
from .closed_form_branches import ClosedFormBranches
from .idealised import Idealised

#: The target is moved by this many times the idealisation's position bound along each axis (see
#: the module): ``sqrt 3`` reaches across the bound in any direction, 3 leaves a margin.
NUDGE = 3.0
#: Two answers whose joints differ by less than this [rad] are one (the nudges find a branch
#: several times).
SAME = 1e-9

_WORLD = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@dataclass(frozen=True)
class UnprovedCall:
    """One solve's values the fallback reads.

    Attributes:
        seed: The structure's seed ``q'`` [rad].
        arm_seed: The caller's seed ``q`` [rad] (moved into the limits), or None.
        start: ``time.perf_counter()`` at the call's start [s].
        timeout: Cap on the numeric search [s] (None: its default).
    """

    seed: list[float]
    arm_seed: npt.ArrayLike | None
    start: float
    timeout: float | None


class IdealisedFallback(ClosedFormBranches):
    """What a rounded arm answers when no polished branch is valid (mixed in; see the module)."""

    idealised: Idealised | None
    _miss_bound: tuple[float, float] | None

    #: The numeric solver of the same robot (:class:`.closed_form_routes.ClosedFormRoutes`).
    numeric: Any

    def _unproved(
        self,
        target: Target,
        branches: Branches,
        had_branches: bool,
        rejected: list[IKSolution],
        call: UnprovedCall,
    ) -> IKResult:
        """The answer of a rounded arm's target none of whose polished branches is valid.

        Args:
            target: The position or pose target, world frame.
            branches: The ideal arm's branches of ``target`` (their status, message and gap).
            had_branches: Whether the ideal arm had a branch of ``target``.
            rejected: The polished branches on target outside the limits.
            call: The seeds, the start and the numeric search's cap.
        """
        seed, start = call.seed, call.start
        if had_branches and self._outside_proved(rejected, target):
            return self._result([], rejected, branches.status, branches.message, start)
        if not had_branches and self._beyond(target):
            return self._failure("out_of_reach", self._no_branch(branches), start, None, target)
        p = target.position.tolist()
        r = target.rotation.tolist() if isinstance(target, PoseTarget) else None
        valid, more, found = self._nudged(target, seed, p, r)
        if valid:
            return self._result(valid, rejected, "ok", "", start, "closed_form_polished")
        if not had_branches:  # the nudges' branches are the only ones
            if not found:
                message = self._no_branch(branches)
                return self._failure("out_of_reach", message, start, branches.gap, target)
            rejected = more
            if self._outside_proved(rejected, target):
                return self._result([], rejected, "ok", "", start)
        return self._searched(target, rejected, call)

    def _no_branch(self, branches: Branches) -> str:
        """Why the ideal arm has no branch (its structure's words, else the default)."""
        return branches.message or f"no {self.structure.name} branch reaches the target"

    def _beyond(self, target: Target) -> bool:
        """Whether the target is farther from the base than the arm reaches and the nudges go.

        The reach (:func:`kin.ik.reach.arm_reach`, the true arm's) plus :data:`NUDGE` times the
        position bound [m]: no nudged target there has a branch; the nudges are not tried.
        """
        from ..reach import arm_reach

        assert self.idealised is not None
        reach = arm_reach(self.robot)
        margin = NUDGE * self.idealised.position_bound
        return reach.distance(target.position) > reach.maximum + margin

    def _nudged(
        self, target: Target, seed: list[float], p: list[float], r: list[list[float]] | None
    ) -> tuple[list[tuple[float, IKSolution]], list[IKSolution], bool]:
        """The ideal arm's branches of the nudged targets, polished onto ``target`` and judged.

        Returns the valid (distance to the seed, solution) pairs and the rejected solutions,
        each once, and whether any nudged target had a branch.
        """
        assert self.idealised is not None
        step = NUDGE * self.idealised.position_bound
        found = False
        thetas: list[tuple[tuple[float, ...], str]] = []
        for axis in range(3):
            for sign in (1.0, -1.0):
                position = target.position.copy()
                position[axis] += sign * step
                moved = dataclasses.replace(target, position=position)  # type: ignore[type-var]
                nudged = self._branches(moved, seed)
                if nudged.status != "out_of_reach" and nudged.thetas:
                    found = True
                    thetas.extend(nudged.thetas)
        if not thetas:
            return [], [], found
        polished = Branches(self._polish_each(thetas, target, math.inf)[0])
        valid, rejected = self._verify(target, polished, seed, p, r, quiet=True)
        kept = _distinct([solution for _, solution in valid])
        return [(math.dist(s.q.tolist(), seed), s) for s in kept], _distinct(rejected), found

    def _outside_proved(self, rejected: list[IKSolution], target: Target) -> bool:
        """Whether branches on target outside the limits prove that none inside exists.

        Some, each :meth:`_isolated` (the "every branch outside the limits" of ``outside_limits``),
        and, unless the target has more equations than joints, no branch dropped by the last
        verification within the idealisation's bound of the target
        (:attr:`~.branch_verification.BranchVerification._nearest_miss`: a polish that stalled
        near a singularity may hide a valid branch; a full pose on four joints is reached by
        some branches of its projection only within that bound, and by none closer).
        """
        assert self._miss_bound is not None
        if not rejected:
            return False
        square = (6 if isinstance(target, PoseTarget) else 3) <= len(rejected[0].q)
        if square and self._nearest_miss <= max(self._miss_bound):
            return False
        return all(self._isolated(s.q, target) for s in rejected)

    def _isolated(self, q: np.ndarray, target: Target) -> bool:
        """Whether a branch on target outside the limits proves that no valid one is near it.

        The polish moves a joint by about ``bound / sigma_min(J)`` (the idealisation's bound
        over the smallest singular value of the task's Jacobian at ``q``): isolated when that is
        under :data:`~.branch_verification.OUTSIDE_MARGIN` (near a singularity the true arm's
        branches may be far from the ideal ones'). A redundant target's (a position on four
        joints) branches are also a continuum the structure chose from: isolated only when,
        besides, a joint is farther than the margin outside its limits in every copy.
        """
        judge = self._judge
        rows = 6 if isinstance(target, PoseTarget) else 3
        if rows < len(q):
            lower, upper = judge.model.lowerPositionLimit, judge.model.upperPositionLimit
            copies = q[:, None] + 2.0 * math.pi * np.arange(-2, 3)
            outside = np.maximum(lower[:, None] - copies, copies - upper[:, None]).min(axis=1)
            if not outside.max() > OUTSIDE_MARGIN:
                return False
        jacobian = pin.computeFrameJacobian(judge.model, judge.data, q, judge.frame_id, _WORLD)
        smallest = np.linalg.svd(jacobian[:rows], compute_uv=False)[-1]
        assert self._miss_bound is not None
        return bool(smallest * OUTSIDE_MARGIN > max(self._miss_bound))

    def _searched(self, target: Target, rejected: list[IKSolution], call: UnprovedCall) -> IKResult:
        """The numeric search's answer, polished and judged at the closed form's tolerances."""
        result = self.numeric.solve(target, call.arm_seed, timeout=call.timeout)
        if result.success:
            p = target.position.tolist()
            r = target.rotation.tolist() if isinstance(target, PoseTarget) else None
            thetas = [(self._dh_angles(s.q), s.branch or result.method) for s in result.solutions]
            polished = Branches(self._polish_each(thetas, target, math.inf)[0])
            valid, _ = self._verify(target, polished, call.seed, p, r, quiet=True)
            if valid:
                return self._result(valid, rejected, "ok", "", call.start, result.method)
            return result  # type: ignore[no-any-return]
        if rejected:
            return self._result([], rejected, "ok", "", call.start)
        return dataclasses.replace(result, time=time.perf_counter() - call.start)  # type: ignore[no-any-return]

    def _dh_angles(self, q: np.ndarray) -> tuple[float, ...]:
        """The structure's DH angles ``direction * q + theta offset`` of the arm's ``q`` [rad]."""
        forward = q if self._directions is None else q * self._directions
        return tuple(v + offset for v, offset in zip(forward.tolist(), self._offsets))


def _distinct(solutions: list[IKSolution]) -> list[IKSolution]:
    """``solutions`` without repeats (joints within :data:`SAME` of an earlier one's), in order."""
    kept: list[IKSolution] = []
    for solution in solutions:
        if all(np.abs(solution.q - other.q).max() >= SAME for other in kept):
            kept.append(solution)
    return kept
