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
