"""The registered closed-form structures, asked in turn whether a DH table fits.

Each entry is a class meeting :class:`~.closed_form_structure.ClosedFormStructure`. Several may
share a joint count: :func:`recognise` asks, in order, every structure of the table's joint
count and takes the first that fits. :func:`register` adds one (see
:mod:`.closed_form_structure` for what it must provide).
"""

from __future__ import annotations

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
from .six_r.spherical_wrist import SphericalWrist6R
from .six_r.three_parallel import ThreeParallel6R
from .six_r.ur_wrist import URWrist6R

#: The registered structures, in the order they are asked.
CLOSED_FORMS: list[type[ClosedFormStructure]] = [
    Planar2R,
    ParallelAxes2,  # every axis parallel: planar 2R read from any frame, RRP, planar 3R, SCARA
    Offset3R,
    ParallelAxes3,
    ParallelAxes,
    YawPlanar,  # base yaw, three parallel pitch joints
    YawPlanarRoll,  # base yaw, two parallel pitch joints, a roll (Kinova's 4-DOF arms)
    FiveDof,
    URWrist6R,
    SphericalWrist6R,
    Pieper6R,
    ThreeParallel6R,
    Reversed6R,  # the 6R families above, read from the tool
    General6R,  # last: any other 6R arm, by elimination
]


def register(structure: type[ClosedFormStructure], *, first: bool = False) -> None:
    """Add a structure to :data:`CLOSED_FORMS` (last, or ``first``); once only.

    Raises:
        TypeError: ``structure`` lacks a part of :class:`ClosedFormStructure`.
    """
    missing = [
        part
        for part in ("name", "dof", "target_kinds", "branch_labels", "recognise", "solve")
        + ("solve_batch",)
        if not hasattr(structure, part)
    ]
    if missing:
        raise TypeError(f"{structure.__name__} is not a closed-form structure: no {missing}")
    if structure in CLOSED_FORMS:
        return
    if first:
        CLOSED_FORMS.insert(0, structure)
    else:
        CLOSED_FORMS.append(structure)


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
    found = flipped_axes(table)
    if found is not None:
        turned, flips = found
        for structure in CLOSED_FORMS:
            if structure.dof != table.dof:
                continue
            try:
                return structure.recognise(table), table, None
            except StructureError:
                pass
            try:
                return structure.recognise(turned), turned, flips
            except StructureError:
                pass
    return recognise(table), table, None


def recognise(table: DHTable) -> ClosedFormStructure:
    """The structure of the table's arm: the first of :data:`CLOSED_FORMS` that fits.

    Structures read the DH values only, not the rows' ``direction``: give them
    :func:`.joint_directions.forward_table` of a table with reversed joints (their answers are
    then ``q' = direction * q``), as :class:`~.closed_form.ClosedFormSolver` does.

    Raises:
        StructureError: No closed-form structure fits; the message says what does not fit each
            one that has the table's number of joints.
    """
    failures = []
    for structure in CLOSED_FORMS:
        if structure.dof != table.dof:
            continue
        try:
            return structure.recognise(table)
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
