"""The spherical-wrist case of the Pieper family, by its old import path.

:class:`~.pieper.SphericalWrist6R` (PUMA 560, Kinova Jaco 2 and most industrial arms: a
spherical wrist, axes 2 and 3 parallel) lives in :mod:`.pieper`, solved by that family's one
algorithm and its compiled twin (``kin/_native/ik/analytic/six_r/_pieper_arms.c``); answers keep the name
``spherical_wrist``. This module only keeps ``from kin.ik.analytic.six_r.spherical_wrist import
SphericalWrist6R`` working.
"""

from __future__ import annotations

from .pieper import SphericalWrist6R

__all__ = ["SphericalWrist6R"]
