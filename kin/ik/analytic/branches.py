"""What a closed-form branch solver returns: DH joint angles per branch, or why there are none."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

#: Distance beyond the reachable set [m] still treated as reachable (round-off of FK targets).
REACH_TOL = 1e-10

BranchStatus = Literal["ok", "out_of_reach", "singular"]


@dataclass
class Branches:
    """Branches of one closed-form solve, before limits, verification and ordering.

    Attributes:
        thetas: Per branch, the DH joint angles (``q + theta offset``) [rad] and the branch label.
        status: ``"ok"``; ``"singular"`` when branches merge or a joint is free (the free joint then
            keeps the seed's value); ``"out_of_reach"`` when there is no branch.
        gap: For ``"out_of_reach"``, distance from the target to the reachable set [m] (measured
            in the arm's plane), or None if the miss is not a distance (orientation).
        message: One sentence for a person.
    """

    thetas: list[tuple[tuple[float, ...], str]] = field(default_factory=list)
    status: BranchStatus = "ok"
    gap: float | None = None
    message: str = ""

    def singular(self, message: str) -> None:
        """Mark the solve as singular (keeps the first reason)."""
        if self.status == "ok":
            self.status = "singular"
            self.message = message

    def out_of_reach(self, gap: float | None, message: str) -> Branches:
        """Mark the solve as out of reach and drop any branch."""
        self.thetas.clear()
        self.status = "out_of_reach"
        self.gap = gap
        self.message = message
        return self
