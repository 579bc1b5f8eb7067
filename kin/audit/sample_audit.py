"""Audit a DH table against printed samples: every reading tried, ranked, best first."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from .audited_table import AuditedTable, load_audited_table
from .length_fit import length_refits
from .printed import SampleScore, score_readings
from .readings import candidate_readings
from .samples import SampleSet, read_samples

#: Readings (best first) whose single-length refits are tried when none reproduces every sample.
REFIT_TOP = 3


@dataclass(frozen=True, eq=False)
class SampleAudit:
    """Result of :func:`audit_samples`.

    Attributes:
        audited: The table under audit, with its file's units.
        samples: The printed samples.
        scores: One score per reading, best first (``scores[0]`` is the best reading).
    """

    audited: AuditedTable
    samples: SampleSet
    scores: tuple[SampleScore, ...]

    @property
    def best(self) -> SampleScore:
        """The best reading's score."""
        return self.scores[0]

    def as_written(self) -> SampleScore:
        """The score of the table as written (no change)."""
        return next(s for s in self.scores if not s.reading.changes)


def audit_samples(
    table: str | Path | AuditedTable,
    samples: str | Path | SampleSet,
    *,
    pairs: bool = True,
    refit: bool = True,
) -> SampleAudit:
    """Try the readings of ``table`` on the printed ``samples`` and rank them.

    Args:
        table: Table file, shipped robot name, or an :class:`AuditedTable`.
        samples: Sample CSV file (see :mod:`kin.audit.samples`) or a :class:`SampleSet`.
        pairs: Also try every combination of two changes.
        refit: When no reading reproduces every sample, also try the best readings with one
            link length refitted to the samples (a length the source used but did not print).

    Raises:
        AuditError: The sample file is unusable (the message names the file and line).
        dh2urdf.TableError: The table file is malformed.
    """
    audited = table if isinstance(table, AuditedTable) else load_audited_table(table)
    if not isinstance(samples, SampleSet):
        samples = read_samples(samples, audited.table.dof)
    readings = candidate_readings(audited, pairs=pairs)
    scores = score_readings(audited, samples, readings)
    if refit and scores[0].count < len(samples):
        extra: list[SampleScore] = []
        for score in scores[:REFIT_TOP]:
            extra += length_refits(audited, samples, score)
        order = len(scores)
        merged = [*scores, *(_renumber(s, order + k) for k, s in enumerate(extra))]
        scores = sorted(merged, key=lambda s: s.rank_key)
    return SampleAudit(audited, samples, tuple(scores))


def _renumber(score: SampleScore, order: int) -> SampleScore:
    return replace(score, order=order)
