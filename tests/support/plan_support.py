"""Shared pieces of the planning tests: planar2's swing through a ball, and the resampling of a
motion's configurations to a largest joint step.
"""

from __future__ import annotations

import math

import numpy as np

SWING = ["--robot", "planar2", "--start", "-90", "0", "--goal", "90", "0", "--deg"]
#: Largest joint step of the resampled check [rad].
RESAMPLE = 0.005
#: planar2's straight swing from -90 to +90 deg of its first joint passes through this ball.
BALL = "[[sphere]]\nname = 'ball'\nradius = 0.04\nxyz = [0.45, 0.0, 0.0]\n"


def write_ball(folder) -> str:  # noqa: ANN001
    """The ball's cell file in ``folder``."""
    scene = folder / "ball.toml"
    scene.write_text(BALL, encoding="utf-8")
    return str(scene)


def _resampled(path: np.ndarray) -> np.ndarray:
    """Every configuration of the straight motions, no joint step over RESAMPLE."""
    rows = [path[:1]]
    for a, b in zip(path[:-1], path[1:]):
        steps = max(1, math.ceil(float(np.abs(b - a).max()) / RESAMPLE))
        rows.append(a + np.linspace(0.0, 1.0, steps + 1)[1:, None] * (b - a))
    return np.vstack(rows)
