"""Random arms with axes 2-4 parallel (general, classic, intersecting) for the closed-form tests."""

from __future__ import annotations

import math

import numpy as np
from arm_tables import make_table, random_pose

from dh2urdf import DHTable

PI = math.pi


def random_table(family: str, convention: str, seed: int) -> DHTable:
    """A random arm with axes 2-4 parallel: lengths in +-0.5 m, offsets, twists of joints 1, 4,
    5, base and tool random; ``a5`` at least 5 cm (general, classic) or 0 (intersecting);
    classic: wrist twists +-90 deg."""
    rng = np.random.default_rng(seed + (0 if convention == "standard" else 50))
    a = rng.uniform(-0.5, 0.5, 6)
    d = rng.uniform(-0.3, 0.3, 6)
    alpha = rng.uniform(-PI, PI, 6)
    theta = rng.uniform(-PI, PI, 6)
    j = 0 if convention == "standard" else 1  # modified: row i + 1 holds joint i's a, alpha
    alpha[1 + j] = alpha[2 + j] = 0.0
    a[4 + j] = rng.choice([-1.0, 1.0]) * rng.uniform(0.05, 0.5)
    if family == "classic":
        alpha[3 + j], alpha[4 + j] = rng.choice([PI / 2, -PI / 2], 2)
    elif family == "intersecting":
        a[4 + j] = 0.0
    return make_table(a, alpha, d, theta, convention, random_pose(rng), random_pose(rng),
                      f"{family}_{convention}_{seed}")  # fmt: skip
