"""Reversed joints (``direction = -1`` rows) for the closed forms: the equivalent forward table.

A row with ``direction = -1`` has the DH angle ``theta - q`` (length ``d - q``). The same arm
with that row's direction set to 1 and its variable ``q' = -q`` is the same chain: the closed-form
structures (:mod:`.registry`), which read the DH values only, solve the forward table in ``q'``,
and the solvers map the seeds in (``q' = direction * q``) and the answers out
(``q = direction * q'``, :func:`to_joint`) before the judge measures them on the true arm.
``direction`` being +-1, the two maps are the same product.

The limits of a reversed row mirror: ``q`` in ``[lower, upper]`` is ``q'`` in
``[-upper, -lower]``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable


def reversed_joints(table: DHTable) -> np.ndarray | None:
    """The table's directions (dof,) [1] when a row is reversed, else None (nothing to map)."""
    if all(row.direction == 1 for row in table.rows):
        return None
    return table.directions


def forward_table(table: DHTable) -> DHTable:
    """The same arm with every direction 1: reversed rows get ``q' = -q`` and mirrored limits.

    Args:
        table: A DH table (SI units); returned as is when no row is reversed.

    Returns:
        The table whose FK at ``q'`` is ``table``'s at ``q = direction * q'``; the limits of a
        reversed row are ``[-upper, -lower]`` [rad] or [m].
    """
    if reversed_joints(table) is None:
        return table
    rows = tuple(
        row
        if row.direction == 1
        else dataclasses.replace(row, direction=1, lower=-row.upper, upper=-row.lower)
        for row in table.rows
    )
    return dataclasses.replace(table, rows=rows)


#: A twist this close to +-pi [rad] is turned to 0 by :func:`flipped_axes` (the tables' own
#: rounding of pi; a URDF that rounds pi to 3.1416 is the idealised table's business).
ANTIPARALLEL_TOLERANCE = 1e-9


def flipped_axes(table: DHTable) -> tuple[DHTable, np.ndarray] | None:
    """The same arm with every twist of +-pi made 0 by turning the next joint's axis over.

    DH leaves each z axis's sense free: an arm whose consecutive axes are antiparallel (a twist
    of pi, as a URDF extraction writes axes along their URDF directions) is the arm whose later
    axis points the other way, with a twist of 0, that joint reversed (``q' = -q``, mirrored
    limits) and the rest of the chain unchanged. Structures written for parallel axes (twist 0)
    then fit it: Kinova's arms extracted from their URDF get the spherical-wrist family.

    Standard DH: row ``i``'s ``Rx(pi)`` moves through row ``i + 1`` (``theta, d -> -theta, -d``,
    its twist plus pi); modified DH: through row ``i``'s own joint (``theta, d -> -theta, -d``),
    row ``i + 1``'s twist plus pi. At the chain's end it goes into the tool transform.

    Args:
        table: A table whose rows all have direction 1 (:func:`forward_table`), SI units.

    Returns:
        ``(table', flips)``: the table whose FK at ``q' = flips * q`` is ``table``'s at ``q``,
        flips (dof,) of +-1; None when no twist is within :data:`ANTIPARALLEL_TOLERANCE` of pi.
    """
    rows = list(table.rows)
    flips = np.ones(len(rows))
    tool = np.array(table.T_last_tool, dtype=float)
    standard = table.convention == "standard"
    changed = False
    for i, row in enumerate(rows):
        if abs(abs(row.alpha) - math.pi) > ANTIPARALLEL_TOLERANCE:
            continue
        changed = True
        rows[i] = dataclasses.replace(row, alpha=0.0)
        turned = i + 1 if standard else i  # the joint whose axis turns over
        if turned < len(rows):
            joint = rows[turned]
            rows[turned] = dataclasses.replace(
                joint, theta=-joint.theta, d=-joint.d, lower=-joint.upper, upper=-joint.lower
            )
            flips[turned] *= -1.0
        following = i + 1  # the next twist (standard: the turned row's own) gains pi
        if following < len(rows):
            rows[following] = dataclasses.replace(
                rows[following], alpha=math.remainder(rows[following].alpha + math.pi, 2 * math.pi)
            )
        else:  # the tool frame, seen from the turned last frame
            tool = _RX_PI @ tool
    if not changed:
        return None
    return dataclasses.replace(table, rows=tuple(rows), T_last_tool=tool), flips


#: A half turn about x (4x4).
_RX_PI = np.diag([1.0, -1.0, -1.0, 1.0])


def mirrored_limits(
    lower: npt.ArrayLike, upper: npt.ArrayLike, directions: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The limits of ``q' = direction * q`` given those of ``q`` (each (dof,) [rad] or [m])."""
    low, high = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    return np.where(directions > 0, low, -high), np.where(directions > 0, high, -low)


def to_joint(q: npt.ArrayLike, directions: np.ndarray) -> np.ndarray:
    """The arm's joint values ``q = direction * q'`` of the forward table's ``q'`` (..., dof).

    Also the other way (``q' = direction * q``): the map is its own inverse.
    """
    return np.asarray(q, dtype=float) * directions
