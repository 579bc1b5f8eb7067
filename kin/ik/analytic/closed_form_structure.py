"""What a closed-form structure plug-in provides, so the solvers can use it without knowing it.

A structure is one module (``planar2r.py``, ``offset3r.py``, ``five_dof.py``, ``ur_wrist.py``,
``spherical_wrist.py``, ``pieper.py``, ``three_parallel.py``, ``reversed_chain.py``) holding its
recogniser, its parameters, its scalar and its batched solve. :mod:`.registry` lists the
registered structures; :func:`~.registry.recognise` asks them in turn (several may share a joint
count; the first that fits wins); :class:`~.closed_form.ClosedFormSolver` and
:class:`~.batch.BatchSolver` call only what is below.

A new structure must provide (:class:`ClosedFormStructure`), as a class:

- ``name: ClassVar[str]``: short id; the solver reports ``"closed_form:<name>"``;
- ``dof: ClassVar[int]``: its number of joints (only tables of that many joints are offered);
- ``target_kinds: ClassVar[tuple[type, ...]]``: the target classes its closed form solves, of
  :class:`~kin.ik.PositionTarget`, :class:`~kin.ik.PoseTarget`, :class:`~kin.ik.PitchTarget`
  (a :class:`~kin.ik.PositionTarget` on an arm whose closed form lacks it goes to the numeric
  solver);
- ``branch_labels: tuple[str, ...]`` (class or instance attribute): the meaning of each of the
  ``B`` columns of :meth:`~ClosedFormStructure.solve`;
- ``recognise(table: DHTable) -> Self`` (classmethod): its parameters read from the table;
  raises :class:`~kin.ik.exceptions.StructureError` naming what does not fit;
- ``solve(position (3,), rotation (3, 3) or None) -> (B, dof)``: candidate joint vectors
  ``q`` [rad] of one tool target ``T_world_tool`` (position [m] and ``R_world_tool`` in the
  world frame, the URDF root: the structure applies the table's base and tool transforms), a
  row of NaN where a branch does not exist; not wrapped into the limits, not verified;
- ``solve_batch(positions (N, 3), rotations (N, 3, 3) or None) -> (N, B, dof)``: the same for
  N targets.

The solvers do the rest: each angle moved by ``2 pi`` into the limits nearest the seed, every
candidate measured by the judge (:mod:`kin.ik.judge`), the valid ones ordered by distance to the
seed. A structure that gives more implements :class:`DetailedStructure` too (the three shipped
ones do): ``branches`` (scalar, with statuses, the distance out of reach, a free joint kept at the
seed's value, labels per branch) and ``batch_branches`` (with the elbow side); one that takes
pitch targets adds :class:`PitchStructure`.

To register one: ``kin.ik.analytic.registry.register(MyStructure)`` (asked after the shipped
ones; ``first=True`` to ask it first), or add it to ``CLOSED_FORMS`` in
``kin/ik/analytic/registry.py``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar, Protocol, runtime_checkable

import numpy as np

from dh2urdf import DHTable

from .branches import Branches
from .structure import BaseFrame

if TYPE_CHECKING:
    from ..targets.target import PitchTarget, Target


@runtime_checkable
class ClosedFormStructure(Protocol):
    """A closed-form structure: recogniser, candidate joint vectors, batched (see the module)."""

    name: ClassVar[str]
    dof: ClassVar[int]
    target_kinds: ClassVar[tuple[type, ...]]

    @property
    def branch_labels(self) -> tuple[str, ...]:
        """The meaning of each of the B candidate columns."""
        ...

    @classmethod
    def recognise(cls, table: DHTable) -> ClosedFormStructure:
        """The structure's parameters read from ``table``; raises ``StructureError``."""
        ...

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """Candidate joint vectors (B, dof) [rad] of one world target; NaN rows: no branch."""
        ...

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """Candidate joint vectors (N, B, dof) [rad] of N world targets."""
        ...


@dataclass(frozen=True, eq=False)
class BatchBranches:
    """Candidates of N targets with what a detailed structure knows of them.

    Attributes:
        q: Joint vectors (N, B, dof) [rad], NaN where a branch does not exist.
        elbow_up: (N, B) whether the elbow is above the line from shoulder to wrist (world z).
        approach: For pitch targets, the approach axes in the world (N, 3) the tool's
            ``approach_in_tool`` axis must meet; else None.
    """

    q: np.ndarray
    elbow_up: np.ndarray
    approach: np.ndarray | None = None


@dataclass(frozen=True)
class TableStructure:
    """What the shipped structures share: their offsets, their frame 0, the plain interface.

    Subclasses implement :meth:`batch_branches`; :meth:`solve` and :meth:`solve_batch` follow.

    Attributes:
        offsets: DH angle offsets ``theta`` [rad] (DH angle = q + offset).
        base: DH frame 0 in the world.
    """

    offsets: tuple[float, ...]
    base: BaseFrame = field(repr=False, compare=False)

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """Candidates of N world targets with the elbow side (the subclass's)."""
        raise NotImplementedError

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """Candidate joint vectors (B, dof) [rad] of one world target."""
        rotations = None if rotation is None else np.reshape(rotation, (1, 3, 3))
        return self.solve_batch(np.reshape(position, (1, 3)), rotations)[0]

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """Candidate joint vectors (N, B, dof) [rad] of N world targets."""
        return self.batch_branches(positions, rotations).q


@runtime_checkable
class DetailedStructure(ClosedFormStructure, Protocol):
    """A structure that reports why branches are missing, free joints and the elbow side."""

    def branches(self, target: Target, seed: Sequence[float]) -> Branches:
        """Branches (DH angles ``q + theta`` [rad], labels, status) of one world target.

        ``seed`` [rad]: the value kept by a free joint (and the roll of a pitch target without one).
        """
        ...

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """:meth:`solve_batch` with the elbow side."""
        ...


@runtime_checkable
class PitchStructure(DetailedStructure, Protocol):
    """A structure that also solves :class:`~kin.ik.PitchTarget` (tool point + approach pitch)."""

    @property
    def approach_in_tool(self) -> tuple[float, float, float]:
        """The approach axis in the tool frame."""
        ...

    def approach(self, target: PitchTarget, seed: Sequence[float]) -> tuple[float, float, float]:
        """The target's approach axis in the world frame."""
        ...

    def pitch_batch_branches(
        self, positions: np.ndarray, pitch: np.ndarray, roll: np.ndarray
    ) -> BatchBranches:
        """Candidates of N tool points (N, 3) [m] with pitch [rad] and wrist roll ``q5`` [rad]."""
        ...


def candidate_branches(
    structure: ClosedFormStructure, q: np.ndarray, offsets: Sequence[float]
) -> Branches:
    """:class:`Branches` (DH angles ``q + theta``) of a plain structure's candidates (B, dof).

    The NaN rows are dropped; none left: out of reach (no distance known).
    """
    branches = Branches()
    exists = (~np.isnan(q).any(axis=1)).tolist()
    rows = (q + np.asarray(offsets, dtype=float)).tolist() if any(offsets) else q.tolist()
    branches.thetas.extend(
        (tuple(row), label)
        for row, label, found in zip(rows, structure.branch_labels, exists)
        if found
    )
    if not branches.thetas:
        branches.out_of_reach(None, f"no {structure.name} branch reaches the target")
    return branches
