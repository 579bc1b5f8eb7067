"""Stage 0 of the numeric pipeline: the closed form with a free joint, when the arm has one.

:func:`free_joint_closed_form` picks the arm's closed form, first that fits:
:class:`~kin.ik.analytic.seven_dof.SevenDofIK` (humanoid7's structure: joint 1 free, full poses
and positions) and :class:`~kin.ik.analytic.spherical_shoulder7.SphericalShoulder7RIK` (axes 1-3
and 5-6 meeting: Panda, xArm7; joint 7 free, full poses only). Both meet :class:`FreeJointClosedForm`:
the free joint from a start, the other joints in closed form, the branch nearest the start.
Starts: the caller's seed, then the seed-table samples near the target. When a start's free joint
gives no branch inside the limits, the seed and the first sample scan it outward from there
(coarse to fine): the answer keeps the start's free joint as nearly as the target allows. The
judge (:mod:`kin.ik.judge`) measures every answer. Most targets end here, in tens of microseconds.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any, ClassVar, Protocol

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ..analytic.seven_dof import SevenDofIK
from ..analytic.spherical_shoulder7 import SphericalShoulder7RIK, spherical_shoulder7
from ..analytic.structure import seven_dof
from ..exceptions import StructureError
from ..result import IKResult, IKSolution
from .numeric_target import NumericTarget

if TYPE_CHECKING:
    from .search import Search
    from .solver import NumericIK

#: :attr:`IKResult.method` of this stage.
METHOD = "closed_form_free_joint"


class FreeJointClosedForm(Protocol):
    """A closed form for chosen values of a free joint (what stage 0 asks of it)."""

    #: Whether its compiled twin of :meth:`first` is built.
    compiled_twin: ClassVar[bool]

    def prepare(self, position: np.ndarray, rotation: np.ndarray | None) -> Any:
        """The target's constants for :meth:`first`, or None for a target it does not take."""
        ...

    def first(
        self, target: Any, starts: np.ndarray, out: np.ndarray, step: float, compiled: bool
    ) -> int:
        """Index of the first start giving a branch inside the limits (written to ``out``), or -1."""
        ...


def free_joint_closed_form(
    table: DHTable, lower: Sequence[float], upper: Sequence[float]
) -> FreeJointClosedForm | None:
    """The free-joint closed form of an arm, or None when none fits its table.

    Args:
        table: The arm's DH table.
        lower: Lower joint limits [rad].
        upper: Upper joint limits [rad].
    """
    try:
        return SevenDofIK(seven_dof(table), lower, upper)
    except StructureError:
        pass
    try:
        return SphericalShoulder7RIK(spherical_shoulder7(table), lower, upper)
    except StructureError:
        return None


def solve_free_joint(
    ik: NumericIK, search: Search, seed_q: npt.ArrayLike | None
) -> IKResult | None:
    """The closed form from the caller's seed, then from seed-table samples; None if none verifies."""
    closed = ik.closed_form
    if closed is None:
        return None
    target = search.target
    prepared = closed.prepare(target.position, target.rotation)
    if prepared is None:  # a target this closed form does not take
        return None
    position = target.position.tolist()
    rotation = None if target.rotation is None else target.rotation.ravel().tolist()
    out = np.empty(7)
    for label, starts, indices, step in _starts(ik, target, seed_q):
        offset = 0
        while offset < len(starts):
            index = closed.first(prepared, starts[offset:], out, step, ik.compiled)
            if index < 0:
                break
            offset += index + 1
            position_error, rotation_error = ik.judge.errors(out, position, rotation)
            if position_error < search.position_tol and (
                rotation_error is None or rotation_error < search.rotation_tol
            ):  # the limits: the closed form's business
                solution = IKSolution(out.copy(), "", True, position_error, rotation_error)
                if label is None:
                    label = f"seed-table sample {int(indices[offset - 1])}"  # type: ignore[index]
                return search.success(
                    solution, METHOD, f"closed form with the free joints of {label}"
                )
    return None


def _starts(
    ik: NumericIK, target: NumericTarget, seed_q: npt.ArrayLike | None
) -> Iterator[tuple[str | None, np.ndarray, np.ndarray | None, float]]:
    """Blocks of closed-form starts, in order: ``(label, starts, sample indices, step)``.

    The caller's seed (scanned, coarse then fine); the seed-table sample nearest the target
    (scanned likewise; for a full pose by pose distance, for a position the nearest to the
    target's grid cell centre); the next ``closed_form_starts`` samples (not scanned). Looked up
    lazily: most targets need the first block only.
    """
    steps = ik.closed_form_steps
    if seed_q is not None:
        seed = ik.seed_vector(seed_q)[None]
        for step in steps:
            yield "the given seed", seed, None, step
    table = ik.table
    position, rotation = target.position, target.rotation
    if rotation is None:
        candidates = table.cell_samples(position)
        if candidates is None:
            return
        for step in steps:
            yield None, table.q[candidates[:1]], candidates, step
        rest = candidates[1 : ik.closed_form_starts]
    else:
        found = table.ranked(position, rotation)
        if found is None or not found[0].size:
            return
        candidates, distances = found
        first = int(distances.argmin())
        for step in steps:
            yield None, table.q[candidates[first : first + 1]], candidates[first:], step
        order = np.argsort(distances, kind="stable")[: ik.closed_form_starts]
        rest = candidates[order[order != first]]
    if rest.size:
        yield None, table.q[rest], rest, 0.0
