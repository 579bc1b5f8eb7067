"""Random arms of the Pieper families (spherical wrist, intersecting or parallel first axes)."""

from __future__ import annotations

import math

import numpy as np
from arm_tables import make_table, random_pose

from dh2urdf import DHTable

PI = math.pi


def random_table(family: str, convention: str, seed: int) -> DHTable:
    """A random arm of ``family`` with a spherical wrist: random twists (0 or 180 deg for
    alpha1 in the parallel family), lengths in +-0.5 m, offsets, base and tool."""
    rng = np.random.default_rng(seed + (0 if convention == "standard" else 50))
    a = rng.uniform(-0.5, 0.5, 6)
    d = rng.uniform(-0.5, 0.5, 6)
    theta = rng.uniform(-PI, PI, 6)
    alpha = rng.uniform(-PI, PI, 6)
    j = 0 if convention == "standard" else 1  # modified: row i + 1 holds joint i's a, alpha
    a[3 + j] = a[4 + j] = d[4] = 0.0
    if family == "intersecting":
        a[j] = 0.0
    elif family == "parallel":
        alpha[j] = rng.choice([0.0, PI])
    return make_table(a, alpha, d, theta, convention, random_pose(rng), random_pose(rng),
                      f"{family}_{convention}_{seed}")  # fmt: skip
