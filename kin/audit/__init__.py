"""Audit a DH table: which reading of it reproduces a source's printed numbers, or a maker's URDF.

A paper's table and the numbers computed from it often disagree: a convention mislabelled, joint
offsets printed into the joint values, a twist sign flipped, a length in another unit, digits
truncated, a link length used but not printed. :func:`audit_samples` tries the table as written,
every single change and every pair of changes (:mod:`kin.audit.readings`) on printed samples
(:mod:`kin.audit.samples`) and ranks them; :func:`audit_urdf` fits the constant base and tool
transforms that map each reading's tool onto a reference URDF frame and ranks the residuals.
The command is ``dh2urdf audit`` (:mod:`kin.commands.audit`).
"""

from .audited_table import AuditedTable, load_audited_table
from .changes import Change, elementary_changes
from .exceptions import AuditError
from .printed import SampleScore, score_readings
from .readings import Reading, apply_changes, candidate_readings
from .sample_audit import SampleAudit, audit_samples
from .samples import SampleSet, read_samples
from .se3_fit import BaseToolFit, fit_base_tool
from .urdf_audit import UrdfAudit, UrdfScore, audit_urdf

__all__ = [
    "AuditError",
    "AuditedTable",
    "BaseToolFit",
    "Change",
    "Reading",
    "SampleAudit",
    "SampleScore",
    "SampleSet",
    "UrdfAudit",
    "UrdfScore",
    "apply_changes",
    "audit_samples",
    "audit_urdf",
    "candidate_readings",
    "elementary_changes",
    "fit_base_tool",
    "load_audited_table",
    "read_samples",
    "score_readings",
]
