"""Arms with a spherical wrist for the closed-form tests: the PUMA 560 and random Pieper tables."""

from __future__ import annotations

import functools
import math

import numpy as np

from dh2urdf import DHTable
from support.arm_tables import make_table, random_pose

PI = math.pi

PUMA_A = [0, 0.4318, 0.0203, 0, 0, 0]
PUMA_ALPHA = [PI / 2, 0, -PI / 2, PI / 2, -PI / 2, 0]
PUMA_D = [0, 0, 0.15005, 0.4318, 0, 0]
ARMS = ("puma560", "puma560_moved", "random_standard_0", "random_standard_1",
        "random_modified_0", "random_modified_1", "skew_standard_0", "skew_modified_0")  # fmt: skip


def random_pieper_table(seed: int, convention: str, skew: bool) -> DHTable:
    """A random arm with a spherical wrist; ``skew``: twists other than +-90 deg where allowed."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.5, 0.5, 6)
    d = rng.uniform(-0.5, 0.5, 6)
    theta = rng.uniform(-PI, PI, 6)
    alpha = rng.uniform(-PI, PI, 6) if skew else rng.choice([PI / 2, -PI / 2], 6)
    j = 0 if convention == "standard" else 1  # modified: row i + 1 holds joint i's a, alpha
    alpha[1 + j] = 0.0
    a[3 + j] = a[4 + j] = d[4] = 0.0
    return make_table(a, alpha, d, theta, convention, random_pose(rng), random_pose(rng),
                      f"pieper_{convention}_{seed}")  # fmt: skip


@functools.cache
def arm_table(name: str) -> DHTable:
    if name == "puma560":
        return make_table(PUMA_A, PUMA_ALPHA, PUMA_D, [0] * 6, name="puma560")
    if name == "puma560_moved":
        rng = np.random.default_rng(560)
        return make_table(PUMA_A, PUMA_ALPHA, PUMA_D, [0.1, -0.2, 0.3, -0.4, 0.5, -0.6],
                          base=random_pose(rng), tool=random_pose(rng), name="puma560_moved")  # fmt: skip
    kind, convention, seed = name.split("_")
    offset = (0 if convention == "standard" else 10) + (100 if kind == "skew" else 0)
    return random_pieper_table(int(seed) + offset, convention, kind == "skew")
