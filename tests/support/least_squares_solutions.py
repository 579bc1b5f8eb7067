"""The distinct solutions that least-squares starts find: an IK enumeration independent of ours."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from support.arm_tables import wrapped_gap


def least_squares_solutions(
    residual: Callable[[np.ndarray], np.ndarray], rng: np.random.Generator, starts: int
) -> list[np.ndarray]:
    """Distinct joint vectors [rad] (1e-5 apart modulo 2 pi) where ``residual`` vanishes (to
    1e-10), from ``starts`` random starts in [-pi, pi]^6 (no limits); local minima off target are
    dropped."""
    from scipy.optimize import least_squares

    solutions: list[np.ndarray] = []
    for _ in range(starts):
        fit = least_squares(residual, rng.uniform(-math.pi, math.pi, 6), xtol=1e-15, ftol=1e-15,
                            gtol=1e-15)  # fmt: skip
        if np.abs(fit.fun).max() > 1e-10:
            continue  # a local minimum off target
        if not solutions or wrapped_gap(np.array(solutions), fit.x).min() > 1e-5:
            solutions.append(fit.x)
    return solutions
