"""Readings of a DH table: the table as written, and the plausible ways its source may differ.

A :class:`Change` is one elementary difference between the table as written and what its source
may have computed with: the other DH convention, joint offsets not applied (the printed joint
values are DH angles), one twist sign flipped (or all of them), the sign of a length or of an
offset flipped, the table's lengths in another unit, the samples' angles in the other unit, the
printed values truncated rather than rounded. A :class:`Reading` is zero, one or two changes and
the table variant they give; :func:`candidate_readings` lists them all, each variant once.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from dh2urdf import DHTable
from dh2urdf.units import ANGLE_UNITS, LENGTH_UNITS

from .audited_table import AuditedTable

ChangeKind = Literal[
    "convention",
    "offsets",
    "angle_unit",
    "length_unit",
    "sample_length_unit",
    "twist_all",
    "twist",
    "d_sign",
    "a_sign",
    "theta_sign",
    "truncated",
    "length",
]

#: Changes that only concern how the samples are read (not the table, not a URDF comparison).
SAMPLE_KINDS: frozenset[str] = frozenset({"angle_unit", "sample_length_unit", "truncated"})


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


@dataclass(frozen=True, eq=False)
class Reading:
    """A way of computing the samples: the changes and the table variant they give.

    Attributes:
        changes: The changes from the table as written (empty: the table as written).
        table: The table variant (SI values).
        sample_angle_unit: Unit the samples' angles (joint values, roll-pitch-yaw) are read in.
        sample_length_unit: Unit the samples' lengths (positions, prismatic joint values) are
            read in.
        truncated: The source truncates its printed values instead of rounding them.
    """

    changes: tuple[Change, ...]
    table: DHTable
    sample_angle_unit: str
    sample_length_unit: str
    truncated: bool

    @property
    def label(self) -> str:
        """The changes in one line, or ``"table as written"``."""
        return "; ".join(c.text for c in self.changes) or "table as written"


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
        out.append(
            Change(
                "offsets",
                None,
                None,
                "offsets: applied -> not applied (joint values are DH angles)",
                f"read the joint values as DH angles, q = value - offset (rows {rows});"
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
    if len(twists) > 1:
        out.append(
            Change(
                "twist_all",
                None,
                None,
                "every twist sign flipped",
                "alpha = -alpha in rows " + ", ".join(str(r.index) for r in twists),
            )
        )
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
    for kind, field, unit, scale in (
        ("d_sign", "d", lu, audited.meters),
        ("a_sign", "a", lu, audited.meters),
        ("theta_sign", "theta", au, audited.radians),
    ):
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


def apply_changes(audited: AuditedTable, changes: tuple[Change, ...]) -> Reading:
    """The reading that ``changes`` give (applied in order to the table as written)."""
    table = audited.table
    rows = list(table.rows)
    convention = table.convention
    base, tool = np.array(table.T_world_base), np.array(table.T_last_tool)
    angle_unit, length_unit, truncated = audited.angle_unit, audited.length_unit, False
    for change in changes:
        i = (change.row or 0) - 1
        if change.kind == "convention":
            convention = "standard" if convention == "modified" else "modified"
        elif change.kind == "offsets":
            rows = [
                dataclasses.replace(
                    r, **({"theta": 0.0} if r.joint_type == "revolute" else {"d": 0.0})
                )
                for r in rows
            ]
        elif change.kind == "angle_unit":
            angle_unit = str(change.value)
        elif change.kind == "sample_length_unit":
            length_unit = str(change.value)
        elif change.kind == "length_unit":
            k = LENGTH_UNITS[str(change.value)] / audited.meters
            rows = [dataclasses.replace(r, a=r.a * k, d=r.d * k) for r in rows]
            base[:3, 3] *= k
            tool[:3, 3] *= k
        elif change.kind == "twist_all":
            rows = [dataclasses.replace(r, alpha=-r.alpha) for r in rows]
        elif change.kind == "truncated":
            truncated = True
        elif change.kind == "length":
            name, value = str(change.value).split("=")
            rows[i] = dataclasses.replace(rows[i], **{name: float(value)})
        else:
            field = {"twist": "alpha", "d_sign": "d", "a_sign": "a", "theta_sign": "theta"}
            name = field[change.kind]
            rows[i] = dataclasses.replace(rows[i], **{name: -getattr(rows[i], name)})
    variant = dataclasses.replace(
        table,
        convention=convention,
        rows=tuple(rows),
        T_world_base=base,
        T_last_tool=tool,
    )
    return Reading(changes, variant, angle_unit, length_unit, truncated)


def _signature(reading: Reading) -> tuple:
    t = reading.table
    params = tuple((r.a, r.alpha, r.d, r.theta) for r in t.rows)
    return (
        t.convention,
        params,
        t.T_world_base.tobytes(),
        t.T_last_tool.tobytes(),
        reading.sample_angle_unit,
        reading.sample_length_unit,
        reading.truncated,
    )


def candidate_readings(
    audited: AuditedTable, *, samples: bool = True, pairs: bool = True
) -> list[Reading]:
    """The table as written, every single change, and every pair of changes; each variant once.

    Args:
        audited: The table under audit.
        samples: Include the changes to the reading of printed samples (angle unit, truncation).
        pairs: Include the combinations of two changes.

    Returns:
        Readings in order of generation: as written, singles, pairs. A variant reached by several
        sets of changes is kept under the first (fewest changes).
    """
    singles = elementary_changes(audited, samples=samples)
    sets: list[tuple[Change, ...]] = [(), *((c,) for c in singles)]
    if pairs:
        sets += [
            (x, y)
            for x, y in itertools.combinations(singles, 2)
            if x.kind != y.kind or x.row is not None
        ]
    seen: set[tuple] = set()
    out = []
    for changes in sets:
        reading = apply_changes(audited, changes)
        key = _signature(reading)
        if key not in seen:
            seen.add(key)
            out.append(reading)
    return out


def sample_radians(reading: Reading) -> float:
    """Radians per unit of the samples' angles under ``reading``."""
    return ANGLE_UNITS[reading.sample_angle_unit]


def sample_meters(reading: Reading) -> float:
    """Meters per unit of the samples' lengths under ``reading``."""
    return LENGTH_UNITS[reading.sample_length_unit]
