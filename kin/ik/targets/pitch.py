"""A tool position with the tool pitch, and optionally the wrist roll, of a five-joint arm."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .values import checked_angle, checked_vector

__all__ = ["PitchTarget"]


@dataclass(frozen=True, eq=False)
class PitchTarget:
    """A tool position with the tool pitch, and optionally the wrist roll, of a five-joint arm.

    ``pitch`` is the angle of the tool's approach axis (the wrist-roll axis, pointing from the
    wrist to the tool) *below the horizontal*, measured in the vertical plane through the base
    axis and the target, from the horizontal direction pointing away from the base axis:
    ``approach = cos(pitch) h - sin(pitch) z0`` with ``h`` the horizontal unit vector from the base
    axis to the target. So 0 is "pointing straight out", +pi/2 "pointing straight down", -pi/2
    "pointing straight up". It does not depend on the branch (shoulder front or back). For the
    Abaas et al. arm (``lab5``, 002) with the shoulder in front, ``pitch = pi/2 - (q2 + q3 + q4)``:
    the paper's eq. (9) ``90 - theta234 = +phi``.

    Attributes:
        position: Tool point in the world frame [m], shape (3,).
        pitch: Approach angle below the horizontal [rad].
        roll: Wrist-roll joint value ``q5`` [rad] (as the papers pose it), or None to keep the
            seed's.
    """

    position: np.ndarray
    pitch: float
    roll: float | None = None

    def __init__(self, position: npt.ArrayLike, pitch: float, roll: float | None = None):
        object.__setattr__(self, "position", checked_vector(position, 3, "position"))
        object.__setattr__(self, "pitch", checked_angle(pitch, "pitch"))
        object.__setattr__(self, "roll", None if roll is None else checked_angle(roll, "roll"))

    @property
    def finite(self) -> bool:
        """Whether every value is finite."""
        isfinite = math.isfinite
        return (
            all(map(isfinite, self.position.tolist()))
            and isfinite(self.pitch)
            and (self.roll is None or isfinite(self.roll))
        )
