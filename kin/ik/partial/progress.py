"""What one partial-pose search has found so far, shared by its stages."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..result import IKSolution
from .settings import SAME_SOLUTION

__all__ = ["Progress"]


@dataclass
class Progress:
    """The answers of one search so far (mutable: each stage adds to it).

    Attributes:
        found: Solutions on target inside the limits, each joint vector once.
        outside: Solutions on target outside the limits.
        attempts: ``(weighted cost, q)`` of the closed-form branches off target.
        method: The stage that answered (:attr:`~kin.ik.IKResult.method`), ``""`` until one did.
    """

    found: list[IKSolution] = field(default_factory=list)
    outside: list[IKSolution] = field(default_factory=list)
    attempts: list[tuple[float, np.ndarray]] = field(default_factory=list)
    method: str = ""

    def add(self, solution: IKSolution) -> None:
        """Keep ``solution`` in :attr:`found` unless one there is the same joint vector."""
        for other in self.found:
            if float(np.abs(other.q - solution.q).max()) < SAME_SOLUTION:
                return
        self.found.append(solution)
