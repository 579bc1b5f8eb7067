"""Which free-joint closed form answers an arm (stage 0 of the numeric pipeline, :mod:`.free_joint`).

:func:`free_joint_closed_form` picks the arm's closed form, first that fits:
:class:`~kin.ik.analytic.seven_r.seven_dof.SevenDofIK` (humanoid7's structure: joint 1 free),
:class:`~kin.ik.analytic.seven_r.spherical_shoulder7.SphericalShoulder7RIK` (Panda, xArm7:
joint 7 free), then :class:`~kin.ik.analytic.seven_r.general_7r.General7RIK` (any other 7R arm);
a table that reverses a joint is solved on its forward table (:class:`_ReversedJoints`). Each
meets :class:`FreeJointClosedForm`. Angles in [rad].
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar, Protocol, cast

import numpy as np

from dh2urdf import DHTable

from ..analytic.joint_directions import forward_table, mirrored_limits, reversed_joints
from ..analytic.seven_r.general_7r import General7RIK
from ..analytic.seven_r.seven_dof import SevenDofIK
from ..analytic.seven_r.shoulder7_structure import spherical_shoulder7
from ..analytic.seven_r.spherical_shoulder7 import SphericalShoulder7RIK
from ..analytic.structure import seven_dof
from ..exceptions import StructureError


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
    table: DHTable, lower: Sequence[float], upper: Sequence[float], *, general: bool = True
) -> FreeJointClosedForm | None:
    """The free-joint closed form of an arm, or None when none fits its table.

    Args:
        table: The arm's DH table.
        lower: Lower joint limits [rad].
        upper: Upper joint limits [rad].
        general: Also the general 7R form (:class:`General7RIK`) when no special one fits.
    """
    directions = reversed_joints(table)
    if directions is not None:  # solved on the forward table, in q' = direction * q
        low, high = mirrored_limits(lower, upper, directions)
        closed = free_joint_closed_form(
            forward_table(table), low.tolist(), high.tolist(), general=general
        )
        return (
            None
            if closed is None
            else cast(FreeJointClosedForm, _ReversedJoints(closed, directions))
        )
    try:
        return SevenDofIK(seven_dof(table), lower, upper)
    except StructureError:
        pass
    try:
        return SphericalShoulder7RIK(spherical_shoulder7(table), lower, upper)
    except StructureError:
        pass
    if not general or table.dof != 7:
        return None
    try:  # any other 7R: an end joint held, the 6R closed forms for the rest
        return General7RIK(table, lower, upper)
    except StructureError:
        return None


class _ReversedJoints:
    """A free-joint closed form of the forward table, taking and giving the arm's q.

    The table reverses a joint (:mod:`~kin.ik.analytic.joint_directions`): starts are mapped in
    (``q' = direction * q``), answers out, before the judge measures them on the true arm.
    """

    def __init__(self, closed: FreeJointClosedForm, directions: np.ndarray):
        self._closed = closed
        self._directions = directions
        self.compiled_twin = closed.compiled_twin
        self.costly = bool(getattr(closed, "costly", False))
        #: The free joint (0-based), the forward form's.
        self.free: int = getattr(closed, "free", -1)

    def prepare(self, position: np.ndarray, rotation: np.ndarray | None) -> Any:
        """The forward closed form's :meth:`FreeJointClosedForm.prepare` (the same target)."""
        return self._closed.prepare(position, rotation)

    def branches_at(
        self, position: np.ndarray, rotation: np.ndarray | None, values: np.ndarray
    ) -> np.ndarray | None:
        """The forward form's ``branches_at`` in the arm's q: free-joint ``values`` (G,) [rad] in."""
        found = self._closed.branches_at(  # type: ignore[attr-defined]
            position, rotation, values * self._directions[self.free]
        )
        return None if found is None else found * self._directions

    def first(
        self, target: Any, starts: np.ndarray, out: np.ndarray, step: float, compiled: bool
    ) -> int:
        """:meth:`FreeJointClosedForm.first` in the arm's q: ``out`` holds q (7,) [rad]."""
        index = self._closed.first(target, starts * self._directions, out, step, compiled)
        if index >= 0:
            out *= self._directions
        return index
