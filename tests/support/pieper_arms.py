"""Arms of the Pieper families (spherical wrist, intersecting or parallel first axes)."""

from __future__ import annotations

import functools
import math

import numpy as np

from dh2urdf import DHTable
from support.arm_tables import make_table, random_family_table, random_pose
from support.spherical_wrist_arms import PUMA_A, PUMA_ALPHA, PUMA_D

PI = math.pi


def _pieper_shape(
    family: str, rng: np.random.Generator, a: np.ndarray, alpha: np.ndarray, d: np.ndarray, j: int
) -> None:
    """A spherical wrist; the first axes intersecting (``a1 = 0``), parallel (``alpha1`` 0 or
    180 deg) or general."""
    a[3 + j] = a[4 + j] = d[4] = 0.0
    if family == "intersecting":
        a[j] = 0.0
    elif family == "parallel":
        alpha[j] = rng.choice([0.0, PI])


def random_table(family: str, convention: str, seed: int) -> DHTable:
    """A random arm of ``family`` with a spherical wrist: random twists (0 or 180 deg for
    alpha1 in the parallel family), lengths and offsets in +-0.5 m, joint offsets, base and tool."""
    return random_family_table(family, convention, seed, 0.5, False, _pieper_shape)


@functools.cache
def arm_table(name: str) -> DHTable:
    """``puma560_moved`` (PUMA 560 with joint offsets on a random base and tool) or
    ``{family}_{convention}_{seed}`` (:func:`random_table`)."""
    if name == "puma560_moved":
        rng = np.random.default_rng(560)
        return make_table(PUMA_A, PUMA_ALPHA, PUMA_D, [0.1, -0.2, 0.3, -0.4, 0.5, -0.6],
                          base=random_pose(rng), tool=random_pose(rng), name=name)  # fmt: skip
    family, convention, seed = name.split("_")
    return random_table(family, convention, int(seed))
