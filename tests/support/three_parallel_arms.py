"""Random arms with axes 2-4 parallel (general, classic, intersecting) for the closed-form tests."""

from __future__ import annotations

import functools
import math

import numpy as np

from dh2urdf import DHTable
from support.arm_tables import random_family_table, ur5_or_random

PI = math.pi


def _three_parallel_shape(
    family: str, rng: np.random.Generator, a: np.ndarray, alpha: np.ndarray, d: np.ndarray, j: int
) -> None:
    """Axes 2-4 parallel; ``a5`` at least 5 cm (general, classic) or 0 (intersecting); classic:
    wrist twists +-90 deg."""
    alpha[1 + j] = alpha[2 + j] = 0.0
    a[4 + j] = rng.choice([-1.0, 1.0]) * rng.uniform(0.05, 0.5)
    if family == "classic":
        alpha[3 + j], alpha[4 + j] = rng.choice([PI / 2, -PI / 2], 2)
    elif family == "intersecting":
        a[4 + j] = 0.0


def random_table(family: str, convention: str, seed: int) -> DHTable:
    """A random arm with axes 2-4 parallel: lengths in +-0.5 m, offsets in +-0.3 m, twists of
    joints 1, 4, 5, joint offsets, base and tool random (:func:`_three_parallel_shape`)."""
    return random_family_table(family, convention, seed, 0.3, True, _three_parallel_shape)


def _random_by_name(name: str) -> DHTable:
    family, convention, seed = name.split("_")
    return random_table(family, convention, int(seed))


@functools.cache
def arm_table(name: str) -> DHTable:
    """``ur5``, ``ur5_moved`` (:func:`~support.arm_tables.ur5_or_random`) or
    ``{family}_{convention}_{seed}`` (:func:`random_table`)."""
    return ur5_or_random(name, _random_by_name)
