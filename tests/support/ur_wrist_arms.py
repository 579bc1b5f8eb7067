"""Arms of the UR family for the closed-form tests: the UR5 (moved or not) and random UR tables."""

from __future__ import annotations

import functools
import math

import numpy as np

from dh2urdf import DHTable
from support.arm_tables import make_table, random_pose, ur5_or_random

PI = math.pi

UR5 = ("ur5", "ur5_moved", "random_standard_0", "random_standard_1", "random_modified_0",
       "random_modified_1")  # fmt: skip


def random_ur_table(seed: int, convention: str) -> DHTable:
    """A random arm of the UR family (the structural twists exact, the rest random).

    Even seeds: wrist twists +-90 deg (the UR arms); odd seeds: any wrist twists (IK-Geo's
    "three parallel, two intersecting" in general).
    """
    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.5, 0.5, 6)
    d = rng.uniform(-0.3, 0.3, 6)
    alpha = rng.uniform(-PI, PI, 6)
    theta = rng.uniform(-PI, PI, 6)
    if seed % 2 == 0:
        alpha[0] = rng.choice([PI / 2, -PI / 2])
    j = 0 if convention == "standard" else 1  # modified: row i + 1 holds joint i's a, alpha
    alpha[1 + j] = alpha[2 + j] = 0.0
    alpha[3 + j], alpha[4 + j] = rng.choice([PI / 2, -PI / 2], 2)
    if seed % 2 == 1:
        alpha[3 + j] *= rng.uniform(0.2, 1.8)
        alpha[4 + j] *= rng.uniform(0.2, 1.8)
    a[4 + j] = 0.0
    return make_table(a, alpha, d, theta, convention, random_pose(rng), random_pose(rng),
                      f"ur_random_{convention}_{seed}")  # fmt: skip


def _random_by_name(name: str) -> DHTable:
    _, convention, seed = name.split("_")
    return random_ur_table(int(seed) + (0 if convention == "standard" else 10), convention)


@functools.cache
def arm_table(name: str) -> DHTable:
    """``ur5``, ``ur5_moved`` (:func:`~support.arm_tables.ur5_or_random`) or
    ``random_{convention}_{seed}`` (:func:`random_ur_table`)."""
    return ur5_or_random(name, _random_by_name)
