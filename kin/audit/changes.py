"""Elementary changes of a DH table: the ways a source may differ from the table as written.

Each :class:`Change` is one difference between the table as written and what its source may
have computed with: the other DH convention; joint offsets not applied (the printed joint values
are DH angles); one offset not applied, or a joint zero a quarter turn away; one joint moving the other way; one twist sign
flipped, or all of them; the sign of a length or of an offset flipped; the table's lengths or
angles in another unit; the samples' lengths or angles in another unit; the printed values
truncated rather than rounded; or (:mod:`kin.audit.length_fit`) one link length refitted. Each
says what changes, in the file's units, and the edit it implies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from dh2urdf.units import LENGTH_UNITS

from .audited_table import AuditedTable

ChangeKind = Literal[
    "convention",
    "offsets",
    "angle_unit",
    "length_unit",
    "table_angle_unit",
    "sample_length_unit",
    "twist_all",
    "twist",
    "d_sign",
    "a_sign",
    "theta_sign",
    "theta_shift",
    "joint_sign",
    "truncated",
    "length",
]


@dataclass(frozen=True)
class Change:
    """One elementary difference from the table as written.

    Attributes:
        kind: What changes (see :data:`ChangeKind`).
        row: 1-based table row it concerns, or None.
        value: The new unit name for the unit kinds; for ``length``,
            ``"a=<meters>"`` or ``"d=<meters>"`` (a refitted length); else None.
        text: What changes, in the file's units (``"alpha1: -90 -> 90 deg"``).
        edit: The edit of the table file (or of the reading of the samples) it implies.
    """

    kind: ChangeKind
    row: int | None
    value: str | None
    text: str
    edit: str


def _num(value: float) -> str:
    return f"{value:.6g}"


def elementary_changes(audited: AuditedTable, *, samples: bool = True) -> list[Change]:
    """The single changes that apply to ``audited`` (those that alter something).

    Args:
        audited: The table under audit.
        samples: Include the changes to the reading of printed samples (angle unit, truncation).
    """
    table, lu, au = audited.table, audited.length_unit, audited.angle_unit
    other = "standard" if table.convention == "modified" else "modified"
    out = [
        Change(
            "convention",
            None,
            None,
            f"convention: {table.convention} -> {other}",
            f'convention = "{other}"',
        )
    ]
    offset_rows = [
        r.index for r in table.rows if (r.theta if r.joint_type == "revolute" else r.d) != 0.0
    ]
    if offset_rows:
        rows = ", ".join(str(i) for i in offset_rows)
        types = {table.rows[i - 1].joint_type for i in offset_rows}
        values = " and ".join(
            n for t, n in (("revolute", "angles"), ("prismatic", "lengths")) if t in types
        )
        out.append(
            Change(
                "offsets",
                None,
                None,
                f"offsets: applied -> not applied (joint values are DH {values})",
                f"read the joint values as DH {values}, q = value - offset (rows {rows});"
                " or set the offsets of rows " + rows + " to 0",
            )
        )
    if samples:
        other_angle = "rad" if au == "deg" else "deg"
        out.append(
            Change(
                "angle_unit",
                None,
                other_angle,
                f"joint angle unit: {au} -> {other_angle}",
                f"the samples' angles are in {other_angle}",
            )
        )
    for unit in sorted(LENGTH_UNITS):
        if unit != lu:
            out.append(
                Change(
                    "length_unit",
                    None,
                    unit,
                    f"length unit of the table: {lu} -> {unit}",
                    f'length_unit = "{unit}" (the samples stay in {lu})',
                )
            )
    other_table_angle = "rad" if au == "deg" else "deg"
    out.append(
        Change(
            "table_angle_unit",
            None,
            other_table_angle,
            f"angle unit of the table: {au} -> {other_table_angle}",
            f'angle_unit = "{other_table_angle}" for alpha and theta (the samples stay in {au})',
        )
    )
    if samples:
        for unit in sorted(LENGTH_UNITS):
            if unit != lu:
                out.append(
                    Change(
                        "sample_length_unit",
                        None,
                        unit,
                        f"length unit of the samples: {lu} -> {unit}",
                        f"the samples' lengths are in {unit} (no table edit)",
                    )
                )
    twists = [r for r in table.rows if abs(math.sin(r.alpha)) > 1e-12]
    for r in twists:
        old = r.alpha / audited.radians
        out.append(
            Change(
                "twist",
                r.index,
                None,
                f"alpha{r.index}: {_num(old)} -> {_num(-old)} {au}",
                f"row {r.index}: alpha = {_num(-old)}",
            )
        )
    if len(twists) > 1:  # after the rows: a pair of rows reads better than all-but-one
        out.append(
            Change(
                "twist_all",
                None,
                None,
                "every twist sign flipped",
                "alpha = -alpha in rows " + ", ".join(str(r.index) for r in twists),
            )
        )
    signs: tuple[tuple[ChangeKind, str, str, float], ...] = (
        ("d_sign", "d", lu, audited.meters),
        ("a_sign", "a", lu, audited.meters),
        ("theta_sign", "theta", au, audited.radians),
    )
    for kind, field, unit, scale in signs:
        for r in table.rows:
            old = getattr(r, field) / scale
            if old != 0.0:
                out.append(
                    Change(
                        kind,
                        r.index,
                        None,
                        f"{field}{r.index}: {_num(old)} -> {_num(-old)} {unit}",
                        f"row {r.index}: {field} = {_num(-old)}",
                    )
                )
    for r in table.rows:  # one offset not applied, or a joint zero a quarter turn away
        if r.joint_type != "revolute":
            continue
        old = r.theta / audited.radians
        quarter = math.pi / 2 / audited.radians
        for new in ([0.0] if old != 0.0 else []) + [old + quarter, old - quarter]:
            out.append(
                Change(
                    "theta_shift",
                    r.index,
                    repr(new * audited.radians),
                    f"theta{r.index}: {_num(old)} -> {_num(new)} {au}",
                    f"row {r.index}: theta = {_num(new)}",
                )
            )
    for r in table.rows:
        out.append(
            Change(
                "joint_sign",
                r.index,
                None,
                f"q{r.index}: reversed (the source's joint {r.index} moves the other way)",
                f"write direction = {-r.direction} on row {r.index}",
            )
        )
    if samples:
        out.append(
            Change(
                "truncated",
                None,
                None,
                "printed values: rounded -> truncated",
                "the source truncates its printed digits (no table edit)",
            )
        )
    return out
