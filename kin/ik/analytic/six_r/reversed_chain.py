"""Closed-form IK of a 6R arm whose chain read from the tool end fits a 6R family (IK-Geo's reversal).

An arm with its special axes at the base (a spherical shoulder: axes 1, 2, 3 meeting; three
parallel axes 3, 4, 5 with axes 1 and 2 meeting; ...) is, read backwards, an arm of a family of
:mod:`.three_parallel` (the UR case among them) or :mod:`.pieper` (the spherical-wrist case among
them). The reversed chain is again a DH table, built exactly (no number rounded):

- a standard row ``A_i = Rz(t_i) Tz(d_i) Tx(a_i) Rx(alpha_i)`` has the inverse
  ``Rx(-alpha_i) Tx(-a_i) Rz(-t_i) Tz(-d_i)``: a *modified* row with ``-alpha_i, -a_i, -d_i``,
  offset ``-theta_i`` and joint variable ``-q_i``;
- a modified row ``Rx(alpha_i) Tx(a_i) Rz(t_i) Tz(d_i)`` inverts to ``Rz(-t_i) Tz(-d_i)
  Tx(-a_i) Rx(-alpha_i)``: a *standard* row, likewise negated;

so ``T_world_tool(q)^-1 = T_last_tool^-1 A_n^-1 ... A_1^-1 T_world_base^-1`` is the table
:func:`reverse_table`: rows in reverse order, the other convention, base ``T_last_tool^-1``, tool
``T_world_base^-1``, joint ``j`` of it being ``-q_{n+1-j}`` (limits negated and swapped). The
target ``T`` becomes ``T^-1``; each branch ``q'`` of the reversed arm gives ``q = -q'`` read
backwards.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from dh2urdf import DHTable
from dh2urdf.dh_table import Convention

from ...exceptions import StructureError, TargetError
from ...targets.target import PoseTarget
from ..closed_form_structure import ClosedFormStructure
from ._six_r import target_arrays, wrap_array
from .pieper import Pieper6R
from .three_parallel import ThreeParallel6R

#: The forward 6R families a reversed table is offered to, in order (each gives its special case:
#: :class:`~.three_parallel.URWrist6R`, :class:`~.pieper.SphericalWrist6R`).
FORWARD: tuple[type[ClosedFormStructure], ...] = (ThreeParallel6R, Pieper6R)


def _inverse(T: np.ndarray) -> np.ndarray:
    """Inverse of a rigid transform (4x4) [m]."""
    matrix = np.asarray(T, dtype=float)
    return pin.SE3(matrix[:3, :3].copy(), matrix[:3, 3].copy()).inverse().homogeneous


def reverse_table(table: DHTable) -> DHTable:
    """The arm read from its tool to its base (see the module): ``T_rev(q') = T(q)^-1``.

    Joint ``j`` (1-based) of the result is joint ``n + 1 - j`` of ``table`` with its variable
    negated, ``q'_j = -q_{n+1-j}`` [rad] (limits ``[-upper, -lower]``); the result's world frame is
    ``table``'s tool frame and its tool frame ``table``'s world frame. Rows keep their names; an
    index is the row's position in the reversed table.

    Raises:
        StructureError: A joint is prismatic (its variable cannot be negated into a DH row).
    """
    rows = []
    for j, row in enumerate(reversed(table.rows)):
        if row.joint_type != "revolute":
            raise StructureError(
                table.name, "reversed chain", f"row {row.index} ('{row.name}') is prismatic"
            )
        rows.append(
            dataclasses.replace(
                row,
                index=j + 1,
                a=-row.a,
                alpha=-row.alpha,
                d=-row.d,
                theta=-row.theta,
                lower=-row.upper,
                upper=-row.lower,
            )
        )
    convention: Convention = "modified" if table.convention == "standard" else "standard"
    return DHTable(
        name=table.name,
        description=f"{table.description} (read from the tool)",
        source=table.source,
        convention=convention,
        rows=tuple(rows),
        T_world_base=_inverse(table.T_last_tool),
        T_last_tool=_inverse(table.T_world_base),
    )


@dataclass(frozen=True)
class Reversed6R:
    """A 6R arm solved through its reversed chain by a forward 6R family (8 branches).

    Attributes:
        inner: The forward family's structure of :func:`reverse_table` of the arm.
    """

    name: ClassVar[str] = "reversed"
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)

    inner: ClosedFormStructure

    @property
    def branch_labels(self) -> tuple[str, ...]:
        """The inner family's labels, read from the tool end."""
        return tuple(
            f"{label} (from the tool, {self.inner.name})" for label in self.inner.branch_labels
        )

    @classmethod
    def recognise(cls, table: DHTable) -> Reversed6R:
        """The reversed arm's family.

        Raises:
            StructureError: No forward 6R family fits the reversed table; the message gives each
                family's mismatch, with rows numbered from the tool (row 1 is the table's last).
        """
        if table.dof != 6:
            raise StructureError(table.name, "6R reversed chain", f"{table.dof} joints, expected 6")
        reversed_table = reverse_table(table)
        failures = []
        for family in FORWARD:
            try:
                return cls(family.recognise(reversed_table))
            except StructureError as err:
                failures.append(err.mismatch)
        raise StructureError(
            table.name,
            "6R reversed chain",
            "read from the tool (row 1 = the last row, twists and lengths negated): "
            + "; ".join(failures),
        )

    def solve(
        self, position: npt.ArrayLike, rotation: npt.ArrayLike | None, free: float = 0.0
    ) -> np.ndarray:
        """The 8 branches reaching a tool pose.

        Args:
            position: Tool position in the world frame [m], (3,).
            rotation: Tool rotation ``R_world_tool``, (3, 3).
            free: Value given to the inner family's free joint at a singularity [rad] (a joint of
                the reversed arm: its variable is the negated joint of this one).

        Returns:
            Joint vectors [rad] in (-pi, pi], (8, 6), one row per :attr:`branch_labels`, NaN rows
            where a branch does not exist. Not verified, not wrapped into limits.
        """
        if rotation is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs a full pose")
        p = np.asarray(position, dtype=float).reshape(3)
        r = np.asarray(rotation, dtype=float).reshape(3, 3)
        branches = self.inner.solve(-r.T @ p, np.ascontiguousarray(r.T), free)  # type: ignore[call-arg]
        return _forward(branches)

    def solve_batch(
        self, positions: npt.ArrayLike, rotations: npt.ArrayLike | None, free: float = 0.0
    ) -> np.ndarray:
        """:meth:`solve` of N tool poses at once: (N, 8, 6) [rad].

        Raises:
            TargetError: No rotations, or ``positions`` not (N, 3) / ``rotations`` not (N, 3, 3).
        """
        if rotations is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs full poses")
        p, r = target_arrays(positions, rotations)
        r_inverse = np.ascontiguousarray(np.swapaxes(r, 1, 2))
        p_inverse = -np.einsum("nij,nj->ni", r_inverse, p)
        branches = self.inner.solve_batch(p_inverse, r_inverse, free)  # type: ignore[call-arg]
        return _forward(branches)


def _forward(branches: np.ndarray) -> np.ndarray:
    """Joint vectors of the arm from those of its reversed chain: ``q = -q'`` read backwards."""
    return wrap_array(-branches[..., ::-1])
