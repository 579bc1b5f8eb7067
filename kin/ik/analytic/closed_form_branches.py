"""The branches of a closed-form arm's target, in its joints (:class:`ClosedFormBranches`).

What :class:`~.closed_form.ClosedFormSolver` asks before it judges: the structure's branches of
a target (DH angles, world frame), an idealised structure's polished on the true chain
(:mod:`.idealised`; those far outside the limits judged unpolished, :mod:`.branch_verification`),
and the caller's seed as the structure's joints (``q' = direction * q``
when the table reverses a joint or the structure turns an axis over, :mod:`.joint_directions`),
checked once. Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from ..exceptions import TargetError
from ..result import IKSolution
from ..target import PoseTarget, Target
from .branch_verification import UnpolishedVerification
from .branches import Branches
from .closed_form_structure import candidate_branches
from .idealised import polish


class ClosedFormBranches(UnpolishedVerification):
    """Branches and seeds of :class:`~.closed_form.ClosedFormSolver` (mixed in)."""

    _detailed: bool

    def _branches(self, target: Target, seed: list[float]) -> Branches:
        """Branches (DH angles) of a target of the closed form's kinds, in the world frame."""
        structure = self.structure
        if self._detailed:
            return structure.branches(target, seed)  # type: ignore[attr-defined]
        rotation = target.rotation if isinstance(target, PoseTarget) else None
        candidates = structure.solve(target.position, rotation)
        return candidate_branches(structure, candidates, self._offsets)

    def _polished(self, branches: Branches, target: Target, near: float = math.inf) -> Branches:
        """The idealised structure's branches moved onto the true chain (:func:`.idealised.polish`).

        ``near``: a branch whose tool on the true chain starts farther than this [m], [rad] from
        the target is dropped, not polished (the pose route: a branch of the pose's projection
        that far from the pose itself cannot reach it).
        """
        branches.thetas = self._polish_each(branches.thetas, target, near)[0]
        return branches

    def _verify_polished(
        self,
        target: Target,
        branches: Branches,
        seed: list[float],
        p: list[float],
        r: list[list[float]] | None,
        quiet: bool = False,
        near: float = math.inf,
    ) -> tuple[list[tuple[float, IKSolution]], list[IKSolution]]:
        """An idealised arm's branches polished and verified (:meth:`_verify`'s answer).

        The branches far outside the limits (:meth:`_far_outside`) are set aside, the others
        polished and judged. When one is valid, those set aside are judged unpolished
        (:meth:`_verify_far`: rejected, with a reason when off target by at most the bound);
        else they are polished and judged as every branch was before the rule (a "no"
        rests on polished branches only). Rejected ones follow the others.
        """
        branches.thetas, far = self._polish_each(branches.thetas, target, near, keep_far=True)
        valid, rejected = self._verify(target, branches, seed, p, r, quiet)
        if not far:
            return valid, rejected
        if valid:
            rejected += self._verify_far(far, seed, p, r, quiet)
            return valid, rejected
        missed = self._nearest_miss
        polished = Branches(self._polish_each(far, target, near)[0])
        valid, more = self._verify(target, polished, seed, p, r, quiet)
        self._nearest_miss = min(missed, self._nearest_miss)  # of both calls
        return valid, rejected + more

    def _polish_each(
        self,
        thetas: list[tuple[tuple[float, ...], str]],
        target: Target,
        near: float,
        keep_far: bool = False,
    ) -> tuple[list[tuple[tuple[float, ...], str]], list[tuple[tuple[float, ...], str]]]:
        """Each branch (DH angles [rad], label) polished; those that give up (``near``) dropped.

        ``keep_far``: a branch far outside the limits (:meth:`_far_outside`) is set aside as it
        is. Returns the polished branches in their order, and those set aside.
        """
        judge, offsets, directions = self._judge, self._offsets, self._directions
        rotation = target.rotation if isinstance(target, PoseTarget) else None
        far_outside = self._far_outside if keep_far else None
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

    def _forward_seed(self, seed: npt.ArrayLike) -> npt.ArrayLike:
        """The seed ``q`` [rad] as the forward table's ``q' = direction * q``.

        A seed of the wrong size, or with a value that is not finite, is returned as given, for
        :meth:`_seed_list` to name.
        """
        directions = self._directions
        assert directions is not None
        if (
            seed.__class__ is np.ndarray
            and seed.shape == directions.shape  # type: ignore[union-attr]
            and seed.dtype == np.float64  # type: ignore[union-attr]
            and math.isfinite(sum(seed.tolist()))  # type: ignore[union-attr]
        ):
            return seed * directions  # the common case: one check
        values = np.asarray(seed, dtype=float).reshape(-1)
        if values.shape != directions.shape or not np.isfinite(values).all():
            return seed
        return values * directions

    def _seed_list(self, seed: npt.ArrayLike | None) -> list[float]:
        """The seed as floats [rad] (zeros if None).

        Raises:
            TargetError: The seed has the wrong size or a value that is not finite.
        """
        if seed is None:
            return self._zero_seed
        nq = len(self._lower)
        if seed.__class__ is np.ndarray and seed.shape == (nq,):  # type: ignore[union-attr]
            seed_list = seed.tolist()  # type: ignore[union-attr]
            if math.isfinite(sum(seed_list)):  # the common case: one check, no copy
                return seed_list
        seed_list = np.asarray(seed, dtype=float).reshape(-1).tolist()
        if len(seed_list) != nq:
            raise TargetError(
                f"the seed of '{self.robot.name}' must have {nq} values, got {len(seed_list)}"
            )
        if not all(math.isfinite(v) for v in seed_list):
            raise TargetError(f"the seed must be finite, got {seed_list}")
        return seed_list
