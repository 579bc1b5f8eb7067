"""The batched solve of a structure that solves one target at a time: a loop over its ``solve``.

The small arms' closed forms (:mod:`.planar`, :mod:`.three_joint`) solve one target in plain
floats; N targets are N such solves (:class:`PerTargetBatch`), with no elbow side to report.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .closed_form_structure import BatchBranches


class PerTargetBatch:
    """``solve_batch`` and ``batch_branches`` of a structure from its one-target ``solve``."""

    dof: ClassVar[int]
    branch_labels: tuple[str, ...]

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """Candidate joint vectors (B, dof) [rad] of one world target (the structure's)."""
        raise NotImplementedError

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets (N, 3) [m] and rotations (N, 3, 3) or None: (N, B, dof)."""
        shape = (-1, len(self.branch_labels), self.dof)
        if rotations is None:
            return np.array([self.solve(p, None) for p in positions]).reshape(shape)
        return np.array([self.solve(p, r) for p, r in zip(positions, rotations)]).reshape(shape)

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """:meth:`solve_batch`; no elbow side (all False)."""
        q = self.solve_batch(positions, rotations)
        return BatchBranches(q, np.zeros(q.shape[:2], dtype=bool))
