"""A rounded arm's polish, and its "no" only when it is proved (:class:`IdealisedPolish`, issue 32).

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
   isolated (:meth:`IdealisedPolish.isolated`: the polish moves a joint less than
   :data:`~.branch_verification.OUTSIDE_MARGIN` there; a redundant target's branch also lies
   farther than that margin outside), and none dropped near the target: ``outside_limits``
   (checked first when the target itself has branches; the nudges then cannot add a valid one).
3. **Else a numeric search** (:class:`~kin.ik.numeric.solver.NumericIK`, bounded by its work:
   the same answer on a busy machine), its answers polished and judged at the closed form's
   tolerances (its own answer when the polish does not reach them); none found: the branches
   outside the limits (``outside_limits``), or the search's ``not_found`` / ``timeout``.

Runs only when no branch of the target itself is valid: a rounded arm's usual solve is unchanged.

The usual solve is :meth:`IdealisedPolish.verify_polished`: every branch of the ideal arm moved
onto the true chain (:func:`.idealised.polish`) and judged by the closed form's verifier, those
far outside the limits judged unpolished (:mod:`.branch_verification`).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from ..result import IKResult, IKSolution
from ..targets.target import PoseTarget, Target
from .branch_verification import OUTSIDE_MARGIN, BranchVerifier
from .branches import Branches
from .closed_form_branches import ClosedFormArm
from .idealised import Idealised, polish

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


class IdealisedPolish:
    """A rounded arm's branches polished onto the true chain, and its "no" only when proved.

    Held by :class:`~.closed_form.ClosedFormSolver` of an arm solved on its idealised table
    (:mod:`.idealised`); see the module.

    Args:
        arm: The arm as its (idealised) structure sees it; ``arm.idealised`` is not None.
        verifier: The closed form's branch verifier (the judge, the tolerances, the limits).
        numeric: Gives the numeric solver of the same robot (built on first use): the search
            of :meth:`unproved` when neither the branches nor the nudges answer.
    """

    def __init__(
        self, arm: ClosedFormArm, verifier: BranchVerifier, numeric: Callable[[], Any]
    ) -> None:
        assert arm.idealised is not None
        self.arm = arm
        self.idealised: Idealised = arm.idealised
        self.verifier = verifier
        self._numeric = numeric

    def polished(self, branches: Branches, target: Target, near: float = math.inf) -> Branches:
        """The idealised structure's branches moved onto the true chain (:func:`.idealised.polish`).

        ``near``: a branch whose tool on the true chain starts farther than this [m], [rad] from
        the target is dropped, not polished (the pose route: a branch of the pose's projection
        that far from the pose itself cannot reach it).
        """
        branches.thetas = self.polish_each(branches.thetas, target, near)[0]
        return branches

    def verify_polished(
        self,
        target: Target,
        branches: Branches,
        seed: list[float],
        p: list[float],
        r: list[list[float]] | None,
        quiet: bool = False,
        near: float = math.inf,
    ) -> tuple[list[tuple[float, IKSolution]], list[IKSolution]]:
        """An idealised arm's branches polished and verified (:meth:`.BranchVerifier.verify`'s answer).

        The branches far outside the limits (:meth:`.BranchVerifier.far_outside`) are set aside, the others
        polished and judged. When one is valid, those set aside are judged unpolished
        (:meth:`.BranchVerifier.verify_far`: rejected, with a reason when off target by at most the bound);
        else they are polished and judged as every branch was before the rule (a "no"
        rests on polished branches only). Rejected ones follow the others.
        """
        branches.thetas, far = self.polish_each(branches.thetas, target, near, keep_far=True)
        valid, rejected = self.verifier.verify(target, branches, seed, p, r, quiet)
        if not far:
            return valid, rejected
        if valid:
            rejected += self.verifier.verify_far(far, seed, p, r, quiet)
            return valid, rejected
        missed = self.verifier.nearest_miss
        polished = Branches(self.polish_each(far, target, near)[0])
        valid, more = self.verifier.verify(target, polished, seed, p, r, quiet)
        self.verifier.nearest_miss = min(missed, self.verifier.nearest_miss)  # of both calls
        return valid, rejected + more

    def polish_each(
        self,
        thetas: list[tuple[tuple[float, ...], str]],
        target: Target,
        near: float,
        keep_far: bool = False,
    ) -> tuple[list[tuple[tuple[float, ...], str]], list[tuple[tuple[float, ...], str]]]:
        """Each branch (DH angles [rad], label) polished; those that give up (``near``) dropped.

        ``keep_far``: a branch far outside the limits (:meth:`.BranchVerifier.far_outside`) is set aside as it
        is. Returns the polished branches in their order, and those set aside.
        """
        judge, offsets, directions = self.verifier.judge, self.arm.offsets, self.arm.directions
        rotation = target.rotation if isinstance(target, PoseTarget) else None
        far_outside = self.verifier.far_outside if keep_far else None
        moved, kept = [], []
        for branch, label in thetas:
            if far_outside is not None and far_outside(branch):
                kept.append((branch, label))
                continue
            q = np.array([theta - offset for theta, offset in zip(branch, offsets)])
            if directions is not None:  # q' -> q (the judge's)
                q = q * directions
            q = polish(
                judge.model, judge.data, judge.frame_id, q, target.position, rotation, give_up=near
            )
            if q[0] == q[0]:  # not NaN: polished
                if directions is not None:
                    q = q * directions
                moved.append((tuple([v + offset for v, offset in zip(q.tolist(), offsets)]), label))
        return moved, kept

    def unproved(
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
        if had_branches and self.outside_proved(rejected, target):
            return self.verifier.result([], rejected, branches.status, branches.message, start)
        if not had_branches and self.beyond(target):
            return self.verifier.failure(
                "out_of_reach", self.no_branch(branches), start, None, target
            )
        p = target.position.tolist()
        r = target.rotation.tolist() if isinstance(target, PoseTarget) else None
        valid, more, found = self.nudged(target, seed, p, r)
        if valid:
            return self.verifier.result(valid, rejected, "ok", "", start, "closed_form_polished")
        if not had_branches:  # the nudges' branches are the only ones
            if not found:
                message = self.no_branch(branches)
                return self.verifier.failure("out_of_reach", message, start, branches.gap, target)
            rejected = more
            if self.outside_proved(rejected, target):
                return self.verifier.result([], rejected, "ok", "", start)
        return self.searched(target, rejected, call)

    def no_branch(self, branches: Branches) -> str:
        """Why the ideal arm has no branch (its structure's words, else the default)."""
        return branches.message or f"no {self.arm.structure.name} branch reaches the target"

    def beyond(self, target: Target) -> bool:
        """Whether the target is farther from the base than the arm reaches and the nudges go.

        The reach (:func:`kin.ik.reach.arm_reach`, the true arm's) plus :data:`NUDGE` times the
        position bound [m]: no nudged target there has a branch; the nudges are not tried.
        """
        from ..reach import arm_reach

        reach = arm_reach(self.arm.robot)
        margin = NUDGE * self.idealised.position_bound
        return reach.distance(target.position) > reach.maximum + margin

    def nudged(
        self, target: Target, seed: list[float], p: list[float], r: list[list[float]] | None
    ) -> tuple[list[tuple[float, IKSolution]], list[IKSolution], bool]:
        """The ideal arm's branches of the nudged targets, polished onto ``target`` and judged.

        Returns the valid (distance to the seed, solution) pairs and the rejected solutions,
        each once, and whether any nudged target had a branch.
        """
        step = NUDGE * self.idealised.position_bound
        found = False
        thetas: list[tuple[tuple[float, ...], str]] = []
        for axis in range(3):
            for sign in (1.0, -1.0):
                position = target.position.copy()
                position[axis] += sign * step
                moved = dataclasses.replace(target, position=position)  # type: ignore[type-var]
                nudged = self.arm.branches(moved, seed)
                if nudged.status != "out_of_reach" and nudged.thetas:
                    found = True
                    thetas.extend(nudged.thetas)
        if not thetas:
            return [], [], found
        polished = Branches(self.polish_each(thetas, target, math.inf)[0])
        valid, rejected = self.verifier.verify(target, polished, seed, p, r, quiet=True)
        kept = _distinct([solution for _, solution in valid])
        return [(math.dist(s.q.tolist(), seed), s) for s in kept], _distinct(rejected), found

    def outside_proved(self, rejected: list[IKSolution], target: Target) -> bool:
        """Whether branches on target outside the limits prove that none inside exists.

        Some, each :meth:`isolated` (the "every branch outside the limits" of ``outside_limits``),
        and, unless the target has more equations than joints, no branch dropped by the last
        verification within the idealisation's bound of the target
        (:attr:`.BranchVerifier.nearest_miss`: a polish that stalled
        near a singularity may hide a valid branch; a full pose on four joints is reached by
        some branches of its projection only within that bound, and by none closer).
        """
        assert self.verifier.miss_bound is not None
        if not rejected:
            return False
        square = (6 if isinstance(target, PoseTarget) else 3) <= len(rejected[0].q)
        if square and self.verifier.nearest_miss <= max(self.verifier.miss_bound):
            return False
        return all(self.isolated(s.q, target) for s in rejected)

    def isolated(self, q: np.ndarray, target: Target) -> bool:
        """Whether a branch on target outside the limits proves that no valid one is near it.

        The polish moves a joint by about ``bound / sigma_min(J)`` (the idealisation's bound
        over the smallest singular value of the task's Jacobian at ``q``): isolated when that is
        under :data:`~.branch_verification.OUTSIDE_MARGIN` (near a singularity the true arm's
        branches may be far from the ideal ones'). A redundant target's (a position on four
        joints) branches are also a continuum the structure chose from: isolated only when,
        besides, a joint is farther than the margin outside its limits in every copy.
        """
        judge = self.verifier.judge
        rows = 6 if isinstance(target, PoseTarget) else 3
        if rows < len(q):
            lower, upper = judge.model.lowerPositionLimit, judge.model.upperPositionLimit
            copies = q[:, None] + 2.0 * math.pi * np.arange(-2, 3)
            outside = np.maximum(lower[:, None] - copies, copies - upper[:, None]).min(axis=1)
            if not outside.max() > OUTSIDE_MARGIN:
                return False
        jacobian = pin.computeFrameJacobian(judge.model, judge.data, q, judge.frame_id, _WORLD)
        smallest = np.linalg.svd(jacobian[:rows], compute_uv=False)[-1]
        assert self.verifier.miss_bound is not None
        return bool(smallest * OUTSIDE_MARGIN > max(self.verifier.miss_bound))

    def searched(self, target: Target, rejected: list[IKSolution], call: UnprovedCall) -> IKResult:
        """The numeric search's answer, polished and judged at the closed form's tolerances."""
        result = self._numeric().solve(target, call.arm_seed, timeout=call.timeout)
        if result.success:
            p = target.position.tolist()
            r = target.rotation.tolist() if isinstance(target, PoseTarget) else None
            thetas = [
                (self.arm.dh_angles(s.q), s.branch or result.method) for s in result.solutions
            ]
            polished = Branches(self.polish_each(thetas, target, math.inf)[0])
            valid, _ = self.verifier.verify(target, polished, call.seed, p, r, quiet=True)
            if valid:
                return self.verifier.result(valid, rejected, "ok", "", call.start, result.method)
            return result  # type: ignore[no-any-return]
        if rejected:
            return self.verifier.result([], rejected, "ok", "", call.start)
        return dataclasses.replace(result, time=time.perf_counter() - call.start)  # type: ignore[no-any-return]


def _distinct(solutions: list[IKSolution]) -> list[IKSolution]:
    """``solutions`` without repeats (joints within :data:`SAME` of an earlier one's), in order."""
    kept: list[IKSolution] = []
    for solution in solutions:
        if all(np.abs(solution.q - other.q).max() >= SAME for other in kept):
            kept.append(solution)
    return kept
