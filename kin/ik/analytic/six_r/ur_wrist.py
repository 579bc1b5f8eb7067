"""The UR case of the three-parallel family, by its old import path.

:class:`~.three_parallel.URWrist6R` (UR3, UR5, UR10 and the e-series, Unitree Z1: axes 2-4
parallel, axes 5 and 6 meeting) lives in :mod:`.three_parallel`, solved by that family's one
algorithm and its compiled twin (``kin/_native/ik/analytic/six_r/_three_parallel.c``); answers keep the name
``ur_wrist``. This module only keeps ``from kin.ik.analytic.six_r.ur_wrist import URWrist6R``
working.
"""

from __future__ import annotations

from .three_parallel import URWrist6R

__all__ = ["URWrist6R"]
