"""Audit a DH table against a reference URDF: readings ranked by the fit of a fixed base and tool.

Each reading's tool is mapped onto the URDF frame by constant transforms fitted in closed form,
``T_urdf(q) = B T_table(q) E`` (:mod:`kin.audit.se3_fit`), over joint vectors sampled within
both models' limits; the residuals rank the readings.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .audited_table import AuditedTable, load_audited_table
from .fk_many import many_tool_poses
from .readings import Reading, candidate_readings
from .reference import ReferenceUrdf, load_reference, sample_joint_vectors
from .se3_fit import BaseToolFit, fit_base_tool_many

#: Default number of joint vectors sampled.
COUNT = 64
#: Default tolerances for "the reading reproduces the URDF": [m] and [rad].
POSITION_TOL = 1e-6
ROTATION_TOL = 1e-6


@dataclass(frozen=True, eq=False)
class UrdfScore:
    """One reading against the reference.

    Attributes:
        reading: The reading (table variant).
        fit: The fitted base and tool transforms and the residuals.
        reproduced: Both residuals within the tolerances.
        order: Place of the reading in the generation order.
        same_as_best: The reading is the best one's model up to constant base and tool
            transforms (:func:`same_model`): one finding, not another.
    """

    reading: Reading
    fit: BaseToolFit
    reproduced: bool
    order: int
    same_as_best: bool = False

    @property
    def rank_key(self) -> tuple:
        """Sort key, best first: reproduced, fewest changes, position then rotation residual."""
        changes = len(self.reading.changes) if self.reproduced else 0
        return (
            not self.reproduced,
            changes,
            self.fit.position_residual_m,
            self.fit.rotation_residual_rad,
            self.order,
        )


@dataclass(frozen=True, eq=False)
class UrdfAudit:
    """Result of :func:`audit_urdf`.

    Attributes:
        audited: The table under audit.
        reference: The reference URDF and frame.
        q: The sampled joint vectors (N, dof) [rad, m].
        scores: One score per reading, best first.
        position_tol: Tolerance [m] used for ``reproduced``.
        rotation_tol: Tolerance [rad] used for ``reproduced``.
    """

    audited: AuditedTable
    reference: ReferenceUrdf
    q: np.ndarray
    scores: tuple[UrdfScore, ...]
    position_tol: float
    rotation_tol: float

    @property
    def best(self) -> UrdfScore:
        """The best reading's score."""
        return self.scores[0]


def audit_urdf(
    table: str | Path | AuditedTable,
    urdf: str | Path,
    frame: str,
    *,
    count: int = COUNT,
    seed: int = 0,
    pairs: bool = True,
    position_tol: float = POSITION_TOL,
    rotation_tol: float = ROTATION_TOL,
) -> UrdfAudit:
    """Fit base and tool transforms for every reading of ``table`` against ``urdf``'s ``frame``.

    Args:
        table: Table file, shipped robot name, or an :class:`AuditedTable`.
        urdf: The reference URDF file.
        frame: The URDF frame that corresponds to the table's tool (e.g. ``"tool0"``).
        count: Number of joint vectors sampled within both models' limits.
        seed: Seed of the joint-vector sampling.
        pairs: Also try every combination of two changes.
        position_tol: A reading reproduces the URDF when its position residual [m] and ...
        rotation_tol: ... rotation residual [rad] are within these.

    Raises:
        AuditError: The URDF cannot be loaded, lacks ``frame``, or has too few joints.
    """
    audited = table if isinstance(table, AuditedTable) else load_audited_table(table)
    reference = load_reference(urdf, frame, audited.table)
    q = sample_joint_vectors(audited.table, reference, count, seed)
    T_ref = reference.poses(q)
    readings = candidate_readings(audited, samples=False, pairs=pairs)
    q_all = q[None] * np.stack([r.signs for r in readings])[:, None, :]  # the table's q
    T_table = many_tool_poses([r.table for r in readings], q_all)
    scores = []
    for order, (reading, fit) in enumerate(
        zip(readings, fit_base_tool_many(T_table, T_ref), strict=True)
    ):
        ok = fit.position_residual_m <= position_tol and fit.rotation_residual_rad <= rotation_tol
        scores.append(UrdfScore(reading, fit, ok, order))
    ranked = sorted(scores, key=lambda s: s.rank_key)
    best = ranked[0]
    check = sample_joint_vectors(audited.table, reference, 64, seed + 1)  # fresh joint vectors
    for k, score in enumerate(ranked[1:], start=1):
        if score.reproduced and best.reproduced and same_model(best, score, check):
            ranked[k] = replace(score, same_as_best=True)
    return UrdfAudit(audited, reference, q, tuple(ranked), position_tol, rotation_tol)


def same_model(first: UrdfScore, second: UrdfScore, q: np.ndarray, tol: float = 1e-9) -> bool:
    """Whether two readings are one model up to constant base and tool transforms.

    Both were fitted to the reference: ``T_ref = B1 T1(q) E1 = B2 T2(q) E2``, so
    ``T2(q) = B2^-1 B1 T1(q) E1 E2^-1`` must hold at every joint vector; this checks it at
    ``q`` (other joint vectors than the fit's) with each table's own NumPy DH product, to ``tol``
    [m, and in the rotation entries].
    """
    from kin.batch_fk import batch_forward_kinematics

    t1 = batch_forward_kinematics(first.reading.table, q * first.reading.signs)
    t2 = batch_forward_kinematics(second.reading.table, q * second.reading.signs)
    base = np.linalg.inv(second.fit.T_ref_base) @ first.fit.T_ref_base
    tool = first.fit.T_tool_ref @ np.linalg.inv(second.fit.T_tool_ref)
    predicted = base @ t1 @ tool
    return bool(np.abs(predicted - t2).max() <= tol)
