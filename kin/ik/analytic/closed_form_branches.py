"""The branches of a closed-form arm's target, in its joints (:class:`ClosedFormBranches`).

What :class:`~.closed_form.ClosedFormSolver` asks before it judges: the structure's branches of
a target (DH angles, world frame), an idealised structure's polished on the true chain
(:mod:`.idealised`), and the caller's seed as the structure's joints (``q' = direction * q``
when the table reverses a joint or the structure turns an axis over, :mod:`.joint_directions`),
checked once. Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from ..exceptions import TargetError
from ..limit_rule import LIMIT_TOL, TWO_PI
from ..target import PoseTarget, Target
from .branch_verification import BranchVerification
from .branches import Branches
from .closed_form_structure import candidate_branches
from .idealised import polish

#: A branch outside the joint limits by more than this [rad] is not polished when another is (the
#: polish moves a joint by far less: at most 4e-5 rad on the corpus' AL5D, 1e-7 where it lands).
OUTSIDE_MARGIN = 1e-2


class ClosedFormBranches(BranchVerification):
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

    def _polished(
        self, branches: Branches, target: Target, near: float = math.inf, limits: bool = True
    ) -> Branches:
        """The idealised structure's branches moved onto the true chain (:func:`.idealised.polish`).

        ``near``: a branch whose tool on the true chain starts farther than this [m], [rad] from
        the target is dropped, not polished (the pose route: a branch of the pose's projection
        that far from the pose itself cannot reach it).

        ``limits``: the branches with a joint farther than :data:`OUTSIDE_MARGIN` [rad] outside
        its limits (every copy ``+ 2 pi k``) are neither polished nor kept when another branch is
        polished: the judge would reject them (the polish moves a joint by far less than the
        margin), and unpolished they would miss the target by the idealisation's error. When
        none is polished they are all polished, as without ``limits`` (the answer then names the
        branches outside the limits). False for candidates judged elsewhere (the partial-pose
        solver's).
        """
        thetas = branches.thetas
        if limits:
            outside = self._outside
            inside = [branch for branch in thetas if not outside(branch[0])]
            if inside and len(inside) < len(thetas):
                moved = self._polish_each(inside, target, near)
                if moved:
                    branches.thetas = moved
                    return branches
        branches.thetas = self._polish_each(thetas, target, near)
        return branches

    def _polish_each(
        self, thetas: list[tuple[tuple[float, ...], str]], target: Target, near: float
    ) -> list[tuple[tuple[float, ...], str]]:
        """Each branch (DH angles [rad], label) polished; those that give up (``near``) dropped."""
        judge, offsets = self._judge, self._offsets
        rotation = target.rotation if isinstance(target, PoseTarget) else None
        signs = 1.0 if self._directions is None else self._directions  # q' <-> q (the judge's)
        moved = []
        for branch, label in thetas:
            q = np.subtract(branch, offsets) * signs
            q = polish(
                judge.model, judge.data, judge.frame_id, q, target.position, rotation, give_up=near
            )
            if q[0] == q[0]:  # not NaN: polished
                moved.append((tuple(np.add(q * signs, offsets).tolist()), label))
        return moved

    def _outside(self, thetas: tuple[float, ...] | list[float]) -> bool:
        """Whether a joint of ``thetas`` (DH angles [rad]) is far outside its limits.

        Farther than :data:`OUTSIDE_MARGIN` (and :data:`~kin.ik.limit_rule.LIMIT_TOL`) in every
        copy ``+ 2 pi k``.
        """
        tolerance = LIMIT_TOL + OUTSIDE_MARGIN
        for theta, offset, lower, upper in zip(thetas, self._offsets, self._lower, self._upper):
            span = upper - lower + 2.0 * tolerance
            if span < TWO_PI and (theta - offset - lower + tolerance) % TWO_PI > span:
                return True
        return False

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
