"""Units accepted at the edges (table files, command lines) and their factors to SI."""

from __future__ import annotations

import math

#: Length units and their factor to meters.
LENGTH_UNITS: dict[str, float] = {"cm": 0.01, "m": 1.0, "mm": 0.001}

#: Angle units and their factor to radians.
ANGLE_UNITS: dict[str, float] = {"deg": math.pi / 180.0, "rad": 1.0}
