"""The calibration report: errors before and after, parameters with their standard deviations.

Text for a person (lengths in mm, angles in deg) and a JSON-ready dict (SI units). Warnings name
every correction larger than :data:`WARN_LENGTH` or :data:`WARN_ANGLE` (a sign that the nominal
table is wrong, or the data, rather than that the arm is a little off).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .calibration import Calibration
from .errors import Errors
from .outputs import tilts

#: Corrections beyond these are warned about [m], [rad].
WARN_LENGTH = 0.010
WARN_ANGLE = math.radians(1.0)


def _show(value: float, angle: bool, signed: bool = False) -> str:
    shown, unit = (math.degrees(value), "deg") if angle else (value * 1e3, "mm")
    return f"{shown:+.4f} {unit}" if signed else f"{shown:.4f} {unit}"


def _nominal(calibration: Calibration) -> np.ndarray:
    """The nominal value of every parameter (row values, nominal tool; base: the first guess)."""
    model = calibration.model
    out = np.array(calibration.start, dtype=float)
    tool = calibration.table.T_last_tool
    for i, p in enumerate(model.parameters):
        if p.row is not None:
            out[i] = getattr(calibration.table.rows[p.row], p.kind)
        elif p.group != "base" and p.kind == "t":
            out[i] = tool[p.axis, 3]
    return out


def parameter_rows(calibration: Calibration) -> list[dict[str, Any]]:
    """Per parameter: name, unit, nominal, calibrated, change, std (SI), identifiable."""
    nominal = _nominal(calibration)
    mask = calibration.identifiability.identifiable
    out = []
    for i, p in enumerate(calibration.model.parameters):
        std = float(calibration.std[i])
        out.append(
            {
                "name": p.name,
                "unit": "rad" if p.angle else "m",
                "nominal": float(nominal[i]),
                "calibrated": float(calibration.x[i]),
                "change": float(calibration.x[i] - nominal[i]),
                "std": None if math.isnan(std) else std,
                "identifiable": bool(mask[i]),
            }
        )
    return out


def warnings(calibration: Calibration) -> list[str]:
    """Corrections of the rows larger than 10 mm or 1 deg (base, tool and markers are unknowns)."""
    out = []
    rows = {p.name for p in calibration.model.parameters if p.row is not None}
    for row in parameter_rows(calibration):
        if row["name"] not in rows:
            continue
        limit = WARN_ANGLE if row["unit"] == "rad" else WARN_LENGTH
        if abs(row["change"]) > limit:
            out.append(
                f"{row['name']} changes by {_show(row['change'], row['unit'] == 'rad', True)}, "
                f"more than {_show(limit, row['unit'] == 'rad')}: check the table and the data"
            )
    return out


def _stats(errors: Errors | None) -> dict[str, float | None] | None:
    if errors is None:
        return None
    rms, rot_rms = errors.rms()
    top, rot_top = errors.max()
    return {
        "position_rms_m": rms,
        "position_max_m": top,
        "rotation_rms_rad": rot_rms,
        "rotation_max_rad": rot_top,
    }


def calibration_json(calibration: Calibration) -> dict[str, Any]:
    """The report as a JSON-ready dict (SI units)."""
    found = calibration.identifiability
    data = calibration.measurements
    base = calibration.model.T_measurement_base(calibration.x)
    return {
        "robot": calibration.table.name,
        "measurements": data.path,
        "rows": data.count,
        "kind": "poses" if data.markers == 0 else f"positions of {data.markers} point(s)",
        "loss": calibration.loss,
        "noise": {
            "position_m": calibration.noise.position,
            "rotation_rad": calibration.noise.rotation,
        },
        "identifiable": found.rank,
        "parameters_total": len(calibration.x),
        "rank_tolerance": found.tolerance,
        "condition_number": found.condition_number,
        "before": _stats(calibration.before),
        "after": _stats(calibration.after),
        "cross_validated": _stats(calibration.cross_validated),
        "folds": calibration.folds,
        "parameters": parameter_rows(calibration),
        "unidentifiable": [
            {
                "name": u.name,
                "absorbed_by": [{"name": n, "coefficient": c} for n, c in u.combination],
                "reason": u.reason,
            }
            for u in found.unidentifiable
        ],
        "T_measurement_base": base.tolist(),
        "T_last_tool": calibration.model.T_last_tool(calibration.x).tolist(),
        "tilts_rad": {calibration.table.rows[i].name: b for i, b in tilts(calibration).items()},
        "residuals_before_m": calibration.before.position.tolist(),
        "residuals_after_m": calibration.after.position.tolist(),
        "warnings": warnings(calibration),
        "evaluations": calibration.evaluations,
    }


def _error_line(label: str, errors: Errors | None, rotation: bool) -> str:
    if errors is None:
        return f"  {label:<26} -"
    rms, rot_rms = errors.rms()
    top, rot_top = errors.max()
    line = f"  {label:<26} {rms * 1e3:>10.4f} {top * 1e3:>10.4f}"
    if rotation and rot_rms is not None and rot_top is not None:
        line += f" {math.degrees(rot_rms):>11.5f} {math.degrees(rot_top):>11.5f}"
    return line


def _combination(terms: tuple[tuple[str, float], ...]) -> str:
    return " ".join(f"{c:+.4g} {n}" for n, c in terms) or "nothing (no effect on the measurements)"


def calibration_text(calibration: Calibration) -> str:
    """The report for a person: errors, parameters, what is not identifiable, warnings."""
    data = calibration.measurements
    found = calibration.identifiability
    rotation = data.markers == 0
    kind = (
        "full poses"
        if rotation
        else f"positions of {data.markers} point{'s' if data.markers > 1 else ''}"
    )
    method = (
        "Levenberg-Marquardt"
        if calibration.loss == "linear"
        else f"trust region, {calibration.loss} loss"
    )
    lines = [
        f"calibration of {calibration.table.name} from {data.path}: {data.count} rows, {kind}; {method}",
        f"identifiable parameters: {found.rank} of {len(calibration.x)} (rank tolerance "
        f"{found.tolerance:g}, condition number {found.condition_number:.1f})",
        "",
        "  errors                     RMS [mm]   max [mm]"
        + ("   RMS [deg]   max [deg]" if rotation else ""),
        _error_line("before (nominal arm)", calibration.before, rotation),
        _error_line("after (fit)", calibration.after, rotation),
        _error_line(
            f"cross-validated ({calibration.folds}-fold)"
            if calibration.folds
            else "cross-validated",
            calibration.cross_validated,
            rotation,
        ),
        "",
        f"  {'parameter':<30} {'nominal':>14} {'calibrated':>14} {'change':>14} {'std':>12}",
    ]
    framed = {p.name for p in calibration.model.parameters if p.group == "base" or p.kind == "r"}
    for row in parameter_rows(calibration):
        if not row["identifiable"] or row["name"] in framed:
            continue  # the base and the frames' rotations: as poses below
        angle = row["unit"] == "rad"
        std = "-" if row["std"] is None else _show(row["std"], angle)
        lines.append(
            f"  {row['name']:<30} {_show(row['nominal'], angle):>14} {_show(row['calibrated'], angle):>14} "
            f"{_show(row['change'], angle, True):>14} {std:>12}"
        )
    from .outputs import _rpy

    frames = [
        ("DH frame 0 in the measurement frame", calibration.model.T_measurement_base(calibration.x))
    ]
    if rotation:
        frames.append(
            ("measured frame in the last DH frame", calibration.model.T_last_tool(calibration.x))
        )
    lines.append("")
    for label, pose in frames:
        xyz = " ".join(f"{v * 1e3:.3f}" for v in pose[:3, 3])
        rpy = " ".join(f"{math.degrees(v):.4f}" for v in _rpy(pose[:3, :3]))
        lines.append(f"  {label}: xyz {xyz} mm, rpy {rpy} deg")
    lines += [
        "",
        "not identifiable (kept at the starting value; a unit change of it acts as the combination):",
    ]
    for u in found.unidentifiable:
        reason = f" ({u.reason})" if u.reason else ""
        lines.append(f"  {u.name}{reason}: {_combination(u.combination)}")
    if not found.unidentifiable:
        lines.append("  none")
    told = warnings(calibration)
    lines += ["", "warnings:" if told else "warnings: none"] + [f"  {w}" for w in told]
    return "\n".join(lines)
