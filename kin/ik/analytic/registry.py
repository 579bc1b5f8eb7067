"""The registered closed-form structures, in an explicit, documented precedence.

Each entry (:class:`ClosedFormEntry`) names a class meeting
:class:`~.closed_form_structure.ClosedFormStructure` and its ``precedence``. Several structures
may share a joint count: :func:`recognise` asks, lowest precedence first, every structure of the
table's joint count and takes the first that fits, so a special case (with its faster form or
compiled twin) stands before the family that also takes it, and the general 6R form stands last.
The shipped precedences are multiples of 10 (:data:`SHIPPED`), leaving room for a new entry
between two. :func:`register` adds one; ``docs/adding-a-closed-form.md`` shows a worked example.
Which solver answers which robot overall (closed form, numeric, batches) is
:mod:`kin.ik.solver_table`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dh2urdf import DHTable

from ..exceptions import StructureError
from .closed_form_structure import ClosedFormStructure
from .five_joint.five_dof import FiveDof
from .joint_directions import flipped_axes
from .planar.offset3r import Offset3R
from .planar.parallel_axes import ParallelAxes, ParallelAxes2, ParallelAxes3
from .planar.planar2r import Planar2R
from .planar.yaw_planar import YawPlanar
from .planar.yaw_roll import YawPlanarRoll
from .six_r.general_6r import General6R
from .six_r.pieper import Pieper6R
from .six_r.reversed_chain import Reversed6R
from .six_r.three_parallel import ThreeParallel6R
from .structure import refuse_tilts
from .three_joint.wrist3 import Wrist3


@dataclass(frozen=True)
class ClosedFormEntry:
    """One registered closed form and its place in the asking order.

    Attributes:
        structure: The structure class (meets :class:`ClosedFormStructure`).
        precedence: Lower is asked first among the structures of the same joint count (and
            listed first in messages); unique across the registry.
        why: One line: why it stands where it does.
    """

    structure: type[ClosedFormStructure]
    precedence: int
    why: str


#: The shipped closed forms, by precedence. A special case stands before the family that also
#: fits its tables (its answers and branch labels are the special case's).
SHIPPED: tuple[ClosedFormEntry, ...] = (
    ClosedFormEntry(Planar2R, 10, "the planar 2R of the paper, before the any-frame 2R"),
    ClosedFormEntry(
        ParallelAxes2,
        20,
        "every axis parallel, 2 joints: a planar 2R the planar 2R form does not take",
    ),
    ClosedFormEntry(Offset3R, 30, "base yaw, two parallel pitch joints, a shoulder offset"),
    ClosedFormEntry(
        ParallelAxes3, 40, "every axis parallel, 3 joints: planar 3R, planar 2R with a slide"
    ),
    ClosedFormEntry(Wrist3, 45, "three revolute axes through one point: a wrist alone"),
    ClosedFormEntry(
        ParallelAxes, 50, "every axis parallel, 4 joints: SCARA, before the yaw-planar arms"
    ),
    ClosedFormEntry(YawPlanar, 60, "base yaw, three parallel pitch joints"),
    ClosedFormEntry(
        YawPlanarRoll, 70, "base yaw, two parallel pitch joints, a roll (Kinova 4-DOF)"
    ),
    ClosedFormEntry(FiveDof, 80, "base yaw, three parallel pitch joints, a wrist roll"),
    ClosedFormEntry(
        ThreeParallel6R,
        90,
        "three parallel axes 2-4, any joints 1, 5, 6; the UR case (axes 5, 6 meeting: ur_wrist, "
        "compiled twin) first, as before the spherical wrist",
    ),
    ClosedFormEntry(
        Pieper6R,
        100,
        "spherical wrist, any first three joints; the case of parallel axes 2, 3 (spherical_wrist, "
        "compiled twin) first",
    ),
    ClosedFormEntry(
        Reversed6R, 130, "the 6R families above read from the tool, before the general form"
    ),
    ClosedFormEntry(General6R, 1000, "any other 6R arm, by elimination: always last"),
)

_entries: list[ClosedFormEntry] = list(SHIPPED)

#: The registered structures in the order they are asked (kept in step with :func:`entries`;
#: updated in place by :func:`register`).
CLOSED_FORMS: list[type[ClosedFormStructure]] = [entry.structure for entry in SHIPPED]


def _recognise(structure: type[ClosedFormStructure], table: DHTable) -> ClosedFormStructure:
    """``structure.recognise(table)``; the general 6R form is given the registry's structures.

    It refuses a rounded table another family fits once idealised: the registry passes it the
    list of its rivals (it does not import the registry).
    """
    if structure is General6R:
        return General6R.recognise(table, rivals=tuple(CLOSED_FORMS))
    return structure.recognise(table)


def entries() -> tuple[ClosedFormEntry, ...]:
    """Every registered entry, shipped and added, lowest precedence first."""
    return tuple(_entries)


def register(
    structure: type[ClosedFormStructure],
    *,
    precedence: int | None = None,
    first: bool = False,
    why: str = "",
) -> ClosedFormEntry:
    """Add a structure to the registry; once only (a second call returns its entry).

    Args:
        structure: The structure class.
        precedence: Its place in the asking order (lower first; see :data:`SHIPPED` for the
            shipped values). None: after every entry, or before every entry with ``first``.
        first: With ``precedence`` None, ask it before every other structure.
        why: One line: why it stands there.

    Raises:
        TypeError: ``structure`` lacks a part of :class:`ClosedFormStructure`.
        ValueError: ``precedence`` is taken by another entry.
    """
    missing = [
        part
        for part in ("name", "dof", "target_kinds", "branch_labels", "recognise", "solve")
        + ("solve_batch",)
        if not hasattr(structure, part)
    ]
    if missing:
        raise TypeError(f"{structure.__name__} is not a closed-form structure: no {missing}")
    for entry in _entries:
        if entry.structure is structure:
            return entry
    taken = {entry.precedence: entry.structure.__name__ for entry in _entries}
    if precedence is None:
        precedence = min(taken) - 10 if first else max(taken) + 10
    elif precedence in taken:
        raise ValueError(
            f"precedence {precedence} is {taken[precedence]}'s; choose a free value "
            f"(taken: {', '.join(f'{p} {n}' for p, n in sorted(taken.items()))})"
        )
    entry = ClosedFormEntry(structure, precedence, why)
    _entries.append(entry)
    _entries.sort(key=lambda e: e.precedence)
    CLOSED_FORMS[:] = [e.structure for e in _entries]
    return entry


def recognise_turned(table: DHTable) -> tuple[ClosedFormStructure, DHTable, np.ndarray | None]:
    """:func:`recognise`, asking each structure also of the table with antiparallel axes turned.

    A twist of pi (two consecutive axes antiparallel, as a URDF extraction writes them) is the
    same arm as a twist of 0 with the later axis turned over (:func:`.joint_directions.flipped_axes`):
    each structure, in order, is asked of the table, then of that turned table. Kinova's arms
    read from their URDF (twist pi between the parallel axes 2 and 3) get the spherical-wrist
    family, with its compiled twin, instead of the general Pieper one.

    Args:
        table: A forward table (every direction 1, :func:`.joint_directions.forward_table`).

    Returns:
        ``(structure, the table it fits, flips)``: flips (dof,) of +-1 when it fits the turned
        table (its joint values are ``q' = flips * q``), else None.

    Raises:
        StructureError: No structure fits either table (the message is :func:`recognise`'s of
            the table as given).
    """
    refuse_tilts(table, "closed-form")
    found = flipped_axes(table)
    if found is not None:
        turned, flips = found
        for structure in CLOSED_FORMS:
            if structure.dof != table.dof:
                continue
            # A family's special cases (``cases``: the UR arms of the three-parallel family,
            # the spherical wrist of Pieper's) first, each of the table, then of the turned one.
            for asked in (*getattr(structure, "cases", ()), structure):
                try:
                    return _recognise(asked, table), table, None
                except StructureError:
                    pass
                try:
                    return _recognise(asked, turned), turned, flips
                except StructureError:
                    pass
    return recognise(table), table, None


def recognise(table: DHTable) -> ClosedFormStructure:
    """The structure of the table's arm: the first of :data:`CLOSED_FORMS` that fits.

    Structures read the DH values only, not the rows' ``direction``: give them
    :func:`.joint_directions.forward_table` of a table with reversed joints (their answers are
    then ``q' = direction * q``), as :class:`~.closed_form.ClosedFormSolver` does.

    Raises:
        StructureError: No closed-form structure fits (none fits a row tilted by Hayati's
            ``beta``); the message says what does not fit each one that has the table's number
            of joints.
    """
    refuse_tilts(table, "closed-form")  # every structure reads plain DH rows
    failures = []
    for structure in CLOSED_FORMS:
        if structure.dof != table.dof:
            continue
        try:
            return _recognise(structure, table)
        except StructureError as err:
            failures.append(err)
    if len(failures) == 1:
        raise failures[0]
    if failures:
        raise StructureError(table.name, "closed-form", "; ".join(err.mismatch for err in failures))
    counts = sorted({structure.dof for structure in CLOSED_FORMS})
    kinds = ", ".join(f"{s.dof}: {s.name}" for s in CLOSED_FORMS)
    raise StructureError(
        table.name,
        "closed-form",
        f"{table.dof} joints; closed-form solvers exist for "
        + ", ".join(str(c) for c in counts)
        + f" joints ({kinds})",
    )
