"""Settings of the distance bound inside the numeric solve (:mod:`.collision_bound`).

A frozen value, checked when built: a bad field raises :class:`~kin.ik.IKError` naming it and
its range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..exceptions import IKError
from ..numeric.differential_ik import QP_SOLVERS

__all__ = ["DistanceBound"]


@dataclass(frozen=True)
class DistanceBound:
    """Settings of the distance-bounded solve.

    Attributes:
        margin: Distance kept between every checked pair, beyond the model's padding and the
            contact tolerance (:data:`~kin.collision.requests.CONTACT_TOLERANCE`) [m].
        influence: Pairs closer than this enter the QP as inequalities [m].
        gain: Fraction of a pair's gap to ``margin`` a step may close (or must open) [1], in (0, 1].
        opening: Most a pair inside ``margin`` must open per step [m] (a deep one opens steadily).
        iterations: Steps per start [1].
        patience: A start is given up after this many steps without progress [1] (the error
            not halved, no pair inside the padding opened by a millimeter).
        random_starts: Starts drawn inside the limits after the given ones [1].
        damping: Constant damping of the step [1] (added to ``error_damping |e|^2``).
        error_damping: Damping proportional to the squared weighted error [1].
        max_step: Largest joint change per step [rad] (or [m]).
        qp_solver: The QP solver's name for qpsolvers.
        random_seed: Seed of the random starts.
    """

    margin: float = 0.002
    influence: float = 0.05
    gain: float = 0.5
    opening: float = 0.01
    iterations: int = 80
    patience: int = 15
    random_starts: int = 8
    damping: float = 1e-9
    error_damping: float = 1e-3
    max_step: float = 0.2
    qp_solver: str = "daqp"
    random_seed: int = 0

    def __post_init__(self) -> None:
        """Check every field: a bad one raises :class:`~kin.ik.IKError` naming it and its range."""
        ranges = (
            ("margin", self.margin >= 0.0, ">= 0 m"),
            ("influence", self.influence > self.margin, "> margin"),
            ("gain", 0.0 < self.gain <= 1.0, "in (0, 1]"),
            ("opening", self.opening > 0.0, "> 0 m"),
            ("iterations", self.iterations >= 1, ">= 1"),
            ("patience", self.patience >= 1, ">= 1"),
            ("random_starts", self.random_starts >= 0, ">= 0"),
            ("damping", self.damping >= 0.0, ">= 0"),
            ("error_damping", self.error_damping >= 0.0, ">= 0"),
            ("max_step", self.max_step > 0.0, "> 0 rad"),
        )
        for name, ok, expected in ranges:
            value = getattr(self, name)
            if not (ok and math.isfinite(value)):
                raise IKError(f"DistanceBound.{name}: {value!r} must be a finite number {expected}")
        if self.qp_solver not in QP_SOLVERS:
            raise IKError(
                f"DistanceBound.qp_solver: unknown QP solver {self.qp_solver!r}; choose one of: "
                f"{', '.join(QP_SOLVERS)}"
            )
