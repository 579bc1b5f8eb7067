"""A special 7R closed form near a general 7R arm: the candidates of :class:`.general_7r.General7RIK`.

Makers' URDFs round and drift: Kinova's Gen3 writes 1.5708 for pi/2 and puts its wrist axes
0.35 mm apart, so no special form fits it and each free-joint value costs a general 6R
elimination (:mod:`..six_r.general_6r`). Snapped (:func:`ideal_form`: the twists and tiny lengths
of :func:`~kin.ik.analytic.idealised.idealise`, then every length below :data:`IDEAL_LENGTH`),
the arm may be humanoid7's (:class:`~.seven_dof.SevenDofIK`, joint 1 free), whose branches at a
free value are closed form (and compiled: ``held_rows``, ``kin/_native/_held7.h``).
:class:`~.general_7r.General7RIK` then holds joint 1 and polishes each of those branches onto the
true arm with joint 1 fixed (Newton on the 6R left,
:func:`~kin.ik.analytic.six_r._general_6r_chain.polish`), as ssik's ``srs_polished`` does for such
arms; a value where the snapped arm is near a double root (within a margin proportional to the
deviation: a pair of branches the true arm has there may be missing) is solved by the 6R
elimination instead. It keeps this route only when it recovers the arm's sampled joint vectors
from their poses (:meth:`~.general_7r.General7RIK.__init__`); the tests hold its branches to the
elimination's at every value (tests/test_ik_ideal_7r.py). Lengths [m], angles [rad].
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from dh2urdf import DHTable
from kin.batch_fk import batch_forward_kinematics

from ...exceptions import StructureError
from ..idealised import FK_TOLERANCE, idealise
from ..structure import seven_dof
from .seven_dof import SevenDofIK

#: Largest ``|a|`` or ``|d|`` snapped to zero [m] (the tool then strays at most
#: :data:`~kin.ik.analytic.idealised.FK_TOLERANCE` over sampled joint vectors, or no form).
IDEAL_LENGTH = 1e-3
#: Sampled joint vectors of the tool's deviation check, and their seed.
SAMPLES = 256
SAMPLE_SEED = 0


def ideal_table(table: DHTable) -> tuple[DHTable, float] | None:
    """The table with its twists and lengths below :data:`IDEAL_LENGTH` snapped, and its deviation.

    The deviation [m]: the largest distance between the two tools over sampled joint vectors.
    None when nothing is snapped, or the deviation exceeds
    :data:`~kin.ik.analytic.idealised.FK_TOLERANCE`.
    """
    snapped = idealise(table)
    start = table if snapped is None else snapped.table
    rows = tuple(
        dataclasses.replace(
            row,
            a=0.0 if abs(row.a) < IDEAL_LENGTH else row.a,
            d=0.0 if row.joint_type == "revolute" and abs(row.d) < IDEAL_LENGTH else row.d,
        )
        for row in start.rows
    )
    if snapped is None and rows == table.rows:
        return None
    ideal = dataclasses.replace(start, rows=rows)
    rng = np.random.default_rng(SAMPLE_SEED)
    q = rng.uniform(np.maximum(table.lower, -np.pi), np.minimum(table.upper, np.pi),
                    (SAMPLES, table.dof))  # fmt: skip
    true = batch_forward_kinematics(table, q)[:, :3, 3]
    near = batch_forward_kinematics(ideal, q)[:, :3, 3]
    deviation = float(np.linalg.norm(true - near, axis=1).max())
    return (ideal, deviation) if deviation <= FK_TOLERANCE else None


def ideal_form(
    table: DHTable, lower: Sequence[float], upper: Sequence[float]
) -> tuple[SevenDofIK, float] | None:
    """humanoid7's form of the snapped table (:func:`ideal_table`) and its deviation [m], or None.

    Args:
        table: A forward 7R table (every direction 1) that no special form fits as it is.
        lower: Lower joint limits [rad] (7).
        upper: Upper joint limits [rad] (7).
    """
    if table.dof != 7 or any(row.joint_type != "revolute" for row in table.rows):
        return None
    snapped = ideal_table(table)
    if snapped is None:
        return None
    try:
        return SevenDofIK(seven_dof(snapped[0]), lower, upper), snapped[1]
    except StructureError:
        return None
