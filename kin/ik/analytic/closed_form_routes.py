"""Where a closed-form arm sends what its closed form does not answer alone (:class:`ClosedFormRoutes`).

:class:`~.closed_form.ClosedFormSolver` answers the target kinds of its structure; a partial
pose goes to the partial-pose solver (:mod:`kin.ik.partial_pose`, whose candidates are this
closed form's branches: :meth:`ClosedFormRoutes.pose_candidates`), a full pose on an arm that
solves positions or projects poses is first tried on its branches
(:meth:`ClosedFormRoutes._pose_from_branches`), and a kind the closed form does not take (a
position on a five-joint arm) goes to the numeric solver with the seed as the preferred posture.
Both solvers are built on first use. Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import threading
import time
from typing import Any

import numpy as np
import numpy.typing as npt

from ...configuration import default_seed, seed_inside
from ..result import IKResult, IKSolution
from ..target import PoseTarget, PositionTarget, Target
from .closed_form_structure import candidate_branches
from .idealised import FK_TOLERANCE, Idealised
from .idealised_fallback import IdealisedFallback
from .position_near_seed import NearSeedAnswer, PositionNearSeed

#: An idealised arm's branch of a pose's projection is polished onto the pose (the pose route)
#: when its tool on the true chain is within this [m] and [rad] of the pose: ten times the
#: largest tool displacement the idealisation may cause; farther ones cannot reach the pose.
IDEAL_NEAR = 10.0 * FK_TOLERANCE


class ClosedFormRoutes(IdealisedFallback):
    """The partial-pose and numeric routes of :class:`~.closed_form.ClosedFormSolver` (mixed in)."""

    idealised: Idealised | None
    _kinds: tuple[type, ...]
    _lock: threading.Lock
    _numeric: Any
    _partial: Any
    #: :attr:`_near_seed`: not yet built (None), built, or False (the arm is no 6R closed form).
    _position_near_seed: PositionNearSeed | bool | None = None

    @property
    def partial(self) -> Any:
        """The solver of partial poses (:mod:`kin.ik.partial_pose`), built on first use.

        This closed form's branches are its candidates, then weighted least squares.
        """
        if self._partial is None:
            from ..partial_pose import PartialPoseIK

            # The numeric solver's seed table gives starts in the right basin where the closed
            # form's branches miss (a five-joint arm's masked poses: a thin set).
            self._partial = PartialPoseIK(
                self.robot,
                self.structure,
                self.name,
                samples=self.numeric.nearest_samples,
                pose_candidates=self.pose_candidates,
            )
        return self._partial

    def pose_candidates(
        self, position: np.ndarray, rotations: np.ndarray, seed: npt.ArrayLike
    ) -> list[tuple[np.ndarray, str]]:
        """The closed form's branches of full poses, as the arm's joint vectors, not yet judged.

        The candidates of the partial-pose solver (:mod:`kin.ik.partial_pose`): for each tool
        rotation of ``rotations`` (K, 3, 3) at ``position`` [m] (world frame), every branch of the
        structure, the idealised structure's polished on the true chain (:mod:`.idealised`),
        turned into the arm's joints (offsets and directions applied). Neither wrapped into the
        limits nor measured: the caller judges them on the components it constrains.

        Args:
            position: Tool position [m], world frame.
            rotations: Tool rotations (K, 3, 3), world frame.
            seed: Joint vector [rad] inside the limits (a free joint's value at a singularity).
        """
        if PoseTarget not in self._kinds:
            return []
        forward = seed if self._directions is None else self._forward_seed(seed)
        seed_list = self._seed_list(forward)
        out: list[tuple[np.ndarray, str]] = []
        with self._lock:
            for rotation in rotations:
                target = PoseTarget(position, rotation)
                branches = self._branches(target, seed_list)
                if branches.status == "out_of_reach":
                    continue
                if self.idealised is not None:
                    branches = self._polished(branches, target)
                for thetas, label in branches.thetas:
                    q = np.subtract(thetas, self._offsets)
                    if self._directions is not None:
                        q = q * self._directions
                    out.append((q, label))
        return out

    @property
    def _near_seed(self) -> PositionNearSeed | None:
        """The answer nearest the seed of a position (6R arms whose closed form takes poses)."""
        if self._position_near_seed is None:
            fits = PoseTarget in self._kinds and len(self._lower) == 6
            fits = fits and all(row.joint_type == "revolute" for row in self.robot.table.rows)
            self._position_near_seed = (
                PositionNearSeed(self.robot, self.pose_candidates) if fits else False
            )
        built = self._position_near_seed
        return built if isinstance(built, PositionNearSeed) else None

    @property
    def numeric(self) -> Any:
        """The numeric solver of the same robot, for the target kinds the closed form lacks."""
        if self._numeric is None:
            from ..numeric.solver import NumericIK

            # Built inside a solve: its seed table within that call's budget, or in the
            # background for the next calls (NumericIK.solve).
            self._numeric = NumericIK(self.robot, closed_form=False, prepare=False)
        return self._numeric

    def _pose_from_branches(
        self, target: PoseTarget, seed: npt.ArrayLike | None, start: float
    ) -> IKResult | None:
        """A full pose by its closed form's branches, measured on the whole pose.

        The branches of its position (or of its projection on the arm's poses) are every joint
        vector that can reach the pose: those that do (the judge, at the solver's tolerances)
        are the answer. An idealised arm's branches near the pose (:data:`IDEAL_NEAR`) are
        polished on the true chain first (:func:`.idealised.polish`), the far ones dropped, those
        far outside the limits judged unpolished (:meth:`_verify_polished`).
        None when none does (no warning): the partial-pose solver then gives the nearest pose,
        or the answer at its looser tolerances. A rounded arm's branches all on target outside
        the limits, each isolated (:meth:`~.idealised_fallback.IdealisedFallback._isolated`),
        give ``outside_limits`` here, as the partial-pose solver gives an exact arm's.
        """
        if self._directions is not None and seed is not None:
            seed = self._forward_seed(seed)
        seed_list = self._seed_list(seed)
        if not target.finite:
            return None
        if PoseTarget in self._kinds:  # the projection of the pose on the arm's poses
            branches = self._branches(target, seed_list)
        elif self._detailed:  # it reads the target's position
            branches = self.structure.branches(target, seed_list)  # type: ignore[attr-defined]
        else:
            candidates = self.structure.solve(target.position, None)
            branches = candidate_branches(self.structure, candidates, self._offsets)
        if branches.status == "out_of_reach":
            return None
        p, r = target.position.tolist(), target.rotation.tolist()
        if self.idealised is not None:  # its branches near the pose, polished on the true chain
            valid, rejected = self._verify_polished(
                target, branches, seed_list, p, r, quiet=True, near=IDEAL_NEAR
            )
            method = "closed_form_polished"
            if not valid and self._outside_proved(rejected, target):
                return self._result([], rejected, branches.status, branches.message, start)
        else:
            valid, rejected = self._verify(target, branches, seed_list, p, r, quiet=True)
            method = "closed_form"
        if not valid:
            return None
        return self._result(valid, rejected, branches.status, branches.message, start, method)

    def _solve_numeric(
        self, target: Target, seed: npt.ArrayLike | None, timeout: float | None
    ) -> IKResult:
        """A target the closed form does not take, by the numeric solver.

        The arm is redundant for it (a position on a five- or six-joint arm): on a 6R arm whose
        closed form takes poses, the answer nearest the seed (:mod:`.position_near_seed`: damped
        least squares from the seed and the closed form's branches at the seed's tool rotation,
        each slid along the target's answers toward the seed; no seed: the default one);
        otherwise, or when none of those reaches the target, the numeric solver with the seed as
        the preferred posture, so the answer stays near it (a path's samples do not jump).
        """
        from ..numeric.numeric_target import NumericTarget

        if isinstance(target, PositionTarget) and target.finite and self._near_seed is not None:
            start = time.perf_counter()
            near = seed_inside(self.robot, default_seed(self.robot) if seed is None else seed)
            answer = self._near_seed.solve(target.position, np.asarray(near, dtype=float))
            if answer is not None:
                return near_seed_result(self.name, answer, start)
        if seed is None or not target.finite:
            return self.numeric.solve(target, seed, timeout=timeout)
        posture = np.asarray(seed, dtype=float).reshape(-1)
        preferred = NumericTarget.from_arrays(target.position, None, posture=posture)
        return self.numeric.solve(preferred, posture, timeout=timeout)


def near_seed_result(solver: str, answer: NearSeedAnswer, start: float) -> IKResult:
    """The result of a position answered by :mod:`.position_near_seed` (method ``near_seed``).

    Args:
        solver: The closed form's name (``closed_form:<structure>``).
        answer: The answer nearest the seed.
        start: :func:`time.perf_counter` at the solve's start [s].
    """
    solution = IKSolution(answer.q, "", True, answer.position_error, None)
    message = f"the answer nearest the seed: from the {answer.start}, slid toward the seed"
    return IKResult(
        success=True,
        solver=solver,
        status="ok",
        message=message,
        solutions=(solution,),
        iterations=answer.steps,
        time=time.perf_counter() - start,
        method="near_seed",
    )
