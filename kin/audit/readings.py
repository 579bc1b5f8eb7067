"""Readings of a DH table: zero, one or two changes and the table variant they give.

:func:`apply_changes` builds the variant (SI values) and how the joint values (the samples', or a
reference URDF's) are read under it;
:func:`candidate_readings` lists the table as written, every single change of
:func:`kin.audit.changes.elementary_changes` and every pair, each variant once.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import numpy as np

from dh2urdf import DHRow, DHTable
from dh2urdf.units import ANGLE_UNITS, LENGTH_UNITS

from .audited_table import AuditedTable
from .changes import Change, elementary_changes


def with_field(row: DHRow, field: str, value: float) -> DHRow:
    """``row`` with one of its DH values (``a``, ``alpha``, ``d``, ``theta``) replaced."""
    if field == "a":
        return dataclasses.replace(row, a=value)
    if field == "alpha":
        return dataclasses.replace(row, alpha=value)
    if field == "d":
        return dataclasses.replace(row, d=value)
    if field == "theta":
        return dataclasses.replace(row, theta=value)
    raise ValueError(f"not a DH value: {field!r}")


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
    joint_signs: tuple[float, ...] = ()

    @property
    def signs(self) -> np.ndarray:
        """Per joint, +1, or -1 where the source's joint turns (or slides) the other way."""
        return np.array(self.joint_signs or (1.0,) * self.table.dof)

    @property
    def label(self) -> str:
        """The changes in one line, or ``"table as written"``."""
        return "; ".join(c.text for c in self.changes) or "table as written"


def apply_changes(audited: AuditedTable, changes: tuple[Change, ...]) -> Reading:
    """The reading that ``changes`` give (applied in order to the table as written)."""
    table = audited.table
    rows = list(table.rows)
    convention = table.convention
    base, tool = np.array(table.T_world_base), np.array(table.T_last_tool)
    angle_unit, length_unit, truncated = audited.angle_unit, audited.length_unit, False
    signs = [1.0] * table.dof
    for change in changes:
        i = (change.row or 0) - 1
        if change.kind == "convention":
            convention = "standard" if convention == "modified" else "modified"
        elif change.kind == "offsets":  # the values are the DH angles (lengths) themselves
            rows = [
                dataclasses.replace(
                    with_field(r, "theta" if r.joint_type == "revolute" else "d", 0.0),
                    direction=1,
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
        elif change.kind == "table_angle_unit":
            k = ANGLE_UNITS[str(change.value)] / audited.radians
            rows = [
                dataclasses.replace(r, alpha=r.alpha * k, theta=r.theta * k, beta=r.beta * k)
                for r in rows
            ]
        elif change.kind == "theta_shift":
            rows[i] = with_field(rows[i], "theta", float(str(change.value)))
        elif change.kind == "joint_sign":
            signs[i] = -signs[i]
        elif change.kind == "twist_all":
            rows = [dataclasses.replace(r, alpha=-r.alpha) for r in rows]
        elif change.kind == "truncated":
            truncated = True
        elif change.kind == "length":
            name, value = str(change.value).split("=")
            rows[i] = with_field(rows[i], name, float(value))
        else:
            field = {"twist": "alpha", "d_sign": "d", "a_sign": "a", "theta_sign": "theta"}
            name = field[change.kind]
            rows[i] = with_field(rows[i], name, -getattr(rows[i], name))
    variant = dataclasses.replace(
        table,
        convention=convention,
        rows=tuple(rows),
        T_world_base=base,
        T_last_tool=tool,
    )
    return Reading(changes, variant, angle_unit, length_unit, truncated, tuple(signs))


def _signature(reading: Reading) -> tuple:
    t = reading.table
    params = tuple((r.a, r.alpha, r.d, r.theta, r.direction, r.beta) for r in t.rows)
    return (
        t.convention,
        params,
        t.T_world_base.tobytes(),
        t.T_last_tool.tobytes(),
        reading.sample_angle_unit,
        reading.sample_length_unit,
        reading.truncated,
        reading.joint_signs,
    )


def _same_scale(x: Change, y: Change) -> bool:
    """Table and samples both read in the same other length unit: the table as written again."""
    kinds = {x.kind, y.kind}
    return kinds == {"length_unit", "sample_length_unit"} and x.value == y.value


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
            if (x.kind != y.kind or x.row is not None) and not _same_scale(x, y)
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
