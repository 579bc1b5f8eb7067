"""A closed-form arm as its structure sees it (:class:`ClosedFormArm`), and its branches of a target.

What :class:`~.closed_form.ClosedFormSolver` and the objects it holds (the branch verifier,
:mod:`.branch_verification`; the idealised table's polish, :mod:`.idealised_fallback`) read:
the structure that fits the table (:func:`recognise_arm`, exact or on the idealised table,
:mod:`.idealised`), its branches of a target (DH angles, world frame), and the caller's seed as
the structure's joints (``q' = direction * q`` when the table reverses a joint or the structure
turns an axis over, :mod:`.joint_directions`), checked once. Everything here depends on the
table alone: computed once, as floats and lists, so that a solve runs on the math module rather
than on small NumPy arrays. Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable
from kin import RobotModel

from ..exceptions import StructureError, TargetError
from ..targets.target import PoseTarget, Target
from .branches import Branches
from .closed_form_structure import ClosedFormStructure, DetailedStructure, candidate_branches
from .idealised import Idealised, idealise
from .joint_directions import forward_table, mirrored_limits, reversed_joints
from .registry import recognise_turned


@dataclass(frozen=True, eq=False)
class ClosedFormArm:
    """The values of one arm's closed form that depend on its table alone (see the module).

    Attributes:
        robot: The loaded robot.
        structure: The structure that fits the (forward, possibly idealised) table.
        table: The table the structure solves (forward, turned over where it turns axes,
            idealised when rounded).
        idealised: The idealised table the structure fits when the true one misses it by
            rounding (:mod:`.idealised`: answers polished on the true chain), else None.
        directions: Per joint 1 or -1 when the table reverses a joint or the structure fits it
            with antiparallel axes turned over (:func:`.registry.recognise_turned`), else None:
            the structure solves its table in ``q' = direction * q``; seeds are mapped in,
            answers out before the judge measures them on the true arm.
        offsets: The structure's table's theta offsets [rad] (DH angle = ``q' + offset``).
        lower: Lower limits of ``q'`` [rad, m] (those of the forward table).
        upper: Upper limits of ``q'`` [rad, m].
        has_offsets: Whether any theta offset is not zero.
        detailed: Whether the structure gives its branches itself (:class:`DetailedStructure`).
        zero_seed: The zero seed as floats (the seed of a call given none, as the structure
            reads it; compared by identity first).
    """

    robot: RobotModel
    structure: ClosedFormStructure
    table: DHTable
    idealised: Idealised | None
    directions: np.ndarray | None
    offsets: list[float]
    lower: list[float]
    upper: list[float]
    has_offsets: bool
    detailed: bool
    zero_seed: list[float]

    def branches(self, target: Target, seed: list[float]) -> Branches:
        """Branches (DH angles) of a target of the closed form's kinds, in the world frame."""
        structure = self.structure
        if self.detailed:
            return structure.branches(target, seed)  # type: ignore[attr-defined]
        rotation = target.rotation if isinstance(target, PoseTarget) else None
        candidates = structure.solve(target.position, rotation)
        return candidate_branches(structure, candidates, self.offsets)

    def joints_of(self, thetas: tuple[float, ...] | list[float]) -> np.ndarray:
        """The arm's joint vector ``q`` [rad, m] of the structure's DH angles ``thetas``."""
        q = np.subtract(thetas, self.offsets)
        return q if self.directions is None else q * self.directions

    def dh_angles(self, q: np.ndarray) -> tuple[float, ...]:
        """The structure's DH angles ``direction * q + theta offset`` of the arm's ``q`` [rad]."""
        forward = q if self.directions is None else q * self.directions
        return tuple(v + offset for v, offset in zip(forward.tolist(), self.offsets))

    def forward_seed(self, seed: npt.ArrayLike) -> npt.ArrayLike:
        """The seed ``q`` [rad] as the forward table's ``q' = direction * q``.

        A seed of the wrong size, or with a value that is not finite, is returned as given, for
        :meth:`seed_list` to name.
        """
        directions = self.directions
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

    def seed_list(self, seed: npt.ArrayLike | None) -> list[float]:
        """The seed as floats [rad] (zeros if None).

        Raises:
            TargetError: The seed has the wrong size or a value that is not finite.
        """
        if seed is None:
            return self.zero_seed
        nq = len(self.lower)
        if seed.__class__ is np.ndarray and seed.shape == (nq,):  # type: ignore[union-attr]
            seed_list = seed.tolist()  # type: ignore[union-attr]
            if math.isfinite(sum(seed_list)):  # the common case: one check, no copy
                return seed_list  # type: ignore[no-any-return]
        seed_list = np.asarray(seed, dtype=float).reshape(-1).tolist()
        if len(seed_list) != nq:
            raise TargetError(
                f"the seed of '{self.robot.name}' must have {nq} values, got {len(seed_list)}"
            )
        if not all(math.isfinite(v) for v in seed_list):
            raise TargetError(f"the seed must be finite, got {seed_list}")
        return seed_list  # type: ignore[no-any-return]


def recognise_arm(robot: RobotModel) -> ClosedFormArm:
    """The structure that fits ``robot``'s table, exactly or on its idealised table.

    The registered structures (:mod:`.registry`) are asked on the forward table
    (:mod:`.joint_directions`), then, when none fits, on the table with its rounded twists
    snapped (:func:`.idealised.idealise`).

    Raises:
        StructureError: The table does not fit a closed-form structure, even idealised.
    """
    directions = reversed_joints(robot.table)
    table = forward_table(robot.table)
    idealised: Idealised | None = None
    structure: ClosedFormStructure
    try:
        structure, table, flips = recognise_turned(table)
    except StructureError as exact:
        ideal = idealise(table)
        if ideal is None:
            raise
        try:
            structure, table, flips = recognise_turned(ideal.table)
        except StructureError:
            raise exact from None
        idealised = ideal
    if flips is not None:
        directions = flips if directions is None else directions * flips
    lower = robot.model.lowerPositionLimit.tolist()
    upper = robot.model.upperPositionLimit.tolist()
    if directions is not None:  # the limits of q' (those of the forward table)
        mirrored = mirrored_limits(lower, upper, directions)
        lower, upper = mirrored[0].tolist(), mirrored[1].tolist()
    offsets = [row.theta for row in table.rows]
    return ClosedFormArm(
        robot,
        structure,
        table,
        idealised,
        directions,
        offsets,
        lower,
        upper,
        any(offsets),
        isinstance(structure, DetailedStructure),
        [0.0] * len(lower),
    )
