"""Units a DH table file probably got wrong: degrees in a radian table, millimeters in meters.

:func:`warn_units` gives one :class:`~dh2urdf.exceptions.UnitWarning` per suspicion, naming the
file and field and the line to write instead; the thresholds (:data:`RADIAN_SUSPECT`,
:data:`LIMIT_SUSPECT`, :data:`LENGTH_SUSPECT`) serve the scenes and the joint values on the
command line too. Angles [rad], lengths [m].
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from .dh_table import DHRow
from .exceptions import UnitWarning

__all__ = ["LENGTH_SUSPECT", "LIMIT_SUSPECT", "RADIAN_SUSPECT", "warn_units"]


#: An angle above this in a table said to be in radians is probably in degrees [rad].
RADIAN_SUSPECT = 2 * math.pi + 1e-9
#: A revolute limit above this (four turns) in a radian table is probably in degrees [rad]:
#: real multi-turn joints stop within two turns (ABB and FANUC joint 6: +-400 to 450 deg).
LIMIT_SUSPECT = 8 * math.pi + 1e-9
#: An arm longer than this (its lengths laid end to end) is probably not in meters [m].
LENGTH_SUSPECT = 20.0


def _fixed_angles(data: dict[str, Any]) -> list[tuple[str, float]]:
    """The angles of ``[base]`` and ``[tool]`` as written (rpy, or a DH-style alpha/theta)."""
    angles = []
    for key in ("base", "tool"):
        section = data.get(key)
        if isinstance(section, dict):
            angles += [(f"{key}.rpy", float(v)) for v in section.get("rpy", [])]
            angles += [
                (f"{key}.{k}", float(section[k])) for k in ("alpha", "theta") if k in section
            ]
    return angles


def _tool_extent(
    rows: tuple[DHRow, ...], convention: str, base: np.ndarray, tool: np.ndarray
) -> float:
    """The tool's largest distance from the world origin [m] over a few joint vectors.

    ``q = 0``, the lower and the upper limits, and eight seeded vectors inside the limits
    (revolute ones within a turn of the lower limit). Where the lengths laid end to end are long only because two
    nearly parallel axes put their common normal far away (a URDF that rounds pi to 3.1416:
    ``d`` of tens of km, out and back), the tool stays near: no unit slip there.
    """
    lower = np.array([row.lower for row in rows], dtype=float)
    upper = np.array([row.upper for row in rows], dtype=float)
    revolute = np.array([row.joint_type == "revolute" for row in rows])
    high = np.where(revolute, np.minimum(upper, lower + 2.0 * math.pi), upper)
    samples = [np.zeros(len(rows)), lower, upper]
    samples += list(
        np.random.default_rng(0).uniform(lower, np.maximum(high, lower), (8, len(rows)))
    )
    extent = 0.0
    with np.errstate(all="ignore"):  # extreme tables: an overflow is an infinite extent
        for q in samples:
            pose = base
            for row, value in zip(rows, q.tolist()):
                pose = pose @ row.transform(convention, value)  # type: ignore[arg-type]
            distance = float(np.linalg.norm((pose @ tool)[:3, 3]))
            extent = max(extent, distance) if math.isfinite(distance) else math.inf
    return extent


def warn_units(
    path: str,
    rows: tuple[DHRow, ...],
    data: dict[str, Any],
    base: np.ndarray,
    tool: np.ndarray,
) -> None:
    """One :class:`UnitWarning` per suspicious unit: degrees in a radian table, a giant arm.

    Angles beyond a turn: alpha, theta and beta of every row, the rpy or alpha/theta of ``[base]``
    and ``[tool]``; beyond four turns: revolute limits (multi-turn joints are real; prismatic
    limits are lengths). Length: every ``|a| + |d|``, the largest
    prismatic travel and the base and tool offsets, laid end to end.
    """
    if data["angle_unit"] == "rad":
        angles: list[tuple[str, float, float, str]] = []
        turn, turns = (RADIAN_SUSPECT, "a turn"), (LIMIT_SUSPECT, "four turns")
        for row in rows:
            where = f"{path}, joint row {row.index}, field"
            written = data["joints"][row.index - 1]  # as written: the rows' are reduced
            angles += [
                (f"{where} 'alpha'", float(written["alpha"]), *turn),
                (f"{where} 'theta'", float(written["theta"]), *turn),
                (f"{where} 'beta'", float(written.get("beta", 0.0)), *turn),
            ]
            if row.joint_type == "revolute":
                angles += [(f"{where} 'limits'", v, *turns) for v in (row.lower, row.upper)]
        angles += [(f"{path}, field '{key}'", v, *turn) for key, v in _fixed_angles(data)]
        for where, value, bound, words in angles:
            if abs(value) > bound:
                warnings.warn(
                    f"{where}: {value:g} rad is more than {words}: are the angles in degrees? "
                    'then write angle_unit = "deg"',
                    UnitWarning,
                    stacklevel=3,
                )
                break
    length = sum(abs(row.a) + abs(row.d) for row in rows)
    length += sum(
        max(abs(row.lower), abs(row.upper)) for row in rows if row.joint_type == "prismatic"
    )
    length += float(np.linalg.norm(base[:3, 3])) + float(np.linalg.norm(tool[:3, 3]))
    if length > LENGTH_SUSPECT and _tool_extent(rows, data["convention"], base, tool) > (
        LENGTH_SUSPECT
    ):
        hint = 'length_unit = "mm"' if data["length_unit"] == "m" else "the length unit"
        warnings.warn(
            f"{path}: the arm's lengths add up to {length:g} m (more than {LENGTH_SUSPECT:g} m): "
            f"are they in millimeters? then write {hint}",
            UnitWarning,
            stacklevel=3,
        )
