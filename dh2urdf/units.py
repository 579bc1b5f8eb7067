"""Units accepted at the edges (table files, command lines) and their factors to SI."""

from __future__ import annotations

import math

#: Length units and their factor to meters.
LENGTH_UNITS: dict[str, float] = {"cm": 0.01, "m": 1.0, "mm": 0.001}

#: Angle units and their factor to radians.
ANGLE_UNITS: dict[str, float] = {"deg": math.pi / 180.0, "rad": 1.0}


def angle_to_radians(value: float, factor: float) -> float:
    """An angle written in a unit, reduced modulo a turn in that unit, in radians.

    The reduction (:func:`math.fmod`, exact on floats) comes before the conversion, so an angle
    of any size keeps its digits: 1e18 deg gives the radians of ``fmod(1e18, 360)`` deg.

    Args:
        value: The angle [unit].
        factor: The unit's factor to radians (:data:`ANGLE_UNITS`).

    Returns:
        The angle [rad], of magnitude below one turn.
    """
    return math.fmod(value, 2.0 * math.pi / factor) * factor
