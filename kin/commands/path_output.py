"""What ``kin path`` writes: the CSV of the joint path and the text summary."""

from __future__ import annotations

import csv
import os
import sys
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

from dh2urdf.output_text import shown_name

if TYPE_CHECKING:
    from ..path import PathResult, TimedPath
    from .joint_units import JointUnits


def write_csv(
    file: str, units: JointUnits, result: PathResult, timed: TimedPath | None, dense: bool
) -> None:
    """One row per sample (per --dt sample with --dt), SI, header with units."""
    if timed is not None and dense:
        write_joint_csv(file, units, timed.q, timed.t, timed.qd)
    elif timed is not None:
        write_joint_csv(file, units, result.q, timed.waypoint_times, timed.waypoint_qd)
    else:
        write_joint_csv(file, units, result.q)


def write_joint_csv(
    file: str | os.PathLike[str],
    units: JointUnits,
    q: Iterable[Any],
    t: Iterable[float] | None = None,
    qd: Iterable[Any] | None = None,
) -> None:
    """A joint path as CSV, SI, a header with units, written whole or not at all.

    Args:
        file: The file.
        units: The joints' names and SI units.
        q: Joint vectors [rad] / [m], one row each.
        t: Their times [s], or None (no time column).
        qd: Their joint velocities [rad/s] / [m/s] (with ``t``), or None.
    """
    import io
    from pathlib import Path

    from .output_file import write_text_atomic

    names, labels = units.joint_names, units.si_labels
    header = ["sample"] + (["t [s]"] if t is not None else [])
    header += [f"{n} [{u}]" for n, u in zip(names, labels)]
    if qd is not None:
        header += [f"{n} velocity [{u}/s]" for n, u in zip(names, labels)]
    times = [] if t is None else list(t)
    speeds = None if qd is None else list(qd)
    stream = io.StringIO()
    writer = csv.writer(stream)
    writer.writerow(header)
    for index, values in enumerate(q):
        row = [index] + ([] if t is None else [f"{times[index]:.9g}"])
        row += [f"{v:.12g}" for v in values]
        row += [] if speeds is None else [f"{v + 0.0:.9g}" for v in speeds[index]]
        writer.writerow(row)
    write_text_atomic(Path(file), stream.getvalue())  # whole, or not at all


def print_text(
    robot: str,
    units: JointUnits,
    unit: str,
    length: float,
    result: PathResult,
    timed: TimedPath | None,
    collides: bool = False,
) -> None:
    """A summary, then one line per sample in command-line units.

    ``collides``: the collision check found contact (the summary says so; the ``collisions:``
    line after the samples says where).
    """
    out = sys.stdout.write
    status = "followed" if result.success else result.message
    if collides:
        status += ", IN COLLISION (see the collisions line)"
    out(f"{robot} ({result.method}): {len(result.path)} samples, {status}\n")
    if len(result.q):
        out(f"max deviation from the path: {result.max_deviation / length:.3g} {unit}\n")
    if result.max_step_joint >= 0:
        j = result.max_step_joint
        step = result.max_joint_step / units.scales[j]
        out(f"max joint step: {step:.4g} {units.labels[j]} ({shown_name(units.joint_names[j])})\n")
    changes = ", ".join(map(str, result.branch_changes)) or "none"
    out(f"branch changes at samples: {changes}\n")
    times = None
    if timed is not None:
        out(f"duration: {timed.duration:.4g} s\n")
        times = timed.waypoint_times
    columns = units.columns()
    widths = [max(10, len(c)) for c in columns]
    head = "sample" + ("     t [s]" if times is not None else "")
    out(head + "  " + "  ".join(f"{c:>{w}}" for c, w in zip(columns, widths)) + "  branch\n")
    for i, q in enumerate(result.q):
        values = "  ".join(f"{v:>{w}.4f}" for v, w in zip(units.from_si(q), widths))
        t = f"{times[i]:>10.4f}" if times is not None else ""
        out(f"{i:>6}{t}  {values}  {result.branches[i]}\n")
