"""Refit one link length of a reading to the printed samples (a length printed one way, used another).

The tool position is affine in each DH length ``a_i`` or ``d_i`` (the rotations do not depend on
it), so the best value of one length, all else fixed, is a one-dimensional linear least-squares
problem: two batched FK evaluations (the length at 0 and at 1 m) give the line, the printed
positions give the value. The value is then written with the fewest decimals (of the table's
length unit) that reproduce as many samples as the exact one: the number a source would print.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .audited_table import AuditedTable
from .printed import SampleScore, predicted_values, score_readings
from .readings import Change, Reading, apply_changes
from .samples import SampleSet

#: Decimals (in the table's length unit) tried for a refitted length.
DECIMALS = (0, 1, 2, 3, 4)


def _set_length(reading: Reading, row: int, field: str, value_m: float) -> Reading:
    rows = list(reading.table.rows)
    rows[row - 1] = dataclasses.replace(rows[row - 1], **{field: value_m})
    table = dataclasses.replace(reading.table, rows=tuple(rows))
    return dataclasses.replace(reading, table=table)


def length_candidates(
    audited: AuditedTable, samples: SampleSet, reading: Reading, row: int, field: str
) -> list[float]:
    """Values [m] of length ``field`` (``"a"`` or ``"d"``) of ``row`` (1-based) worth trying.

    The least-squares value over all printed coordinates, and the value each printed coordinate
    alone asks for (a source may mix two lengths, one per column or per case: the consensus of
    the single-coordinate values finds each, where the mean of all would find neither).
    """
    printed = samples.values[:, :3]
    given = ~np.isnan(printed)
    at0 = predicted_values(audited, samples, _set_length(reading, row, field, 0.0))[:, :3]
    at1 = predicted_values(audited, samples, _set_length(reading, row, field, 1.0))[:, :3]
    slope = np.where(given, at1 - at0, 0.0)  # [file unit] per meter
    gap = np.where(given, printed - at0, 0.0)
    norm = float(np.sum(slope * slope))
    if norm < 1e-18:
        return []
    out = [float(np.sum(slope * gap) / norm)]
    strong = np.abs(slope) > 0.1 * np.abs(slope).max()
    out += [float(v) for v in (gap[strong] / slope[strong])]
    return out


def length_refits(audited: AuditedTable, samples: SampleSet, reading: Reading) -> list[SampleScore]:
    """Readings of ``reading`` plus one refitted length, for every nonzero length of the table.

    Returns:
        The scores of the refitted readings (unsorted); each adds a ``length`` change whose
        value has the fewest decimals that reproduce as many samples as the exact value.
    """
    candidates: list[Reading] = []
    meta: list[tuple[tuple[int, str], int]] = []  # (row, field), decimals of the value
    for original in audited.table.rows:
        for field in ("a", "d"):
            if getattr(original, field) == 0.0:
                continue
            if field == "d" and original.joint_type != "revolute":
                continue
            old = getattr(original, field) / audited.meters
            options: dict[float, int] = {}
            for exact in length_candidates(audited, samples, reading, original.index, field):
                for k in reversed(DECIMALS):
                    value = round(exact / audited.meters, k)
                    options[value] = min(k, options.get(value, k))
            for value, places in options.items():
                if abs(value - old) < 1e-12:
                    continue
                change = Change(
                    "length",
                    original.index,
                    f"{field}={value * audited.meters!r}",
                    f"{field}{original.index}: {old:.6g} -> {value:.6g} {audited.length_unit}",
                    f"row {original.index}: {field} = {value:.6g}",
                )
                candidates.append(apply_changes(audited, (*reading.changes, change)))
                meta.append(((original.index, field), places))
    if not candidates:
        return []
    scores = score_readings(audited, samples, candidates)
    places_of = {id(r): m for r, m in zip(candidates, meta, strict=True)}
    best: dict[tuple[int, str], tuple[tuple, SampleScore]] = {}
    for score in scores:  # per length: the fewest decimals among the best counts
        key, places = places_of[id(score.reading)]
        rank = (score.count, score.values_reproduced, -places)
        if key not in best or rank > best[key][0]:
            best[key] = (rank, score)
    return [score for _, score in best.values()]
