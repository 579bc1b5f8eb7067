"""Where a closed-form arm sends what its closed form does not answer alone (:class:`ClosedFormRoutes`).

:class:`~.closed_form.ClosedFormSolver` answers the target kinds of its structure and holds one
:class:`ClosedFormRoutes` for the rest (built from the same arm, verifier and polish); a partial
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
from collections.abc import Callable
from typing import Any, Generic, TypeVar

import numpy as np
import numpy.typing as npt

from ...configuration import default_seed, seed_inside
from ..result import IKResult, IKSolution
from ..targets.target import PoseTarget, PositionTarget, Target
from .branch_verification import BranchVerifier
from .closed_form_branches import ClosedFormArm
from .closed_form_structure import candidate_branches
from .idealised import FK_TOLERANCE
from .idealised_fallback import IdealisedPolish
from .position_near_seed import NearSeedAnswer, PositionNearSeed

#: An idealised arm's branch of a pose's projection is polished onto the pose (the pose route)
#: when its tool on the true chain is within this [m] and [rad] of the pose: ten times the
#: largest tool displacement the idealisation may cause; farther ones cannot reach the pose.
IDEAL_NEAR = 10.0 * FK_TOLERANCE


_Built = TypeVar("_Built")
#: What :class:`OnFirstUse` holds before it is built.
_UNBUILT = object()


class OnFirstUse(Generic[_Built]):
    """A value built by ``build()`` the first time it is asked for (``holder()``), then kept."""

    def __init__(self, build: Callable[[], _Built]) -> None:
        self._build = build
        self._value: Any = _UNBUILT

    def __call__(self) -> _Built:
        """The value, built now if it is not yet (None is a value too)."""
        if self._value is _UNBUILT:
            self._value = self._build()
        return self._value  # type: ignore[no-any-return]


class ClosedFormRoutes:
    """The partial-pose and numeric routes of :class:`~.closed_form.ClosedFormSolver` (see the module).

    Args:
        arm: The arm as its structure sees it.
        verifier: The closed form's branch verifier.
        polish: The idealised table's polish (:mod:`.idealised_fallback`), None for an exact arm.
        numeric: Gives the numeric solver of the same robot, built on first use.
        name: The solver's name (``closed_form:<structure>``).
        lock: The solver's lock (one solve at a time: the judge's Pinocchio data is shared).
    """

    def __init__(
        self,
        arm: ClosedFormArm,
        verifier: BranchVerifier,
        polish: IdealisedPolish | None,
        numeric: OnFirstUse[Any],
        name: str,
        lock: threading.Lock,
    ) -> None:
        self.arm = arm
        self.verifier = verifier
        self.polish = polish
        self.numeric = numeric
        self.name = name
        self._lock = lock
        self._kinds = tuple(arm.structure.target_kinds)
        self.partial = OnFirstUse(self._partial_solver)
        #: The answer nearest the seed of a position (6R arms whose closed form takes poses),
        #: or None.
        self.near_seed = OnFirstUse(self._position_near_seed)

    def _partial_solver(self) -> Any:
        """The solver of partial poses (:mod:`kin.ik.partial_pose`).

        This closed form's branches are its candidates, then weighted least squares.
        """
        from ..partial_pose import PartialPoseIK

        # The numeric solver's seed table gives starts in the right basin where the closed
        # form's branches miss (a five-joint arm's masked poses: a thin set).
        return PartialPoseIK(
            self.arm.robot,
            self.arm.structure,
            self.name,
            samples=self.numeric().nearest_samples,
            pose_candidates=self.pose_candidates,
        )

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
        arm = self.arm
        forward = seed if arm.directions is None else arm.forward_seed(seed)
        seed_list = arm.seed_list(forward)
        out: list[tuple[np.ndarray, str]] = []
        with self._lock:
            for rotation in rotations:
                target = PoseTarget(position, rotation)
                branches = arm.branches(target, seed_list)
                if branches.status == "out_of_reach":
                    continue
                if self.polish is not None:
                    branches = self.polish.polished(branches, target)
                for thetas, label in branches.thetas:
                    out.append((arm.joints_of(thetas), label))
        return out

    def _position_near_seed(self) -> PositionNearSeed | None:
        """:attr:`near_seed`, built (None: the arm is no 6R closed form taking poses)."""
        arm = self.arm
        fits = PoseTarget in self._kinds and len(arm.lower) == 6
        fits = fits and all(row.joint_type == "revolute" for row in arm.robot.table.rows)
        return PositionNearSeed(arm.robot, self.pose_candidates) if fits else None

    def pose_from_branches(
        self, target: PoseTarget, seed: npt.ArrayLike | None, start: float
    ) -> IKResult | None:
        """A full pose by its closed form's branches, measured on the whole pose.

        The branches of its position (or of its projection on the arm's poses) are every joint
        vector that can reach the pose: those that do (the judge, at the solver's tolerances)
        are the answer. An idealised arm's branches near the pose (:data:`IDEAL_NEAR`) are
        polished on the true chain first (:func:`.idealised.polish`), the far ones dropped, those
        far outside the limits judged unpolished (:meth:`.IdealisedPolish.verify_polished`).
        None when none does (no warning): the partial-pose solver then gives the nearest pose,
        or the answer at its looser tolerances. A rounded arm's branches all on target outside
        the limits, each isolated (:meth:`.IdealisedPolish.isolated`),
        give ``outside_limits`` here, as the partial-pose solver gives an exact arm's.
        """
        arm, verifier = self.arm, self.verifier
        if arm.directions is not None and seed is not None:
            seed = arm.forward_seed(seed)
        seed_list = arm.seed_list(seed)
        if not target.finite:
            return None
        if PoseTarget in self._kinds:  # the projection of the pose on the arm's poses
            branches = arm.branches(target, seed_list)
        elif arm.detailed:  # it reads the target's position
            branches = arm.structure.branches(target, seed_list)  # type: ignore[attr-defined]
        else:
            candidates = arm.structure.solve(target.position, None)
            branches = candidate_branches(arm.structure, candidates, arm.offsets)
        if branches.status == "out_of_reach":
            return None
        p, r = target.position.tolist(), target.rotation.tolist()
        polish = self.polish
        if polish is not None:  # its branches near the pose, polished on the true chain
            valid, rejected = polish.verify_polished(
                target, branches, seed_list, p, r, quiet=True, near=IDEAL_NEAR
            )
            method = "closed_form_polished"
            if not valid and polish.outside_proved(rejected, target):
                return verifier.result([], rejected, branches.status, branches.message, start)
        else:
            valid, rejected = verifier.verify(target, branches, seed_list, p, r, quiet=True)
            method = "closed_form"
        if not valid:
            return None
        return verifier.result(valid, rejected, branches.status, branches.message, start, method)

    def solve_numeric(
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

        robot = self.arm.robot
        if isinstance(target, PositionTarget) and target.finite:
            near_seed = self.near_seed()
            if near_seed is not None:
                start = time.perf_counter()
                near = seed_inside(robot, default_seed(robot) if seed is None else seed)
                answer = near_seed.solve(target.position, np.asarray(near, dtype=float))
                if answer is not None:
                    return near_seed_result(self.name, answer, start)
        if seed is None or not target.finite:
            return self.numeric().solve(target, seed, timeout=timeout)  # type: ignore[no-any-return]
        posture = np.asarray(seed, dtype=float).reshape(-1)
        preferred = NumericTarget.from_arrays(target.position, None, posture=posture)
        return self.numeric().solve(preferred, posture, timeout=timeout)  # type: ignore[no-any-return]


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
