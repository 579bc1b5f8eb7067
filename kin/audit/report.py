"""Text and JSON reports of an audit: readings best first, the edits the best one implies."""

from __future__ import annotations

from typing import Any

import numpy as np

from .printed import SampleScore, rpy_of
from .sample_audit import SampleAudit
from .urdf_audit import UrdfAudit, UrdfScore


def _changes(score: SampleScore | UrdfScore) -> list[str]:
    return [c.text for c in score.reading.changes]


def _edits(score: SampleScore | UrdfScore) -> list[str]:
    return [c.edit for c in score.reading.changes]


def sample_audit_json(audit: SampleAudit) -> dict[str, Any]:
    """The audit as a JSON-ready dict; ``readings`` best first, SI residuals."""
    labels = audit.samples.labels
    readings = []
    for s in audit.scores:
        readings.append(
            {
                "changes": _changes(s),
                "edits": _edits(s),
                "reproduced": s.count,
                "samples": len(labels),
                "values_reproduced": s.values_reproduced,
                "values": s.values,
                "max_residual_m": s.max_residual_m,
                "reproduced_samples": [
                    lab for lab, ok in zip(labels, s.reproduced, strict=True) if ok
                ],
                "residuals_m": [float(v) for v in s.position_residual_m],
            }
        )
    a = audit.audited
    return {
        "table": a.path,
        "samples_file": audit.samples.path,
        "length_unit": a.length_unit,
        "angle_unit": a.angle_unit,
        "readings": readings,
    }


def _pose(matrix: np.ndarray, meters: float, radians: float) -> dict[str, list[float]]:
    return {
        "xyz": [float(v) for v in matrix[:3, 3] / meters],
        "rpy": [float(v) for v in rpy_of(matrix[:3, :3]) / radians],
    }


def urdf_audit_json(audit: UrdfAudit) -> dict[str, Any]:
    """The audit as a JSON-ready dict; ``base``/``tool`` xyz and rpy in the table's units."""
    a = audit.audited
    readings = []
    for s in audit.scores:
        readings.append(
            {
                "changes": _changes(s),
                "edits": _edits(s),
                "reproduced": s.reproduced,
                "same_as_best": s.same_as_best,
                "position_residual_m": s.fit.position_residual_m,
                "rotation_residual_rad": s.fit.rotation_residual_rad,
                "unique": bool(s.fit.unique),
                "base": _pose(s.fit.T_ref_base, a.meters, a.radians),
                "tool": _pose(s.fit.T_tool_ref, a.meters, a.radians),
                "T_urdf_base": s.fit.T_ref_base.tolist(),
                "T_tool_urdf": s.fit.T_tool_ref.tolist(),
            }
        )
    return {
        "table": a.path,
        "urdf": audit.reference.path,
        "frame": audit.reference.frame,
        "joints_matched_by": audit.reference.mapped_by,
        "joint_vectors": len(audit.q),
        "length_unit": a.length_unit,
        "angle_unit": a.angle_unit,
        "readings": readings,
    }


def _length(value_m: float, audit_meters: float, unit: str) -> str:
    return f"{value_m / audit_meters:.4g} {unit}"


def equally_good(audit: SampleAudit, tol_m: float = 1e-9) -> list[SampleScore]:
    """Readings as good as the best: the samples cannot tell their tables apart.

    Same counts, same number of changes, same residuals to ``tol_m`` [m] per sample: e.g. an
    offset moved between two joints whose axes coincide.
    """
    best = audit.best
    return [
        s
        for s in audit.scores[1:]
        if s.count == best.count
        and s.values_reproduced == best.values_reproduced
        and len(s.reading.changes) == len(best.reading.changes)
        and np.allclose(s.position_residual_m, best.position_residual_m, rtol=0.0, atol=tol_m)
    ]


def sample_audit_text(audit: SampleAudit, top: int = 10) -> str:
    """A readable report: the ``top`` readings, the edits of the best, each sample under it."""
    a, samples = audit.audited, audit.samples
    n = len(samples)
    lines = [
        f"audit of {a.table.name} ({a.path}: {a.table.convention} DH, {a.length_unit}, "
        f"{a.angle_unit}) against {samples.path}: {n} samples, {audit.best.values} printed values",
        f"{len(audit.scores)} readings tried; best first (most samples reproduced, then those "
        "with joint values within the table's limits, then printed values, then fewest changes):",
        "",
        f"{'rank':>4}  {'samples':>7}  {'in limits':>9}  {'values':>7}  {'max residual':>12}  "
        "reading",
    ]
    for rank, s in enumerate(audit.scores[:top], start=1):
        residual = _length(s.max_residual_m, a.meters, a.length_unit)
        inside = int((s.reproduced & s.within_limits).sum())
        lines.append(
            f"{rank:>4}  {f'{s.count}/{n}':>7}  {inside:>9}  "
            f"{f'{s.values_reproduced}/{s.values}':>7}  {residual:>12}  {s.reading.label}"
        )
    written = audit.as_written()
    rank = audit.scores.index(written) + 1
    lines += [
        "",
        f"table as written: rank {rank}, {written.count}/{n} samples, "
        f"{written.values_reproduced}/{written.values} values, max residual "
        f"{_length(written.max_residual_m, a.meters, a.length_unit)}",
    ]
    best = audit.best
    if best.count == 0:
        lines.append(
            "no reading reproduces a sample: the printed values are no FK of the printed joint "
            "values under any reading tried (the best is the closest)"
        )
    if best.reading.changes:
        lines.append("the best reading implies:")
        lines += [f"  - {c.text}: {c.edit}" for c in best.reading.changes]
    else:
        lines.append("the best reading is the table as written: no edit")
    same = equally_good(audit)
    if same:
        shown = ", ".join(f"[{s.reading.label}]" for s in same[:5])
        more = f", ... ({len(same)} in all)" if len(same) > 5 else ""
        lines.append(f"equally good (the samples cannot tell them apart): {shown}{more}")
    slack = best.joint_slack
    largest = float(np.nanmax(slack)) if slack is not None and slack.size else 0.0
    lines.append(
        "tolerance of a printed value: half a unit of its last printed digit"
        + (
            f", plus the rounding of the printed joint values carried to it (at most "
            f"{largest:.2g} in the printed unit, first order)"
            if largest > 0
            else ""
        )
    )
    lines.append("samples under the best reading:")
    width = max(len(label) for label in samples.labels)
    for k, label in enumerate(samples.labels):
        verdict = "reproduced" if best.reproduced[k] else "not reproduced"
        limits = "" if best.within_limits[k] else "  (joint values outside the table's limits)"
        residual = _length(best.position_residual_m[k], a.meters, a.length_unit)
        lines.append(f"  {label:<{width}}  {verdict:<14}  residual {residual}{limits}")
    return "\n".join(lines)


def urdf_audit_text(audit: UrdfAudit, top: int = 10) -> str:
    """A readable report: the ``top`` readings, then base and tool of the best."""
    a, ref = audit.audited, audit.reference
    lines = [
        f"audit of {a.table.name} ({a.path}: {a.table.convention} DH) against {ref.path}, frame "
        f"'{ref.frame}' (joints matched by {ref.mapped_by}), {len(audit.q)} joint vectors",
        f"{len(audit.scores)} readings tried; best first (reproduced: within "
        f"{audit.position_tol:g} m and {audit.rotation_tol:g} rad):",
        "",
        f"{'rank':>4}  {'reproduced':>10}  {'position [m]':>12}  {'rotation [rad]':>14}  reading",
    ]
    same = [s for s in audit.scores[1:] if s.same_as_best]
    others = [s for s in audit.scores if not s.same_as_best]
    for rank, s in enumerate(others[:top], start=1):
        lines.append(
            f"{rank:>4}  {'yes' if s.reproduced else 'no':>10}  "
            f"{s.fit.position_residual_m:>12.3e}  {s.fit.rotation_residual_rad:>14.3e}  "
            f"{s.reading.label}"
        )
        if rank == 1 and same:
            labels = ", ".join(f"[{t.reading.label}]" for t in same[:6])
            more = f", ... ({len(same)} in all)" if len(same) > 6 else ""
            lines.append(
                f"{'':>4}  {len(same):>10}  same model as rank 1 up to the base/tool transform "
                f"(one finding, not {len(same) + 1}): {labels}{more}"
            )
    best = audit.best
    lines += ["", f"best reading: {best.reading.label}"]
    lines += [f"  - {c.text}: {c.edit}" for c in best.reading.changes]
    for name, matrix, meaning in (
        ("base", best.fit.T_ref_base, "pose of the table's world frame in the URDF root"),
        ("tool", best.fit.T_tool_ref, f"pose of '{ref.frame}' in the table's tool frame"),
    ):
        pose = _pose(matrix, a.meters, a.radians)
        xyz = ", ".join(_shown(v) for v in pose["xyz"])
        rpy = ", ".join(_shown(v) for v in pose["rpy"])
        lines.append(
            f"  {name}: xyz = ({xyz}) {a.length_unit}, rpy = ({rpy}) {a.angle_unit}  ({meaning})"
        )
    if not best.fit.unique:
        lines.append(
            "  base and tool are not unique: a motion of both leaves every sample in place "
            "(e.g. a planar arm: a shift or turn along the common joint axis)"
        )
    return "\n".join(lines)


def _shown(value: float) -> str:
    """A number for the text report, round-off below 1e-12 shown as 0."""
    return f"{value if abs(value) > 1e-12 else 0.0:.9g}"
