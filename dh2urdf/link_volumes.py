"""The volumes of a DH table's links: radii of its segments and housing cylinders.

A row's body, in the URDF the writer emits (collision and visual alike):

- its ``d`` segment (along the joint axis) and its ``a`` segment (along the common normal) are
  cylinders of radius ``radius_d`` / ``radius_a``, else ``radius``. A segment whose radius the
  row states is a capsule: a sphere of its radius closes each end where it meets the next
  segment (the joint), but the chain's free ends (at the base and the tool), which stay flat. A
  segment without one is a plain cylinder of :data:`DEFAULT_RADIUS`, a stick to see the chain
  by (the URDF of such a table is the one earlier versions wrote);
- each ``[[joints.housing]]`` of the row is a flat-ended cylinder between two points ``from`` and
  ``to`` of DH frame ``i`` (the frame the row ends in, which moves with joint ``i``), of its
  ``radius``: a motor housing around the joint axis, or a tube offset from the DH lines;
- each ``[[joints.allow_contact]]`` of row ``i`` names an earlier ``row`` whose body row ``i``'s
  body is not checked against, with its ``reason`` (as an SRDF's ``<disable_collisions>``):
  ``kin.collision`` skips every link pair carried by the two joints (reason ``"table: <reason>"``).
  For a pair the volumes cannot keep apart where the real arm's bodies never meet, or that the
  maker's SRDF disables (the shipped Panda's forearm and hand flange overlap at the maker's
  default posture).

Table syntax (lengths in the table's ``length_unit``)::

    [[joints]]
    ...
    radius = 0.06                  # both segments; or radius_a = ..., radius_d = ...
    [[joints.housing]]             # optional, any number
    from = [0.0, 0.0, -0.07]
    to = [0.0, 0.0, 0.07]
    radius = 0.065
    [[joints.allow_contact]]       # optional, any number
    row = 3                        # an earlier row
    reason = "the maker's SRDF: Never"
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .dh_table import AllowedContact, DHRow, DHTable, Housing
from .exceptions import TableError
from .quoted_input import quoted
from .table_values import MAX_LENGTH
from .table_values import length as _length
from .table_values import positive as _positive

#: Radius of a segment whose row states none [m]: a stick to see the chain by, not the arm's
#: body (``kin check`` says so when a table relies on it).
DEFAULT_RADIUS = 0.01

#: The row keys read here.
VOLUME_KEYS = ("allow_contact", "housing", "radius", "radius_a", "radius_d")


def parse_volumes(path: str, data: dict[str, Any], index: int, meters: float) -> dict[str, Any]:
    """The row's ``radius``, ``radius_a``, ``radius_d`` [m] (or None), housings, allowed contacts.

    Args:
        path: The table file, for errors.
        data: The row's fields as read from TOML.
        index: The row number (1-based), for errors.
        meters: Meters per length unit of the table.

    Raises:
        TableError: A radius not positive or above ``MAX_LENGTH``, a malformed housing, an
            ``allow_contact`` not naming an earlier row or without a reason.
    """
    out: dict[str, Any] = {}
    for key in ("radius", "radius_a", "radius_d"):
        value = data.get(key)
        out[key] = None if value is None else _positive(path, value, index, key, meters, MAX_LENGTH)
    entries = data.get("housing", [])
    if not isinstance(entries, list):
        raise TableError(
            path, f"expected [[joints.housing]] tables, got {quoted(entries)}", index, "housing"
        )
    out["housings"] = tuple(
        _housing(path, entry, index, f"housing[{n}]", meters) for n, entry in enumerate(entries)
    )
    contacts = data.get("allow_contact", [])
    if not isinstance(contacts, list):
        raise TableError(
            path,
            f"expected [[joints.allow_contact]] tables, got {quoted(contacts)}",
            index,
            "allow_contact",
        )
    out["allowed_contacts"] = tuple(
        _allowed(path, entry, index, f"allow_contact[{n}]") for n, entry in enumerate(contacts)
    )
    return out


def _allowed(path: str, entry: Any, index: int, key: str) -> AllowedContact:
    if not isinstance(entry, dict) or set(entry) != {"row", "reason"}:
        raise TableError(
            path, f"expected a table of row and reason, got {quoted(entry)}", index, key
        )
    row, reason = entry["row"], entry["reason"]
    if isinstance(row, bool) or not isinstance(row, int) or not 1 <= row < index:
        raise TableError(
            path,
            f"expected an earlier row, 1 to {index - 1}, got {quoted(row)}",
            index,
            f"{key}.row",
        )
    if not isinstance(reason, str) or not reason.strip() or "\n" in reason:
        raise TableError(
            path, f"expected a one-line reason, got {quoted(reason)}", index, f"{key}.reason"
        )
    return AllowedContact(row, reason.strip())


def _housing(path: str, entry: Any, index: int, key: str, meters: float) -> Housing:
    if not isinstance(entry, dict) or set(entry) != {"from", "to", "radius"}:
        raise TableError(
            path,
            f"expected a table of from = [x, y, z], to = [x, y, z] and radius, got {quoted(entry)}",
            index,
            key,
        )
    ends = []
    for side in ("from", "to"):
        point = entry[side]
        if not isinstance(point, list) or len(point) != 3:
            raise TableError(
                path, f"expected [x, y, z], got {quoted(point)}", index, f"{key}.{side}"
            )
        ends.append(tuple(_length(path, v, index, f"{key}.{side}", meters) for v in point))
    radius = _positive(path, entry["radius"], index, f"{key}.radius", meters, MAX_LENGTH)
    if np.linalg.norm(np.subtract(ends[1], ends[0])) <= 1e-9:
        raise TableError(path, "from and to are the same point: give the axis", index, key)
    return Housing(ends[0], ends[1], radius)  # type: ignore[arg-type]


def segment_radii(row: DHRow) -> tuple[float, float]:
    """The radii [m] of the row's ``a`` and ``d`` segments (stated or :data:`DEFAULT_RADIUS`)."""
    fallback = row.radius if row.radius is not None else DEFAULT_RADIUS
    radius_a = row.radius_a if row.radius_a is not None else fallback
    radius_d = row.radius_d if row.radius_d is not None else fallback
    return radius_a, radius_d


def default_radius_rows(table: DHTable) -> tuple[int, ...]:
    """The rows (1-based) with a segment of nonzero length whose radius the table leaves out.

    A row with housings or a collision mesh (:mod:`dh2urdf.link_meshes`) states its body: its
    segments' default radius is then no claim.
    """
    rows = []
    for row in table.rows:
        if row.housings or any(mesh.collision for mesh in row.meshes):
            continue
        stated_a = row.radius_a is not None or row.radius is not None
        stated_d = row.radius_d is not None or row.radius is not None
        if (row.a != 0.0 and not stated_a) or (row.d != 0.0 and not stated_d):
            rows.append(row.index)
    return tuple(rows)


def default_radius_note(table: DHTable) -> str | None:
    """One line saying the table's links are default sticks, or None when it states its radii."""
    rows = default_radius_rows(table)
    if not rows:
        return None
    drawn = [row for row in table.rows if row.a != 0.0 or row.d != 0.0]
    which = f"{table.name}'s" if len(rows) == len(drawn) else f"some of {table.name}'s"
    return (
        f"note: {which} links are default {DEFAULT_RADIUS * 100:g} cm sticks, not the arm's "
        f"body (no radius in rows {', '.join(map(str, rows))} of its table: add radius, "
        "radius_a, radius_d, [[joints.housing]] or [[joints.mesh]] to a row)"
    )
