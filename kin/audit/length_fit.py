"""Refit one link length of a reading to the printed samples (a length printed one way, used another).

The tool position is affine in each DH length ``a_i`` or ``d_i`` (the rotations do not depend on
it), so the best value of one length, all else fixed, is a one-dimensional linear least-squares
problem: two batched FK evaluations (the length at 0 and at 1 m) give the line, the printed
positions give the value, written with the fewest decimals that reproduce as many samples (the
number a source would print), never more decimals than the table file's most precise length.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .audited_table import AuditedTable
from .changes import Change
from .printed import SampleScore, predicted_values, score_readings
from .readings import Reading, apply_changes, with_field
from .samples import SampleSet

#: Samples a refitted length must reproduce beyond the reading without it.
MIN_GAIN = 2


def _set_length(reading: Reading, row: int, field: str, value_m: float) -> Reading:
    rows = list(reading.table.rows)
    rows[row - 1] = with_field(rows[row - 1], field, value_m)
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
    ends = [_set_length(reading, row, field, value) for value in (0.0, 1.0)]
    at0, at1 = predicted_values(audited, samples, ends)[:, :, :3]
    slope = np.where(given, at1 - at0, 0.0)  # [file unit] per meter
    gap = np.where(given, printed - at0, 0.0)
    norm = float(np.sum(slope * slope))
    if norm < 1e-18:
        return []
    out = [float(np.sum(slope * gap) / norm)]
    strong = np.abs(slope) > 0.1 * np.abs(slope).max()
    out += [float(v) for v in (gap[strong] / slope[strong])]
    return out


def _places(value: float) -> int:
    """Fewest decimals that write ``value`` (at most 6)."""
    return next((k for k in range(7) if abs(round(value, k) - value) < 1e-9), 6)


def length_refits(
    audited: AuditedTable, samples: SampleSet, base: SampleScore
) -> list[SampleScore]:
    """The reading of ``base`` plus one refitted length, for every nonzero length of the table.

    A refitted length is written with no more decimals than the table file's most precise length
    (the precision its source prints), and kept only when it reproduces at least
    :data:`MIN_GAIN` more samples than ``base`` (one free number can always fit one sample).

    Returns:
        The scores of the kept readings (unsorted), at most one per length: the one with the
        most samples reproduced, then the fewest decimals.
    """
    reading = base.reading
    lengths = [v / audited.meters for r in audited.table.rows for v in (r.a, r.d)]
    decimals = range(max(_places(v) for v in lengths) + 1)
    candidates: list[Reading] = []
    meta: list[tuple[tuple[int, str], int]] = []  # (row, field), decimals of the value
    for row in reading.table.rows:
        for field in ("a", "d"):
            old = getattr(row, field) / audited.meters
            if old == 0.0 or (field == "d" and row.joint_type != "revolute"):
                continue
            options: dict[float, int] = {}
            for exact in length_candidates(audited, samples, reading, row.index, field):
                for k in reversed(decimals):
                    value = round(exact / audited.meters, k)
                    options[value] = min(k, options.get(value, k))
            for value, places in options.items():
                if f"{value:.6g}" == f"{old:.6g}":
                    continue
                change = Change(
                    "length",
                    row.index,
                    f"{field}={value * audited.meters!r}",
                    f"{field}{row.index}: {old:.6g} -> {value:.6g} {audited.length_unit}",
                    f"row {row.index}: {field} = {value:.6g}",
                )
                candidates.append(apply_changes(audited, (*reading.changes, change)))
                meta.append(((row.index, field), places))
    if not candidates:
        return []
    scores = score_readings(audited, samples, candidates)
    places_of = {id(r): m for r, m in zip(candidates, meta, strict=True)}
    best: dict[tuple[int, str], tuple[tuple, SampleScore]] = {}
    for score in scores:  # per length: the most samples, then the fewest decimals
        if score.count < base.count + MIN_GAIN:
            continue
        key, places = places_of[id(score.reading)]
        rank = (score.count, score.values_reproduced, -places)
        if key not in best or rank > best[key][0]:
            best[key] = (rank, score)
    return [score for _, score in best.values()]
