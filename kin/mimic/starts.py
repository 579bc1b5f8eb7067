"""Starts near a target for a chain with mimic joints: a table of sampled poses.

The independent joints are sampled uniformly inside their limits (seeded, reproducible), every
joint's value follows from the coupling, and the table's NumPy DH product gives each sample's
tool pose (:func:`kin.batch_fk.batch_forward_kinematics`, the same product as
:meth:`kin.mimic.arm.MimicArm.fk`). The search of :mod:`.descent` then starts from the samples
whose poses are nearest the target (:class:`kin.ik.numeric.seed_table.SeedTable`) before it draws
random ones. Units: joint values [rad] or [m], lengths [m].
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..batch_fk import batch_forward_kinematics
from ..ik.numeric.seed_table import SeedTable, table_of_poses

if TYPE_CHECKING:
    from .arm import MimicArm

__all__ = ["SAMPLES", "sample_table"]

#: Samples of a chain's table (a few milliseconds to build, once per solver).
SAMPLES = 4000

#: Second entropy word of the samples' generator (any fixed value; keeps them apart).
_STREAM = 0x313C


def sample_table(arm: MimicArm, size: int = SAMPLES, seed: int = 0) -> SeedTable:
    """``size`` samples of ``arm``'s independent joints inside the limits, with their tool poses."""
    rng = np.random.default_rng([seed, _STREAM])
    q = rng.uniform(arm.lower, arm.upper, size=(size, arm.nq))
    return table_of_poses(q, batch_forward_kinematics(arm.table, arm.chain.expand(q)))
