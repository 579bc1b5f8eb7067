"""Random general 7R arms for the closed-form tests: a table and the same numbers as reference arrays."""

from __future__ import annotations

import math

import numpy as np
from arm_tables import make_table, random_pose
from dh_reference import ReferenceTable

PI = math.pi


def random_arm(seed: int, convention: str) -> tuple:
    """A random 7R table (lengths +-0.4 m, any twist and offset, random base and tool), its
    reference arrays, and limits +-2 pi."""
    rng = np.random.default_rng(seed)
    a, d = rng.uniform(-0.4, 0.4, (2, 7))
    alpha, theta = rng.uniform(-PI, PI, (2, 7))
    base, tool = random_pose(rng), random_pose(rng)
    table = make_table(a, alpha, d, theta, convention, base, tool, name=f"r7_{convention}{seed}")
    ones = np.ones(7)
    reference = ReferenceTable(
        convention, tuple(f"j{i}" for i in range(1, 8)), np.zeros(7, dtype=bool), a, alpha, d,
        theta, -2 * PI * ones, 2 * PI * ones, base, tool,
    )  # fmt: skip
    return table, reference
