"""The answer of a motion plan: a status, the joint path, and what the search cost.

Made by :func:`kin.plan.plan`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

__all__ = ["PlanResult", "PlanStatus", "STATUSES"]

#: Why a plan has, or has not, a path.
PlanStatus = Literal[
    "ok", "start_in_collision", "goal_in_collision", "out_of_reach", "timeout", "not_found"
]
#: Every :data:`PlanStatus`, ``"ok"`` first.
STATUSES: tuple[str, ...] = (
    "ok",
    "start_in_collision",
    "goal_in_collision",
    "out_of_reach",
    "timeout",
    "not_found",
)


@dataclass(frozen=True)
class PlanResult:
    """A collision-free joint path from the start to a goal, or why there is none.

    Attributes:
        status: ``"ok"`` (a certified path), ``"start_in_collision"`` / ``"goal_in_collision"``
            (``message`` names the pair), ``"out_of_reach"`` (no IK answer of the target),
            ``"timeout"`` (the clock cap came first), ``"not_found"`` (the work budget was spent).
        planner: The OMPL planner's name (e.g. ``"RRTConnect"``).
        message: One sentence for a person.
        path: Joint path, shape (M, nq) [rad] (or [m] for prismatic joints): the start first, a
            goal last; empty (0, nq) without a path. Every straight joint motion between two
            consecutive rows is collision-free by :mod:`kin.path.collision_check`'s rule.
        goal_index: Which of :attr:`goals` the path reaches, or None.
        goals: The goal configurations offered to the planner (one for a joint goal; every
            collision-free IK branch for a target), shape (G, nq).
        plan_time: Wall time of the search and simplification [s] (not the checker's one-off setup).
        length: Joint-space length of :attr:`path`, the sum of each step's Euclidean norm [rad].
        straight_length: The straight joint line's length from the start to the reached goal
            [rad] (the shortest a path to it can be), or None.
        checks: Configurations checked (validity of states, and the points between states that
            the motion rule subdivided) [count]: the work the search did.
        clearance: Smallest distance between the padded shapes over the path's rows [m] (a lower
            bound between rows is the rule's, not this number), or None.
        seed: The random seed of the search.
    """

    status: PlanStatus
    planner: str
    message: str
    path: np.ndarray
    goal_index: int | None = None
    goals: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    plan_time: float = 0.0
    length: float = 0.0
    straight_length: float | None = None
    checks: int = 0
    clearance: float | None = None
    seed: int = 0

    @property
    def success(self) -> bool:
        """A path was found (:attr:`status` ``"ok"``)."""
        return self.status == "ok"
