"""The verdict of a joint path's collision check: the first colliding place, and the whole path.

Made by :func:`kin.path.collision_check.check_path_collisions` (the rule between samples and where
contact begins are stated there).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from dh2urdf.output_text import shown_name

from ..collision.requests import CONTACT_TOLERANCE

__all__ = ["RULE", "TOLERANCE", "PathCollision", "PathCollisionCheck"]

#: Default scale below which a pair is not shown apart between samples [m].
TOLERANCE = 1e-6
#: The rule in one line (printed by ``kin path``).
RULE = (
    "between samples: free when d0 + d1 > the links' largest motion bound (sum of |dq_j| times "
    f"the reach from joint j) + twice the contact tolerance {CONTACT_TOLERANCE:g} m, else halved "
    "down to 1e-6 m, each midpoint judged as a sample"
)


@dataclass(frozen=True)
class PathCollision:
    """The first place where a joint path collides.

    Attributes:
        segment: Index ``i`` of the segment from sample ``i`` to ``i + 1``; for a colliding
            sample ``i``, the segment that ends there (``i - 1``, or 0 for the first sample).
        fraction: Where along the segment contact begins, 0 (sample ``i``) to 1 (sample
            ``i + 1``), to the module's resolution (``tolerance`` of link motion).
        q: The joint vector there [rad] / [m].
        a: Link (base side) of the pair.
        b: Link or scene object.
        kind: ``"self"`` or ``"scene"``.
        at_sample: The place is a sample (not the motion between two).
        proven: In contact there by :meth:`~kin.collision.CollisionChecker.in_collision`
            (False: every point checked is free, but the pair is not shown beyond the contact
            tolerance at the module's resolution).
    """

    segment: int
    fraction: float
    q: np.ndarray
    a: str
    b: str
    kind: str
    at_sample: bool
    proven: bool

    def describe(self) -> str:
        """One line: where and which pair."""
        if self.at_sample:
            sample = self.segment + (1 if self.fraction >= 1.0 else 0)
            place = f"sample {sample}"
        else:
            place = (
                f"between samples {self.segment} and {self.segment + 1} (t = {self.fraction:.6g})"
            )
        pair = f"{shown_name(self.a)} / {shown_name(self.b)} ({self.kind})"
        if not self.at_sample and self.proven:
            return (
                f"contact begins between samples {self.segment} and {self.segment + 1} at "
                f"t = {self.fraction:.6g} of the segment: {pair}"
            )
        verdict = (
            "collides"
            if self.proven
            else f"comes within the contact tolerance {CONTACT_TOLERANCE:g} m + 1e-6 m (not proven)"
        )
        return f"{place} {verdict}: {pair}"


@dataclass(frozen=True)
class PathCollisionCheck:
    """The verdict on a joint path.

    Attributes:
        free: No sample collides and every motion between samples is shown free.
        first: The first colliding place along the path, or None.
        sample_collisions: Per sample, whether it collides, shape (M,).
        checks: Configurations checked between samples (the subdivisions).
        rule: The rule used between samples.
    """

    free: bool
    first: PathCollision | None
    sample_collisions: np.ndarray
    checks: int
    rule: str = RULE
    resolution: float = TOLERANCE

    @property
    def first_sample(self) -> int | None:
        """Index of the first colliding sample, or None (every sample free)."""
        colliding = np.flatnonzero(self.sample_collisions)
        return int(colliding[0]) if colliding.size else None

    def describe(self) -> str:
        """One line: ``"free"``, or the first colliding sample and where contact begins."""
        if self.first is None:
            return "free"
        sample = self.first_sample
        samples = "no sample collides" if sample is None else f"first colliding sample {sample}"
        return (
            f"{samples}; {self.first.describe()} "
            f"(resolution {self.resolution:.3g} m of link motion)"
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict, SI."""
        first = self.first
        return {
            "free": self.free,
            "rule": self.rule,
            "resolution_m": self.resolution,
            "first_colliding_sample": self.first_sample,
            "colliding_samples": np.flatnonzero(self.sample_collisions).tolist(),
            "checks_between_samples": self.checks,
            "first": None
            if first is None
            else {
                "segment": first.segment,
                "fraction": first.fraction,
                "at_sample": first.at_sample,
                "q": first.q.tolist(),
                "a": first.a,
                "b": first.b,
                "kind": first.kind,
                "proven": first.proven,
            },
        }
