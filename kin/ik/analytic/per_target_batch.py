"""The batched solve of a structure that solves one target at a time: a loop over its ``solve``.

The small arms' closed forms (:mod:`.planar`, :mod:`.three_joint`) solve one target in plain
floats; N targets are N such solves, with no elbow side to report. Each of those structures
answers ``solve_batch`` and ``batch_branches`` by these two functions (called, not inherited).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from .closed_form_structure import BatchBranches


class OneTargetForm(Protocol):
    """A structure solving one target at a time: its ``dof``, labels and ``solve``."""

    @property
    def dof(self) -> int:
        """Number of joints."""
        ...

    @property
    def branch_labels(self) -> tuple[str, ...]:
        """One label per branch of a target."""
        ...

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """Candidate joint vectors (B, dof) [rad] of one world target."""
        ...


def solve_each(
    form: OneTargetForm, positions: np.ndarray, rotations: np.ndarray | None
) -> np.ndarray:
    """``form.solve`` of N targets (N, 3) [m] and rotations (N, 3, 3) or None: (N, B, dof)."""
    shape = (-1, len(form.branch_labels), form.dof)
    if rotations is None:
        return np.array([form.solve(p, None) for p in positions]).reshape(shape)
    return np.array([form.solve(p, r) for p, r in zip(positions, rotations)]).reshape(shape)


def branches_of_each(
    form: OneTargetForm, positions: np.ndarray, rotations: np.ndarray | None
) -> BatchBranches:
    """:func:`solve_each` with no elbow side (all False)."""
    q = solve_each(form, positions, rotations)
    return BatchBranches(q, np.zeros(q.shape[:2], dtype=bool))
